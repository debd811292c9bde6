//! Classical fixed-step fourth-order Runge-Kutta.

use super::stages::StageBuffers;
use super::OdeSystem;

/// Nodes of the classical RK4 tableau.
pub(super) const C: [f64; 4] = [0.0, 0.5, 0.5, 1.0];
/// Coupling coefficients of the classical RK4 tableau (row `i` on stages `0..i`).
pub(super) const A: [&[f64]; 4] = [&[], &[0.5], &[0.0, 0.5], &[0.0, 0.0, 1.0]];
/// Weights of the classical RK4 tableau.
pub(super) const B: [f64; 4] = [1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0];

/// Classical Runge-Kutta of order 4 with a fixed step, over a state of a fixed length.
///
/// The stage buffers `k1..k4` and the stage-argument buffer are allocated in [`Rk4::new`]; stepping
/// allocates nothing. Long states are combined in parallel, bitwise identically for any thread count (see
/// the [module documentation](super)).
#[derive(Clone, Debug)]
pub struct Rk4 {
    buffers: StageBuffers,
}

impl Rk4 {
    /// A stepper for states of `dimension` elements.
    pub fn new(dimension: usize) -> Self {
        Self {
            buffers: StageBuffers::new(4, dimension),
        }
    }

    /// Length of the states this stepper accepts.
    pub fn dimension(&self) -> usize {
        self.buffers.temp.len()
    }

    /// Advances `state` in place by one step of `step_s` seconds from time `t_s` (s). Four right-hand-side
    /// evaluations.
    ///
    /// # Panics
    /// If `state.len()` differs from the dimension given to [`Rk4::new`].
    pub fn step<S: OdeSystem + ?Sized>(
        &mut self,
        system: &S,
        t_s: f64,
        state: &mut [f64],
        step_s: f64,
    ) {
        assert_eq!(
            state.len(),
            self.dimension(),
            "state length != Rk4 dimension"
        );
        system.derivative(t_s, state, &mut self.buffers.k[0]);
        self.buffers.eval(system, t_s, state, step_s, &C, &A);
        self.buffers.combine(state, step_s, &B);
        state.copy_from_slice(&self.buffers.temp);
    }

    /// Number of steps [`Rk4::integrate`] takes from `t0_s` to `t1_s` (s) with `max_step_s` (s): 0 when
    /// `t1_s <= t0_s`, else `ceil((t1 - t0) / max_step - 1e-9)`, at least 1.
    pub fn step_count(t0_s: f64, t1_s: f64, max_step_s: f64) -> usize {
        StepPlan::new(t0_s, t1_s, max_step_s).map_or(0, |plan| plan.steps)
    }

    /// Advances `state` in place from `t0_s` to `t1_s` (s) in steps of `max_step_s` (s), the last step
    /// shortened to land exactly on `t1_s`.
    ///
    /// The number of steps is `ceil((t1 - t0) / max_step - 1e-9)`: when the interval is an integer number of
    /// steps up to rounding, no sliver step is added and the last step may exceed `max_step_s` by at most a
    /// relative 1e-9. Step `i` starts at `t0 + i * max_step`, so times do not accumulate rounding. Does
    /// nothing when `t1_s <= t0_s`.
    ///
    /// # Panics
    /// If `max_step_s` is not strictly positive and finite, or on a state length mismatch.
    pub fn integrate<S: OdeSystem + ?Sized>(
        &mut self,
        system: &S,
        t0_s: f64,
        t1_s: f64,
        state: &mut [f64],
        max_step_s: f64,
    ) {
        assert!(
            max_step_s > 0.0 && max_step_s.is_finite(),
            "max_step_s must be positive and finite, got {max_step_s}"
        );
        let Some(plan) = StepPlan::new(t0_s, t1_s, max_step_s) else {
            return;
        };
        for i in 0..plan.steps {
            self.step(system, plan.start_s(i), state, plan.step_s(i));
        }
    }
}

/// The steps of [`Rk4::integrate`] from `t0_s` to `t1_s`: `steps` steps of `max_step_s`, the last one
/// shortened (or lengthened by at most a relative 1e-9) to land on `t1_s`. Shared by the fused kernel so
/// that both split an interval identically.
#[derive(Clone, Copy, Debug)]
pub(super) struct StepPlan {
    t0_s: f64,
    t1_s: f64,
    max_step_s: f64,
    /// Number of steps, at least 1.
    pub(super) steps: usize,
}

impl StepPlan {
    /// The plan, or `None` when `t1_s <= t0_s` (nothing to do). `max_step_s` must be positive.
    pub(super) fn new(t0_s: f64, t1_s: f64, max_step_s: f64) -> Option<Self> {
        (t1_s > t0_s).then(|| Self {
            t0_s,
            t1_s,
            max_step_s,
            steps: ((t1_s - t0_s) / max_step_s - 1e-9).ceil().max(1.0) as usize,
        })
    }

    /// Start of step `i` (s): `t0 + i * max_step`, so times do not accumulate rounding.
    pub(super) fn start_s(&self, i: usize) -> f64 {
        self.t0_s + i as f64 * self.max_step_s
    }

    /// Length of step `i` (s).
    #[inline]
    pub(super) fn step_s(&self, i: usize) -> f64 {
        if i + 1 == self.steps {
            self.t1_s - self.start_s(i)
        } else {
            self.max_step_s
        }
    }
}
