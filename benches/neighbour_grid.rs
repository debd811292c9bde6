//! Benchmark: the engine's sensing grid on its own. Satellites uniform in a ball at the density of
//! `bench/million-bifurcating-drag.toml` (10⁶ in a ball of 23 208 m, about 2.4 per 500 m cell), stored
//! in cell order and ranked by id as the engine keeps them. Group `grid_build`:
//! `NeighbourGrid::build_ranked` over the 500 m sensing range (N = 100 000, 1 000 000). Group
//! `grid_query_100m`: one 100 m query per satellite in storage order (the bifurcating law's avoidance
//! reach), summing the neighbours' distances (N = 100 000). Throughput is reported in satellites per
//! second (criterion's "elements"): one build or one query per satellite.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use rayon::prelude::*;
use satflock::grid::NeighbourGrid;

/// Sensing range of the bench scenarios \[m\].
const SENSING_RANGE_M: f64 = 500.0;
/// The bifurcating law's avoidance radius there \[m\].
const AVOIDANCE_RADIUS_M: f64 = 100.0;
/// Satellites per m³ of `bench/million-bifurcating-drag.toml`: 10⁶ in a ball of 23 208 m.
const DENSITY_PER_M3: f64 =
    1e6 / (4.0 / 3.0 * std::f64::consts::PI * 23_208.0 * 23_208.0 * 23_208.0);

/// `n` satellites uniform in the ball of the bench density, stored in cell order of the sensing grid
/// (as the engine's storage order keeps them), with their ids as ranks (ascending within each cell).
fn swarm(n: usize) -> ([Vec<f64>; 3], Vec<u32>) {
    let radius_m = (n as f64 / DENSITY_PER_M3 * 3.0 / (4.0 * std::f64::consts::PI)).cbrt();
    let mut state = 0x853c_49e6_748f_ea9b_u64;
    let mut uniform = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut points = Vec::with_capacity(n);
    while points.len() < n {
        let p = [0; 3].map(|_| (2.0 * uniform() - 1.0) * radius_m);
        if p.iter().map(|c| c * c).sum::<f64>() <= radius_m * radius_m {
            points.push(p);
        }
    }
    let mut grid = NeighbourGrid::new();
    let [x, y, z] = [0, 1, 2].map(|a| points.iter().map(|p| p[a]).collect::<Vec<_>>());
    grid.build(&x, &y, &z, SENSING_RANGE_M)
        .expect("finite points");
    let order = grid.cell_order();
    let stored = [0, 1, 2].map(|a| order.iter().map(|&i| points[i as usize][a]).collect());
    (stored, order.to_vec())
}

fn build(c: &mut Criterion) {
    let mut group = c.benchmark_group("grid_build");
    group.sample_size(10);
    for n in [100_000usize, 1_000_000] {
        let ([x, y, z], ranks) = swarm(n);
        let mut grid = NeighbourGrid::new();
        group.throughput(Throughput::Elements(n as u64));
        group.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, _| {
            b.iter(|| {
                grid.build_ranked(&x, &y, &z, SENSING_RANGE_M, Some(&ranks))
                    .expect("finite points")
            });
        });
    }
    group.finish();
}

fn query(c: &mut Criterion) {
    let mut group = c.benchmark_group("grid_query_100m");
    group.sample_size(10);
    let n = 100_000usize;
    let ([x, y, z], ranks) = swarm(n);
    let mut grid = NeighbourGrid::new();
    grid.build_ranked(&x, &y, &z, SENSING_RANGE_M, Some(&ranks))
        .expect("finite points");
    group.throughput(Throughput::Elements(n as u64));
    group.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, _| {
        b.iter(|| {
            (0..n)
                .into_par_iter()
                .with_min_len(4096)
                .map(|i| {
                    let mut sum_m = 0.0;
                    grid.for_each_within(i, AVOIDANCE_RADIUS_M, |nb| sum_m += nb.distance_m);
                    sum_m
                })
                .sum::<f64>()
        });
    });
    group.finish();
}

criterion_group!(benches, build, query);
criterion_main!(benches);
