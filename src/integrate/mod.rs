//! Numerical integration of ordinary differential equations `dy/dt = f(t, y)`.
//!
//! The state is a plain `&mut [f64]` of any length: one satellite (6 numbers: position in m, velocity in
//! m/s) or a whole swarm stepped together (6N numbers, N up to 10^5). Time is in seconds.
//!
//! | type | method |
//! | --- | --- |
//! | [`Rk4`] | classical fixed-step Runge-Kutta of order 4 |
//! | [`AdaptiveStepper`]`<`[`Rkf78`]`>` | Fehlberg's embedded 7(8) pair (NASA TR R-287, 1968), 13 stages; propagates the **8th-order** solution (local extrapolation), error control on the 7th |
//! | [`AdaptiveStepper`]`<`[`Dop853`]`>` | Dormand-Prince 8(5,3) of Hairer, Nørsett & Wanner, 12 stages; propagates the 8th-order solution |
//! | [`Stepper`] | one of the above, chosen at run time by [`IntegratorMethod`] |
//!
//! # Allocation and determinism
//!
//! Every stepper allocates its stage buffers once, in `new`; stepping allocates nothing. The stage linear
//! combinations are element-wise. For states longer than [`PARALLEL_MIN_LEN`] elements they run on the rayon
//! pool in chunks of the fixed length [`CHUNK_LEN`]; each element is computed by the same expression
//! whichever chunk or thread holds it, so results are bitwise identical for any thread count, and bitwise
//! identical to the serial path. The only reduction, the error norm of the adaptive stepper, is a maximum,
//! which is exact and independent of order.
//!
//! # Error control (adaptive stepper)
//!
//! The error norm is the **maximum norm** over all state components of
//! `|e_i| / (absolute + relative * max(|y_i|, |y_new_i|))`, where `e_i` is the embedded local error estimate.
//! A step is accepted when the norm is at most 1. The maximum norm (rather than Hairer's root mean square)
//! is chosen so that, in a swarm stepped together, one satellite's error is not diluted by the 6N - 6
//! components of the others: the accepted accuracy does not depend on N. The next step is
//! `h * clamp(0.9 * err^(-1/(q+1)), 0.2, 5)`, with `q` = [`ButcherTableau::ERROR_ORDER`]; after a rejected
//! step the step is not allowed to grow.

mod adaptive;
mod fused;
mod rk4;
mod stages;
mod stepper;
mod tableau;

pub use adaptive::{AdaptiveStepper, IntegrationStats};
pub use fused::{
    FusedError, FusedRk4, SegmentInputs, Simd, PARALLEL_CHUNK, PARALLEL_MIN_SAT_STEPS,
};
pub use rk4::Rk4;
pub use stages::{CHUNK_LEN, PARALLEL_MIN_LEN};
pub use stepper::Stepper;
pub use tableau::{real_stability_bound, stability_function, ButcherTableau, Dop853, Rkf78};

use std::fmt;
use std::str::FromStr;

/// Right-hand side of `dy/dt = f(t, y)`.
///
/// Implemented for every closure `Fn(f64, &[f64], &mut [f64])`.
pub trait OdeSystem {
    /// Writes `dy/dt` at time `t_s` (s) and state `state` into `derivative`.
    ///
    /// `state` and `derivative` have the same length; the units of `derivative` are those of `state`
    /// per second. Every element of `derivative` must be written: the buffer holds stale values from an
    /// earlier stage.
    fn derivative(&self, t_s: f64, state: &[f64], derivative: &mut [f64]);
}

impl<F: Fn(f64, &[f64], &mut [f64]) + ?Sized> OdeSystem for F {
    fn derivative(&self, t_s: f64, state: &[f64], derivative: &mut [f64]) {
        self(t_s, state, derivative)
    }
}

/// Local error tolerances of the adaptive stepper.
///
/// A component `y_i` is allowed a local error per step of `absolute + relative * max(|y_i|, |y_new_i|)`, in
/// the unit of `y_i`. The same `absolute` applies to every component, so with a Cartesian state it is in m
/// for positions and m/s for velocities.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Tolerances {
    /// Relative tolerance (dimensionless), at least 0.
    pub relative: f64,
    /// Absolute tolerance, in the unit of each state component (m, m/s); strictly positive.
    pub absolute: f64,
}

impl Default for Tolerances {
    /// `relative = 1e-10`, `absolute = 1e-6` (1 µm and 1 µm/s for a Cartesian state). On a low Earth orbit
    /// (|r| ≈ 7e6 m, |v| ≈ 7.5e3 m/s) the relative term dominates for positions (0.7 mm per step) and the two
    /// terms are comparable for velocities.
    fn default() -> Self {
        Self {
            relative: 1e-10,
            absolute: 1e-6,
        }
    }
}

/// Why an adaptive integration stopped early.
///
/// On every error the state passed to [`AdaptiveStepper::integrate`] holds the last accepted state, at the
/// time reported as `t_s`.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum IntegrateError {
    /// The step size needed to meet the tolerances fell below the resolution of the time variable.
    #[error(
        "step size underflow at t = {t_s} s: step {step_s} s is too small to meet the tolerances"
    )]
    StepSizeUnderflow {
        /// Time of the last accepted state (s).
        t_s: f64,
        /// Rejected step size (s).
        step_s: f64,
    },
    /// A trial step produced a NaN or infinite value (in the new state or its error estimate).
    #[error("non-finite value in state component {index} when stepping from t = {t_s} s")]
    NonFinite {
        /// Time of the last accepted state, from which the failing step started (s).
        t_s: f64,
        /// Lowest index of a non-finite state component.
        index: usize,
    },
    /// The number of step attempts (accepted plus rejected) in one call reached the limit.
    #[error("too many steps: {max_steps} step attempts reached at t = {t_s} s")]
    TooManySteps {
        /// Time of the last accepted state (s).
        t_s: f64,
        /// The limit that was reached (see [`AdaptiveStepper::set_max_steps`]).
        max_steps: usize,
    },
    /// The end time is before the start time, or a time is not finite. Only forward integration is
    /// supported.
    #[error("invalid interval: from t0 = {t0_s} s to t1 = {t1_s} s (need finite t1 >= t0)")]
    InvalidInterval {
        /// Start time (s).
        t0_s: f64,
        /// End time (s).
        t1_s: f64,
    },
    /// The fused kernel refused its input.
    #[error(transparent)]
    Fused(#[from] FusedError),
}

/// Choice of integration method, as written in scenario files and on the command line.
///
/// Serialised and parsed as `"rk4"`, `"rk78"` or `"dop853"`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum IntegratorMethod {
    /// Fixed-step classical Runge-Kutta 4 ([`Rk4`]).
    Rk4,
    /// Adaptive Runge-Kutta-Fehlberg 7(8) ([`AdaptiveStepper`]`<`[`Rkf78`]`>`).
    Rk78,
    /// Adaptive Dormand-Prince 8(5,3) ([`AdaptiveStepper`]`<`[`Dop853`]`>`).
    Dop853,
}

impl IntegratorMethod {
    /// Every method, in the order of the names in [`IntegratorMethod::NAMES`].
    pub const ALL: [IntegratorMethod; 3] = [Self::Rk4, Self::Rk78, Self::Dop853];
    /// The accepted names, as parsed by `FromStr` and written by serde and `Display`.
    pub const NAMES: [&'static str; 3] = ["rk4", "rk78", "dop853"];

    /// The name of this method (`"rk4"`, `"rk78"` or `"dop853"`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Rk4 => Self::NAMES[0],
            Self::Rk78 => Self::NAMES[1],
            Self::Dop853 => Self::NAMES[2],
        }
    }

    /// An adaptive method's stability interval on the negative real axis (`h |λ|`, from its tableau:
    /// [`tableau::real_stability_bound`]); `None` for the fixed-step RK4, whose step the caller chooses.
    pub fn adaptive_stability_bound(self) -> Option<f64> {
        match self {
            Self::Rk4 => None,
            Self::Rk78 => Some(tableau::real_stability_bound::<Rkf78>()),
            Self::Dop853 => Some(tableau::real_stability_bound::<Dop853>()),
        }
    }
}

impl fmt::Display for IntegratorMethod {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Error of parsing an [`IntegratorMethod`] from an unknown name.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown integrator method {name:?}; valid names are \"rk4\", \"rk78\", \"dop853\"")]
pub struct ParseIntegratorMethodError {
    /// The name that was not recognised.
    pub name: String,
}

impl FromStr for IntegratorMethod {
    type Err = ParseIntegratorMethodError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| ParseIntegratorMethodError { name: s.to_owned() })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn method_names_round_trip() {
        for m in IntegratorMethod::ALL {
            assert_eq!(m.to_string().parse::<IntegratorMethod>().unwrap(), m);
            assert_eq!(serde_json::to_string(&m).unwrap(), format!("\"{m}\""));
        }
        let err = "rk45".parse::<IntegratorMethod>().unwrap_err();
        assert!(err.to_string().contains("\"rk78\""));
    }

    #[test]
    fn default_tolerances() {
        let t = Tolerances::default();
        assert_eq!((t.relative, t.absolute), (1e-10, 1e-6));
    }
}
