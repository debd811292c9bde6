//! Validation of `grid::NeighbourGrid` against brute-force all-pairs search.
//!
//! The reference is an independent O(N²) loop using the grid's documented inclusion rule,
//! `sqrt(dx² + dy² + dz²) <= r` with `dx = x[j] - x[i]` in f64, so neighbour sets, separation vectors and
//! distances must agree exactly (no tolerance).

use proptest::prelude::*;
use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};
use satflock::grid::{GridLayout, Neighbour, NeighbourError, NeighbourGrid};

/// A random swarm of `n` satellites (m). Modes: 0 clustered (a few tight clusters 1 km apart),
/// 1 sparse (spread over 200 km), 2 integer lattice (many pairs exactly at integer radii),
/// 3 ECI-sized offsets (7e6 m) with metre spacing, 4 flat (all z equal).
fn swarm(seed: u64, n: usize, mode: u8) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (mut x, mut y, mut z) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..n {
        let p: [f64; 3] = match mode {
            0 => {
                let c = rng.random_range(0..4) as f64 * 1000.0;
                [
                    c + rng.random_range(-20.0..20.0),
                    rng.random_range(-20.0..20.0),
                    -c + rng.random_range(-20.0..20.0),
                ]
            }
            1 => [
                rng.random_range(-1e5..1e5),
                rng.random_range(-1e5..1e5),
                rng.random_range(-1e5..1e5),
            ],
            2 => [
                rng.random_range(0..6) as f64,
                rng.random_range(0..6) as f64,
                rng.random_range(0..6) as f64,
            ],
            3 => [
                7e6 + rng.random_range(0.0..30.0),
                -1e6 + rng.random_range(0.0..30.0),
                3e5 + rng.random_range(0.0..30.0),
            ],
            _ => [
                rng.random_range(-50.0..50.0),
                rng.random_range(-50.0..50.0),
                0.0,
            ],
        };
        x.push(p[0]);
        y.push(p[1]);
        z.push(p[2]);
    }
    (x, y, z)
}

/// `f` run on a rayon pool of `threads` threads.
fn on_threads<R: Send>(threads: usize, f: impl FnOnce() -> R + Send) -> R {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

/// All j != i within `reach` of i, ascending j, by the documented inclusion rule.
fn brute_within(x: &[f64], y: &[f64], z: &[f64], i: usize, reach: f64) -> Vec<Neighbour> {
    (0..x.len())
        .filter(|&j| j != i)
        .filter_map(|j| {
            let (dx, dy, dz) = (x[j] - x[i], y[j] - y[i], z[j] - z[i]);
            let d = (dx * dx + dy * dy + dz * dz).sqrt();
            (d <= reach).then_some(Neighbour {
                index: j,
                dx_m: dx,
                dy_m: dy,
                dz_m: dz,
                distance_m: d,
            })
        })
        .collect()
}

/// The grid's neighbours of i, sorted by index for comparison with the brute-force set.
fn grid_within(g: &NeighbourGrid, i: usize, reach: Option<f64>) -> Vec<Neighbour> {
    let mut out = Vec::new();
    match reach {
        None => g.for_each_neighbour(i, |nb| out.push(nb)),
        Some(r) => g.for_each_within(i, r, |nb| out.push(nb)),
    }
    let len = out.len();
    out.sort_by_key(|nb| nb.index);
    out.dedup_by_key(|nb| nb.index);
    assert_eq!(out.len(), len, "a neighbour was visited twice");
    out
}

/// Nearest other satellite, ties to the smaller index.
fn brute_nearest(x: &[f64], y: &[f64], z: &[f64], i: usize) -> Option<(usize, f64)> {
    let mut best: Option<(usize, f64)> = None;
    for j in (0..x.len()).filter(|&j| j != i) {
        let d = ((x[j] - x[i]).powi(2) + (y[j] - y[i]).powi(2) + (z[j] - z[i]).powi(2)).sqrt();
        if best.is_none_or(|(_, b)| d < b) {
            best = Some((j, d));
        }
    }
    best
}

/// Typical spacing of each mode, to pick radii that give from ~0 to ~50 neighbours.
fn radius_for(mode: u8, factor: f64) -> f64 {
    match mode {
        0 => 5.0 * factor,
        1 => 2e4 * factor,
        2 => (factor * 4.0).round().max(1.0),
        3 => 3.0 * factor,
        _ => 8.0 * factor,
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Same neighbour sets (indices, separation vectors and distances bit for bit) as brute force, for
    /// the grid radius and for a larger reach, plus the same nearest neighbour.
    #[test]
    fn val_grid_matches_brute_force(
        seed in any::<u64>(),
        n in 0usize..300,
        mode in 0u8..5,
        factor in 0.05f64..3.0,
        reach_factor in 0.0f64..4.0,
    ) {
        let (x, y, z) = swarm(seed, n, mode);
        let r = radius_for(mode, factor);
        let mut g = NeighbourGrid::new();
        g.build(&x, &y, &z, r).unwrap();
        prop_assert_eq!(g.len(), n);
        for i in 0..n {
            prop_assert_eq!(grid_within(&g, i, None), brute_within(&x, &y, &z, i, r));
            let reach = r * reach_factor;
            prop_assert_eq!(grid_within(&g, i, Some(reach)), brute_within(&x, &y, &z, i, reach));
            let nearest = g.nearest_neighbour(i).map(|nb| (nb.index, nb.distance_m));
            prop_assert_eq!(nearest, brute_nearest(&x, &y, &z, i));
        }
    }
}

/// Both layouts are exercised by the proptest above: the clustered and 200 km modes build sparse grids,
/// the lattice and ECI-offset modes dense ones.
#[test]
fn val_modes_cover_both_layouts() {
    let mut g = NeighbourGrid::new();
    for (mode, factor, layout) in [
        (0, 1.0, GridLayout::Sparse),
        (1, 0.05, GridLayout::Sparse),
        (2, 0.25, GridLayout::Dense),
        (3, 1.0, GridLayout::Dense),
    ] {
        let (x, y, z) = swarm(1, 200, mode);
        g.build(&x, &y, &z, radius_for(mode, factor)).unwrap();
        assert_eq!(g.layout(), layout, "mode {mode}");
    }
}

/// A neighbour exactly at the radius is included; one ulp beyond is not, also at ECI-sized coordinates
/// where 7e6 + 0.25 is exact, so the computed separation is exactly the radius.
#[test]
fn val_boundary_exactly_at_radius() {
    let beyond = f64::from_bits(1.5_f64.to_bits() + 1);
    let x = [0.0, 1.5, 0.0, 0.0];
    let y = [0.0, 0.0, beyond, 0.0];
    let z = [0.0, 0.0, 0.0, -1.5];
    let mut g = NeighbourGrid::new();
    g.build(&x, &y, &z, 1.5).unwrap();
    let found: Vec<usize> = grid_within(&g, 0, None).iter().map(|nb| nb.index).collect();
    assert_eq!(found, vec![1, 3]);

    let x = [7e6, 7e6 + 0.25, 7e6 + 0.5 + 1e-9];
    g.build(&x, &[0.0; 3], &[0.0; 3], 0.25).unwrap();
    let found: Vec<(usize, f64)> = grid_within(&g, 1, None)
        .iter()
        .map(|nb| (nb.index, nb.dx_m))
        .collect();
    assert_eq!(found, vec![(0, -0.25)]);
}

/// The visit order is a function of the inputs only: the same after rebuilding over another swarm in
/// between (reused buffers), and the same from 1 or 4 rayon threads.
#[test]
fn val_visit_order_is_deterministic() {
    use rayon::prelude::*;
    let (x, y, z) = swarm(42, 2000, 0);
    let r = radius_for(0, 1.0);
    let orders = |g: &NeighbourGrid| -> Vec<Vec<usize>> {
        (0..g.len())
            .into_par_iter()
            .map(|i| {
                let mut v = Vec::new();
                g.for_each_neighbour(i, |nb| v.push(nb.index));
                v
            })
            .collect()
    };
    let mut g = NeighbourGrid::new();
    g.build(&x, &y, &z, r).unwrap();
    let first = orders(&g);
    assert!(
        first.iter().map(Vec::len).sum::<usize>() > 2000,
        "too few neighbours to test order"
    );

    let (x2, y2, z2) = swarm(43, 3000, 1);
    g.build(&x2, &y2, &z2, 10.0).unwrap();
    g.build(&x, &y, &z, r).unwrap();
    for threads in [1, 4] {
        assert_eq!(
            on_threads(threads, || orders(&g)),
            first,
            "{threads} threads"
        );
    }
}

#[test]
fn val_degenerate_swarms() {
    let mut g = NeighbourGrid::new();
    g.build(&[], &[], &[], 1.0).unwrap();
    assert!(g.is_empty());

    g.build(&[3.0], &[4.0], &[5.0], 1.0).unwrap();
    assert_eq!(g.len(), 1);
    assert!(grid_within(&g, 0, None).is_empty());
    assert_eq!(g.nearest_neighbour(0), None);

    // 100 coincident satellites: each sees the 99 others at distance 0.
    let c = vec![7e6; 100];
    g.build(&c, &c, &c, 1e-3).unwrap();
    for i in [0, 57, 99] {
        let nbs = grid_within(&g, i, None);
        assert_eq!(nbs.len(), 99);
        assert!(nbs.iter().all(|nb| nb.distance_m == 0.0));
        let nearest = g.nearest_neighbour(i).unwrap();
        assert_eq!(
            (nearest.index, nearest.distance_m),
            (usize::from(i == 0), 0.0)
        );
    }
}

#[test]
fn val_bad_input_is_an_error_not_a_panic() {
    let mut g = NeighbourGrid::new();
    for r in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            g.build(&[0.0], &[0.0], &[0.0], r),
            Err(NeighbourError::InvalidRadius { .. })
        ));
    }
    // NaN is not equal to itself, so match the fields.
    match g.build(&[0.0, 1.0], &[0.0, f64::NAN], &[0.0, 0.0], 1.0) {
        Err(NeighbourError::NonFinitePosition {
            index: 1,
            x_m,
            y_m,
            z_m,
        }) => assert!(x_m == 1.0 && y_m.is_nan() && z_m == 0.0),
        other => panic!("expected NonFinitePosition for satellite 1, got {other:?}"),
    }
    assert!(g.is_empty(), "a failed build leaves the grid empty");
    assert_eq!(
        g.build(&[0.0, 1.0], &[0.0], &[0.0, 0.0], 1.0),
        Err(NeighbourError::LengthMismatch { x: 2, y: 1, z: 2 })
    );
}

/// A satellite alone far from the rest still finds its exact nearest neighbour (ring search widens,
/// then falls back to a full scan).
#[test]
fn val_nearest_neighbour_beyond_radius() {
    let (mut x, mut y, mut z) = swarm(5, 500, 0);
    x.push(5e5);
    y.push(-3e5);
    z.push(1e5);
    let mut g = NeighbourGrid::new();
    g.build(&x, &y, &z, 1.0).unwrap();
    for i in [0, 250, 500] {
        let nb = g.nearest_neighbour(i).unwrap();
        assert_eq!(
            Some((nb.index, nb.distance_m)),
            brute_nearest(&x, &y, &z, i)
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(60))]

    /// A masked grid answers as brute force over the visible satellites only: hidden ones are nobody's
    /// neighbour or nearest neighbour, yet can still be asked about their own neighbourhood; the next
    /// build clears the mask.
    #[test]
    fn val_mask_hides_exactly_the_invisible(
        seed in any::<u64>(),
        n in 2usize..300,
        mode in 0u8..5,
        factor in 0.05f64..3.0,
        hidden_every in 1usize..6,
    ) {
        let (x, y, z) = swarm(seed, n, mode);
        let r = radius_for(mode, factor);
        let visible = |i: usize| !(i * 7 + seed as usize % 5).is_multiple_of(hidden_every) || hidden_every == 1;
        let mut g = NeighbourGrid::new();
        g.build(&x, &y, &z, r).unwrap();
        prop_assert!(!g.is_masked());
        g.mask(visible);
        prop_assert!(g.is_masked());
        for i in 0..n {
            let expected: Vec<Neighbour> = brute_within(&x, &y, &z, i, r)
                .into_iter()
                .filter(|nb| visible(nb.index))
                .collect();
            prop_assert_eq!(grid_within(&g, i, None), expected);
            let nearest = (0..n)
                .filter(|&j| j != i && visible(j))
                .map(|j| {
                    let d = ((x[j] - x[i]).powi(2) + (y[j] - y[i]).powi(2) + (z[j] - z[i]).powi(2)).sqrt();
                    (j, d)
                })
                .fold(None, |best: Option<(usize, f64)>, (j, d)| match best {
                    Some((_, b)) if b <= d => best,
                    _ => Some((j, d)),
                });
            prop_assert_eq!(g.nearest_neighbour(i).map(|nb| (nb.index, nb.distance_m)), nearest);
        }
        g.build(&x, &y, &z, r).unwrap();
        prop_assert!(!g.is_masked());
        prop_assert_eq!(grid_within(&g, 0, None), brute_within(&x, &y, &z, 0, r));
    }
}

/// A build large enough to split across threads (tens of thousands of satellites) stores the same order
/// and answers the same neighbours on 1 and 4 threads, equal to brute force for a sample of satellites;
/// the first non-finite position is the one reported, whatever the split.
#[test]
fn val_large_build_is_the_same_on_any_thread_count() {
    let n = 40_000;
    let (x, y, z) = swarm(11, n, 1);
    let r = radius_for(1, 0.4);
    let build = |threads: usize| {
        on_threads(threads, || {
            let mut g = NeighbourGrid::new();
            g.build(&x, &y, &z, r).unwrap();
            g
        })
    };
    let (one, four) = (build(1), build(4));
    assert_eq!(one.cell_order(), four.cell_order());
    assert_eq!(one.layout(), four.layout());
    let mut found = 0;
    for i in (0..n).step_by(397) {
        let expected = brute_within(&x, &y, &z, i, r);
        assert_eq!(grid_within(&one, i, None), expected);
        assert_eq!(grid_within(&four, i, None), expected);
        found += expected.len();
    }
    assert!(found > 50, "too few neighbours to test: {found}");

    // Ranked by a shuffle of the indices: on 1 and 4 threads the storage order is cells ascending in
    // (z, y, x), within a cell ascending rank, as the cells computed here from the positions say.
    let rank: Vec<u32> = (0..n as u32).map(|i| (i * 7_919) % n as u32).collect();
    let ranked = |threads: usize| {
        on_threads(threads, || {
            let mut g = NeighbourGrid::new();
            g.build_ranked(&x, &y, &z, r, Some(&rank)).unwrap();
            g.cell_order().to_vec()
        })
    };
    let inv_cell = 1.0 / one.cell_size_m();
    let axes = [&x, &y, &z];
    let lo = axes.map(|v| v.iter().copied().fold(f64::INFINITY, f64::min));
    let hi = axes.map(|v| v.iter().copied().fold(f64::NEG_INFINITY, f64::max));
    let dims: [u64; 3] = std::array::from_fn(|a| ((hi[a] - lo[a]) * inv_cell).floor() as u64 + 1);
    let cell = |i: usize| -> [u64; 3] {
        std::array::from_fn(|a| (((axes[a][i] - lo[a]) * inv_cell) as u64).min(dims[a] - 1))
    };
    let mut expected: Vec<u32> = (0..n as u32).collect();
    expected.sort_by_key(|&i| {
        let c = cell(i as usize);
        (c[2], c[1], c[0], rank[i as usize])
    });
    assert_eq!(ranked(1), expected);
    assert_eq!(ranked(4), expected);

    let mut bad_x = x.clone();
    bad_x[30_000] = f64::NAN;
    bad_x[35_000] = f64::INFINITY;
    for threads in [1, 4] {
        let error = on_threads(threads, || {
            NeighbourGrid::new().build(&bad_x, &y, &z, r).unwrap_err()
        });
        assert!(
            matches!(
                error,
                NeighbourError::NonFinitePosition { index: 30_000, .. }
            ),
            "{error:?}"
        );
    }
}
