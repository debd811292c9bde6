//! The link list of a [`super::PigeonState`]: satellite ids (32-bit) held inline in the state up to
//! [`INLINE`] ids, on the heap beyond, and the membership test the law makes for every sensed
//! neighbour.
//!
//! Inline, a state's links sit next to its other fields: the update reads the previous state by the
//! satellite's storage index (scattered in memory while the engine walks the grid's cell order) and
//! finds the links in the same cache lines, with no second scattered read through a heap pointer and
//! no allocation per satellite.

/// Ids held inline; a longer list lives on the heap. 13 ids make this list 72 bytes and a
/// [`super::PigeonState`] 128.
pub(super) const INLINE: usize = 13;

/// Lists up to this length are searched by a branch-free linear scan, longer ones by bisection.
const LINEAR_SCAN_MAX: usize = 32;

/// A list of satellite ids: the first `len` of `inline`, or `heap` when longer than [`INLINE`].
#[derive(Clone, Default)]
pub(super) struct LinkIds {
    /// Number of ids.
    len: u32,
    /// The ids when `len ≤ INLINE` (the entries past `len` are stale and never read).
    inline: [u32; INLINE],
    /// The ids when `len > INLINE`.
    heap: Option<Box<[u32]>>,
}

impl LinkIds {
    /// The ids.
    pub(super) fn as_slice(&self) -> &[u32] {
        match &self.heap {
            Some(ids) => ids,
            None => &self.inline[..self.len as usize],
        }
    }

    /// Replaces the ids with `ids`, reusing the heap list when it has the same length.
    pub(super) fn assign(&mut self, ids: &[u32]) {
        self.len = u32::try_from(ids.len()).expect("a satellite id list is below 2^32 ids");
        if ids.len() <= INLINE {
            self.heap = None;
            self.inline[..ids.len()].copy_from_slice(ids);
        } else {
            match &mut self.heap {
                Some(heap) if heap.len() == ids.len() => heap.copy_from_slice(ids),
                heap => *heap = Some(ids.into()),
            }
        }
    }
}

impl PartialEq for LinkIds {
    fn eq(&self, other: &Self) -> bool {
        self.as_slice() == other.as_slice()
    }
}

impl std::fmt::Debug for LinkIds {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.as_slice()).finish()
    }
}

/// Whether the sorted ids `ids` hold satellite `id`: a linear scan without branches on the ids for a
/// short list, bisection for a long one (the same answer either way).
pub(super) fn contains(ids: &[u32], id: usize) -> bool {
    let Ok(id) = u32::try_from(id) else {
        return false;
    };
    if ids.len() <= LINEAR_SCAN_MAX {
        ids.iter().fold(false, |found, &x| found | (x == id))
    } else {
        ids.binary_search(&id).is_ok()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inline_and_heap_lists_keep_their_ids_and_compare_by_ids() {
        let mut a = LinkIds::default();
        assert!(a.as_slice().is_empty());
        let long: Vec<u32> = (0..40).map(|k| 3 * k + 1).collect();
        for len in [0, 1, INLINE - 1, INLINE, INLINE + 1, 40, 40, 3] {
            a.assign(&long[..len]);
            assert_eq!(a.as_slice(), &long[..len]);
            let mut b = LinkIds::default();
            b.assign(&long[..len]);
            assert_eq!(a, b);
        }
        // Stale inline entries past the length do not count.
        let mut c = LinkIds::default();
        c.assign(&[9, 8, 7]);
        c.assign(&[1, 4, 7]);
        assert_eq!(a, c);
    }

    /// The state the inline ids are sized for.
    #[cfg(target_pointer_width = "64")]
    #[test]
    fn a_pigeon_state_is_two_cache_lines() {
        assert_eq!(std::mem::size_of::<LinkIds>(), 72);
        assert_eq!(std::mem::size_of::<super::super::PigeonState>(), 128);
    }

    #[test]
    fn contains_equals_bisection_on_short_and_long_lists() {
        for len in [0usize, 1, 5, 31, 32, 33, 100] {
            let ids: Vec<u32> = (0..len as u32).map(|k| 2 * k + 5).collect();
            for id in 0..(2 * len + 10) {
                assert_eq!(
                    contains(&ids, id),
                    ids.binary_search(&(id as u32)).is_ok(),
                    "len {len}, id {id}"
                );
            }
            assert!(!contains(&ids, 1usize << 32 | 5));
        }
    }
}
