//! Well-conditioned trigonometric kernels used by the closed-form transition matrices.
//!
//! With `θ = ω t`, the closed forms need `sin θ / ω`, `(1 − cos θ) / ω²` and `(θ − sin θ) / ω³`.
//! Written naively these lose digits (or divide by zero) when `θ` is small. They are computed here
//! as `t · sinc(θ)`, `t² · cosc(θ)` and `t³ · sinc3(θ)`, which are accurate for every `θ`, including
//! `ω = 0`.

/// `sin θ / θ` \[-\], with the limit 1 at `θ = 0`.
pub(crate) fn sinc(theta: f64) -> f64 {
    // Below 1e-4 the two-term series is exact to ~θ⁶/5040 ≈ 2e-28, far under one ulp of 1.
    if theta.abs() < 1e-4 {
        let t2 = theta * theta;
        1.0 - t2 / 6.0 * (1.0 - t2 / 20.0)
    } else {
        theta.sin() / theta
    }
}

/// `(1 − cos θ) / θ²` \[-\], with the limit 1/2 at `θ = 0`.
///
/// Uses `1 − cos θ = 2 sin²(θ/2)`, which has no cancellation.
pub(crate) fn cosc(theta: f64) -> f64 {
    let half = sinc(0.5 * theta);
    0.5 * half * half
}

/// `(θ − sin θ) / θ³` \[-\], with the limit 1/6 at `θ = 0`.
pub(crate) fn sinc3(theta: f64) -> f64 {
    if theta.abs() < 1.0 {
        sinc3_series(theta)
    } else {
        sinc3_direct(theta)
    }
}

/// Taylor series of `sinc3`, `Σ_k (−1)^k θ^(2k) / (2k+3)!`, nested as
/// `(1/6)·[1 − θ²/(4·5)·(1 − θ²/(6·7)·(1 − …))]` and kept through `θ¹⁴`. For `|θ| ≤ 1` the first
/// omitted term, `θ¹⁶/19! ≤ 8.2e-18`, is 5e-17 of the leading 1/6: below rounding.
fn sinc3_series(theta: f64) -> f64 {
    let t2 = theta * theta;
    let mut acc = 1.0;
    for k in (1..=7).rev() {
        let m = f64::from(2 * k + 2) * f64::from(2 * k + 3);
        acc = 1.0 - t2 * acc / m;
    }
    acc / 6.0
}

/// `sinc3` from its definition. For `|θ| ≥ 1` the subtraction loses at most a factor
/// `1/(1 − sin 1) ≈ 6.3` in relative accuracy, i.e. about 1.4e-15.
fn sinc3_direct(theta: f64) -> f64 {
    (theta - theta.sin()) / (theta * theta * theta)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_at_zero() {
        assert_eq!(sinc(0.0), 1.0);
        assert_eq!(cosc(0.0), 0.5);
        assert_eq!(sinc3(0.0), 1.0 / 6.0);
    }

    #[test]
    fn series_and_direct_branches_agree_at_the_switch() {
        // At θ = 1 the direct formula is accurate to ~1.4e-15 (see sinc3_direct) and the series to
        // rounding, so the two must agree to a few 1e-15 relative.
        let (series, direct) = (sinc3_series(1.0), sinc3_direct(1.0));
        assert!(
            (series - direct).abs() / direct < 4e-15,
            "{series} vs {direct}"
        );
        // sinc's switch: the direct quotient has no cancellation, so agreement is to rounding.
        let (b, a) = (sinc(1e-4 - 1e-16), sinc(1e-4 + 1e-16));
        assert!((b - a).abs() < 4.0 * f64::EPSILON, "{b} vs {a}");
    }

    #[test]
    fn match_reference_values() {
        // Reference values computed in double precision with the exact definitions at θ = 2, where
        // no cancellation occurs, and from the Taylor series at θ = 0.1 by hand:
        // (0.1 − sin 0.1)/0.001 = 1/6 − 0.01/120 + 1e-4/5040 − … = 0.16658335317…, summed below.
        let t = 2.0_f64;
        assert!((sinc(t) - t.sin() / t).abs() < 1e-16);
        assert!((cosc(t) - (1.0 - t.cos()) / (t * t)).abs() < 1e-16);
        assert!((sinc3(t) - (t - t.sin()) / (t * t * t)).abs() < 1e-16);
        let expected =
            1.0 / 6.0 - 0.01 / 120.0 + 1e-4 / 5040.0 - 1e-6 / 362_880.0 + 1e-8 / 39_916_800.0;
        // Remaining series terms are below 1e-10/13! = 1.6e-20; 1e-16 is a few ulp of 0.167.
        assert!((sinc3(0.1) - expected).abs() < 1e-16);
    }
}
