//! Stage evaluation and stage linear combinations shared by every explicit Runge-Kutta stepper.

use rayon::prelude::*;

use super::OdeSystem;

/// States with at least this many elements have their stage combinations computed in parallel.
pub const PARALLEL_MIN_LEN: usize = 16_384;

/// Fixed chunk length (elements) of the parallel stage combinations and error-norm partials. Fixed, so that
/// the split of work never depends on the number of threads.
pub const CHUNK_LEN: usize = 4_096;

/// `out[i] = base[i] + h * sum_j coeffs[j] * stages[j][offset + i]` for one chunk. Zero coefficients are
/// skipped; the sum runs over `j` in increasing order.
fn lincomb_chunk(
    out: &mut [f64],
    base: &[f64],
    h: f64,
    coeffs: &[f64],
    stages: &[Vec<f64>],
    offset: usize,
) {
    for (idx, (o, b)) in out.iter_mut().zip(base).enumerate() {
        let i = offset + idx;
        let mut acc = 0.0;
        for (a, k) in coeffs.iter().zip(stages) {
            if *a != 0.0 {
                acc += a * k[i];
            }
        }
        *o = b + h * acc;
    }
}

/// `out = base + h * sum_j coeffs[j] * stages[j]`, element-wise; parallel over fixed chunks for long states.
pub(crate) fn lincomb(out: &mut [f64], base: &[f64], h: f64, coeffs: &[f64], stages: &[Vec<f64>]) {
    debug_assert_eq!(out.len(), base.len());
    if out.len() < PARALLEL_MIN_LEN {
        lincomb_chunk(out, base, h, coeffs, stages, 0);
    } else {
        out.par_chunks_mut(CHUNK_LEN)
            .zip(base.par_chunks(CHUNK_LEN))
            .enumerate()
            .for_each(|(c, (o, b))| lincomb_chunk(o, b, h, coeffs, stages, c * CHUNK_LEN));
    }
}

/// Preallocated stage derivatives `k[0..s]` and the stage-argument buffer of an explicit Runge-Kutta stepper.
#[derive(Clone, Debug)]
pub(crate) struct StageBuffers {
    /// Stage derivatives `k_j = f(t + c_j h, Y_j)`, each of the state's length.
    pub(crate) k: Vec<Vec<f64>>,
    /// Stage argument `Y_j`, or the new state after [`StageBuffers::combine`].
    pub(crate) temp: Vec<f64>,
}

impl StageBuffers {
    /// Buffers for `stages` stages over a state of `dimension` elements.
    pub(crate) fn new(stages: usize, dimension: usize) -> Self {
        Self {
            k: vec![vec![0.0; dimension]; stages],
            temp: vec![0.0; dimension],
        }
    }

    /// Evaluates stages 2..s of an explicit Runge-Kutta step from `(t, y)` with step `h`; `k[0]` must
    /// already hold `f(t, y)`. `a[i]` holds the `i` coefficients of stage `i` on stages `0..i`. Returns the
    /// number of right-hand-side evaluations (s - 1).
    pub(crate) fn eval<S: OdeSystem + ?Sized>(
        &mut self,
        system: &S,
        t: f64,
        y: &[f64],
        h: f64,
        c: &[f64],
        a: &[&[f64]],
    ) -> usize {
        for i in 1..c.len() {
            let (done, rest) = self.k.split_at_mut(i);
            lincomb(&mut self.temp, y, h, a[i], done);
            system.derivative(t + c[i] * h, &self.temp, &mut rest[0]);
        }
        c.len() - 1
    }

    /// Writes `y + h * sum_j b[j] k_j` into `temp`.
    pub(crate) fn combine(&mut self, y: &[f64], h: f64, b: &[f64]) {
        lincomb(&mut self.temp, y, h, b, &self.k);
    }
}
