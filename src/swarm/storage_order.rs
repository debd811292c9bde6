//! The satellites' storage order. The engine keeps every per-satellite array (state, fleet, truth,
//! commands, the law's states, buffers) in one order of its own, the **storage order**, which it
//! re-sorts by grid cell (`simulation/resort.rs`). Ids never change: a satellite's id is its index in the
//! scenario, and everything a law, a random stream, an event or an output names is by id;
//! [`StorageOrder`] and [`Placement`] translate.
//!
//! Nothing a run computes depends on the storage order: each satellite's computations read the same
//! inputs wherever it is stored, neighbours are visited in (cell, id) order whatever the storage order
//! ([`crate::grid::NeighbourGrid::build_ranked`]), and what is summed over satellites is summed by id.

use rayon::prelude::*;

/// Which satellite id each entry of a view's per-satellite slices holds, and back: the engine's storage
/// order, borrowed.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Placement<'a> {
    /// Satellite id of each storage index.
    pub id_of: &'a [u32],
    /// Storage index of each satellite id.
    pub index_of: &'a [u32],
}

impl Placement<'_> {
    /// `by_index` (one value per storage index) gathered into id order.
    pub fn by_id<T: Clone>(&self, by_index: &[T]) -> Vec<T> {
        self.index_of
            .iter()
            .map(|&k| by_index[k as usize].clone())
            .collect()
    }

    /// `by_id` (one value per satellite id) gathered into storage order.
    pub fn by_index<T: Clone>(&self, by_id: &[T]) -> Vec<T> {
        self.id_of
            .iter()
            .map(|&id| by_id[id as usize].clone())
            .collect()
    }
}

/// Which satellite id each storage index holds, and back.
#[derive(Clone, Debug)]
pub(crate) struct StorageOrder {
    /// Satellite id at each storage index.
    id_of: Vec<u32>,
    /// Storage index of each satellite id.
    index_of: Vec<u32>,
    /// Whether storage index == id for every satellite.
    identity: bool,
}

impl StorageOrder {
    /// The identity order of `n` satellites (storage index = id).
    pub fn identity(n: usize) -> Self {
        let id_of: Vec<u32> = (0..n as u32).collect();
        Self {
            index_of: id_of.clone(),
            id_of,
            identity: true,
        }
    }

    /// The satellite id stored at `index`.
    #[inline]
    pub fn id_at(&self, index: usize) -> usize {
        self.id_of[index] as usize
    }

    /// The storage index of satellite `id`.
    #[inline]
    pub fn index_of(&self, id: usize) -> usize {
        self.index_of[id] as usize
    }

    /// The ids by storage index, for a ranked grid build; `None` for the identity order.
    pub fn ranks(&self) -> Option<&[u32]> {
        (!self.identity).then_some(self.id_of.as_slice())
    }

    /// The translation a view needs; `None` for the identity order.
    pub fn placement(&self) -> Option<Placement<'_>> {
        (!self.identity).then(|| Placement {
            id_of: &self.id_of,
            index_of: &self.index_of,
        })
    }

    /// Gathers `by_index` (one value per storage index) into id order.
    pub fn by_id<T: Clone>(&self, by_index: &[T]) -> Vec<T> {
        match self.placement() {
            None => by_index.to_vec(),
            Some(p) => p.by_id(by_index),
        }
    }

    /// Moves to the storage order in which new index `k` holds what old index `moves[k]` held.
    pub fn apply(&mut self, moves: &Moves) {
        moves.apply(&mut self.id_of);
        for (k, &id) in self.id_of.iter().enumerate() {
            self.index_of[id as usize] = k as u32;
        }
        self.identity = self
            .id_of
            .iter()
            .enumerate()
            .all(|(k, &id)| k == id as usize);
    }
}

/// A change of the storage order: new index `k` holds what old index `moves[k]` held (`moves` a
/// permutation of `0..n`). Its cycles are listed once, so that every per-satellite array then moves by
/// swaps along them: the indices of the swaps are read in sequence, none waits on the one before, and
/// the arrays move independently of one another (in parallel, [`Self::apply_all`]), where following
/// `moves` array by array made each step of a cycle wait on the load of the last.
pub(crate) struct Moves {
    /// Old index of what new index `k` holds.
    moves: Vec<u32>,
    /// The cycles of length two or more, one after another: each lists `c0`, `moves[c0]`,
    /// `moves[moves[c0]]`, … up to the index whose move is `c0`.
    cycles: Vec<u32>,
    /// The end (exclusive) of each cycle in `cycles`.
    ends: Vec<u32>,
}

impl Moves {
    /// The change of order `moves` (a permutation of `0..moves.len()`), with its cycles listed.
    pub fn new(moves: Vec<u32>) -> Self {
        let mut visited = vec![false; moves.len()];
        let (mut cycles, mut ends) = (Vec::new(), Vec::new());
        for start in 0..moves.len() {
            if visited[start] || moves[start] as usize == start {
                continue;
            }
            let mut k = start;
            loop {
                visited[k] = true;
                cycles.push(k as u32);
                k = moves[k] as usize;
                if k == start {
                    break;
                }
            }
            ends.push(cycles.len() as u32);
        }
        Self {
            moves,
            cycles,
            ends,
        }
    }

    /// Old index of what each new index holds.
    pub fn as_slice(&self) -> &[u32] {
        &self.moves
    }

    /// Whether every index keeps what it held.
    pub fn is_identity(&self) -> bool {
        self.cycles.is_empty()
    }

    /// Rearranges `data` (one entry per old index) in place so that `data[k]` afterwards holds what
    /// `data[moves[k]]` held: along each cycle `c0, c1, …, cm`, the swaps `(c0, c1), (c1, c2), …`.
    pub fn apply<T>(&self, data: &mut [T]) {
        debug_assert_eq!(data.len(), self.moves.len());
        let mut begin = 0;
        for &end in &self.ends {
            let cycle = &self.cycles[begin..end as usize];
            for pair in cycle.windows(2) {
                data.swap(pair[0] as usize, pair[1] as usize);
            }
            begin = end as usize;
        }
    }

    /// [`Self::apply`] to each of `arrays`, the arrays in parallel.
    pub fn apply_all<T: Send>(&self, arrays: Vec<&mut [T]>) {
        arrays.into_par_iter().for_each(|data| self.apply(data));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn permute_moves_each_entry_from_its_old_index() {
        let moves = Moves::new(vec![3u32, 0, 4, 1, 2, 5]);
        let mut data = ['a', 'b', 'c', 'd', 'e', 'f'];
        moves.apply(&mut data);
        assert_eq!(data, ['d', 'a', 'e', 'b', 'c', 'f']);
        let mut order = StorageOrder::identity(6);
        order.apply(&moves);
        assert!(order.ranks().is_some());
        for (k, &id) in moves.as_slice().iter().enumerate() {
            assert_eq!(order.id_at(k), id as usize);
            assert_eq!(order.index_of(order.id_at(k)), k);
        }
        assert_eq!(order.by_id(&data), ['a', 'b', 'c', 'd', 'e', 'f']);
    }

    /// On a larger permutation (long cycles, fixed points, two-cycles), every array moved by the
    /// listed cycles, alone or several in parallel, holds the gather `old[moves[k]]`.
    #[test]
    fn listed_cycles_move_every_array_as_the_gather() {
        let n = 5000;
        // A shuffle by a fixed linear congruential stream, then every 7th index put back in place.
        let mut moves: Vec<u32> = (0..n as u32).collect();
        let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
        for k in (1..n).rev() {
            x = x.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            moves.swap(k, (x >> 33) as usize % (k + 1));
        }
        let mut fixed = Vec::new();
        for k in (0..n).step_by(7) {
            let at = moves.iter().position(|&m| m as usize == k).unwrap();
            moves.swap(at, k);
            fixed.push(k);
        }
        let moves = Moves::new(moves);
        assert!(fixed.iter().all(|&k| moves.as_slice()[k] as usize == k));
        let old: Vec<u64> = (0..n as u64).map(|k| k * k + 3).collect();
        let want: Vec<u64> = moves.as_slice().iter().map(|&m| old[m as usize]).collect();
        let mut one = old.clone();
        moves.apply(&mut one);
        assert_eq!(one, want);
        let (mut a, mut b) = (old.clone(), old.clone());
        moves.apply_all(vec![&mut a[..], &mut b[..]]);
        assert_eq!((a, b), (want.clone(), want));
        assert!(!moves.is_identity());
        assert!(Moves::new((0..9).collect()).is_identity());
    }
}
