//! The random-stream derivation (`satflock::random`): thread independence, independence of streams whose
//! coordinates are adjacent (seeds, ticks, satellites, purposes, and the old `seed + step` shift),
//! distribution checks of the draws, campaign sub-seeds, reproducibility.
//!
//! The draws are deterministic, so each statistical check below has a fixed outcome: a tolerance that
//! holds holds forever. The tolerances are still set as significance levels (stated beside each), so that
//! a chance failure would be rare if the derivation changed, and a real defect (a shared or shifted
//! stream gives |r| ≈ 1, a bias of a bit gives a large χ²) is far outside them.

use std::collections::HashSet;

use rand::{Rng, RngExt};
use rand_distr::{Distribution, Normal};
use rayon::prelude::*;
use satflock::random::{sub_seed, Purpose, RandomStream};

/// Draws per sequence in the correlation and distribution checks.
const N: usize = 100_000;

/// Standard deviation of the Pearson correlation of two independent samples of N values: 1/√N.
const R_SIGMA: f64 = 0.003_162_277_660_168_379_5;

/// |r| bound of the issue: 0.01 = 3.16 σ_r, a two-sided significance of 0.16 % per pair. Over the 27
/// lag-0 pairs checked in this file the chance that at least one independent pair exceeds it is ~4 %
/// (a fixed outcome, see the file doc); a shared, shifted or otherwise related stream gives |r| near 1.
const R_MAX: f64 = 0.01;

fn normals(seed: u64, purpose: Purpose, satellite: u64, tick: u64) -> Vec<f64> {
    let mut s = RandomStream::new(seed, purpose, satellite, tick);
    (0..N).map(|_| s.standard_normal()).collect()
}

fn pearson(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        let (dx, dy) = (x - ma, y - mb);
        sab += dx * dy;
        saa += dx * dx;
        sbb += dy * dy;
    }
    sab / (saa * sbb).sqrt()
}

fn assert_uncorrelated(what: &str, a: &[f64], b: &[f64]) {
    let r = pearson(a, b);
    assert!(r.abs() < R_MAX, "{what}: r = {r:.5} (bound {R_MAX})");
}

/// Every satellite's draws are the same whether 1 or 4 threads make them, in whatever order the
/// scheduler visits satellites: each stream is addressed by its coordinates, not by a shared generator.
#[test]
fn val_streams_identical_on_1_and_4_threads() {
    let satellites = 10_000u64;
    let draw = |threads: usize| -> Vec<u64> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            (0..satellites)
                .into_par_iter()
                .flat_map_iter(|i| {
                    // Several purposes and ticks per satellite, through every drawing method.
                    let mut out = Vec::with_capacity(12);
                    for (purpose, tick) in [
                        (Purpose::InitialStates, 0),
                        (Purpose::NavigationNoise, 17),
                        (Purpose::ProcessNoise, 1_000_003),
                        (Purpose::LawUpdate, 5),
                    ] {
                        let mut s = RandomStream::new(42, purpose, i, tick);
                        out.push(s.next_u64());
                        out.push(s.uniform_range(-3.0, 5.0).to_bits());
                        out.push(s.standard_normal().to_bits());
                    }
                    out
                })
                .collect()
        })
    };
    let one = draw(1);
    let four = draw(4);
    assert_eq!(one.len(), 12 * satellites as usize);
    assert!(one == four, "draws differ between 1 and 4 threads");
}

/// Consecutive seeds draw unrelated noise: same purpose, satellite and tick, seeds s and s + 1.
#[test]
fn val_adjacent_seeds_are_uncorrelated() {
    for s in [0u64, 1, 41, 1 << 32, u64::MAX - 1] {
        for purpose in [Purpose::InitialStates, Purpose::NavigationNoise] {
            let a = normals(s, purpose, 3, 10);
            let b = normals(s.wrapping_add(1), purpose, 3, 10);
            assert_uncorrelated(&format!("seeds {s}, {s}+1, {purpose:?}"), &a, &b);
        }
    }
}

/// The failure mode of the former `seed + step` seeding: seed s at tick t + k drew exactly what seed
/// s + 1 drew at tick t + k − 1 (r = 1). Both directions of the shift, k = 1, 2, 3.
#[test]
fn val_adjacent_seeds_shifted_by_a_few_ticks_are_uncorrelated() {
    let (s, t) = (7u64, 100u64);
    let base_s = normals(s, Purpose::NavigationNoise, 0, t);
    let base_s1 = normals(s + 1, Purpose::NavigationNoise, 0, t);
    for k in 1..=3 {
        let shifted_s1 = normals(s + 1, Purpose::NavigationNoise, 0, t + k);
        assert_uncorrelated(
            &format!("seed s tick t vs seed s+1 tick t+{k}"),
            &base_s,
            &shifted_s1,
        );
        let shifted_s = normals(s, Purpose::NavigationNoise, 0, t + k);
        assert_uncorrelated(
            &format!("seed s+1 tick t vs seed s tick t+{k}"),
            &base_s1,
            &shifted_s,
        );
    }
}

/// Negative control: the correlation check does detect the former scheme, where navigation noise came
/// from `ChaCha8Rng::seed_from_u64(seed + step)`: seed s at step t + 1 and seed s + 1 at step t give r = 1.
#[test]
fn val_correlation_check_detects_the_former_seed_plus_step_scheme() {
    use rand::rngs::ChaCha8Rng;
    use rand::SeedableRng;
    let old = |seed: u64, step: u64| -> Vec<f64> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed.wrapping_add(step));
        (0..N)
            .map(|_| rng.sample(rand_distr::StandardNormal))
            .collect()
    };
    let r = pearson(&old(7, 101), &old(8, 100));
    assert!(r > 1.0 - 1e-12, "r = {r}");
}

/// Neither is seed s + 1's sequence seed s's shifted by a few draws: cross-correlation at lags −16..16.
/// 33 lags: the bound is 5 σ_r = 0.0158 (Bonferroni over 33 lags: family-wise significance 2e-5); a
/// shifted copy would give r ≈ 1 at its lag.
#[test]
fn val_adjacent_seeds_have_no_lagged_copy() {
    let a = normals(7, Purpose::ProcessNoise, 2, 0);
    let b = normals(8, Purpose::ProcessNoise, 2, 0);
    let m = N - 16;
    for lag in 0..=16usize {
        for (x, y, dir) in [(&a, &b, "+"), (&b, &a, "-")] {
            let r = pearson(&x[..m], &y[lag..lag + m]);
            assert!(r.abs() < 5.0 * R_SIGMA, "lag {dir}{lag}: r = {r:.5}");
        }
    }
}

/// Adjacent satellites, adjacent ticks and different purposes of one seed are uncorrelated.
#[test]
fn val_adjacent_satellites_ticks_and_purposes_are_uncorrelated() {
    let seed = 12_345;
    let base = normals(seed, Purpose::NavigationNoise, 8, 50);
    for (what, other) in [
        (
            "satellite 9",
            normals(seed, Purpose::NavigationNoise, 9, 50),
        ),
        (
            "satellite 7",
            normals(seed, Purpose::NavigationNoise, 7, 50),
        ),
        ("tick 51", normals(seed, Purpose::NavigationNoise, 8, 51)),
        ("tick 49", normals(seed, Purpose::NavigationNoise, 8, 49)),
        (
            "satellite 9 tick 51",
            normals(seed, Purpose::NavigationNoise, 9, 51),
        ),
    ] {
        assert_uncorrelated(&format!("satellite 8 tick 50 vs {what}"), &base, &other);
    }
    // Satellite 0 tick 0 of every purpose, pairwise.
    let per_purpose: Vec<_> = Purpose::ALL
        .iter()
        .map(|&p| (p, normals(seed, p, 0, 0)))
        .collect();
    for (i, (pa, a)) in per_purpose.iter().enumerate() {
        for (pb, b) in &per_purpose[i + 1..] {
            assert_uncorrelated(&format!("{pa:?} vs {pb:?}"), a, b);
        }
    }
}

/// Standard-normal draws: mean, standard deviation and the two-sided tail mass beyond 2.
#[test]
fn val_standard_normal_moments() {
    for (seed, purpose, satellite, tick) in [
        (1u64, Purpose::NavigationNoise, 0u64, 0u64),
        (2, Purpose::ProcessNoise, 999, 123_456),
        (3, Purpose::LawUpdate, 5, 1),
    ] {
        let x = normals(seed, purpose, satellite, tick);
        let n = x.len() as f64;
        let mean = x.iter().sum::<f64>() / n;
        let std = (x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
        // Mean: standard error 1/√N = 0.00316; within 5 σ.
        assert!(mean.abs() < 5.0 * R_SIGMA, "{purpose:?}: mean {mean:.5}");
        // Standard deviation: standard error of the sample std ≈ 1/√(2N) = 0.0022; 3 % is ≈ 13 σ, the
        // issue's bound, which catches any scaling error (e.g. a variance/std mix-up).
        assert!((std - 1.0).abs() < 0.03, "{purpose:?}: std {std:.5}");
        // P(|x| > 2) = 0.04550; the count is binomial with σ = √(N p (1 − p)) = 65.9; within 5 σ.
        // Checks the ziggurat's tails, which mean and std barely see.
        let tail = x.iter().filter(|v| v.abs() > 2.0).count() as f64;
        let p = 0.045_500_263_896_358_4;
        let sigma = (n * p * (1.0 - p)).sqrt();
        assert!(
            (tail - n * p).abs() < 5.0 * sigma,
            "{purpose:?}: {tail} draws beyond ±2, expected {:.0} ± {sigma:.0}",
            n * p
        );
    }
}

/// Uniform draws lie in [0, 1) and pass a χ² test on 20 equal bins.
#[test]
fn val_uniform_chi_square_20_bins() {
    for (seed, satellite, tick) in [(1u64, 0u64, 0u64), (2, 17, 3), (1 << 40, 1 << 33, 77)] {
        let mut s = RandomStream::new(seed, Purpose::InitialStates, satellite, tick);
        let mut bins = [0u64; 20];
        for _ in 0..N {
            let u = s.uniform();
            assert!((0.0..1.0).contains(&u), "u = {u}");
            bins[(u * 20.0) as usize] += 1;
        }
        let expected = N as f64 / 20.0;
        let chi2: f64 = bins
            .iter()
            .map(|&c| (c as f64 - expected).powi(2) / expected)
            .sum();
        // 19 degrees of freedom: the 0.1 % and 99.9 % quantiles are 5.407 and 43.82 (two-sided
        // significance 0.2 %). Too small a χ² (too even a histogram) is as suspect as too large.
        assert!(
            (5.407..43.82).contains(&chi2),
            "seed {seed}: chi2 = {chi2:.2}, bins {bins:?}"
        );
    }
}

/// `uniform_range` maps [0, 1) affinely: draws within [lo, hi], mean (lo + hi)/2 within 5 standard errors.
#[test]
fn val_uniform_range() {
    let (lo, hi) = (-3.0, 5.0);
    let mut s = RandomStream::new(9, Purpose::LawUpdate, 1, 2);
    let x: Vec<f64> = (0..N).map(|_| s.uniform_range(lo, hi)).collect();
    assert!(x.iter().all(|v| (lo..=hi).contains(v)));
    let mean = x.iter().sum::<f64>() / N as f64;
    // Standard error: (hi − lo)/√12/√N = 0.0073.
    let se = (hi - lo) / 12f64.sqrt() / (N as f64).sqrt();
    assert!((mean - 1.0).abs() < 5.0 * se, "mean {mean}");
}

/// `rand` and `rand_distr` distributions draw from a `RandomStream` (it is a `rand::Rng`).
#[test]
fn val_rand_distributions_draw_from_a_stream() {
    let mut s = RandomStream::new(4, Purpose::ProcessNoise, 0, 0);
    let normal = Normal::new(10.0, 2.0).unwrap();
    let x: Vec<f64> = (0..N).map(|_| normal.sample(&mut s)).collect();
    let mean = x.iter().sum::<f64>() / N as f64;
    // Standard error 2/√N = 0.0063; within 5 σ.
    assert!((mean - 10.0).abs() < 5.0 * 2.0 * R_SIGMA, "mean {mean}");
    let k: u32 = s.random_range(0..10);
    assert!(k < 10);
    assert!(s.words_used() > 2 * N as u64);
}

/// `sub_seed` has no collisions over 10⁶ indices (it is a bijection in the index), and campaigns with
/// adjacent parent seeds share no run seed.
#[test]
fn val_sub_seed_collision_free_and_unrelated_across_parents() {
    let count = 1_000_000u64;
    let mut previous: Option<HashSet<u64>> = None;
    for parent in [0u64, 1, 2, 3] {
        let seeds: HashSet<u64> = (0..count).map(|i| sub_seed(parent, i)).collect();
        assert_eq!(seeds.len(), count as usize, "parent {parent}: collisions");
        if let Some(prev) = &previous {
            // Adjacent parents: any shared value would be an accident of probability ≈ 2·10¹²/2⁶⁴ ≈ 1e-7
            // for unrelated sequences; a shifted sequence (the `seed + index` mistake) would share ~10⁶.
            let shared = seeds.intersection(prev).count();
            assert_eq!(
                shared,
                0,
                "parents {} and {parent} share {shared} sub-seeds",
                parent - 1
            );
        }
        previous = Some(seeds);
    }
    for parent in [u64::MAX, 1 << 63] {
        let seeds: HashSet<u64> = (0..count).map(|i| sub_seed(parent, i)).collect();
        assert_eq!(seeds.len(), count as usize, "parent {parent}: collisions");
    }
}

/// Sub-seeds look uniform bit by bit: each of the 64 bits is set in a fraction 1/2 ± 5 σ of 10⁶ run seeds
/// (σ = 0.5/√10⁶ = 0.0005; 64 bits × 5 σ: family-wise significance 4e-5); the same index under adjacent
/// parents differs in about 32 bits.
#[test]
fn val_sub_seed_bits_are_balanced() {
    let count = 1_000_000u64;
    let mut set = [0u64; 64];
    let mut differing_bits = 0u64;
    for i in 0..count {
        let v = sub_seed(5, i);
        for (b, c) in set.iter_mut().enumerate() {
            *c += (v >> b) & 1;
        }
        differing_bits += u64::from((v ^ sub_seed(6, i)).count_ones());
    }
    for (b, &c) in set.iter().enumerate() {
        let f = c as f64 / count as f64;
        assert!((f - 0.5).abs() < 5.0 * 0.0005, "bit {b}: fraction {f}");
    }
    // Mean Hamming distance: 32 with σ = 4/√10⁶ = 0.004; within 0.1.
    let mean = differing_bits as f64 / count as f64;
    assert!((mean - 32.0).abs() < 0.1, "mean Hamming distance {mean}");
}

/// The same coordinates give the same bytes, twice; any changed coordinate gives different bytes.
#[test]
fn val_reproducible_and_distinct() {
    let bytes = |seed, purpose, satellite, tick| {
        let mut s = RandomStream::new(seed, purpose, satellite, tick);
        let mut b = vec![0u8; 4096];
        s.fill_bytes(&mut b);
        b
    };
    let reference = bytes(3, Purpose::NavigationNoise, 11, 29);
    assert_eq!(reference, bytes(3, Purpose::NavigationNoise, 11, 29));
    for other in [
        bytes(4, Purpose::NavigationNoise, 11, 29),
        bytes(3, Purpose::ProcessNoise, 11, 29),
        bytes(3, Purpose::NavigationNoise, 12, 29),
        bytes(3, Purpose::NavigationNoise, 11, 30),
    ] {
        assert_ne!(reference, other);
    }
}

/// Golden values: the derivation is part of every run's reproducibility, so a change to it (key, stream
/// id, word position, tags) must be deliberate. If this fails, every seeded run draws differently.
///
/// The values were computed independently of the crate, by a 40-line Python transcription of the module
/// doc's derivation (SplitMix64 key words, ChaCha8 with the DJB layout: block counter in state words 12–13
/// = tick × 2¹⁶, stream id in 14–15 = satellite; `u64` = two little-endian words, low first), whose ChaCha
/// core reproduces the published all-zero-key ChaCha20 keystream (76 b8 e0 ad a0 f1 3d 90 …).
#[test]
fn regress_derivation_is_stable() {
    let mut s = RandomStream::new(1, Purpose::InitialStates, 0, 0);
    let mut t = RandomStream::new(2, Purpose::NavigationNoise, 3, 4);
    let got = [s.next_u64(), s.next_u64(), t.next_u64(), sub_seed(1, 0)];
    assert_eq!(got, GOLDEN, "got {got:#018x?}");
}

/// First two `u64` of (seed 1, initial states, satellite 0, tick 0), first `u64` of (seed 2, navigation
/// noise, satellite 3, tick 4), and `sub_seed(1, 0)`.
const GOLDEN: [u64; 4] = [
    0xf077_f24a_73d5_aca2,
    0xc2d0_e80b_22d4_b423,
    0x9d8d_21d4_1fe4_fee4,
    0xc1c0_cc4f_4519_bc7f,
];
