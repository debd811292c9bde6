//! Where one pass of the state update reads each satellite's previous state and writes its new one:
//! two buffers (the previous states, read by every update through [`Broadcast`], and the buffer the new
//! states are written into by evaluation slot), or, for a law that reads only its own previous state
//! ([`GuidanceLaw::reads_neighbour_broadcasts`] `false`), one buffer updated in place, each satellite's
//! previous state swapped out into a per-thread holder before its update writes the new one.
//!
//! The pass evaluates satellites in slots (the sensing grid's cell order, or storage order), each slot
//! once, in parallel; the new states go to disjoint places because distinct slots name distinct
//! satellites, which [`StatePass::update`] checks before it writes. The writes through shared
//! references to the buffers are this module's unsafe code; it is the only place the engine's passes
//! use it.
#![allow(unsafe_code)]

use super::Broadcast;
#[cfg(doc)]
use super::GuidanceLaw;
use crate::grid::NeighbourGrid;

/// The state buffers of one pass and how its slots map to satellites.
pub(super) enum StatePass<'a, S> {
    /// New states written by slot into a second buffer; the previous ones read by storage index.
    Buffered {
        /// Previous states, by storage index.
        previous: &'a [S],
        /// The buffer receiving the new state of the satellite in each slot.
        next: SlotWrites<'a, S>,
    },
    /// New states written over the previous ones, by storage index.
    InPlace {
        /// Every state, by storage index.
        states: SlotWrites<'a, S>,
        /// The grid whose cell order the slots follow (`None`: the slots are the storage order).
        grid: Option<&'a NeighbourGrid>,
    },
}

impl<'a, S: Clone + Default> StatePass<'a, S> {
    /// A pass writing into `next` (by slot) from `previous` (by storage index).
    pub(super) fn buffered(previous: &'a [S], next: &'a mut [S]) -> Self {
        Self::Buffered {
            previous,
            next: SlotWrites::new(next),
        }
    }

    /// A pass updating `states` (by storage index) in place, its slots following the cell order of
    /// `grid` (or the storage order for `None`).
    pub(super) fn in_place(states: &'a mut [S], grid: Option<&'a NeighbourGrid>) -> Self {
        Self::InPlace {
            states: SlotWrites::new(states),
            grid,
        }
    }

    /// Hints that the previous state of the satellite at storage index `index` is about to be read.
    pub(super) fn prefetch(&self, index: usize) {
        match self {
            Self::Buffered { previous, .. } => {
                if let Some(state) = previous.get(index) {
                    crate::prefetch::read_all(state);
                }
            }
            Self::InPlace { states, .. } => {
                if index < states.len {
                    crate::prefetch::read_all(states.base.wrapping_add(index));
                }
            }
        }
    }

    /// Runs `update` with the broadcast the satellite at storage index `index`, evaluated in slot
    /// `slot`, reads and the state its new value goes into (holding an outdated state on entry; see
    /// [`GuidanceLaw::update_state_into`]), and returns what `update` returns. `holder` is the calling
    /// thread's holder of the previous state in place (any value on entry; it is left holding this
    /// satellite's previous state).
    ///
    /// # Panics
    /// If `index` is not the satellite of `slot` (see the module docs), or either is out of range.
    ///
    /// # Safety
    /// No other call of this pass may use the same `slot` while the state given to `update` lives.
    pub(super) unsafe fn update<R>(
        &self,
        slot: usize,
        index: usize,
        holder: &mut S,
        update: impl FnOnce(&Broadcast<'_, S>, &mut S) -> R,
    ) -> R {
        match self {
            Self::Buffered { previous, next } => {
                // SAFETY: the caller gives each slot to one call at a time.
                let state = unsafe { next.at(slot) };
                update(&Broadcast::new(index, previous), state)
            }
            Self::InPlace { states, grid } => {
                let state = self.own_state(states, *grid, slot, index);
                std::mem::swap(holder, state);
                update(&Broadcast::own_only(holder), state)
            }
        }
    }

    /// Keeps the previous state of the removed satellite at storage index `index` (slot `slot`).
    ///
    /// # Panics
    /// As [`Self::update`].
    ///
    /// # Safety
    /// As [`Self::update`].
    pub(super) unsafe fn keep(&self, slot: usize, index: usize) {
        match self {
            Self::Buffered { previous, next } => {
                // SAFETY: the caller gives each slot to one call at a time.
                unsafe { next.at(slot) }.clone_from(&previous[index]);
            }
            Self::InPlace { .. } => {} // it is already in place
        }
    }

    /// The in-place state of the satellite at storage index `index`, checked to be the satellite of
    /// `slot` (so that distinct slots never reach the same state).
    #[allow(clippy::mut_from_ref)] // distinct slots reach distinct states, checked here
    fn own_state<'s>(
        &self,
        states: &'s SlotWrites<'a, S>,
        grid: Option<&NeighbourGrid>,
        slot: usize,
        index: usize,
    ) -> &'s mut S {
        let owner = grid.map_or(index, |g| g.slot(index));
        assert_eq!(
            owner, slot,
            "satellite {index} is not the one in slot {slot}"
        );
        // SAFETY: the slot → index map is one-to-one (`owner == slot` above, and the grid's `slot` is a
        // function), and the caller gives each slot to one call at a time.
        unsafe { states.at(index) }
    }
}

/// A buffer written at disjoint places by the threads of one pass.
pub(super) struct SlotWrites<'a, S> {
    base: *mut S,
    len: usize,
    _buffer: std::marker::PhantomData<&'a mut [S]>,
}

// SAFETY: the buffer is borrowed mutably for the pass, and its users write each element from one
// thread at a time (see `at`); `S: Send` lets a state move between threads.
unsafe impl<S: Send> Sync for SlotWrites<'_, S> {}

impl<'a, S> SlotWrites<'a, S> {
    fn new(buffer: &'a mut [S]) -> Self {
        Self {
            base: buffer.as_mut_ptr(),
            len: buffer.len(),
            _buffer: std::marker::PhantomData,
        }
    }

    /// The element at `k`.
    ///
    /// # Panics
    /// If `k` is out of range.
    ///
    /// # Safety
    /// No other reference to element `k` may live while the returned one does.
    #[allow(clippy::mut_from_ref)] // the caller guarantees exclusive use of element `k`
    unsafe fn at(&self, k: usize) -> &mut S {
        assert!(k < self.len, "element {k} of a buffer of {}", self.len);
        // SAFETY: `k` is in range, and the caller guarantees that no other reference to it lives.
        unsafe { &mut *self.base.add(k) }
    }
}
