//! What a simulation is built from ([`SimulationConfig`], [`SatelliteInit`]), why it can stop or refuse
//! to start ([`SimError`], typed variants carrying the numbers), and what a finished run totals
//! ([`RunTotals`]).

use thiserror::Error;

use crate::dynamics::PhysicalProperties;
use crate::environment::{Obstacle, Threat};
use crate::integrate::{IntegrateError, IntegratorMethod, Tolerances};
use crate::metrics::FiveElements;
use crate::orbit::{CartesianState, EarthModel, RelativeStateHill};
use crate::swarm::actuator::Actuator;
use crate::swarm::dynamics::DynamicsModel;
use crate::swarm::law::{CommandKind, Law, LawError};
use crate::swarm::simulation::tracked::TrackedObject;

/// When the guidance law is evaluated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ControlTiming {
    /// Inside the integrator's right-hand side; the swarm is integrated as one coupled system. Law
    /// states are updated once per integration step (`step_s`).
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
    /// The ring neighbourhood: when given, each satellite senses this many live, linked satellites
    /// nearest ahead along the orbit and as many behind, at any distance, instead of those within
    /// `range_m` (threats and obstacles are still sensed within range).
    pub ring_neighbours: Option<usize>,
}

impl Sensing {
    /// Whether the satellites' navigation states carry noise.
    pub fn has_navigation_noise(&self) -> bool {
        self.position_noise_m > 0.0 || self.velocity_noise_mps > 0.0
    }
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
    /// Physical properties of the virtual reference orbit, for the force models that read them (drag,
    /// SRP; the scenario layer's default is the swarm's mean). A member origin uses its own.
    pub reference_properties: PhysicalProperties,
    /// Mean motion of the reference orbit \[rad/s\], given to laws.
    pub mean_motion_rad_s: f64,
    /// Length of the run \[s\].
    pub duration_s: f64,
    /// Recording cadence \[s\].
    pub record_interval_s: f64,
    /// Sensors and links.
    pub sensing: Sensing,
    /// Standard deviation of the process (acceleration) noise per satellite and Hill axis \[m/s^2\], held
    /// over a control period (sampled) or integration step (continuous); 0 for none. A disturbance: it
    /// moves the satellites but is not counted in the delta-v ledger.
    pub process_noise_m_s2: f64,
    /// Kinematic threats (straight lines in the Hill frame, or real objects' tracked paths).
    pub threats: Vec<Threat>,
    /// Spherical obstacles, static in the Hill frame or centred on a real object's tracked path.
    pub obstacles: Vec<Obstacle>,
    /// The real objects among the threats and obstacles, with their orbits (each names a threat or
    /// obstacle of tracked motion; the engine places it at t = 0 and after every segment).
    pub tracked_objects: Vec<TrackedObject>,
    /// A satellite farther than this from the LVLH origin stops the run as diverged \[m\].
    pub max_distance_m: f64,
    /// Seed of every random draw of the run.
    pub seed: u64,
}

/// The engine's relative time tolerance: two instants closer than `TIME_EPSILON × max(base step,
/// 1 s)` are the same instant ([`SimulationConfig::time_epsilon_s`]); a step shorter than that would
/// never be taken, so the scenario layer refuses steps below 1000 × `TIME_EPSILON` seconds.
pub const TIME_EPSILON: f64 = 1e-9;

impl SimulationConfig {
    /// Base step: the control period in sampled mode, the integration step in continuous mode \[s\].
    pub fn base_step_s(&self) -> f64 {
        match self.control {
            ControlTiming::Sampled { period_s } => period_s,
            ControlTiming::Continuous => self.step_s,
        }
    }

    /// The time tolerance of the run's clock \[s\]: [`TIME_EPSILON`] × max(base step, 1 s).
    pub fn time_epsilon_s(&self) -> f64 {
        TIME_EPSILON * self.base_step_s().max(1.0)
    }
}

/// One satellite at t = 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SatelliteInit {
    /// State relative to the reference orbit at t = 0, Hill frame \[m, m/s\].
    pub relative_state: RelativeStateHill,
    /// Mass, drag and SRP areas and coefficients.
    pub properties: PhysicalProperties,
    /// Physical radius \[m\] (collision counting and d_min).
    pub radius_m: f64,
    /// Thrusters.
    pub actuator: Actuator,
    /// The drag areas a law may command (`None`: the drag area stays `properties.drag_area_m2`). The
    /// initial area must be one of them.
    pub drag_attitudes: Option<crate::swarm::DragAttitudes>,
}

/// What a divergence check saw.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Divergence {
    /// A position or velocity component is NaN or infinite.
    NotFinite,
    /// The satellite is farther from the LVLH origin than allowed.
    TooFar {
        /// Its distance \[m\].
        distance_m: f64,
        /// The bound, `dynamics.max_distance_m` \[m\].
        limit_m: f64,
    },
    /// The satellite's density altitude fell below the atmosphere model's floor (re-entry: the drag
    /// model no longer applies).
    BelowAtmosphere {
        /// Its density altitude \[m\].
        altitude_m: f64,
        /// The atmosphere's floor \[m\].
        floor_m: f64,
    },
}

impl std::fmt::Display for Divergence {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Divergence::NotFinite => f.write_str("state is not finite (NaN or infinite)"),
            Divergence::TooFar {
                distance_m,
                limit_m,
            } => write!(
                f,
                "{distance_m:.3} m from the LVLH origin, beyond the allowed {limit_m} m"
            ),
            Divergence::BelowAtmosphere {
                altitude_m,
                floor_m,
            } => write!(
                f,
                "density altitude {:.3} km is below the atmosphere model's floor of {:.1} km \
                 (re-entry: drag no longer applies)",
                altitude_m / 1e3,
                floor_m / 1e3
            ),
        }
    }
}

/// Why a run stopped early or could not start. Setup errors ([`SimError::is_setup`]) are the caller's
/// input; the others happen while running.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum SimError {
    /// A tracked object could not be placed (SGP4 failed, e.g. the object decayed; its integration
    /// failed; or it is not of tracked motion).
    #[error("{object} at t = {time_s} s: {message}")]
    TrackedObject {
        /// Which threat or obstacle, by name.
        object: String,
        /// Run time \[s\].
        time_s: f64,
        /// What went wrong.
        message: String,
    },
    /// The swarm is empty.
    #[error("the swarm has no satellite (allowed: 1 or more)")]
    NoSatellites,
    /// The sensing range is not a positive finite number.
    #[error("sensing range {range_m} m is out of range (allowed: finite, > 0)")]
    SensingRange {
        /// The range given \[m\].
        range_m: f64,
    },
    /// The LVLH origin names a satellite that does not exist.
    #[error("origin member {member} does not exist (allowed: 0..{count})")]
    OriginMember {
        /// The index given.
        member: usize,
        /// Number of satellites.
        count: usize,
    },
    /// An event lies outside the run.
    #[error("event `{event}` at t = {time_s} s is outside the run [0, {duration_s}] s")]
    EventOutsideRun {
        /// What the event does.
        event: String,
        /// Its time \[s\].
        time_s: f64,
        /// Length of the run \[s\].
        duration_s: f64,
    },
    /// An event names a satellite or threat that does not exist.
    #[error(
        "event `{event}` {when} names {what} {index}, which does not exist (allowed: 0..{count})"
    )]
    EventTarget {
        /// What the event does.
        event: String,
        /// When it fires: `at t = T s`, or `on condition KEY`.
        when: String,
        /// `satellite` or `threat`.
        what: &'static str,
        /// The index given.
        index: usize,
        /// How many exist.
        count: usize,
    },
    /// The control period is too long for the law's fastest closed-loop rate.
    #[error(
        "control period {period_s} s is too long for law `{law}`, whose fastest closed-loop rate is \
         {rate_per_s:.4} 1/s: a zero-order hold needs period < {limit_s:.4} s to stay accurate \
         (unstable beyond {:.4} s)", 2.0 * limit_s
    )]
    ControlPeriodTooLong {
        /// The law.
        law: &'static str,
        /// The period \[s\].
        period_s: f64,
        /// The longest accepted period \[s\].
        limit_s: f64,
        /// The law's fastest rate \[1/s\].
        rate_per_s: f64,
    },
    /// The fixed integration step is too long for the law's fastest closed-loop rate.
    #[error(
        "integration step {step_s} s is too long for law `{law}`, whose fastest closed-loop rate is \
         {rate_per_s:.4} 1/s: RK4 needs step < {limit_s:.4} s (unstable beyond {:.4} s)",
        limit_s * 2.78 / 1.4
    )]
    StepTooLong {
        /// The law.
        law: &'static str,
        /// The step \[s\].
        step_s: f64,
        /// The longest accepted step \[s\].
        limit_s: f64,
        /// The law's fastest rate \[1/s\].
        rate_per_s: f64,
    },
    /// The longest adaptive step is too long for the law's fastest closed-loop rate under continuous
    /// control: the explicit adaptive integrator would cut every step to its stability limit, whatever
    /// its error control, and crawl.
    #[error(
        "integration step {step_s} s (the longest {integrator} step) is too long for law `{law}`, whose \
         fastest closed-loop rate is {rate_per_s:.4} 1/s under continuous control: {integrator} is \
         stable only for step < {stability_bound:.3} / rate = {:.4} s and would cut every step to that \
         (accepted: step < {limit_s:.4} s, half of it); shorten dynamics.step_s, use sampled control or \
         soften the law", 2.0 * limit_s
    )]
    AdaptiveStepTooLong {
        /// The law.
        law: &'static str,
        /// The integrator's name.
        integrator: &'static str,
        /// The longest adaptive step \[s\].
        step_s: f64,
        /// The longest accepted step \[s\].
        limit_s: f64,
        /// The law's fastest rate \[1/s\].
        rate_per_s: f64,
        /// The integrator's stability interval on the negative real axis (`h |λ|`).
        stability_bound: f64,
    },
    /// The law's command kind does not fit the dynamics (velocity commands need the kinematic model,
    /// acceleration commands a dynamic one).
    #[error("law `{law}` commands {command:?}, which the `{dynamics}` dynamics cannot follow")]
    CommandKindMismatch {
        /// The law.
        law: &'static str,
        /// What it commands.
        command: CommandKind,
        /// The dynamics model.
        dynamics: &'static str,
    },
    /// Process noise that cannot apply: negative or non-finite, or on the kinematic model (no forces).
    #[error(
        "process noise {sigma_m_s2} m/s^2 cannot apply to the `{dynamics}` dynamics (allowed: finite, \
         >= 0, and 0 on the kinematic model)"
    )]
    ProcessNoise {
        /// The standard deviation given \[m/s^2\].
        sigma_m_s2: f64,
        /// The dynamics model.
        dynamics: &'static str,
    },
    /// The inertial force set was built for other Earth constants than the simulation's.
    #[error(
        "the force set's Earth constants (mu = {forces_mu_m3_s2} m^3/s^2) are not the simulation's \
         (mu = {config_mu_m3_s2} m^3/s^2): build both from the same EarthModel"
    )]
    ForcesEarth {
        /// The force set's mu \[m^3/s^2\].
        forces_mu_m3_s2: f64,
        /// The configuration's mu \[m^3/s^2\].
        config_mu_m3_s2: f64,
    },
    /// A satellite's state became non-finite or left the allowed distance from the LVLH origin.
    #[error("satellite {satellite} diverged at t = {time_s} s: {reason}")]
    Diverged {
        /// Index of the first diverging satellite.
        satellite: usize,
        /// Time of detection \[s\].
        time_s: f64,
        /// What was seen.
        reason: Divergence,
    },
    /// The law commanded a live satellite a non-finite acceleration (or velocity, kinematic model), or
    /// one whose norm overflows: the run stops rather than apply it as zero or saturated thrust.
    #[error(
        "law `{law}` commanded satellite {satellite} [{}, {}, {}] at tick {tick} (segment from t = \
         {time_s} s): not a finite command (allowed: finite components whose norm is finite, below \
         about 1e154 m/s^2)",
        command[0], command[1], command[2]
    )]
    BadCommand {
        /// Id of the satellite (the smallest such id).
        satellite: usize,
        /// The control tick (sampled) or the tick of the segment (continuous).
        tick: u64,
        /// Start of the segment \[s\].
        time_s: f64,
        /// The law's name.
        law: String,
        /// The command after the actuator's failed axes, Hill frame \[m/s^2\] (\[m/s\] kinematic).
        command: [f64; 3],
    },
    /// A satellite's initial drag area is not one of its drag attitudes, or drag attitudes were given
    /// without a force set that computes drag.
    #[error("satellite {satellite}: {reason}")]
    DragAttitudes {
        /// Id of the satellite.
        satellite: usize,
        /// What is wrong and what is allowed.
        reason: String,
    },
    /// The law commanded a drag mode the satellite does not have, or a non-finite area.
    #[error(
        "law `{law}` commanded satellite {satellite} the drag {command} at tick {tick} (t = {time_s} s), \
         which it cannot present (allowed: {allowed})"
    )]
    BadDragCommand {
        /// Id of the satellite.
        satellite: usize,
        /// The control tick.
        tick: u64,
        /// Time of the tick \[s\].
        time_s: f64,
        /// The law's name.
        law: String,
        /// The command, as text.
        command: String,
        /// The satellite's modes or range, as text.
        allowed: String,
    },
    /// A condition event's numbers are out of range (a negative or non-finite threshold, a
    /// `threat_within_m` without threats).
    #[error("event {event}: condition `{condition}`: {reason}")]
    EventCondition {
        /// The event's index in the scenario's `[[events]]`.
        event: usize,
        /// The condition's key.
        condition: &'static str,
        /// What is wrong.
        reason: String,
    },
    /// The integrator failed (step-size underflow, non-finite derivative).
    #[error("integration failed: {0}")]
    Integration(#[from] IntegrateError),
    /// The law refused its parameters, could not start, or failed while running
    /// ([`LawError::Failed`]).
    #[error(transparent)]
    Law(#[from] LawError),
    /// The conjunction monitor could not screen a segment.
    #[error("conjunction monitor: {0}")]
    Conjunction(#[from] crate::conjunction::ConjunctionError),
    /// The recorder could not write.
    #[error("recording failed: {0}")]
    Recording(#[from] std::io::Error),
    /// The caller's cancel flag was set (a signal): the run stopped after a whole segment.
    #[error("interrupted at t = {time_s} s")]
    Interrupted {
        /// Simulated time reached \[s\].
        time_s: f64,
    },
}

impl SimError {
    /// Whether the error is about the input (the setup), as opposed to something that happened while
    /// running: a command-line tool maps the first to a usage error.
    pub fn is_setup(&self) -> bool {
        matches!(
            self,
            SimError::NoSatellites
                | SimError::SensingRange { .. }
                | SimError::OriginMember { .. }
                | SimError::EventOutsideRun { .. }
                | SimError::EventTarget { .. }
                | SimError::EventCondition { .. }
                | SimError::ControlPeriodTooLong { .. }
                | SimError::StepTooLong { .. }
                | SimError::AdaptiveStepTooLong { .. }
                | SimError::CommandKindMismatch { .. }
                | SimError::ProcessNoise { .. }
                | SimError::ForcesEarth { .. }
                | SimError::DragAttitudes { .. }
        )
    }
}

/// Refuses steps and control periods that cannot resolve the law's fastest closed-loop rate k (for the
/// lightest satellite): RK4 is stable for h·k ≤ 2.78 and a zero-order hold for T·k < 2 (first-order
/// damping); under continuous control an adaptive method's longest step must lie within its own
/// stability interval ([`IntegratorMethod::adaptive_stability_bound`]), or it cuts every step to it
/// and crawls. A margin of two on each keeps the run accurate, not merely bounded. Also refuses a command
/// kind the dynamics cannot follow.
pub fn check_law_fits(
    law: &Law,
    config: &SimulationConfig,
    min_mass_kg: f64,
) -> Result<(), SimError> {
    let kinematic = matches!(config.dynamics, DynamicsModel::Kinematic);
    let command = law.command_kind();
    if kinematic != (command == CommandKind::Velocity) {
        return Err(SimError::CommandKindMismatch {
            law: law.name(),
            command,
            dynamics: config.dynamics.name(),
        });
    }
    let Some(rate) = law.fastest_rate_per_s(min_mass_kg) else {
        return Ok(());
    };
    if let ControlTiming::Sampled { period_s } = config.control {
        if period_s * rate >= 1.0 {
            return Err(SimError::ControlPeriodTooLong {
                law: law.name(),
                period_s,
                limit_s: 1.0 / rate,
                rate_per_s: rate,
            });
        }
    }
    if config.integrator == IntegratorMethod::Rk4 && config.step_s * rate >= 1.4 {
        return Err(SimError::StepTooLong {
            law: law.name(),
            step_s: config.step_s,
            limit_s: 1.4 / rate,
            rate_per_s: rate,
        });
    }
    if let (Some(bound), ControlTiming::Continuous) =
        (config.integrator.adaptive_stability_bound(), config.control)
    {
        let limit_s = 0.5 * bound / rate;
        if config.step_s >= limit_s {
            return Err(SimError::AdaptiveStepTooLong {
                law: law.name(),
                integrator: config.integrator.name(),
                step_s: config.step_s,
                limit_s,
                rate_per_s: rate,
                stability_bound: bound,
            });
        }
    }
    Ok(())
}

/// Totals of a run so far.
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
