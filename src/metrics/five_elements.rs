//! Five-element cluster characterisation of Gao, Li & Wei, "Satellite Cluster Formation Reconfiguration
//! Based on the Bifurcating Potential Field", *Aerospace* 9(3):137, 2022, §2.1, Eqs. 1–9, as restated in
//! `shared/specs/gao-bifurcating-potential.md` §2.
//!
//! The five elements of a snapshot of N satellites with positions `r_i` and velocities `v_i`:
//!
//! 1. size N;
//! 2. movement: mean state `r_o = Σ r_i / N`, `v_o = Σ v_i / N` (Eqs. 1–2);
//! 3. outer boundary `d_max = max_i |r_i - r_o|` (Eq. 3). The paper's Table 5 instead matches the cluster
//!    diameter `max_{i<j} |r_i - r_j|`, reported as well ([`FiveElements::diameter_m`], spec §2 item 3);
//! 4. inner boundary `d_min = min_{i≠j} (|r_i - r_j| - a_i - a_j)` with physical radii `a_i` (Eq. 4);
//! 5. distribution uniformity `L = Σ m_i³ / M³` (Eqs. 5–9) with `m_i = ½ min_{j≠i} |r_i - r_j|` and
//!    `M = ½ max_{i≠j} (|r_i - r_j| + m_i + m_j)`, exactly as the spec's Appendix A (Eq. 8 is the paper's,
//!    not the true enclosing sphere; it is kept on purpose).
//!
//! Positions are subtracted from the centroid before anything else (ECI coordinates are ~7e6 m while
//! separations may be centimetres); `L`, `d_max`, `d_min` and the diameter are frame-invariant.
//!
//! Cost: nearest neighbours come from the cell-list grid (O(N)); the two maximum-over-pairs terms (Eq. 8
//! and the diameter) use an exact branch-and-bound over coarse cells: a pair of cells is searched only if
//! the largest distance between their bounding boxes plus their largest weights can beat the best pair
//! found so far. The result equals the all-pairs maximum bit for bit.

use std::sync::atomic::{AtomicU64, Ordering};

use rayon::prelude::*;

use super::{check_radii, MetricsError};
use crate::swarm::neighbours::NeighbourGrid;

/// The five elements of a cluster snapshot (spec §2). Lengths in metres, velocities in metres per
/// second; vectors in the frame of the inputs (ECI per the paper).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct FiveElements {
    /// Cluster size N (element 1).
    pub n: usize,
    /// Mean position `r_o` (m, input frame; element 2, Eq. 1).
    pub r_o_m: [f64; 3],
    /// Mean velocity `v_o` (m/s, input frame; element 2, Eq. 2).
    pub v_o_mps: [f64; 3],
    /// Outer boundary, largest distance from a satellite to `r_o` (m; element 3, Eq. 3).
    pub d_max_m: f64,
    /// Cluster diameter, largest pairwise distance (m; what the paper's Table 5 reports as `d_max`).
    pub diameter_m: f64,
    /// Inner boundary, smallest pairwise surface gap `|r_i - r_j| - a_i - a_j` (m; element 4, Eq. 4).
    /// Negative when bodies overlap.
    pub d_min_m: f64,
    /// Distribution uniformity `L` (dimensionless; element 5, Eqs. 5–9). 0 when all satellites coincide
    /// (`M = 0`).
    pub uniformity_l: f64,
}

/// Buffers reused across calls of [`five_elements`] (a neighbour grid and O(N) scratch arrays), so a
/// recorder calling it every output step does not allocate once warmed up.
#[derive(Clone, Debug, Default)]
pub struct FiveElementsWorkspace {
    grid: NeighbourGrid,
    /// Positions relative to `r_o` (m).
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    /// `m_i`, half the nearest-neighbour distance (m).
    half_nn: Vec<f64>,
    /// Index of each satellite's nearest neighbour.
    nn: Vec<usize>,
    pairs: PairScratch,
}

impl FiveElementsWorkspace {
    /// Empty workspace.
    pub fn new() -> Self {
        Self::default()
    }
}

/// Computes the five elements of a snapshot.
///
/// * `positions_eci_m[i]`: position of satellite i (m, ECI or any inertial Cartesian frame);
/// * `velocities_eci_mps[i]`: its velocity (m/s, same frame);
/// * `radii_m`: physical radii `a_i` (m, finite, >= 0) for `d_min`; `None` means point satellites
///   (`a_i = 0`, as the paper's tables);
/// * `workspace`: reusable buffers.
///
/// # Errors
/// [`MetricsError::TooFewSatellites`] for N < 2; [`MetricsError::LengthMismatch`] when the slices differ
/// in length; [`MetricsError::NonFinite`] for a NaN or infinite coordinate;
/// [`MetricsError::InvalidRadius`] for a negative or non-finite radius.
pub fn five_elements(
    positions_eci_m: &[[f64; 3]],
    velocities_eci_mps: &[[f64; 3]],
    radii_m: Option<&[f64]>,
    workspace: &mut FiveElementsWorkspace,
) -> Result<FiveElements, MetricsError> {
    let n = positions_eci_m.len();
    if n < 2 {
        return Err(MetricsError::TooFewSatellites { n });
    }
    if velocities_eci_mps.len() != n {
        return Err(MetricsError::LengthMismatch {
            what: "velocities",
            expected: n,
            got: velocities_eci_mps.len(),
        });
    }
    for (what, rows) in [
        ("position", positions_eci_m),
        ("velocity", velocities_eci_mps),
    ] {
        if let Some(index) = rows.iter().position(|r| !r.iter().all(|c| c.is_finite())) {
            return Err(MetricsError::NonFinite { what, index });
        }
    }
    let a_max = radii_m.map(|a| check_radii(a, n)).transpose()?;

    // Elements 1–2 (Eqs. 1–2). Sum offsets from satellite 0, not raw ECI coordinates: the offsets are
    // cluster-sized, so the sum keeps sub-millimetre accuracy at N = 1e5.
    let (r_o_m, mean_offset_m) = mean_state(positions_eci_m);
    let (v_o_mps, _) = mean_state(velocities_eci_mps);
    let ws = workspace;
    let p0 = positions_eci_m[0];
    ws.x.clear();
    ws.y.clear();
    ws.z.clear();
    for r in positions_eci_m {
        ws.x.push((r[0] - p0[0]) - mean_offset_m[0]);
        ws.y.push((r[1] - p0[1]) - mean_offset_m[1]);
        ws.z.push((r[2] - p0[2]) - mean_offset_m[2]);
    }

    // Element 3 (Eq. 3).
    let d_max_m = (0..n)
        .map(|i| norm(ws.x[i], ws.y[i], ws.z[i]))
        .fold(0.0, f64::max);

    // Eq. 6: m_i = d_i / 2 from exact nearest neighbours.
    build_grid_for_spacing(&mut ws.grid, &ws.x, &ws.y, &ws.z)?;
    let grid = &ws.grid;
    ws.half_nn.resize(n, 0.0);
    ws.nn.resize(n, 0);
    ws.half_nn
        .par_iter_mut()
        .zip(ws.nn.par_iter_mut())
        .enumerate()
        .for_each(|(i, (m, j))| {
            let nb = grid
                .nearest_neighbour(i)
                .expect("a grid with two or more satellites has a nearest neighbour");
            *m = 0.5 * nb.distance_m;
            *j = nb.index;
        });

    // Element 4 (Eq. 4).
    let d_min_m = match (radii_m, a_max) {
        (Some(a), Some(a_max)) => min_surface_gap(grid, &ws.nn, a, a_max),
        // Point satellites: the smallest nearest-neighbour distance (0.5 and 2 scale exactly).
        _ => 2.0 * ws.half_nn.iter().copied().fold(f64::INFINITY, f64::min),
    };

    // Eq. 8 and the diameter.
    let big_m = 0.5 * max_pair_sum(&ws.x, &ws.y, &ws.z, Some(&ws.half_nn), &mut ws.pairs);
    let diameter_m = max_pair_sum(&ws.x, &ws.y, &ws.z, None, &mut ws.pairs);

    // Eqs. 5, 7, 9: L = Σ (4/3 π m_i³) / (4/3 π M³), summed in index order.
    let sum_m3: f64 = ws.half_nn.iter().map(|m| m * m * m).sum();
    let uniformity_l = if big_m > 0.0 {
        sum_m3 / (big_m * big_m * big_m)
    } else {
        0.0
    };

    Ok(FiveElements {
        n,
        r_o_m,
        v_o_mps,
        d_max_m,
        diameter_m,
        d_min_m,
        uniformity_l,
    })
}

/// Mean of `rows`, returned as `(mean, mean - rows[0])`; the offsets from `rows[0]` are summed so that
/// large common coordinates do not swamp small differences.
fn mean_state(rows: &[[f64; 3]]) -> ([f64; 3], [f64; 3]) {
    let p0 = rows[0];
    let mut sum = [0.0; 3];
    for r in rows {
        for a in 0..3 {
            sum[a] += r[a] - p0[a];
        }
    }
    let offset = sum.map(|s| s / rows.len() as f64);
    (
        [p0[0] + offset[0], p0[1] + offset[1], p0[2] + offset[2]],
        offset,
    )
}

fn norm(x: f64, y: f64, z: f64) -> f64 {
    (x * x + y * y + z * z).sqrt()
}

/// Builds `grid` with a cell size that suits the swarm's spacing, so nearest-neighbour queries stay
/// cheap whatever the swarm's dimension (curve, surface or volume). The answers are exact at any cell
/// size; only speed depends on it.
fn build_grid_for_spacing(
    grid: &mut NeighbourGrid,
    x: &[f64],
    y: &[f64],
    z: &[f64],
) -> Result<(), MetricsError> {
    let n = x.len() as f64;
    let extent = [x, y, z]
        .map(|c| {
            let (lo, hi) = c
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                    (lo.min(v), hi.max(v))
                });
            hi - lo
        })
        .into_iter()
        .fold(0.0, f64::max);
    if extent == 0.0 {
        // All satellites coincide; any cell size finds them.
        grid.build(x, y, z, 1.0)?;
        return Ok(());
    }
    // Start from the spacing of a volume-filling swarm, then shrink while cells hold more than 4
    // satellites on average (curves and surfaces are denser per cell); the square root assumes a
    // surface, between the curve and volume cases.
    let mut cell_m = extent / n.cbrt();
    for _ in 0..4 {
        grid.build(x, y, z, cell_m)?;
        let mean_occupancy = n / grid.occupied_cells() as f64;
        if mean_occupancy <= 4.0 {
            break;
        }
        cell_m /= (mean_occupancy / 2.0).sqrt();
    }
    Ok(())
}

/// `min_{i<j} (d_ij - (a_i + a_j))`, exact: the nearest-neighbour pairs give an upper bound `g`, and a
/// pair can only beat it if `d_ij < g + a_i + a_j <= g + a_i + a_max`.
fn min_surface_gap(grid: &NeighbourGrid, nn: &[usize], a: &[f64], a_max: f64) -> f64 {
    let n = nn.len();
    let gap_ub = (0..n)
        .map(|i| {
            let j = nn[i];
            let p = grid.position_m(i);
            let q = grid.position_m(j);
            norm(q[0] - p[0], q[1] - p[1], q[2] - p[2]) - (a[i] + a[j])
        })
        .fold(f64::INFINITY, f64::min);
    (0..n)
        .into_par_iter()
        .map(|i| {
            let mut best = gap_ub;
            // 1e-12 relative slack: rounding must never exclude a candidate.
            let reach = (gap_ub + a[i] + a_max) * (1.0 + 1e-12);
            grid.for_each_within(i, reach, |nb| {
                best = best.min(nb.distance_m - (a[i] + a[nb.index]));
            });
            best
        })
        .reduce(|| f64::INFINITY, f64::min)
}

/// Scratch buffers of [`max_pair_sum`].
#[derive(Clone, Debug, Default)]
struct PairScratch {
    /// (coarse cell key, satellite), sorted.
    keyed: Vec<(u64, u32)>,
    bins: Vec<Bin>,
    /// (upper bound, bin a, bin b) of the bin pairs that may hold the maximum.
    bin_pairs: Vec<(f64, u32, u32)>,
}

/// One occupied coarse cell: its satellites `keyed[start..end]`, their bounding box and largest weight.
#[derive(Clone, Copy, Debug)]
struct Bin {
    start: usize,
    end: usize,
    lo: [f64; 3],
    hi: [f64; 3],
    w_max: f64,
}

/// Value of the pair (i, j): `d_ij + (w_i + w_j)` (or `d_ij` without weights), symmetric in i and j to
/// the last bit.
#[inline]
fn pair_value(x: &[f64], y: &[f64], z: &[f64], w: Option<&[f64]>, i: usize, j: usize) -> f64 {
    let d = norm(x[j] - x[i], y[j] - y[i], z[j] - z[i]);
    match w {
        Some(w) => d + (w[i] + w[j]),
        None => d,
    }
}

/// `true` when a candidate whose value is at most `bound` (up to rounding) cannot beat `best`.
/// The 1e-12 relative slack dwarfs the few-ulp rounding of distances and bounds.
#[inline]
fn cannot_beat(bound: f64, best: f64) -> bool {
    bound * (1.0 + 1e-12) <= best
}

/// Largest distance between two axis-aligned boxes.
fn box_max_distance(a_lo: [f64; 3], a_hi: [f64; 3], b_lo: [f64; 3], b_hi: [f64; 3]) -> f64 {
    let mut s = 0.0;
    for k in 0..3 {
        let e = (b_hi[k] - a_lo[k]).abs().max((a_hi[k] - b_lo[k]).abs());
        s += e * e;
    }
    s.sqrt()
}

/// `max_{i<j} pair_value(i, j)` over N >= 2 points with non-negative weights, exactly (the same value as
/// the all-pairs loop), by branch-and-bound over coarse cells.
fn max_pair_sum(x: &[f64], y: &[f64], z: &[f64], w: Option<&[f64]>, s: &mut PairScratch) -> f64 {
    let n = x.len();
    let weight = |i: usize| w.map_or(0.0, |w| w[i]);

    // Lower bound from a few farthest-point sweeps, starting at the point farthest from the centroid.
    let mut a = (0..n)
        .max_by(|&i, &j| {
            let bi = norm(x[i], y[i], z[i]) + weight(i);
            let bj = norm(x[j], y[j], z[j]) + weight(j);
            bi.total_cmp(&bj)
        })
        .expect("n >= 2");
    let mut best = f64::NEG_INFINITY;
    for _ in 0..3 {
        let (j, v) = (0..n)
            .filter(|&j| j != a)
            .map(|j| (j, pair_value(x, y, z, w, a, j)))
            .max_by(|p, q| p.1.total_cmp(&q.1))
            .expect("n >= 2");
        best = best.max(v);
        a = j;
    }

    // Coarse cells: aim for about 2 √N occupied cells, so that cell pairs (~4 N) and the satellites per
    // cell pair stay balanced; refine the grid until a curve- or surface-like swarm fills enough cells.
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for i in 0..n {
        for (k, v) in [x[i], y[i], z[i]].into_iter().enumerate() {
            lo[k] = lo[k].min(v);
            hi[k] = hi[k].max(v);
        }
    }
    let extent = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
    let target_bins = (2.0 * (n as f64).sqrt()).ceil() as usize;
    let mut g = ((target_bins as f64).cbrt().ceil() as u64).max(1);
    loop {
        let inv_h = if extent > 0.0 { g as f64 / extent } else { 0.0 };
        s.keyed.clear();
        for i in 0..n {
            let cell = |v: f64, k: usize| (((v - lo[k]) * inv_h).floor() as u64).min(g - 1);
            let key = cell(x[i], 0) + g * (cell(y[i], 1) + g * cell(z[i], 2));
            s.keyed.push((key, i as u32));
        }
        s.keyed.sort_unstable();
        let occupied = 1 + s.keyed.windows(2).filter(|p| p[0].0 != p[1].0).count();
        if occupied * 8 >= target_bins || g >= 1 << 20 {
            break;
        }
        g *= 2;
    }

    s.bins.clear();
    let mut start = 0;
    while start < n {
        let key = s.keyed[start].0;
        let mut end = start;
        let mut bin = Bin {
            start,
            end,
            lo: [f64::INFINITY; 3],
            hi: [f64::NEG_INFINITY; 3],
            w_max: 0.0,
        };
        while end < n && s.keyed[end].0 == key {
            let i = s.keyed[end].1 as usize;
            for (k, v) in [x[i], y[i], z[i]].into_iter().enumerate() {
                bin.lo[k] = bin.lo[k].min(v);
                bin.hi[k] = bin.hi[k].max(v);
            }
            bin.w_max = bin.w_max.max(weight(i));
            end += 1;
        }
        bin.end = end;
        s.bins.push(bin);
        start = end;
    }

    // Bin pairs that might beat the lower bound, most promising first.
    s.bin_pairs.clear();
    for (ia, ba) in s.bins.iter().enumerate() {
        for (ib, bb) in s.bins.iter().enumerate().skip(ia) {
            if ia == ib && ba.end - ba.start < 2 {
                continue;
            }
            let bound = box_max_distance(ba.lo, ba.hi, bb.lo, bb.hi) + ba.w_max + bb.w_max;
            if !cannot_beat(bound, best) {
                s.bin_pairs.push((bound, ia as u32, ib as u32));
            }
        }
    }
    s.bin_pairs
        .sort_unstable_by(|p, q| q.0.total_cmp(&p.0).then((p.1, p.2).cmp(&(q.1, q.2))));

    // Values are >= 0, so the bit patterns of f64 order like the numbers and an atomic max is exact;
    // the maximum does not depend on the order in which threads find it.
    let best_bits = AtomicU64::new(best.max(0.0).to_bits());
    let keyed = &s.keyed;
    let bins = &s.bins;
    s.bin_pairs.par_iter().for_each(|&(bound, ia, ib)| {
        if cannot_beat(bound, f64::from_bits(best_bits.load(Ordering::Relaxed))) {
            return;
        }
        let (ba, bb) = (bins[ia as usize], bins[ib as usize]);
        let mut local = f64::from_bits(best_bits.load(Ordering::Relaxed));
        for sa in ba.start..ba.end {
            let i = keyed[sa].1 as usize;
            let p = [x[i], y[i], z[i]];
            let reach = box_max_distance(p, p, bb.lo, bb.hi) + weight(i) + bb.w_max;
            if cannot_beat(reach, local) {
                continue;
            }
            let sb_start = if ia == ib { sa + 1 } else { bb.start };
            for &(_, j) in &keyed[sb_start..bb.end] {
                let v = pair_value(x, y, z, w, i, j as usize);
                if v > local {
                    local = v;
                }
            }
        }
        best_bits.fetch_max(local.to_bits(), Ordering::Relaxed);
    });
    f64::from_bits(best_bits.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::rngs::ChaCha8Rng;
    use rand::{RngExt, SeedableRng};

    fn brute(x: &[f64], y: &[f64], z: &[f64], w: Option<&[f64]>) -> f64 {
        let mut best = f64::NEG_INFINITY;
        for i in 0..x.len() {
            for j in i + 1..x.len() {
                best = best.max(pair_value(x, y, z, w, i, j));
            }
        }
        best
    }

    /// The branch-and-bound maximum equals the all-pairs maximum bit for bit, on volume, shell, circle,
    /// clustered and coincident sets, with and without weights.
    #[test]
    fn max_pair_sum_equals_brute_force_exactly() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let mut scratch = PairScratch::default();
        for &n in &[2usize, 3, 10, 101, 1000, 3000] {
            for shape in 0..5 {
                let mut x = Vec::with_capacity(n);
                let mut y = Vec::with_capacity(n);
                let mut z = Vec::with_capacity(n);
                for k in 0..n {
                    let (u, v, t): (f64, f64, f64) = (
                        rng.random_range(-1.0..1.0),
                        rng.random_range(-1.0..1.0),
                        rng.random_range(-1.0..1.0),
                    );
                    let p = match shape {
                        0 => [u, v, t],
                        1 => {
                            let r = norm(u, v, t).max(1e-9);
                            [u / r, v / r, t / r]
                        }
                        2 => {
                            let a = std::f64::consts::TAU * k as f64 / n as f64;
                            [a.cos(), 0.0, a.sin()]
                        }
                        3 => {
                            let c = (k % 4) as f64 * 10.0;
                            [c + 0.01 * u, 0.01 * v, c * 0.5 + 0.01 * t]
                        }
                        _ => [1.5, -2.0, 0.25],
                    };
                    x.push(p[0]);
                    y.push(p[1]);
                    z.push(p[2]);
                }
                let w: Vec<f64> = (0..n).map(|_| rng.random_range(0.0..0.05)).collect();
                assert_eq!(
                    max_pair_sum(&x, &y, &z, None, &mut scratch),
                    brute(&x, &y, &z, None),
                    "n = {n}, shape {shape}, no weights"
                );
                assert_eq!(
                    max_pair_sum(&x, &y, &z, Some(&w), &mut scratch),
                    brute(&x, &y, &z, Some(&w)),
                    "n = {n}, shape {shape}, weights"
                );
            }
        }
    }
}
