//! Cell-list neighbour grid: fixed-radius neighbour queries and exact nearest-neighbour queries over a
//! swarm's positions, rebuilt every step in O(N).
//!
//! Design (measurements in `ENGINEERING-NOTES.md` §1.4):
//!
//! * Space is cut into cubic cells whose edge is the query radius (plus a relative margin of 1e-6 that
//!   absorbs floating-point rounding in the cell assignment), so every neighbour within the radius lies in
//!   the 3 × 3 × 3 block of cells around a satellite.
//! * Satellites are counting-sorted by cell into one `items` array, and their coordinates are copied in
//!   that order, so a query walks contiguous memory. All buffers are kept across rebuilds: once the grid
//!   has seen its largest swarm, [`NeighbourGrid::build`] does not allocate, and queries never allocate.
//! * **Dense layout** (a `cell_start` array over the whole bounding box) when the box holds at most
//!   `8 N + 64` cells; otherwise a **sparse layout** (the occupied cells' keys, sorted, found by binary
//!   search), so a thinly spread swarm costs O(N) memory instead of a huge grid. At most 2^20 cells per
//!   axis are used; for an even thinner spread the cell edge grows beyond the radius, which keeps the
//!   answers exact and only costs speed.
//!
//! * A fixed-radius query prefilters each row of cells in branch-free batches: the squared distances of
//!   up to 64 candidates, the slots that pass appended without a branch (most candidates fail,
//!   unpredictably; module `prefilter`: a portable loop, and AVX-512 and AVX2 copies chosen at run
//!   time that pass the same candidates). The copy is chosen once per query, and the whole query (row
//!   loop, batches, exact test and the caller's visit) is compiled once per copy, inlined into one
//!   function, so a row costs no call. The passing slots of all rows are buffered, then the exact test and the
//!   visits run in one loop in slot order. A query keeps only the cells that the box
//!   `[p − reach, p + reach]` meets (often the satellite's own cell alone for a reach well below the
//!   cell edge). The answers and their order are those of a plain slot-by-slot
//!   walk of the whole block (tested).
//! * A grid may keep a **neighbour list** across its builds (module `neighbour_list`, a Verlet list:
//!   each satellite's candidates within a reach plus a skin, made again once a satellite has moved half
//!   the skin). Queries within the list's reach test only those candidates and give the walk's answers
//!   in the walk's order; the engine's sensing grid keeps one for its law's queries.
//! * [`NeighbourGrid::mask`] hides satellites from every query until the next build (the engine hides
//!   removed and unlinked ones), so a caller need not look up per-neighbour flags by index.
//!
//! Positions are in any Cartesian frame, in metres; the grid never mixes frames (it only takes
//! differences). Queries take `&self`, and [`NeighbourGrid`] is `Sync`, so many rayon threads can query one
//! grid at once.
//!
//! **Inclusion rule**, identical in every query: satellite `j` is within distance `r` of satellite `i`
//! when `sqrt(dx² + dy² + dz²) <= r` with `dx = x\[j\] - x\[i\]` (and likewise `dy`, `dz`) evaluated in f64, so a
//! brute-force loop written that way returns exactly the same sets.
//!
//! **Visit order** (deterministic: it depends only on the positions and radius given to the last build,
//! never on thread count or on earlier builds): rows of cells in ascending (z, y) cell order, within a row
//! the cells in ascending x, within a cell the satellites in ascending index (or ascending rank, for
//! [`NeighbourGrid::build_ranked`]). If a query's block of cells
//! would be larger than the swarm (a reach far beyond the cell size), the query scans all satellites in
//! storage order instead (storage order is the cell order above).

mod neighbour_list;
mod prefilter;
mod ring;

pub use ring::RingOrder;

use std::mem::MaybeUninit;
use std::ops::Range;

use neighbour_list::{NeighbourList, ReachSeen};
#[cfg(target_arch = "x86_64")]
use prefilter::{Avx2Batches, Avx512Batches};
use prefilter::{Batches, Candidates, PortableBatches, Prefilter};

use rayon::prelude::*;
use thiserror::Error;

/// Relative margin added to the cell edge: `cell = radius * (1 + CELL_MARGIN)`.
///
/// The computed cell coordinate `(x - x_min) / cell` carries a rounding error of at most about
/// `3 ε · cells_per_axis ≈ 1.4e-9` cells (ε = 2.2e-16, at most 2^21 cells per axis), so two points closer
/// than the radius can never land two cells apart once the cell is 1e-6 larger than the radius.
const CELL_MARGIN: f64 = 1e-6;

/// Distance (as a fraction of the cell edge) guaranteed per ring of cells: a satellite `k + 1` or more
/// cells away (Chebyshev distance in cell coordinates) is at least `k · cell · GAP_FACTOR` away. The
/// 1e-8 slack covers the ≤ 3e-9-cell rounding error of two cell coordinates (see [`CELL_MARGIN`]).
const GAP_FACTOR: f64 = 1.0 - 1e-8;

/// Margin (in cells) by which a query widens the box `[p − reach, p + reach]` before it keeps only the
/// cells that box meets along each axis: far above the ≤ 3e-9-cell rounding of two cell coordinates
/// (see [`CELL_MARGIN`]) and of the squared-distance test, so no cell holding a satellite within the
/// reach is ever dropped.
const BOX_MARGIN_CELLS: f64 = 1e-6;

/// Smallest number of satellites per parallel work item of a build (the answers never depend on it).
const PARALLEL_MIN_LEN: usize = 8192;

/// Candidates whose squared distances a fixed-radius query computes in one branch-free batch.
const SCAN_BATCH: usize = 64;

// The AVX-512 prefilter stores eight slots at a time at the running count: its bound needs this.
const _: () = assert!(SCAN_BATCH.is_multiple_of(8) && SCAN_BATCH >= 8);

/// Candidate slots a query buffers (after the squared-distance prefilter) before it visits them.
const PASSED_CAPACITY: usize = 4 * SCAN_BATCH;

/// At most this many cells per axis; thinner spreads get cells larger than the radius.
const MAX_CELLS_PER_AXIS: f64 = 1_048_576.0;

/// Smallest cell edge (m): four times the smallest normal f64. A subnormal radius (below 2.2e-308 m) would
/// give a cell whose inverse is infinite, and the cell count per axis would wrap to 0; the edge is clamped
/// up to this instead, which (like any cell larger than the radius) keeps the answers exact.
const MIN_CELL_M: f64 = 4.0 * f64::MIN_POSITIVE;

/// The dense layout is used when the bounding box holds at most `DENSE_CELLS_PER_POINT · N + DENSE_EXTRA_CELLS` cells.
const DENSE_CELLS_PER_POINT: u64 = 8;
/// See [`DENSE_CELLS_PER_POINT`].
const DENSE_EXTRA_CELLS: u64 = 64;

/// Largest swarm a grid accepts (indices are stored as `u32`, dense cell counts stay below 2^32).
pub const MAX_POINTS: usize = 1 << 28;

/// Why a grid could not be built.
#[derive(Clone, Debug, PartialEq, Error)]
#[non_exhaustive]
pub enum NeighbourError {
    /// The query radius is zero, negative, infinite or NaN.
    #[error("neighbour radius must be finite and > 0 m, got {radius_m} m")]
    InvalidRadius {
        /// The rejected radius (m).
        radius_m: f64,
    },
    /// The x, y and z slices have different lengths.
    #[error("position slices differ in length: x has {x}, y has {y}, z has {z} entries")]
    LengthMismatch {
        /// Length of the x slice.
        x: usize,
        /// Length of the y slice.
        y: usize,
        /// Length of the z slice.
        z: usize,
    },
    /// A ranked build got a different number of ranks than positions.
    #[error("{ranks} ranks for {points} positions")]
    RankLength {
        /// Number of positions.
        points: usize,
        /// Number of ranks.
        ranks: usize,
    },
    /// A coordinate is NaN or infinite. The grid refuses the whole swarm rather than silently dropping a
    /// satellite; filter lost satellites out before building.
    #[error("position of satellite {index} is not finite: ({x_m}, {y_m}, {z_m}) m")]
    NonFinitePosition {
        /// Index of the offending satellite.
        index: usize,
        /// Its x coordinate (m).
        x_m: f64,
        /// Its y coordinate (m).
        y_m: f64,
        /// Its z coordinate (m).
        z_m: f64,
    },
    /// More satellites than [`MAX_POINTS`].
    #[error("{n} satellites exceed the neighbour grid's limit of {max}")]
    TooManyPoints {
        /// Number of satellites given.
        n: usize,
        /// The limit, [`MAX_POINTS`].
        max: usize,
    },
}

/// One neighbour `j` of a query satellite `i`, with the separation vector `p_j - p_i` in the frame of the
/// positions given to [`NeighbourGrid::build`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Neighbour {
    /// Index `j` of the neighbour in the slices given to [`NeighbourGrid::build`].
    pub index: usize,
    /// `x\[j\] - x\[i\]` (m).
    pub dx_m: f64,
    /// `y\[j\] - y\[i\]` (m).
    pub dy_m: f64,
    /// `z\[j\] - z\[i\]` (m).
    pub dz_m: f64,
    /// `sqrt(dx² + dy² + dz²)` (m).
    pub distance_m: f64,
}

/// How the grid stores its cells (chosen by each build, see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum GridLayout {
    /// A `cell_start` entry for every cell of the bounding box.
    #[default]
    Dense,
    /// Only occupied cells, as sorted keys found by binary search.
    Sparse,
}

/// Cell-list index over a swarm's positions. See the module docs for layout, inclusion rule and visit
/// order.
#[derive(Clone, Debug, Default)]
pub struct NeighbourGrid {
    /// Query radius of [`Self::for_each_neighbour`] (m).
    radius_m: f64,
    /// Cell edge (m), `>= radius_m * (1 + CELL_MARGIN)`.
    cell_m: f64,
    /// `1 / cell_m` (1/m).
    inv_cell: f64,
    /// Lower corner of the bounding box (m).
    origin_m: [f64; 3],
    /// Cells per axis (each >= 1).
    dims: [u64; 3],
    layout: GridLayout,
    /// Number of non-empty cells.
    occupied: usize,
    /// Coordinates in storage (cell) order (m).
    xs: Vec<f64>,
    ys: Vec<f64>,
    zs: Vec<f64>,
    /// Original satellite index of each storage slot.
    items: Vec<u32>,
    /// Storage slot of each satellite.
    slot_of: Vec<u32>,
    /// Dense: start slot of every cell (length cells + 1). Sparse: start slot of every occupied cell
    /// (length occupied + 1).
    cell_start: Vec<u32>,
    /// Sparse only: key of every occupied cell, ascending.
    cell_keys: Vec<u64>,
    /// Build scratch (dense): cell of every satellite.
    scratch_cell: Vec<u32>,
    /// Build scratch (sparse): (cell key, satellite) pairs.
    scratch_pairs: Vec<(u64, u32)>,
    /// Whether [`NeighbourGrid::mask`] was applied since the last build.
    masked: bool,
    /// Per storage slot: hidden by the mask. Empty when nothing is hidden.
    hidden: Vec<bool>,
    /// The copy of the squared-distance prefilter queries run (the fastest this CPU has).
    prefilter: Prefilter,
    /// Whether the grid keeps a neighbour list ([`Self::keep_neighbour_list`]).
    keeps_list: bool,
    /// The neighbour list, kept across builds (module `neighbour_list`).
    list: NeighbourList,
    /// The largest reach queried since the last build (noted only when a list is kept).
    reach_seen: ReachSeen,
}

impl NeighbourGrid {
    /// An empty grid (no satellites, radius 0). Call [`Self::build`] before querying.
    pub fn new() -> Self {
        Self::default()
    }

    /// Rebuilds the grid over the positions `(x_m\[i\], y_m\[i\], z_m\[i\])` (m, any Cartesian frame) with
    /// query radius `radius_m` (m). Reuses all buffers: no allocation once the grid has seen a swarm this
    /// large and this spread out.
    ///
    /// N = 0 and N = 1 are valid (every query then finds nothing), as are coincident satellites.
    ///
    /// # Errors
    /// [`NeighbourError::InvalidRadius`] unless `radius_m` is finite and positive;
    /// [`NeighbourError::LengthMismatch`], [`NeighbourError::TooManyPoints`];
    /// [`NeighbourError::NonFinitePosition`] for the first satellite with a NaN or infinite coordinate.
    /// After an error the grid is empty.
    pub fn build(
        &mut self,
        x_m: &[f64],
        y_m: &[f64],
        z_m: &[f64],
        radius_m: f64,
    ) -> Result<(), NeighbourError> {
        self.build_ranked(x_m, y_m, z_m, radius_m, None)
    }

    /// [`Self::build`] with each cell's satellites stored (and so visited) in ascending `rank[i]`
    /// instead of ascending index `i` (ranks distinct; `None`: the index). The engine keeps its
    /// satellites in a storage order of its own and ranks them by id, so every query visits exactly as
    /// over the same positions given in id order.
    ///
    /// # Errors
    /// Those of [`Self::build`]; [`NeighbourError::RankLength`] unless `rank` has one entry per
    /// satellite.
    pub fn build_ranked(
        &mut self,
        x_m: &[f64],
        y_m: &[f64],
        z_m: &[f64],
        radius_m: f64,
        rank: Option<&[u32]>,
    ) -> Result<(), NeighbourError> {
        let n = x_m.len();
        if y_m.len() != n || z_m.len() != n {
            self.clear();
            if !(radius_m.is_finite() && radius_m > 0.0) {
                return Err(NeighbourError::InvalidRadius { radius_m });
            }
            return Err(NeighbourError::LengthMismatch {
                x: n,
                y: y_m.len(),
                z: z_m.len(),
            });
        }
        self.build_ranked_from(n, |i| [x_m[i], y_m[i], z_m[i]], radius_m, rank)
    }

    /// [`Self::build_ranked`] over `n` positions read through `position_m` (index → x, y, z \[m\]),
    /// so a caller whose positions sit in a table of its own needs no component-wise copy.
    ///
    /// # Errors
    /// Those of [`Self::build_ranked`] but the length mismatch.
    pub(crate) fn build_ranked_from(
        &mut self,
        n: usize,
        position_m: impl Fn(usize) -> [f64; 3] + Sync,
        radius_m: f64,
        rank: Option<&[u32]>,
    ) -> Result<(), NeighbourError> {
        self.clear();
        if !(radius_m.is_finite() && radius_m > 0.0) {
            return Err(NeighbourError::InvalidRadius { radius_m });
        }
        if let Some(rank) = rank.filter(|r| r.len() != n) {
            return Err(NeighbourError::RankLength {
                points: n,
                ranks: rank.len(),
            });
        }
        if n > MAX_POINTS {
            return Err(NeighbourError::TooManyPoints { n, max: MAX_POINTS });
        }
        // The bounding box (minima and maxima: the same values whatever the split), whether every
        // coordinate is finite, and, with a neighbour list of these satellites, the largest squared
        // move since it was made (its check, read with the positions), in one pass over fixed chunks,
        // each a plain loop. Plain comparisons skip a NaN, which the finiteness flag reports (the box
        // is then not used).
        let made_at = self.keeps_list.then(|| self.list.made_at_of(n)).flatten();
        let (mut lo, mut hi, finite, largest_move_m2) = (0..n.div_ceil(PARALLEL_MIN_LEN))
            .into_par_iter()
            .map(|chunk| {
                let (mut lo, mut hi, mut finite) =
                    ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3], true);
                let mut largest_move_m2: f64 = 0.0;
                for i in chunk * PARALLEL_MIN_LEN..((chunk + 1) * PARALLEL_MIN_LEN).min(n) {
                    let now = position_m(i);
                    for (a, v) in now.into_iter().enumerate() {
                        lo[a] = if v < lo[a] { v } else { lo[a] };
                        hi[a] = if v > hi[a] { v } else { hi[a] };
                        finite &= v.is_finite();
                    }
                    if let Some(made_at) = made_at {
                        let then = made_at[i];
                        let (dx, dy, dz) = (now[0] - then[0], now[1] - then[1], now[2] - then[2]);
                        largest_move_m2 = largest_move_m2.max(dx * dx + dy * dy + dz * dz);
                    }
                }
                (lo, hi, finite, largest_move_m2)
            })
            .reduce(
                || ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3], true, 0.0),
                |(lo_a, hi_a, finite_a, move_a), (lo_b, hi_b, finite_b, move_b)| {
                    (
                        [0, 1, 2].map(|a| lo_a[a].min(lo_b[a])),
                        [0, 1, 2].map(|a| hi_a[a].max(hi_b[a])),
                        finite_a && finite_b,
                        move_a.max(move_b),
                    )
                },
            );
        let largest_move_m2 = made_at.map(|_| largest_move_m2);
        if !finite {
            // The first satellite with a non-finite coordinate (a search only on this error path).
            let i = (0..n)
                .into_par_iter()
                .with_min_len(PARALLEL_MIN_LEN)
                .position_first(|i| !position_m(i).iter().all(|v| v.is_finite()))
                .expect("a non-finite coordinate was seen");
            let [x_m, y_m, z_m] = position_m(i);
            return Err(NeighbourError::NonFinitePosition {
                index: i,
                x_m,
                y_m,
                z_m,
            });
        }
        if n == 0 {
            lo = [0.0; 3];
            hi = [0.0; 3];
        }
        let extent = [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]];
        let extent_max = extent[0].max(extent[1]).max(extent[2]);
        self.radius_m = radius_m;
        self.cell_m = (radius_m * (1.0 + CELL_MARGIN))
            .max(extent_max / MAX_CELLS_PER_AXIS)
            .max(MIN_CELL_M);
        self.inv_cell = 1.0 / self.cell_m;
        self.origin_m = lo;
        // The largest coordinate maps to floor(extent / cell), computed exactly as in `cell_coord`, so
        // every satellite's cell index is below `dims` (float casts saturate, so nothing can wrap).
        self.dims = extent.map(|e| ((e * self.inv_cell).floor() as u64).saturating_add(1));
        let cells = self.dims[0]
            .saturating_mul(self.dims[1])
            .saturating_mul(self.dims[2]);
        self.layout = if cells <= DENSE_CELLS_PER_POINT * n as u64 + DENSE_EXTRA_CELLS {
            GridLayout::Dense
        } else {
            GridLayout::Sparse
        };

        self.items.resize(n, 0);
        match self.layout {
            GridLayout::Dense => self.sort_dense(n, &position_m, cells as usize),
            GridLayout::Sparse => self.sort_sparse(n, &position_m),
        }
        if let Some(rank) = rank {
            sort_cells_by_rank(&mut self.items, &self.cell_start, rank);
        }
        self.xs.resize(n, 0.0);
        self.ys.resize(n, 0.0);
        self.zs.resize(n, 0.0);
        self.slot_of.resize(n, 0);
        self.xs
            .par_iter_mut()
            .zip(self.ys.par_iter_mut())
            .zip(self.zs.par_iter_mut())
            .zip(self.items.par_iter())
            .with_min_len(PARALLEL_MIN_LEN)
            .for_each(|(((x, y), z), &i)| {
                [*x, *y, *z] = position_m(i as usize);
            });
        for (slot, &i) in self.items.iter().enumerate() {
            self.slot_of[i as usize] = slot as u32;
        }
        if self.keeps_list {
            let mut list = std::mem::take(&mut self.list);
            list.refresh(self, &position_m, &self.reach_seen, largest_move_m2);
            self.list = list;
        }
        Ok(())
    }

    /// Makes the grid keep a neighbour list across its builds (`keep`; `false` drops it): each build
    /// then checks how far the satellites have moved since the list was made, and queries within the
    /// list's reach (learned: the largest reach queried between two builds) test only each satellite's
    /// candidates. The answers and their order stay exactly those of the walk (module
    /// `neighbour_list`); it pays when the same satellites are queried build after build at a reach
    /// small against the cells, as the engine's law queries are.
    pub(crate) fn keep_neighbour_list(&mut self, keep: bool) {
        self.keeps_list = keep;
        if !keep {
            self.list = NeighbourList::default();
        }
    }

    /// Renumbers the neighbour list after the caller moved its satellites: satellite index `k` now is
    /// the one that was `moves[k]` (a permutation of `0..len`), so the list lasts across the move.
    /// The grid itself holds the old indices until its next build.
    pub(crate) fn renumber_neighbour_list(&mut self, moves: &[u32]) {
        self.list.renumber(moves);
    }

    /// How many times the grid's neighbour list was made (0 without one).
    pub(crate) fn neighbour_lists_made(&self) -> u64 {
        self.list.made()
    }

    /// Counting sort by dense cell index; stable, so each cell lists its satellites in ascending index.
    fn sort_dense(
        &mut self,
        n: usize,
        position_m: &(impl Fn(usize) -> [f64; 3] + Sync),
        cells: usize,
    ) {
        // One entry beyond the `cells + 1` kept, for the counts' offset below.
        self.cell_start.clear();
        self.cell_start.resize(cells + 2, 0);
        // Every satellite's cell in parallel (each on its own), then the serial counting sort.
        let mut cell_of_point = std::mem::take(&mut self.scratch_cell);
        cell_of_point.resize(n, 0);
        let grid = &*self;
        // Fixed chunks, each a plain loop (rayon's per-item closure call cost more than its body).
        cell_of_point
            .par_chunks_mut(PARALLEL_MIN_LEN)
            .enumerate()
            .for_each(|(chunk, cells)| {
                let first = chunk * PARALLEL_MIN_LEN;
                for (k, cell) in cells.iter_mut().enumerate() {
                    *cell = grid.key(grid.cell_of(position_m(first + k))) as u32;
                }
            });
        // Cell c's count at entry c + 2: after the running sum, entry c + 1 is the start of cell c,
        // the write cursor of the stable scatter, which leaves it at the cell's end, the start of
        // cell c + 1; entry 0 stays 0. (No pass to shift the cursors back; local slices, so the
        // loops keep their bounds in registers.)
        let (cell_start, items) = (&mut self.cell_start[..], &mut self.items[..]);
        for &c in &cell_of_point {
            cell_start[c as usize + 2] += 1;
        }
        let mut occupied = 0;
        let mut running = 0;
        for start in &mut cell_start[2..] {
            occupied += usize::from(*start > 0);
            running += *start;
            *start = running;
        }
        for (i, &c) in cell_of_point.iter().enumerate() {
            let cursor = &mut cell_start[c as usize + 1];
            items[*cursor as usize] = i as u32;
            *cursor += 1;
        }
        self.cell_start.truncate(cells + 1);
        self.occupied = occupied;
        self.scratch_cell = cell_of_point;
    }

    /// Sort of (cell key, index) pairs; keys are unique per (cell, satellite), so the order is fixed.
    fn sort_sparse(&mut self, n: usize, position_m: &impl Fn(usize) -> [f64; 3]) {
        self.scratch_pairs.clear();
        for i in 0..n {
            let key = self.key(self.cell_of(position_m(i)));
            self.scratch_pairs.push((key, i as u32));
        }
        self.scratch_pairs.sort_unstable();
        self.cell_keys.clear();
        self.cell_start.clear();
        for (slot, &(key, i)) in self.scratch_pairs.iter().enumerate() {
            if self.cell_keys.last() != Some(&key) {
                self.cell_keys.push(key);
                self.cell_start.push(slot as u32);
            }
            self.items[slot] = i;
        }
        self.cell_start.push(n as u32);
        self.occupied = self.cell_keys.len();
    }

    /// Empties the grid, keeping its buffers: every query then finds nothing.
    pub fn clear(&mut self) {
        self.radius_m = 0.0;
        self.dims = [1; 3];
        self.layout = GridLayout::Dense;
        self.occupied = 0;
        self.xs.clear();
        self.ys.clear();
        self.zs.clear();
        self.items.clear();
        self.slot_of.clear();
        self.cell_start.clear();
        self.cell_start.push(0);
        self.cell_start.push(0);
        self.cell_keys.clear();
        self.masked = false;
        self.hidden.clear();
    }

    /// Hides every satellite `i` with `visible(i) == false` from all queries until the next build: it is
    /// nobody's neighbour and nobody's nearest neighbour. A hidden satellite can still be queried about
    /// its own neighbourhood (its position stays in the grid). Costs one pass over the satellites in
    /// index order, and one in storage order when something is hidden.
    pub fn mask(&mut self, visible: impl Fn(usize) -> bool) {
        self.hidden.clear();
        if (0..self.len()).any(|i| !visible(i)) {
            self.hidden
                .extend(self.items.iter().map(|&i| !visible(i as usize)));
        }
        self.masked = true;
    }

    /// Whether [`Self::mask`] was applied since the last build (so its visibility rule holds for every
    /// query).
    pub fn is_masked(&self) -> bool {
        self.masked
    }

    /// Whether the satellite in storage slot `s` is hidden by the mask.
    #[inline(always)]
    fn hidden_slot(&self, s: usize) -> bool {
        self.hidden.get(s).copied().unwrap_or(false)
    }

    /// Query radius of the last successful build (m); 0 for an empty or failed grid.
    pub fn radius_m(&self) -> f64 {
        self.radius_m
    }

    /// Cell edge used by the last build (m): the radius times (1 + 1e-6), or more for swarms spread over
    /// more than 2^20 radii, and never less than `4 * f64::MIN_POSITIVE` (a subnormal radius is clamped up).
    pub fn cell_size_m(&self) -> f64 {
        self.cell_m
    }

    /// Number of satellites in the grid.
    pub fn len(&self) -> usize {
        self.items.len()
    }

    /// `true` when the grid holds no satellite.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// Storage layout chosen by the last build.
    pub fn layout(&self) -> GridLayout {
        self.layout
    }

    /// Number of non-empty cells (a measure of how well the cell size fits the spacing).
    pub fn occupied_cells(&self) -> usize {
        self.occupied
    }

    /// The satellites in storage order: `cell_order()[s]` is the satellite stored in slot `s`. Storage
    /// order is cell order (cells ascending in (z, y, x), within a cell ascending index, or ascending
    /// rank after [`Self::build_ranked`]), so satellites
    /// next to each other here are close in space: evaluating per-satellite work in this order keeps
    /// neighbouring satellites' data in cache. Empty before a successful build.
    pub fn cell_order(&self) -> &[u32] {
        &self.items
    }

    /// Storage slot of satellite `i` (its position in [`Self::cell_order`]).
    ///
    /// # Panics
    /// If `i >= self.len()`.
    pub fn slot(&self, i: usize) -> usize {
        self.slot_of[i] as usize
    }

    /// Position of satellite `i` as given to the last build (m, the caller's frame).
    ///
    /// # Panics
    /// If `i >= self.len()`.
    pub fn position_m(&self, i: usize) -> [f64; 3] {
        let s = self.slot_of[i] as usize;
        [self.xs[s], self.ys[s], self.zs[s]]
    }

    /// Calls `visit` once for every satellite `j != i`, not hidden by [`Self::mask`], with
    /// `|p_j - p_i| <= radius_m()` (see the module docs for the inclusion rule and the deterministic visit
    /// order). Never allocates.
    ///
    /// # Panics
    /// If `i >= self.len()`.
    pub fn for_each_neighbour(&self, i: usize, visit: impl FnMut(Neighbour)) {
        self.for_each_within(i, self.radius_m, visit);
    }

    /// Like [`Self::for_each_neighbour`] but with any reach `reach_m` (m), smaller or larger than the grid
    /// radius. A reach of a few cells walks the cells of the `(2k + 1)³` block around `i` that the box
    /// `[p − reach, p + reach]` meets; a reach whose block of cells exceeds the swarm size scans all
    /// satellites. A negative or NaN reach visits nothing. Never
    /// allocates.
    ///
    /// # Panics
    /// If `i >= self.len()`.
    pub fn for_each_within(&self, i: usize, reach_m: f64, visit: impl FnMut(Neighbour)) {
        self.for_each_within_slot(self.slot_of[i] as usize, reach_m, visit);
    }

    /// [`Self::for_each_within`] of the satellite stored in slot `si` (its position in
    /// [`Self::cell_order`]): for callers walking the satellites in storage order.
    ///
    /// # Panics
    /// If `si >= self.len()`.
    pub(crate) fn for_each_within_slot(
        &self,
        si: usize,
        reach_m: f64,
        mut visit: impl FnMut(Neighbour),
    ) {
        if reach_m.is_nan() || reach_m < 0.0 {
            return;
        }
        if self.keeps_list {
            self.reach_seen.note(reach_m);
            if self.list.serves(reach_m) && self.list.visit(self, si, reach_m, &mut visit) {
                return;
            }
        }
        self.walk(si, reach_m, visit);
    }

    /// The walk of the cells around the satellite in slot `si` for [`Self::for_each_within_slot`] (a
    /// reach neither negative nor NaN).
    fn walk(&self, si: usize, reach_m: f64, visit: impl FnMut(Neighbour)) {
        // The copy of the prefilter is chosen once per query, and the whole query is compiled once
        // per copy, with its batches inlined into the row loop.
        match (self.prefilter.avx512(), self.prefilter.avx2()) {
            #[cfg(target_arch = "x86_64")]
            #[allow(unsafe_code)]
            // SAFETY: `batches` exists only on a CPU with AVX-512F, AVX-512VL and POPCNT, the
            // features the function enables.
            (Some(batches), _) => unsafe { self.within_avx512(batches, si, reach_m, visit) },
            #[cfg(target_arch = "x86_64")]
            #[allow(unsafe_code)]
            // SAFETY: `batches` exists only on a CPU with AVX2 and POPCNT, the features the function
            // enables.
            (_, Some(batches)) => unsafe { self.within_avx2(batches, si, reach_m, visit) },
            _ => self.within(PortableBatches, si, reach_m, visit),
        }
    }

    /// [`Self::within`] compiled with AVX2 and POPCNT enabled, for their batches (`batches` proves
    /// the CPU has them).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,popcnt")]
    fn within_avx2(
        &self,
        batches: Avx2Batches,
        si: usize,
        reach_m: f64,
        visit: impl FnMut(Neighbour),
    ) {
        self.within(batches, si, reach_m, visit);
    }

    /// [`Self::within`] compiled with AVX-512F, AVX-512VL and POPCNT enabled, for their batches
    /// (`batches` proves the CPU has them).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx512vl,popcnt")]
    fn within_avx512(
        &self,
        batches: Avx512Batches,
        si: usize,
        reach_m: f64,
        visit: impl FnMut(Neighbour),
    ) {
        self.within(batches, si, reach_m, visit);
    }

    /// The query of [`Self::for_each_within_slot`] (a reach neither negative nor NaN), prefiltering
    /// with `batches`.
    #[inline(always)]
    fn within<B: Batches>(
        &self,
        batches: B,
        si: usize,
        reach_m: f64,
        visit: impl FnMut(Neighbour),
    ) {
        let p = [self.xs[si], self.ys[si], self.zs[si]];
        let c = self.cell_of(p);
        // Satellites k + 1 or more cells away are farther than k · gap (> reach once k = K).
        let gap = self.cell_m * GAP_FACTOR;
        // (Float-to-int casts truncate, which is floor for the non-negative values here, and saturate.)
        let k = ((reach_m / gap) as u64)
            .saturating_add(1)
            .min(self.max_dim());
        // Prefilter on squared distance, with a relative margin so it never rejects a point that passes
        // the exact `sqrt(d2) <= reach` test.
        let reach2 = reach_m * reach_m * (1.0 + 1e-10);
        let mut query = Query {
            grid: self,
            batches,
            si,
            p,
            reach_m,
            reach2,
            // Not zeroed: a 1 KB fill per query cost about a tenth of a short query.
            passed: [const { MaybeUninit::uninit() }; PASSED_CAPACITY],
            count: 0,
            visit,
        };
        if self.block_cells(c, k) > self.brute_force_threshold() {
            query.scan(0..self.len());
        } else {
            // Only the cells the box [p − reach, p + reach] meets: all 3 × 3 × 3 for a reach of the
            // radius, often the satellite's own cell alone for a reach well below it.
            let (x_lo, x_hi) = self.reach_span(c, k, p, reach_m, 0);
            let (y_lo, y_hi) = self.reach_span(c, k, p, reach_m, 1);
            let (z_lo, z_hi) = self.reach_span(c, k, p, reach_m, 2);
            for z in z_lo..=z_hi {
                for y in y_lo..=y_hi {
                    query.scan(self.row(y, z, x_lo, x_hi));
                }
            }
        }
        query.visit_passed();
    }

    /// The nearest other satellite to satellite `i`, at any distance (the search widens ring by ring of
    /// cells beyond the grid radius, and falls back to a scan of all satellites when the rings grow larger
    /// than the swarm). Ties in distance go to the smaller index; satellites hidden by [`Self::mask`] are
    /// skipped. `None` when the grid holds fewer than two satellites or every other one is hidden. Never
    /// allocates.
    ///
    /// # Panics
    /// If `i >= self.len()`.
    pub fn nearest_neighbour(&self, i: usize) -> Option<Neighbour> {
        if self.len() < 2 {
            return None;
        }
        let si = self.slot_of[i] as usize;
        let p = [self.xs[si], self.ys[si], self.zs[si]];
        let c = self.cell_of(p);
        let mut best: Option<Neighbour> = None;
        // A candidate farther than the best so far in squared distance by more than the rounding of a
        // root is not at or below its distance: each row of cells is scanned for squared distances
        // alone (no bounds checks, no root: the root's latency and the compare waiting on it were most
        // of a query), and only a candidate within the bound is compared exactly.
        let mut reach_m2 = f64::INFINITY;
        let mut scan = |slots: Range<usize>, best: &mut Option<Neighbour>| {
            let first = slots.start;
            let (xs, ys, zs) = (
                &self.xs[slots.clone()],
                &self.ys[slots.clone()],
                &self.zs[slots],
            );
            for (k, ((&x, &y), &z)) in xs.iter().zip(ys).zip(zs).enumerate() {
                let (dx, dy, dz) = (x - p[0], y - p[1], z - p[2]);
                let d2 = dx * dx + dy * dy + dz * dz;
                if d2 > reach_m2 {
                    continue;
                }
                let s = first + k;
                if s == si || self.hidden_slot(s) {
                    continue;
                }
                let d = d2.sqrt();
                let j = self.items[s] as usize;
                let better = match *best {
                    None => true,
                    Some(b) => d < b.distance_m || (d == b.distance_m && j < b.index),
                };
                if better {
                    *best = Some(Neighbour {
                        index: j,
                        dx_m: dx,
                        dy_m: dy,
                        dz_m: dz,
                        distance_m: d,
                    });
                    reach_m2 = squared_distance_bound_m2(d);
                }
            }
        };
        let gap = self.cell_m * GAP_FACTOR;
        let max_k = self.max_dim();
        for k in 0..=max_k {
            if self.block_cells(c, k) > self.brute_force_threshold() {
                scan(0..self.len(), &mut best);
                return best;
            }
            self.visit_ring(c, k, &mut |slots| scan(slots, &mut best));
            // Everything not yet visited is more than k · gap away.
            if best.is_some_and(|b| b.distance_m <= k as f64 * gap) {
                return best;
            }
        }
        best
    }

    /// Cell coordinates of a position (clamped into the grid).
    #[inline(always)]
    fn cell_of(&self, p: [f64; 3]) -> [u64; 3] {
        let mut c = [0; 3];
        for a in 0..3 {
            let u = (p[a] - self.origin_m[a]) * self.inv_cell;
            // Float-to-int casts truncate (floor, as u >= 0: p is never below the origin, the lowest
            // coordinate) and saturate (NaN -> 0, beyond i32's range -> its bound); the clamp keeps
            // negatives at 0 and guards the top edge (dims <= 2^20 + 1, far inside i32). The cast to
            // i32 gives the cast to u64's cells for every input in one conversion instruction (to u64
            // takes a compare, a subtraction and a second conversion on x86-64).
            c[a] = (u as i32).clamp(0, (self.dims[a] - 1) as i32) as u64;
        }
        c
    }

    /// Linear cell key, ascending in (z, y, x) lexicographic order.
    #[inline(always)]
    fn key(&self, c: [u64; 3]) -> u64 {
        c[0] + self.dims[0] * (c[1] + self.dims[1] * c[2])
    }

    #[inline(always)]
    fn max_dim(&self) -> u64 {
        self.dims[0].max(self.dims[1]).max(self.dims[2])
    }

    /// Above this many cells in a query block, a scan of all satellites is cheaper.
    #[inline(always)]
    fn brute_force_threshold(&self) -> u64 {
        4 * self.len() as u64 + 64
    }

    /// Inclusive cell range `[c - k, c + k]` clamped to the grid along axis `a`.
    #[inline(always)]
    fn span(&self, c: [u64; 3], k: u64, a: usize) -> (u64, u64) {
        (
            c[a].saturating_sub(k),
            c[a].saturating_add(k).min(self.dims[a] - 1),
        )
    }

    /// [`Self::span`] narrowed to the cells that the interval `[p − reach, p + reach]` (widened by
    /// [`BOX_MARGIN_CELLS`]) meets along axis `a`: dropping whole cells, never a satellite within the
    /// reach, so a query visits the same satellites in the same order.
    #[inline(always)]
    fn reach_span(&self, c: [u64; 3], k: u64, p: [f64; 3], reach_m: f64, a: usize) -> (u64, u64) {
        let (lo, hi) = self.span(c, k, a);
        let u = (p[a] - self.origin_m[a]) * self.inv_cell;
        let r = reach_m * self.inv_cell + BOX_MARGIN_CELLS;
        // Casts truncate (floor for non-negative values) and saturate (negative -> 0).
        let (box_lo, box_hi) = ((u - r) as u64, (u + r) as u64);
        (lo.max(box_lo.min(c[a])), hi.min(box_hi.max(c[a])))
    }

    /// Number of grid cells in the clamped block of half-width `k` around cell `c`.
    #[inline(always)]
    fn block_cells(&self, c: [u64; 3], k: u64) -> u64 {
        (0..3)
            .map(|a| {
                let (lo, hi) = self.span(c, k, a);
                hi - lo + 1
            })
            .product()
    }

    /// Storage slots of the cells `(x_lo..=x_hi, y, z)`: one contiguous range in both layouts.
    #[inline(always)]
    fn row(&self, y: u64, z: u64, x_lo: u64, x_hi: u64) -> Range<usize> {
        let k0 = self.key([x_lo, y, z]);
        let k1 = k0 + (x_hi - x_lo) + 1;
        match self.layout {
            GridLayout::Dense => {
                self.cell_start[k0 as usize] as usize..self.cell_start[k1 as usize] as usize
            }
            GridLayout::Sparse => {
                let a = self.cell_keys.partition_point(|&key| key < k0);
                let b = a + self.cell_keys[a..].partition_point(|&key| key < k1);
                self.cell_start[a] as usize..self.cell_start[b] as usize
            }
        }
    }

    /// Visits every slot in the clamped block of half-width `k` around cell `c`, in visit order (the
    /// plain walk the batched scan of [`Self::for_each_within`] is tested against).
    #[cfg(test)]
    fn visit_block(&self, c: [u64; 3], k: u64, f: &mut impl FnMut(usize)) {
        let (x_lo, x_hi) = self.span(c, k, 0);
        let (y_lo, y_hi) = self.span(c, k, 1);
        let (z_lo, z_hi) = self.span(c, k, 2);
        for z in z_lo..=z_hi {
            for y in y_lo..=y_hi {
                self.row(y, z, x_lo, x_hi).for_each(&mut *f);
            }
        }
    }

    /// Visits every slot in the cells at Chebyshev distance exactly `k` from cell `c` (clamped), as
    /// ranges of slots (rows of cells).
    fn visit_ring(&self, c: [u64; 3], k: u64, f: &mut impl FnMut(Range<usize>)) {
        let (x_lo, x_hi) = self.span(c, k, 0);
        let (y_lo, y_hi) = self.span(c, k, 1);
        let (z_lo, z_hi) = self.span(c, k, 2);
        for z in z_lo..=z_hi {
            for y in y_lo..=y_hi {
                if z.abs_diff(c[2]) == k || y.abs_diff(c[1]) == k {
                    f(self.row(y, z, x_lo, x_hi));
                } else {
                    if c[0] >= k {
                        f(self.row(y, z, c[0] - k, c[0] - k));
                    }
                    if k > 0 && c[0] + k < self.dims[0] {
                        f(self.row(y, z, c[0] + k, c[0] + k));
                    }
                }
            }
        }
    }
}

/// A squared distance \[m²\] at or above every `d2` whose rounded square root is at most `distance_m`
/// (a rounded root `√d2`): `d2` above it has a root above `distance_m`. The square times 1 + 4ε
/// covers the roundings of both roots and of the square; where the square is subnormal (distances
/// below 2⁻⁵¹¹ m), the smallest normal number does (a `d2` above it has a root of at least 2⁻⁵¹¹).
fn squared_distance_bound_m2(distance_m: f64) -> f64 {
    (distance_m * distance_m * (1.0 + 4.0 * f64::EPSILON)).max(f64::MIN_POSITIVE)
}

/// Sorts the satellites of each cell (`items[cell_start[c] .. cell_start[c + 1]]`, slots counted from
/// `cell_start[0]`; already in ascending index) by rank: nearly sorted when the storage order follows the
/// ranks, which the sort exploits. Cells are independent, so halves of the cells go to the rayon pool
/// (each cell sorted whole by one thread: the same order on any thread count).
fn sort_cells_by_rank(items: &mut [u32], cell_start: &[u32], rank: &[u32]) {
    let cells = cell_start.len() - 1;
    if items.len() <= PARALLEL_MIN_LEN || cells < 2 {
        let first = cell_start[0] as usize;
        for window in cell_start.windows(2) {
            let (start, end) = (window[0] as usize - first, window[1] as usize - first);
            if end - start > 1 {
                items[start..end].sort_unstable_by_key(|&i| rank[i as usize]);
            }
        }
        return;
    }
    let half = cells / 2;
    let (low, high) = items.split_at_mut((cell_start[half] - cell_start[0]) as usize);
    rayon::join(
        || sort_cells_by_rank(low, &cell_start[..=half], rank),
        || sort_cells_by_rank(high, &cell_start[half..], rank),
    );
}

/// One fixed-radius query under way: each row of cells is scanned in batches (the squared distances
/// of a whole batch, with the slots that pass appended without a branch: most candidates fail,
/// unpredictably). The exact test and the visits run over everything passed so far, in slot order,
/// once the buffer might not hold another batch and at the end: one loop over the passed candidates
/// per query, not one per row.
struct Query<'g, B, V> {
    grid: &'g NeighbourGrid,
    batches: B,
    /// The querying satellite's slot and position (m).
    si: usize,
    p: [f64; 3],
    /// The reach (m), and the squared reach of the prefilter (m²).
    reach_m: f64,
    reach2: f64,
    /// The candidate slots passed so far (the first `count`, written by the prefilter), ascending;
    /// the entries beyond are not yet written.
    passed: [MaybeUninit<u32>; PASSED_CAPACITY],
    count: usize,
    visit: V,
}

impl<B: Batches, V: FnMut(Neighbour)> Query<'_, B, V> {
    /// Prefilters the candidate slots `slots` (one row of cells, or all satellites).
    #[inline(always)]
    fn scan(&mut self, slots: Range<usize>) {
        let g = self.grid;
        let mut start = slots.start;
        while start < slots.end {
            if self.count + SCAN_BATCH > PASSED_CAPACITY {
                self.visit_passed();
            }
            let end = (start + SCAN_BATCH).min(slots.end);
            let window: &mut [MaybeUninit<u32>; SCAN_BATCH] = (&mut self.passed
                [self.count..self.count + SCAN_BATCH])
                .try_into()
                .expect("a window of SCAN_BATCH slots");
            let candidates = Candidates {
                xs: &g.xs[start..end],
                ys: &g.ys[start..end],
                zs: &g.zs[start..end],
                first_slot: start as u32,
            };
            self.count += self
                .batches
                .passing(candidates, self.p, self.reach2, window);
            start = end;
        }
    }

    /// The exact test and the visit of the candidate slots passed so far, which it empties.
    #[inline(always)]
    #[allow(unsafe_code)]
    fn visit_passed(&mut self) {
        let (g, p) = (self.grid, self.p);
        for passed in &self.passed[..self.count] {
            // SAFETY: the first `count` entries are written: each batch's `passing` wrote the first
            // entries of its window (at the count before it), as many as it returned (the contract of
            // the unsafe trait `Batches`).
            let s = unsafe { passed.assume_init() } as usize;
            let (dx, dy, dz) = (g.xs[s] - p[0], g.ys[s] - p[1], g.zs[s] - p[2]);
            let d = (dx * dx + dy * dy + dz * dz).sqrt();
            if s != self.si && d <= self.reach_m && !g.hidden_slot(s) {
                (self.visit)(Neighbour {
                    index: g.items[s] as usize,
                    dx_m: dx,
                    dy_m: dy,
                    dz_m: dz,
                    distance_m: d,
                });
            }
        }
        self.count = 0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_is_sync_and_send() {
        fn check<T: Sync + Send>() {}
        check::<NeighbourGrid>();
    }

    #[test]
    fn thin_spread_uses_sparse_layout_and_tight_swarm_dense() {
        let mut g = NeighbourGrid::new();
        // 1000 satellites over 200 km with a 10 m radius: 2e4 cells per axis, far more than 8 N.
        let x: Vec<f64> = (0..1000).map(|i| i as f64 * 200.0).collect();
        let y: Vec<f64> = (0..1000)
            .map(|i| ((i * 7919) % 1000) as f64 * 200.0)
            .collect();
        let z = vec![0.0; 1000];
        g.build(&x, &y, &z, 10.0).unwrap();
        assert_eq!(g.layout(), GridLayout::Sparse);
        g.build(&x, &y, &z, 5e4).unwrap();
        assert_eq!(g.layout(), GridLayout::Dense);
    }

    /// The plain query: every slot of the whole block (or every slot when the block outgrows the
    /// swarm), with the documented inclusion rule, in visit order.
    fn plain_within(g: &NeighbourGrid, i: usize, reach_m: f64) -> Vec<Neighbour> {
        let si = g.slot_of[i] as usize;
        let p = [g.xs[si], g.ys[si], g.zs[si]];
        let c = g.cell_of(p);
        let k = ((reach_m / (g.cell_m * GAP_FACTOR)).floor() + 1.0).min(g.max_dim() as f64) as u64;
        let mut out = Vec::new();
        let mut test = |s: usize| {
            let (dx, dy, dz) = (g.xs[s] - p[0], g.ys[s] - p[1], g.zs[s] - p[2]);
            let d = (dx * dx + dy * dy + dz * dz).sqrt();
            if s != si && d <= reach_m {
                out.push(Neighbour {
                    index: g.items[s] as usize,
                    dx_m: dx,
                    dy_m: dy,
                    dz_m: dz,
                    distance_m: d,
                });
            }
        };
        if g.block_cells(c, k) > g.brute_force_threshold() {
            (0..g.len()).for_each(test);
        } else {
            g.visit_block(c, k, &mut test);
        }
        out
    }

    /// The batched scan changes neither the answers nor their order: it equals the plain slot-by-slot
    /// walk of the block, neighbour by neighbour, with either copy of the prefilter, on dense and sparse
    /// layouts, at ECI-sized offsets, on a lattice with many pairs exactly at the reach, for reaches
    /// from a fraction of a cell to several cells (and the all-satellite scan when the block outgrows
    /// the swarm, and queries passing more candidates than the buffer holds).
    #[test]
    fn batched_query_visits_exactly_what_the_plain_walk_visits() {
        let mut uniform = prefilter::tests::uniform_draws(0x2545_f491_4f6c_dd1d);
        let mut g = NeighbourGrid::new();
        let (mut visited, mut most) = (0, 0);
        for (offset, spread, lattice) in [
            (0.0, 100.0, false),
            (7e6, 30.0, false),
            (0.0, 6.0, true),
            (-3e5, 2e5, false),
        ] {
            let n = 1500;
            let mut coordinate = || {
                let v = uniform() * spread;
                offset + if lattice { v.floor() } else { v }
            };
            let (mut x, mut y, mut z) = (Vec::new(), Vec::new(), Vec::new());
            for _ in 0..n {
                x.push(coordinate());
                y.push(coordinate());
                z.push(coordinate());
            }
            let radius = spread / 12.0;
            g.build(&x, &y, &z, radius).unwrap();
            for reach in [
                0.05 * radius,
                0.3 * radius,
                radius,
                1.7 * radius,
                3.0 * radius,
                6.0 * radius,
            ] {
                let reach = if lattice {
                    reach.round().max(1.0)
                } else {
                    reach
                };
                for prefilter in prefilter::tests::copies() {
                    g.prefilter = prefilter;
                    for i in 0..n {
                        let mut batched = Vec::new();
                        g.for_each_within(i, reach, |nb| batched.push(nb));
                        assert_eq!(
                            batched,
                            plain_within(&g, i, reach),
                            "satellite {i}, reach {reach}, {prefilter:?}"
                        );
                        visited += batched.len();
                        most = most.max(batched.len());
                    }
                }
            }
        }
        assert!(visited > 100_000, "too few neighbours to test: {visited}");
        assert!(
            most > PASSED_CAPACITY,
            "no query filled the candidate buffer: at most {most} neighbours"
        );
    }

    /// A ranked build over positions in a shuffled storage order, ranked by their original index,
    /// answers every query with exactly the neighbours, in exactly the order, of the plain build over the
    /// positions in original order (indices mapped back through the shuffle), on dense and sparse
    /// layouts and with crowded cells; a rank slice of the wrong length is refused.
    #[test]
    fn ranked_build_visits_as_the_build_in_rank_order() {
        let mut uniform = prefilter::tests::uniform_draws(0x9e37_79b9_7f4a_7c15);
        let (mut visited, mut layouts) = (0, Vec::new());
        for (spread, radius) in [(100.0, 8.0), (2e4, 900.0), (4.0, 3.0)] {
            let n = 1200;
            let original: Vec<[f64; 3]> = (0..n)
                .map(|_| [uniform() * spread, uniform() * spread, uniform() * spread])
                .collect();
            // storage[k] holds original index perm[k] (a fixed shuffle).
            let mut perm: Vec<usize> = (0..n).collect();
            for k in (1..n).rev() {
                perm.swap(k, (uniform() * (k + 1) as f64) as usize % (k + 1));
            }
            let rank: Vec<u32> = perm.iter().map(|&i| i as u32).collect();
            let axis = |a: usize, order: &dyn Fn(usize) -> usize| -> Vec<f64> {
                (0..n).map(|k| original[order(k)][a]).collect()
            };
            let (mut plain, mut ranked) = (NeighbourGrid::new(), NeighbourGrid::new());
            let id = |k: usize| k;
            let shuffled = |k: usize| perm[k];
            plain
                .build(&axis(0, &id), &axis(1, &id), &axis(2, &id), radius)
                .unwrap();
            ranked
                .build_ranked(
                    &axis(0, &shuffled),
                    &axis(1, &shuffled),
                    &axis(2, &shuffled),
                    radius,
                    Some(&rank),
                )
                .unwrap();
            assert_eq!(plain.layout(), ranked.layout());
            layouts.push(ranked.layout());
            for (k, &i) in perm.iter().enumerate() {
                let (mut a, mut b) = (Vec::new(), Vec::new());
                plain.for_each_neighbour(i, |nb| a.push(nb));
                ranked.for_each_neighbour(k, |mut nb| {
                    nb.index = perm[nb.index];
                    b.push(nb);
                });
                assert_eq!(a, b, "satellite {i} (stored at {k}), spread {spread}");
                visited += a.len();
            }
        }
        assert!(visited > 100_000, "too few neighbours to test: {visited}");
        assert!(layouts.contains(&GridLayout::Sparse) && layouts.contains(&GridLayout::Dense));
        let mut g = NeighbourGrid::new();
        assert_eq!(
            g.build_ranked(&[0.0; 3], &[0.0; 3], &[0.0; 3], 1.0, Some(&[0, 1])),
            Err(NeighbourError::RankLength {
                points: 3,
                ranks: 2
            })
        );
    }

    /// The nearest-neighbour search drops a candidate whose squared distance is above
    /// `squared_distance_bound_m2(d)` without its root: every such candidate's rounded root must be above
    /// `d`. The first double above the bound has a root above `d` (so every larger one does), for
    /// distances that are roots of squared distances across the range: ordinary, with mantissas at the
    /// rounding edges, tiny (squares subnormal or zero), zero, and huge (square overflowing).
    #[test]
    fn nothing_above_the_squared_bound_has_a_root_at_or_below_the_distance() {
        let mut squares = vec![0.0, f64::MIN_POSITIVE, 1e-320, 5e-324, 1e300, f64::MAX];
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        for _ in 0..200_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            // Random bits for the mantissa, exponents over the whole normal range.
            let mantissa = 1.0 + (state >> 12) as f64 / (1u64 << 52) as f64;
            let exponent = (state % 2000) as i32 - 1000;
            squares.push(mantissa * 2f64.powi(exponent));
        }
        for d2 in squares {
            let d = d2.sqrt();
            let bound = squared_distance_bound_m2(d);
            assert!(
                bound >= d2,
                "{d2:e}: bound {bound:e} below the square it came from"
            );
            let above = bound.next_up();
            assert!(
                above.sqrt() > d,
                "{d2:e}: {above:e} above the bound {bound:e} has root {:e} <= {d:e}",
                above.sqrt()
            );
        }
    }

    /// `cell_of` is floor((p − origin) / cell) clamped into [0, dims − 1] on every axis, with NaN in
    /// cell 0: checked on coordinates inside, on the edges of, below and far beyond a grid of the
    /// largest cell count per axis.
    #[test]
    fn cell_coordinates_are_the_clamped_floor() {
        let mut g = NeighbourGrid::new();
        // 1 m radius over 3e6 m on x: capped at 2^20 cells per axis there; one cell on y and z.
        g.build(&[0.0, 3e6], &[0.0; 2], &[0.0; 2], 1.0).unwrap();
        let dims = g.dims;
        assert_eq!(dims[0], MAX_CELLS_PER_AXIS as u64 + 1);
        let expected = |u: f64, dim: u64| -> u64 {
            if u.is_nan() || u < 0.0 {
                0
            } else {
                (u.floor().min((dim - 1) as f64)) as u64
            }
        };
        let cell = g.cell_size_m();
        for x in [
            0.0,
            0.5 * cell,
            cell,
            12_345.678,
            3e6,
            3e6 + 10.0 * cell,
            -1e-9,
            -5.0 * cell,
            1e300,
            -1e300,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ] {
            let c = g.cell_of([x, x, x]);
            for a in 0..3 {
                let u = (x - g.origin_m[a]) * g.inv_cell;
                assert_eq!(c[a], expected(u, dims[a]), "x = {x}, axis {a}");
            }
        }
    }

    #[test]
    fn extreme_spread_caps_cells_per_axis() {
        let mut g = NeighbourGrid::new();
        // 1e-3 m radius over 1e9 m: 1e12 cells per axis uncapped.
        g.build(&[0.0, 1e9, 1e9 + 5e-4], &[0.0; 3], &[0.0; 3], 1e-3)
            .unwrap();
        assert!(g.cell_size_m() >= 1e9 / MAX_CELLS_PER_AXIS);
        let mut found = Vec::new();
        g.for_each_neighbour(1, |nb| found.push(nb.index));
        assert_eq!(found, vec![2]);
    }
}
