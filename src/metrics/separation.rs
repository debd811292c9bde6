//! Minimum separation and hard-body collision count of a swarm, from a built
//! [`NeighbourGrid`] (O(N) for a well-sized grid, exact at any grid radius).
//!
//! The grid's positions are used as given to [`NeighbourGrid::build`] (m, any Cartesian frame), so the
//! engine can reuse the grid it already built for its collision-avoidance terms.

use rayon::prelude::*;

use super::{check_radii, MetricsError};
use crate::grid::NeighbourGrid;

/// Separation summary of a swarm snapshot.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Separation {
    /// Smallest centre-to-centre distance over all pairs (m).
    pub min_distance_m: f64,
    /// A pair `(i, j)`, `i < j`, at `min_distance_m`; among ties, the lexicographically smallest.
    pub closest_pair: (usize, usize),
    /// Number of unordered pairs with centre distance `< a_i + a_j` (hard bodies overlapping; touching
    /// bodies do not count).
    pub collisions: usize,
}

/// Minimum pairwise centre distance and the number of colliding pairs, for the satellites in `grid`
/// with hard-body radii `radii_m[i]` (m, finite and >= 0; all zeros counts no collision).
///
/// Runs in parallel over satellites; the result does not depend on the thread count (minimum with a
/// fixed tie-break, integer count).
///
/// # Errors
/// [`MetricsError::TooFewSatellites`] when the grid holds fewer than two satellites;
/// [`MetricsError::LengthMismatch`] / [`MetricsError::InvalidRadius`] for bad radii.
pub fn min_separation(grid: &NeighbourGrid, radii_m: &[f64]) -> Result<Separation, MetricsError> {
    let n = grid.len();
    if n < 2 {
        return Err(MetricsError::TooFewSatellites { n });
    }
    let a_max = check_radii(radii_m, n)?;
    let (min_distance_m, closest_pair) = (0..n)
        .into_par_iter()
        .filter_map(|i| {
            grid.nearest_neighbour(i)
                .map(|nb| (nb.distance_m, (i.min(nb.index), i.max(nb.index))))
        })
        .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
        .expect("a grid with two or more satellites has a nearest neighbour");
    let collisions = (0..n)
        .into_par_iter()
        .map(|i| {
            let mut count = 0;
            // A partner j can only collide when d < a_i + a_j <= a_i + a_max.
            grid.for_each_within(i, radii_m[i] + a_max, |nb| {
                if nb.index > i && nb.distance_m < radii_m[i] + radii_m[nb.index] {
                    count += 1;
                }
            });
            count
        })
        .sum();
    Ok(Separation {
        min_distance_m,
        closest_pair,
        collisions,
    })
}
