//! Five-element cluster characterisation of Gao, Li & Wei, "Satellite Cluster Formation Reconfiguration
//! Based on the Bifurcating Potential Field", *Aerospace* 9(3):137, 2022, §2.1, Eqs. 1–9, as restated in
//! `docs/methods/bifurcating.md` §2.
//!
//! The five elements of a snapshot of N satellites with positions `r_i` and velocities `v_i`:
//!
//! 1. size N;
//! 2. movement: mean state `r_o = Σ r_i / N`, `v_o = Σ v_i / N` (Eqs. 1–2);
//! 3. outer boundary `d_max = max_i |r_i - r_o|` (Eq. 3). The paper's Table 5 instead matches the cluster
//!    diameter `max_{i<j} |r_i - r_j|`, reported as well ([`FiveElements::diameter_m`], method page §2);
//! 4. inner boundary `d_min = min_{i≠j} (|r_i - r_j| - a_i - a_j)` with physical radii `a_i` (Eq. 4);
//! 5. distribution uniformity `L = Σ m_i³ / M³` (Eqs. 5–9) with `m_i = ½ min_{j≠i} |r_i - r_j|` and
//!    `M = ½ max_{i≠j} (|r_i - r_j| + m_i + m_j)`, exactly as our reconstruction defines it (Eq. 8 is the paper's,
//!    not the true enclosing sphere; it is kept on purpose).
//!
//! Positions are subtracted from the centroid before anything else (ECI coordinates are ~7e6 m while
//! separations may be centimetres); `L`, `d_max`, `d_min` and the diameter are frame-invariant.
//!
//! Cost: nearest neighbours come from the cell-list grid (O(N)); the two maximum-over-pairs terms (Eq. 8
//! and the diameter) use an exact dual-tree branch and bound over a kd-tree: a pair of tree nodes is
//! searched only if the largest distance between their bounding boxes plus their largest weights can
//! beat the best pair found so far. The result equals the all-pairs maximum bit for bit. Box bounds are
//! loose by about a leaf's size, so swarms whose satellites all lie near the outer boundary (a spherical
//! shell, a ring) open many more node pairs than filled volumes or disks; measured on 2 cores at
//! N = 1e5: ~0.1 s for a ball or a disk, ~0.4 s for a ring, ~0.9 s for a spherical shell per call.

use rayon::prelude::*;

use super::{check_radii, MetricsError, MAX_COORDINATE};
use crate::grid::NeighbourGrid;

/// The five elements of a cluster snapshot (method page §2). Lengths in metres, velocities in metres per
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
        if let Some(index) = rows
            .iter()
            .position(|r| r.iter().any(|c| c.abs() > MAX_COORDINATE))
        {
            return Err(MetricsError::OutOfRange {
                what,
                index,
                value: rows[index].iter().fold(0.0, |m: f64, c| m.max(c.abs())),
                limit: MAX_COORDINATE,
            });
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

    // Exact duplicates would make nearest-neighbour queries quadratic (every duplicate scans its whole
    // cell), so a swarm with any is reduced to its distinct positions first.
    if let Some(groups) = duplicate_groups(&ws.x, &ws.y, &ws.z) {
        let (d_min_m, big_m, diameter_m, sum_m3) = with_duplicates(ws, &groups, radii_m)?;
        let uniformity_l = if big_m > 0.0 {
            sum_m3 / (big_m * big_m * big_m)
        } else {
            0.0
        };
        return Ok(FiveElements {
            n,
            r_o_m,
            v_o_mps,
            d_max_m,
            diameter_m,
            d_min_m,
            uniformity_l,
        });
    }

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

/// Groups of satellites at exactly the same position (by the bits of their offsets), each group's members
/// in ascending index, groups in order of their first member; `None` when all positions are distinct.
fn duplicate_groups(x: &[f64], y: &[f64], z: &[f64]) -> Option<Vec<Vec<usize>>> {
    let key = |i: usize| (x[i].to_bits(), y[i].to_bits(), z[i].to_bits());
    let mut order: Vec<usize> = (0..x.len()).collect();
    order.sort_unstable_by_key(|&i| (key(i), i));
    if order.windows(2).all(|w| key(w[0]) != key(w[1])) {
        return None;
    }
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for (k, &i) in order.iter().enumerate() {
        if k > 0 && key(order[k - 1]) == key(i) {
            groups.last_mut().expect("a group is open").push(i);
        } else {
            groups.push(vec![i]);
        }
    }
    groups.sort_unstable_by_key(|g| g[0]);
    Some(groups)
}

/// `(d_min, M, diameter, Σ m_i³)` of a swarm with duplicate positions, exactly as the general path would
/// give them, in O(N log N): a satellite with a twin has m_i = 0; the others find their nearest neighbour
/// among the distinct positions; cross-group pairs use each group's largest radius (and weight), and
/// within a group the gap is minus its two largest radii.
fn with_duplicates(
    ws: &mut FiveElementsWorkspace,
    groups: &[Vec<usize>],
    radii_m: Option<&[f64]>,
) -> Result<(f64, f64, f64, f64), MetricsError> {
    let g = groups.len();
    let ux: Vec<f64> = groups.iter().map(|m| ws.x[m[0]]).collect();
    let uy: Vec<f64> = groups.iter().map(|m| ws.y[m[0]]).collect();
    let uz: Vec<f64> = groups.iter().map(|m| ws.z[m[0]]).collect();
    // Half nearest-neighbour distance of every distinct position (0 for a group of two or more).
    let mut half_u = vec![0.0; g];
    let mut nn_u = vec![0usize; g];
    if g >= 2 {
        build_grid_for_spacing(&mut ws.grid, &ux, &uy, &uz)?;
        for k in 0..g {
            let nb = ws
                .grid
                .nearest_neighbour(k)
                .expect("a grid with two or more positions has a nearest neighbour");
            nn_u[k] = nb.index;
            if groups[k].len() == 1 {
                half_u[k] = 0.5 * nb.distance_m;
            }
        }
    }
    let sum_m3: f64 = {
        let mut m = vec![0.0; ws.x.len()];
        for (k, members) in groups.iter().enumerate() {
            for &i in members {
                m[i] = half_u[k];
            }
        }
        m.iter().map(|v| v * v * v).sum()
    };
    // Some group has two or more members, so d_min is at most 0 and never stays infinite.
    let d_min_m = match radii_m {
        None => 2.0 * half_u.iter().copied().fold(f64::INFINITY, f64::min),
        Some(a) => {
            let mut best = f64::INFINITY;
            let mut a_u = vec![0.0; g];
            for (k, members) in groups.iter().enumerate() {
                let (mut top1, mut top2) = (f64::NEG_INFINITY, f64::NEG_INFINITY);
                for &i in members {
                    if a[i] > top1 {
                        top2 = top1;
                        top1 = a[i];
                    } else if a[i] > top2 {
                        top2 = a[i];
                    }
                }
                a_u[k] = top1;
                if members.len() >= 2 {
                    best = best.min(0.0 - (top1 + top2));
                }
            }
            if g >= 2 {
                let a_max = a_u.iter().copied().fold(0.0, f64::max);
                best = best.min(min_surface_gap(&ws.grid, &nn_u, &a_u, a_max));
            }
            best
        }
    };
    let (big_m, diameter_m) = if g >= 2 {
        (
            0.5 * max_pair_sum(&ux, &uy, &uz, Some(&half_u), &mut ws.pairs),
            max_pair_sum(&ux, &uy, &uz, None, &mut ws.pairs),
        )
    } else {
        (0.0, 0.0)
    };
    Ok((d_min_m, big_m, diameter_m, sum_m3))
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
    /// Satellite indices, permuted so that every tree node owns a contiguous range.
    order: Vec<u32>,
    nodes: Vec<Node>,
    /// Node pairs still to search, with their upper bounds (a depth-first stack).
    stack: Vec<(f64, u32, u32)>,
}

/// Node of a kd-tree: satellites `order[start..end]`, their bounding box and largest weight.
#[derive(Clone, Copy, Debug)]
struct Node {
    start: usize,
    end: usize,
    lo: [f64; 3],
    hi: [f64; 3],
    w_max: f64,
    /// Indices of the two children, `None` for a leaf.
    children: Option<(u32, u32)>,
}

/// Leaves hold at most this many satellites.
const LEAF_SIZE: usize = 16;

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

/// Upper bound of `pair_value` over satellite pairs drawn from nodes `a` and `b`.
fn node_bound(a: &Node, b: &Node) -> f64 {
    box_max_distance(a.lo, a.hi, b.lo, b.hi) + a.w_max + b.w_max
}

/// Node over `order[start..end]` with its bounding box and largest weight (no children yet).
fn make_node(
    coords: [&[f64]; 3],
    weight: impl Fn(usize) -> f64,
    order: &[u32],
    start: usize,
    end: usize,
) -> Node {
    let mut node = Node {
        start,
        end,
        lo: [f64::INFINITY; 3],
        hi: [f64::NEG_INFINITY; 3],
        w_max: 0.0,
        children: None,
    };
    for &i in &order[start..end] {
        let i = i as usize;
        for (k, c) in coords.iter().enumerate() {
            node.lo[k] = node.lo[k].min(c[i]);
            node.hi[k] = node.hi[k].max(c[i]);
        }
        node.w_max = node.w_max.max(weight(i));
    }
    node
}

/// `max_{i<j} pair_value(i, j)` over N >= 2 points with non-negative weights, exactly (the same value as
/// the all-pairs loop), by a dual-tree branch and bound over a kd-tree: a pair of nodes is opened only
/// if the largest distance between their bounding boxes plus their largest weights can beat the best
/// pair found so far, most promising pairs first.
fn max_pair_sum(x: &[f64], y: &[f64], z: &[f64], w: Option<&[f64]>, s: &mut PairScratch) -> f64 {
    let n = x.len();
    let coords = [x, y, z];
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

    // kd-tree: split every node larger than a leaf at the median of its longest box axis.
    s.order.clear();
    s.order.extend(0..n as u32);
    s.nodes.clear();
    s.nodes.push(make_node(coords, weight, &s.order, 0, n));
    let mut k = 0;
    while k < s.nodes.len() {
        let node = s.nodes[k];
        let axis = (0..3)
            .max_by(|&p, &q| (node.hi[p] - node.lo[p]).total_cmp(&(node.hi[q] - node.lo[q])))
            .expect("three axes");
        if node.end - node.start > LEAF_SIZE && node.hi[axis] > node.lo[axis] {
            let mid = (node.start + node.end) / 2;
            let c = coords[axis];
            s.order[node.start..node.end].select_nth_unstable_by(mid - node.start, |&p, &q| {
                c[p as usize].total_cmp(&c[q as usize])
            });
            let left = make_node(coords, weight, &s.order, node.start, mid);
            let right = make_node(coords, weight, &s.order, mid, node.end);
            let first = s.nodes.len() as u32;
            s.nodes.push(left);
            s.nodes.push(right);
            s.nodes[k].children = Some((first, first + 1));
        }
        k += 1;
    }

    // Depth-first search of node pairs (a <= b), largest bound first.
    let nodes = &s.nodes;
    let order = &s.order;
    s.stack.clear();
    s.stack.push((node_bound(&nodes[0], &nodes[0]), 0, 0));
    let mut children: [(f64, u32, u32); 3] = [(0.0, 0, 0); 3];
    while let Some((bound, a, b)) = s.stack.pop() {
        if cannot_beat(bound, best) {
            continue;
        }
        let (na, nb) = (&nodes[a as usize], &nodes[b as usize]);
        let count = match (a == b, na.children, nb.children) {
            (true, None, _) | (false, None, None) => {
                for sa in na.start..na.end {
                    let i = order[sa] as usize;
                    let p = [x[i], y[i], z[i]];
                    let reach = box_max_distance(p, p, nb.lo, nb.hi) + weight(i) + nb.w_max;
                    if cannot_beat(reach, best) {
                        continue;
                    }
                    let sb_start = if a == b { sa + 1 } else { nb.start };
                    for &j in &order[sb_start..nb.end] {
                        best = best.max(pair_value(x, y, z, w, i, j as usize));
                    }
                }
                0
            }
            (true, Some((l, r)), _) => {
                children[0] = (0.0, l, l);
                children[1] = (0.0, l, r);
                children[2] = (0.0, r, r);
                3
            }
            (false, ca, cb) => {
                // Open the node with the wider box (a leaf is never opened).
                let wide = |nd: &Node| (0..3).map(|k| nd.hi[k] - nd.lo[k]).fold(0.0, f64::max);
                let open_a = match (ca, cb) {
                    (Some(_), Some(_)) => wide(na) >= wide(nb),
                    (open, _) => open.is_some(),
                };
                if open_a {
                    let (l, r) = ca.expect("opened node has children");
                    children[0] = (0.0, l, b);
                    children[1] = (0.0, r, b);
                } else {
                    let (l, r) = cb.expect("opened node has children");
                    children[0] = (0.0, a, l);
                    children[1] = (0.0, a, r);
                }
                2
            }
        };
        let pending = &mut children[..count];
        for c in pending.iter_mut() {
            c.0 = node_bound(&nodes[c.1 as usize], &nodes[c.2 as usize]);
        }
        // Push the smallest bound first so the largest is searched next.
        pending.sort_unstable_by(|p, q| p.0.total_cmp(&q.0));
        for &c in pending.iter() {
            if !cannot_beat(c.0, best) {
                s.stack.push(c);
            }
        }
    }
    best
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
