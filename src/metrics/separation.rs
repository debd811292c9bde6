//! Minimum separation and hard-body collision count of a swarm, from a built
//! [`NeighbourGrid`] (O(N) for a well-sized grid, exact at any grid radius), and
//! [`SeparationTracker`], the same exact answer for a moving swarm without a full search every step.
//!
//! The grid's positions are used as given to [`NeighbourGrid::build`] (m, any Cartesian frame), so the
//! engine can reuse the grid it already built for its collision-avoidance terms.
//!
//! **Tracking a moving swarm exactly.** After a full search at time t_k the tracker keeps every
//! satellite's position p_i(t_k) and nearest-neighbour distance d_i(t_k). At a later snapshot it fits the
//! affine motion q ≈ M p + b that best carries the anchors onto the positions now (least squares,
//! `motion_fit`), with e_i the residual of satellite i, e_max the largest and σ a lower bound of M's
//! smallest singular value. Then for every pair d_ij(t) ≥ σ d_ij(t_k) − e_i − e_j ≥ σ d_i(t_k) − e_i −
//! e_max =: L_i (the plain bound with displacements is the case M = I; a swarm drifting together has
//! residuals far below its displacements, so the bound stays tight for many more steps). The plain
//! bound is tried first, as it needs no fitting pass; the fit once the plain bound lets more than a
//! 32nd of the swarm through (the plain bound again, should the fit do worse), and from then on until the
//! next full search. As any affine motion gives a valid
//! bound, a snapshot after two fitted ones first uses their linear extrapolation, in the same pass that
//! sums its own fit, and takes the fit's residuals only when the extrapolation lets too many
//! through. The previous
//! closest pair's distance now, U, is an upper bound of the minimum. A pair at the minimum has both ends
//! with L ≤ U, and a colliding pair (d_ij < a_i + a_j ≤ a_i + a_max) both ends with L_i < a_i + a_max; so
//! the exact minimum, its lexicographically smallest pair and the collision count are those of the
//! *candidates* (the satellites meeting either test), searched among themselves. L is lowered by a margin
//! of 1e-9 times the largest coordinate magnitude (times 1 + ‖M‖), a million times the rounding of the
//! distances and residuals involved, so floating
//! point never drops a candidate. When the candidates exceed a quarter of the swarm, or the satellite set
//! gained a member, or the narrow searches since the last full search have searched as many candidates as
//! the swarm holds (anchors gone stale: pairs close then have drifted apart but keep their satellites
//! candidates), the tracker does a full search and takes new anchors. Satellites may leave the set
//! between snapshots (a removed satellite): the bounds of the others stay valid.
//!
//! **Tied swarms.** On a lattice every satellite ties the minimum within the margin, so every one is a
//! candidate. Once that forces a full search within two narrow ones of the last, full searches also list
//! each satellite's close partners (`close_pairs`): d_i is replaced by the distance beyond the list, the
//! listed pairs are measured directly (their closest also bounds the minimum from above), and the answer
//! is the better of theirs and the candidates', a colliding pair counted once.

use rayon::prelude::*;

use nalgebra::Vector3;

use super::close_pairs::ClosePairs;
use super::motion_fit::{AffineMotion, FitSums, SUM_BLOCK};
use super::{check_radii, MetricsError};
use crate::grid::{NeighbourGrid, MAX_POINTS};

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
    search(grid, radii_m, &mut Vec::new(), &mut Vec::new())
}

/// [`min_separation`], also writing every satellite's nearest-neighbour distance (m) into `nearest_m`
/// (resized to the grid's length; `by_slot_m` is scratch). The queries run in the grid's storage
/// order (consecutive queries then read the same rows of cells, in cache; in the order of the
/// satellites, twice as slow at 10⁶ in the engine), and their distances are gathered back by
/// satellite; the minimum with its tie-break and the collision count do not depend on the order.
fn search(
    grid: &NeighbourGrid,
    radii_m: &[f64],
    nearest_m: &mut Vec<f64>,
    by_slot_m: &mut Vec<f64>,
) -> Result<Separation, MetricsError> {
    let n = grid.len();
    if n < 2 {
        return Err(MetricsError::TooFewSatellites { n });
    }
    let a_max = check_radii(radii_m, n)?;
    let order = grid.cell_order();
    by_slot_m.resize(n, 0.0);
    let (min_distance_m, closest_pair) = by_slot_m
        .par_iter_mut()
        .zip(order)
        .with_min_len(256)
        .filter_map(|(nearest, &i)| {
            let i = i as usize;
            grid.nearest_neighbour(i).map(|nb| {
                *nearest = nb.distance_m;
                (nb.distance_m, (i.min(nb.index), i.max(nb.index)))
            })
        })
        .reduce_with(nearer)
        .expect("a grid with two or more satellites has a nearest neighbour");
    nearest_m.resize(n, 0.0);
    nearest_m
        .par_iter_mut()
        .enumerate()
        .with_min_len(4096)
        .for_each(|(i, nearest)| *nearest = by_slot_m[grid.slot(i)]);
    let collisions = order
        .par_iter()
        .with_min_len(256)
        .map(|&i| {
            let i = i as usize;
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

/// The nearer of two pairs given as (distance (m), pair): the smaller distance, then the
/// lexicographically smaller pair (the tie-break of [`Separation::closest_pair`]).
pub(super) fn nearer(a: (f64, (usize, usize)), b: (f64, (usize, usize))) -> (f64, (usize, usize)) {
    if b.0.total_cmp(&a.0).then(b.1.cmp(&a.1)).is_lt() {
        b
    } else {
        a
    }
}

/// A grid cell edge (m) that suits an exact nearest-neighbour search over the `count` positions
/// `position_m(k)` (m): the swarm's mean spacing (cube root of bounding-box volume per satellite, flat
/// swarms padded to a slab). `None` when every position is the same point or a coordinate is not
/// finite (or there are none).
fn spacing_cell_m(count: usize, position_m: impl Fn(usize) -> [f64; 3]) -> Option<f64> {
    if count == 0 {
        return None;
    }
    let mut low = [f64::INFINITY; 3];
    let mut high = [f64::NEG_INFINITY; 3];
    for i in 0..count {
        for (a, v) in position_m(i).into_iter().enumerate() {
            low[a] = low[a].min(v);
            high[a] = high[a].max(v);
        }
    }
    let extent = [high[0] - low[0], high[1] - low[1], high[2] - low[2]];
    let largest = extent[0].max(extent[1]).max(extent[2]);
    if !(largest.is_finite() && largest > 0.0) {
        return None;
    }
    let floor = largest / (count as f64).cbrt();
    let volume: f64 = extent.iter().map(|e| e.max(floor)).product();
    let cell_m = (volume / count as f64).cbrt();
    cell_m.is_finite().then_some(cell_m)
}

/// The satellites one [`SeparationTracker`] update sees: how many, each one's id (strictly ascending
/// in `k`) and position (m, one Cartesian frame kept across calls). The engine reads them straight
/// from its truth states, so a snapshot needs no copy of its positions.
pub(crate) trait TrackedPositions: Sync {
    /// Number of satellites in the snapshot.
    fn len(&self) -> usize;
    /// Id of the `k`-th satellite.
    fn id(&self, k: usize) -> usize;
    /// Position of the `k`-th satellite (m).
    fn position_m(&self, k: usize) -> [f64; 3];
    /// Whether the ids ascend strictly by construction, so that an update need not check them.
    fn ids_known_ascending(&self) -> bool {
        false
    }
    /// Index `k` of the satellite with id `id`, if it is there (ids ascending): a bisection unless
    /// the implementation knows better.
    fn index_of_id(&self, id: usize) -> Option<usize> {
        let n = self.len();
        let (mut low, mut high) = (0, n);
        while low < high {
            let mid = low + (high - low) / 2;
            if self.id(mid) < id {
                low = mid + 1;
            } else {
                high = mid;
            }
        }
        (low < n && self.id(low) == id).then_some(low)
    }
    /// Hints the cache at the position of the satellite with id `id`, to be read soon through
    /// [`Self::index_of_id`] (nothing unless the implementation can find it cheaply).
    fn prefetch_id(&self, _id: usize) {}
}

/// Positions given as three columns with their ids ([`SeparationTracker::update`]); equal lengths.
struct Columns<'a> {
    ids: &'a [usize],
    x_m: &'a [f64],
    y_m: &'a [f64],
    z_m: &'a [f64],
}

impl TrackedPositions for Columns<'_> {
    fn len(&self) -> usize {
        self.ids.len()
    }

    fn id(&self, k: usize) -> usize {
        self.ids[k]
    }

    fn position_m(&self, k: usize) -> [f64; 3] {
        [self.x_m[k], self.y_m[k], self.z_m[k]]
    }
}

/// Smallest number of satellites per parallel work item of the tracker's per-satellite passes.
const PARALLEL_MIN_LEN: usize = 4096;

/// Satellites per batch of the residual pass's square roots (a divisor of [`SUM_BLOCK`]).
const RESIDUAL_BATCH: usize = 64;
/// Lanes of the residual pass's largest-residual maxima (one 512-bit register).
const RESIDUAL_LANES: usize = 8;
const _: () = assert!(
    SUM_BLOCK.is_multiple_of(RESIDUAL_BATCH) && RESIDUAL_BATCH.is_multiple_of(RESIDUAL_LANES)
);

/// A narrow search takes at most `1 / NARROW_SHARE` of the swarm as candidates; beyond that a full
/// search is cheaper.
const NARROW_SHARE: usize = 4;

/// The plain displacement bound hands over to the fitted motion's once it lets more than
/// `1 / PLAIN_SHARE` of the swarm through. A fitted pass costs about two plain passes; a candidate of a
/// narrow search costs a grid slot and a nearest-neighbour query, many times one satellite's share of a
/// pass. (Law `none` at 10⁵, 300 steps: 46–47 M sat-steps/s with a quarter, 51–52 M with a 32nd.)
const PLAIN_SHARE: usize = 32;

/// A full search forced by too many candidates within this many narrow searches of the previous one
/// turns the close-pair lists on: the satellites tie at their nearest distances.
const TIED_WITHIN: u64 = 2;

/// A full search forced by stale anchors within this many narrow searches of the previous one (the
/// narrow searches took more than a 32nd of the swarm each, on average) turns the close-pair lists on.
const STALE_WITHIN: u64 = PLAIN_SHARE as u64;

/// Up to this many candidates a narrow search compares all pairs directly; above it, it builds a grid of
/// the candidates.
const DIRECT_PAIRS_UP_TO: usize = 48;

/// Exact minimum separation, closest pair and collision count of a moving swarm over successive
/// snapshots, with a full nearest-neighbour search only when the motion since the last one requires it
/// (see the module docs for the bound and why the answer is exact). Buffers are kept across calls.
#[derive(Clone, Debug, Default)]
pub struct SeparationTracker {
    /// Per satellite id: position (m) at the last full search and its nearest-neighbour distance then
    /// (m); a NaN distance marks an id that was not in that search.
    anchors: Vec<[f64; 4]>,
    /// Ids of the last answer's closest pair.
    closest: Option<(usize, usize)>,
    grid: NeighbourGrid,
    /// Each satellite's nearest-neighbour distance at the last search (m), and the same by grid slot
    /// (the search's scratch).
    nearest_m: Vec<f64>,
    by_slot_m: Vec<f64>,
    /// Per satellite of the current snapshot: σ d_i − e_i, its lower bound before the swarm-wide terms
    /// (m): the contraction of the motion used times its anchor's nearest distance, less its distance
    /// from where that motion puts it.
    slack_m: Vec<f64>,
    /// The block sums of the fit ([`AffineMotion::fit`]).
    fit_blocks: Vec<FitSums>,
    /// Whether the plain displacement bound let more than a 32nd of the swarm through since the last
    /// full search, so that the fitted motion's bound is used first.
    fitted: bool,
    /// The fitted motions of the last two snapshots since the last full search (earlier, later), from
    /// which the next one is extrapolated.
    motions: [Option<AffineMotion>; 2],
    /// Candidates of a narrow search: their index in the snapshot, positions and radii.
    candidates: Vec<usize>,
    candidate_x: Vec<f64>,
    candidate_y: Vec<f64>,
    candidate_z: Vec<f64>,
    candidate_radii: Vec<f64>,
    /// Whether full searches list the close pairs (set for good once a full search had to follow
    /// another within [`TIED_WITHIN`] narrow searches because too many satellites were candidates).
    lists_pairs: bool,
    /// The close pairs of the last full search (empty unless `lists_pairs`).
    close_pairs: ClosePairs,
    /// The listed pairs colliding now (snapshot indices).
    colliding: Vec<(usize, usize)>,
    /// Narrow searches since the last full search.
    narrow_since_full: u64,
    /// Candidates searched by the narrow searches since the last full search.
    searched_since_full: usize,
    full_searches: u64,
    narrow_searches: u64,
}

impl SeparationTracker {
    /// An empty tracker (its first update is a full search).
    pub fn new() -> Self {
        Self::default()
    }

    /// The caller renumbered its satellites (the engine re-sorting its storage) so that new id `k` is
    /// old id `moves[k]`: `move_anchors` gets the per-id anchors, one per id `0..moves.len()`
    /// (NaN-marked where an id had none), to rearrange that way. The close pairs are renamed too, so the
    /// next update can stay a narrow search.
    pub(crate) fn renumber(&mut self, moves: &[u32], move_anchors: impl FnOnce(&mut [[f64; 4]])) {
        let n = moves.len();
        if self.anchors.len() > n {
            // Ids beyond the renumbering: start afresh.
            self.anchors.clear();
            self.close_pairs.clear();
            self.closest = None;
            return;
        }
        self.anchors.resize(n, [0.0, 0.0, 0.0, f64::NAN]);
        move_anchors(&mut self.anchors);
        if !self.close_pairs.is_empty() {
            let mut new_ids = vec![0u32; n];
            for (k, &old) in moves.iter().enumerate() {
                new_ids[old as usize] = k as u32;
            }
            self.close_pairs.rename(&new_ids);
        }
        let new_id = |old: usize| moves.iter().position(|&m| m as usize == old).unwrap_or(old);
        self.closest = self.closest.map(|(a, b)| {
            let (a, b) = (new_id(a), new_id(b));
            (a.min(b), a.max(b))
        });
    }

    /// Full searches done so far (the first update, and whenever the bound let too many through).
    pub fn full_searches(&self) -> u64 {
        self.full_searches
    }

    /// Updates answered by a search among the candidates only.
    pub fn narrow_searches(&self) -> u64 {
        self.narrow_searches
    }

    /// The separation of the satellites `ids` (strictly ascending satellite identifiers, e.g. the live
    /// satellites' indices) at positions `x_m`, `y_m`, `z_m` (m, one Cartesian frame kept across calls)
    /// with hard-body radii `radii_m` (m, finite and >= 0). Equal to [`min_separation`] over the same
    /// satellites, with [`Separation::closest_pair`] given as ids.
    ///
    /// # Errors
    /// [`MetricsError::TooFewSatellites`] with fewer than two satellites; [`MetricsError::LengthMismatch`]
    /// when the slices differ in length; [`MetricsError::UnorderedIds`] when `ids` is not strictly
    /// ascending; [`MetricsError::IdTooLarge`] for an id of [`crate::grid::MAX_POINTS`] or more (the
    /// tracker keeps 32 bytes per id up to the largest: give dense ids, like indices);
    /// [`MetricsError::InvalidRadius`]; [`MetricsError::Grid`] for a non-finite position. After an error
    /// the next update is a full search.
    pub fn update(
        &mut self,
        ids: &[usize],
        x_m: &[f64],
        y_m: &[f64],
        z_m: &[f64],
        radii_m: &[f64],
    ) -> Result<Separation, MetricsError> {
        let n = ids.len();
        if n >= 2 {
            for (what, got) in [("x", x_m.len()), ("y", y_m.len()), ("z", z_m.len())] {
                if got != n {
                    self.closest = None;
                    return Err(MetricsError::LengthMismatch {
                        what,
                        expected: n,
                        got,
                    });
                }
            }
        }
        let columns = Columns { ids, x_m, y_m, z_m };
        self.update_from(&columns, radii_m)
    }

    /// [`Self::update`] with the satellites' ids and positions read through `positions`
    /// (`radii_m[k]` the radius of its `k`-th satellite, m).
    pub(crate) fn update_from(
        &mut self,
        positions: &impl TrackedPositions,
        radii_m: &[f64],
    ) -> Result<Separation, MetricsError> {
        let result = self.checked_update(positions, radii_m);
        if result.is_err() {
            self.closest = None;
        }
        result
    }

    fn checked_update(
        &mut self,
        positions: &impl TrackedPositions,
        radii_m: &[f64],
    ) -> Result<Separation, MetricsError> {
        let n = positions.len();
        if n < 2 {
            return Err(MetricsError::TooFewSatellites { n });
        }
        if !positions.ids_known_ascending() {
            if let Some(index) = (1..n).find(|&k| positions.id(k) <= positions.id(k - 1)) {
                return Err(MetricsError::UnorderedIds { index });
            }
        }
        // The ids index the per-id anchors (ascending: the last is the largest).
        let largest_id = positions.id(n - 1);
        if largest_id >= MAX_POINTS {
            return Err(MetricsError::IdTooLarge {
                id: largest_id,
                limit: MAX_POINTS,
            });
        }
        let a_max = check_radii(radii_m, n)?;
        let separation = match self.narrow(positions, radii_m, a_max)? {
            Some(separation) => {
                self.narrow_searches += 1;
                self.narrow_since_full += 1;
                separation
            }
            None => {
                self.full_searches += 1;
                self.narrow_since_full = 0;
                self.searched_since_full = 0;
                self.full(positions, radii_m)?
            }
        };
        self.closest = Some(separation.closest_pair);
        Ok(separation)
    }

    /// A full search over every satellite; takes new anchors.
    fn full(
        &mut self,
        positions: &impl TrackedPositions,
        radii_m: &[f64],
    ) -> Result<Separation, MetricsError> {
        for anchor in &mut self.anchors {
            anchor[3] = f64::NAN;
        }
        self.fitted = false;
        self.motions = [None, None];
        self.close_pairs.clear();
        let n = positions.len();
        let Some(cell_m) = spacing_cell_m(n, |k| positions.position_m(k)) else {
            // Every satellite at one point (a non-finite coordinate is refused by the grid below).
            if let Some(index) =
                (0..n).find(|&k| !positions.position_m(k).iter().all(|v| v.is_finite()))
            {
                return Err(MetricsError::NonFinite {
                    what: "position",
                    index,
                });
            }
            return Ok(coincident(positions, radii_m));
        };
        self.grid
            .build_ranked_from(n, |k| positions.position_m(k), cell_m, None)?;
        let separation = search(
            &self.grid,
            radii_m,
            &mut self.nearest_m,
            &mut self.by_slot_m,
        )?;
        let top = positions.id(n - 1) + 1;
        if self.anchors.len() < top {
            self.anchors.resize(top, [0.0, 0.0, 0.0, f64::NAN]);
        }
        // The distance that bounds each satellite's pairs: beyond its listed partners, or its nearest.
        if self.lists_pairs {
            self.close_pairs
                .list(&self.grid, positions, &mut self.nearest_m);
        }
        for k in 0..n {
            let [x, y, z] = positions.position_m(k);
            self.anchors[positions.id(k)] = [x, y, z, self.nearest_m[k]];
        }
        let (a, b) = separation.closest_pair;
        Ok(Separation {
            closest_pair: (positions.id(a), positions.id(b)),
            ..separation
        })
    }

    /// The search among the candidates, or `None` when the bound cannot be used (no previous answer, a
    /// satellite without an anchor, too many candidates).
    fn narrow(
        &mut self,
        positions: &impl TrackedPositions,
        radii_m: &[f64],
        a_max: f64,
    ) -> Result<Option<Separation>, MetricsError> {
        let Some((a, b)) = self.closest else {
            return Ok(None);
        };
        let (Some(ia), Some(ib)) = (positions.index_of_id(a), positions.index_of_id(b)) else {
            return Ok(None);
        };
        let ([xa, ya, za], [xb, yb, zb]) = (positions.position_m(ia), positions.position_m(ib));
        let (dx, dy, dz) = (xb - xa, yb - ya, zb - za);
        let mut upper_m = (dx * dx + dy * dy + dz * dz).sqrt();
        // The listed pairs are measured directly; their closest is an upper bound too.
        let listed = (!self.close_pairs.is_empty()).then(|| {
            self.close_pairs
                .measure(positions, radii_m, &mut self.colliding)
        });
        if let Some((d, _)) = listed.flatten() {
            upper_m = upper_m.min(d);
        }
        // The plain displacement bound (M = I) first, unless it let more than a 32nd of the swarm
        // through since the last full search; then the fitted motion of the swarm, and the plain bound
        // again (up to a quarter) should the fit do worse.
        let n = positions.len();
        let identity = AffineMotion::IDENTITY;
        let plain = |tracker: &mut Self| {
            tracker.select_candidates(&identity, None, positions, radii_m, a_max, upper_m)
        };
        let plain_enough = !self.fitted
            && match plain(self) {
                Some(count) => count <= n / PLAIN_SHARE,
                // A satellite without an anchor, or a bound that is not finite.
                None => return Ok(None),
            };
        if !plain_enough {
            self.fitted = true;
            let count = match self.select_fitted(positions, radii_m, a_max, upper_m) {
                Some(count) if count <= n / NARROW_SHARE => Some(count),
                _ => plain(self),
            };
            if count.is_none_or(|count| count > n / NARROW_SHARE) {
                // Too many candidates so soon after a full search: the satellites tie.
                if count.is_some() && self.narrow_since_full < TIED_WITHIN {
                    self.lists_pairs = true;
                }
                return Ok(None);
            }
        }
        // Anchors go stale: pairs close at the last full search may have drifted apart, yet keep
        // their satellites candidates. Once the narrow searches since then have searched as many
        // candidates as the swarm holds (as much work as a full search), a full search takes new
        // anchors instead: at most twice the work of the better choice in hindsight.
        self.searched_since_full += self.candidates.len();
        if self.searched_since_full > n {
            // That soon, the satellites crowd at their nearest distances (a guided swarm held at its
            // avoidance radius): list the close pairs, as for a tie.
            if self.narrow_since_full < STALE_WITHIN {
                self.lists_pairs = true;
            }
            return Ok(None);
        }
        let among_candidates = self.search_candidates(positions, radii_m)?;
        // The minimum is a listed pair's or a pair of candidates' (see `close_pairs`); a colliding
        // pair is counted once: among the candidates when both its ends are candidates.
        let Some(listed) = listed else {
            return Ok(among_candidates);
        };
        let candidates = &self.candidates;
        let is_candidate = |k: usize| candidates.binary_search(&k).is_ok();
        let listed_collisions = self
            .colliding
            .iter()
            .filter(|&&(ka, kb)| !(is_candidate(ka) && is_candidate(kb)))
            .count();
        let found = among_candidates.map(|found| (found.min_distance_m, found.closest_pair));
        let Some(best) = listed.into_iter().chain(found).reduce(nearer) else {
            return Ok(None);
        };
        Ok(Some(Separation {
            min_distance_m: best.0,
            closest_pair: best.1,
            collisions: listed_collisions + among_candidates.map_or(0, |found| found.collisions),
        }))
    }

    /// The separation among the selected candidates (ids in the answer), `None` with fewer than two.
    fn search_candidates(
        &mut self,
        positions: &impl TrackedPositions,
        radii_m: &[f64],
    ) -> Result<Option<Separation>, MetricsError> {
        let m = self.candidates.len();
        if m < 2 {
            return Ok(None);
        }
        self.candidate_x.clear();
        self.candidate_y.clear();
        self.candidate_z.clear();
        self.candidate_radii.clear();
        for &k in &self.candidates {
            let [x, y, z] = positions.position_m(k);
            self.candidate_x.push(x);
            self.candidate_y.push(y);
            self.candidate_z.push(z);
            self.candidate_radii.push(radii_m[k]);
        }
        let (cx, cy, cz) = (&self.candidate_x, &self.candidate_y, &self.candidate_z);
        let separation =
            match spacing_cell_m(m, |k| [cx[k], cy[k], cz[k]]).filter(|_| m > DIRECT_PAIRS_UP_TO) {
                Some(cell_m) => {
                    self.grid.build(cx, cy, cz, cell_m)?;
                    search(
                        &self.grid,
                        &self.candidate_radii,
                        &mut self.nearest_m,
                        &mut self.by_slot_m,
                    )?
                }
                None => direct(cx, cy, cz, &self.candidate_radii),
            };
        let (p, q) = separation.closest_pair;
        Ok(Some(Separation {
            closest_pair: (
                positions.id(self.candidates[p]),
                positions.id(self.candidates[q]),
            ),
            ..separation
        }))
    }
}

impl SeparationTracker {
    /// The candidates under the swarm's fitted motion. With the fitted motions of earlier snapshots,
    /// one pass takes every residual under their extrapolation and the sums of this snapshot's fit; the
    /// fit's own residuals are taken only when the extrapolation lets more than a quarter of the swarm
    /// through. Returns as [`Self::select_candidates`].
    fn select_fitted(
        &mut self,
        positions: &impl TrackedPositions,
        radii_m: &[f64],
        a_max: f64,
        upper_m: f64,
    ) -> Option<usize> {
        let anchors = &self.anchors;
        let anchored = |k: usize| {
            anchors
                .get(positions.id(k))
                .filter(|a| !a[3].is_nan())
                .map(|a| Vector3::new(a[0], a[1], a[2]))
        };
        let origin_m = anchored(0)?;
        let predicted = match self.motions {
            [Some(earlier), Some(later)] => later.extrapolated_from(&earlier),
            [_, later] => later,
        };
        let fresh = match predicted {
            Some(predicted) => {
                let count = self.select_candidates(
                    &predicted,
                    Some(origin_m),
                    positions,
                    radii_m,
                    a_max,
                    upper_m,
                )?;
                let fresh = AffineMotion::from_sums(&self.fit_blocks, origin_m)?;
                self.motions = [self.motions[1], Some(fresh)];
                if count <= positions.len() / NARROW_SHARE {
                    return Some(count);
                }
                fresh
            }
            None => {
                let now_of = |k: usize| Vector3::from(positions.position_m(k));
                let fresh =
                    AffineMotion::fit(positions.len(), anchored, now_of, &mut self.fit_blocks)?;
                self.motions = [self.motions[1], Some(fresh)];
                fresh
            }
        };
        self.select_candidates(&fresh, None, positions, radii_m, a_max, upper_m)
    }

    /// Fills `candidates` with the satellites whose lower bound under `motion` (from the anchors to the
    /// `positions` now) does not exclude them from the minimum (`upper_m`) or from a collision:
    /// returns how many, or `None` when a satellite has no anchor or a residual or `upper_m` is not
    /// finite. With `fit_origin_m`, the
    /// same pass also fills `fit_blocks` with the sums of this snapshot's fit about that origin
    /// ([`AffineMotion::from_sums`]).
    fn select_candidates(
        &mut self,
        motion: &AffineMotion,
        fit_origin_m: Option<Vector3<f64>>,
        positions: &impl TrackedPositions,
        radii_m: &[f64],
        a_max: f64,
        upper_m: f64,
    ) -> Option<usize> {
        let n = positions.len();
        let anchors = &self.anchors;
        let contraction = motion.contraction;
        self.slack_m.resize(n, 0.0);
        self.fit_blocks.clear();
        self.fit_blocks
            .resize(n.div_ceil(SUM_BLOCK), FitSums::default());
        // Residuals from the motion, their maximum and the largest coordinate magnitude, in parallel
        // over the fit's fixed blocks (maxima: the same values in any order; sums: per block).
        let (largest_m, scale_m) = self
            .slack_m
            .par_chunks_mut(SUM_BLOCK)
            .zip(self.fit_blocks.par_iter_mut())
            .enumerate()
            .map(|(b, (slack, sums))| {
                let mut largest_coordinate_m = 0.0_f64;
                let mut largest_moved_m = [0.0_f64; RESIDUAL_LANES];
                let mut all_finite = true;
                let mut held_m = [0.0; RESIDUAL_BATCH];
                for (c, slack) in slack.chunks_mut(RESIDUAL_BATCH).enumerate() {
                    // First the squared residuals (in `slack` until their roots replace them), the
                    // fit's sums and the largest coordinate; then the roots of the batch together
                    // (a vector square root: one scalar root per satellite held this loop up).
                    for (offset, (slack, held_m)) in slack.iter_mut().zip(&mut held_m).enumerate() {
                        let k = b * SUM_BLOCK + c * RESIDUAL_BATCH + offset;
                        let a = anchors.get(positions.id(k)).filter(|a| !a[3].is_nan())?;
                        let [x, y, z] = positions.position_m(k);
                        let (anchor, now) = (Vector3::new(a[0], a[1], a[2]), Vector3::new(x, y, z));
                        *slack = motion.residual_squared_m2(&anchor, &now);
                        *held_m = contraction * a[3];
                        if let Some(origin_m) = fit_origin_m {
                            sums.add(anchor - origin_m, now - anchor);
                        }
                        // The largest magnitude of the six coordinates (as scalars: no vector round
                        // trip through the stack). A finite residual makes every coordinate finite,
                        // and a pass with any other gives no bound, so plain comparisons give the
                        // maxima (no NaN handling).
                        let largest = [a[1], a[2], x, y, z]
                            .into_iter()
                            .fold(a[0].abs(), |m, v| larger(m, v.abs()));
                        largest_coordinate_m = larger(largest_coordinate_m, largest);
                    }
                    for (lanes, held_m) in slack
                        .chunks_mut(RESIDUAL_LANES)
                        .zip(held_m.chunks(RESIDUAL_LANES))
                    {
                        for ((slack, held_m), largest) in
                            lanes.iter_mut().zip(held_m).zip(&mut largest_moved_m)
                        {
                            let moved_m = slack.sqrt();
                            all_finite &= moved_m.is_finite();
                            *slack = held_m - moved_m;
                            *largest = larger(*largest, moved_m);
                        }
                    }
                }
                all_finite.then(|| {
                    let moved_m = largest_moved_m.into_iter().fold(0.0, larger);
                    (moved_m, largest_coordinate_m)
                })
            })
            .try_reduce(|| (0.0, 0.0), |a, b| Some((a.0.max(b.0), a.1.max(b.1))))?;
        if !(upper_m.is_finite() && scale_m.is_finite()) {
            return None;
        }
        let margin_m = 1e-9 * scale_m * (1.0 + motion.norm);
        let slack_m = &self.slack_m;
        self.candidates.clear();
        // Fixed chunks, each filtered by a plain loop that extends the output (rayon's per-item
        // filter folder was compiled to a call per satellite in some builds: a quarter of this
        // stage's time).
        self.candidates.par_extend(
            slack_m[..n]
                .par_chunks(PARALLEL_MIN_LEN)
                .zip(radii_m[..n].par_chunks(PARALLEL_MIN_LEN))
                .enumerate()
                .flat_map_iter(|(chunk, (slack_m, radii_m))| {
                    let first = chunk * PARALLEL_MIN_LEN;
                    (0..slack_m.len())
                        .filter(move |&o| {
                            let lower_m = slack_m[o] - largest_m - margin_m;
                            lower_m <= upper_m || lower_m < radii_m[o] + a_max
                        })
                        .map(move |o| first + o)
                }),
        );
        Some(self.candidates.len())
    }
}

/// The larger of two numbers that are not NaN (a plain comparison: cheaper than [`f64::max`], which
/// must handle NaN).
#[inline]
fn larger(a: f64, b: f64) -> f64 {
    if b > a {
        b
    } else {
        a
    }
}

/// Every pair compared directly (a few candidates): the same distances, pair and count as a search
/// through the grid. At least two positions.
fn direct(x_m: &[f64], y_m: &[f64], z_m: &[f64], radii_m: &[f64]) -> Separation {
    let mut min_distance_m = f64::INFINITY;
    let mut closest_pair = (0, 1);
    let mut collisions = 0;
    for i in 0..x_m.len() {
        for j in i + 1..x_m.len() {
            let (dx, dy, dz) = (x_m[j] - x_m[i], y_m[j] - y_m[i], z_m[j] - z_m[i]);
            let d = (dx * dx + dy * dy + dz * dz).sqrt();
            // Pairs come in lexicographic order, so the first at the minimum is the smallest.
            if d < min_distance_m {
                min_distance_m = d;
                closest_pair = (i, j);
            }
            if d < radii_m[i] + radii_m[j] {
                collisions += 1;
            }
        }
    }
    Separation {
        min_distance_m,
        closest_pair,
        collisions,
    }
}

/// Every satellite at one point: distance 0, the first two ids, and every pair whose radii are not both
/// zero collides.
fn coincident(positions: &impl TrackedPositions, radii_m: &[f64]) -> Separation {
    let n = positions.len();
    let zero = radii_m.iter().filter(|r| **r == 0.0).count();
    Separation {
        min_distance_m: 0.0,
        closest_pair: (positions.id(0), positions.id(1)),
        collisions: n * (n - 1) / 2 - zero * zero.saturating_sub(1) / 2,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::rngs::ChaCha8Rng;
    use rand::{RngExt, SeedableRng};

    /// All pairs in id order: the minimum distance, its lexicographically smallest pair (ids) and the
    /// colliding pairs.
    fn brute_force(ids: &[usize], p: &[[f64; 3]], radii: &[f64]) -> Separation {
        let mut best = (f64::INFINITY, (0, 0));
        let mut collisions = 0;
        for i in 0..p.len() {
            for j in i + 1..p.len() {
                let d = ((p[j][0] - p[i][0]).powi(2)
                    + (p[j][1] - p[i][1]).powi(2)
                    + (p[j][2] - p[i][2]).powi(2))
                .sqrt();
                if d < best.0 {
                    best = (d, (ids[i], ids[j]));
                }
                if d < radii[i] + radii[j] {
                    collisions += 1;
                }
            }
        }
        Separation {
            min_distance_m: best.0,
            closest_pair: best.1,
            collisions,
        }
    }

    /// How a test swarm is laid out and moves.
    #[derive(Clone, Copy, Debug)]
    enum Motion {
        /// Uniform in a box, random constant velocities.
        Random,
        /// Tight clusters of a few satellites, each cluster drifting and its members jittering.
        Clustered,
        /// Pairs on head-on courses that pass through each other (collisions come and go).
        Colliding,
        /// An integer lattice (every ninth satellite 1 m closer to its neighbour) translated by 1/8 m a
        /// step: exact distance ties everywhere.
        Lattice,
        /// A lattice of the given spacing (m) whose satellites jitter by up to 1e-9 m a step: every
        /// satellite ties the minimum to within the bound's rounding margin.
        TiedLattice(f64),
        /// A tenth of the satellites in pairs 1 m apart that separate at 0.4 m a step, the others
        /// still on a 20 m lattice: the pairs' anchors go stale while they stay candidates.
        Separating,
        /// Uniform in a box, the whole swarm turning about z by 0.01 rad a step (satellites at the edge
        /// move 1.4 m a step) and drifting, each satellite also jittering by up to 1 mm: a swarm that
        /// moves together, nearly affinely.
        Turning,
    }

    /// What a tracker did over a test run: its full and narrow searches, how many updates right
    /// after a renumbering were narrow searches, and whether it listed close pairs by the end.
    struct TrackerRun {
        full: u64,
        narrow: u64,
        narrow_after_renumbering: u64,
        lists_pairs: bool,
    }

    /// Runs `steps` snapshots of a moving swarm through one tracker and checks every answer against
    /// the brute force; removes a few satellites (and brings some back) mid-run when `removals`.
    /// Returns (full, narrow) search counts.
    fn check_motion(
        motion: Motion,
        n: usize,
        steps: usize,
        removals: bool,
        seed: u64,
    ) -> (u64, u64) {
        let run = check_motion_renumbered(motion, n, steps, removals, false, seed);
        (run.full, run.narrow)
    }

    /// [`check_motion`], the satellites renumbered by a random permutation every 9th step when
    /// `renumber` (positions, velocities, radii and flags move with them, and the tracker is told).
    fn check_motion_renumbered(
        motion: Motion,
        n: usize,
        steps: usize,
        removals: bool,
        renumber: bool,
        seed: u64,
    ) -> TrackerRun {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut position: Vec<[f64; 3]> = Vec::with_capacity(n);
        let mut velocity: Vec<[f64; 3]> = Vec::with_capacity(n);
        let mut unit = || -> f64 { rng.random_range(-1.0..1.0) };
        for i in 0..n {
            let (p, v) = match motion {
                Motion::Random | Motion::Turning => (
                    [100.0 * unit(), 100.0 * unit(), 100.0 * unit()],
                    [0.3 * unit(), 0.3 * unit(), 0.3 * unit()],
                ),
                Motion::Clustered => {
                    let c = (i / 4) as f64;
                    (
                        [c * 10.0 + unit(), (c * 7.0) % 30.0 + unit(), unit()],
                        [0.05 * unit(), 0.05 * unit(), 0.05 * unit()],
                    )
                }
                Motion::Colliding => {
                    let k = (i / 2) as f64;
                    let side = if i % 2 == 0 { -1.0 } else { 1.0 };
                    (
                        [5.0 * k, side * (2.0 + unit()), 0.2 * unit()],
                        [0.0, -side * 0.05 * (1.0 + 0.5 * unit()), 0.0],
                    )
                }
                Motion::Lattice => (
                    [
                        (i % 7) as f64 * 3.0 + if i % 9 == 0 { 1.0 } else { 0.0 },
                        ((i / 7) % 7) as f64 * 3.0,
                        (i / 49) as f64 * 3.0,
                    ],
                    [0.125, 0.0, 0.0],
                ),
                Motion::Separating if i < n / 10 => {
                    let (p, side) = ((i / 2) as f64, if i % 2 == 0 { -1.0 } else { 1.0 });
                    let centre = [
                        10.0 + (p % 5.0) * 20.0,
                        10.0 + (p / 5.0).floor() % 5.0 * 20.0,
                        10.0 + (p / 25.0).floor() * 20.0,
                    ];
                    (
                        [centre[0] + side * 0.5, centre[1], centre[2]],
                        [side * 0.2, 0.0, 0.0],
                    )
                }
                Motion::Separating => {
                    let q = i - n / 10;
                    (
                        [
                            (q % 7) as f64 * 20.0,
                            ((q / 7) % 7) as f64 * 20.0,
                            (q / 49) as f64 * 20.0,
                        ],
                        [0.0; 3],
                    )
                }
                Motion::TiedLattice(spacing_m) => (
                    [
                        (i % 7) as f64 * spacing_m,
                        ((i / 7) % 7) as f64 * spacing_m,
                        (i / 49) as f64 * spacing_m,
                    ],
                    [0.0; 3],
                ),
            };
            position.push(p);
            velocity.push(v);
        }
        let radii: Vec<f64> = (0..n)
            .map(|i| {
                if i % 5 == 0 {
                    0.0
                } else {
                    0.1 + 0.4 * unit().abs()
                }
            })
            .collect();
        let (mut radii, mut live) = (radii, vec![true; n]);
        let mut tracker = SeparationTracker::new();
        let mut narrow_after_renumbering = 0;
        for step in 0..steps {
            let renumbered = renumber && step % 9 == 4;
            if renumbered {
                let mut moves: Vec<u32> = (0..n as u32).collect();
                for k in (1..n).rev() {
                    moves.swap(k, rng.random_range(0..=k));
                }
                fn gather<T: Copy>(data: &mut [T], moves: &[u32]) {
                    let old = data.to_vec();
                    for (k, &m) in moves.iter().enumerate() {
                        data[k] = old[m as usize];
                    }
                }
                gather(&mut position, &moves);
                gather(&mut velocity, &moves);
                gather(&mut radii, &moves);
                gather(&mut live, &moves);
                tracker.renumber(&moves, |anchors| gather(anchors, &moves));
            }
            let narrow_before = tracker.narrow_searches();
            if removals && step > 0 && step % 7 == 0 {
                let k = rng.random_range(0..n);
                live[k] = !live[k];
                // Also remove the last answer's closest pair now and then.
                if step % 14 == 0 {
                    if let Some((a, _)) = tracker.closest {
                        live[a] = false;
                    }
                }
            }
            let ids: Vec<usize> = (0..n).filter(|&i| live[i]).collect();
            let p: Vec<[f64; 3]> = ids.iter().map(|&i| position[i]).collect();
            let r: Vec<f64> = ids.iter().map(|&i| radii[i]).collect();
            let (x, y, z): (Vec<f64>, Vec<f64>, Vec<f64>) = (
                p.iter().map(|q| q[0]).collect(),
                p.iter().map(|q| q[1]).collect(),
                p.iter().map(|q| q[2]).collect(),
            );
            let got = tracker.update(&ids, &x, &y, &z, &r).unwrap();
            assert!(tracker.searched_since_full <= ids.len());
            let want = brute_force(&ids, &p, &r);
            assert_eq!(got, want, "{motion:?} n = {n} step {step}");
            assert_eq!(got.min_distance_m.to_bits(), want.min_distance_m.to_bits());
            if renumbered && tracker.narrow_searches() > narrow_before {
                narrow_after_renumbering += 1;
            }
            for i in 0..n {
                if let Motion::Turning = motion {
                    let (sin, cos) = 0.01_f64.sin_cos();
                    let [x, y, z] = position[i];
                    position[i] = [
                        cos * x - sin * y + 0.3 + 1e-3 * rng.random_range(-1.0..1.0),
                        sin * x + cos * y + 1e-3 * rng.random_range(-1.0..1.0),
                        z + 1e-3 * rng.random_range(-1.0..1.0),
                    ];
                    continue;
                }
                let jitter = match motion {
                    Motion::Clustered => 0.02,
                    Motion::TiedLattice(_) => 1e-9,
                    _ => 0.0,
                };
                for a in 0..3 {
                    position[i][a] += velocity[i][a] + jitter * rng.random_range(-1.0..1.0);
                }
            }
        }
        TrackerRun {
            full: tracker.full_searches(),
            narrow: tracker.narrow_searches(),
            narrow_after_renumbering,
            lists_pairs: tracker.lists_pairs,
        }
    }

    /// Renumbering the satellites between updates (as the engine's storage re-sort does) keeps every
    /// answer equal to the brute force, and the update right after it stays a narrow search.
    #[test]
    fn tracker_follows_a_renumbering() {
        for motion in [Motion::Random, Motion::Clustered, Motion::Colliding] {
            let TrackerRun {
                full,
                narrow,
                narrow_after_renumbering: after,
                ..
            } = check_motion_renumbered(motion, 300, 60, true, true, 29);
            assert!(
                full >= 1 && narrow >= 10,
                "{motion:?}: {full} full, {narrow} narrow"
            );
            assert!(
                after >= 3,
                "{motion:?}: {after} narrow updates right after a renumbering"
            );
        }
    }

    /// The tracker equals the O(N²) brute force (distance bit for bit, pair, collision count) at every
    /// step of moving swarms, and the narrow search is what answers most steps.
    #[test]
    fn tracker_equals_brute_force_on_moving_swarms() {
        for (motion, n) in [
            (Motion::Random, 300),
            (Motion::Clustered, 200),
            (Motion::Colliding, 120),
            (Motion::Lattice, 150),
        ] {
            for removals in [false, true] {
                let (full, narrow) = check_motion(motion, n, 60, removals, 11 + n as u64);
                assert!(full >= 1, "{motion:?}");
                assert!(
                    narrow >= 10,
                    "{motion:?} removals {removals}: {full} full, {narrow} narrow"
                );
            }
        }
    }

    /// A swarm that turns and drifts as a whole (its edge moving 1.4 m a step, far more than the
    /// nearest-neighbour distances of ~10 m, so the plain displacement bound would need a full search
    /// every few steps) is answered by the fitted motion's bound with one full search in 60 steps, and
    /// every answer equals the brute force.
    #[test]
    fn a_swarm_moving_together_needs_one_full_search() {
        let (full, narrow) = check_motion(Motion::Turning, 2000, 60, false, 3);
        assert_eq!((full, narrow), (1, 59));
    }

    /// A lattice whose satellites all tie at their nearest distance: after one full search that finds
    /// every satellite a candidate, the tracker lists the close pairs and answers the other updates
    /// by narrow searches. Every answer equals the brute force, also with the lattice's neighbours
    /// overlapping (a 0.7 m lattice against radii up to 0.5 m: colliding pairs listed, some of them
    /// also among the candidates, counted once), with satellites removed and brought back, and
    /// renumbered.
    #[test]
    fn a_tied_lattice_is_answered_through_its_close_pairs() {
        for spacing_m in [3.0, 0.7] {
            for removals in [false, true] {
                let (full, narrow) =
                    check_motion(Motion::TiedLattice(spacing_m), 343, 40, removals, 7);
                assert!(
                    full <= 4 && narrow >= 36,
                    "spacing {spacing_m} m, removals {removals}: {full} full, {narrow} narrow"
                );
            }
            let TrackerRun { full, narrow, .. } =
                check_motion_renumbered(Motion::TiedLattice(spacing_m), 343, 40, true, true, 8);
            assert!(full >= 1 && narrow >= 10, "{full} full, {narrow} narrow");
        }
    }

    /// Pairs that start close and drift apart stay candidates under their stale anchors (a tenth of
    /// the swarm, every step); once the narrow searches have searched as many candidates as the swarm
    /// holds, a full search takes fresh anchors, and as that came within a few narrow searches, the
    /// full searches from then on list the close pairs. Every answer equals the brute force.
    #[test]
    fn stale_anchors_are_refreshed() {
        let run = check_motion_renumbered(Motion::Separating, 400, 30, false, false, 13);
        assert!(
            run.full >= 2 && run.narrow >= 20,
            "{} full, {} narrow",
            run.full,
            run.narrow
        );
        assert!(run.lists_pairs);
    }

    /// Many candidates (more than the direct-comparison limit) go through the candidates' own grid.
    #[test]
    fn tracker_equals_brute_force_with_many_candidates() {
        let (full, narrow) = check_motion(Motion::Colliding, 1000, 25, true, 5);
        assert!(full >= 1 && narrow >= 5, "{full} full, {narrow} narrow");
    }

    /// The tracker's full search is the reference [`min_separation`] (ids mapped), and coincident or
    /// non-finite swarms, unordered ids and too few satellites are handled without panicking.
    #[test]
    fn tracker_edge_cases() {
        let mut tracker = SeparationTracker::new();
        let ids = [2, 5, 9];
        let sep = tracker
            .update(&ids, &[0.0; 3], &[1.0; 3], &[2.0; 3], &[0.0, 0.0, 0.5])
            .unwrap();
        assert_eq!(sep.min_distance_m, 0.0);
        assert_eq!(sep.closest_pair, (2, 5));
        assert_eq!(sep.collisions, 2);
        assert!(matches!(
            tracker.update(&[3, 1], &[0.0, 1.0], &[0.0; 2], &[0.0; 2], &[0.0; 2]),
            Err(MetricsError::UnorderedIds { index: 1 })
        ));
        assert!(matches!(
            tracker.update(&[1], &[0.0], &[0.0], &[0.0], &[0.0]),
            Err(MetricsError::TooFewSatellites { n: 1 })
        ));
        // An id the per-id anchors cannot hold is refused, not allocated for.
        assert!(matches!(
            tracker.update(&[0, 1 << 33], &[0.0, 1.0], &[0.0; 2], &[0.0; 2], &[0.0; 2]),
            Err(MetricsError::IdTooLarge { id, limit: MAX_POINTS }) if id == 1 << 33
        ));
        assert!(tracker
            .update(&[0, 1], &[0.0, f64::NAN], &[0.0; 2], &[0.0; 2], &[0.0; 2])
            .is_err());
        let (x, y, z) = ([0.0, 3.0, 7.0], [0.0, 0.0, 1.0], [0.0; 3]);
        let mut grid = NeighbourGrid::new();
        grid.build(&x, &y, &z, 2.0).unwrap();
        let reference = min_separation(&grid, &[1.0, 2.5, 0.0]).unwrap();
        let tracked = tracker
            .update(&[4, 6, 8], &x, &y, &z, &[1.0, 2.5, 0.0])
            .unwrap();
        assert_eq!(tracked.min_distance_m, reference.min_distance_m);
        assert_eq!(tracked.collisions, reference.collisions);
        assert_eq!(tracked.closest_pair, (4, 6));
        assert_eq!(reference.closest_pair, (0, 1));
    }
}
