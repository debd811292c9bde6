//! The exponential function of the one-layer atmosphere ([`exp_lanes`], over a block of lanes; one
//! lane in the generic path), written in plain IEEE arithmetic so that the compiler vectorises it
//! inside the fused kernel's lane loops (`f64::exp` is a library call per lane there, five times the
//! cost of the whole J2 step), and the generic path calls the same arithmetic: both paths keep the
//! same bits.
//!
//! Table-driven (the scheme of Tang, ACM TOMS 15(2), 1989, in the form of ARM's optimized-routines
//! `exp`): `x = (64 k + j) ln 2 / 64 + r`, `|r| <= ln 2 / 128`, `e^x = 2^k 2^(j/64) e^r`, with
//! `2^(j/64)` from a table of 64 entries and `e^r` from a polynomial of degree 5. It replaced a
//! degree-11 polynomial on `|r| <= ln 2 / 2` (issue 24, round 3): 24 operations per call instead of
//! 35, and within 1 ulp of `f64::exp` instead of 2.
//!
//! How the lanes read the table is the one thing that differs between the copies ([`ExpTable`]): by
//! index ([`IndexedExpTable`]; a gather in the AVX2 and AVX-512 copies of a lane loop), or, in the
//! fused kernel's AVX-512 copy, by permuting the table's columns held in 512-bit registers
//! ([`PermutedExpTable`]), because gathers are slow on some CPUs (AMD Zen 4: the two gathers were 30 %
//! of the drag kernel's time). Both read the same entries, so the results are the same bits.

/// 1.5 · 2^52: adding and subtracting it rounds a double of magnitude below 2^51 to the nearest
/// integer (ties to even), and leaves that integer in the low bits of the sum.
const ROUND: f64 = 6_755_399_441_055_744.0;
/// Table entries per octave (2^6).
const TABLE_BITS: u32 = 6;
const TABLE_SIZE: usize = 1 << TABLE_BITS;
/// 64 / ln 2.
const TABLE_OVER_LN2: f64 = TABLE_SIZE as f64 * std::f64::consts::LOG2_E;
/// ln 2 / 64 split in two (fdlibm's `ln2HI`, `ln2LO` over 64, exact scalings): `k · LN2_HI_OVER`
/// is exact for |k| < 2^21 (here |k| <= 65 500).
const LN2_HI_OVER: f64 = f64::from_bits(0x3fe6_2e42_fee0_0000) / TABLE_SIZE as f64;
const LN2_LO_OVER: f64 = f64::from_bits(0x3dea_39ef_3579_3c76) / TABLE_SIZE as f64;
/// `e^r = 1 + r + r^2 (c0 + c1 r + c2 r^2 + c3 r^3)` on |r| <= ln 2 / 128: a Chebyshev fit of
/// (e^r - 1 - r) / r^2 of degree 3 (mpmath's `chebyfit` at 50 digits, rounded to doubles). Relative
/// error of `1 + r + r^2 p(r)` against e^r, coefficients rounded: 4.4e-18 (0.04 ulp).
const POLY: [f64; 4] = [
    0.499_999_999_999_850_73,
    0.166_666_666_666_645_34,
    0.041_666_707_395_191_96,
    0.008_333_339_151_693_497,
];
/// For j = 0..63: `(tail, bits)` with `hi = 2^(j/64)` rounded to a double, `tail = (2^(j/64) - hi) / hi`
/// rounded (|tail| < 2^-53), and `bits` = the bits of `hi` minus `j << 46`, so that adding the
/// reduced argument's integer shifted by 46 gives the bits of `2^k hi` directly (the layout of ARM's
/// optimized-routines). Checked against double-double arithmetic in the tests.
const TABLE: [(f64, u64); TABLE_SIZE] = [
    (0.0, 0x3ff0_0000_0000_0000),
    (-1.507066976926039e-17, 0x3fef_ec9a_3e77_8061),
    (4.9997448722726326e-17, 0x3fef_d9b0_d315_8574),
    (7.357846871247418e-18, 0x3fef_c745_1875_9bc8),
    (8.189317638195515e-17, 0x3fef_b558_6cf9_890f),
    (1.6665881442326747e-18, 0x3fef_a3ec_32d3_d1a2),
    (-7.402825309426177e-17, 0x3fef_9301_d012_5b51),
    (-6.170654745608695e-17, 0x3fef_829a_aea9_2de0),
    (-2.7939114859515733e-17, 0x3fef_72b8_3c7d_517b),
    (4.776959425256223e-17, 0x3fef_635b_eb6f_cb75),
    (9.341710609905046e-17, 0x3fef_5487_3168_b9aa),
    (4.585670326662351e-17, 0x3fef_463b_8862_8cd6),
    (7.826573258636076e-17, 0x3fef_387a_6e75_6238),
    (2.823784425951061e-17, 0x3fef_2b45_65e2_7cdd),
    (3.2904726646008416e-17, 0x3fef_1e9d_f51f_dee1),
    (4.721368121170128e-17, 0x3fef_1285_a6e4_030b),
    (3.3484623336251524e-17, 0x3fef_06fe_0a31_b715),
    (5.527550048505249e-17, 0x3fee_fc08_b264_16ff),
    (-6.346552106729483e-17, 0x3fee_f1a7_373a_a9cb),
    (-1.5456342819397733e-17, 0x3fee_e7db_34e5_9ff7),
    (3.750854201303127e-17, 0x3fee_dea6_4c12_3422),
    (-5.346099009198751e-18, 0x3fee_d60a_21f7_2e2a),
    (2.1023049675215714e-18, 0x3fee_ce08_6061_892d),
    (1.3357510088834541e-17, 0x3fee_c6a2_b5c1_3cd0),
    (1.9572585293112036e-17, 0x3fee_bfda_d536_2a27),
    (-5.478069123926778e-17, 0x3fee_b9b2_769d_2ca7),
    (-2.1571477251208752e-17, 0x3fee_b42b_569d_4f82),
    (6.663804589232195e-17, 0x3fee_af47_36b5_27da),
    (5.68648095791174e-17, 0x3fee_ab07_dd48_5429),
    (7.007875046906994e-17, 0x3fee_a76f_15ad_2148),
    (-4.8923067513522756e-17, 0x3fee_a47e_b03a_5585),
    (-6.872303720902018e-17, 0x3fee_a238_8255_2225),
    (-6.835808657661922e-17, 0x3fee_a09e_667f_3bcd),
    (-8.416011634717156e-18, 0x3fee_9fb2_3c65_1a2f),
    (-2.092304381843353e-17, 0x3fee_9f75_e8ec_5f74),
    (-3.833464968654295e-17, 0x3fee_9feb_5642_67c9),
    (-2.3591094770850053e-17, 0x3fee_a114_73eb_0187),
    (9.50689710108796e-18, 0x3fee_a2f3_36cf_4e62),
    (-6.735219232374683e-17, 0x3fee_a589_994c_ce13),
    (-7.226635472101257e-17, 0x3fee_a8d9_9b44_92ed),
    (5.1548301170786783e-17, 0x3fee_ace5_422a_a0db),
    (2.4253985766689806e-17, 0x3fee_b1ae_9915_7736),
    (-6.432131775424189e-18, 0x3fee_b737_b0cd_c5e5),
    (-6.336161863401293e-17, 0x3fee_bd82_9fde_4e50),
    (1.5341410053603723e-17, 0x3fee_c491_82a3_f090),
    (-4.123367330661149e-17, 0x3fee_cc66_7b5d_e565),
    (-6.152602891550265e-17, 0x3fee_d503_b23e_255d),
    (3.540948262646183e-17, 0x3fee_de6b_5579_fdbf),
    (4.875160526227062e-17, 0x3fee_e89f_995a_d3ad),
    (-4.719539664590972e-18, 0x3fee_f3a2_b84f_15fb),
    (-1.0772487078934056e-17, 0x3fee_ff76_f2fb_5e47),
    (1.821405440362259e-17, 0x3fef_0c1e_904b_c1d2),
    (1.685487290628973e-17, 0x3fef_199b_dd85_529c),
    (3.621615935336894e-17, 0x3fef_27f1_2e57_d14b),
    (1.01562190116415e-17, 0x3fef_3720_dcef_9069),
    (-5.495118966122005e-17, 0x3fef_472d_4a07_897c),
    (1.790126907604513e-17, 0x3fef_5818_dcfb_a487),
    (5.265370768556274e-17, 0x3fef_69e6_03db_3285),
    (-3.266924100901318e-17, 0x3fef_7c97_337b_9b5f),
    (1.7963932659833022e-17, 0x3fef_902e_e78b_3ff6),
    (-5.545065618639427e-17, 0x3fef_a4af_a2a4_90da),
    (5.336805878514151e-17, 0x3fef_ba1b_ee61_5a27),
    (4.5784915277060095e-17, 0x3fef_d076_5b6e_4540),
    (2.0414278897578303e-17, 0x3fef_e7c1_819e_90d8),
];
/// The argument range: beyond it the result would leave the normal doubles.
const MIN_ARG: f64 = -708.0;
const MAX_ARG: f64 = 709.0;

/// e^x of each of `L` lanes, the table read by `table` (the same bits whichever reads it): for x in
/// \[−708, 709\] (arguments outside are clamped to that range: e^−708 ≈ 3e−308, a density of zero for
/// every purpose; e^709 ≈ 8e307), NaN for NaN; within 1 ulp of `f64::exp` (tested). Tang's
/// table-driven reduction `x = (64 k + j) ln 2 / 64 + r` (module documentation),
/// `e^x = 2^k hi_j (1 + q)` with `q = tail_j + r + r^2 p(r)`, formed as `s + s q` with `s = 2^k hi_j`
/// (so the rounding of `hi_j` is corrected by its tail). No fused multiply-add: the portable copy of
/// the fused kernel and the generic path would call the library's `fma` per operation.
#[inline(always)]
pub(crate) fn exp_lanes<const L: usize>(x: &[f64; L], table: impl ExpTable) -> [f64; L] {
    let mut shifted_bits = [0_u64; L];
    let mut reduced = [0.0; L];
    for l in 0..L {
        let x = x[l].clamp(MIN_ARG, MAX_ARG);
        let shifted = x * TABLE_OVER_LN2 + ROUND;
        let k = shifted - ROUND;
        reduced[l] = (x - k * LN2_HI_OVER) - k * LN2_LO_OVER;
        // 64 k + j is in the low bits of `shifted` (two's complement): j indexes the table, the rest
        // shifted into the exponent field gives 2^k.
        shifted_bits[l] = shifted.to_bits();
    }
    let (tails, bits) = table.entries(&shifted_bits);
    let mut out = [0.0; L];
    for l in 0..L {
        let (r, ki) = (reduced[l], shifted_bits[l]);
        let r2 = r * r;
        let p = (POLY[0] + POLY[1] * r) + (POLY[2] + POLY[3] * r) * r2;
        let q = (tails[l] + r) + r2 * p;
        let scale = f64::from_bits(bits[l].wrapping_add(ki << (52 - TABLE_BITS)));
        out[l] = scale + scale * q;
    }
    out
}

/// How the lanes of [`exp_lanes`] read the table: for each lane, the entry `(tail, bits)` at the low
/// [`TABLE_BITS`] bits of its index. Every implementation returns the same entries.
pub(crate) trait ExpTable: Copy {
    /// The entries at `indices[l] mod 64`, as `(tails, bits)`.
    fn entries<const L: usize>(self, indices: &[u64; L]) -> ([f64; L], [u64; L]);
}

/// The table read lane by lane by index (any CPU; a gather in a vectorised lane loop).
#[derive(Clone, Copy, Debug)]
pub(crate) struct IndexedExpTable;

impl ExpTable for IndexedExpTable {
    #[inline(always)]
    fn entries<const L: usize>(self, indices: &[u64; L]) -> ([f64; L], [u64; L]) {
        let mut tails = [0.0; L];
        let mut bits = [0; L];
        for l in 0..L {
            (tails[l], bits[l]) = entry(indices[l]);
        }
        (tails, bits)
    }
}

/// The table's entry `(tail, bits)` at `index mod 64`.
#[inline(always)]
fn entry(index: u64) -> (f64, u64) {
    TABLE[(index & (TABLE_SIZE as u64 - 1)) as usize]
}

/// The table read eight lanes at a time by permuting its columns (AVX-512F): a value exists only on a
/// CPU with AVX-512F (made by [`PermutedExpTable::new`] after the run-time check), which is what makes
/// its reads safe to run. Lanes beyond the last multiple of eight are read by index.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PermutedExpTable(());

impl PermutedExpTable {
    /// The permuted read, if this CPU has AVX-512F.
    pub(crate) fn new() -> Option<Self> {
        #[cfg(target_arch = "x86_64")]
        {
            std::arch::is_x86_feature_detected!("avx512f").then_some(Self(()))
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            None
        }
    }
}

impl ExpTable for PermutedExpTable {
    #[inline(always)]
    #[cfg_attr(not(target_arch = "x86_64"), allow(unused_mut))]
    fn entries<const L: usize>(self, indices: &[u64; L]) -> ([f64; L], [u64; L]) {
        let mut tails = [0.0; L];
        let mut bits = [0; L];
        let mut start = 0;
        #[cfg(target_arch = "x86_64")]
        while start + 8 <= L {
            let eight = indices[start..start + 8].try_into().expect("eight lanes");
            #[allow(unsafe_code)]
            // SAFETY: `self` exists, so the CPU has AVX-512F, the only feature the function enables.
            let (t, b) = unsafe { permuted_entries(eight) };
            tails[start..start + 8].copy_from_slice(&t);
            bits[start..start + 8].copy_from_slice(&b);
            start += 8;
        }
        for l in start..L {
            (tails[l], bits[l]) = entry(indices[l]);
        }
        (tails, bits)
    }
}

/// The table's two columns as bits, `[tails, bits]`, each read by the permuted copy as four pairs of
/// 512-bit registers.
const COLUMNS: [[u64; TABLE_SIZE]; 2] = {
    let mut columns = [[0; TABLE_SIZE]; 2];
    let mut j = 0;
    while j < TABLE_SIZE {
        columns[0][j] = TABLE[j].0.to_bits();
        columns[1][j] = TABLE[j].1;
        j += 1;
    }
    columns
};

/// The entries at `indices mod 64` of eight lanes, as `(tails, bits)`.
///
/// # Safety
/// The CPU must have AVX-512F.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
#[allow(unsafe_code)]
#[inline]
unsafe fn permuted_entries(indices: &[u64; 8]) -> ([f64; 8], [u64; 8]) {
    use std::arch::x86_64::_mm512_loadu_si512;
    // SAFETY: one whole `[u64; 8]`, unaligned access allowed.
    let lanes = unsafe { _mm512_loadu_si512(indices.as_ptr().cast()) };
    // SAFETY: the caller's CPU has AVX-512F.
    let (tails, bits) = unsafe {
        (
            permuted_column(&COLUMNS[0], lanes),
            permuted_column(&COLUMNS[1], lanes),
        )
    };
    (tails.map(f64::from_bits), bits)
}

/// Entries `indices mod 64` of one column for eight lanes: the column's 64 entries are four pairs of
/// 512-bit registers; a two-source permute picks from each pair by an index's low four bits, and bits
/// 4 and 5 choose among the four pairs.
///
/// # Safety
/// The CPU must have AVX-512F.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
#[allow(unsafe_code)]
#[inline]
unsafe fn permuted_column(
    column: &[u64; TABLE_SIZE],
    indices: std::arch::x86_64::__m512i,
) -> [u64; 8] {
    use std::arch::x86_64::*;
    // SAFETY: the column is 64 u64, so the four pairs of blocks of eight from `column[16 p]` are in
    // it; unaligned access allowed.
    let pair = |p: usize| unsafe {
        let first = column.as_ptr().add(16 * p).cast::<__m512i>();
        _mm512_permutex2var_epi64(
            _mm512_loadu_si512(first),
            indices,
            _mm512_loadu_si512(first.add(1)),
        )
    };
    let pairs = [pair(0), pair(1), pair(2), pair(3)];
    let bit4 = _mm512_test_epi64_mask(indices, _mm512_set1_epi64(16));
    let bit5 = _mm512_test_epi64_mask(indices, _mm512_set1_epi64(32));
    let low = _mm512_mask_blend_epi64(bit4, pairs[0], pairs[1]);
    let high = _mm512_mask_blend_epi64(bit4, pairs[2], pairs[3]);
    let mut out = [0_u64; 8];
    // SAFETY: one whole `[u64; 8]`, unaligned access allowed.
    unsafe {
        _mm512_storeu_si512(
            out.as_mut_ptr().cast(),
            _mm512_mask_blend_epi64(bit5, low, high),
        )
    };
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// e^x of one lane, the table read by index (the generic path's call).
    fn exp(x: f64) -> f64 {
        exp_lanes(&[x], IndexedExpTable)[0]
    }

    /// The permuted read gives every entry the indexed read gives, whatever the bits above the index
    /// (the reduced argument's integer and sign are there), in whole blocks of eight and in the lanes
    /// after the last block; and so `exp_lanes` gives the same bits either way. On a CPU without
    /// AVX-512F there is no permuted read to compare.
    #[test]
    fn the_permuted_read_gives_the_indexed_entries() {
        #[cfg(target_arch = "x86_64")]
        assert_eq!(
            PermutedExpTable::new().is_some(),
            std::arch::is_x86_feature_detected!("avx512f")
        );
        let Some(permuted) = PermutedExpTable::new() else {
            return;
        };
        let mut indices = [0_u64; 19];
        let mut high = 0x9e37_79b9_7f4a_7c15_u64;
        for start in 0..64 {
            for (l, index) in indices.iter_mut().enumerate() {
                high = high.rotate_left(7) ^ 0x2545_f491_4f6c_dd1d;
                *index = (high << TABLE_BITS) | ((start + 5 * l as u64) % 64);
            }
            let (tails, bits) = permuted.entries(&indices);
            let (want_tails, want_bits) = IndexedExpTable.entries(&indices);
            assert_eq!(bits, want_bits, "indices {indices:x?}");
            assert_eq!(tails.map(f64::to_bits), want_tails.map(f64::to_bits));
        }
        let xs: [f64; 16] = std::array::from_fn(|l| -40.0 + 5.3 * l as f64 + 0.011 * l as f64);
        assert_eq!(
            exp_lanes(&xs, permuted).map(f64::to_bits),
            exp_lanes(&xs, IndexedExpTable).map(f64::to_bits)
        );
    }

    /// Within 1 ulp of the library's `exp` (itself within 1 ulp of the true value) over the whole
    /// range, densely where the atmosphere evaluates it (|x| < 40) and at the ends and special values.
    #[test]
    fn within_one_ulp_of_the_library_exp() {
        let mut worst: f64 = 0.0;
        let mut check = |x: f64| {
            let want = x.exp();
            let got = exp(x);
            let ulp = f64::from_bits(want.to_bits() + 1) - want;
            let err = (got - want).abs() / ulp;
            assert!(err <= 1.0, "exp({x}) = {got}, library {want}: {err} ulp");
            worst = worst.max(err);
        };
        for i in 0..=400_000 {
            check(-40.0 + 80.0 * i as f64 / 400_000.0);
        }
        for i in 0..=20_000 {
            check(MIN_ARG + (MAX_ARG - MIN_ARG) * i as f64 / 20_000.0);
        }
        // Every table entry and both ends of its interval of r.
        for j in -200..=200 {
            let centre = j as f64 * std::f64::consts::LN_2 / TABLE_SIZE as f64;
            for offset in [-1.0, -0.999, 0.0, 0.999, 1.0] {
                check(centre + offset * std::f64::consts::LN_2 / (2 * TABLE_SIZE) as f64);
            }
        }
        for x in [0.0, -0.0, 1.0, -1.0, 1e-300, -1e-300, MIN_ARG, MAX_ARG] {
            check(x);
        }
        assert_eq!(exp(0.0), 1.0);
        assert!(worst > 0.0, "the test compares something");
        assert!(exp(f64::NAN).is_nan());
        assert_eq!(exp(-1e6), exp(MIN_ARG));
        assert_eq!(exp(1e6), exp(MAX_ARG));
    }

    /// `hi + hi tail` of every entry, raised to the 64th power in double-double arithmetic (six
    /// squarings, about 1e-31 relative), is 2^j: the table holds 2^(j/64) to about 1e-32 relative, and
    /// each `hi` is in \[1, 2) with its exponent bits offset as the lookup expects.
    #[test]
    fn the_table_holds_the_powers_of_two() {
        /// a * b = p + e exactly (Dekker's product, no fused multiply-add).
        fn two_product(a: f64, b: f64) -> (f64, f64) {
            let split = |v: f64| {
                let c = 134_217_729.0 * v;
                let high = c - (c - v);
                (high, v - high)
            };
            let p = a * b;
            let ((ah, al), (bh, bl)) = (split(a), split(b));
            (p, ((ah * bh - p) + ah * bl + al * bh) + al * bl)
        }
        let square = |(h, l): (f64, f64)| {
            let (p, e) = two_product(h, h);
            let e = e + 2.0 * h * l;
            let s = p + e;
            (s, e - (s - p))
        };
        for (j, &(tail, bits)) in TABLE.iter().enumerate() {
            let hi = f64::from_bits(bits.wrapping_add((j as u64) << (52 - TABLE_BITS)));
            assert!((1.0..2.0).contains(&hi), "entry {j}: {hi}");
            assert!(tail.abs() < f64::EPSILON / 2.0, "entry {j}: tail {tail}");
            let mut v = (hi, hi * tail);
            for _ in 0..TABLE_BITS {
                v = square(v);
            }
            let want = (1u64 << j) as f64;
            let rel = ((v.0 - want) + v.1).abs() / want;
            assert!(rel < 1e-29, "entry {j}: (2^(j/64))^64 off by {rel}");
        }
    }
}
