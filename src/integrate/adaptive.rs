//! Adaptive embedded Runge-Kutta stepper with step-size control.

use std::marker::PhantomData;

use rayon::prelude::*;

use super::stages::{StageBuffers, CHUNK_LEN, PARALLEL_MIN_LEN};
use super::{ButcherTableau, IntegrateError, OdeSystem, Tolerances};

/// Safety factor of the step-size controller.
const SAFETY: f64 = 0.9;
/// Smallest factor by which one step may shrink the next.
const FACTOR_MIN: f64 = 0.2;
/// Largest factor by which one step may grow the next.
const FACTOR_MAX: f64 = 5.0;
/// Default limit on step attempts per call to [`AdaptiveStepper::integrate`].
const DEFAULT_MAX_STEPS: usize = 1_000_000;

/// Counters of one call to [`AdaptiveStepper::integrate`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct IntegrationStats {
    /// Steps accepted.
    pub accepted_steps: usize,
    /// Steps rejected because the error estimate exceeded the tolerances.
    pub rejected_steps: usize,
    /// Evaluations of the right-hand side (each one covers the whole state).
    pub rhs_evaluations: usize,
}

/// Per-chunk partial of the error norm: maxima of the scaled error estimates and the first index of a
/// non-finite value.
#[derive(Clone, Copy, Debug, Default)]
struct NormPartial {
    high: f64,
    low: f64,
    first_non_finite: Option<usize>,
}

/// Adaptive embedded Runge-Kutta stepper for the tableau `T` ([`Rkf78`](super::Rkf78) or
/// [`Dop853`](super::Dop853)) over states of a fixed length.
///
/// All buffers (`T::STAGES` stage vectors, the stage argument, the error-norm partials) are allocated in
/// [`AdaptiveStepper::new`]; integrating allocates nothing. The error norm and controller are described in
/// the [module documentation](super). The whole state shares one step size (lockstep).
#[derive(Clone, Debug)]
pub struct AdaptiveStepper<T: ButcherTableau> {
    buffers: StageBuffers,
    partials: Vec<NormPartial>,
    tolerances: Tolerances,
    max_step_s: f64,
    max_steps: usize,
    step_guess_s: Option<f64>,
    tableau: PhantomData<T>,
}

impl<T: ButcherTableau> AdaptiveStepper<T> {
    /// A stepper for states of `dimension` elements with the given local error tolerances.
    ///
    /// # Panics
    /// If `tolerances.absolute` is not strictly positive and finite or `tolerances.relative` is negative or
    /// not finite.
    pub fn new(dimension: usize, tolerances: Tolerances) -> Self {
        assert!(
            tolerances.absolute > 0.0 && tolerances.absolute.is_finite(),
            "absolute tolerance must be positive and finite, got {}",
            tolerances.absolute
        );
        assert!(
            tolerances.relative >= 0.0 && tolerances.relative.is_finite(),
            "relative tolerance must be non-negative and finite, got {}",
            tolerances.relative
        );
        Self {
            buffers: StageBuffers::new(T::STAGES, dimension),
            partials: vec![NormPartial::default(); dimension.div_ceil(CHUNK_LEN).max(1)],
            tolerances,
            max_step_s: f64::INFINITY,
            max_steps: DEFAULT_MAX_STEPS,
            step_guess_s: None,
            tableau: PhantomData,
        }
    }

    /// Length of the states this stepper accepts.
    pub fn dimension(&self) -> usize {
        self.buffers.temp.len()
    }

    /// The local error tolerances.
    pub fn tolerances(&self) -> Tolerances {
        self.tolerances
    }

    /// Sets the largest step size (s); `f64::INFINITY` (the default) means no limit.
    ///
    /// # Panics
    /// If `max_step_s` is not strictly positive.
    pub fn set_max_step_s(&mut self, max_step_s: f64) {
        assert!(
            max_step_s > 0.0,
            "max_step_s must be positive, got {max_step_s}"
        );
        self.max_step_s = max_step_s;
    }

    /// Sets the first step size (s) tried by the next call to [`AdaptiveStepper::integrate`], replacing the
    /// step size kept from the previous call. Without it, the first call estimates a starting step by
    /// Hairer's algorithm (Hairer, Nørsett & Wanner, *Solving ODEs I*, II.4), at the cost of one extra
    /// right-hand-side evaluation.
    ///
    /// # Panics
    /// If `step_s` is not strictly positive and finite.
    pub fn set_initial_step_s(&mut self, step_s: f64) {
        assert!(
            step_s > 0.0 && step_s.is_finite(),
            "initial step must be positive and finite, got {step_s}"
        );
        self.step_guess_s = Some(step_s);
    }

    /// Replaces the step size kept from the previous call: `Some(h)` as [`AdaptiveStepper::set_initial_step_s`],
    /// `None` to estimate a starting step afresh. Lets one stepper integrate several independent systems
    /// (each with its own remembered step) without one's step size leaking into the next.
    pub fn set_step_guess_s(&mut self, step_s: Option<f64>) {
        if let Some(h) = step_s {
            self.set_initial_step_s(h);
        } else {
            self.step_guess_s = None;
        }
    }

    /// Sets the limit on step attempts (accepted plus rejected) per call to
    /// [`AdaptiveStepper::integrate`]; the default is 1 000 000.
    pub fn set_max_steps(&mut self, max_steps: usize) {
        self.max_steps = max_steps;
    }

    /// The step size (s) the next call will try first: the controller's proposal after the last accepted
    /// step, or the value given to [`AdaptiveStepper::set_initial_step_s`]; `None` before the first call.
    pub fn next_step_s(&self) -> Option<f64> {
        self.step_guess_s
    }

    /// Advances `state` in place by one step of exactly `step_s` (s) from `t_s` (s), with the propagated
    /// solution of `T` and no error control (`T::STAGES` right-hand-side evaluations). Meant for
    /// measuring the order of the method and for fixed-step runs; no check for non-finite values.
    ///
    /// # Panics
    /// If `state.len()` differs from the dimension given to [`AdaptiveStepper::new`].
    pub fn step_fixed<S: OdeSystem + ?Sized>(
        &mut self,
        system: &S,
        t_s: f64,
        state: &mut [f64],
        step_s: f64,
    ) {
        assert_eq!(
            state.len(),
            self.dimension(),
            "state length != stepper dimension"
        );
        system.derivative(t_s, state, &mut self.buffers.k[0]);
        self.buffers.eval(system, t_s, state, step_s, T::C, T::A);
        self.buffers.combine(state, step_s, T::B);
        state.copy_from_slice(&self.buffers.temp);
    }

    /// Integrates `state` in place from `t0_s` to `t1_s` (s, `t1_s >= t0_s`), landing exactly on `t1_s`.
    ///
    /// The first step tried is the step size kept from the previous call (see
    /// [`AdaptiveStepper::next_step_s`]), limited by the maximum step. A step that would end within 1 % of
    /// a step length before `t1_s` is stretched to end on it. On error, `state` holds the last accepted
    /// state, at the time given in the error.
    ///
    /// # Errors
    /// [`IntegrateError::NonFinite`] if a trial step yields a NaN or infinite value,
    /// [`IntegrateError::StepSizeUnderflow`] if the step needed falls below `16 eps max(|t|, |t1|)`,
    /// [`IntegrateError::TooManySteps`] past the step-attempt limit, [`IntegrateError::InvalidInterval`] if
    /// `t1_s < t0_s` or a time is not finite.
    ///
    /// # Panics
    /// If `state.len()` differs from the dimension given to [`AdaptiveStepper::new`].
    pub fn integrate<S: OdeSystem + ?Sized>(
        &mut self,
        system: &S,
        t0_s: f64,
        t1_s: f64,
        state: &mut [f64],
    ) -> Result<IntegrationStats, IntegrateError> {
        assert_eq!(
            state.len(),
            self.dimension(),
            "state length != stepper dimension"
        );
        if !(t0_s.is_finite() && t1_s.is_finite() && t1_s >= t0_s) {
            return Err(IntegrateError::InvalidInterval { t0_s, t1_s });
        }
        let mut stats = IntegrationStats::default();
        if t1_s == t0_s {
            return Ok(stats);
        }
        system.derivative(t0_s, state, &mut self.buffers.k[0]);
        stats.rhs_evaluations += 1;
        let mut h = match self.step_guess_s {
            Some(h) => h,
            None => {
                stats.rhs_evaluations += 1;
                self.initial_step(system, t0_s, t1_s, state)
            }
        }
        .min(self.max_step_s);
        let exponent = -1.0 / (f64::from(T::ERROR_ORDER) + 1.0);
        let mut t = t0_s;
        let mut previous_rejected = false;
        loop {
            if stats.accepted_steps + stats.rejected_steps >= self.max_steps {
                return Err(IntegrateError::TooManySteps {
                    t_s: t,
                    max_steps: self.max_steps,
                });
            }
            let last = t + 1.01 * h >= t1_s;
            let h_try = if last { t1_s - t } else { h };
            stats.rhs_evaluations += self.buffers.eval(system, t, state, h_try, T::C, T::A);
            self.buffers.combine(state, h_try, T::B);
            let (err, non_finite) = self.error_norm(state, h_try);
            if let Some(index) = non_finite {
                return Err(IntegrateError::NonFinite { t_s: t, index });
            }
            let factor = if err > 0.0 {
                (SAFETY * err.powf(exponent)).clamp(FACTOR_MIN, FACTOR_MAX)
            } else {
                FACTOR_MAX
            };
            if err <= 1.0 {
                stats.accepted_steps += 1;
                state.copy_from_slice(&self.buffers.temp);
                let proposal = h_try
                    * if previous_rejected {
                        factor.min(1.0)
                    } else {
                        factor
                    };
                previous_rejected = false;
                if last {
                    // A last step shortened to land on t1 says little about the step the dynamics allow:
                    // keep the larger of the step it replaced and the controller's proposal.
                    self.step_guess_s = Some(proposal.max(h).min(self.max_step_s));
                    return Ok(stats);
                }
                t += h_try;
                h = proposal.min(self.max_step_s);
                system.derivative(t, state, &mut self.buffers.k[0]);
                stats.rhs_evaluations += 1;
            } else {
                stats.rejected_steps += 1;
                previous_rejected = true;
                h = h_try * factor.min(1.0);
                if h.is_nan() || h <= 16.0 * f64::EPSILON * t.abs().max(t1_s.abs()) {
                    return Err(IntegrateError::StepSizeUnderflow { t_s: t, step_s: h });
                }
            }
        }
    }

    /// Error norm of the trial step from `y` to `buffers.temp` with step `h`, and the lowest index of a
    /// non-finite value in the new state or the error estimate.
    fn error_norm(&mut self, y: &[f64], h: f64) -> (f64, Option<usize>) {
        let y_new = &self.buffers.temp;
        let k = &self.buffers.k;
        let tol = self.tolerances;
        if y.len() < PARALLEL_MIN_LEN {
            self.partials[..1].fill(norm_chunk::<T>(y, y_new, k, tol, 0));
        } else {
            self.partials
                .par_iter_mut()
                .zip(y.par_chunks(CHUNK_LEN).zip(y_new.par_chunks(CHUNK_LEN)))
                .enumerate()
                .for_each(|(c, (p, (yc, ync)))| {
                    *p = norm_chunk::<T>(yc, ync, k, tol, c * CHUNK_LEN)
                });
        }
        let used = if y.len() < PARALLEL_MIN_LEN {
            &self.partials[..1]
        } else {
            &self.partials[..]
        };
        let mut total = NormPartial::default();
        for p in used {
            total.high = total.high.max(p.high);
            total.low = total.low.max(p.low);
            total.first_non_finite = total.first_non_finite.or(p.first_non_finite);
        }
        let err = if T::B_ERROR_LOW.is_some() {
            // Hairer's DOP853 estimate: |h| err5^2 / sqrt(err5^2 + 0.01 err3^2).
            let denominator = total.high * total.high + 0.01 * total.low * total.low;
            if denominator > 0.0 {
                h.abs() * total.high * total.high / denominator.sqrt()
            } else {
                0.0
            }
        } else {
            h.abs() * total.high
        };
        (err, total.first_non_finite)
    }

    /// Hairer's starting step (*Solving ODEs I*, II.4, algorithm of `hinit` in `dop853.f`), with the
    /// maximum norm. `buffers.k[0]` holds `f(t0, y)`; uses `k[1]` and `temp` as scratch.
    fn initial_step<S: OdeSystem + ?Sized>(
        &mut self,
        system: &S,
        t0_s: f64,
        t1_s: f64,
        y: &[f64],
    ) -> f64 {
        let tol = self.tolerances;
        let scale = |yi: f64| tol.absolute + tol.relative * yi.abs();
        let (f0, rest) = self.buffers.k.split_at_mut(1);
        let f0 = &f0[0];
        let d0 = y
            .iter()
            .fold(0.0_f64, |m, &yi| m.max((yi / scale(yi)).abs()));
        let d1 = y
            .iter()
            .zip(f0)
            .fold(0.0_f64, |m, (&yi, &fi)| m.max((fi / scale(yi)).abs()));
        let h0 = if d0 < 1e-5 || d1 < 1e-5 {
            1e-6
        } else {
            0.01 * d0 / d1
        }
        .min(self.max_step_s)
        .min(t1_s - t0_s);
        for ((ti, &yi), &fi) in self.buffers.temp.iter_mut().zip(y).zip(f0) {
            *ti = yi + h0 * fi;
        }
        let f1 = &mut rest[0];
        system.derivative(t0_s + h0, &self.buffers.temp, f1);
        let d2 = y
            .iter()
            .zip(f0.iter().zip(f1.iter()))
            .fold(0.0_f64, |m, (&yi, (&a, &b))| {
                m.max(((b - a) / scale(yi)).abs())
            })
            / h0;
        let d12 = d1.max(d2);
        let h1 = if d12 <= 1e-15 || !d12.is_finite() {
            (h0 * 1e-3).max(1e-6)
        } else {
            (0.01 / d12).powf(1.0 / (f64::from(T::ERROR_ORDER) + 1.0))
        };
        (100.0 * h0).min(h1)
    }
}

/// Error-norm partial over one chunk starting at state index `offset`.
fn norm_chunk<T: ButcherTableau>(
    y: &[f64],
    y_new: &[f64],
    k: &[Vec<f64>],
    tol: Tolerances,
    offset: usize,
) -> NormPartial {
    let mut p = NormPartial::default();
    for (idx, (&yi, &yn)) in y.iter().zip(y_new).enumerate() {
        let i = offset + idx;
        let scale = tol.absolute + tol.relative * yi.abs().max(yn.abs());
        let estimate = |weights: &[f64]| {
            let mut e = 0.0;
            for (w, kj) in weights.iter().zip(k) {
                if *w != 0.0 {
                    e += w * kj[i];
                }
            }
            (e / scale).abs()
        };
        let high = estimate(T::B_ERROR);
        let low = T::B_ERROR_LOW.map_or(0.0, estimate);
        if !(yn.is_finite() && high.is_finite() && low.is_finite()) && p.first_non_finite.is_none()
        {
            p.first_non_finite = Some(i);
        }
        p.high = p.high.max(high);
        p.low = p.low.max(low);
    }
    p
}
