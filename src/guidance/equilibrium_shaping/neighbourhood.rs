//! Node neighbourhoods through the cell-list grid ([`NeighbourGrid`]): what keeps the law's set-up,
//! checks and record-time metrics near O(N) at 10⁶ nodes instead of a loop over every node pair.
//!
//! * [`extent_m`]: the diagonal of the nodes' bounding box, the length scale of the coincidence test.
//! * [`closest_pair_within`]: the closest node pair within a distance (the coincidence test of
//!   [`super::shaping::check_nodes`]), from the pairs the grid finds.
//! * [`pair_cutoff_m`] and [`pair_tail_per_s`]: the radius beyond which the Gershgorin bound of the
//!   Eq. 1 field's Jacobian at the nodes neglects a pair, and the analytic bound of what it neglects
//!   (added back, so the bound stays an upper bound).
//! * [`NodePairs`]: the node pairs within a radius, each node's partners in ascending index (the
//!   record-time formation error).
//! * [`PairValues`]: one value per node pair within a radius, tabulated once (the Eq. 1 field's
//!   attractions a_ij, looked up per neighbour and step instead of recomputed).
//!
//! Nodes are Hill-frame positions \[m\].

use nalgebra::Vector3;

use crate::grid::NeighbourGrid;

/// What the Gershgorin bound of the Eq. 1 field may neglect, relative to the repulsion strength b
/// (the scale of its rows): the tail bound [`pair_tail_per_s`] at [`pair_cutoff_m`] is at most
/// `NEGLECTED_RELATIVE` · b.
pub const NEGLECTED_RELATIVE: f64 = 1e-16;

/// Fixed-point iterations that solve for [`pair_cutoff_m`] (each gains a factor of about 20 in
/// accuracy; the tail bound is recomputed from the radius found, so the accuracy of the solve only
/// affects how much is neglected, never the bound's validity).
const CUTOFF_ITERATIONS: usize = 30;

/// Diagonal of the axis-aligned bounding box of `nodes_m` \[m\] (0 without nodes): between 1 and √3
/// times the largest node distance, in O(N).
pub fn extent_m(nodes_m: &[Vector3<f64>]) -> f64 {
    let Some(first) = nodes_m.first() else {
        return 0.0;
    };
    let (low, high) = nodes_m
        .iter()
        .fold((*first, *first), |(low, high), p| (low.inf(p), high.sup(p)));
    (high - low).norm()
}

/// A grid over `nodes_m` (finite coordinates) with query radius `radius_m` \[m\], clamped to the
/// smallest positive number (the grid clamps its cells, not its inclusion rule, so a zero radius still
/// finds coincident nodes).
///
/// # Panics
/// If a node coordinate is not finite or there are more nodes than the grid indexes (2³² − 1): the
/// callers check both first.
pub fn node_grid(nodes_m: &[Vector3<f64>], radius_m: f64) -> NeighbourGrid {
    let axis = |k: usize| -> Vec<f64> { nodes_m.iter().map(|p| p[k]).collect() };
    let mut grid = NeighbourGrid::new();
    grid.build(
        &axis(0),
        &axis(1),
        &axis(2),
        radius_m.max(f64::MIN_POSITIVE),
    )
    .expect("finite nodes, fewer than 2^32");
    grid
}

/// The closest node pair (first, second, distance \[m\]), first < second, among the pairs at most
/// `threshold_m` \[m\] apart (`None` when there is none): the smallest distance, ties to the smallest
/// first then second index, as a loop over every pair in lexicographic order would pick. The distance
/// is computed as `‖ξ_i − ξ_j‖` is (the grid's inclusion rule). O(N log N) (the grid's build) plus the
/// pairs found.
pub fn closest_pair_within(
    nodes_m: &[Vector3<f64>],
    threshold_m: f64,
) -> Option<(usize, usize, f64)> {
    let grid = node_grid(nodes_m, threshold_m);
    let mut closest: Option<(usize, usize, f64)> = None;
    for i in 0..nodes_m.len() {
        grid.for_each_neighbour(i, |nb| {
            let (j, d) = (nb.index, nb.distance_m);
            let better = match closest {
                None => true,
                Some((a, b, best)) => d < best || (d == best && (i, j) < (a, b)),
            };
            if j > i && d <= threshold_m && better {
                closest = Some((i, j, d));
            }
        });
    }
    closest
}

/// Upper bound of one row sum of |∂g/∂y| of the Eq. 1 pair term at its node distance δ, i.e. of
/// |h| + (2 b e/c) |y_k| ‖y‖₁ with e = e^(−δ²/c) and h = a − b e (zero but for rounding, below b e):
/// b e^(−u) (1 + 2√3 u), u = δ²/c, for repulsion strength `b_per_s` \[1/s\], range `c_m2` \[m²\] and
/// `distance_m` = δ \[m\]. Decreasing in δ for δ² ≥ c.
fn pair_row_bound_per_s(b_per_s: f64, c_m2: f64, distance_m: f64) -> f64 {
    let u = distance_m * distance_m / c_m2;
    b_per_s * (-u).exp() * (1.0 + 2.0 * 3f64.sqrt() * u)
}

/// Bound of what the Gershgorin row sums of the Eq. 1 field's stacked Jacobian at `nodes` nodes lose
/// when every pair farther apart than `cutoff_m` \[m\] (≥ √c) is left out \[1/s\]: each left-out pair
/// changes a row by at most twice `pair_row_bound_per_s` at δ (once in the own block, once in the
/// neighbour's), which is at most its value at `cutoff_m`, and a row has at most `nodes` − 1 pairs.
pub fn pair_tail_per_s(b_per_s: f64, c_m2: f64, cutoff_m: f64, nodes: usize) -> f64 {
    2.0 * nodes.saturating_sub(1) as f64 * pair_row_bound_per_s(b_per_s, c_m2, cutoff_m)
}

/// The smallest cutoff radius r_c ≥ √c \[m\] (to the solve's accuracy) at which
/// [`pair_tail_per_s`] ≤ [`NEGLECTED_RELATIVE`] · b for `nodes` nodes and range `c_m2` = c \[m²\]: with
/// u = r_c²/c, 2 (N − 1)(1 + 2√3 u) e^(−u) ≤ ε, solved by the fixed-point iteration
/// u ← ln(2 (N − 1)/ε) + ln(1 + 2√3 u) from below: 22.3 m at 10³ nodes and 23.8 m at 10⁶ for
/// c = 10 m² (7.0 √c and 7.5 √c; it grows as √(c ln N)).
pub fn pair_cutoff_m(c_m2: f64, nodes: usize) -> f64 {
    let log_ratio = (2.0 * nodes.max(2).saturating_sub(1) as f64 / NEGLECTED_RELATIVE).ln();
    let mut u: f64 = log_ratio;
    for _ in 0..CUTOFF_ITERATIONS {
        u = log_ratio + (1.0 + 2.0 * 3f64.sqrt() * u).ln();
    }
    (c_m2 * u.max(1.0)).sqrt()
}

/// The node pairs (i, j) whose nodes are at most a radius apart, δ_ij ≤ r, each node's later partners
/// (j > i) visited in ascending j: a sum over them runs in the order of a loop over every pair in
/// lexicographic order restricted to them, so it has the same bits when the radius reaches every pair.
#[derive(Clone, Debug)]
pub struct NodePairs {
    /// The grid over the nodes with the radius; `None` when the radius reaches every pair.
    grid: Option<NeighbourGrid>,
    /// Number of nodes.
    count: usize,
}

impl NodePairs {
    /// Every pair of `count` nodes.
    pub fn every(count: usize) -> Self {
        Self { grid: None, count }
    }

    /// The pairs of `nodes_m` (finite) at most `radius_m` \[m\] apart: every pair when the radius
    /// reaches the bounding box's diagonal ([`extent_m`]) or is not finite, else those the grid finds.
    pub fn within(nodes_m: &[Vector3<f64>], radius_m: f64) -> Self {
        if radius_m.is_finite() && radius_m < extent_m(nodes_m) {
            Self {
                grid: Some(node_grid(nodes_m, radius_m)),
                count: nodes_m.len(),
            }
        } else {
            Self::every(nodes_m.len())
        }
    }

    /// Calls `visit(j)` for every partner j > i of node `i`, in ascending j; `scratch` holds the
    /// partners meanwhile (kept by the caller across nodes, so a loop over nodes allocates only while
    /// it grows).
    pub fn for_each_later_partner(
        &self,
        i: usize,
        scratch: &mut Vec<usize>,
        mut visit: impl FnMut(usize),
    ) {
        match &self.grid {
            None => (i + 1..self.count).for_each(visit),
            Some(grid) => {
                scratch.clear();
                grid.for_each_neighbour(i, |nb| {
                    if nb.index > i {
                        scratch.push(nb.index);
                    }
                });
                scratch.sort_unstable();
                scratch.iter().for_each(|j| visit(*j));
            }
        }
    }
}

/// Largest mean number of partners per node [`PairValues::within`] tabulates (a radius reaching more
/// leaves the table empty: its lookups then miss and the caller computes the values, as without it).
pub const MAX_MEAN_PARTNERS: usize = 64;

/// One value per ordered node pair (i, j), j ≠ i, whose nodes are at most a radius apart: each node's
/// partners in ascending index, found by binary search. O(N k) memory and set-up (k: partners per
/// node), O(log k) per lookup.
#[derive(Clone, Debug, Default)]
pub struct PairValues {
    /// Node i's partners and values are at `starts[i]..starts[i + 1]` (empty table: no entries).
    starts: Vec<usize>,
    /// Partner indices, ascending within each node's range.
    partners: Vec<u32>,
    /// `value(i, j)` of each entry.
    values: Vec<f64>,
}

impl PairValues {
    /// `value(i, j)` for the pairs of `nodes_m` (finite) at most `radius_m` \[m\] apart (the grid's
    /// inclusion rule); empty when the radius is not finite or the pairs exceed
    /// [`MAX_MEAN_PARTNERS`] per node on average.
    pub fn within(
        nodes_m: &[Vector3<f64>],
        radius_m: f64,
        value: impl Fn(usize, usize) -> f64,
    ) -> Self {
        if !radius_m.is_finite() || nodes_m.len() > u32::MAX as usize {
            return Self::default();
        }
        let grid = node_grid(nodes_m, radius_m);
        let limit = MAX_MEAN_PARTNERS.saturating_mul(nodes_m.len());
        let mut table = Self {
            starts: Vec::with_capacity(nodes_m.len() + 1),
            ..Self::default()
        };
        table.starts.push(0);
        for i in 0..nodes_m.len() {
            let start = table.partners.len();
            grid.for_each_neighbour(i, |nb| table.partners.push(nb.index as u32));
            if table.partners.len() > limit {
                return Self::default();
            }
            table.partners[start..].sort_unstable();
            for &j in &table.partners[start..] {
                table.values.push(value(i, j as usize));
            }
            table.starts.push(table.partners.len());
        }
        table
    }

    /// The value of the pair (i, j), `None` when the table does not hold it.
    #[inline]
    pub fn get(&self, i: usize, j: usize) -> Option<f64> {
        let (Some(&start), Some(&end), Ok(j)) =
            (self.starts.get(i), self.starts.get(i + 1), u32::try_from(j))
        else {
            return None;
        };
        let e = self.partners[start..end].binary_search(&j).ok()?;
        Some(self.values[start + e])
    }
}

#[cfg(test)]
mod tests {
    //! Every query against a brute-force loop over every node pair, on clouds with planted close and
    //! tied pairs; the cutoff against its defining inequality.

    use super::*;

    /// `count` points uniform in a cube of side `side_m` \[m\] (xorshift, fixed seed).
    fn cloud(count: usize, side_m: f64, seed: u64) -> Vec<Vector3<f64>> {
        let mut state = seed;
        let mut uniform = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        (0..count)
            .map(|_| Vector3::new(uniform(), uniform(), uniform()) * side_m)
            .collect()
    }

    fn brute_closest(nodes: &[Vector3<f64>], threshold_m: f64) -> Option<(usize, usize, f64)> {
        let mut closest: Option<(usize, usize, f64)> = None;
        for i in 0..nodes.len() {
            for j in i + 1..nodes.len() {
                let d = (nodes[i] - nodes[j]).norm();
                if d <= threshold_m && closest.is_none_or(|(_, _, best)| d < best) {
                    closest = Some((i, j, d));
                }
            }
        }
        closest
    }

    #[test]
    fn closest_pair_within_matches_every_pair() {
        let mut nodes = cloud(300, 50.0, 7);
        // Planted: a near pair, an exact duplicate, and a tie of two duplicates (the first pair wins).
        nodes[40] = nodes[17] + Vector3::new(1e-8, 0.0, 0.0);
        nodes[250] = nodes[3];
        nodes[120] = nodes[2];
        for threshold_m in [0.0, 1e-9, 1e-6, 0.5, 3.0] {
            assert_eq!(
                closest_pair_within(&nodes, threshold_m),
                brute_closest(&nodes, threshold_m),
                "threshold {threshold_m} m"
            );
        }
        assert_eq!(closest_pair_within(&nodes, 0.0), Some((2, 120, 0.0)));
        let distinct = cloud(300, 50.0, 11);
        assert_eq!(closest_pair_within(&distinct, 1e-9), None);
        let all_on_one = vec![Vector3::new(1.0, 2.0, 3.0); 5];
        assert_eq!(closest_pair_within(&all_on_one, 0.0), Some((0, 1, 0.0)));
    }

    #[test]
    fn extent_is_the_bounding_box_diagonal() {
        let nodes = [
            Vector3::new(1.0, -2.0, 0.5),
            Vector3::new(4.0, 2.0, 0.5),
            Vector3::new(2.0, 0.0, -11.5),
        ];
        assert_eq!(extent_m(&nodes), (9.0f64 + 16.0 + 144.0).sqrt());
        assert_eq!(extent_m(&[]), 0.0);
        let cloud = cloud(200, 30.0, 3);
        let largest = (0..cloud.len())
            .flat_map(|i| (0..cloud.len()).map(move |j| (i, j)))
            .map(|(i, j)| (cloud[i] - cloud[j]).norm())
            .fold(0.0, f64::max);
        let extent = extent_m(&cloud);
        assert!(largest <= extent && extent <= 3f64.sqrt() * largest);
    }

    #[test]
    fn node_pairs_are_every_pair_within_the_radius_in_lexicographic_order() {
        let nodes = cloud(400, 60.0, 5);
        for radius_m in [4.0, 13.0, 200.0, f64::INFINITY] {
            let pairs = NodePairs::within(&nodes, radius_m);
            let mut found = Vec::new();
            let mut scratch = Vec::new();
            for i in 0..nodes.len() {
                pairs.for_each_later_partner(i, &mut scratch, |j| found.push((i, j)));
            }
            let brute: Vec<(usize, usize)> = (0..nodes.len())
                .flat_map(|i| (i + 1..nodes.len()).map(move |j| (i, j)))
                .filter(|(i, j)| (nodes[*i] - nodes[*j]).norm() <= radius_m)
                .collect();
            assert_eq!(found, brute, "radius {radius_m} m");
        }
    }

    #[test]
    fn pair_values_hold_every_pair_within_the_radius() {
        let nodes = cloud(300, 40.0, 9);
        let value = |i: usize, j: usize| (i * 1000 + j) as f64;
        let table = PairValues::within(&nodes, 6.0, value);
        for i in 0..nodes.len() {
            for j in 0..nodes.len() {
                let within = j != i && (nodes[i] - nodes[j]).norm() <= 6.0;
                let expected = within.then(|| value(i, j));
                assert_eq!(table.get(i, j), expected, "pair ({i}, {j})");
            }
        }
        assert_eq!(table.get(nodes.len(), 0), None);
        // Beyond the mean partner cap, and at an infinite radius: nothing is tabulated.
        assert_eq!(PairValues::within(&nodes, 1e3, value).get(0, 1), None);
        assert_eq!(
            PairValues::within(&nodes, f64::INFINITY, value).get(0, 1),
            None
        );
    }

    #[test]
    fn pair_cutoff_meets_its_tail_target() {
        let (b, c) = (20.0, 10.0);
        for nodes in [129, 2_000, 1_000_000, 100_000_000] {
            let r_c = pair_cutoff_m(c, nodes);
            let tail = pair_tail_per_s(b, c, r_c, nodes);
            // At the fixed point to rounding; 1 % smaller radius would not meet it.
            assert!(
                tail <= NEGLECTED_RELATIVE * b * (1.0 + 1e-9),
                "{nodes}: {tail:e}"
            );
            let smaller = pair_tail_per_s(b, c, 0.99 * r_c, nodes);
            assert!(smaller > NEGLECTED_RELATIVE * b, "{nodes}: {smaller:e}");
            assert!(r_c >= c.sqrt());
        }
        assert!((pair_cutoff_m(c, 1_000_000) - 23.80).abs() < 0.01);
        assert!((pair_cutoff_m(c, 1_000) - 22.27).abs() < 0.01);
    }
}
