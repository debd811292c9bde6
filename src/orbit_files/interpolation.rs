//! Interpolation of ephemeris samples: [`Interpolation`] (what an OEM segment's `INTERPOLATION` and
//! `INTERPOLATION_DEGREE` name, and how many samples each needs), the Lagrange polynomial through
//! values ([`lagrange`]) and the Hermite polynomial through values and derivatives ([`hermite`]).
//!
//! Both work on times centred on and scaled by their window (so that the powers stay near 1), which
//! keeps the arithmetic well conditioned for windows of seconds or days.

/// How an OEM segment says its states are to be interpolated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// `INTERPOLATION = LAGRANGE` (or `LINEAR`, degree 1): each of the six components by the
    /// Lagrange polynomial of `degree` through `degree + 1` samples.
    Lagrange {
        /// `INTERPOLATION_DEGREE`.
        degree: usize,
    },
    /// `INTERPOLATION = HERMITE`: positions by the Hermite polynomial through the positions and
    /// velocities of `n = max(2, ⌈(degree + 1) / 2⌉)` samples (its degree, 2n − 1, is the declared
    /// degree or the next odd one), the velocity by its derivative or, when every sample gives
    /// accelerations, by the Hermite polynomial through velocities and accelerations.
    Hermite {
        /// `INTERPOLATION_DEGREE`.
        degree: usize,
    },
}

impl Interpolation {
    /// The samples one interpolation uses.
    pub fn samples(self) -> usize {
        match self {
            Self::Lagrange { degree } => degree + 1,
            Self::Hermite { degree } => (degree + 1).div_ceil(2).max(2),
        }
    }
}

/// Centre and half-width of the nodes `t` (the half-width 1 for a single node).
fn frame(t: &[f64]) -> (f64, f64) {
    let (lo, hi) = (t[0], t[t.len() - 1]);
    let half = 0.5 * (hi - lo);
    (0.5 * (lo + hi), if half > 0.0 { half } else { 1.0 })
}

/// The Lagrange polynomial through `(t[i], y[i])` at `at` (the nodes distinct and increasing).
pub(crate) fn lagrange(t: &[f64], y: &[f64], at: f64) -> f64 {
    let (centre, scale) = frame(t);
    let x = (at - centre) / scale;
    let nodes: Vec<f64> = t.iter().map(|&ti| (ti - centre) / scale).collect();
    let mut sum = 0.0;
    for (j, (&xj, &yj)) in nodes.iter().zip(y).enumerate() {
        let mut weight = 1.0;
        for (m, &xm) in nodes.iter().enumerate() {
            if m != j {
                weight *= (x - xm) / (xj - xm);
            }
        }
        sum += weight * yj;
    }
    sum
}

/// The Hermite polynomial through values `y[i]` and derivatives `dy[i]` at nodes `t[i]` (distinct,
/// increasing): its value and derivative at `at`. Newton's divided differences on the doubled nodes.
pub(crate) fn hermite(t: &[f64], y: &[f64], dy: &[f64], at: f64) -> (f64, f64) {
    let (centre, scale) = frame(t);
    let m = 2 * t.len();
    let z: Vec<f64> = (0..m).map(|i| (t[i / 2] - centre) / scale).collect();
    let mut c: Vec<f64> = (0..m).map(|i| y[i / 2]).collect();
    for j in 1..m {
        for i in (j..m).rev() {
            c[i] = if j == 1 && i % 2 == 1 {
                dy[i / 2] * scale
            } else {
                (c[i] - c[i - 1]) / (z[i] - z[i - j])
            };
        }
    }
    let x = (at - centre) / scale;
    let (mut p, mut dp) = (c[m - 1], 0.0);
    for k in (0..m - 1).rev() {
        dp = dp * (x - z[k]) + p;
        p = p * (x - z[k]) + c[k];
    }
    (p, dp / scale)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A polynomial of the interpolant's degree is reproduced exactly (to rounding).
    #[test]
    fn reproduce_polynomials_of_their_degree() {
        let f = |x: f64| 3.0 - 2.0 * x + 0.5 * x.powi(3) - 0.01 * x.powi(5);
        let df = |x: f64| -2.0 + 1.5 * x.powi(2) - 0.05 * x.powi(4);
        let t: Vec<f64> = (0..6).map(|i| 100.0 + 7.0 * f64::from(i)).collect();
        let y: Vec<f64> = t.iter().map(|&x| f((x - 110.0) / 10.0)).collect();
        let dy: Vec<f64> = t.iter().map(|&x| df((x - 110.0) / 10.0) / 10.0).collect();
        for at in [100.0, 103.3, 117.9, 135.0] {
            let want = f((at - 110.0) / 10.0);
            assert!(
                (lagrange(&t, &y, at) - want).abs() < 1e-11,
                "lagrange at {at}"
            );
            // Three nodes with derivatives: degree 5.
            let (p, dp) = hermite(&t[..3], &y[..3], &dy[..3], at.min(114.0));
            let a = at.min(114.0);
            assert!((p - f((a - 110.0) / 10.0)).abs() < 1e-11, "hermite at {a}");
            assert!(
                (dp - df((a - 110.0) / 10.0) / 10.0).abs() < 1e-11,
                "hermite' at {a}"
            );
        }
    }

    #[test]
    fn samples_per_method() {
        assert_eq!(Interpolation::Lagrange { degree: 5 }.samples(), 6);
        assert_eq!(Interpolation::Hermite { degree: 5 }.samples(), 3);
        assert_eq!(Interpolation::Hermite { degree: 7 }.samples(), 4);
        assert_eq!(Interpolation::Hermite { degree: 1 }.samples(), 2);
        assert_eq!(Interpolation::Hermite { degree: 3 }.samples(), 2);
    }
}
