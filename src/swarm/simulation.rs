//! The simulation loop: propagates the reference orbit and every satellite, evaluates the guidance law,
//! applies actuator limits, runs the event timeline and hands snapshots to a recorder.
//!
//! Control timing (see `DESIGN.md`):
//! * [`ControlTiming::Continuous`]: the law is evaluated inside the integrator's right-hand side and the
//!   swarm (reference, satellites and delta-v ledgers) is integrated as one coupled system;
//! * [`ControlTiming::Sampled`]: the law runs every control period and its command is held (zero-order
//!   hold, constant in the dynamics frame: ECI for inertial truth, Hill for the linear models); between
//!   ticks every satellite is propagated on its own, in parallel.
//!
//! Time advances in segments whose ends are the control ticks (or integration steps), the recording times,
//! the event times and the end of the run; every one of them is hit exactly. After each segment the
//! engine checks every satellite for divergence (non-finite state, or farther than the configured bound
//! from the LVLH origin) and tracks the minimum separation.
//!
//! Determinism: every per-satellite computation is independent and written to its own slot; reductions are
//! serial; navigation noise is drawn from a ChaCha8 stream per (seed, step, satellite). Results are
//! therefore bitwise identical for any number of threads.

use std::collections::BTreeMap;
use std::sync::Mutex;

use nalgebra::Vector3;
use rand::rngs::ChaCha8Rng;
use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};
use rayon::prelude::*;
use thiserror::Error;

use crate::grid::NeighbourGrid;
use crate::integrate::{
    AdaptiveStepper, Dop853, IntegrateError, IntegratorMethod, OdeSystem, Rk4, Rkf78, Tolerances,
};
use crate::metrics::{five_elements, min_separation, FiveElements, FiveElementsWorkspace};
use crate::orbit::{CartesianState, EarthModel, GravityModel, LvlhFrame, RelativeStateHill};
use crate::relative::SchweighartSedwick;
use crate::swarm::actuator::Actuator;
use crate::swarm::dynamics::DynamicsModel;
use crate::swarm::events::{Event, EventAction, ThrustAxis};
use crate::swarm::law::{GuidanceLaw, LawError, SharedInfo, SwarmView};
use crate::swarm::recorder::{Recorder, Snapshot};
use crate::swarm::state::{
    ledger_index, reference_of, satellite_index, satellite_of, SwarmState, LEDGER_COMPONENTS,
    SATELLITE_COMPONENTS,
};

/// Satellites per parallel work item. Fixed, so that the split of work never depends on the thread count.
const CHUNK: usize = 256;
/// State components of one satellite as propagated alone in sampled mode: position, velocity, ledger.
const SOLO: usize = SATELLITE_COMPONENTS + LEDGER_COMPONENTS;

/// When the guidance law is evaluated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ControlTiming {
    /// Inside the integrator's right-hand side; the swarm is integrated as one coupled system.
    Continuous,
    /// Every `period_s` seconds, command held in between (zero-order hold).
    Sampled {
        /// Control period \[s\].
        period_s: f64,
    },
}

/// What the LVLH frame (and so every relative state a law sees) is centred on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Origin {
    /// The uncontrolled virtual reference orbit.
    VirtualReference,
    /// A member satellite (e.g. the "target spacecraft" of a cluster).
    Member(usize),
}

/// Sensors and links of every satellite.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sensing {
    /// Range of sensors and inter-satellite links \[m\].
    pub range_m: f64,
    /// Standard deviation of each satellite's navigation position error, per Hill axis \[m\].
    pub position_noise_m: f64,
    /// Standard deviation of each satellite's navigation velocity error, per Hill axis \[m/s\].
    pub velocity_noise_mps: f64,
}

/// Everything the engine needs besides the satellites and the law.
#[derive(Clone, Debug, PartialEq)]
pub struct SimulationConfig {
    /// Earth constants.
    pub earth: EarthModel,
    /// Truth dynamics.
    pub dynamics: DynamicsModel,
    /// Integration method.
    pub integrator: IntegratorMethod,
    /// RK4 step, or the longest step and segment length of the adaptive method \[s\].
    pub step_s: f64,
    /// Tolerances of the adaptive method.
    pub tolerances: Tolerances,
    /// When the law is evaluated.
    pub control: ControlTiming,
    /// LVLH origin.
    pub origin: Origin,
    /// Reference orbit at t = 0, ECI.
    pub reference: CartesianState,
    /// Mean motion of the reference orbit \[rad/s\], given to laws.
    pub mean_motion_rad_s: f64,
    /// Length of the run \[s\].
    pub duration_s: f64,
    /// Recording cadence \[s\].
    pub record_interval_s: f64,
    /// Sensors and links.
    pub sensing: Sensing,
    /// A satellite farther than this from the LVLH origin stops the run as diverged \[m\].
    pub max_distance_m: f64,
    /// Seed of every random draw of the run.
    pub seed: u64,
}

/// One satellite at t = 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SatelliteInit {
    /// State relative to the reference orbit at t = 0, Hill frame \[m, m/s\].
    pub relative_state: RelativeStateHill,
    /// Mass \[kg\].
    pub mass_kg: f64,
    /// Physical radius \[m\] (collision counting and d_min).
    pub radius_m: f64,
    /// Thrusters.
    pub actuator: Actuator,
}

/// Why a run stopped early or could not start.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum SimError {
    /// A satellite's state became non-finite or left the allowed distance from the LVLH origin.
    #[error("satellite {satellite} diverged at t = {time_s} s: {reason}")]
    Diverged {
        /// Index of the first diverging satellite.
        satellite: usize,
        /// Time of detection \[s\].
        time_s: f64,
        /// What was seen.
        reason: String,
    },
    /// The integrator failed (step-size underflow, non-finite derivative).
    #[error("integration failed: {0}")]
    Integration(#[from] IntegrateError),
    /// The law refused its parameters.
    #[error(transparent)]
    Law(#[from] LawError),
    /// The configuration cannot run (with what is wrong and what is allowed).
    #[error("invalid simulation setup: {0}")]
    InvalidSetup(String),
    /// The recorder could not write.
    #[error("recording failed: {0}")]
    Recording(#[from] std::io::Error),
}

/// Totals of a finished run.
#[derive(Clone, Debug, PartialEq)]
pub struct RunTotals {
    /// Simulated time reached \[s\].
    pub time_s: f64,
    /// Satellite-steps integrated (live satellites × base steps).
    pub satellite_steps: u64,
    /// Smallest separation between two live satellites seen at any segment end \[m\].
    pub min_separation_m: f64,
    /// Largest number of simultaneous collisions (pairs closer than the sum of radii) seen.
    pub max_collisions: usize,
    /// Distinct colliding pairs counted at segment ends, summed over the run.
    pub collision_pair_samples: usize,
    /// Five elements at the last time.
    pub final_five_elements: Option<FiveElements>,
}

/// What the satellites sense at one evaluation: relative states, their positions component-wise, and the
/// neighbour grid over them. Allocated once.
struct Sensed {
    relative: Vec<RelativeStateHill>,
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    grid: NeighbourGrid,
    /// Navigation noise held over the current step: position \[m\] and velocity \[m/s\], Hill frame.
    noise: Vec<[f64; 6]>,
}

/// Buffers of the separation and five-element metrics over the live satellites. Allocated once.
struct LiveMetrics {
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    radii_m: Vec<f64>,
    grid: NeighbourGrid,
    workspace: FiveElementsWorkspace,
}

/// Per-evaluation work buffers, allocated once.
struct Scratch {
    sensed: Sensed,
    live: LiveMetrics,
    applied_hill: Vec<Vector3<f64>>,
    per_satellite: Vec<[f64; SOLO]>,
}

impl Scratch {
    fn new(n: usize) -> Self {
        Self {
            sensed: Sensed {
                relative: vec![RelativeStateHill::default(); n],
                x: vec![0.0; n],
                y: vec![0.0; n],
                z: vec![0.0; n],
                grid: NeighbourGrid::new(),
                noise: vec![[0.0; 6]; n],
            },
            live: LiveMetrics {
                x: Vec::with_capacity(n),
                y: Vec::with_capacity(n),
                z: Vec::with_capacity(n),
                radii_m: Vec::with_capacity(n),
                grid: NeighbourGrid::new(),
                workspace: FiveElementsWorkspace::new(),
            },
            applied_hill: vec![Vector3::zeros(); n],
            per_satellite: vec![[0.0; SOLO]; n],
        }
    }
}

/// Per-satellite properties that change only through events, as structure-of-arrays.
struct Fleet {
    masses_kg: Vec<f64>,
    radii_m: Vec<f64>,
    actuators: Vec<Actuator>,
    /// `false` once a satellite is removed.
    active: Vec<bool>,
    /// `false` while a satellite's links are cut.
    links_up: Vec<bool>,
}

/// What the right-hand side reads besides the state and the law.
struct Plant<'a> {
    config: &'a SimulationConfig,
    fleet: &'a Fleet,
    threat_warning_active: bool,
    reference_model: SchweighartSedwick,
}

impl<'a> Plant<'a> {
    fn new(
        config: &'a SimulationConfig,
        fleet: &'a Fleet,
        threat_warning_active: bool,
        reference_model: SchweighartSedwick,
    ) -> Self {
        Self {
            config,
            fleet,
            threat_warning_active,
            reference_model,
        }
    }

    fn n(&self) -> usize {
        self.fleet.masses_kg.len()
    }

    /// The LVLH frame of the origin for a flat state (inertial models only).
    fn frame(&self, data: &[f64]) -> LvlhFrame {
        let n = self.n();
        let (position_m, velocity_mps) = match self.config.origin {
            Origin::VirtualReference => reference_of(data),
            Origin::Member(k) => satellite_of(data, n, k),
        };
        let origin = CartesianState::new(position_m, velocity_mps);
        let gravity = self.config.dynamics.reference_gravity();
        let accel = gravity.acceleration_m_s2(&self.config.earth, &origin.position_m);
        LvlhFrame::from_reference_with_acceleration(&origin, &accel)
    }

    /// Fills `sensed.relative` with every satellite's truth state relative to the origin (Hill).
    fn relative_states(&self, data: &[f64], sensed: &mut Sensed) -> Option<LvlhFrame> {
        let n = self.n();
        match self.config.dynamics {
            DynamicsModel::Inertial(_) => {
                let frame = self.frame(data);
                sensed
                    .relative
                    .par_iter_mut()
                    .with_min_len(CHUNK)
                    .enumerate()
                    .for_each(|(i, rel)| {
                        let (p, v) = satellite_of(data, n, i);
                        *rel = frame.to_hill(&CartesianState::new(p, v));
                    });
                Some(frame)
            }
            DynamicsModel::Hcw(_) | DynamicsModel::J2Linear(_) => {
                let (op, ov) = match self.config.origin {
                    Origin::VirtualReference => (Vector3::zeros(), Vector3::zeros()),
                    Origin::Member(k) => satellite_of(data, n, k),
                };
                sensed
                    .relative
                    .par_iter_mut()
                    .with_min_len(CHUNK)
                    .enumerate()
                    .for_each(|(i, rel)| {
                        let (p, v) = satellite_of(data, n, i);
                        *rel = RelativeStateHill {
                            position_m: p - op,
                            velocity_mps: v - ov,
                        };
                    });
                None
            }
        }
    }

    /// A whole-swarm view: relative states relative to the origin (plus the held navigation noise when
    /// `with_noise`), their positions component-wise, and the grid over them. Returns the LVLH frame used
    /// (inertial models only).
    fn view<'s>(
        &'s self,
        time_s: f64,
        data: &[f64],
        sensed: &'s mut Sensed,
        with_noise: bool,
    ) -> (SwarmView<'s>, Option<LvlhFrame>) {
        let frame = self.relative_states(data, sensed);
        let Sensed {
            relative,
            x,
            y,
            z,
            grid,
            noise,
        } = sensed;
        let sensing = &self.config.sensing;
        if with_noise && (sensing.position_noise_m > 0.0 || sensing.velocity_noise_mps > 0.0) {
            relative
                .par_iter_mut()
                .with_min_len(CHUNK)
                .zip(noise.par_iter())
                .for_each(|(rel, e)| {
                    rel.position_m += Vector3::new(e[0], e[1], e[2]);
                    rel.velocity_mps += Vector3::new(e[3], e[4], e[5]);
                });
        }
        for (i, rel) in relative.iter().enumerate() {
            x[i] = rel.position_m.x;
            y[i] = rel.position_m.y;
            z[i] = rel.position_m.z;
        }
        // A non-finite navigation position leaves the grid empty (no neighbours for this evaluation);
        // the divergence check after the segment then stops the run and names the satellite.
        let _ = grid.build(x, y, z, sensing.range_m);
        let view = SwarmView {
            relative_states: relative,
            masses_kg: &self.fleet.masses_kg,
            active: &self.fleet.active,
            links_up: &self.fleet.links_up,
            grid,
            shared: SharedInfo {
                time_s,
                mean_motion_rad_s: self.config.mean_motion_rad_s,
                threat_warning_active: self.threat_warning_active,
                sensing_range_m: sensing.range_m,
                reference_model: self.reference_model,
            },
        };
        (view, frame)
    }

    /// Evaluates the law for every live satellite on the navigation states, applies the actuators, and
    /// leaves the applied accelerations (Hill frame) in `applied_hill`. Returns the LVLH frame used.
    fn commands(
        &self,
        law: &dyn GuidanceLaw,
        time_s: f64,
        data: &[f64],
        sensed: &mut Sensed,
        applied_hill: &mut [Vector3<f64>],
    ) -> Option<LvlhFrame> {
        let (view, frame) = self.view(time_s, data, sensed, true);
        applied_hill
            .par_iter_mut()
            .with_min_len(CHUNK)
            .enumerate()
            .for_each(|(i, applied)| {
                *applied = if self.fleet.active[i] {
                    let command = law.command_m_s2(&view.satellite(i));
                    self.fleet.actuators[i].apply(&command)
                } else {
                    Vector3::zeros()
                };
            });
        frame
    }
}

/// The coupled swarm as one ODE (continuous control timing).
struct CoupledSwarm<'a> {
    plant: Plant<'a>,
    law: &'a dyn GuidanceLaw,
    scratch: &'a Mutex<Scratch>,
}

impl OdeSystem for CoupledSwarm<'_> {
    fn derivative(&self, t_s: f64, state: &[f64], derivative: &mut [f64]) {
        let plant = &self.plant;
        let config = plant.config;
        let n = plant.n();
        let mut guard = self.scratch.lock().unwrap_or_else(|e| e.into_inner());
        let scratch = &mut *guard;
        // Reference orbit: uncontrolled.
        let (rp, rv) = reference_of(state);
        let ra = config
            .dynamics
            .reference_gravity()
            .acceleration_m_s2(&config.earth, &rp);
        derivative[0..3].copy_from_slice(rv.as_slice());
        derivative[3..6].copy_from_slice(ra.as_slice());

        let Scratch {
            sensed,
            applied_hill,
            per_satellite,
            ..
        } = scratch;
        let frame = plant.commands(self.law, t_s, state, sensed, applied_hill);
        per_satellite
            .par_iter_mut()
            .with_min_len(CHUNK)
            .enumerate()
            .for_each(|(i, d)| {
                if !plant.fleet.active[i] {
                    *d = [0.0; SOLO];
                    return;
                }
                let (p, v) = satellite_of(state, n, i);
                let u = applied_hill[i];
                let control = match &frame {
                    Some(f) => f.vector_hill_to_eci(&u),
                    None => u,
                };
                let (dp, dv) =
                    config
                        .dynamics
                        .satellite_derivative(&config.earth, &p, &v, &control);
                *d = ledger_derivative(&dp, &dv, &u);
            });
        scatter(per_satellite, n, derivative);
    }
}

/// Derivative of one satellite's position, velocity and delta-v ledger.
#[inline]
fn ledger_derivative(dp: &Vector3<f64>, dv: &Vector3<f64>, u_hill: &Vector3<f64>) -> [f64; SOLO] {
    [
        dp.x,
        dp.y,
        dp.z,
        dv.x,
        dv.y,
        dv.z,
        u_hill.x.abs(),
        u_hill.y.abs(),
        u_hill.z.abs(),
        u_hill.norm(),
    ]
}

/// Writes per-satellite blocks (position, velocity, ledger) into the component-major flat layout.
fn scatter(per_satellite: &[[f64; SOLO]], n: usize, flat: &mut [f64]) {
    let body = &mut flat[satellite_index(n, 0, 0)..];
    body.par_chunks_mut(n.max(1))
        .take(SOLO)
        .enumerate()
        .for_each(|(k, component)| {
            for (i, value) in component.iter_mut().enumerate() {
                *value = per_satellite[i][k];
            }
        });
}

/// Reads per-satellite blocks out of the component-major flat layout.
fn gather(flat: &[f64], n: usize, per_satellite: &mut [[f64; SOLO]]) {
    per_satellite
        .par_iter_mut()
        .with_min_len(CHUNK)
        .enumerate()
        .for_each(|(i, block)| {
            for (k, value) in block.iter_mut().enumerate() {
                *value = if k < SATELLITE_COMPONENTS {
                    flat[satellite_index(n, k, i)]
                } else {
                    flat[ledger_index(n, k - SATELLITE_COMPONENTS, i)]
                };
            }
        });
}

/// The integrator of the coupled system, or of one satellite.
enum Stepper {
    Rk4(Rk4),
    Rk78(AdaptiveStepper<Rkf78>),
    Dop853(AdaptiveStepper<Dop853>),
}

impl Stepper {
    fn new(method: IntegratorMethod, dimension: usize, config: &SimulationConfig) -> Self {
        match method {
            IntegratorMethod::Rk4 => Stepper::Rk4(Rk4::new(dimension)),
            IntegratorMethod::Rk78 => {
                let mut stepper = AdaptiveStepper::<Rkf78>::new(dimension, config.tolerances);
                stepper.set_max_step_s(config.step_s);
                Stepper::Rk78(stepper)
            }
            IntegratorMethod::Dop853 => {
                let mut stepper = AdaptiveStepper::<Dop853>::new(dimension, config.tolerances);
                stepper.set_max_step_s(config.step_s);
                Stepper::Dop853(stepper)
            }
        }
    }

    fn advance<S: OdeSystem + ?Sized>(
        &mut self,
        system: &S,
        t0_s: f64,
        t1_s: f64,
        state: &mut [f64],
        max_step_s: f64,
    ) -> Result<(), IntegrateError> {
        match self {
            Stepper::Rk4(rk) => {
                rk.integrate(system, t0_s, t1_s, state, max_step_s);
                Ok(())
            }
            Stepper::Rk78(ad) => ad.integrate(system, t0_s, t1_s, state).map(|_| ()),
            Stepper::Dop853(ad) => ad.integrate(system, t0_s, t1_s, state).map(|_| ()),
        }
    }
}

/// A swarm simulation: state, satellites, law, events, and the loop that advances them.
pub struct Simulation {
    config: SimulationConfig,
    state: SwarmState,
    time_s: f64,
    fleet: Fleet,
    law: Box<dyn GuidanceLaw>,
    /// Pending events, latest first (popped from the back).
    events: Vec<Event>,
    threat_warning_active: bool,
    scratch: Mutex<Scratch>,
    coupled_stepper: Stepper,
    solo_steppers: Vec<Stepper>,
    reference_stepper: Stepper,
    /// Held command in the dynamics frame (ECI or Hill) \[m/s^2\], sampled mode.
    held_control: Vec<Vector3<f64>>,
    /// Held command in the Hill frame \[m/s^2\], sampled mode: what the delta-v ledger integrates.
    held_hill: Vec<Vector3<f64>>,
    step_index: u64,
    totals: RunTotals,
    /// SS model of the reference orbit at t = 0, given to laws ([`SharedInfo::reference_model`]).
    reference_model: SchweighartSedwick,
}

impl Simulation {
    /// Builds a simulation. The satellites' initial states are relative to the reference orbit at t = 0.
    /// Checks that the setup can run: at least one satellite, a valid origin, events inside the run,
    /// steps and periods short enough for the law's fastest rate.
    pub fn new(
        config: SimulationConfig,
        satellites: &[SatelliteInit],
        law: Box<dyn GuidanceLaw>,
        mut events: Vec<Event>,
    ) -> Result<Self, SimError> {
        let n = satellites.len();
        if n == 0 {
            return Err(SimError::InvalidSetup(
                "the swarm has no satellite (allowed: 1 or more)".into(),
            ));
        }
        if !(config.sensing.range_m.is_finite() && config.sensing.range_m > 0.0) {
            return Err(SimError::InvalidSetup(format!(
                "sensing range {} m is out of range (allowed: finite, > 0)",
                config.sensing.range_m
            )));
        }
        if let Origin::Member(k) = config.origin {
            if k >= n {
                return Err(SimError::InvalidSetup(format!(
                    "origin member {k} does not exist (allowed: 0..{})",
                    n - 1
                )));
            }
        }
        for event in &events {
            if !(event.time_s >= 0.0 && event.time_s <= config.duration_s) {
                return Err(SimError::InvalidSetup(format!(
                    "event {:?} at t = {} s is outside the run [0, {}] s",
                    event.action, event.time_s, config.duration_s
                )));
            }
            let bad = match &event.action {
                EventAction::RemoveSatellite(i) => Some(*i),
                EventAction::FailThruster { satellite, .. } => Some(*satellite),
                EventAction::CutLinks(s) | EventAction::RestoreLinks(s) => match s {
                    crate::swarm::events::Selection::All => None,
                    crate::swarm::events::Selection::Satellites(ids) => {
                        ids.iter().copied().find(|&i| i >= n)
                    }
                },
                _ => None,
            };
            if let Some(i) = bad.filter(|&i| i >= n) {
                return Err(SimError::InvalidSetup(format!(
                    "event {:?} at t = {} s names satellite {i}, which does not exist (allowed: 0..{})",
                    event.action,
                    event.time_s,
                    n - 1
                )));
            }
        }
        // Stable sort keeps the file order of simultaneous events; reversed so that pop() is the next.
        events.sort_by(|a, b| a.time_s.total_cmp(&b.time_s));
        events.reverse();

        let mut state = SwarmState::zeros(n);
        state.set_reference(&config.reference.position_m, &config.reference.velocity_mps);
        let reference_frame = {
            let accel = config
                .dynamics
                .reference_gravity()
                .acceleration_m_s2(&config.earth, &config.reference.position_m);
            LvlhFrame::from_reference_with_acceleration(&config.reference, &accel)
        };
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
        let chunks = n.div_ceil(CHUNK);
        let solo_steppers = (0..chunks)
            .map(|_| Stepper::new(config.integrator, SOLO, &config))
            .collect();
        let mut sim = Self {
            coupled_stepper: Stepper::new(config.integrator, state.as_slice().len(), &config),
            reference_stepper: Stepper::new(config.integrator, 6, &config),
            solo_steppers,
            state,
            time_s: 0.0,
            fleet: Fleet {
                masses_kg: satellites.iter().map(|s| s.mass_kg).collect(),
                radii_m: satellites.iter().map(|s| s.radius_m).collect(),
                actuators: satellites.iter().map(|s| s.actuator).collect(),
                active: vec![true; n],
                links_up: vec![true; n],
            },
            law,
            events,
            threat_warning_active: false,
            scratch: Mutex::new(Scratch::new(n)),
            held_control: vec![Vector3::zeros(); n],
            held_hill: vec![Vector3::zeros(); n],
            step_index: 0,
            totals: RunTotals {
                time_s: 0.0,
                satellite_steps: 0,
                min_separation_m: f64::INFINITY,
                max_collisions: 0,
                collision_pair_samples: 0,
                final_five_elements: None,
            },
            reference_model,
            config,
        };
        sim.check_rates(sim.law.as_ref())?;
        sim.apply_due_events()?;
        sim.initialise_law()?;
        Ok(sim)
    }

    /// Refuses steps and control periods that cannot resolve the law's fastest closed-loop rate k:
    /// RK4 is stable for h·k ≤ 2.78 and a zero-order hold for T·k < 2 (first-order damping). We require
    /// a margin of two on both, so that the run is accurate, not merely bounded.
    fn check_rates(&self, law: &dyn GuidanceLaw) -> Result<(), SimError> {
        let min_mass = self
            .fleet
            .masses_kg
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min);
        let Some(rate) = law.fastest_rate_per_s(min_mass) else {
            return Ok(());
        };
        if let ControlTiming::Sampled { period_s } = self.config.control {
            if period_s * rate >= 1.0 {
                return Err(SimError::InvalidSetup(format!(
                    "control period {period_s} s is too long for law `{}`, whose fastest closed-loop \
                     rate is {rate:.4} 1/s: a zero-order hold needs period < {:.4} s to stay accurate \
                     (unstable beyond {:.4} s); shorten control.period_s",
                    law.name(),
                    1.0 / rate,
                    2.0 / rate
                )));
            }
        }
        if self.config.integrator == IntegratorMethod::Rk4 && self.config.step_s * rate >= 1.4 {
            return Err(SimError::InvalidSetup(format!(
                "integration step {} s is too long for law `{}`, whose fastest closed-loop rate is \
                 {rate:.4} 1/s: RK4 needs step < {:.4} s (unstable beyond {:.4} s); shorten \
                 dynamics.step_s",
                self.config.step_s,
                law.name(),
                1.4 / rate,
                2.78 / rate
            )));
        }
        Ok(())
    }

    /// The configuration.
    pub fn config(&self) -> &SimulationConfig {
        &self.config
    }

    /// Current time \[s\].
    pub fn time_s(&self) -> f64 {
        self.time_s
    }

    /// Current state.
    pub fn state(&self) -> &SwarmState {
        &self.state
    }

    /// Which satellites are live.
    pub fn active(&self) -> &[bool] {
        &self.fleet.active
    }

    /// The Schweighart–Sedwick model of the reference orbit at t = 0 that laws get
    /// ([`SharedInfo::reference_model`]).
    pub fn reference_model(&self) -> SchweighartSedwick {
        self.reference_model
    }

    /// The running law.
    pub fn law(&self) -> &dyn GuidanceLaw {
        self.law.as_ref()
    }

    fn plant(&self) -> Plant<'_> {
        Plant::new(
            &self.config,
            &self.fleet,
            self.threat_warning_active,
            self.reference_model,
        )
    }

    /// Base step: the control period in sampled mode, the integration step in continuous mode \[s\].
    fn base_step_s(&self) -> f64 {
        match self.config.control {
            ControlTiming::Sampled { period_s } => period_s,
            ControlTiming::Continuous => self.config.step_s,
        }
    }

    /// Runs from the current time to the end, recording at the cadence (and at the current time when
    /// it is the start). `progress` is called with the simulated time after every segment. On divergence
    /// the recorder has received every snapshot up to the last good one.
    pub fn run(
        &mut self,
        recorder: &mut dyn Recorder,
        progress: &mut dyn FnMut(f64),
    ) -> Result<RunTotals, SimError> {
        let base = self.base_step_s();
        let record = self.config.record_interval_s;
        let duration = self.config.duration_s;
        let eps = 1e-9 * base.max(1.0);
        let mut step_count = (self.time_s / base).round() as u64;
        let mut record_count = (self.time_s / record + 1e-9).floor() as u64 + 1;
        if self.time_s == 0.0 {
            self.record(recorder)?;
        }
        while self.time_s < duration - eps {
            let next_step = ((step_count + 1) as f64 * base).min(duration);
            let next_record = (record_count as f64 * record).min(duration);
            let next_event = self.events.last().map_or(f64::INFINITY, |e| e.time_s);
            let t1 = next_step.min(next_record).min(next_event.max(self.time_s));
            let at_tick = (self.time_s - step_count as f64 * base).abs() <= eps;
            if t1 > self.time_s + eps {
                self.advance(self.time_s, t1, at_tick)?;
            }
            self.time_s = t1;
            if (t1 - next_step).abs() <= eps {
                step_count += 1;
            }
            self.check_divergence()?;
            self.track_separation();
            self.apply_due_events()?;
            if (t1 - next_record).abs() <= eps {
                record_count += 1;
                self.record(recorder)?;
            }
            progress(self.time_s);
        }
        self.totals.time_s = self.time_s;
        Ok(self.totals.clone())
    }

    /// Advances by one base step (control period, or integration step in continuous mode) from the current
    /// time, with the divergence check, separation tracking and due events, but no recording. For callers
    /// that drive the loop themselves (benchmarks, interactive use).
    pub fn step(&mut self) -> Result<(), SimError> {
        let t0 = self.time_s;
        let t1 = t0 + self.base_step_s();
        self.advance(t0, t1, true)?;
        self.time_s = t1;
        self.check_divergence()?;
        self.track_separation();
        self.apply_due_events()
    }

    /// Calls `f` with the running law and a whole-swarm view of the truth relative states at `time_s`
    /// (no navigation noise): the view the law's whole-swarm hooks get.
    fn with_truth_view<R>(
        &mut self,
        time_s: f64,
        f: impl FnOnce(&mut dyn GuidanceLaw, &SwarmView<'_>) -> R,
    ) -> R {
        let scratch = self.scratch.get_mut().unwrap_or_else(|e| e.into_inner());
        let plant = Plant::new(
            &self.config,
            &self.fleet,
            self.threat_warning_active,
            self.reference_model,
        );
        let (view, _) = plant.view(time_s, self.state.as_slice(), &mut scratch.sensed, false);
        f(self.law.as_mut(), &view)
    }

    fn initialise_law(&mut self) -> Result<(), SimError> {
        self.with_truth_view(self.time_s, |law, view| law.initialise(view))?;
        Ok(())
    }

    /// Every law metric name this run can record: the running law's, then those of the laws that events
    /// switch in, without repeats (the columns a recorder must prepare).
    pub fn law_metric_names(&self) -> Vec<&'static str> {
        let mut names: Vec<&'static str> = Vec::new();
        let laws =
            std::iter::once(self.law.as_ref()).chain(self.events.iter().rev().filter_map(|e| {
                match &e.action {
                    EventAction::SwitchLaw(law) => Some(law.as_ref()),
                    _ => None,
                }
            }));
        for law in laws {
            for name in law.metric_names() {
                if !names.contains(name) {
                    names.push(name);
                }
            }
        }
        names
    }

    /// Runs the law's centralised step on the swarm at `time_s` (navigation states without noise: the
    /// centralised step is modelled as having the ground's precise orbit determination).
    fn centralised_update(&mut self, time_s: f64) -> Result<(), SimError> {
        self.with_truth_view(time_s, |law, view| law.centralised_update(view))?;
        Ok(())
    }

    /// The law's results for the summary, from the current (final) swarm.
    pub fn law_results(&mut self) -> BTreeMap<String, serde_json::Value> {
        self.with_truth_view(self.time_s, |law, view| law.results(view))
    }

    /// Totals so far (final after [`Simulation::run`]).
    pub fn totals(&self) -> &RunTotals {
        &self.totals
    }

    /// Draws the navigation noise held during the step that starts now.
    fn draw_noise(&mut self) {
        let sensing = self.config.sensing;
        if sensing.position_noise_m <= 0.0 && sensing.velocity_noise_mps <= 0.0 {
            return;
        }
        let seed = self.config.seed ^ 0x6e61_765f_6e6f_6973; // "nav_nois": a stream family of its own
        let step = self.step_index;
        let scratch = self.scratch.get_mut().unwrap_or_else(|e| e.into_inner());
        scratch
            .sensed
            .noise
            .par_iter_mut()
            .with_min_len(CHUNK)
            .enumerate()
            .for_each(|(i, e)| {
                let mut rng = ChaCha8Rng::seed_from_u64(seed.wrapping_add(step));
                rng.set_stream(i as u64);
                for (k, value) in e.iter_mut().enumerate() {
                    let sigma = if k < 3 {
                        sensing.position_noise_m
                    } else {
                        sensing.velocity_noise_mps
                    };
                    let draw: f64 = StandardNormal.sample(&mut rng);
                    *value = sigma * draw;
                }
            });
    }

    /// Advances the state from t0 to t1 (one segment). `at_tick`: t0 is a control tick.
    fn advance(&mut self, t0: f64, t1: f64, at_tick: bool) -> Result<(), SimError> {
        if at_tick && self.law.centralised_due(t0) {
            self.centralised_update(t0)?;
        }
        if at_tick {
            self.draw_noise();
            self.step_index += 1;
            let live = self.fleet.active.iter().filter(|a| **a).count() as u64;
            self.totals.satellite_steps += live;
        }
        match self.config.control {
            ControlTiming::Continuous => self.advance_coupled(t0, t1),
            ControlTiming::Sampled { .. } => {
                if at_tick {
                    self.hold_commands(t0);
                }
                self.advance_sampled(t0, t1)
            }
        }
    }

    fn advance_coupled(&mut self, t0: f64, t1: f64) -> Result<(), SimError> {
        let plant = Plant::new(
            &self.config,
            &self.fleet,
            self.threat_warning_active,
            self.reference_model,
        );
        let system = CoupledSwarm {
            plant,
            law: self.law.as_ref(),
            scratch: &self.scratch,
        };
        self.coupled_stepper.advance(
            &system,
            t0,
            t1,
            self.state.as_mut_slice(),
            self.config.step_s,
        )?;
        Ok(())
    }

    /// Evaluates the law now and holds the command (in the dynamics frame) until the next tick.
    fn hold_commands(&mut self, t0: f64) {
        let plant = self.plant();
        let mut guard = self.scratch.lock().unwrap_or_else(|e| e.into_inner());
        let Scratch {
            sensed,
            applied_hill,
            ..
        } = &mut *guard;
        let frame = plant.commands(
            self.law.as_ref(),
            t0,
            self.state.as_slice(),
            sensed,
            applied_hill,
        );
        for ((held, hill), u) in self
            .held_control
            .iter_mut()
            .zip(self.held_hill.iter_mut())
            .zip(applied_hill.iter())
        {
            *hill = *u;
            *held = match &frame {
                Some(f) => f.vector_hill_to_eci(u),
                None => *u,
            };
        }
    }

    fn advance_sampled(&mut self, t0: f64, t1: f64) -> Result<(), SimError> {
        let n = self.state.n();
        let config = &self.config;
        let max_step = config.step_s;
        // Reference orbit, alone.
        let gravity = config.dynamics.reference_gravity();
        let earth = config.earth;
        let reference_rhs = |_t: f64, y: &[f64], dy: &mut [f64]| {
            let a = gravity.acceleration_m_s2(&earth, &Vector3::new(y[0], y[1], y[2]));
            dy[0..3].copy_from_slice(&y[3..6]);
            dy[3..6].copy_from_slice(a.as_slice());
        };
        let data = self.state.as_mut_slice();
        self.reference_stepper
            .advance(&reference_rhs, t0, t1, &mut data[0..6], max_step)?;

        let scratch = self.scratch.get_mut().unwrap_or_else(|e| e.into_inner());
        gather(data, n, &mut scratch.per_satellite);
        let held = &self.held_control;
        let held_hill = &self.held_hill;
        let active = &self.fleet.active;
        let dynamics = config.dynamics;
        scratch
            .per_satellite
            .par_chunks_mut(CHUNK)
            .zip(self.solo_steppers.par_iter_mut())
            .enumerate()
            .try_for_each(|(c, (blocks, stepper))| -> Result<(), IntegrateError> {
                for (offset, block) in blocks.iter_mut().enumerate() {
                    let i = c * CHUNK + offset;
                    if !active[i] {
                        continue;
                    }
                    // Held control in the dynamics frame; the ledger integrates the Hill command
                    // of the tick, constant over the period.
                    let control = held[i];
                    let u = held_hill[i];
                    let hill = [u.x.abs(), u.y.abs(), u.z.abs(), u.norm()];
                    let rhs = |_t: f64, y: &[f64], dy: &mut [f64]| {
                        let p = Vector3::new(y[0], y[1], y[2]);
                        let v = Vector3::new(y[3], y[4], y[5]);
                        let (dp, dv) = dynamics.satellite_derivative(&earth, &p, &v, &control);
                        dy[0..3].copy_from_slice(dp.as_slice());
                        dy[3..6].copy_from_slice(dv.as_slice());
                        dy[6..10].copy_from_slice(&hill);
                    };
                    stepper.advance(&rhs, t0, t1, block, max_step)?;
                }
                Ok(())
            })?;
        scatter(&scratch.per_satellite, n, data);
        Ok(())
    }

    fn check_divergence(&self) -> Result<(), SimError> {
        let mut scratch = self.scratch.lock().unwrap_or_else(|e| e.into_inner());
        let sensed = &mut scratch.sensed;
        self.plant().relative_states(self.state.as_slice(), sensed);
        let bound = self.config.max_distance_m;
        for (i, rel) in sensed.relative.iter().enumerate() {
            if !self.fleet.active[i] {
                continue;
            }
            let finite = rel.position_m.iter().all(|v| v.is_finite())
                && rel.velocity_mps.iter().all(|v| v.is_finite());
            if !finite {
                return Err(SimError::Diverged {
                    satellite: i,
                    time_s: self.time_s,
                    reason: "state is not finite (NaN or infinite)".into(),
                });
            }
            let distance = rel.position_m.norm();
            if distance > bound {
                return Err(SimError::Diverged {
                    satellite: i,
                    time_s: self.time_s,
                    reason: format!(
                        "{distance:.3} m from the LVLH origin, beyond the allowed {bound} m \
                         (dynamics.max_distance_m)"
                    ),
                });
            }
        }
        Ok(())
    }

    fn track_separation(&mut self) {
        let scratch = self.scratch.get_mut().unwrap_or_else(|e| e.into_inner());
        let sep = live_separation(
            &scratch.sensed.relative,
            &self.fleet.active,
            &self.fleet.radii_m,
            &mut scratch.live,
        );
        self.totals.min_separation_m = self.totals.min_separation_m.min(sep.0);
        self.totals.max_collisions = self.totals.max_collisions.max(sep.1);
        self.totals.collision_pair_samples += sep.1;
    }

    fn apply_due_events(&mut self) -> Result<(), SimError> {
        let eps = 1e-9 * self.base_step_s().max(1.0);
        while self
            .events
            .last()
            .is_some_and(|e| e.time_s <= self.time_s + eps)
        {
            let event = self.events.pop().expect("checked non-empty");
            match event.action {
                EventAction::SetLawParameters(table) => {
                    self.law.set_parameters(&table)?;
                    self.check_rates(self.law.as_ref())?;
                }
                EventAction::SwitchLaw(law) => {
                    self.check_rates(law.as_ref())?;
                    self.law = law;
                    self.initialise_law()?;
                }
                EventAction::ThreatWarning { active } => self.threat_warning_active = active,
                EventAction::CutLinks(selection) => {
                    for (i, up) in self.fleet.links_up.iter_mut().enumerate() {
                        if selection.contains(i) {
                            *up = false;
                        }
                    }
                }
                EventAction::RestoreLinks(selection) => {
                    for (i, up) in self.fleet.links_up.iter_mut().enumerate() {
                        if selection.contains(i) {
                            *up = true;
                        }
                    }
                }
                EventAction::RemoveSatellite(i) => self.fleet.active[i] = false,
                EventAction::FailThruster { satellite, axis } => {
                    let axes = &mut self.fleet.actuators[satellite].working_axes;
                    match axis {
                        ThrustAxis::X => axes[0] = false,
                        ThrustAxis::Y => axes[1] = false,
                        ThrustAxis::Z => axes[2] = false,
                        ThrustAxis::All => *axes = [false; 3],
                    }
                }
            }
        }
        Ok(())
    }

    /// Builds the snapshot of now and hands it to the recorder.
    fn record(&mut self, recorder: &mut dyn Recorder) -> Result<(), SimError> {
        let n = self.state.n();
        let mut guard = self.scratch.lock().unwrap_or_else(|e| e.into_inner());
        let Scratch {
            sensed,
            live: buffers,
            ..
        } = &mut *guard;
        self.plant().relative_states(self.state.as_slice(), sensed);
        let data = self.state.as_slice();
        let reference_frame = if self.config.dynamics.is_inertial() {
            None
        } else {
            Some(LvlhFrame::from_reference(&CartesianState::new(
                reference_of(data).0,
                reference_of(data).1,
            )))
        };
        let inertial: Vec<CartesianState> = (0..n)
            .map(|i| {
                let (p, v) = satellite_of(data, n, i);
                match &reference_frame {
                    None => CartesianState::new(p, v),
                    Some(f) => f.from_hill(&RelativeStateHill {
                        position_m: p,
                        velocity_mps: v,
                    }),
                }
            })
            .collect();
        let ledgers: Vec<([f64; 3], f64)> = (0..n).map(|i| self.state.ledger(i)).collect();
        let axes: Vec<[f64; 3]> = ledgers.iter().map(|l| l.0).collect();
        let norms: Vec<f64> = ledgers.iter().map(|l| l.1).collect();
        let live: Vec<usize> = (0..n).filter(|&i| self.fleet.active[i]).collect();
        let elements = if live.len() >= 2 {
            let positions: Vec<[f64; 3]> = live
                .iter()
                .map(|&i| inertial[i].position_m.into())
                .collect();
            let velocities: Vec<[f64; 3]> = live
                .iter()
                .map(|&i| inertial[i].velocity_mps.into())
                .collect();
            let radii: Vec<f64> = live.iter().map(|&i| self.fleet.radii_m[i]).collect();
            five_elements(
                &positions,
                &velocities,
                Some(&radii),
                &mut buffers.workspace,
            )
            .ok()
        } else {
            None
        };
        let (min_sep, collisions) = live_separation(
            &sensed.relative,
            &self.fleet.active,
            &self.fleet.radii_m,
            buffers,
        );
        self.totals.final_five_elements = elements;
        let law_metric_names = self.law.metric_names();
        let mut law_metrics = vec![0.0; law_metric_names.len()];
        if !law_metrics.is_empty() {
            let plant = Plant::new(
                &self.config,
                &self.fleet,
                self.threat_warning_active,
                self.reference_model,
            );
            let (view, _) = plant.view(self.time_s, data, sensed, false);
            self.law.record_metrics(&view, &mut law_metrics);
        }
        let snapshot = Snapshot {
            time_s: self.time_s,
            relative_states: &sensed.relative,
            inertial_states: &inertial,
            active: &self.fleet.active,
            delta_v_axes_mps: &axes,
            delta_v_mps: &norms,
            five_elements: elements,
            min_separation_m: min_sep,
            collisions,
            law_metric_names,
            law_metrics: &law_metrics,
        };
        recorder.record(&snapshot)?;
        Ok(())
    }
}

/// The SS model of the reference orbit at t = 0 (spec `takahashi-sakai-j2-distance.md` §2.2): radius
/// and osculating inclination of the LVLH origin's initial ECI state (the virtual reference, or the
/// member origin's state); the dynamics' own model for `J2Linear`; J2 = 0 for the J2-free models.
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
    let j2 = match config.dynamics {
        DynamicsModel::Inertial(GravityModel::J2) => config.earth.j2,
        _ => 0.0,
    };
    SchweighartSedwick::new(
        origin.position_m.norm(),
        (h.z / h.norm()).acos(),
        config.earth.mu_m3_s2,
        config.earth.equatorial_radius_m,
        j2,
    )
}

/// Minimum separation between live satellites \[m\] and the count of pairs closer than the sum of their
/// radii, from relative positions (infinite and 0 with fewer than two live satellites). The search is
/// exact at any distance; the grid's cell size only sets its speed, so it is taken from the swarm's own
/// mean spacing (cube root of bounding-box volume per satellite, flat swarms padded to a slab).
fn live_separation(
    relative: &[RelativeStateHill],
    active: &[bool],
    radii_m: &[f64],
    live: &mut LiveMetrics,
) -> (f64, usize) {
    live.x.clear();
    live.y.clear();
    live.z.clear();
    live.radii_m.clear();
    let mut low = Vector3::repeat(f64::INFINITY);
    let mut high = Vector3::repeat(f64::NEG_INFINITY);
    for (i, rel) in relative.iter().enumerate() {
        if active[i] {
            let p = rel.position_m;
            live.x.push(p.x);
            live.y.push(p.y);
            live.z.push(p.z);
            live.radii_m.push(radii_m[i]);
            low = low.inf(&p);
            high = high.sup(&p);
        }
    }
    let count = live.x.len();
    if count < 2 {
        return (f64::INFINITY, 0);
    }
    let extent = high - low;
    let largest = extent.max();
    if largest == 0.0 {
        // Every live satellite at the same point.
        let collisions = if live.radii_m.iter().any(|r| *r > 0.0) {
            count * (count - 1) / 2
        } else {
            0
        };
        return (0.0, collisions);
    }
    let floor = largest / (count as f64).cbrt();
    let volume: f64 = extent.iter().map(|e| e.max(floor)).product();
    let cell_m = (volume / count as f64).cbrt();
    // A non-finite position makes the cell size or the build fail; the divergence check reports it.
    if !cell_m.is_finite() || live.grid.build(&live.x, &live.y, &live.z, cell_m).is_err() {
        return (f64::NAN, 0);
    }
    match min_separation(&live.grid, &live.radii_m) {
        Ok(sep) => (sep.min_distance_m, sep.collisions),
        Err(_) => (f64::INFINITY, 0),
    }
}
