//! Butcher tableaux of embedded explicit Runge-Kutta pairs, as `const` data.

/// An embedded explicit Runge-Kutta pair: `s` stages
/// `k_i = f(t + c_i h, y + h sum_{j<i} a_ij k_j)`, the propagated solution `y_new = y + h sum_i b_i k_i`,
/// and the local error estimate `e = h sum_i b_error_i k_i`.
///
/// All coefficients are dimensionless. Implemented by unit structs ([`Rkf78`], [`Dop853`]) and used as the
/// type parameter of [`AdaptiveStepper`](super::AdaptiveStepper).
pub trait ButcherTableau {
    /// Number of stages `s` (right-hand-side evaluations per step).
    const STAGES: usize;
    /// Order of the propagated solution (the `B` weights).
    const ORDER: u8;
    /// Order of the embedded companion solution whose difference with `B` gives `B_ERROR`.
    const EMBEDDED_ORDER: u8;
    /// Order `q` of the step-size controller: the local error estimate behaves as `h^(q+1)`, and the next
    /// step is scaled by `err^(-1/(q+1))`. By default the lower of `ORDER` and `EMBEDDED_ORDER`.
    const ERROR_ORDER: u8 = if Self::ORDER < Self::EMBEDDED_ORDER {
        Self::ORDER
    } else {
        Self::EMBEDDED_ORDER
    };
    /// Nodes `c_i`, length `STAGES`.
    const C: &'static [f64];
    /// Strictly lower-triangular coupling coefficients: row `i` holds `a_i0 .. a_i(i-1)` (row 0 is empty).
    const A: &'static [&'static [f64]];
    /// Weights `b_i` of the propagated solution, length `STAGES`.
    const B: &'static [f64];
    /// Error weights `b_i - b_hat_i`, length `STAGES`, where `b_hat` is the embedded companion solution.
    const B_ERROR: &'static [f64];
    /// Second, lower-order error weights, for Hairer's combined error estimator (DOP853 only): with
    /// `err_hi` and `err_lo` the norms of `sum B_ERROR_i k_i` and `sum B_ERROR_LOW_i k_i`, the error is
    /// `h err_hi^2 / sqrt(err_hi^2 + 0.01 err_lo^2)`. `None` for a classical pair (`err = h err_hi`).
    const B_ERROR_LOW: Option<&'static [f64]> = None;
}

/// Runge-Kutta-Fehlberg 7(8): 13 stages; the **8th-order** solution is propagated (local extrapolation)
/// and the step is controlled by the estimated error of the 7th-order solution, which bounds the error of
/// the 8th-order one.
///
/// Fehlberg's paper propagates the 7th-order solution. Local extrapolation (as in Boost.Odeint's
/// `runge_kutta_fehlberg78`) is chosen here because at the same tolerance it conserves the two-body energy
/// about 80 times better (relative drift 2.8e-12 instead of 2.3e-10 over 10 orbits, e = 0.1, rtol 1e-12; see
/// `tests/val_integrate.rs`), at no extra cost.
///
/// Caveat, inherited from the pair: the error estimate `(41/840) h (k_12 + k_13 - k_1 - k_11)` vanishes
/// when `f` depends on `t` only (pure quadrature), since stages 1 and 12 and stages 11 and 13 share their
/// nodes; the step is then controlled by the maximum step alone.
///
/// Coefficients: E. Fehlberg, "Classical fifth-, sixth-, seventh-, and eighth-order Runge-Kutta formulas
/// with stepsize control", NASA TR R-287, 1968, Table X (RK7(8)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Rkf78;

impl ButcherTableau for Rkf78 {
    const STAGES: usize = 13;
    const ORDER: u8 = 8;
    const EMBEDDED_ORDER: u8 = 7;
    const C: &'static [f64] = &[
        0.0,
        2.0 / 27.0,
        1.0 / 9.0,
        1.0 / 6.0,
        5.0 / 12.0,
        1.0 / 2.0,
        5.0 / 6.0,
        1.0 / 6.0,
        2.0 / 3.0,
        1.0 / 3.0,
        1.0,
        0.0,
        1.0,
    ];
    const A: &'static [&'static [f64]] = &[
        &[],
        &[2.0 / 27.0],
        &[1.0 / 36.0, 1.0 / 12.0],
        &[1.0 / 24.0, 0.0, 1.0 / 8.0],
        &[5.0 / 12.0, 0.0, -25.0 / 16.0, 25.0 / 16.0],
        &[1.0 / 20.0, 0.0, 0.0, 1.0 / 4.0, 1.0 / 5.0],
        &[
            -25.0 / 108.0,
            0.0,
            0.0,
            125.0 / 108.0,
            -65.0 / 27.0,
            125.0 / 54.0,
        ],
        &[
            31.0 / 300.0,
            0.0,
            0.0,
            0.0,
            61.0 / 225.0,
            -2.0 / 9.0,
            13.0 / 900.0,
        ],
        &[
            2.0,
            0.0,
            0.0,
            -53.0 / 6.0,
            704.0 / 45.0,
            -107.0 / 9.0,
            67.0 / 90.0,
            3.0,
        ],
        &[
            -91.0 / 108.0,
            0.0,
            0.0,
            23.0 / 108.0,
            -976.0 / 135.0,
            311.0 / 54.0,
            -19.0 / 60.0,
            17.0 / 6.0,
            -1.0 / 12.0,
        ],
        &[
            2383.0 / 4100.0,
            0.0,
            0.0,
            -341.0 / 164.0,
            4496.0 / 1025.0,
            -301.0 / 82.0,
            2133.0 / 4100.0,
            45.0 / 82.0,
            45.0 / 164.0,
            18.0 / 41.0,
        ],
        &[
            3.0 / 205.0,
            0.0,
            0.0,
            0.0,
            0.0,
            -6.0 / 41.0,
            -3.0 / 205.0,
            -3.0 / 41.0,
            3.0 / 41.0,
            6.0 / 41.0,
            0.0,
        ],
        &[
            -1777.0 / 4100.0,
            0.0,
            0.0,
            -341.0 / 164.0,
            4496.0 / 1025.0,
            -289.0 / 82.0,
            2193.0 / 4100.0,
            51.0 / 82.0,
            33.0 / 164.0,
            12.0 / 41.0,
            0.0,
            1.0,
        ],
    ];
    const B: &'static [f64] = &[
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        34.0 / 105.0,
        9.0 / 35.0,
        9.0 / 35.0,
        9.0 / 280.0,
        9.0 / 280.0,
        0.0,
        41.0 / 840.0,
        41.0 / 840.0,
    ];
    const B_ERROR: &'static [f64] = &[
        -41.0 / 840.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        -41.0 / 840.0,
        41.0 / 840.0,
        41.0 / 840.0,
    ];
}

/// Dormand-Prince 8(5,3) ("DOP853"): 12 stages; the 8th-order solution is propagated, and the step is
/// controlled by Hairer's combined estimate from the embedded 5th- and 3rd-order solutions
/// ([`ButcherTableau::B_ERROR_LOW`]), which behaves as `h^8`.
///
/// Coefficients: E. Hairer, S. P. Nørsett, G. Wanner, *Solving Ordinary Differential Equations I*, 2nd ed.,
/// Springer 1993, Section II.10, as published in Hairer's code `dop853.f` (constants `c2..c12`, `a21..a1211`,
/// `b1..b12`, `bhh1..bhh3`, `er1..er12`). The 3 extra stages for dense output are not used.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Dop853;

/// DOP853 weights `b_1 .. b_12` (`dop853.f`), shared by `B` and `B_ERROR_LOW`.
const DOP853_B: [f64; 12] = [
    5.429_373_411_656_876e-2,
    0.0,
    0.0,
    0.0,
    0.0,
    4.450_312_892_752_409,
    1.891_517_899_314_500_4,
    -5.801_203_960_010_585,
    3.111_643_669_578_199e-1,
    -1.521_609_496_625_161e-1,
    2.013_654_008_040_303_4e-1,
    4.471_061_572_777_259e-2,
];

/// DOP853 weights of the 3rd-order solution, `bhh1, bhh2, bhh3` on stages 1, 9 and 12 (`dop853.f`).
const DOP853_BHH: [f64; 3] = [
    0.244_094_488_188_976_4,
    0.733_846_688_281_611_9,
    0.220_588_235_294_117_65e-1,
];

impl ButcherTableau for Dop853 {
    const STAGES: usize = 12;
    const ORDER: u8 = 8;
    const EMBEDDED_ORDER: u8 = 5;
    const ERROR_ORDER: u8 = 7;
    const C: &'static [f64] = &[
        0.0,
        0.526_001_519_587_677_3e-1,
        0.789_002_279_381_516e-1,
        0.118_350_341_907_227_4,
        0.281_649_658_092_772_6,
        1.0 / 3.0,
        0.25,
        4.0 / 13.0,
        127.0 / 195.0,
        0.6,
        6.0 / 7.0,
        1.0,
    ];
    const A: &'static [&'static [f64]] = &[
        &[],
        &[5.260_015_195_876_773e-2],
        &[1.972_505_698_453_79e-2, 5.917_517_095_361_37e-2],
        &[2.958_758_547_680_685e-2, 0.0, 8.876_275_643_042_055e-2],
        &[
            2.413_651_341_592_667e-1,
            0.0,
            -8.845_494_793_282_861e-1,
            9.248_340_032_617_92e-1,
        ],
        &[
            3.703_703_703_703_703_5e-2,
            0.0,
            0.0,
            1.708_286_087_294_738_6e-1,
            1.254_676_875_668_224_2e-1,
        ],
        &[
            3.710_937_5e-2,
            0.0,
            0.0,
            1.702_522_110_195_440_4e-1,
            6.021_653_898_045_596e-2,
            -1.757_812_5e-2,
        ],
        &[
            3.709_200_011_850_479e-2,
            0.0,
            0.0,
            1.703_839_257_122_4e-1,
            1.072_620_304_463_732_8e-1,
            -1.531_943_774_862_440_2e-2,
            8.273_789_163_814_023e-3,
        ],
        &[
            6.241_109_587_160_757e-1,
            0.0,
            0.0,
            -3.360_892_629_446_941_4,
            -8.682_193_468_417_26e-1,
            2.759_209_969_944_671e1,
            2.015_406_755_047_789_4e1,
            -4.348_988_418_106_996e1,
        ],
        &[
            4.776_625_364_382_643_6e-1,
            0.0,
            0.0,
            -2.488_114_619_971_667_7,
            -5.902_908_268_368_43e-1,
            2.123_005_144_818_119_4e1,
            1.527_923_363_288_242_4e1,
            -3.328_821_096_898_486e1,
            -2.033_120_170_850_862_7e-2,
        ],
        &[
            -9.371_424_300_859_873e-1,
            0.0,
            0.0,
            5.186_372_428_844_064,
            1.091_437_348_996_729_5,
            -8.149_787_010_746_927,
            -1.852_006_565_999_696e1,
            2.273_948_709_935_050_5e1,
            2.493_605_552_679_652_4,
            -3.046_764_471_898_219_5,
        ],
        &[
            2.273_310_147_516_538,
            0.0,
            0.0,
            -1.053_449_546_673_725e1,
            -2.000_872_058_224_862_5,
            -1.795_893_186_311_88e1,
            2.794_888_452_941_996e1,
            -2.858_998_277_135_023_7,
            -8.872_856_933_530_63,
            1.236_056_717_579_430_3e1,
            6.433_927_460_157_636e-1,
        ],
    ];
    const B: &'static [f64] = &DOP853_B;
    const B_ERROR: &'static [f64] = &[
        0.131_200_449_941_948_8e-1,
        0.0,
        0.0,
        0.0,
        0.0,
        -0.122_515_644_637_620_44e1,
        -0.495_758_949_657_250_2,
        0.166_437_718_245_498_65e1,
        -0.350_328_848_749_973_7,
        0.334_179_118_713_017_5,
        0.819_232_064_851_157_1e-1,
        -0.223_553_078_638_862_95e-1,
    ];
    const B_ERROR_LOW: Option<&'static [f64]> = Some(&[
        DOP853_B[0] - DOP853_BHH[0],
        0.0,
        0.0,
        0.0,
        0.0,
        DOP853_B[5],
        DOP853_B[6],
        DOP853_B[7],
        DOP853_B[8] - DOP853_BHH[1],
        DOP853_B[9],
        DOP853_B[10],
        DOP853_B[11] - DOP853_BHH[2],
    ]);
}

/// The stability function of the method's propagated solution on the test equation `y' = λ y` at a
/// real `z = h λ`: stages `Y_i = 1 + z Σ_{j<i} a_ij Y_j`, `R(z) = 1 + z Σ_i b_i Y_i` (explicit, so
/// `R` is the polynomial `1 + z bᵀ (I − z A)⁻¹ 𝟙`).
pub fn stability_function<T: ButcherTableau>(z: f64) -> f64 {
    let mut stages = [0.0; 16];
    assert!(T::STAGES <= stages.len(), "at most 16 stages");
    for i in 0..T::STAGES {
        let coupling: f64 = T::A[i].iter().zip(&stages).map(|(a, y)| a * y).sum();
        stages[i] = 1.0 + z * coupling;
    }
    1.0 + z * T::B.iter().zip(&stages).map(|(b, y)| b * y).sum::<f64>()
}

/// How far the method is stable along the negative real axis: the smallest `h |λ|` at which
/// `|R(−h |λ|)|` ([`stability_function`]) exceeds 1, found by a scan in steps of 1e-3 and refined by
/// bisection to 1e-9. An explicit method on a closed loop of rate `k` \[1/s\] needs `h k` below it,
/// whatever its error control asks.
pub fn real_stability_bound<T: ButcherTableau>() -> f64 {
    let unstable = |x: f64| stability_function::<T>(-x).abs() > 1.0;
    let mut x = 0.0;
    while !unstable(x + 1e-3) {
        x += 1e-3;
    }
    let (mut stable, mut beyond) = (x, x + 1e-3);
    while beyond - stable > 1e-9 {
        let mid = 0.5 * (stable + beyond);
        if unstable(mid) {
            beyond = mid;
        } else {
            stable = mid;
        }
    }
    stable
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Classical RK4 as a tableau, only to check the stability computations against RK4's known
    /// polynomial and interval.
    struct ClassicalRk4;

    impl ButcherTableau for ClassicalRk4 {
        const STAGES: usize = 4;
        const ORDER: u8 = 4;
        const EMBEDDED_ORDER: u8 = 3;
        const C: &'static [f64] = &[0.0, 0.5, 0.5, 1.0];
        const A: &'static [&'static [f64]] = &[&[], &[0.5], &[0.0, 0.5], &[0.0, 0.0, 1.0]];
        const B: &'static [f64] = &[1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0];
        const B_ERROR: &'static [f64] = &[0.0; 4];
    }

    #[test]
    fn stability_function_is_the_exponential_to_the_methods_order() {
        // RK4: R(z) = 1 + z + z^2/2 + z^3/6 + z^4/24 exactly.
        for z in [-2.5, -1.0, -0.3, 0.7] {
            let want = 1.0 + z + z * z / 2.0 + z * z * z / 6.0 + z * z * z * z / 24.0;
            assert!((stability_function::<ClassicalRk4>(z) - want).abs() < 1e-14);
        }
        // The eighth-order pairs: R(z) - e^z = O(z^9); at z = -0.05 that is ~ 0.05^9 / 9! = 5e-18,
        // below rounding: |R - e^z| < 1e-15. A wrong coefficient in A or B breaks an order condition
        // and shows at 1e-12 or more.
        for z in [-0.05, 0.05] {
            assert!((stability_function::<Dop853>(z) - z.exp()).abs() < 1e-15);
            assert!((stability_function::<Rkf78>(z) - z.exp()).abs() < 1e-15);
        }
    }

    /// Stable at 101 points from 0 to `bound`, unstable just beyond.
    fn check_interval<T: ButcherTableau>(bound: f64) {
        assert!(
            (0..=100).all(|k| stability_function::<T>(-(k as f64) * bound / 100.0).abs() <= 1.0)
        );
        assert!(stability_function::<T>(-(bound + 1e-6)).abs() > 1.0);
    }

    #[test]
    fn real_stability_bounds() {
        // RK4's interval ends at the real root of |1 + z + z^2/2 + z^3/6 + z^4/24| = 1 below zero,
        // -2.785293563405282 (Hairer & Wanner, Solving ODEs II, section IV.2).
        let rk4 = real_stability_bound::<ClassicalRk4>();
        assert!((rk4 - 2.785_293_563_405_282).abs() < 1e-8, "{rk4}");
        check_interval::<ClassicalRk4>(rk4);
        let dop = real_stability_bound::<Dop853>();
        let rkf = real_stability_bound::<Rkf78>();
        check_interval::<Dop853>(dop);
        check_interval::<Rkf78>(rkf);
        // Eight-order methods with 12 and 13 stages reach further than RK4 along the axis.
        assert!(dop > rk4 && dop < 10.0, "{dop}");
        assert!(rkf > rk4 && rkf < 10.0, "{rkf}");
        eprintln!("real stability bounds: RK4 {rk4:.6}, RKF7(8) {rkf:.6}, DOP853 {dop:.6}");
    }
}
