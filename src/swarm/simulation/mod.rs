//! The simulation: the swarm's state, its satellites, the law with its per-satellite states, the
//! environment and the event timeline, and the loop that advances them.
//!
//! | module | holds |
//! | --- | --- |
//! | `config` | what a simulation is built from, its typed errors, the law/timing fit check, run totals |
//! | `sensing` | truth and navigation relative states, the sensing grid, the law's views, command evaluation |
//! | `propagation` | one segment: the coupled swarm ODE (continuous) or every satellite alone (sampled) |
//! | `scheduler` | the run loop: segments between ticks, records, events and the end; [`Simulation::advance_to`] |
//! | `timeline` | the timed events that fall due, the condition events that fire, their actions and log |
//! | `conditions` | the values the condition events test at a tick |
//! | `monitors` | truth checks after every segment: divergence, separation, threat approach, obstacle clearance |
//! | `snapshots` | what a recorder receives at every recording time |
//! | `resort` | the periodic re-sort of the satellites' storage order by grid cell (sampled control) |
//!
//! Control timing (see `DESIGN.md`):
//! * [`ControlTiming::Continuous`]: the law's command is evaluated inside the integrator's right-hand
//!   side and the swarm (reference, satellites and delta-v ledgers) is integrated as one coupled system;
//!   law states are updated once per integration step, outside the right-hand side;
//! * [`ControlTiming::Sampled`]: at every control tick the law states are updated and the command is
//!   evaluated and held (zero-order hold, constant in the dynamics frame: ECI for inertial truth, Hill for
//!   the linear models); between ticks every satellite is propagated on its own, in parallel.
//!
//! Per tick: sense → update law states → command → actuate → integrate → monitor → record.
//!
//! Determinism: every per-satellite computation is independent and written to its own slot; reductions
//! are serial; every random draw comes from [`crate::random`] keyed by (seed, purpose, satellite, tick).
//! Results are therefore bitwise identical for any number of threads.
//!
//! Storage order: every per-satellite array is kept in the engine's storage order
//! (`swarm/storage_order.rs`),
//! re-sorted by grid cell in sampled control; ids, random streams, events, laws and outputs are by id,
//! and no result depends on the storage order.

mod conditions;
mod config;
mod monitors;
mod propagation;
mod resort;
mod satellites;
mod scheduler;
mod sensing;
mod snapshots;
mod timeline;
mod tracked;

use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex};

use nalgebra::Vector3;

pub use config::{
    check_law_fits, ControlTiming, Divergence, Origin, RunTotals, SatelliteInit, Sensing, SimError,
    SimulationConfig, TIME_EPSILON,
};
pub use tracked::{EnvironmentObject, TrackedObject, TrackedOrbit};

use crate::conjunction::ConjunctionMonitor;
use crate::environment::ApproachMonitor;
use crate::integrate::Stepper;
use crate::orbit::{CartesianState, LvlhFrame, RelativeStateHill};
use crate::relative::SchweighartSedwick;
use crate::swarm::dynamics::DynamicsModel;
use crate::swarm::events::{ConditionTest, Event, EventAction, Selection, Trigger};
use crate::swarm::law::{GuidanceLaw, Law, SwarmView};
use crate::swarm::state::SwarmState;
use crate::swarm::storage_order::Placement;
use monitors::{divergence_check, LiveMetrics, Monitors, OriginStates};
use propagation::{SampledBuffers, StageScratch};
use resort::RESORT_PERIOD_TICKS;
use satellites::Satellites;
use scheduler::Clock;
use sensing::{FleetById, HeldNoise, Plant, Sensed};
use timeline::Timeline;

/// How a segment's integration is done: the coupled system (continuous) or satellites alone (sampled).
/// Only the buffers of the chosen mode are allocated.
enum Integration {
    Coupled {
        stepper: Box<Stepper>,
        scratch: Box<Mutex<StageScratch>>,
    },
    Sampled(SampledBuffers),
}

impl Integration {
    /// Each satellite's remembered step size (adaptive sampled propagation), by storage index.
    fn step_guesses_s(&mut self) -> Option<&mut Vec<Option<f64>>> {
        match self {
            Integration::Sampled(SampledBuffers::Generic { step_guesses_s, .. }) => {
                Some(step_guesses_s)
            }
            _ => None,
        }
    }
}

/// Cumulative wall-clock time per stage of the engine since the simulation was built \[s\]: what
/// [`Simulation::stage_timings`] returns and `summary.json` writes as `timing`. Measured with one
/// `Instant` pair per stage per segment; it measures the machine, so it never enters campaign outcomes.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct StageTimings {
    /// Truth relative states after each segment, navigation states and the sensing grid \[s\].
    pub sensing_s: f64,
    /// Law: centralised step, state updates, commands through the actuators, held commands \[s\].
    pub law_s: f64,
    /// Integration of the reference orbit and every satellite over the segments \[s\].
    pub propagation_s: f64,
    /// Truth monitors: divergence, minimum separation and collisions, threat and obstacle approach,
    /// conjunctions \[s\].
    pub monitors_s: f64,
    /// The conjunction monitor alone, a part of `monitors_s` \[s\] (0 without one).
    pub conjunctions_s: f64,
    /// Snapshots handed to the recorder (metrics, five elements, law metrics and outputs) \[s\].
    pub recording_s: f64,
    /// How the satellites were propagated: the fused kernel and the force set it covers, the generic
    /// per-satellite stepper, or the coupled swarm ODE (continuous control).
    pub propagation_path: &'static str,
    /// How many times the sensing grid made its neighbour list (the law's queries at a reach well
    /// below the sensing range answered from a list kept across ticks, made again once a satellite
    /// has moved an eighth of that reach; 0: every query walked the grid's cells).
    pub neighbour_lists_made: u64,
    /// How many of the separation monitor's updates searched the whole live swarm (the others
    /// searched only the satellites its motion bound could not rule out).
    pub separation_full_searches: u64,
    /// How many of the separation monitor's updates searched only those candidates.
    pub separation_narrow_searches: u64,
}

impl StageTimings {
    /// The sum of the stages \[s\].
    pub fn total_s(&self) -> f64 {
        self.sensing_s + self.law_s + self.propagation_s + self.monitors_s + self.recording_s
    }
}

/// A swarm simulation: state, satellites, law, environment, events, and the loop that advances them.
/// Every per-satellite array below, the law's states included, is in storage order (`fleet.order`).
pub struct Simulation {
    config: SimulationConfig,
    state: SwarmState,
    /// Where the run loop is: time, ticks, base steps, recordings.
    clock: Clock,
    /// The per-satellite table: fleet, truth relative states, applied and held commands.
    satellites: Satellites,
    law: Law,
    /// The pending events and the ground warnings in force.
    timeline: Timeline,
    /// The noise held over the current tick.
    noise: HeldNoise,
    /// The tick's sensing buffers (navigation states and grid).
    sensed: Sensed,
    /// The law's drag commands of the tick, by storage index (empty when no satellite has drag
    /// attitudes).
    drag_commands: Vec<Option<crate::swarm::DragCommand>>,
    /// The swarm's mean altitude over its first and its latest orbit (runs with drag attitudes).
    drag_altitude: AltitudeWindow,
    /// The truth monitors' buffers: separation, threat approach and obstacle clearance.
    monitors: Monitors,
    integration: Integration,
    reference_stepper: Stepper,
    /// The real objects' inertial states (truth-propagated ones) and their stepper.
    tracked: tracked::TrackedStates,
    /// Ticks between re-sorts of the storage order (0: never; sampled control only).
    resort_period_ticks: u64,
    /// A flag another thread (a signal handler) may set to stop the run between segments.
    cancel: Option<Arc<AtomicBool>>,
    totals: RunTotals,
    timings: StageTimings,
    /// SS model of the reference orbit at t = 0, given to laws ([`crate::swarm::SharedInfo::reference_model`]).
    reference_model: SchweighartSedwick,
}

impl Simulation {
    /// Lets `flag` stop the run: the scheduler polls it after every segment (once that segment's
    /// monitors, events and record are done) and, once it is set, returns [`SimError::Interrupted`] with
    /// the time reached. The recorder has then received every snapshot up to that time.
    pub fn set_cancel_flag(&mut self, flag: Arc<AtomicBool>) {
        self.cancel = Some(flag);
    }

    /// Builds a simulation. The satellites' initial states are relative to the reference orbit at t = 0.
    /// Checks that the setup can run: at least one satellite, a valid origin, events inside the run and
    /// naming satellites and threats that exist, a law whose commands the dynamics can follow, steps and
    /// periods short enough for the law's fastest rate.
    pub fn new(
        config: SimulationConfig,
        satellites: &[SatelliteInit],
        law: Law,
        events: Vec<Event>,
    ) -> Result<Self, SimError> {
        Self::assemble(config, satellites, law, events)?.start()
    }

    /// [`Simulation::new`] from satellites the caller no longer needs: they are dropped once their
    /// columns are built, before the law is initialised (a million satellites' descriptions are 168 MB,
    /// not held at the set-up's peak).
    pub(crate) fn from_owned(
        config: SimulationConfig,
        satellites: Vec<SatelliteInit>,
        law: Law,
        events: Vec<Event>,
    ) -> Result<Self, SimError> {
        let sim = Self::assemble(config, &satellites, law, events)?;
        drop(satellites);
        sim.start()
    }

    /// The checks and columns of [`Simulation::new`], before the truth, the events at t = 0 and the law's
    /// initialisation ([`Simulation::start`]).
    fn assemble(
        config: SimulationConfig,
        satellites: &[SatelliteInit],
        law: Law,
        events: Vec<Event>,
    ) -> Result<Self, SimError> {
        let n = satellites.len();
        if n == 0 {
            return Err(SimError::NoSatellites);
        }
        if !(config.sensing.range_m.is_finite() && config.sensing.range_m > 0.0) {
            return Err(SimError::SensingRange {
                range_m: config.sensing.range_m,
            });
        }
        if let Origin::Member(k) = config.origin {
            if k >= n {
                return Err(SimError::OriginMember {
                    member: k,
                    count: n,
                });
            }
        }
        check_events(&events, &config, n)?;
        check_drag_attitudes(&config, satellites)?;
        if config.process_noise_m_s2 != 0.0
            && (matches!(config.dynamics, DynamicsModel::Kinematic)
                || !(config.process_noise_m_s2 > 0.0 && config.process_noise_m_s2.is_finite()))
        {
            return Err(SimError::ProcessNoise {
                sigma_m_s2: config.process_noise_m_s2,
                dynamics: config.dynamics.name(),
            });
        }
        let tracks_threats = events.iter().any(|e| {
            matches!(
                &e.trigger,
                Trigger::Condition(c) if matches!(c.test, ConditionTest::ThreatWithin { .. })
            )
        });
        let senses_neighbours = law.senses_neighbours();
        let mut state = SwarmState::zeros(n);
        state.set_reference(&config.reference.position_m, &config.reference.velocity_mps);
        if let Some(forces) = config.dynamics.forces() {
            if forces.earth() != config.earth {
                return Err(SimError::ForcesEarth {
                    forces_mu_m3_s2: forces.earth().mu_m3_s2,
                    config_mu_m3_s2: config.earth.mu_m3_s2,
                });
            }
        }
        let reference_frame = accelerated_frame_at_start(
            &config.dynamics,
            &config.earth,
            &config.reference,
            &config.reference_properties,
        );
        for (i, sat) in satellites.iter().enumerate() {
            if config.dynamics.is_inertial() {
                let s = reference_frame.from_hill(&sat.relative_state);
                state.set_satellite(i, &s.position_m, &s.velocity_mps);
            } else {
                state.set_satellite(
                    i,
                    &sat.relative_state.position_m,
                    &sat.relative_state.velocity_mps,
                );
            }
        }
        let reference_model = reference_model(&config, &reference_frame, satellites);
        let integration = match config.control {
            ControlTiming::Continuous => Integration::Coupled {
                stepper: Box::new(Stepper::new(
                    config.integrator,
                    state.as_slice().len(),
                    config.tolerances,
                    config.step_s,
                )),
                scratch: Box::new(Mutex::new(StageScratch::new(n))),
            },
            ControlTiming::Sampled { .. } => Integration::Sampled(SampledBuffers::new(
                &config.dynamics,
                config.integrator,
                config.tolerances,
                config.step_s,
                n,
            )),
        };
        let satellites_table = Satellites::new(satellites);
        let min_mass = satellites_table
            .fleet
            .masses_kg
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min);
        check_law_fits(&law, &config, min_mass)?;
        Ok(Self {
            reference_stepper: Stepper::new(config.integrator, 6, config.tolerances, config.step_s),
            tracked: tracked::TrackedStates::new(&config),
            integration,
            state,
            clock: Clock::start(),
            satellites: satellites_table,
            law,
            timeline: Timeline::new(events, config.threats.len()),
            // Buffers a scenario's features need, and only then (a million satellites: 120 bytes each).
            noise: HeldNoise {
                navigation: if config.sensing.has_navigation_noise() {
                    vec![[0.0; 6]; n]
                } else {
                    Vec::new()
                },
                process_hill: if config.process_noise_m_s2 > 0.0 {
                    vec![Vector3::zeros(); n]
                } else {
                    Vec::new()
                },
            },
            sensed: Sensed::new(senses_neighbours),
            drag_commands: if satellites.iter().any(|s| s.drag_attitudes.is_some()) {
                vec![None; n]
            } else {
                Vec::new()
            },
            drag_altitude: AltitudeWindow::new(
                (std::f64::consts::TAU / config.mean_motion_rad_s / config.base_step_s()).round()
                    as usize,
            ),
            monitors: Monitors {
                live: LiveMetrics::new(),
                approach: ApproachMonitor::new(n, config.threats.len(), config.obstacles.len()),
                truth_previous: if config.threats.is_empty() && config.obstacles.is_empty() {
                    Vec::new()
                } else {
                    vec![RelativeStateHill::default(); n]
                },
                conjunctions: None,
                origin_previous: OriginStates::default(),
                diverged: None,
                tracks_threats,
                threat_window_m: None,
                conjunctions_seen: 0,
            },
            resort_period_ticks: RESORT_PERIOD_TICKS,
            cancel: None,
            totals: RunTotals {
                time_s: 0.0,
                satellite_steps: 0,
                min_separation_m: f64::INFINITY,
                max_collisions: 0,
                collision_pair_samples: 0,
                final_five_elements: None,
            },
            timings: StageTimings::default(),
            reference_model,
            config,
        })
    }

    /// The simulation at t = 0: the truth, the real objects placed, the events due and the law
    /// initialised.
    fn start(mut self) -> Result<Self, SimError> {
        let sim = &mut self;
        sim.refresh_truth(0.0);
        sim.place_tracked_objects(0.0, None)?;
        sim.apply_due_events()?;
        sim.initialise_law()?;
        sim.apply_condition_events()?;
        Ok(self)
    }

    /// The configuration.
    pub fn config(&self) -> &SimulationConfig {
        &self.config
    }

    /// Records the control history (`[output] control_history`) or stops recording it: each
    /// [`crate::swarm::Snapshot`] then carries every satellite's commanded and applied acceleration
    /// ([`crate::swarm::Snapshot::commanded_hill_mps2`]). The commands before the actuator get a column
    /// of their own (3 × 8 bytes per satellite), which exists only while this is on; off, nothing is
    /// computed or stored. The kinematic model (whose commands are velocities) has no control
    /// history: the call then leaves it off. Call it before the run (a column switched on later holds
    /// zeros until the next tick).
    pub fn set_control_history(&mut self, on: bool) {
        let on = on && !matches!(self.config.dynamics, DynamicsModel::Kinematic);
        let n = self.satellites.applied_hill.len();
        self.satellites.commanded_hill = if on {
            vec![Vector3::zeros(); n]
        } else {
            Vec::new()
        };
    }

    /// Whether the control history is recorded ([`Simulation::set_control_history`]).
    pub fn records_control_history(&self) -> bool {
        !self.satellites.commanded_hill.is_empty()
    }

    /// Whether a satellite has drag attitudes (a law may command its drag area): the drag-command
    /// buffer exists exactly then.
    pub fn has_drag_attitudes(&self) -> bool {
        !self.drag_commands.is_empty()
    }

    /// Every satellite's drag area now \[m^2\], by id, when a satellite has drag attitudes (a law may
    /// command it); `None` otherwise.
    pub fn drag_areas_m2(&self) -> Option<Vec<f64>> {
        let fleet = &self.satellites.fleet;
        self.has_drag_attitudes().then(|| {
            (0..fleet.active.len())
                .map(|id| fleet.drag_area_m2(fleet.order.index_of(id)))
                .collect()
        })
    }

    /// Each satellite's drag Δv so far, ∫‖a_drag‖dt \[m/s\], by id, when a satellite has drag
    /// attitudes (a left-point sum at the control ticks; not propellant: the thrust ledger is apart).
    pub fn drag_delta_v_mps(&self) -> Option<Vec<f64>> {
        self.has_drag_attitudes().then(|| {
            self.satellites
                .fleet
                .order
                .by_id(&self.satellites.drag_delta_v_mps)
        })
    }

    /// The live satellites' mean altitude above the equatorial radius averaged over the run's first
    /// orbit and over its latest orbit \[m\] (the orbit average removes the osculating oscillation),
    /// when a satellite has drag attitudes and the run has lasted an orbit.
    pub fn mean_altitude_first_and_last_orbit_m(&self) -> Option<(f64, f64)> {
        self.has_drag_attitudes()
            .then(|| self.drag_altitude.first_and_last())
            .flatten()
    }

    /// How many times each satellite's drag area changed, by id (zeros without drag attitudes).
    pub fn drag_switches(&self) -> Vec<u64> {
        if self.has_drag_attitudes() {
            self.satellites
                .fleet
                .order
                .by_id(&self.satellites.drag_switches)
        } else {
            vec![0; self.satellites.fleet.active.len()]
        }
    }

    /// Current time, seconds since the scenario start \[s\].
    pub fn time_s(&self) -> f64 {
        self.clock.time_s
    }

    /// Current state (reference, satellites by id and delta-v ledgers in one flat buffer; a copy).
    pub fn state(&self) -> SwarmState {
        let mut by_id = self.state.clone();
        let order = &self.satellites.fleet.order;
        if order.placement().is_none() {
            return by_id;
        }
        for (to, from) in by_id
            .satellite_components_mut()
            .zip(self.state.satellite_components())
        {
            for (id, value) in to.iter_mut().enumerate() {
                *value = from[order.index_of(id)];
            }
        }
        by_id
    }

    /// Re-sorts the satellites' storage by grid cell every `ticks` control ticks from now on (sampled
    /// control; 0: never; default 32). No result depends on it, only the speed on large swarms: satellites
    /// near in space are then near in memory (see `DESIGN.md`, "Storage order").
    pub fn set_resort_period_ticks(&mut self, ticks: u64) {
        self.resort_period_ticks = ticks;
    }

    /// Number of satellites N (removed ones included).
    pub fn satellite_count(&self) -> usize {
        self.state.n()
    }

    /// Which satellites are live, by id.
    pub fn active(&self) -> Vec<bool> {
        self.satellites
            .fleet
            .order
            .by_id(&self.satellites.fleet.active)
    }

    /// Every satellite's truth state now, by id, relative to the LVLH origin, Hill frame \[m, m/s\].
    pub fn states_hill(&self) -> Vec<RelativeStateHill> {
        self.satellites.fleet.order.by_id(&self.satellites.truth)
    }

    /// Every satellite's inertial state now, by id, ECI (the engine's inertial frame) \[m, m/s\].
    pub fn states_eci(&self) -> Vec<CartesianState> {
        snapshots::inertial_states(&self.config, &self.state, &self.satellites.fleet.order)
    }

    /// The Schweighart–Sedwick model of the reference orbit at t = 0 that laws get
    /// ([`crate::swarm::SharedInfo::reference_model`]).
    pub fn reference_model(&self) -> SchweighartSedwick {
        self.reference_model
    }

    /// The running law with its per-satellite states.
    pub fn law(&self) -> &Law {
        &self.law
    }

    /// Every satellite's state of the running law now, by id, if the law is of type `L`.
    pub fn law_states<L: GuidanceLaw>(&self) -> Option<Vec<L::State>> {
        self.law
            .states_by_id::<L>(self.satellites.fleet.order.placement())
    }

    /// Every satellite's per-satellite law outputs now, by id and satellite-major (satellite i's at
    /// `i * k .. (i + 1) * k`, k = the number of names); the names are `self.law().output_names()`.
    pub fn law_outputs(&self) -> Vec<f64> {
        let mut values = vec![0.0; self.law.output_names().len() * self.state.n()];
        self.law
            .write_outputs(&mut values, self.satellites.fleet.order.placement());
        values
    }

    /// Per threat: whether a ground warning about it is in force.
    pub fn threat_warnings(&self) -> &[bool] {
        &self.timeline.threat_warnings
    }

    /// Monitors the conjunctions closer than `threshold_m` \[m\] (finite, >= 0) from now on, or stops
    /// monitoring them (`None`): every encounter of two satellites, or of a satellite and a threat or
    /// obstacle, whose miss distance falls below the threshold ([`ConjunctionMonitor`]). Call it before
    /// the run.
    ///
    /// # Errors
    /// [`crate::conjunction::ConjunctionError::Threshold`] for a negative or non-finite threshold.
    pub fn set_conjunction_threshold_m(
        &mut self,
        threshold_m: Option<f64>,
    ) -> Result<(), crate::conjunction::ConjunctionError> {
        self.monitors.conjunctions = threshold_m.map(ConjunctionMonitor::new).transpose()?;
        self.monitors.conjunctions_seen = 0;
        let n = self.satellites.truth.len();
        if self.monitors.conjunctions.is_some() && self.monitors.truth_previous.len() != n {
            self.monitors.truth_previous = vec![RelativeStateHill::default(); n];
        }
        Ok(())
    }

    /// The conjunction monitor, when the run monitors conjunctions
    /// ([`Self::set_conjunction_threshold_m`]): every encounter so far, and those found on the last
    /// segment ([`ConjunctionMonitor::last_segment`]).
    pub fn conjunction_monitor(&self) -> Option<&ConjunctionMonitor> {
        self.monitors.conjunctions.as_ref()
    }

    /// The continuous closest-approach and clearance monitor of the threats and obstacles.
    pub fn approach_monitor(&self) -> &ApproachMonitor {
        &self.monitors.approach
    }

    /// Totals so far.
    pub fn totals(&self) -> &RunTotals {
        &self.totals
    }

    /// Wall-clock time spent in each stage of the engine so far, and the propagation path taken.
    pub fn stage_timings(&self) -> StageTimings {
        StageTimings {
            propagation_path: match &self.integration {
                Integration::Coupled { .. } => "coupled swarm ODE (continuous control)",
                Integration::Sampled(buffers) => buffers.path_name(),
            },
            neighbour_lists_made: self.sensed.grids.grid.neighbour_lists_made(),
            separation_full_searches: self.monitors.live.full_searches(),
            separation_narrow_searches: self.monitors.live.narrow_searches(),
            ..self.timings
        }
    }

    /// Recomputes the truth relative states of the swarm state at `t_s` (the state's time: a segment's
    /// end before the clock moves to it), checking every live satellite for divergence in the same pass
    /// (the report the monitors act on).
    fn refresh_truth(&mut self, t_s: f64) {
        let plant = Plant::new(
            &self.config,
            &self.satellites.fleet,
            &self.timeline.threat_warnings,
            self.reference_model,
        );
        let check = divergence_check(&self.config, &self.satellites.fleet);
        let (_, diverged) = plant.truth_relative_checked(
            t_s,
            self.state.as_slice(),
            &mut self.satellites.truth,
            check,
        );
        self.monitors.diverged = diverged;
    }

    /// Calls `f` with the running law and a whole-swarm view of the truth relative states now (no
    /// navigation noise), by id: the view the law's whole-swarm hooks get; and the storage order.
    fn with_truth_view<R>(
        &mut self,
        f: impl FnOnce(&mut Law, &SwarmView<'_>, Option<Placement<'_>>) -> R,
    ) -> R {
        let plant = Plant::new(
            &self.config,
            &self.satellites.fleet,
            &self.timeline.threat_warnings,
            self.reference_model,
        );
        let mut by_id = FleetById::default();
        let view = plant.view_by_id(
            self.clock.time_s,
            &self.satellites.truth,
            &mut self.sensed,
            &mut by_id,
        );
        f(
            &mut self.law,
            &view,
            self.satellites.fleet.order.placement(),
        )
    }

    fn initialise_law(&mut self) -> Result<(), SimError> {
        self.with_truth_view(|law, view, placement| law.initialise(view, placement))?;
        Ok(())
    }

    /// Every law metric name this run can record: the running law's, then those of the laws that events
    /// switch in, without repeats (the columns a recorder must prepare).
    pub fn law_metric_names(&self) -> Vec<&'static str> {
        self.law_names(Law::metric_names)
    }

    /// Every per-satellite law output name this run can record (running law, then switched-in laws).
    pub fn law_output_names(&self) -> Vec<&'static str> {
        self.law_names(Law::output_names)
    }

    fn law_names(&self, names_of: fn(&Law) -> &'static [&'static str]) -> Vec<&'static str> {
        let mut names: Vec<&'static str> = Vec::new();
        let laws = std::iter::once(&self.law).chain(self.timeline.pending_actions().filter_map(
            |action| match action {
                EventAction::SwitchLaw(law) => Some(law),
                _ => None,
            },
        ));
        for law in laws {
            for name in names_of(law) {
                if !names.contains(name) {
                    names.push(name);
                }
            }
        }
        names
    }

    /// The law's results for the summary, from the current (final) swarm.
    ///
    /// For a law that commands the drag area, the engine adds `mean_altitude_decay_m`: the decay of the
    /// live satellites' mean altitude from the run's first orbit to its last \[m\] (absent for a run
    /// shorter than an orbit; see [`Self::mean_altitude_first_and_last_orbit_m`]).
    pub fn law_results(&mut self) -> std::collections::BTreeMap<String, serde_json::Value> {
        let mut results = self.with_truth_view(|law, view, placement| law.results(view, placement));
        if self.law.commands_drag() {
            if let Some((first_m, last_m)) = self.mean_altitude_first_and_last_orbit_m() {
                results.insert("mean_altitude_decay_m".into(), (first_m - last_m).into());
            }
        }
        results
    }
}

/// Refuses timed events outside the run, events naming satellites or threats that do not exist, and
/// conditions with a threshold that is not a finite number.
fn check_events(events: &[Event], config: &SimulationConfig, n: usize) -> Result<(), SimError> {
    for event in events {
        let describe = || format!("{:?}", event.action);
        let when = match &event.trigger {
            Trigger::Time(time_s) => {
                if !(*time_s >= 0.0 && *time_s <= config.duration_s) {
                    return Err(SimError::EventOutsideRun {
                        event: describe(),
                        time_s: *time_s,
                        duration_s: config.duration_s,
                    });
                }
                format!("at t = {time_s} s")
            }
            Trigger::Condition(c) => {
                if let Some(reason) = condition_problem(&c.test, c.hysteresis, config) {
                    return Err(SimError::EventCondition {
                        event: event.index,
                        condition: c.test.key(),
                        reason,
                    });
                }
                format!("on condition `{}`", c.test.key())
            }
        };
        let (what, index, count) = match &event.action {
            EventAction::RemoveSatellite(i) => ("satellite", Some(*i), n),
            EventAction::FailThruster { satellite, .. } => ("satellite", Some(*satellite), n),
            EventAction::CutLinks(Selection::Satellites(ids))
            | EventAction::RestoreLinks(Selection::Satellites(ids)) => {
                ("satellite", ids.iter().copied().find(|&i| i >= n), n)
            }
            EventAction::ThreatWarning { threat, .. } => {
                ("threat", Some(*threat), config.threats.len())
            }
            _ => ("satellite", None, n),
        };
        if let Some(index) = index.filter(|&i| i >= count) {
            return Err(SimError::EventTarget {
                event: describe(),
                when,
                what,
                index,
                count,
            });
        }
    }
    Ok(())
}

/// What is wrong with a condition's numbers (`None`: nothing): thresholds finite and >= 0, a
/// tolerance and hysteresis finite and >= 0, a threat to approach.
fn condition_problem(
    test: &ConditionTest,
    hysteresis: f64,
    config: &SimulationConfig,
) -> Option<String> {
    let bad = |what: &str, v: f64| {
        (!(v.is_finite() && v >= 0.0)).then(|| format!("{what} {v} is not finite and >= 0"))
    };
    bad("hysteresis", hysteresis).or_else(|| match test {
        ConditionTest::MinSeparationBelow { threshold_m } => bad("threshold", *threshold_m),
        ConditionTest::ThreatWithin { distance_m } => bad("distance", *distance_m).or_else(|| {
            config
                .threats
                .is_empty()
                .then(|| "the scenario has no threat".to_string())
        }),
        ConditionTest::UniformityWithin { target, tolerance } => {
            bad("target", *target).or_else(|| bad("tolerance", *tolerance))
        }
        ConditionTest::LawOutcome { bound, .. } => match bound {
            crate::swarm::events::Bound::Above(x) | crate::swarm::events::Bound::Below(x) => {
                (!x.is_finite()).then(|| format!("bound {x} is not finite"))
            }
        },
        ConditionTest::ShapeReached
        | ConditionTest::SatellitesLostAtLeast(_)
        | ConditionTest::Conjunction => None,
    })
}

/// The reference orbit's LVLH frame at t = 0 with its rotation rate's change under the truth forces.
fn accelerated_frame_at_start(
    dynamics: &DynamicsModel,
    earth: &crate::orbit::EarthModel,
    reference: &CartesianState,
    reference_properties: &crate::dynamics::PhysicalProperties,
) -> LvlhFrame {
    let accel = dynamics.reference_acceleration_m_s2(
        earth,
        0.0,
        &reference.position_m,
        &reference.velocity_mps,
        reference_properties,
    );
    LvlhFrame::from_reference_with_acceleration(reference, &accel)
}

/// The Hill state at t = 0, relative to the reference orbit `reference` (EME2000), of a satellite
/// whose EME2000 state is `state`: the inverse of the map the engine places its satellites and
/// records their EME2000 states by (the frame with the reference's acceleration under the truth
/// forces for the inertial models, the plain LVLH frame for the linear and kinematic ones), so a run
/// started from it records `state` at t = 0 to rounding. `reference_properties` are the virtual
/// reference's (drag and SRP).
pub fn hill_state_at_start(
    dynamics: &DynamicsModel,
    earth: &crate::orbit::EarthModel,
    reference: &CartesianState,
    reference_properties: &crate::dynamics::PhysicalProperties,
    state: &CartesianState,
) -> RelativeStateHill {
    if dynamics.is_inertial() {
        accelerated_frame_at_start(dynamics, earth, reference, reference_properties).to_hill(state)
    } else {
        LvlhFrame::from_reference(reference).to_hill(state)
    }
}

/// The SS model of the reference orbit at t = 0: radius and osculating inclination of the LVLH origin's
/// initial ECI state (the virtual reference, or the member origin's state); the dynamics' own model for
/// `J2Linear`; J2 = 0 for the J2-free models.
fn reference_model(
    config: &SimulationConfig,
    reference_frame: &LvlhFrame,
    satellites: &[SatelliteInit],
) -> SchweighartSedwick {
    if let DynamicsModel::J2Linear(model) = config.dynamics {
        return model;
    }
    let origin = match config.origin {
        Origin::VirtualReference => config.reference,
        Origin::Member(k) => reference_frame.from_hill(&satellites[k].relative_state),
    };
    let h = origin.specific_angular_momentum_m2_s();
    let j2 = if config.dynamics.reference_has_j2() {
        config.earth.j2
    } else {
        0.0
    };
    SchweighartSedwick::new(
        origin.position_m.norm(),
        (h.z / h.norm()).acos(),
        config.earth.mu_m3_s2,
        config.earth.equatorial_radius_m,
        j2,
    )
}

/// Refuses drag attitudes whose initial area is not one of them, and drag attitudes under dynamics whose
/// force set computes no drag (a commanded area would change nothing).
fn check_drag_attitudes(
    config: &SimulationConfig,
    satellites: &[SatelliteInit],
) -> Result<(), SimError> {
    let drag = config.dynamics.forces().is_some_and(|f| f.drag().is_some());
    for (id, s) in satellites.iter().enumerate() {
        let Some(attitudes) = &s.drag_attitudes else {
            continue;
        };
        if !drag {
            return Err(SimError::DragAttitudes {
                satellite: id,
                reason: format!(
                    "drag attitudes need a force set with drag (dynamics `{}` has none)",
                    config.dynamics.name()
                ),
            });
        }
        if !attitudes.admits(s.properties.drag_area_m2) {
            return Err(SimError::DragAttitudes {
                satellite: id,
                reason: format!(
                    "initial drag area {} m^2 is not one of its drag attitudes (allowed: {})",
                    s.properties.drag_area_m2,
                    attitudes.describe()
                ),
            });
        }
    }
    Ok(())
}

/// The mean of a per-tick value over the first `length` ticks and over the latest `length` ticks.
struct AltitudeWindow {
    length: usize,
    first_sum: f64,
    first_count: usize,
    latest: std::collections::VecDeque<f64>,
}

impl AltitudeWindow {
    fn new(length: usize) -> Self {
        Self {
            length: length.max(1),
            first_sum: 0.0,
            first_count: 0,
            latest: std::collections::VecDeque::new(),
        }
    }

    fn push(&mut self, value: f64) {
        if self.first_count < self.length {
            self.first_sum += value;
            self.first_count += 1;
        }
        self.latest.push_back(value);
        if self.latest.len() > self.length {
            self.latest.pop_front();
        }
    }

    fn first_and_last(&self) -> Option<(f64, f64)> {
        (self.first_count == self.length).then(|| {
            let latest: f64 = self.latest.iter().sum();
            (
                self.first_sum / self.length as f64,
                latest / self.latest.len() as f64,
            )
        })
    }
}
