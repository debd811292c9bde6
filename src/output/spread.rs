//! The spread of an outcome over runs: median and the 5 % and 95 % percentiles, for tables that summarise
//! many runs (`satflock compare`, campaigns).
//!
//! **Percentile method.** Linear interpolation between order statistics (Hyndman & Fan's definition 7,
//! the default of NumPy, R and Excel's `PERCENTILE.INC`): of the n values sorted ascending, x₀ ≤ … ≤
//! x_{n−1}, the p-quantile is x_⌊h⌋ + (h − ⌊h⌋)(x_{⌊h⌋+1} − x_⌊h⌋) with h = (n − 1) p. It is the
//! minimum at p = 0, the maximum at p = 1 and the usual median at p = 0.5; with one value, that value.
//! Values that do not exist (NaN: a failed run, an outcome the run does not have) are left out and
//! counted apart.

/// Median and 5–95 % spread of the finite values of a sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spread {
    /// Number of values that exist (finite).
    pub count: usize,
    /// 5 % percentile (NaN when `count` is 0).
    pub p05: f64,
    /// Median (NaN when `count` is 0).
    pub median: f64,
    /// 95 % percentile (NaN when `count` is 0).
    pub p95: f64,
}

impl Spread {
    /// The spread of `values`, leaving out those that are not finite.
    pub fn of(values: &[f64]) -> Self {
        let mut sorted: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
        sorted.sort_by(f64::total_cmp);
        Self {
            count: sorted.len(),
            p05: percentile_sorted(&sorted, 0.05),
            median: percentile_sorted(&sorted, 0.5),
            p95: percentile_sorted(&sorted, 0.95),
        }
    }
}

/// The p-quantile (0 ≤ p ≤ 1) of values sorted ascending, by linear interpolation between order
/// statistics (the module's method); NaN for an empty slice.
pub fn percentile_sorted(sorted: &[f64], p: f64) -> f64 {
    let Some(last) = sorted.len().checked_sub(1) else {
        return f64::NAN;
    };
    let h = last as f64 * p.clamp(0.0, 1.0);
    let lo = h.floor() as usize;
    let hi = (lo + 1).min(last);
    sorted[lo] + (h - lo as f64) * (sorted[hi] - sorted[lo])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_match_hand_computed_values() {
        // 1..=10: h = 9 p. p = 0.05: h = 0.45 → 1 + 0.45 (2 − 1) = 1.45; median h = 4.5 → 5.5;
        // p = 0.95: h = 8.55 → 9 + 0.55 = 9.55 (NumPy gives the same: 1.45, 5.5, 9.55).
        let values: Vec<f64> = (1..=10).rev().map(f64::from).collect();
        let s = Spread::of(&values);
        assert_eq!(s.count, 10);
        assert!((s.p05 - 1.45).abs() < 1e-12, "{}", s.p05);
        assert_eq!(s.median, 5.5);
        assert!((s.p95 - 9.55).abs() < 1e-12, "{}", s.p95);
        // Three values 10, 20, 40 with a NaN left out: h = 2 p. p = 0.05: h = 0.1 → 10 + 0.1·10 = 11;
        // median h = 1 → 20; p = 0.95: h = 1.9 → 20 + 0.9·20 = 38.
        let s = Spread::of(&[40.0, f64::NAN, 10.0, 20.0]);
        assert_eq!(s.count, 3);
        assert!((s.p05 - 11.0).abs() < 1e-12);
        assert_eq!(s.median, 20.0);
        assert!((s.p95 - 38.0).abs() < 1e-12);
        // One value is every percentile; none gives NaN.
        let s = Spread::of(&[-3.0]);
        assert_eq!((s.p05, s.median, s.p95), (-3.0, -3.0, -3.0));
        let s = Spread::of(&[f64::NAN, f64::INFINITY]);
        assert_eq!(s.count, 0);
        assert!(s.median.is_nan() && s.p05.is_nan() && s.p95.is_nan());
        // Ends: minimum and maximum.
        assert_eq!(percentile_sorted(&[1.0, 2.0, 4.0], 0.0), 1.0);
        assert_eq!(percentile_sorted(&[1.0, 2.0, 4.0], 1.0), 4.0);
    }
}
