//! The grid's neighbour list (a Verlet list): for every satellite, the others that were within the
//! list's reach plus a skin when the list was made, kept across builds of the grid until some satellite
//! has moved half the skin since. While it holds, every satellite within the reach now is among its
//! candidates (two satellites closer than the reach now were closer than reach + skin then), so a query
//! within the reach tests those few candidates instead of walking rows of cells. It finds exactly the
//! satellites the walk finds, and visits them in the walk's order (ascending storage slot of the
//! current build), with the same differences and distances: the same answers, bit for bit.
//!
//! Its reach is learned: the grid notes the largest reach queried between two builds, and the next
//! build makes the list for that reach when the one it has does not serve it. Only a grid that keeps a
//! list notes reaches ([`super::NeighbourGrid::keep_neighbour_list`]: the engine's sensing grid).

use std::mem::MaybeUninit;
use std::sync::atomic::{AtomicU64, Ordering};

use rayon::prelude::*;

use super::{Neighbour, NeighbourGrid, PARALLEL_MIN_LEN};

/// The skin as a fraction of the list's reach: a list of reach `r` holds the satellites within
/// `r · (1 + SKIN_FRACTION)` and lasts until a satellite has moved `r · SKIN_FRACTION / 2`.
const SKIN_FRACTION: f64 = 0.25;

/// Relative allowance for the rounding of the computed distances and displacements (each within a
/// few ulps, about 1e-15 relative): the list is dropped a little before half the skin is used.
const ROUNDING_ALLOWANCE: f64 = 1e-9;

/// Most candidates a list query tests on the stack; a satellite with more is answered by the walk.
const MAX_CANDIDATES: usize = 128;

/// A list whose reach is below this fraction of the reach queried is made again for the new reach.
const SHRINK_BELOW: f64 = 0.5;

/// The largest reach, as a fraction of the grid's radius, that a list is made for. Near the radius
/// the walk's batched rows are cheap for what they find (about as many candidates as a list of that
/// reach holds, read in order), and a list costs memory (some 19 candidates per satellite at ten
/// neighbours) and its making: the bifurcating bench at 10^5 (reach = radius) ran 1.5x slower with
/// one. Well below the radius the walk's cost is its rows, which the list avoids.
const MAX_REACH_OF_RADIUS: f64 = 0.5;

/// The largest reach queried since it was last taken (m; 0: none), shared by the querying threads.
#[derive(Debug, Default)]
pub(super) struct ReachSeen(AtomicU64);

impl Clone for ReachSeen {
    fn clone(&self) -> Self {
        Self(AtomicU64::new(self.0.load(Ordering::Relaxed)))
    }
}

impl ReachSeen {
    /// Notes a query of reach `reach_m` (finite, non-negative: its bits order as the values).
    #[inline(always)]
    pub(super) fn note(&self, reach_m: f64) {
        let bits = reach_m.to_bits();
        if reach_m.is_finite() && bits > self.0.load(Ordering::Relaxed) {
            self.0.fetch_max(bits, Ordering::Relaxed);
        }
    }

    /// The largest reach noted since the last call (m; 0 when none), forgetting it.
    fn take(&self) -> f64 {
        f64::from_bits(self.0.swap(0, Ordering::Relaxed))
    }
}

/// The candidates of every satellite (by index in the grid's build), and the positions they were
/// found from.
#[derive(Clone, Debug, Default)]
pub(super) struct NeighbourList {
    /// The reach the list answers (m); 0: no list.
    reach_m: f64,
    /// The candidates of satellite `i` are `candidates[start[i]..start[i + 1]]` (length `n + 1`).
    start: Vec<u32>,
    /// Satellite indices (in no particular order: a query sorts what it finds by slot).
    candidates: Vec<u32>,
    /// Every satellite's position when the list was made (m, the grid's frame), by index.
    made_at_m: Vec<[f64; 3]>,
    /// How many times the list was made.
    made: u64,
}

impl NeighbourList {
    /// Whether the list answers a query of reach `reach_m` (m).
    #[inline(always)]
    pub(super) fn serves(&self, reach_m: f64) -> bool {
        reach_m <= self.reach_m && self.reach_m > 0.0
    }

    /// How many times the list was made since the grid was created.
    pub(super) fn made(&self) -> u64 {
        self.made
    }

    /// Where every satellite was when the list was made (m, by index), if there is a list of `n`
    /// satellites: the grid's build measures how far they have moved in its first pass.
    pub(super) fn made_at_of(&self, n: usize) -> Option<&[[f64; 3]]> {
        (self.reach_m > 0.0 && self.made_at_m.len() == n).then_some(&self.made_at_m[..])
    }

    /// Brings the list up to date with the grid's new build over `position_m` (the build's positions
    /// by index), in which the largest squared distance of a satellite from where the list was made is
    /// `largest_move_m2` (m², over [`Self::made_at_of`]; `None` without a list of these satellites):
    /// kept while every
    /// satellite is within half the skin of where the list was made and the reach queried since the
    /// last build (`seen`) is one it serves well, made again for that reach otherwise (or dropped,
    /// when nothing was queried and it no longer holds).
    pub(super) fn refresh(
        &mut self,
        grid: &NeighbourGrid,
        position_m: &(impl Fn(usize) -> [f64; 3] + Sync),
        seen: &ReachSeen,
        largest_move_m2: Option<f64>,
    ) {
        let queried_m = seen.take();
        let n = grid.len();
        let reach_fits = queried_m == 0.0
            || (queried_m <= self.reach_m && queried_m >= SHRINK_BELOW * self.reach_m);
        if reach_fits && largest_move_m2.is_some_and(|moved_m2| self.holds(moved_m2)) {
            return;
        }
        self.reach_m = 0.0;
        if queried_m > 0.0 && queried_m <= MAX_REACH_OF_RADIUS * grid.radius_m() && n > 1 {
            self.make(grid, position_m, queried_m);
        }
    }

    /// Whether no satellite has moved half the skin (less the rounding allowance) since the list was
    /// made, the largest squared move being `largest_move_m2` (m²).
    fn holds(&self, largest_move_m2: f64) -> bool {
        let skin_m = self.reach_m * SKIN_FRACTION;
        let limit_m = 0.5 * (skin_m - ROUNDING_ALLOWANCE * (self.reach_m + skin_m));
        largest_move_m2 <= limit_m * limit_m
    }

    /// Makes the list for reach `reach_m` from the grid's walk at `reach · (1 + skin)`.
    fn make(
        &mut self,
        grid: &NeighbourGrid,
        position_m: &(impl Fn(usize) -> [f64; 3] + Sync),
        reach_m: f64,
    ) {
        let n = grid.len();
        let outer_m = reach_m * (1.0 + SKIN_FRACTION);
        // Each chunk of satellites walks the grid into a list of its own; the chunks are then
        // joined in order (the same list on any thread count).
        let chunks: Vec<(Vec<u32>, Vec<u32>)> = (0..n.div_ceil(PARALLEL_MIN_LEN))
            .into_par_iter()
            .map(|chunk| {
                let (mut counts, mut found) = (Vec::new(), Vec::new());
                for i in chunk * PARALLEL_MIN_LEN..((chunk + 1) * PARALLEL_MIN_LEN).min(n) {
                    let before = found.len();
                    grid.walk(grid.slot(i), outer_m, |nb| found.push(nb.index as u32));
                    counts.push((found.len() - before) as u32);
                }
                (counts, found)
            })
            .collect();
        self.start.clear();
        self.start.push(0);
        self.candidates.clear();
        let mut total = 0u32;
        for (counts, found) in &chunks {
            for &count in counts {
                total += count;
                self.start.push(total);
            }
            self.candidates.extend_from_slice(found);
        }
        self.made_at_m.clear();
        self.made_at_m.par_extend(
            (0..n)
                .into_par_iter()
                .with_min_len(PARALLEL_MIN_LEN)
                .map(position_m),
        );
        self.reach_m = reach_m;
        self.made += 1;
    }

    /// Renumbers the list after its satellites were moved: index `k` now holds the satellite index
    /// `moves[k]` held (a permutation of the indices; a list of another length is dropped).
    pub(super) fn renumber(&mut self, moves: &[u32]) {
        let n = self.made_at_m.len();
        if self.reach_m == 0.0 || moves.len() != n {
            self.reach_m = 0.0;
            return;
        }
        let mut new_of_old = vec![0u32; n];
        for (k, &old) in moves.iter().enumerate() {
            new_of_old[old as usize] = k as u32;
        }
        let mut start = Vec::with_capacity(n + 1);
        let mut candidates = Vec::with_capacity(self.candidates.len());
        start.push(0);
        for &old in moves {
            let old = old as usize;
            let theirs = &self.candidates[self.start[old] as usize..self.start[old + 1] as usize];
            candidates.extend(theirs.iter().map(|&j| new_of_old[j as usize]));
            start.push(candidates.len() as u32);
        }
        self.made_at_m = moves
            .iter()
            .map(|&old| self.made_at_m[old as usize])
            .collect();
        self.start = start;
        self.candidates = candidates;
    }

    /// The query of [`NeighbourGrid::for_each_within_slot`] for the satellite in slot `si` and a reach
    /// the list serves (neither negative nor NaN): the candidates within `reach_m`, not hidden, visited
    /// in ascending slot. Returns `false`, visiting nothing, when the satellite has more candidates
    /// than a query holds: the caller walks the grid instead.
    #[inline(always)]
    pub(super) fn visit(
        &self,
        grid: &NeighbourGrid,
        si: usize,
        reach_m: f64,
        mut visit: impl FnMut(Neighbour),
    ) -> bool {
        let i = grid.items[si] as usize;
        let candidates = &self.candidates[self.start[i] as usize..self.start[i + 1] as usize];
        if candidates.len() > MAX_CANDIDATES {
            return false;
        }
        let p = [grid.xs[si], grid.ys[si], grid.zs[si]];
        let distance_to = |s: usize| {
            let (dx, dy, dz) = (grid.xs[s] - p[0], grid.ys[s] - p[1], grid.zs[s] - p[2]);
            (dx, dy, dz, (dx * dx + dy * dy + dz * dz).sqrt())
        };
        // The slots within the reach, kept ascending by insertion (a handful per satellite).
        let mut within = [const { MaybeUninit::<u32>::uninit() }; MAX_CANDIDATES];
        let mut count = 0;
        for &j in candidates {
            let s = grid.slot_of[j as usize];
            let (.., d) = distance_to(s as usize);
            if d <= reach_m && !grid.hidden_slot(s as usize) {
                let mut k = count;
                // SAFETY (reads below): entries before `count` are written.
                #[allow(unsafe_code)]
                while k > 0 && unsafe { within[k - 1].assume_init() } > s {
                    within[k] = within[k - 1];
                    k -= 1;
                }
                within[k] = MaybeUninit::new(s);
                count += 1;
            }
        }
        for entry in &within[..count] {
            // SAFETY: the first `count` entries are written.
            #[allow(unsafe_code)]
            let s = unsafe { entry.assume_init() } as usize;
            let (dx_m, dy_m, dz_m, distance_m) = distance_to(s);
            visit(Neighbour {
                index: grid.items[s] as usize,
                dx_m,
                dy_m,
                dz_m,
                distance_m,
            });
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::super::prefilter::tests::uniform_draws;
    use super::*;

    /// Every neighbour of satellite `i` within `reach_m`, as bits, in visit order.
    fn answers(grid: &NeighbourGrid, i: usize, reach_m: f64) -> Vec<[u64; 5]> {
        let mut found = Vec::new();
        grid.for_each_within(i, reach_m, |nb| {
            found.push([
                nb.index as u64,
                nb.dx_m.to_bits(),
                nb.dy_m.to_bits(),
                nb.dz_m.to_bits(),
                nb.distance_m.to_bits(),
            ])
        });
        found
    }

    /// A grid keeping a list answers every query bit for bit as one without, build after build, while
    /// satellites drift (a few of them beyond half the skin), are hidden, and are renumbered as the
    /// engine's re-sort renumbers them; the list is made once and then lasts until one of them jumps.
    #[test]
    fn a_kept_list_answers_as_the_walk_build_after_build() {
        let mut uniform = uniform_draws(0x5851_f42d_4c95_7f2d);
        let (n, radius_m, side_m) = (2000, 200.0, 1500.0);
        let mut positions: Vec<[f64; 3]> = (0..n)
            .map(|_| [0.0; 3].map(|_: f64| uniform() * side_m))
            .collect();
        let mut ranks: Vec<u32> = (0..n as u32).collect();
        let (mut kept, mut plain) = (NeighbourGrid::new(), NeighbourGrid::new());
        kept.keep_neighbour_list(true);
        let (mut compared, mut made_before_jumps) = (0, 0);
        for build in 0..30 {
            // Drift of at most 0.2 m per axis per build; at builds 12 and 24 one satellite jumps
            // 9 m, beyond half the skin of a 60 m list (7.5 m).
            for p in &mut positions {
                for v in p.iter_mut() {
                    *v += (uniform() - 0.5) * 0.4;
                }
            }
            if build % 12 == 0 && build > 0 {
                positions[build][0] += 9.0;
            }
            let axis = |a: usize| positions.iter().map(|p| p[a]).collect::<Vec<f64>>();
            let (x, y, z) = (axis(0), axis(1), axis(2));
            kept.build_ranked(&x, &y, &z, radius_m, Some(&ranks))
                .unwrap();
            plain
                .build_ranked(&x, &y, &z, radius_m, Some(&ranks))
                .unwrap();
            if build == 11 {
                made_before_jumps = kept.neighbour_lists_made();
            }
            if build % 5 == 3 {
                let hidden = |i: usize| i % 17 != 3;
                kept.mask(hidden);
                plain.mask(hidden);
            }
            // Queries within the list's reach (60 m), below half of it (a second list), and
            // beyond the largest fraction of the radius a list is made for (the walk).
            let reach_m = match build {
                0..=19 => 60.0,
                20..=24 => 25.0,
                _ => 150.0,
            };
            for i in 0..n {
                for reach in [reach_m, 0.7 * reach_m, 0.0] {
                    let want = answers(&plain, i, reach);
                    compared += want.len();
                    assert_eq!(
                        answers(&kept, i, reach),
                        want,
                        "build {build}, satellite {i}"
                    );
                }
            }
            if build % 7 == 6 {
                // The engine's re-sort: index k now holds what index moves[k] held.
                let mut moves: Vec<u32> = (0..n as u32).collect();
                for k in (1..n).rev() {
                    moves.swap(k, (uniform() * (k + 1) as f64) as usize % (k + 1));
                }
                positions = moves.iter().map(|&old| positions[old as usize]).collect();
                ranks = moves.iter().map(|&old| ranks[old as usize]).collect();
                kept.renumber_neighbour_list(&moves);
            }
        }
        assert!(compared > 50_000, "too few neighbours compared: {compared}");
        // Made after the first build's queries, kept through drift, renumbering and masks until the
        // jump at build 12; made again for the jumps and the smaller reach, not for the walk's.
        assert_eq!(made_before_jumps, 1);
        let made = kept.neighbour_lists_made();
        assert!((3..=5).contains(&made), "lists made: {made}");
        assert!(!kept.list.serves(150.0));
    }
}
