//! Sensing and law evaluation: the truth relative states of every satellite, the navigation states the
//! satellites believe (truth plus navigation noise), the sensing grid over them, the views a law gets,
//! and the evaluation of every satellite's command through its actuator.

use nalgebra::Vector3;
use rayon::prelude::*;

use crate::grid::{NeighbourGrid, RingOrder};
use crate::orbit::{CartesianState, LvlhFrame, RelativeStateHill};
use crate::relative::SchweighartSedwick;
use crate::swarm::actuator::Actuator;
use crate::swarm::dynamics::DynamicsModel;
use crate::swarm::law::{
    own_batch, EnvironmentView, Law, LawContext, OwnSample, SatelliteView, SharedInfo, SwarmView,
    TickEvaluation, OWN_BATCH,
};
use crate::swarm::simulation::config::{ControlTiming, Origin, SimulationConfig};
use crate::swarm::simulation::satellites::Fleet;
use crate::swarm::state::{reference_of, satellite_index, satellite_of};
use crate::swarm::storage_order::Placement;

pub(super) use crate::swarm::CHUNK;

/// The noise held over the current tick, Hill frame (each empty in a scenario without it).
pub(super) struct HeldNoise {
    /// Navigation noise: position \[m\] and velocity \[m/s\].
    pub navigation: Vec<[f64; 6]>,
    /// Process noise \[m/s^2\] (read it through `process_noise_of`).
    pub process_hill: Vec<Vector3<f64>>,
}

/// The truth states, the fleet's flags and masses gathered into id order, for a whole-swarm view while
/// the storage order is not the id order (owned by the caller, so freed with the view).
#[derive(Default)]
pub(super) struct FleetById {
    states: Vec<RelativeStateHill>,
    masses_kg: Vec<f64>,
    active: Vec<bool>,
    links_up: Vec<bool>,
}

/// The navigation view of the swarm at one evaluation: navigation states (truth plus the noise held over
/// the step; empty without navigation noise, when the views read the truth itself) and the sensing grid
/// over them. Allocated when first needed, then kept.
pub(super) struct Sensed {
    pub navigation: Vec<RelativeStateHill>,
    pub grids: SensingGrid,
}

/// The neighbour structures over the navigation positions: the sensing grid, and the ring along the
/// orbit.
pub(super) struct SensingGrid {
    pub grid: NeighbourGrid,
    /// The navigation phases along the orbit \[rad\] and the ring over them (`[sensing]
    /// ring_neighbours`; empty otherwise).
    phases_rad: Vec<f64>,
    ring: RingOrder,
    /// Whether the running law reads neighbours ([`crate::swarm::GuidanceLaw::senses_neighbours`]):
    /// when not, the grid is left empty and no ring is built.
    pub neighbours: bool,
}

impl Sensed {
    /// Empty buffers; `neighbours`: whether the law reads neighbours.
    pub fn new(neighbours: bool) -> Self {
        let mut grid = NeighbourGrid::new();
        // The law's queries repeat for the same satellites tick after tick, at a reach often well
        // below the sensing range: a neighbour list kept across the ticks answers them.
        grid.keep_neighbour_list(true);
        Self {
            navigation: Vec::new(),
            grids: SensingGrid {
                grid,
                phases_rad: Vec::new(),
                ring: RingOrder::new(),
                neighbours,
            },
        }
    }
}

impl SensingGrid {
    /// Rebuilds the grid over the positions of `states` (one per storage index) with radius
    /// `range_m`, each cell's satellites stored by `ranks` (their ids; `None`: by storage index), and
    /// returns its cell order; `None`, with the grid empty, when a position is not finite.
    pub fn grid_over(
        &mut self,
        states: &[RelativeStateHill],
        range_m: f64,
        ranks: Option<&[u32]>,
    ) -> Option<&[u32]> {
        let grid = &mut self.grid;
        rebuild_grid(grid, states, range_m, ranks).then(|| grid.cell_order())
    }
}

/// Rebuilds `grid` over the positions of `states` with radius `range_m` and each cell's satellites by
/// `ranks`; `false`, with the grid empty, when a position is not finite.
fn rebuild_grid(
    grid: &mut NeighbourGrid,
    states: &[RelativeStateHill],
    range_m: f64,
    ranks: Option<&[u32]>,
) -> bool {
    grid.build_ranked_from(
        states.len(),
        |i| states[i].position_m.into(),
        range_m,
        ranks,
    )
    .is_ok()
}

/// The six component columns (x, y, z, vx, vy, vz) of the `n` satellites in the flat state `data`.
fn satellite_components(data: &[f64], n: usize) -> [&[f64]; 6] {
    std::array::from_fn(|k| {
        let start = satellite_index(n, k, 0);
        &data[start..start + n]
    })
}

/// Calls `f` with every satellite's storage index, position and velocity (from `components`) and its
/// slot of `out`, in parallel over chunks: each chunk reads its six columns as slices, so the loop
/// carries no index arithmetic or bounds checks per satellite. `f` may report a satellite
/// (`Some((id, why))`): the report with the smallest id is returned, whatever the thread count.
fn for_each_satellite_state<T: Send, R: Send>(
    components: &[&[f64]; 6],
    out: &mut [T],
    f: impl Fn(usize, Vector3<f64>, Vector3<f64>, &mut T) -> Option<(usize, R)> + Sync,
) -> Option<(usize, R)> {
    out.par_chunks_mut(CHUNK)
        .enumerate()
        .filter_map(|(chunk, out)| {
            let start = chunk * CHUNK;
            let [x, y, z, vx, vy, vz] = components.map(|column| &column[start..start + out.len()]);
            let mut first: Option<(usize, R)> = None;
            for (k, slot) in out.iter_mut().enumerate() {
                let report = f(
                    start + k,
                    Vector3::new(x[k], y[k], z[k]),
                    Vector3::new(vx[k], vy[k], vz[k]),
                    slot,
                );
                if let Some(report) = report {
                    if first.as_ref().is_none_or(|(id, _)| report.0 < *id) {
                        first = Some(report);
                    }
                }
            }
            first
        })
        .min_by_key(|(id, _)| *id)
}

/// What the views and the right-hand side read besides the state and the law.
pub(super) struct Plant<'a> {
    pub config: &'a SimulationConfig,
    pub fleet: &'a Fleet,
    threat_warnings: &'a [bool],
    reference_model: SchweighartSedwick,
}

impl<'a> Plant<'a> {
    pub fn new(
        config: &'a SimulationConfig,
        fleet: &'a Fleet,
        threat_warnings: &'a [bool],
        reference_model: SchweighartSedwick,
    ) -> Self {
        Self {
            config,
            fleet,
            threat_warnings,
            reference_model,
        }
    }

    pub fn n(&self) -> usize {
        self.fleet.masses_kg.len()
    }

    /// The uncontrolled acceleration, ECI \[m/s^2\], of the virtual reference orbit at `position_m`,
    /// `velocity_mps` (ECI), `t_s` after the epoch, with its own physical properties.
    #[inline]
    pub fn reference_acceleration(
        &self,
        t_s: f64,
        position_m: &Vector3<f64>,
        velocity_mps: &Vector3<f64>,
    ) -> Vector3<f64> {
        self.config.dynamics.reference_acceleration_m_s2(
            &self.config.earth,
            t_s,
            position_m,
            velocity_mps,
            &self.config.reference_properties,
        )
    }

    /// The LVLH frame of the origin for a flat state at `t_s` (inertial models only): its angular
    /// velocity from the origin's uncontrolled acceleration (a member origin with its own properties).
    pub fn frame(&self, t_s: f64, data: &[f64]) -> LvlhFrame {
        let n = self.n();
        let (origin, properties) = match self.config.origin {
            Origin::VirtualReference => (reference_of(data), self.config.reference_properties),
            Origin::Member(k) => {
                let index = self.fleet.order.index_of(k);
                (satellite_of(data, n, index), self.fleet.properties(index))
            }
        };
        let origin = CartesianState::new(origin.0, origin.1);
        let accel = self.config.dynamics.reference_acceleration_m_s2(
            &self.config.earth,
            t_s,
            &origin.position_m,
            &origin.velocity_mps,
            &properties,
        );
        LvlhFrame::from_reference_with_acceleration(&origin, &accel)
    }

    /// The Hill state, relative to the LVLH origin, of an object at the EME2000 state `state` at `t_s`,
    /// placed as [`Plant::truth_relative`] places the satellites: by the origin's LVLH frame for the
    /// inertial models; for the linear and kinematic models (whose states are Hill states relative to
    /// the virtual reference) by the virtual reference's frame, less a member origin's state.
    pub fn hill_of(&self, t_s: f64, data: &[f64], state: &CartesianState) -> RelativeStateHill {
        if self.config.dynamics.is_inertial() {
            return self.frame(t_s, data).to_hill(state);
        }
        let (p, v) = reference_of(data);
        let hill = LvlhFrame::from_reference(&CartesianState::new(p, v)).to_hill(state);
        match self.config.origin {
            Origin::VirtualReference => hill,
            Origin::Member(k) => {
                let (op, ov) = satellite_of(data, self.n(), self.fleet.order.index_of(k));
                RelativeStateHill {
                    position_m: hill.position_m - op,
                    velocity_mps: hill.velocity_mps - ov,
                }
            }
        }
    }

    /// Fills `relative` with every satellite's truth state relative to the origin (Hill) at `t_s`.
    /// Returns the LVLH frame used (inertial models only).
    pub fn truth_relative(
        &self,
        t_s: f64,
        data: &[f64],
        relative: &mut [RelativeStateHill],
    ) -> Option<LvlhFrame> {
        let unchecked = |_: usize, _: &Vector3<f64>, _: &RelativeStateHill| None::<(usize, ())>;
        self.truth_relative_checked(t_s, data, relative, unchecked)
            .0
    }

    /// [`Self::truth_relative`], running `check` on each satellite in the same pass (its storage
    /// index, its position in the state — EME2000 for the inertial models, Hill otherwise — and its
    /// relative state; `Some((id, why))` to report it): also returns the report with the smallest id.
    pub fn truth_relative_checked<R: Send>(
        &self,
        t_s: f64,
        data: &[f64],
        relative: &mut [RelativeStateHill],
        check: impl Fn(usize, &Vector3<f64>, &RelativeStateHill) -> Option<(usize, R)> + Sync,
    ) -> (Option<LvlhFrame>, Option<(usize, R)>) {
        let n = self.n();
        let components = satellite_components(data, n);
        if self.config.dynamics.is_inertial() {
            let frame = self.frame(t_s, data);
            let report = for_each_satellite_state(&components, relative, |i, p, v, rel| {
                *rel = frame.to_hill(&CartesianState::new(p, v));
                check(i, &p, rel)
            });
            (Some(frame), report)
        } else {
            let (op, ov) = match self.config.origin {
                Origin::VirtualReference => (Vector3::zeros(), Vector3::zeros()),
                Origin::Member(k) => satellite_of(data, n, self.fleet.order.index_of(k)),
            };
            let report = for_each_satellite_state(&components, relative, |i, p, v, rel| {
                *rel = RelativeStateHill {
                    position_m: p - op,
                    velocity_mps: v - ov,
                };
                check(i, &p, rel)
            });
            (None, report)
        }
    }

    /// The swarm-level information at `time_s`.
    fn shared(&self, time_s: f64) -> SharedInfo {
        SharedInfo {
            time_s,
            mean_motion_rad_s: self.config.mean_motion_rad_s,
            sensing_range_m: self.config.sensing.range_m,
            reference_model: self.reference_model,
        }
    }

    /// A whole-swarm view over the navigation states, in storage order (truth plus `noise` when given,
    /// both by storage index; the truth itself, not a copy, without noise), with the sensing grid
    /// rebuilt over those positions.
    pub fn view<'s>(
        &'s self,
        time_s: f64,
        truth: &'s [RelativeStateHill],
        noise: Option<&[[f64; 6]]>,
        sensed: &'s mut Sensed,
    ) -> SwarmView<'s> {
        let fleet = self.fleet;
        let flags = (&fleet.masses_kg[..], &fleet.active[..], &fleet.links_up[..]);
        let placement = fleet.order.placement();
        let Sensed { navigation, grids } = sensed;
        let Some(noise) = noise else {
            return self.view_of_states(time_s, truth, grids, flags, placement);
        };
        navigation.resize(truth.len(), RelativeStateHill::default());
        navigation
            .par_iter_mut()
            .with_min_len(CHUNK)
            .zip(truth.par_iter().zip(noise.par_iter()))
            .for_each(|(nav, (rel, e))| {
                nav.position_m = rel.position_m + Vector3::new(e[0], e[1], e[2]);
                nav.velocity_mps = rel.velocity_mps + Vector3::new(e[3], e[4], e[5]);
            });
        self.view_of_states(time_s, navigation, grids, flags, placement)
    }

    /// A whole-swarm view of the truth states (`truth` by storage index) with every slice by id, as a
    /// law's whole-swarm hooks get it: gathered into `by_id` unless the storage order is the id order.
    pub fn view_by_id<'s>(
        &'s self,
        time_s: f64,
        truth: &'s [RelativeStateHill],
        sensed: &'s mut Sensed,
        by_id: &'s mut FleetById,
    ) -> SwarmView<'s> {
        let order = &self.fleet.order;
        if order.placement().is_none() {
            return self.view(time_s, truth, None, sensed);
        }
        by_id
            .states
            .resize(truth.len(), RelativeStateHill::default());
        by_id
            .states
            .par_iter_mut()
            .with_min_len(CHUNK)
            .enumerate()
            .for_each(|(id, state)| *state = truth[order.index_of(id)]);
        let fleet = self.fleet;
        by_id.masses_kg = order.by_id(&fleet.masses_kg);
        by_id.active = order.by_id(&fleet.active);
        by_id.links_up = order.by_id(&fleet.links_up);
        self.view_of_states(
            time_s,
            &by_id.states,
            &mut sensed.grids,
            (&by_id.masses_kg, &by_id.active, &by_id.links_up),
            None,
        )
    }

    /// The view over the navigation states `navigation`, with `fleet` (masses, active and link flags)
    /// in the same order, `placement` saying which satellite each entry is: the grid in `grids` is
    /// rebuilt over the navigation positions (ranked by id) and masked with `active && links_up`.
    fn view_of_states<'s>(
        &'s self,
        time_s: f64,
        navigation: &'s [RelativeStateHill],
        grids: &'s mut SensingGrid,
        (masses_kg, active, links_up): (&'s [f64], &'s [bool], &'s [bool]),
        placement: Option<Placement<'s>>,
    ) -> SwarmView<'s> {
        let ranks = placement.map(|p| p.id_of);
        let range_m = self.config.sensing.range_m;
        let SensingGrid {
            grid,
            phases_rad,
            ring,
            neighbours,
        } = grids;
        // A non-finite navigation position leaves the grid empty (no neighbours for this evaluation);
        // the divergence check after the segment then stops the run and names the satellite. A law
        // that reads no neighbours gets the empty grid.
        if !*neighbours {
            grid.clear();
        } else if rebuild_grid(grid, navigation, range_m, ranks) {
            grid.mask(|i| active[i] && links_up[i]);
        }
        let ring = self
            .config
            .sensing
            .ring_neighbours
            .filter(|_| *neighbours)
            .map(|each_side| {
                // The phase along the orbit ahead of the origin, `atan2(y, R + x)` (R the reference
                // orbit's radius at t = 0), ordered once per evaluation: O(N log N).
                let radius_m = self.reference_model.reference_radius_m();
                phases_rad.resize(navigation.len(), 0.0);
                phases_rad
                    .par_iter_mut()
                    .with_min_len(CHUNK)
                    .zip(navigation.par_iter())
                    .for_each(|(phase, nav)| {
                        *phase = nav.position_m.y.atan2(radius_m + nav.position_m.x);
                    });
                ring.build(phases_rad, ranks, |i| active[i] && links_up[i], each_side);
                &*ring
            });
        let view = SwarmView::new(
            navigation,
            masses_kg,
            active,
            links_up,
            grid,
            self.shared(time_s),
            EnvironmentView {
                threats: &self.config.threats,
                obstacles: &self.config.obstacles,
                threat_warnings: self.threat_warnings,
            },
        )
        .in_storage_order(placement);
        match ring {
            Some(ring) => view.with_ring(ring),
            None => view,
        }
    }

    /// The law context of the satellite at storage index `index` at tick `tick` (time `time_s`), for
    /// the state update or (with `for_command`) the command: the two draw from independent streams.
    pub fn context(&self, index: usize, time_s: f64, tick: u64, for_command: bool) -> LawContext {
        let id = self.fleet.order.id_at(index);
        self.context_with(id, self.fleet.actuators[index], time_s, tick, for_command)
    }

    /// The law context of satellite `id` with its actuator already at hand.
    fn context_with(
        &self,
        id: usize,
        actuator: Actuator,
        time_s: f64,
        tick: u64,
        for_command: bool,
    ) -> LawContext {
        let context = LawContext::new(
            time_s,
            tick,
            self.config.base_step_s(),
            actuator,
            id,
            self.config.seed,
        );
        if for_command {
            context.for_command()
        } else {
            context
        }
    }

    /// Evaluates the law for every live satellite of `view` (in storage order) and writes the applied
    /// command (Hill frame) into `applied_hill` by storage index: an acceleration through the
    /// satellite's actuator, or a velocity as commanded (kinematic model). Removed satellites get zero.
    /// Satellites are evaluated in storage order (the plain path; [`Self::commands_in_cell_order`]
    /// gives the same bits faster on large swarms).
    pub fn commands(
        &self,
        law: &Law,
        view: &SwarmView<'_>,
        tick: u64,
        applied_hill: &mut [Vector3<f64>],
    ) {
        applied_hill
            .par_iter_mut()
            .with_min_len(CHUNK)
            .enumerate()
            .for_each(|(i, applied)| *applied = self.command_of(law, view, i, tick));
    }

    /// [`Self::commands`] with the satellites evaluated in the sensing grid's storage (cell) order, so
    /// that consecutive evaluations query overlapping neighbourhoods and find their neighbours' data in
    /// cache (in a storage order far from the cell order, every neighbour query of a large swarm misses). Each command is computed on
    /// its own from the same inputs, so `applied_hill` holds exactly the bits of [`Self::commands`],
    /// whatever the thread count. `scratch` (same length as `applied_hill`) is overwritten: it receives
    /// the law's commands in cell order before they are gathered by storage index through the
    /// actuators. `commanded_hill` is empty, or (control history) receives the law's commands before
    /// the actuator by storage index. Falls back to storage order when the grid is empty (a non-finite
    /// navigation position).
    pub fn commands_in_cell_order(
        &self,
        law: &Law,
        view: &SwarmView<'_>,
        tick: u64,
        scratch: &mut [Vector3<f64>],
        applied_hill: &mut [Vector3<f64>],
        commanded_hill: &mut [Vector3<f64>],
    ) {
        let grid = view.grid;
        let order = grid.cell_order();
        if order.len() != applied_hill.len() || scratch.len() != applied_hill.len() {
            if commanded_hill.is_empty() {
                self.commands(law, view, tick, applied_hill);
            } else {
                self.commands_with_history(law, view, tick, commanded_hill, applied_hill);
            }
            return;
        }
        // Each batch first copies out its satellites' own data (loads by storage index, scattered in memory on a
        // large swarm, issued back to back so they overlap) and hints the law at them (its own data by
        // id is scattered too), then evaluates the laws on the copies.
        let evaluation = PlantTick {
            plant: self,
            time_s: view.shared.time_s,
            tick,
        };
        scratch
            .par_chunks_mut(CHUNK)
            .zip(order.par_chunks(CHUNK))
            .enumerate()
            .for_each(|(chunk, (outs, indices))| {
                for (batch, (outs, indices)) in outs
                    .chunks_mut(OWN_BATCH)
                    .zip(indices.chunks(OWN_BATCH))
                    .enumerate()
                {
                    let first_slot = chunk * CHUNK + batch * OWN_BATCH;
                    let own = own_batch(&evaluation, view, indices, first_slot);
                    own.iter()
                        .flatten()
                        .for_each(|(own, _)| law.prefetch(own.id));
                    for (out, own) in outs.iter_mut().zip(own) {
                        *out = own.map_or_else(Vector3::zeros, |(own, actuator)| {
                            self.commanded(law, &view.satellite_with(own), actuator, tick)
                        });
                    }
                }
            });
        self.actuate_by_index(view, scratch, applied_hill, commanded_hill);
    }

    /// The state update of a stateful law and the commands of one tick in one pass
    /// ([`Law::update_states_and_commands`]): the states and the applied commands are bitwise those of
    /// [`Law::update_states`] followed by [`Self::commands_in_cell_order`]. `scratch` (same length as
    /// `applied_hill`) is overwritten; `commanded_hill` as in [`Self::commands_in_cell_order`].
    /// Returns `false`, doing nothing, when the grid does not hold every satellite (a non-finite
    /// navigation position): the caller then runs the two passes.
    pub fn states_and_commands_in_cell_order(
        &self,
        law: &mut Law,
        view: &SwarmView<'_>,
        tick: u64,
        scratch: &mut [Vector3<f64>],
        applied_hill: &mut [Vector3<f64>],
        commanded_hill: &mut [Vector3<f64>],
    ) -> bool {
        let evaluation = PlantTick {
            plant: self,
            time_s: view.shared.time_s,
            tick,
        };
        if scratch.len() != applied_hill.len()
            || !law.update_states_and_commands(view, &evaluation, scratch)
        {
            return false;
        }
        self.actuate_by_index(view, scratch, applied_hill, commanded_hill);
        true
    }

    /// Writes into `applied_hill[i]` the law's command in `commands_by_slot` of the grid slot of the
    /// satellite at storage index `i` through its actuator ([`Self::through_actuator`]), and into
    /// `commanded_hill[i]` the command itself unless `commanded_hill` is empty (no control history).
    fn actuate_by_index(
        &self,
        view: &SwarmView<'_>,
        commands_by_slot: &[Vector3<f64>],
        applied_hill: &mut [Vector3<f64>],
        commanded_hill: &mut [Vector3<f64>],
    ) {
        let actuators = &self.fleet.actuators;
        if commanded_hill.is_empty() {
            applied_hill
                .par_iter_mut()
                .with_min_len(CHUNK)
                .enumerate()
                .for_each(|(i, applied)| {
                    let command = commands_by_slot[view.grid.slot(i)];
                    *applied = self.through_actuator(actuators[i], command);
                });
        } else {
            applied_hill
                .par_iter_mut()
                .zip(commanded_hill.par_iter_mut())
                .with_min_len(CHUNK)
                .enumerate()
                .for_each(|(i, (applied, commanded))| {
                    *commanded = commands_by_slot[view.grid.slot(i)];
                    *applied = self.through_actuator(actuators[i], *commanded);
                });
        }
    }

    /// [`Self::commands`] that also writes the law's commands before the actuator into
    /// `commanded_hill` (by storage index; zero for a removed satellite): the control history's plain
    /// path, for continuous control (evaluated at a recording time) and a swarm whose grid could not
    /// be built.
    pub fn commands_with_history(
        &self,
        law: &Law,
        view: &SwarmView<'_>,
        tick: u64,
        commanded_hill: &mut [Vector3<f64>],
        applied_hill: &mut [Vector3<f64>],
    ) {
        applied_hill
            .par_iter_mut()
            .zip(commanded_hill.par_iter_mut())
            .with_min_len(CHUNK)
            .enumerate()
            .for_each(|(i, (applied, commanded))| {
                let actuator = self.fleet.actuators[i];
                *commanded = if self.fleet.active[i] {
                    self.commanded(law, &view.satellite_at(i), actuator, tick)
                } else {
                    Vector3::zeros()
                };
                *applied = self.through_actuator(actuator, *commanded);
            });
    }

    /// The applied command of the satellite at storage index `index` (zero for a removed satellite).
    fn command_of(&self, law: &Law, view: &SwarmView<'_>, index: usize, tick: u64) -> Vector3<f64> {
        if !self.fleet.active[index] {
            return Vector3::zeros();
        }
        self.applied(
            law,
            &view.satellite_at(index),
            self.fleet.actuators[index],
            tick,
        )
    }

    /// The applied command of the live satellite `satellite` with actuator `actuator`: the law's command
    /// through the actuator, or the commanded velocity (kinematic model).
    fn applied(
        &self,
        law: &Law,
        satellite: &SatelliteView<'_>,
        actuator: Actuator,
        tick: u64,
    ) -> Vector3<f64> {
        self.through_actuator(actuator, self.commanded(law, satellite, actuator, tick))
    }

    /// The law's command of the live satellite `satellite` with actuator `actuator` (in its context),
    /// before the actuator.
    fn commanded(
        &self,
        law: &Law,
        satellite: &SatelliteView<'_>,
        actuator: Actuator,
        tick: u64,
    ) -> Vector3<f64> {
        let context = self.context_with(
            satellite.id(),
            actuator,
            satellite.shared().time_s,
            tick,
            true,
        );
        law.command(satellite, &context)
    }

    /// The applied command of a law's command `command`: through the actuator `actuator`, or the
    /// commanded velocity itself (kinematic model).
    fn through_actuator(&self, actuator: Actuator, command: Vector3<f64>) -> Vector3<f64> {
        if matches!(self.config.dynamics, DynamicsModel::Kinematic) {
            command
        } else {
            actuator.apply(&command)
        }
    }

    /// Whether commands are held between ticks (sampled mode).
    pub fn sampled(&self) -> bool {
        matches!(self.config.control, ControlTiming::Sampled { .. })
    }
}

/// The engine's side of one tick's evaluation at time `time_s` (the view's time) \[s\], tick `tick`.
struct PlantTick<'p> {
    plant: &'p Plant<'p>,
    time_s: f64,
    tick: u64,
}

impl TickEvaluation for PlantTick<'_> {
    fn own(
        &self,
        swarm: &SwarmView<'_>,
        index: usize,
        slot: usize,
    ) -> Option<(OwnSample, Actuator)> {
        let fleet = self.plant.fleet;
        fleet.active[index].then(|| (OwnSample::of(swarm, index, slot), fleet.actuators[index]))
    }

    fn update_context(&self, id: usize, actuator: Actuator) -> LawContext {
        self.plant
            .context_with(id, actuator, self.time_s, self.tick, false)
    }

    fn command_context(&self, id: usize, actuator: Actuator) -> LawContext {
        self.plant
            .context_with(id, actuator, self.time_s, self.tick, true)
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::run::build_simulation;
    use crate::scenario::Scenario;

    /// The fused pass of a stateful law (one grid walk per satellite, replayed to the state update and
    /// the command) gives exactly the states and applied commands of the two separate passes, at 1 and
    /// 3 threads, over several ticks (so the states it reads are its own earlier outputs): pigeon under
    /// J2 with sampled control and removed and link-cut satellites, and equilibrium shaping in the
    /// kinematic model with continuous control (the scenario `es-e0`).
    #[test]
    fn fused_state_and_command_pass_equals_the_two_passes_bitwise() {
        use crate::guidance::equilibrium_shaping::EquilibriumShaping;
        use crate::guidance::pigeon::Pigeon;
        let pigeon = "name = \"t\"\nseed = 3\nduration_s = 100.0\nrecord_interval_s = 100.0\n\
                      [dynamics]\nmodel = \"j2\"\nintegrator = \"rk4\"\nstep_s = 0.05\n\
                      [reference]\naltitude_m = 600e3\ninclination_deg = 98.0\n\
                      [control]\nmode = \"sampled\"\nperiod_s = 0.05\n\
                      [satellites]\ncount = 3000\nmass_kg = 10.0\nradius_m = 0.05\n\
                      max_accel_mps2 = 5.0\naccel_limit = \"per-axis\"\n\
                      initial = { distribution = \"sphere\", radius_m = 400.0 }\n\
                      [sensing]\nrange_m = 60.0\n[law]\nname = \"pigeon\"\nswitching = true\n\
                      egalitarian_range_m = 50.0\nhierarchical_range_m = 60.0\n\
                      [output]\ntrajectory = false\n";
        fused_equals_two_passes::<Pigeon>(pigeon, true, 0, 4);
        // The threat comes within the satellites' 10 m reach after about 20 s (400 steps).
        let es = include_str!("../../../scenarios/es-e0.toml");
        fused_equals_two_passes::<EquilibriumShaping>(es, false, 380, 80);
    }

    /// See [`fused_state_and_command_pass_equals_the_two_passes_bitwise`]: `ticks` ticks of the
    /// scenario `text` whose law is `L` after `warmup` steps, with every 7th satellite removed and every
    /// 11th (from the 4th) link-cut when `faults`.
    fn fused_equals_two_passes<L: crate::swarm::GuidanceLaw>(
        text: &str,
        faults: bool,
        warmup: usize,
        ticks: u64,
    ) where
        L::State: PartialEq + std::fmt::Debug,
    {
        let scenario = Scenario::from_toml(text, "t", Path::new(".")).unwrap();
        let prepare = || {
            let mut sim = build_simulation(&scenario).unwrap();
            let n = sim.satellites.fleet.active.len();
            if faults {
                for i in (0..n).step_by(7) {
                    sim.satellites.fleet.active[i] = false;
                }
                for i in (3..n).step_by(11) {
                    sim.satellites.fleet.links_up[i] = false;
                }
            }
            sim
        };
        let mut reference = prepare();
        let mut fused = [prepare(), prepare()];
        for _ in 0..warmup {
            reference.step().unwrap();
            for sim in &mut fused {
                sim.step().unwrap();
            }
        }
        let mut moved = false;
        for tick in 0..ticks {
            let n = reference.satellites.fleet.active.len();
            let mut expected = vec![Vector3::zeros(); n];
            {
                let sim = &mut reference;
                let plant = Plant::new(
                    &sim.config,
                    &sim.satellites.fleet,
                    &sim.timeline.threat_warnings,
                    sim.reference_model,
                );
                let view = plant.view(
                    sim.clock.time_s,
                    &sim.satellites.truth,
                    None,
                    &mut sim.sensed,
                );
                let time_s = view.shared.time_s;
                sim.law
                    .update_states(&view, &sim.satellites.fleet.active, &|i| {
                        plant.context(i, time_s, tick, false)
                    });
                let mut scratch = vec![Vector3::zeros(); n];
                plant.commands_in_cell_order(
                    &sim.law,
                    &view,
                    tick,
                    &mut scratch,
                    &mut expected,
                    &mut [],
                );
            }
            moved |= expected.iter().any(|u| u.norm() > 0.0);
            for (threads, sim) in [1, 3].into_iter().zip(&mut fused) {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                let plant = Plant::new(
                    &sim.config,
                    &sim.satellites.fleet,
                    &sim.timeline.threat_warnings,
                    sim.reference_model,
                );
                let view = plant.view(
                    sim.clock.time_s,
                    &sim.satellites.truth,
                    None,
                    &mut sim.sensed,
                );
                let (mut scratch, mut applied) =
                    (vec![Vector3::zeros(); n], vec![Vector3::zeros(); n]);
                let ran = pool.install(|| {
                    plant.states_and_commands_in_cell_order(
                        &mut sim.law,
                        &view,
                        tick,
                        &mut scratch,
                        &mut applied,
                        &mut [],
                    )
                });
                assert!(ran);
                for (a, b) in expected.iter().zip(&applied) {
                    for k in 0..3 {
                        assert_eq!(
                            a[k].to_bits(),
                            b[k].to_bits(),
                            "tick {tick}, {threads} threads"
                        );
                    }
                }
                assert_eq!(
                    reference.law.states::<L>().unwrap(),
                    sim.law.states::<L>().unwrap(),
                    "tick {tick}, {threads} threads"
                );
            }
            // Move on: one step of each (the commands they hold are their own, equal as checked).
            reference.step().unwrap();
            for sim in &mut fused {
                sim.step().unwrap();
            }
        }
        assert!(moved, "no satellite was commanded");
    }

    /// Cell-order evaluation gives exactly the bits of the plain id-order evaluation, at 1 and 3
    /// threads, on a swarm with removed and link-cut satellites and a stateful neighbour law (pigeon,
    /// three neighbour loops) and a memoryless one (bifurcating); and the engine's masked grid gives
    /// the bits of an unmasked one, whose views check every neighbour's flags.
    #[test]
    fn cell_order_commands_equal_id_order_bitwise() {
        for law in [
            "name = \"bifurcating\"\nk_f_kg_per_m_s2 = 0.003\nk_c_kg_per_s2 = 0.25\n\
             k_v_kg_per_s = 2000.0\navoidance_radius_m = 60.0\na = 1.0\nb = 1.0\nradius_m = 300.0\n\
             mu_m = -5000.0",
            "name = \"pigeon\"\nswitching = true\negalitarian_range_m = 50.0\nhierarchical_range_m = 60.0",
        ] {
            let text = format!(
                "name = \"t\"\nseed = 3\nduration_s = 100.0\nrecord_interval_s = 100.0\n\
                 [dynamics]\nmodel = \"j2\"\nintegrator = \"rk4\"\nstep_s = 0.05\n\
                 [reference]\naltitude_m = 600e3\ninclination_deg = 98.0\n\
                 [control]\nmode = \"sampled\"\nperiod_s = 0.05\n\
                 [satellites]\ncount = 3000\nmass_kg = 100.0\nradius_m = 0.5\n\
                 initial = {{ distribution = \"sphere\", radius_m = 400.0 }}\n\
                 [sensing]\nrange_m = 60.0\n[law]\n{law}\n[output]\ntrajectory = false\n"
            );
            let scenario = Scenario::from_toml(&text, "t", Path::new(".")).unwrap();
            let mut sim = build_simulation(&scenario).unwrap();
            for _ in 0..3 {
                sim.step().unwrap();
            }
            for i in (0..3000).step_by(7) {
                sim.satellites.fleet.active[i] = false;
            }
            for i in (3..3000).step_by(11) {
                sim.satellites.fleet.links_up[i] = false;
            }
            let plant = Plant::new(
                &sim.config,
                &sim.satellites.fleet,
                &sim.timeline.threat_warnings,
                sim.reference_model,
            );
            let view = plant.view(sim.clock.time_s, &sim.satellites.truth, None, &mut sim.sensed);
            let n = plant.n();
            let mut plain = vec![Vector3::zeros(); n];
            plant.commands(&sim.law, &view, 5, &mut plain);
            assert!(plain.iter().any(|u| u.norm() > 0.0));
            assert!(view.grid.is_masked());
            let axis = |a: usize| -> Vec<f64> {
                view.relative_states
                    .iter()
                    .map(|s| s.position_m[a])
                    .collect()
            };
            let mut unmasked_grid = NeighbourGrid::new();
            unmasked_grid
                .build_ranked(
                    &axis(0),
                    &axis(1),
                    &axis(2),
                    sim.config.sensing.range_m,
                    sim.satellites.fleet.order.ranks(),
                )
                .unwrap();
            let unmasked = view.with_grid(&unmasked_grid);
            let mut checked = vec![Vector3::zeros(); n];
            plant.commands(&sim.law, &unmasked, 5, &mut checked);
            for (a, b) in plain.iter().zip(&checked) {
                for k in 0..3 {
                    assert_eq!(a[k].to_bits(), b[k].to_bits());
                }
            }
            for threads in [1, 3] {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                let (mut scratch, mut ordered) = (vec![Vector3::zeros(); n], vec![Vector3::zeros(); n]);
                pool.install(|| {
                    plant.commands_in_cell_order(
                        &sim.law,
                        &view,
                        5,
                        &mut scratch,
                        &mut ordered,
                        &mut [],
                    )
                });
                for (a, b) in plain.iter().zip(&ordered) {
                    for k in 0..3 {
                        assert_eq!(a[k].to_bits(), b[k].to_bits());
                    }
                }
            }
        }
    }
}
