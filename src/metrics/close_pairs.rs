//! The close pairs of a swarm at the separation tracker's last full search: for a swarm whose satellites
//! all sit at nearly the same nearest-neighbour distance (a lattice, a regular formation), the
//! per-satellite bound of [`super::SeparationTracker`] cannot exclude anyone, as every satellite ties the
//! minimum to within the rounding margin. Listing each satellite's near partners lets the tracker measure
//! those pairs directly and bound every other pair by the distance beyond the list instead.
//!
//! At a full search, satellite i lists every partner j with d_ij ≤ (1 + [`LIST_BAND`]) d_i (d_i its
//! nearest-neighbour distance), at most [`MAX_LISTED`] of them (else none), and records the distance
//! beyond its list, r_i: the smallest d_ij of a partner not listed (a lower bound of it when none lies
//! within the search reach). Every pair that neither end lists is then at least max(r_i, r_j) apart at
//! the full search, so the tracker's bound holds with r_i in place of d_i for all pairs but the listed
//! ones, which it measures. A satellite that lists nobody has r_i = d_i, the plain bound.
//!
//! Pairs are kept by satellite id, each once (smaller id first, sorted), 8 bytes a pair.

use rayon::prelude::*;

use super::separation::{nearer, TrackedPositions};
use crate::grid::NeighbourGrid;

/// A satellite lists the partners within `(1 + LIST_BAND)` times its nearest-neighbour distance.
pub(super) const LIST_BAND: f64 = 0.25;

/// A satellite lists at most this many partners; with more within the band it lists none.
const MAX_LISTED: usize = 12;

/// The reach of the search for the distance beyond a satellite's list, in nearest-neighbour distances.
const BEYOND_REACH: f64 = 1.0 + 2.0 * LIST_BAND;

/// How many pairs ahead [`ClosePairs::measure`] hints the cache at a pair's second satellite.
const PREFETCH_AHEAD: usize = 16;

/// Smallest number of satellites or pairs per parallel work item.
const PARALLEL_MIN_LEN: usize = 4096;

/// The listed pairs, by id (smaller first), sorted and without repeats.
#[derive(Clone, Debug, Default)]
pub(super) struct ClosePairs {
    pairs: Vec<(u32, u32)>,
}

/// The closest of the listed pairs now: its distance (m) and ids (smaller first).
pub(super) type Closest = Option<(f64, (usize, usize))>;

impl ClosePairs {
    /// No pairs.
    pub fn clear(&mut self) {
        self.pairs.clear();
        self.pairs.shrink_to_fit();
    }

    /// Lists the close pairs of the snapshot `positions` in `grid` (built over the snapshot's indices)
    /// and replaces each satellite's nearest-neighbour distance in `bound_m` (m, by snapshot index) by
    /// the distance beyond its list.
    pub fn list(
        &mut self,
        grid: &NeighbourGrid,
        positions: &impl TrackedPositions,
        bound_m: &mut [f64],
    ) {
        self.pairs.clear();
        self.pairs.par_extend(
            bound_m
                .par_iter_mut()
                .enumerate()
                .with_min_len(PARALLEL_MIN_LEN)
                .flat_map_iter(|(k, beyond)| {
                    let nearest = *beyond;
                    let band = nearest * (1.0 + LIST_BAND);
                    let reach = nearest * BEYOND_REACH;
                    // The listed partners' ids.
                    let mut listed = [0u32; MAX_LISTED];
                    let (mut count, mut overflow) = (0, false);
                    // Partners not visited are farther than the reach.
                    *beyond = reach;
                    grid.for_each_within(k, reach, |nb| {
                        if nb.distance_m > band {
                            *beyond = beyond.min(nb.distance_m);
                        } else if count < MAX_LISTED {
                            listed[count] = pair_id(positions, nb.index);
                            count += 1;
                        } else {
                            overflow = true;
                        }
                    });
                    if overflow || !reach.is_finite() {
                        // Nobody listed: every partner is at least the nearest distance away.
                        *beyond = nearest;
                        count = 0;
                    }
                    let own = pair_id(positions, k);
                    listed
                        .into_iter()
                        .take(count)
                        .map(move |other| (own.min(other), own.max(other)))
                }),
        );
        self.pairs.par_sort_unstable();
        self.pairs.dedup();
    }

    /// Renames the satellites: old id `i` becomes `new_ids[i]` (a permutation of the ids listed).
    pub fn rename(&mut self, new_ids: &[u32]) {
        self.pairs.par_iter_mut().for_each(|(a, b)| {
            let (x, y) = (new_ids[*a as usize], new_ids[*b as usize]);
            (*a, *b) = (x.min(y), x.max(y));
        });
        self.pairs.par_sort_unstable();
    }

    /// Whether no pair is listed.
    pub fn is_empty(&self) -> bool {
        self.pairs.is_empty()
    }

    /// Measures every listed pair whose two satellites are both in `positions` now: the closest one
    /// (smallest distance, then smallest ids), returned, and the pairs closer than the sum of their
    /// radii (`radii_m` by snapshot index, m), whose snapshot indices go to `colliding`. The distances
    /// are computed as the grid and the brute force compute them, bit for bit.
    pub fn measure(
        &self,
        positions: &impl TrackedPositions,
        radii_m: &[f64],
        colliding: &mut Vec<(usize, usize)>,
    ) -> Closest {
        let measured = |&(a, b): &(u32, u32)| {
            let ka = positions.index_of_id(a as usize)?;
            let kb = positions.index_of_id(b as usize)?;
            let ([xa, ya, za], [xb, yb, zb]) = (positions.position_m(ka), positions.position_m(kb));
            let (dx, dy, dz) = (xb - xa, yb - ya, zb - za);
            let d = (dx * dx + dy * dy + dz * dz).sqrt();
            Some((d, (ka, kb), d < radii_m[ka] + radii_m[kb]))
        };
        // Fixed chunks, each scanned by a plain loop in ascending pair order (the first pair at a
        // chunk's minimum is its smallest), then the chunks' answers merged: the same closest pair and
        // count as any order of the pairs (a per-pair parallel reduction cost several times the
        // distances themselves).
        let (closest, collisions) = self
            .pairs
            .par_chunks(PARALLEL_MIN_LEN)
            .map(|pairs| {
                let mut closest: Closest = None;
                let mut collisions = 0;
                for (p, pair) in pairs.iter().enumerate() {
                    // The second satellites lie anywhere in memory: start their loads ahead.
                    if let Some(ahead) = pairs.get(p + PREFETCH_AHEAD) {
                        positions.prefetch_id(ahead.1 as usize);
                    }
                    if let Some((d, _, collides)) = measured(pair) {
                        if closest.is_none_or(|(best, _)| d < best) {
                            closest = Some((d, (pair.0 as usize, pair.1 as usize)));
                        }
                        collisions += usize::from(collides);
                    }
                }
                (closest, collisions)
            })
            .reduce(
                || (None, 0),
                |(a, n), (b, m)| {
                    let closest = match (a, b) {
                        (Some(a), Some(b)) => Some(nearer(a, b)),
                        (a, b) => a.or(b),
                    };
                    (closest, n + m)
                },
            );
        colliding.clear();
        if collisions > 0 {
            colliding.par_extend(
                self.pairs
                    .par_iter()
                    .with_min_len(PARALLEL_MIN_LEN)
                    .filter_map(|pair| measured(pair).filter(|m| m.2).map(|m| m.1)),
            );
        }
        closest
    }
}

/// The id of the satellite at snapshot index `k`, as a pair stores it: the tracker refuses ids of
/// [`crate::grid::MAX_POINTS`] (2^28) or more before it lists any pair, so every id fits 32 bits.
fn pair_id(positions: &impl TrackedPositions, k: usize) -> u32 {
    u32::try_from(positions.id(k)).expect("ids below grid::MAX_POINTS, checked by the tracker")
}
