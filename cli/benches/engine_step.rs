//! Benchmark: one engine step of the `satflock bench` suite's guided cases (`satflock_cli::bench_cases`),
//! throughput in satellite-steps per second:
//! * `engine_step/N` for N = 1 000, 10 000, 100 000: the `hold` law plus a short-range pairwise spring
//!   repulsion through the neighbour grid (about 10 neighbours each), point-mass + J2 truth, RK4 and
//!   sampled control at 1 s (case `hold-repel`);
//! * `engine_step/equilibrium-shaping-hexagonal/10000`: the `equilibrium-shaping` law (Eq. 1 pair field
//!   through the grid, 18 neighbours each) on a 10 000-satellite triangular lattice, sampled at 0.025 s.
//!
//! The actuator limit of `hold-repel` (1e-2 m/s²) exceeds the 3 n² x needed to hold the outermost radial
//! offsets (1.1 km at N = 10^5: 3.8e-3 m/s²), so the swarm stays put however many steps criterion runs;
//! with a limit below that, outer satellites saturate, drift away and every grid query slows down as the
//! box grows.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use satflock_cli::bench_cases::simulation;

fn engine_step(c: &mut Criterion) {
    let mut group = c.benchmark_group("engine_step");
    for n in [1_000usize, 10_000, 100_000] {
        let mut sim = simulation("hold-repel", n).unwrap();
        group.throughput(Throughput::Elements(n as u64));
        group.sample_size(if n >= 100_000 { 10 } else { 20 });
        group.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, _| {
            b.iter(|| sim.step().unwrap())
        });
    }
    let n = 10_000;
    let mut sim = simulation("equilibrium-shaping", n).unwrap();
    group.throughput(Throughput::Elements(n as u64));
    group.sample_size(10);
    group.bench_with_input(
        BenchmarkId::new("equilibrium-shaping-hexagonal", n),
        &n,
        |b, _| b.iter(|| sim.step().unwrap()),
    );
    group.finish();
}

criterion_group!(benches, engine_step);
criterion_main!(benches);
