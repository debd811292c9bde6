//! Benchmark: point-mass + J2 propagation of N independent satellites with RK4 at dt = 1 s. Group
//! `j2_rk4_1s`: the whole swarm stepped as one state vector by the generic `Rk4` (N = 1, 1 000,
//! 100 000). Groups `fused_1_step` and `fused_60_steps`: the fused structure-of-arrays kernel
//! (`FusedRk4`, the engine's sampled path) advancing the swarm by one step (one control period of 1 s)
//! or by a 60-step segment per call, with the portable (SSE2) copy and the widest the CPU has
//! (N = 1 000, 10 000, 100 000). Group `fork_join`: one step on the calling thread against one forked
//! onto the pool, N = 1 024 … 32 768 (the parallel threshold's crossover). Throughput is reported in
//! satellite-steps per second (criterion's "elements").

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use nalgebra::Vector3;
use rayon::prelude::*;
use satflock::integrate::{FusedRk4, Rk4, SegmentInputs, Simd};
use satflock::orbit::{EarthModel, GravityModel, KeplerianElements};

fn swarm_state(n: usize) -> Vec<f64> {
    let mu = EarthModel::WGS84_EGM96.mu_m3_s2;
    (0..n)
        .flat_map(|i| {
            let s = KeplerianElements {
                semi_major_axis_m: 6_978_137.0 + (i % 100) as f64,
                eccentricity: 0.001,
                inclination_rad: 1.7,
                raan_rad: 0.0,
                arg_perigee_rad: 0.0,
                true_anomaly_rad: 1e-6 * i as f64,
            }
            .to_cartesian(mu)
            .unwrap();
            s.to_array()
        })
        .collect()
}

fn j2_rhs(_t: f64, y: &[f64], dy: &mut [f64]) {
    let earth = EarthModel::WGS84_EGM96;
    dy.par_chunks_mut(6 * 256)
        .zip(y.par_chunks(6 * 256))
        .for_each(|(d, s)| {
            for (d, s) in d.chunks_exact_mut(6).zip(s.chunks_exact(6)) {
                let a = GravityModel::J2.acceleration_m_s2(&earth, &Vector3::new(s[0], s[1], s[2]));
                d[0..3].copy_from_slice(&s[3..6]);
                d[3..6].copy_from_slice(a.as_slice());
            }
        });
}

fn propagation(c: &mut Criterion) {
    let mut group = c.benchmark_group("j2_rk4_1s");
    for n in [1usize, 1_000, 100_000] {
        let mut y = swarm_state(n);
        let mut rk4 = Rk4::new(y.len());
        group.throughput(Throughput::Elements(n as u64));
        if n >= 100_000 {
            group.sample_size(10);
        }
        group.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, _| {
            let mut t = 0.0;
            b.iter(|| {
                rk4.step(&j2_rhs, t, &mut y, 1.0);
                t += 1.0;
            })
        });
    }
    group.finish();
}

/// The swarm of [`swarm_state`] in the component-major layout.
fn component_major(n: usize) -> Vec<f64> {
    let y = swarm_state(n);
    (0..6)
        .flat_map(|k| y.iter().skip(k).step_by(6).copied().collect::<Vec<_>>())
        .collect()
}

fn fused(c: &mut Criterion) {
    for steps in [1usize, 60] {
        let mut group = c.benchmark_group(format!(
            "fused_{steps}_step{}",
            if steps > 1 { "s" } else { "" }
        ));
        for simd in [Simd::Portable, Simd::detect()] {
            let kernel = FusedRk4::new(GravityModel::J2, EarthModel::WGS84_EGM96)
                .with_simd(simd)
                .expect("portable and detected copies run");
            for n in [1_000usize, 10_000, 100_000] {
                let mut y = component_major(n);
                group.throughput(Throughput::Elements((n * steps) as u64));
                if n * steps >= 1_000_000 {
                    group.sample_size(10);
                }
                let id = BenchmarkId::new(simd.name(), n);
                group.bench_with_input(id, &n, |b, _| {
                    let mut t = 0.0;
                    b.iter(|| {
                        let t1 = t + steps as f64;
                        kernel
                            .advance(&mut y, n, &SegmentInputs::default(), t, t1, 1.0)
                            .expect("valid input");
                        t = t1;
                    })
                });
            }
            if simd == Simd::Portable && Simd::detect() == Simd::Portable {
                break;
            }
        }
        group.finish();
    }
}

/// One step of N satellites (a 1 s control period) with the widest copy, on the calling thread
/// (`serial`) and forked onto the rayon pool (`parallel`, threshold 0): where `parallel` starts to win is
/// the crossover [`satflock::integrate::PARALLEL_MIN_SAT_STEPS`] should sit at. N below two
/// `PARALLEL_CHUNK`s never splits.
fn fork_join(c: &mut Criterion) {
    let mut group = c.benchmark_group("fork_join");
    let kernel = FusedRk4::new(GravityModel::J2, EarthModel::WGS84_EGM96);
    for n in [1_024usize, 2_048, 4_096, 8_192, 16_384, 32_768] {
        let mut y = component_major(n);
        group.throughput(Throughput::Elements(n as u64));
        for (name, threshold) in [("serial", usize::MAX), ("parallel", 0)] {
            let kernel = kernel.with_parallel_min_sat_steps(threshold);
            group.bench_with_input(BenchmarkId::new(name, n), &n, |b, _| {
                let mut t = 0.0;
                b.iter(|| {
                    kernel
                        .advance(&mut y, n, &SegmentInputs::default(), t, t + 1.0, 1.0)
                        .expect("valid input");
                    t += 1.0;
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, propagation, fused, fork_join);
criterion_main!(benches);
