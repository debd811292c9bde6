//! Propagation of one or a few orbits (no control), with outputs at exact multiples of an output step:
//! the library side of `satflock propagate`.

use thiserror::Error;

use crate::integrate::{IntegrateError, IntegratorMethod, Stepper, Tolerances};

use crate::orbit::{CartesianState, EarthModel, GravityModel};

/// How to propagate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PropagationSettings {
    /// Earth constants.
    pub earth: EarthModel,
    /// Gravity model.
    pub gravity: GravityModel,
    /// Integrator.
    pub integrator: IntegratorMethod,
    /// RK4 step, or longest step of the adaptive method \[s\].
    pub step_s: f64,
    /// Tolerances of the adaptive method.
    pub tolerances: Tolerances,
    /// Length of the propagation \[s\].
    pub duration_s: f64,
    /// Output spacing \[s\]; outputs at k · output_step_s for k = 0, 1, … up to the duration.
    pub output_step_s: f64,
}

/// A propagation that could not run.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum PropagateError {
    /// A setting is out of range.
    #[error("{setting} = {value} is out of range (allowed: {allowed})")]
    InvalidSetting {
        /// The setting's name.
        setting: &'static str,
        /// Its value.
        value: f64,
        /// The allowed range.
        allowed: &'static str,
    },
    /// The integrator failed.
    #[error(transparent)]
    Integration(#[from] IntegrateError),
}

impl PropagationSettings {
    fn check(&self) -> Result<(), PropagateError> {
        let positive = |setting, value: f64| {
            if value.is_finite() && value > 0.0 {
                Ok(())
            } else {
                Err(PropagateError::InvalidSetting {
                    setting,
                    value,
                    allowed: "finite, > 0",
                })
            }
        };
        positive("duration_s", self.duration_s)?;
        positive("output_step_s", self.output_step_s)?;
        positive("step_s", self.step_s)?;
        positive("rtol", self.tolerances.relative)?;
        positive("atol", self.tolerances.absolute)?;
        Ok(())
    }
}

/// Propagates `initial` orbits together under the same gravity and calls `visit(t, states)` at t = 0 and
/// at every multiple of the output step up to the duration (the last output lands on the duration when it
/// is not a multiple). The integrator lands exactly on every output time.
pub fn propagate(
    initial: &[CartesianState],
    settings: &PropagationSettings,
    mut visit: impl FnMut(f64, &[CartesianState]),
) -> Result<(), PropagateError> {
    settings.check()?;
    let m = initial.len();
    let mut y: Vec<f64> = initial
        .iter()
        .flat_map(|s| s.position_m.iter().chain(s.velocity_mps.iter()).copied())
        .collect();
    let earth = settings.earth;
    let gravity = settings.gravity;
    let rhs = move |_t: f64, y: &[f64], dy: &mut [f64]| {
        for (state, d) in y.chunks_exact(6).zip(dy.chunks_exact_mut(6)) {
            let r = nalgebra::Vector3::new(state[0], state[1], state[2]);
            let a = gravity.acceleration_m_s2(&earth, &r);
            d[0..3].copy_from_slice(&state[3..6]);
            d[3..6].copy_from_slice(a.as_slice());
        }
    };
    let mut states = initial.to_vec();
    let unpack = |y: &[f64], states: &mut [CartesianState]| {
        for (s, c) in states.iter_mut().zip(y.chunks_exact(6)) {
            *s = CartesianState::new(
                nalgebra::Vector3::new(c[0], c[1], c[2]),
                nalgebra::Vector3::new(c[3], c[4], c[5]),
            );
        }
    };
    visit(0.0, &states);
    let mut stepper = Stepper::new(
        settings.integrator,
        6 * m,
        settings.tolerances,
        settings.step_s,
    );
    let outputs = (settings.duration_s / settings.output_step_s).floor() as u64;
    let mut t = 0.0;
    let mut k = 1;
    loop {
        // Output times are computed from their index, never accumulated, so they are exact multiples.
        let next = if k <= outputs {
            k as f64 * settings.output_step_s
        } else {
            settings.duration_s
        };
        if next <= t {
            break;
        }
        stepper.advance(&rhs, t, next, &mut y, settings.step_s)?;
        t = next;
        unpack(&y, &mut states);
        visit(t, &states);
        k += 1;
    }
    Ok(())
}
