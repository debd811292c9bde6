//! The satellites' storage order. The engine keeps every per-satellite array (state, fleet, truth,
//! commands, the law's states, buffers) in one order of its own, the **storage order**, which it
//! re-sorts by grid cell (`simulation/resort.rs`). Ids never change: a satellite's id is its index in the
//! scenario, and everything a law, a random stream, an event or an output names is by id;
//! [`StorageOrder`] and [`Placement`] translate.
//!
//! Nothing a run computes depends on the storage order: each satellite's computations read the same
//! inputs wherever it is stored, neighbours are visited in (cell, id) order whatever the storage order
//! ([`crate::grid::NeighbourGrid::build_ranked`]), and what is summed over satellites is summed by id.

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
    pub fn apply(&mut self, moves: &[u32], visited: &mut Vec<bool>) {
        permute(&mut self.id_of, moves, visited);
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

/// Rearranges `data` in place so that `data[k]` afterwards holds what `data[moves[k]]` held (`moves` a
/// permutation of `0..data.len()`), following each cycle of the permutation with swaps; `visited` is
/// scratch.
pub(crate) fn permute<T>(data: &mut [T], moves: &[u32], visited: &mut Vec<bool>) {
    debug_assert_eq!(data.len(), moves.len());
    visited.clear();
    visited.resize(data.len(), false);
    for start in 0..data.len() {
        if visited[start] {
            continue;
        }
        let mut k = start;
        visited[k] = true;
        while moves[k] as usize != start {
            let next = moves[k] as usize;
            data.swap(k, next);
            visited[next] = true;
            k = next;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn permute_moves_each_entry_from_its_old_index() {
        let moves = [3u32, 0, 4, 1, 2, 5];
        let mut data = ['a', 'b', 'c', 'd', 'e', 'f'];
        let mut visited = Vec::new();
        permute(&mut data, &moves, &mut visited);
        assert_eq!(data, ['d', 'a', 'e', 'b', 'c', 'f']);
        let mut order = StorageOrder::identity(6);
        order.apply(&moves, &mut visited);
        assert!(order.ranks().is_some());
        for (k, &id) in moves.iter().enumerate() {
            assert_eq!(order.id_at(k), id as usize);
            assert_eq!(order.index_of(order.id_at(k)), k);
        }
        assert_eq!(order.by_id(&data), ['a', 'b', 'c', 'd', 'e', 'f']);
    }
}
