//! Which satellite pairs a segment must look at: a Verlet list through the neighbour grid.
//!
//! At a *build* (time t_a) every live satellite's position is kept as its anchor a_i and the list holds
//! every pair closer than `threshold + skin` then, found through a [`NeighbourGrid`] of that radius. On a
//! later segment, with `M_i` a bound on how far satellite `i`'s path over the segment strays from its
//! anchor (its end's distance from the anchor plus [`HermiteSegment::sweep_bound_m`]), a pair's distance
//! anywhere on the segment is at least `|a_j − a_i| − M_i − M_j`: a pair left out of the list
//! (`|a_j − a_i| > threshold + skin`) cannot come below the threshold while `2 max M ≤ skin`. When that
//! fails, the list is built again at the segment's end with a skin of `max(threshold, 8 D)` (`D` the
//! largest sweep of the segment; the build covers the segment itself since `2 D ≤ skin`). A build costs
//! one grid over the live satellites; between builds a segment costs one pass over them and the pairs
//! of the list. The list is by storage index: a re-sort of the storage asks for a new build
//! ([`PairScreen::invalidate`]).

use rayon::prelude::*;

use crate::environment::HermiteSegment;
use crate::grid::{NeighbourError, NeighbourGrid};
use crate::orbit::RelativeStateHill;

/// Smallest number of satellites per parallel work item (the answers never depend on it).
const PARALLEL_MIN_LEN: usize = 4096;

/// The skin of a build, in units of the largest sweep of the segment it is built on.
const SKIN_SWEEPS: f64 = 8.0;

/// The Verlet list of candidate pairs (see the module docs). Buffers are kept across builds.
#[derive(Clone, Debug, Default)]
pub(crate) struct PairScreen {
    /// Whether the list and the anchors hold (false before the first build and after a re-sort).
    valid: bool,
    /// The skin of the last build \[m\].
    skin_m: f64,
    /// Each satellite's position at the last build, Hill frame \[m\], by storage index.
    anchors: Vec<[f64; 3]>,
    /// Storage indices of the pairs within `threshold + skin` at the last build.
    pairs: Vec<(u32, u32)>,
    grid: NeighbourGrid,
    builds: u64,
}

/// A segment as the screen sees it: the satellites' truth at both ends by storage index, which are
/// live (ascending storage indices) and their end positions.
pub(crate) struct Ends<'a> {
    /// Start of the segment \[s\].
    pub t0_s: f64,
    /// End of the segment \[s\], later than `t0_s`.
    pub t1_s: f64,
    /// Truth at `t0_s`, Hill frame, by storage index.
    pub start: &'a [RelativeStateHill],
    /// Truth at `t1_s`, Hill frame, by storage index.
    pub end: &'a [RelativeStateHill],
    /// Storage indices of the live satellites, ascending.
    pub live: &'a [usize],
}

impl Ends<'_> {
    /// Satellite `i`'s path over the segment (finite states: the divergence check runs first).
    pub fn segment(&self, i: usize) -> HermiteSegment {
        let (a, b) = (&self.start[i], &self.end[i]);
        HermiteSegment {
            t0_s: self.t0_s,
            t1_s: self.t1_s,
            p0_hill_m: a.position_m,
            v0_hill_mps: a.velocity_mps,
            p1_hill_m: b.position_m,
            v1_hill_mps: b.velocity_mps,
        }
    }
}

impl PairScreen {
    /// Forgets the list: the next segment builds it again (the storage order changed).
    pub fn invalidate(&mut self) {
        self.valid = false;
    }

    /// Builds of the list so far.
    pub fn builds(&self) -> u64 {
        self.builds
    }

    /// The candidate pairs of the segment `ends` (storage indices; some may have been removed since
    /// the build: the caller skips them), building the list again when the bound requires it.
    ///
    /// # Errors
    /// The grid's, for a non-finite position (the divergence check reports it first).
    pub fn pairs(
        &mut self,
        ends: &Ends<'_>,
        threshold_m: f64,
    ) -> Result<&[(u32, u32)], NeighbourError> {
        let anchors = &self.anchors;
        let valid = self.valid;
        let (sweep_m, strayed_m) = ends
            .live
            .par_iter()
            .with_min_len(PARALLEL_MIN_LEN)
            .map(|&i| {
                let sweep_m = ends.segment(i).sweep_bound_m();
                let strayed_m = if valid {
                    let p = ends.end[i].position_m;
                    let a = anchors[i];
                    let (dx, dy, dz) = (p.x - a[0], p.y - a[1], p.z - a[2]);
                    (dx * dx + dy * dy + dz * dz).sqrt() + sweep_m
                } else {
                    f64::INFINITY
                };
                (sweep_m, strayed_m)
            })
            .reduce(|| (0.0, 0.0), |a, b| (a.0.max(b.0), a.1.max(b.1)));
        if !(valid && 2.0 * strayed_m <= self.skin_m) {
            self.build(ends, threshold_m, sweep_m)?;
        }
        Ok(&self.pairs)
    }

    /// Builds the list at the segment's end with the skin `max(threshold, 8 × sweep)`.
    fn build(
        &mut self,
        ends: &Ends<'_>,
        threshold_m: f64,
        sweep_m: f64,
    ) -> Result<(), NeighbourError> {
        self.valid = false;
        self.builds += 1;
        self.skin_m = threshold_m.max(SKIN_SWEEPS * sweep_m);
        let n = ends.end.len();
        self.anchors.resize(n, [0.0; 3]);
        for (anchor, state) in self.anchors.iter_mut().zip(ends.end) {
            *anchor = state.position_m.into();
        }
        let position = |axis: usize| -> Vec<f64> {
            ends.live
                .iter()
                .map(|&i| ends.end[i].position_m[axis])
                .collect()
        };
        let (x, y, z) = (position(0), position(1), position(2));
        self.grid.build(&x, &y, &z, threshold_m + self.skin_m)?;
        let grid = &self.grid;
        let live = ends.live;
        let chunks: Vec<Vec<(u32, u32)>> = (0..live.len())
            .into_par_iter()
            .with_min_len(PARALLEL_MIN_LEN)
            .fold(Vec::new, |mut pairs, k| {
                grid.for_each_neighbour(k, |nb| {
                    if nb.index > k {
                        pairs.push((live[k] as u32, live[nb.index] as u32));
                    }
                });
                pairs
            })
            .collect();
        self.pairs.clear();
        for chunk in chunks {
            self.pairs.extend(chunk);
        }
        self.valid = true;
        Ok(())
    }
}
