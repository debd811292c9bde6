//! The squared-distance prefilter of a fixed-radius grid query: which of a batch of up to
//! [`SCAN_BATCH`] candidates lie within the reach, by squared distance. Three copies that give the
//! same answers: a portable branch-free loop (one candidate per iteration); on x86-64 CPUs with
//! AVX-512F, AVX-512VL and POPCNT (detected at run time), eight candidates per instruction with
//! their passing slots compressed into place; and on x86-64 CPUs with AVX2 and POPCNT but not those,
//! four candidates per instruction, their passing slots moved to the front by a byte shuffle from a
//! table of the sixteen outcomes. All compute `dx² + dy² + dz²` with the same IEEE operations in the
//! same order (no fused multiply-add), so they pass exactly the same candidates.

use std::mem::MaybeUninit;

use super::SCAN_BATCH;

/// A batch of candidates: their coordinates (m, one length, at most [`SCAN_BATCH`]) from storage slot
/// `first_slot` on.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Candidates<'a> {
    pub xs: &'a [f64],
    pub ys: &'a [f64],
    pub zs: &'a [f64],
    pub first_slot: u32,
}

/// Which copy of the prefilter a grid runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Prefilter {
    /// The portable loop (any CPU).
    Portable,
    /// AVX-512F + AVX-512VL, eight candidates at a time (x86-64 only; falls back to the portable loop
    /// on a CPU without them).
    Avx512,
    /// AVX2, four candidates at a time (x86-64 only; falls back to the portable loop on a CPU without
    /// it).
    Avx2,
}

impl Default for Prefilter {
    /// The fastest copy this CPU runs.
    fn default() -> Self {
        if avx512_available() {
            Prefilter::Avx512
        } else if avx2_available() {
            Prefilter::Avx2
        } else {
            Prefilter::Portable
        }
    }
}

/// Whether this CPU runs the AVX2 copy.
pub(crate) fn avx2_available() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("popcnt")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Whether this CPU runs the AVX-512 copy.
pub(crate) fn avx512_available() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx512f")
            && std::arch::is_x86_feature_detected!("avx512vl")
            && std::arch::is_x86_feature_detected!("popcnt")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

impl Prefilter {
    /// The AVX-512 copy's batches when this grid runs that copy on a CPU that has it, else `None` (run
    /// [`PortableBatches`]). Checked once per query, not once per batch.
    #[inline]
    pub(crate) fn avx512(self) -> Option<Avx512Batches> {
        (self == Prefilter::Avx512 && avx512_available()).then_some(Avx512Batches(()))
    }

    /// The AVX2 copy's batches when this grid runs that copy on a CPU that has it, else `None`.
    #[inline]
    pub(crate) fn avx2(self) -> Option<Avx2Batches> {
        (self == Prefilter::Avx2 && avx2_available()).then_some(Avx2Batches(()))
    }
}

/// One copy of the prefilter as a type, so that a query is compiled once per copy with the copy's
/// batches inlined into its row loop.
///
/// # Safety
/// [`Batches::passing`] must write the first entries of `passed`, as many as it returns: the query
/// reads them as initialised.
#[allow(unsafe_code)]
pub(crate) unsafe trait Batches: Copy {
    /// Writes to the front of `passed`, ascending, the storage slots `first_slot + o` of the
    /// `candidates` `(xs[o], ys[o], zs[o])` whose squared distance from `p` (m) is at most `reach2`
    /// (m²), and returns how many there are (at most the number of candidates).
    ///
    /// # Panics
    /// If the slices differ in length or are longer than [`SCAN_BATCH`].
    fn passing(
        self,
        candidates: Candidates<'_>,
        p: [f64; 3],
        reach2: f64,
        passed: &mut [MaybeUninit<u32>; SCAN_BATCH],
    ) -> usize;
}

/// The portable copy's batches (any CPU).
#[derive(Clone, Copy, Debug)]
pub(crate) struct PortableBatches;

// SAFETY: `passing_portable` writes every entry below the count it returns.
#[allow(unsafe_code)]
unsafe impl Batches for PortableBatches {
    #[inline(always)]
    fn passing(
        self,
        candidates: Candidates<'_>,
        p: [f64; 3],
        reach2: f64,
        passed: &mut [MaybeUninit<u32>; SCAN_BATCH],
    ) -> usize {
        check_lengths(candidates);
        passing_portable(candidates, p, reach2, passed)
    }
}

/// The AVX-512 copy's batches: a value exists only on a CPU with AVX-512F, AVX-512VL and POPCNT
/// (made by [`Prefilter::avx512`] after the run-time check), which is what makes its batches safe to
/// run.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Avx512Batches(());

// SAFETY: `passing_avx512` stores eight slots at each running count below the count it returns,
// and the portable fallback writes every entry below its count.
#[allow(unsafe_code)]
unsafe impl Batches for Avx512Batches {
    #[inline(always)]
    #[allow(unsafe_code)]
    fn passing(
        self,
        candidates: Candidates<'_>,
        p: [f64; 3],
        reach2: f64,
        passed: &mut [MaybeUninit<u32>; SCAN_BATCH],
    ) -> usize {
        check_lengths(candidates);
        #[cfg(target_arch = "x86_64")]
        {
            // SAFETY: `self` exists, so the CPU has AVX-512F, AVX-512VL and POPCNT, the only features
            // the function enables; the lengths were checked above.
            unsafe { passing_avx512(candidates, p, reach2, passed) }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            passing_portable(candidates, p, reach2, passed)
        }
    }
}

/// The AVX2 copy's batches: a value exists only on a CPU with AVX2 and POPCNT (made by
/// [`Prefilter::avx2`] after the run-time check), which is what makes its batches safe to run.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Avx2Batches(());

// SAFETY: `passing_avx2` stores four slots at each running count for every whole group of four and
// writes the rest one by one, every entry below the count it returns.
#[allow(unsafe_code)]
unsafe impl Batches for Avx2Batches {
    #[inline(always)]
    #[allow(unsafe_code)]
    fn passing(
        self,
        candidates: Candidates<'_>,
        p: [f64; 3],
        reach2: f64,
        passed: &mut [MaybeUninit<u32>; SCAN_BATCH],
    ) -> usize {
        check_lengths(candidates);
        #[cfg(target_arch = "x86_64")]
        {
            // SAFETY: `self` exists, so the CPU has AVX2 and POPCNT, the only features the function
            // enables; the lengths were checked above.
            unsafe { passing_avx2(candidates, p, reach2, passed) }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            passing_portable(candidates, p, reach2, passed)
        }
    }
}

/// Panics unless the three coordinate slices have one length, at most [`SCAN_BATCH`].
#[inline(always)]
fn check_lengths(candidates: Candidates<'_>) {
    let n = candidates.xs.len();
    assert!(candidates.ys.len() == n && candidates.zs.len() == n && n <= SCAN_BATCH);
}

/// The portable copy: each candidate's slot is written, and the count advances only when it passes
/// (no branch: most candidates fail, unpredictably).
fn passing_portable(
    candidates: Candidates<'_>,
    p: [f64; 3],
    reach2: f64,
    passed: &mut [MaybeUninit<u32>; SCAN_BATCH],
) -> usize {
    passing_portable_from(candidates, p, reach2, passed, 0, 0)
}

/// The portable loop over the candidates from offset `start` on, appending at `count` (the slots
/// passed before `start`); returns the new count.
#[inline(always)]
fn passing_portable_from(
    candidates: Candidates<'_>,
    p: [f64; 3],
    reach2: f64,
    passed: &mut [MaybeUninit<u32>; SCAN_BATCH],
    start: usize,
    mut count: usize,
) -> usize {
    let Candidates {
        xs,
        ys,
        zs,
        first_slot,
    } = candidates;
    let (xs, ys, zs) = (&xs[start..], &ys[start..], &zs[start..]);
    for (k, ((&x, &y), &z)) in xs.iter().zip(ys).zip(zs).enumerate() {
        let (dx, dy, dz) = (x - p[0], y - p[1], z - p[2]);
        passed[count].write(first_slot + (start + k) as u32);
        count += usize::from(dx * dx + dy * dy + dz * dz <= reach2);
    }
    count
}

/// For each 4-bit outcome of four candidates (bit `l`: candidate `l` passes), the byte shuffle that moves
/// the passing candidates' 32-bit slots, in order, to the front of a 128-bit register.
#[cfg(target_arch = "x86_64")]
const COMPRESS_4: [[u8; 16]; 16] = {
    let mut table = [[0x80; 16]; 16];
    let mut mask = 0;
    while mask < 16 {
        let mut to = 0;
        let mut lane = 0;
        while lane < 4 {
            if mask & (1 << lane) != 0 {
                let mut byte = 0;
                while byte < 4 {
                    table[mask][4 * to + byte] = (4 * lane + byte) as u8;
                    byte += 1;
                }
                to += 1;
            }
            lane += 1;
        }
        mask += 1;
    }
    table
};

/// The AVX2 copy: four candidates per step, the passing lanes' slots shuffled to the front of a
/// 128-bit register and stored at the current count; the candidates after the last whole group of
/// four by the portable loop.
///
/// # Safety
/// The CPU must have AVX2 and POPCNT; the three coordinate slices must have one length, at most
/// [`SCAN_BATCH`].
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,popcnt")]
#[allow(unsafe_code)]
#[inline]
unsafe fn passing_avx2(
    candidates: Candidates<'_>,
    p: [f64; 3],
    reach2: f64,
    passed: &mut [MaybeUninit<u32>; SCAN_BATCH],
) -> usize {
    use std::arch::x86_64::*;
    let Candidates {
        xs,
        ys,
        zs,
        first_slot,
    } = candidates;
    let n = xs.len();
    let (px, py, pz) = (
        _mm256_set1_pd(p[0]),
        _mm256_set1_pd(p[1]),
        _mm256_set1_pd(p[2]),
    );
    let r2 = _mm256_set1_pd(reach2);
    // Slots are below 2^28 (`MAX_POINTS`), so they fit the 32-bit lanes.
    let mut slots = _mm_add_epi32(
        _mm_set1_epi32(first_slot as i32),
        _mm_setr_epi32(0, 1, 2, 3),
    );
    let four = _mm_set1_epi32(4);
    let mut count = 0usize;
    let mut start = 0usize;
    while start + 4 <= n {
        // SAFETY: lanes start..start + 4 are inside the slices (equal lengths, checked by the
        // caller).
        let (x, y, z) = unsafe {
            (
                _mm256_loadu_pd(xs.as_ptr().add(start)),
                _mm256_loadu_pd(ys.as_ptr().add(start)),
                _mm256_loadu_pd(zs.as_ptr().add(start)),
            )
        };
        let (dx, dy, dz) = (
            _mm256_sub_pd(x, px),
            _mm256_sub_pd(y, py),
            _mm256_sub_pd(z, pz),
        );
        // (dx² + dy²) + dz², as the portable copy sums.
        let d2 = _mm256_add_pd(
            _mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)),
            _mm256_mul_pd(dz, dz),
        );
        let pass = _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_LE_OQ>(d2, r2)) as usize;
        // SAFETY: the table row is 16 bytes; count <= start and start + 4 <= n <= SCAN_BATCH, so the
        // four stored u32 fit in `passed`.
        unsafe {
            let shuffle = _mm_loadu_si128(COMPRESS_4[pass].as_ptr().cast());
            _mm_storeu_si128(
                passed.as_mut_ptr().add(count).cast::<__m128i>(),
                _mm_shuffle_epi8(slots, shuffle),
            );
        }
        count += pass.count_ones() as usize;
        slots = _mm_add_epi32(slots, four);
        start += 4;
    }
    passing_portable_from(candidates, p, reach2, passed, start, count)
}

/// The AVX-512 copy: eight candidates per step (the last step masked), the passing lanes' slots
/// compressed to the front of a 256-bit register and stored at the current count.
///
/// # Safety
/// The CPU must have AVX-512F, AVX-512VL and POPCNT; the three coordinate slices must have one
/// length, at most [`SCAN_BATCH`].
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,popcnt")]
#[allow(unsafe_code)]
#[inline]
unsafe fn passing_avx512(
    candidates: Candidates<'_>,
    p: [f64; 3],
    reach2: f64,
    passed: &mut [MaybeUninit<u32>; SCAN_BATCH],
) -> usize {
    use std::arch::x86_64::*;
    let Candidates {
        xs,
        ys,
        zs,
        first_slot,
    } = candidates;
    let n = xs.len();
    let (px, py, pz) = (
        _mm512_set1_pd(p[0]),
        _mm512_set1_pd(p[1]),
        _mm512_set1_pd(p[2]),
    );
    let r2 = _mm512_set1_pd(reach2);
    // Slots are below 2^28 (`MAX_POINTS`), so they fit the 32-bit lanes.
    let mut slots = _mm256_add_epi32(
        _mm256_set1_epi32(first_slot as i32),
        _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7),
    );
    let eight = _mm256_set1_epi32(8);
    let mut count = 0usize;
    let mut start = 0usize;
    while start < n {
        let lanes = (n - start).min(8);
        let live: __mmask8 = (0xffu16 >> (8 - lanes)) as u8;
        // SAFETY: the masked loads touch only lanes start..start + lanes, inside the slices (equal
        // lengths, checked by the caller).
        let (x, y, z) = unsafe {
            (
                _mm512_maskz_loadu_pd(live, xs.as_ptr().add(start)),
                _mm512_maskz_loadu_pd(live, ys.as_ptr().add(start)),
                _mm512_maskz_loadu_pd(live, zs.as_ptr().add(start)),
            )
        };
        let (dx, dy, dz) = (
            _mm512_sub_pd(x, px),
            _mm512_sub_pd(y, py),
            _mm512_sub_pd(z, pz),
        );
        // (dx² + dy²) + dz², as the portable copy sums.
        let d2 = _mm512_add_pd(
            _mm512_add_pd(_mm512_mul_pd(dx, dx), _mm512_mul_pd(dy, dy)),
            _mm512_mul_pd(dz, dz),
        );
        let pass = _mm512_mask_cmp_pd_mask::<_CMP_LE_OQ>(live, d2, r2);
        // SAFETY: `start` is a multiple of 8 below n <= SCAN_BATCH (a multiple of 8), so
        // count <= start <= SCAN_BATCH - 8 and the eight stored u32 fit in `passed`.
        unsafe {
            _mm256_storeu_si256(
                passed.as_mut_ptr().add(count).cast::<__m256i>(),
                _mm256_maskz_compress_epi32(pass, slots),
            );
        }
        count += pass.count_ones() as usize;
        slots = _mm256_add_epi32(slots, eight);
        start += 8;
    }
    count
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// Every copy of the prefilter this CPU runs.
    pub(in crate::grid) fn copies() -> Vec<Prefilter> {
        let mut copies = vec![Prefilter::Portable];
        if avx512_available() {
            copies.push(Prefilter::Avx512);
        }
        if avx2_available() {
            copies.push(Prefilter::Avx2);
        }
        copies
    }

    /// Uniform draws in [0, 1) from a xorshift64 generator seeded with `seed` (test data only).
    pub(in crate::grid) fn uniform_draws(mut state: u64) -> impl FnMut() -> f64 {
        move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// Every copy passes exactly the candidates a plain `<=` test on the squared distance passes, in
    /// ascending order, for every batch length from 0 to SCAN_BATCH and candidates exactly at the reach.
    #[test]
    fn every_copy_passes_what_the_plain_test_passes() {
        let mut uniform = uniform_draws(0x9e37_79b9_7f4a_7c15);
        let p = [1.5, -2.0, 0.25];
        let reach2 = 1.0;
        for n in 0..=SCAN_BATCH {
            let mut xs = Vec::new();
            let (mut ys, mut zs) = (Vec::new(), Vec::new());
            for k in 0..n {
                if k % 5 == 0 {
                    // Exactly at the reach along one axis.
                    xs.push(p[0] + 1.0);
                    ys.push(p[1]);
                    zs.push(p[2]);
                } else {
                    xs.push(p[0] + 3.0 * uniform() - 1.5);
                    ys.push(p[1] + 3.0 * uniform() - 1.5);
                    zs.push(p[2] + 3.0 * uniform() - 1.5);
                }
            }
            let first_slot = 1000 * n as u32;
            let expected: Vec<u32> = (0..n)
                .filter(|&o| {
                    let (dx, dy, dz) = (xs[o] - p[0], ys[o] - p[1], zs[o] - p[2]);
                    dx * dx + dy * dy + dz * dz <= reach2
                })
                .map(|o| first_slot + o as u32)
                .collect();
            for copy in copies() {
                let mut passed = [MaybeUninit::new(u32::MAX); SCAN_BATCH];
                let candidates = Candidates {
                    xs: &xs,
                    ys: &ys,
                    zs: &zs,
                    first_slot,
                };
                let count = match (copy.avx512(), copy.avx2()) {
                    (Some(avx512), _) => avx512.passing(candidates, p, reach2, &mut passed),
                    (_, Some(avx2)) => avx2.passing(candidates, p, reach2, &mut passed),
                    _ => PortableBatches.passing(candidates, p, reach2, &mut passed),
                };
                // SAFETY: every entry was initialised above.
                #[allow(unsafe_code)]
                let passed: Vec<u32> = passed[..count]
                    .iter()
                    .map(|s| unsafe { s.assume_init() })
                    .collect();
                assert_eq!(passed, expected, "{copy:?}, n = {n}");
            }
        }
    }
}
