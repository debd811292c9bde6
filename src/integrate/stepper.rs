//! One integrator chosen at run time: [`Stepper`] dispatches to RK4 or an adaptive pair by
//! [`IntegratorMethod`], so callers (the swarm engine, single-orbit propagation) do not repeat the match.

use super::{
    AdaptiveStepper, Dop853, IntegrateError, IntegratorMethod, OdeSystem, Rk4, Rkf78, Tolerances,
};

/// An integrator of a state of fixed length, of the method chosen at run time.
pub enum Stepper {
    /// Fixed-step RK4.
    Rk4(Rk4),
    /// Adaptive RKF7(8).
    Rk78(AdaptiveStepper<Rkf78>),
    /// Adaptive DOP853.
    Dop853(AdaptiveStepper<Dop853>),
}

impl Stepper {
    /// A stepper for states of `dimension` numbers; `max_step_s` is the RK4 step, or the longest step of
    /// the adaptive methods \[s\].
    pub fn new(
        method: IntegratorMethod,
        dimension: usize,
        tolerances: Tolerances,
        max_step_s: f64,
    ) -> Self {
        match method {
            IntegratorMethod::Rk4 => Stepper::Rk4(Rk4::new(dimension)),
            IntegratorMethod::Rk78 => {
                let mut stepper = AdaptiveStepper::<Rkf78>::new(dimension, tolerances);
                stepper.set_max_step_s(max_step_s);
                Stepper::Rk78(stepper)
            }
            IntegratorMethod::Dop853 => {
                let mut stepper = AdaptiveStepper::<Dop853>::new(dimension, tolerances);
                stepper.set_max_step_s(max_step_s);
                Stepper::Dop853(stepper)
            }
        }
    }

    /// The step the adaptive methods will try first (None for RK4 or before the first call).
    pub fn step_guess_s(&self) -> Option<f64> {
        match self {
            Stepper::Rk4(_) => None,
            Stepper::Rk78(ad) => ad.next_step_s(),
            Stepper::Dop853(ad) => ad.next_step_s(),
        }
    }

    /// Replaces the step the adaptive methods will try first (`None`: estimate afresh); no effect on RK4.
    pub fn set_step_guess_s(&mut self, step_s: Option<f64>) {
        match self {
            Stepper::Rk4(_) => {}
            Stepper::Rk78(ad) => ad.set_step_guess_s(step_s),
            Stepper::Dop853(ad) => ad.set_step_guess_s(step_s),
        }
    }

    /// Integrates `state` from `t0_s` to `t1_s` exactly (RK4 in steps of at most `max_step_s`, the last
    /// one shortened; the adaptive methods under their tolerances).
    pub fn advance<S: OdeSystem + ?Sized>(
        &mut self,
        system: &S,
        t0_s: f64,
        t1_s: f64,
        state: &mut [f64],
        max_step_s: f64,
    ) -> Result<(), IntegrateError> {
        match self {
            Stepper::Rk4(rk) => {
                rk.integrate(system, t0_s, t1_s, state, max_step_s);
                Ok(())
            }
            Stepper::Rk78(ad) => ad.integrate(system, t0_s, t1_s, state).map(|_| ()),
            Stepper::Dop853(ad) => ad.integrate(system, t0_s, t1_s, state).map(|_| ()),
        }
    }
}
