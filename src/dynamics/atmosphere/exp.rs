//! The exponential function of the one-layer atmosphere ([`exp`]), written in plain IEEE arithmetic so
//! that the compiler vectorises it inside the fused kernel's lane loops (`f64::exp` is a library call
//! per lane there, five times the cost of the whole J2 step), and the generic path calls the same
//! function: both paths keep the same bits.

/// 1.5 · 2^52: adding and subtracting it rounds a double of magnitude below 2^51 to the nearest
/// integer (ties to even), and leaves that integer in the low bits of the sum.
const ROUND: f64 = 6_755_399_441_055_744.0;
/// 1 / ln 2.
const INV_LN2: f64 = std::f64::consts::LOG2_E;
/// ln 2 split in two (fdlibm's `ln2HI`, `ln2LO`): `k · LN2_HI` is exact for |k| < 2^11.
const LN2_HI: f64 = f64::from_bits(0x3fe6_2e42_fee0_0000);
const LN2_LO: f64 = f64::from_bits(0x3dea_39ef_3579_3c76);
/// The coefficients of e^r on |r| <= ln 2 / 2, degree 11: 1, 1, then a Chebyshev fit of
/// (e^r - 1 - r) / r^2 of degree 9 (mpmath's `chebyfit` at 60 digits, rounded to doubles). Relative
/// error of the polynomial itself, coefficients rounded: 1.6e-17 (Taylor needs degree 13 for 4e-18).
const POLY: [f64; 12] = [
    1.0,
    1.0,
    0.5000000000000001,
    0.16666666666666669,
    0.041666666666624164,
    0.008333333333330065,
    0.0013888888917196719,
    0.00019841269863040545,
    2.4801521322368692e-05,
    2.7557268480310024e-06,
    2.7620075879983367e-07,
    2.5100375832561234e-08,
];
/// The argument range: beyond it the result would leave the normal doubles.
const MIN_ARG: f64 = -708.0;
const MAX_ARG: f64 = 709.0;

/// e^x for x in \[−708, 709\] (arguments outside are clamped to that range: e^−708 ≈ 3e−308, a
/// density of zero for every purpose; e^709 ≈ 8e307), NaN for NaN; within 2 ulp of the correctly
/// rounded value (tested against `f64::exp`). Cody–Waite reduction x = k ln 2 + r, |r| ≤ ln 2 / 2,
/// and a polynomial of degree 11 for e^r (relative error 1.6e-17, by Estrin's scheme), scaled by
/// 2^k through the exponent bits. No fused multiply-add: the portable copy of the fused kernel and
/// the generic path would call the library's `fma` per operation.
#[inline(always)]
pub fn exp(x: f64) -> f64 {
    let x = x.clamp(MIN_ARG, MAX_ARG);
    let shifted = x * INV_LN2 + ROUND;
    let k = shifted - ROUND;
    let r = (x - k * LN2_HI) - k * LN2_LO;
    // The polynomial by Estrin's scheme: pairs, then pairs of pairs in r^2, r^4, r^8 (a dependency
    // chain of 8 operations instead of Horner's 22: the fused kernel is latency-bound).
    let r2 = r * r;
    let r4 = r2 * r2;
    let r8 = r4 * r4;
    let pair = |j: usize| POLY[j] + POLY[j + 1] * r;
    let low = (pair(0) + pair(2) * r2) + (pair(4) + pair(6) * r2) * r4;
    let high = pair(8) + pair(10) * r2;
    let p = low + high * r8;
    // k is in the low bits of `shifted` (two's complement); 2^k from the exponent field.
    let k_bits = shifted.to_bits().wrapping_add(1023) << 52;
    p * f64::from_bits(k_bits)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Within 2 ulp of the library's `exp` (itself within 1 ulp of the true value) over the whole
    /// range, densely where the atmosphere evaluates it (|x| < 40) and at the ends and special values.
    #[test]
    fn within_two_ulp_of_the_library_exp() {
        let mut worst: f64 = 0.0;
        let mut check = |x: f64| {
            let want = x.exp();
            let got = exp(x);
            let ulp = f64::from_bits(want.to_bits() + 1) - want;
            let err = (got - want).abs() / ulp;
            assert!(err <= 2.0, "exp({x}) = {got}, library {want}: {err} ulp");
            worst = worst.max(err);
        };
        for i in 0..=400_000 {
            check(-40.0 + 80.0 * i as f64 / 400_000.0);
        }
        for i in 0..=20_000 {
            check(MIN_ARG + (MAX_ARG - MIN_ARG) * i as f64 / 20_000.0);
        }
        for x in [
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.5 * LN2_HI,
            -0.5 * LN2_HI,
            1e-300,
            MIN_ARG,
            MAX_ARG,
        ] {
            check(x);
        }
        assert_eq!(exp(0.0), 1.0);
        assert!(worst > 0.0, "the test compares something");
        assert!(exp(f64::NAN).is_nan());
        assert_eq!(exp(-1e6), exp(MIN_ARG));
    }
}
