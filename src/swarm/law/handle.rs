//! A law as the engine holds it: [`Law`] wraps any [`GuidanceLaw`] together with the per-satellite states
//! of every satellite (two buffers: the states of the previous tick, read by every update, and the
//! states being written; one, updated in place, for a law that reads no neighbour's broadcast — see
//! module `state_pass`), behind one object-safe interface: the only type-erased layer. The object-safe
//! trait and the [`Law`] methods forwarding to it are generated from one list (`erased_law!`); the law's
//! capabilities (module `capability`) reach the engine through the law's `as_*` accessors, each
//! forwarded once. [`LawParameters`] carries a law's typed parameter set through the event timeline.
//!
//! The state update evaluates the satellites in the sensing grid's storage (cell) order, so that
//! consecutive updates query overlapping neighbourhoods and find their data in cache, and then places
//! each new state at its satellite's id; every state is computed on its own from the same inputs, so
//! the states are bitwise those of the plain id-order update (kept for the tests), on any thread count.
//!
//! When a tick both updates the states and evaluates the commands (sampled control, or the kinematic
//! model), the two run in one pass ([`Law::update_states_and_commands`]): each satellite's grid walk
//! is collected once and replayed to the update and the command, with the bits of the two separate
//! passes.

use std::any::Any;
use std::borrow::Cow;
use std::collections::BTreeMap;

use nalgebra::Vector3;
use rayon::prelude::*;

use super::state_pass::StatePass;
#[cfg(doc)]
use super::{Centralised, CommandsDrag, Diagnostics, Reports, TargetFormation};
use super::{
    CommandKind, GuidanceLaw, Headline, LawContext, LawError, Neighbour, OwnSample, SatelliteView,
    SwarmFacts, SwarmView,
};
use crate::swarm::storage_order::{Moves, Placement};
use crate::swarm::{Actuator, DragCommand, CHUNK};

/// Satellites whose own data a pass copies out together before evaluating them (loads by storage index, scattered
/// in memory on a large swarm, issued back to back so they overlap).
pub(crate) const OWN_BATCH: usize = 16;

thread_local! {
    /// Per-thread buffer of the satellite's collected neighbour walk in the fused pass (so the pass
    /// never allocates once the buffers have grown).
    static SENSED: std::cell::RefCell<Vec<Neighbour>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// The own data and actuators of the satellites at entries `indices` of the view's slices (at most
/// [`OWN_BATCH`]; grid slots from `first_slot` on), `None` for a removed one: copied out together, so
/// the loads (scattered in memory when the storage order strays from the cell order) issue back to
/// back and overlap.
pub(crate) fn own_batch(
    tick: &dyn TickEvaluation,
    swarm: &SwarmView<'_>,
    indices: &[u32],
    first_slot: usize,
) -> [Option<(OwnSample, Actuator)>; OWN_BATCH] {
    let mut own = [None; OWN_BATCH];
    for (k, (own, &i)) in own.iter_mut().zip(indices).enumerate() {
        *own = tick.own(swarm, i as usize, first_slot + k);
    }
    own
}

/// What the engine supplies to the fused state-and-command pass of one tick
/// ([`Law::update_states_and_commands`]).
pub(crate) trait TickEvaluation: Sync {
    /// The own data and actuator of the satellite at entry `index` of the view's slices (its grid slot
    /// is `slot`); `None` for a removed satellite.
    fn own(
        &self,
        swarm: &SwarmView<'_>,
        index: usize,
        slot: usize,
    ) -> Option<(OwnSample, Actuator)>;
    /// The context of satellite `id`'s state update.
    fn update_context(&self, id: usize, actuator: Actuator) -> LawContext;
    /// The context of satellite `id`'s command.
    fn command_context(&self, id: usize, actuator: Actuator) -> LawContext;
}

/// A typed parameter set for a law, carried by a `set-law-parameters` event. The law it reaches checks
/// that it is of its own [`GuidanceLaw::Parameters`] type.
pub struct LawParameters(Box<dyn Any + Send + Sync>);

impl LawParameters {
    /// Wraps a law's parameter set.
    pub fn new<P: Any + Send + Sync>(parameters: P) -> Self {
        Self(Box::new(parameters))
    }
}

impl std::fmt::Debug for LawParameters {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("LawParameters(..)")
    }
}

/// Writes the object-safe trait `ErasedLaw` (the face of a law with its states, implemented once, for
/// [`Stateful`]) and, for each of its methods, the [`Law`] method of the same name that forwards to it,
/// from one list: `shared` methods take `&self`, `exclusive` ones `&mut self`.
macro_rules! erased_law {
    (
        shared { $($(#[$s_doc:meta])* $s_vis:vis fn $s_name:ident($($s_arg:ident: $s_ty:ty),* $(,)?) $(-> $s_ret:ty)?;)* }
        exclusive { $($(#[$x_doc:meta])* $x_vis:vis fn $x_name:ident($($x_arg:ident: $x_ty:ty),* $(,)?) $(-> $x_ret:ty)?;)* }
    ) => {
        trait ErasedLaw: Send + Sync {
            $(fn $s_name(&self, $($s_arg: $s_ty),*) $(-> $s_ret)?;)*
            $(fn $x_name(&mut self, $($x_arg: $x_ty),*) $(-> $x_ret)?;)*
        }

        impl Law {
            $($(#[$s_doc])* $s_vis fn $s_name(&self, $($s_arg: $s_ty),*) $(-> $s_ret)? {
                self.0.$s_name($($s_arg),*)
            })*
            $($(#[$x_doc])* $x_vis fn $x_name(&mut self, $($x_arg: $x_ty),*) $(-> $x_ret)? {
                self.0.$x_name($($x_arg),*)
            })*
        }
    };
}

erased_law! {
    shared {
        /// Registry name of the law.
        pub fn name() -> &'static str;
        /// Whether the law keeps a per-satellite state (a zero-sized state means it does not, and the
        /// engine skips its update).
        pub fn is_stateful() -> bool;
        /// What the law commands.
        pub fn command_kind() -> CommandKind;
        /// See [`GuidanceLaw::prefetch`].
        pub(crate) fn prefetch(id: usize);
        /// See [`GuidanceLaw::senses_neighbours`].
        pub fn senses_neighbours() -> bool;
        /// See [`GuidanceLaw::commands_nothing`].
        pub fn commands_nothing() -> bool;
        /// See [`GuidanceLaw::check_swarm`].
        pub fn check_swarm(swarm: &SwarmFacts) -> Result<(), LawError>;
        /// See [`GuidanceLaw::fastest_rate_per_s`] \[1/s\].
        pub fn fastest_rate_per_s(mass_kg: f64) -> Option<f64>;
        /// Whether the law commands the drag area (it is a [`CommandsDrag`] law).
        pub fn commands_drag() -> bool;
        /// Every satellite's drag command from its current state ([`CommandsDrag::drag_command`]), by
        /// storage index, into `out`; `false` (and `out` untouched) for a law that does not command
        /// drag.
        pub(crate) fn drag_commands(out: &mut [Option<DragCommand>]) -> bool;
        /// Names of the per-satellite outputs ([`Diagnostics::output_names`]).
        pub fn output_names() -> &'static [&'static str];
        /// Writes every satellite's per-satellite outputs into `values` (satellite-major: satellite
        /// i's outputs at `i * k .. (i + 1) * k`, k = the number of output names), the states being
        /// stored in the storage order `placement`.
        pub(crate) fn write_outputs(values: &mut [f64], placement: Option<Placement<'_>>);
        /// Names of the law's metrics ([`Diagnostics::metric_names`]).
        pub fn metric_names() -> &'static [&'static str];
        /// The law's headline outcomes ([`Reports::headlines`]).
        pub fn headlines() -> &'static [Headline];
        /// The law's results ([`Reports::results`], serialised), the states being stored in the
        /// storage order `placement`; empty for a law without them.
        pub(crate) fn results(
            swarm: &SwarmView<'_>,
            placement: Option<Placement<'_>>,
        ) -> BTreeMap<String, serde_json::Value>;
        /// The formation the law steers to, Hill frame relative to the LVLH origin \[m\]
        /// ([`TargetFormation::target_formation_hill_m`]; `None` when the law has no fixed target
        /// points).
        pub fn target_formation_hill_m() -> Option<Vec<Vector3<f64>>>;
        /// The command of the satellite `satellite` from its current state.
        pub(crate) fn command(satellite: &SatelliteView<'_>, context: &LawContext) -> Vector3<f64>;
        /// The law itself, as `Any` (for [`Law::downcast_ref`]).
        fn law_as_any() -> &dyn Any;
        /// The states after the last update (a `Vec` of the law's state type), as `Any`.
        fn states_as_any() -> &dyn Any;
    }
    exclusive {
        /// Creates every satellite's state and initialises the law with the whole swarm (`swarm` by id),
        /// the states then being stored in the storage order `placement`.
        pub(crate) fn initialise(
            swarm: &SwarmView<'_>,
            placement: Option<Placement<'_>>,
        ) -> Result<(), LawError>;
        /// Moves the states to the storage order in which new index `k` holds old index `moves[k]`.
        pub(crate) fn permute_states(moves: &Moves);
        /// Updates every live satellite's state (removed satellites keep theirs), in the sensing grid's
        /// cell order if `in_cell_order` (see [`Law::update_states`]), else in storage order.
        fn update_states_in(
            swarm: &SwarmView<'_>,
            active: &[bool],
            context: &(dyn Fn(usize) -> LawContext + Sync),
            in_cell_order: bool,
        );
        /// One tick's state update and command evaluation in one pass over the satellites in the
        /// sensing grid's cell order: each live satellite's neighbour walk is collected once and
        /// replayed to its state update and then to its command (from the new state), so the states
        /// and the law's commands (before the actuator, which the caller applies; written by grid slot
        /// into `commands_by_slot`; zero for a removed satellite) are bitwise those of
        /// [`Self::update_states`] followed by the command evaluation, on any thread count.
        /// Returns `false`, doing nothing, when the grid does not hold every satellite (left empty by a
        /// non-finite navigation position): the caller then runs the two passes.
        pub(crate) fn update_states_and_commands(
            swarm: &SwarmView<'_>,
            tick: &dyn TickEvaluation,
            commands_by_slot: &mut [Vector3<f64>],
        ) -> bool;
        /// Replaces the law's parameters ([`GuidanceLaw::set_parameters`]; refused when they are not of
        /// the law's parameter type).
        pub(crate) fn set_parameters(parameters: &LawParameters) -> Result<(), LawError>;
        /// Records the law's metrics ([`Diagnostics::record_metrics`]) into `values`, the states being
        /// stored in the storage order `placement`.
        pub(crate) fn record_metrics(
            swarm: &SwarmView<'_>,
            values: &mut [f64],
            placement: Option<Placement<'_>>,
        );
        /// Whether the law's centralised step is due at `time_s` \[s\]
        /// ([`Centralised::centralised_due`]; never for a law without one).
        pub(crate) fn centralised_due(time_s: f64) -> bool;
        /// The law's centralised step ([`Centralised::centralised_update`]).
        pub(crate) fn centralised_update(swarm: &SwarmView<'_>) -> Result<(), LawError>;
    }
}

/// A law and its per-satellite states.
struct Stateful<L: GuidanceLaw> {
    law: L,
    /// States after the last update, by storage index (read by commands, outputs and the next update).
    current: Vec<L::State>,
    /// Buffer the next update writes into (by storage index, or by grid slot in cell order); it holds
    /// outdated states whose allocations the law may reuse ([`GuidanceLaw::update_state_into`]). Empty
    /// for a law that reads no neighbour's broadcast: its states are updated in place in `current`.
    next: Vec<L::State>,
}

impl<L: GuidanceLaw> Stateful<L> {
    /// After a buffered pass that wrote the new states into `next` by evaluation slot (the cell order
    /// of `grid`, or the storage order for `None`): each goes to its storage index in `current`,
    /// leaving the outdated one in `next` for reuse.
    fn place_new_states(&mut self, grid: Option<&crate::grid::NeighbourGrid>) {
        match grid {
            Some(grid) => {
                for (index, state) in self.current.iter_mut().enumerate() {
                    std::mem::swap(state, &mut self.next[grid.slot(index)]);
                }
            }
            None => std::mem::swap(&mut self.current, &mut self.next),
        }
    }
}

/// `states` (by storage index) by id: borrowed in the identity order, gathered otherwise.
fn states_by_id<'s, S: Clone>(states: &'s [S], placement: Option<Placement<'_>>) -> Cow<'s, [S]> {
    match placement {
        None => Cow::Borrowed(states),
        Some(p) => Cow::Owned(p.by_id(states)),
    }
}

impl<L: GuidanceLaw> ErasedLaw for Stateful<L> {
    fn name(&self) -> &'static str {
        self.law.name()
    }

    fn is_stateful(&self) -> bool {
        std::mem::size_of::<L::State>() != 0
    }

    fn command_kind(&self) -> CommandKind {
        self.law.command_kind()
    }

    fn commands_drag(&self) -> bool {
        self.law.as_commands_drag().is_some()
    }

    fn prefetch(&self, id: usize) {
        self.law.prefetch(id);
    }

    fn senses_neighbours(&self) -> bool {
        self.law.senses_neighbours()
    }

    fn commands_nothing(&self) -> bool {
        self.law.commands_nothing()
    }

    fn fastest_rate_per_s(&self, mass_kg: f64) -> Option<f64> {
        self.law.fastest_rate_per_s(mass_kg)
    }

    fn check_swarm(&self, swarm: &SwarmFacts) -> Result<(), LawError> {
        self.law.check_swarm(swarm)
    }

    fn output_names(&self) -> &'static [&'static str] {
        self.law.as_diagnostics().map_or(&[], |d| d.output_names())
    }

    fn metric_names(&self) -> &'static [&'static str] {
        self.law.as_diagnostics().map_or(&[], |d| d.metric_names())
    }

    fn headlines(&self) -> &'static [Headline] {
        self.law.as_reports().map_or(&[], |r| r.report_headlines())
    }

    fn initialise(
        &mut self,
        swarm: &SwarmView<'_>,
        placement: Option<Placement<'_>>,
    ) -> Result<(), LawError> {
        // The law sets the states by id; they are then stored in the storage order.
        let mut by_id = vec![L::State::default(); swarm.len()];
        let result = self.law.initialise(swarm, &mut by_id);
        self.current = match placement {
            None => by_id,
            Some(p) => p.by_index(&by_id),
        };
        // A law updated in place needs no second buffer.
        self.next = if self.law.reads_neighbour_broadcasts() {
            self.current.clone()
        } else {
            Vec::new()
        };
        result
    }

    fn update_states_in(
        &mut self,
        swarm: &SwarmView<'_>,
        active: &[bool],
        context: &(dyn Fn(usize) -> LawContext + Sync),
        in_cell_order: bool,
    ) {
        if !self.is_stateful() {
            return; // a memoryless law: nothing to update
        }
        let grid = swarm.grid;
        let cells = grid.cell_order();
        let in_cell_order = in_cell_order && cells.len() == self.current.len();
        let Self { law, current, next } = self;
        let law = &*law;
        // The satellite at entry `index` of the view's slices (the states' storage order too), in
        // evaluation slot `slot`.
        let evaluate = |pass: &StatePass<'_, L::State>, holder: &mut L::State, slot, index| {
            // SAFETY: every slot of the pass is evaluated once (the slots are the positions of
            // `cells` or of the storage order).
            #[allow(unsafe_code)]
            unsafe {
                if active[index] {
                    pass.update(slot, index, holder, |broadcast, out| {
                        law.update_state_into(
                            &swarm.satellite_at(index),
                            broadcast,
                            &context(index),
                            out,
                        );
                    });
                } else {
                    pass.keep(slot, index);
                }
            }
        };
        let in_place = !law.reads_neighbour_broadcasts();
        let order = in_cell_order.then_some(grid);
        let pass = if in_place {
            StatePass::in_place(current, order)
        } else {
            StatePass::buffered(current, next)
        };
        if in_cell_order {
            cells
                .par_iter()
                .enumerate()
                .with_min_len(CHUNK)
                .for_each_init(L::State::default, |holder, (slot, &index)| {
                    evaluate(&pass, holder, slot, index as usize);
                });
        } else {
            (0..active.len())
                .into_par_iter()
                .with_min_len(CHUNK)
                .for_each_init(L::State::default, |holder, index| {
                    evaluate(&pass, holder, index, index);
                });
        }
        if !in_place {
            self.place_new_states(order);
        }
    }

    fn update_states_and_commands(
        &mut self,
        swarm: &SwarmView<'_>,
        tick: &dyn TickEvaluation,
        commands_by_slot: &mut [Vector3<f64>],
    ) -> bool {
        let grid = swarm.grid;
        let cells = grid.cell_order();
        if cells.len() != self.current.len() || commands_by_slot.len() != self.current.len() {
            return false;
        }
        let in_place = !self.law.reads_neighbour_broadcasts();
        let Self { law, current, next } = self;
        let law = &*law;
        let pass = if in_place {
            StatePass::in_place(current, Some(grid))
        } else {
            StatePass::buffered(current, next)
        };
        // The new state of the satellite in grid slot `s` goes where the pass puts it, and its command
        // (before the actuator) into `commands_by_slot[s]`.
        commands_by_slot
            .par_chunks_mut(CHUNK)
            .zip(cells.par_chunks(CHUNK))
            .enumerate()
            .for_each(|(chunk, (commands, indices))| {
                // The buffer is taken out of the thread-local for the chunk, not borrowed across the
                // law's calls: a law that runs rayon work of its own may have this thread pick up
                // another chunk meanwhile, which then starts from an empty buffer instead of panicking.
                let mut sensed = SENSED.take();
                let mut holder = L::State::default();
                for (batch, (commands, indices)) in commands
                    .chunks_mut(OWN_BATCH)
                    .zip(indices.chunks(OWN_BATCH))
                    .enumerate()
                {
                    let first_slot = chunk * CHUNK + batch * OWN_BATCH;
                    let own = own_batch(tick, swarm, indices, first_slot);
                    // The previous states are read by storage index too: scattered like the own data.
                    own.iter().flatten().for_each(|(own, _)| {
                        law.prefetch(own.id);
                        pass.prefetch(own.index);
                    });
                    for (k, (out, (own, &index))) in
                        commands.iter_mut().zip(own.iter().zip(indices)).enumerate()
                    {
                        let slot = first_slot + k;
                        // SAFETY: every slot of the pass is evaluated once (the chunks and batches
                        // split the slots without overlap).
                        #[allow(unsafe_code)]
                        let Some((own, actuator)) = *own
                        else {
                            unsafe { pass.keep(slot, index as usize) };
                            *out = Vector3::zeros();
                            continue;
                        };
                        swarm.satellite_with(own).collect_neighbours(&mut sensed);
                        let satellite = swarm.satellite_sensing(own, &sensed);
                        let id = own.id;
                        // SAFETY: as above.
                        #[allow(unsafe_code)]
                        let command = unsafe {
                            pass.update(slot, own.index, &mut holder, |broadcast, state| {
                                law.update_state_into(
                                    &satellite,
                                    broadcast,
                                    &tick.update_context(id, actuator),
                                    state,
                                );
                                law.command(&satellite, state, &tick.command_context(id, actuator))
                            })
                        };
                        *out = command;
                    }
                }
                SENSED.set(sensed);
            });
        if !in_place {
            self.place_new_states(Some(grid));
        }
        true
    }

    fn command(&self, satellite: &SatelliteView<'_>, context: &LawContext) -> Vector3<f64> {
        self.law
            .command(satellite, &self.current[satellite.index()], context)
    }

    fn drag_commands(&self, out: &mut [Option<DragCommand>]) -> bool {
        let Some(drag) = self.law.as_commands_drag() else {
            return false;
        };
        if out.len() != self.current.len() {
            return false;
        }
        out.par_iter_mut()
            .with_min_len(CHUNK)
            .zip(&self.current)
            .for_each(|(o, state)| *o = drag.drag_command(state));
        true
    }

    fn set_parameters(&mut self, parameters: &LawParameters) -> Result<(), LawError> {
        let typed =
            parameters
                .0
                .downcast_ref::<L::Parameters>()
                .ok_or(LawError::ParameterType {
                    law: self.law.name(),
                    expected: std::any::type_name::<L::Parameters>(),
                })?;
        self.law.set_parameters(typed)
    }

    fn write_outputs(&self, values: &mut [f64], placement: Option<Placement<'_>>) {
        let Some(diagnostics) = self.law.as_diagnostics() else {
            return;
        };
        let k = diagnostics.output_names().len();
        if k == 0 {
            return;
        }
        for (state, row) in states_by_id(&self.current, placement)
            .iter()
            .zip(values.chunks_mut(k))
        {
            diagnostics.write_outputs(state, row);
        }
    }

    fn record_metrics(
        &mut self,
        swarm: &SwarmView<'_>,
        values: &mut [f64],
        placement: Option<Placement<'_>>,
    ) {
        if let Some(diagnostics) = self.law.as_diagnostics_mut() {
            let states = states_by_id(&self.current, placement);
            diagnostics.record_metrics(swarm, &states, values);
        }
    }

    fn centralised_due(&mut self, time_s: f64) -> bool {
        self.law
            .as_centralised()
            .is_some_and(|c| c.centralised_due(time_s))
    }

    fn centralised_update(&mut self, swarm: &SwarmView<'_>) -> Result<(), LawError> {
        self.law
            .as_centralised()
            .map_or(Ok(()), |c| c.centralised_update(swarm))
    }

    fn results(
        &self,
        swarm: &SwarmView<'_>,
        placement: Option<Placement<'_>>,
    ) -> BTreeMap<String, serde_json::Value> {
        self.law.as_reports().map_or_else(BTreeMap::new, |r| {
            r.report_json(swarm, &states_by_id(&self.current, placement))
        })
    }

    fn permute_states(&mut self, moves: &Moves) {
        let (current, next) = (&mut self.current, &mut self.next);
        rayon::join(
            || moves.apply(current),
            || {
                if !next.is_empty() {
                    moves.apply(next);
                }
            },
        );
    }

    fn target_formation_hill_m(&self) -> Option<Vec<Vector3<f64>>> {
        self.law
            .as_target_formation()
            .and_then(|t| t.target_formation_hill_m())
    }

    fn law_as_any(&self) -> &dyn Any {
        &self.law
    }

    fn states_as_any(&self) -> &dyn Any {
        &self.current
    }
}

/// A guidance law with the per-satellite states of every satellite, ready for the engine.
pub struct Law(Box<dyn ErasedLaw>);

impl Law {
    /// Wraps a law. Its states are created (as `Default`) when the engine initialises it.
    pub fn new<L: GuidanceLaw>(law: L) -> Self {
        Self(Box::new(Stateful {
            law,
            current: Vec::new(),
            next: Vec::new(),
        }))
    }

    /// The law itself, if it is of type `L` (e.g. to read a law's own results after a run).
    pub fn downcast_ref<L: GuidanceLaw>(&self) -> Option<&L> {
        self.law_as_any().downcast_ref::<L>()
    }

    /// Every satellite's law state after the last update, by storage index, if the law is of type `L`
    /// (empty before the law is initialised).
    #[cfg(test)]
    pub(crate) fn states<L: GuidanceLaw>(&self) -> Option<&[L::State]> {
        self.states_as_any()
            .downcast_ref::<Vec<L::State>>()
            .map(Vec::as_slice)
    }

    /// Every satellite's law state after the last update, by id (the states being stored in the storage
    /// order `placement`), if the law is of type `L`.
    pub(crate) fn states_by_id<L: GuidanceLaw>(
        &self,
        placement: Option<Placement<'_>>,
    ) -> Option<Vec<L::State>> {
        let states = self.states_as_any().downcast_ref::<Vec<L::State>>()?;
        Some(states_by_id(states, placement).into_owned())
    }

    /// Updates every live satellite's state (removed satellites keep theirs), evaluating the satellites
    /// in the sensing grid's cell order (`active`, `context` and the states are by entry in the view's
    /// slices, the storage order): the same bits as [`Self::update_states_in_storage_order`], faster
    /// on large swarms. Falls back to storage order when the grid does not hold every satellite (left empty
    /// by a non-finite navigation position).
    pub(crate) fn update_states(
        &mut self,
        swarm: &SwarmView<'_>,
        active: &[bool],
        context: &(dyn Fn(usize) -> LawContext + Sync),
    ) {
        self.update_states_in(swarm, active, context, true)
    }

    /// [`Self::update_states`] evaluating the satellites in storage order (the plain reference path).
    #[cfg(test)]
    pub(crate) fn update_states_in_storage_order(
        &mut self,
        swarm: &SwarmView<'_>,
        active: &[bool],
        context: &(dyn Fn(usize) -> LawContext + Sync),
    ) {
        self.update_states_in(swarm, active, context, false)
    }
}

impl std::fmt::Debug for Law {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Law({})", self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::Law;
    use crate::grid::NeighbourGrid;
    use crate::guidance::pigeon::{Pigeon, PigeonParameters, PigeonState};
    use crate::swarm::law::test_swarm::{grid_of, random_swarm, view};
    use crate::swarm::{
        Actuator, Broadcast, GuidanceLaw, LawContext, LawError, LimitKind, SatelliteView, SwarmView,
    };
    use nalgebra::Vector3;

    const PERIOD_S: f64 = 0.5;

    fn pigeon() -> Law {
        Law::new(pigeon_law())
    }

    fn pigeon_law() -> Pigeon {
        Pigeon::new(PigeonParameters {
            egalitarian_range_m: 50.0,
            hierarchical_range_m: 60.0,
            link_delay_m: 5.0,
            desired_separation_m: 30.0,
            min_separation_m: 10.0,
            ..PigeonParameters::default()
        })
        .unwrap()
    }

    /// The pigeon law without its declaration that it reads no neighbour's broadcast: the engine
    /// updates it through two buffers, the reference for the in-place update.
    struct Buffered(Pigeon);

    impl GuidanceLaw for Buffered {
        type State = PigeonState;
        type Parameters = PigeonParameters;
        fn name(&self) -> &'static str {
            "buffered-pigeon"
        }
        fn initialise(
            &mut self,
            swarm: &SwarmView<'_>,
            states: &mut [PigeonState],
        ) -> Result<(), LawError> {
            self.0.initialise(swarm, states)
        }
        fn update_state_into(
            &self,
            satellite: &SatelliteView<'_>,
            broadcast: &Broadcast<'_, PigeonState>,
            context: &LawContext,
            state: &mut PigeonState,
        ) {
            self.0
                .update_state_into(satellite, broadcast, context, state);
        }
        fn command(
            &self,
            satellite: &SatelliteView<'_>,
            state: &PigeonState,
            context: &LawContext,
        ) -> Vector3<f64> {
            self.0.command(satellite, state, context)
        }
        fn set_parameters(&mut self, parameters: &PigeonParameters) -> Result<(), LawError> {
            self.0.set_parameters(parameters)
        }
    }

    /// Every field equal, the floating-point ones bit for bit.
    fn assert_same_states(a: &[PigeonState], b: &[PigeonState], what: &str) {
        assert_eq!(a.len(), b.len());
        for (i, (x, y)) in a.iter().zip(b).enumerate() {
            assert_eq!(x, y, "{what}: satellite {i}");
            assert_eq!(
                x.local_order_parameter.to_bits(),
                y.local_order_parameter.to_bits()
            );
            assert_eq!(
                x.hierarchical_probability.to_bits(),
                y.hierarchical_probability.to_bits()
            );
        }
    }

    /// The cell-order state update gives bitwise the states of the plain id-order update, and the
    /// in-place update those of the two-buffer one: the pigeon law (a heap-backed state rebuilt in
    /// place) over a random swarm that moves between ticks (so the grid's order changes and the
    /// outdated buffers it reuses belong to other satellites), with removed and link-cut satellites,
    /// six ticks, on 1 and 2 threads.
    #[test]
    fn cell_order_state_update_equals_id_order_bitwise() {
        let n = 2000;
        let mut states = random_swarm(n);
        let masses_kg = vec![10.0; n];
        let active: Vec<bool> = (0..n).map(|i| i % 13 != 5).collect();
        let links_up: Vec<bool> = (0..n).map(|i| i % 17 != 3).collect();
        let context = |i: usize, tick: u64| {
            LawContext::new(
                tick as f64 * PERIOD_S,
                tick,
                PERIOD_S,
                Actuator::new(5.0, LimitKind::PerAxis),
                i,
                7,
            )
        };
        let mut reference = pigeon();
        let mut laws = [pigeon(), pigeon()];
        let mut buffered = Law::new(Buffered(pigeon_law()));
        for tick in 0..6u64 {
            let grid = grid_of(&states);
            let time_s = tick as f64 * PERIOD_S;
            let swarm = view(&states, &masses_kg, &active, &links_up, &grid, time_s);
            if tick == 0 {
                reference.initialise(&swarm, None).unwrap();
                buffered.initialise(&swarm, None).unwrap();
                for law in &mut laws {
                    law.initialise(&swarm, None).unwrap();
                }
            }
            reference.update_states_in_storage_order(&swarm, &active, &|i| context(i, tick));
            // The in-place update (the pigeon law's) gives the two-buffer update's states.
            buffered.update_states(&swarm, &active, &|i| context(i, tick));
            assert_same_states(
                reference.states::<Pigeon>().unwrap(),
                buffered.states::<Buffered>().unwrap(),
                &format!("tick {tick}, two buffers"),
            );
            for (threads, law) in [1, 2].into_iter().zip(&mut laws) {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                pool.install(|| law.update_states(&swarm, &active, &|i| context(i, tick)));
                assert_same_states(
                    reference.states::<Pigeon>().unwrap(),
                    law.states::<Pigeon>().unwrap(),
                    &format!("tick {tick}, {threads} thread(s)"),
                );
            }
            for s in &mut states {
                s.position_m += PERIOD_S * 5.0 * s.velocity_mps;
            }
        }
        // The comparison is not vacuous: both patterns occur and most satellites have links.
        let last = reference.states::<Pigeon>().unwrap();
        assert!(last.iter().any(|s| s.hierarchical) && last.iter().any(|s| !s.hierarchical));
        let linked = last.iter().filter(|s| !s.egalitarian().is_empty()).count();
        assert!(linked > n / 2, "{linked} satellites with links");
        assert!(last
            .iter()
            .any(|s| s.hierarchical && s.neighbours().len() > s.egalitarian().len()));
    }

    /// With an unbuilt grid (what a non-finite navigation position leaves) the update falls back to id
    /// order: nobody has neighbours, and the states are still those of the plain path.
    #[test]
    fn state_update_without_a_grid_falls_back_to_id_order() {
        let n = 300;
        let states = random_swarm(n);
        let (masses_kg, flags) = (vec![10.0; n], vec![true; n]);
        let grid = NeighbourGrid::new();
        let swarm = view(&states, &masses_kg, &flags, &flags, &grid, 0.0);
        let context = |i: usize| {
            LawContext::new(
                0.0,
                0,
                PERIOD_S,
                Actuator::new(5.0, LimitKind::PerAxis),
                i,
                7,
            )
        };
        let (mut reference, mut law) = (pigeon(), pigeon());
        reference.initialise(&swarm, None).unwrap();
        law.initialise(&swarm, None).unwrap();
        reference.update_states_in_storage_order(&swarm, &flags, &context);
        law.update_states(&swarm, &flags, &context);
        let updated = law.states::<Pigeon>().unwrap();
        assert!(updated
            .iter()
            .all(|s| s.updates == 1 && s.egalitarian().is_empty()));
        assert_same_states(reference.states::<Pigeon>().unwrap(), updated, "no grid");
    }

    /// A law that runs rayon work of its own inside its update and command gets the states and
    /// commands of the two separate passes from the fused pass, on 2 threads. (A thread waiting on such
    /// work may pick up another chunk of the pass; the pass takes its neighbour buffer out of the
    /// thread-local rather than borrowing it across the law's calls, so that cannot panic — a case
    /// this test exercises only when the scheduler happens to interleave that way.)
    #[test]
    fn fused_pass_survives_a_law_with_its_own_rayon_work() {
        use nalgebra::Vector3;
        use rayon::prelude::*;

        use super::{OwnSample, TickEvaluation};
        use crate::swarm::{Broadcast, GuidanceLaw, LawError, SatelliteView, SwarmView};

        struct Nested;
        fn inner() -> f64 {
            (0..256).into_par_iter().map(|k| k as f64).sum()
        }
        impl GuidanceLaw for Nested {
            type State = f64;
            type Parameters = ();
            fn name(&self) -> &'static str {
                "nested"
            }
            fn update_state(
                &self,
                me: &SatelliteView<'_>,
                broadcast: &Broadcast<'_, f64>,
                _: &LawContext,
            ) -> f64 {
                let mut sum = *broadcast.own() + inner();
                me.for_each_neighbour(|nb| sum += nb.distance_m);
                sum
            }
            fn command(&self, me: &SatelliteView<'_>, state: &f64, _: &LawContext) -> Vector3<f64> {
                let mut count = 0.0;
                me.for_each_neighbour(|_| count += 1.0);
                Vector3::new(*state, count, inner())
            }
            fn set_parameters(&mut self, _: &()) -> Result<(), LawError> {
                Ok(())
            }
        }
        struct Tick<'a> {
            active: &'a [bool],
        }
        impl TickEvaluation for Tick<'_> {
            fn own(
                &self,
                swarm: &SwarmView<'_>,
                id: usize,
                slot: usize,
            ) -> Option<(OwnSample, Actuator)> {
                self.active[id].then(|| {
                    (
                        OwnSample::of(swarm, id, slot),
                        Actuator::new(5.0, LimitKind::PerAxis),
                    )
                })
            }
            fn update_context(&self, id: usize, actuator: Actuator) -> LawContext {
                LawContext::new(0.0, 0, PERIOD_S, actuator, id, 7)
            }
            fn command_context(&self, id: usize, actuator: Actuator) -> LawContext {
                self.update_context(id, actuator).for_command()
            }
        }

        let n = 6000;
        let states = random_swarm(n);
        let masses_kg = vec![10.0; n];
        let active: Vec<bool> = (0..n).map(|i| i % 13 != 5).collect();
        let grid = grid_of(&states);
        let swarm = view(&states, &masses_kg, &active, &active, &grid, 0.0);
        let tick = Tick { active: &active };
        let (mut reference, mut fused) = (Law::new(Nested), Law::new(Nested));
        reference.initialise(&swarm, None).unwrap();
        fused.initialise(&swarm, None).unwrap();
        reference.update_states_in_storage_order(&swarm, &active, &|i| {
            tick.update_context(i, Actuator::new(5.0, LimitKind::PerAxis))
        });
        let expected: Vec<Vector3<f64>> = (0..n)
            .map(|i| match tick.own(&swarm, i, grid.slot(i)) {
                Some((_, actuator)) => {
                    reference.command(&swarm.satellite(i), &tick.command_context(i, actuator))
                }
                None => Vector3::zeros(),
            })
            .collect();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let mut by_slot = vec![Vector3::zeros(); n];
        assert!(pool.install(|| fused.update_states_and_commands(&swarm, &tick, &mut by_slot)));
        for i in 0..n {
            assert_eq!(expected[i], by_slot[grid.slot(i)], "satellite {i}");
        }
        assert_eq!(
            reference.states::<Nested>().unwrap(),
            fused.states::<Nested>().unwrap()
        );
    }
}
