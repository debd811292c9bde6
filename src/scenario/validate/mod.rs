//! Range checks of a parsed scenario and its translation into the engine's types, one function per
//! section (`prepare` calls them in order). Every error is an [`Invalid`] in the scenario's file: the
//! dotted key, the value, what is wrong and what is allowed.
//!
//! | file | checks |
//! | --- | --- |
//! | `settings.rs` | top-level times, `[earth]`, `[dynamics]` (integration, model, forces, process noise), `[control]`, the run's size (`[output]`), `[sensing]` |
//! | `orbit_inputs.rs` | the orbit files named (OEM, OMM, TLE of the swarm and the reference), read once; the epoch (`epoch_utc`, else the files') |
//! | `reference.rs` | `[reference]`: the orbit, the origin, the virtual reference's properties |
//! | `satellites.rs` | `[satellites]`: count, properties, drag attitudes, initial states, overrides, the start at t = 0 |
//! | `properties.rs` | the per-satellite physical properties: values, lists, distributions, `properties_file` |
//! | `states_csv.rs` | the CSV files of initial states, confined to the scenario's folder |
//! | `environment.rs` | `[[threats]]`, `[[obstacles]]` |
//! | `law.rs` | `[law]`, `[[events]]` |

mod conjunctions;
mod environment;
mod events;
mod initial_states;
mod law;
mod orbit_inputs;
mod properties;
mod reference;
mod satellites;
mod settings;
mod states_csv;

pub use law::merge_law_parameters;

use crate::invalid::Invalid;
use crate::scenario::{Scenario, ScenarioError};
use crate::swarm::{check_law_fits, Event, Law, SatelliteInit, SimError, SimulationConfig};

/// Largest run (satellites × base steps) accepted without `[output] allow_large = true`: about an hour of
/// the engine's throughput on two cores (~10^6 satellite-steps/s), far beyond any paper's run; a larger
/// count is almost always a step or duration in the wrong unit.
const MAX_SATELLITE_STEPS: f64 = 1e10;

/// Shortest `dynamics.step_s` and `control.period_s` \[s\]: 1000 × the engine's time tolerance
/// ([`crate::swarm::TIME_EPSILON`], relative to 1 s), so that every step is an instant of its own.
const MIN_STEP_S: f64 = 1e-6;

/// Largest number of CSV rows (recordings × satellites with a trajectory, recordings without) accepted
/// without `[output] allow_large = true`: about 10 GB of text.
const MAX_OUTPUT_ROWS: f64 = 5e7;

/// Largest eccentricity accepted for the circular-orbit linear models (HCW, Schweighart–Sedwick).
const LINEAR_MODEL_MAX_ECCENTRICITY: f64 = 0.01;

/// Largest `satellites.count`. Every satellite carries its state, the integrator's stages, its sensed
/// neighbours and the law's scratch (several hundred bytes to a few kB), so 10^7 satellites already need
/// several GB and hours per simulated orbit; a larger count is a typo, not a swarm this engine can run.
pub const MAX_SATELLITES: usize = 10_000_000;

/// Lowest perigee altitude of the reference orbit \[m\]: below 100 km (the Kármán line) drag brings a
/// satellite down within hours (and the atmosphere models end there).
pub const MIN_PERIGEE_ALTITUDE_M: f64 = 100e3;

/// Largest apogee radius of the reference orbit \[m\]: the Earth's Hill sphere (about 1.5 million km);
/// beyond it the Sun, not the Earth, governs the motion, and the relative models lose meaning (a radius
/// of 1e154 m or more even overflows them).
pub const MAX_APOGEE_RADIUS_M: f64 = 1.5e9;

/// A fixed integration step or a control period may be at most this fraction of the orbit period. With
/// 100 RK4 steps per orbit (n h = 0.063 rad) the phase error of an oscillation of the orbit's frequency
/// is (n h)^5 / 120 = 8e-9 rad per step, 1e-6 rad per orbit; at 10 steps per orbit it is 1e-2 rad per
/// orbit, a visibly wrong orbit. A control sampled more coarsely than that cannot follow the orbital
/// dynamics it acts on, whatever the law's own rate.
pub const MAX_STEP_FRACTION_OF_PERIOD: f64 = 0.01;

/// A velocity noise (1 sigma) may be at most this many times `n * sensing.range_m`, the relative velocity
/// scale of orbital motion across the sensing range (a bounded relative orbit of size R moves at about
/// 2 n R): beyond it the measured velocity of every neighbour is noise.
pub const MAX_VELOCITY_NOISE_FACTOR: f64 = 10.0;

/// Largest initial-state CSV file \[bytes\]: 10^7 satellites at about 100 bytes a row.
pub const MAX_STATES_CSV_BYTES: u64 = 1 << 30;

/// A validated scenario, ready to become a [`crate::swarm::Simulation`].
pub struct Prepared {
    /// Scenario name.
    pub name: String,
    /// Engine configuration.
    pub config: SimulationConfig,
    /// Satellites at t = 0.
    pub satellites: Vec<SatelliteInit>,
    /// The law at t = 0.
    pub law: Law,
    /// The event timeline.
    pub events: Vec<Event>,
    /// Whether to write the trajectory file.
    pub write_trajectory: bool,
    /// The conjunction threshold of `[conjunctions] threshold_m` \[m\] (`None`: no conjunction
    /// monitor).
    pub conjunction_threshold_m: Option<f64>,
    /// Extra metadata for the summary.
    pub tags: std::collections::BTreeMap<String, String>,
    /// The instant of t = 0.
    pub epoch: crate::time::Epoch,
    /// Where the law came from when a caller's law replaced the scenario's ([`Prepared::replace_law`]:
    /// e.g. `python:MyLaw`); `None`: the scenario's own `[law]` runs.
    pub law_source: Option<String>,
    /// Warnings found when the scenario was prepared: the run still starts. `summary.json`'s
    /// `warnings` lists them first and `satflock run` prints them when it loads the scenario. Today:
    /// the `pigeon` law (with `switching = true`) whose initial egalitarian link graph is not
    /// connected. A warning about the scenario's `[law]` starts with its key (`law.`) and is dropped
    /// by [`Prepared::replace_law`].
    pub warnings: Vec<String>,
}

impl Prepared {
    /// Replaces the scenario's law by a caller's `law` (one the scenario file cannot name: a law written
    /// in Python, a law of an embedding program); `source` says where it came from (`python:NAME`; the
    /// run's `summary.json` gives it as its `controller`, `scenario.toml` in a comment). The law is
    /// checked as the scenario's own law is: against the dynamics and the timing
    /// ([`check_law_fits`], a refusal naming `dynamics.model`, `control.period_s` or
    /// `dynamics.step_s`) and against the swarm. The scenario's law events (`set-law-parameters`,
    /// `switch-law`) are written for its own law and are refused, naming the first one.
    pub fn replace_law(
        &mut self,
        scenario: &Scenario,
        law: Law,
        source: &str,
    ) -> Result<(), ScenarioError> {
        let sources = scenario.sources();
        let c = Checker { file: &sources };
        if let Some(k) = scenario
            .file
            .events
            .iter()
            .position(|e| crate::scenario::controller::is_law_event(&e.action))
        {
            return Err(c.keys(
                &scenario.event_key(k),
                format!(
                    "is a law event of the scenario's own law: it cannot apply to the caller's law \
                     `{source}`"
                ),
                "with a caller's law: every event but set-law-parameters and switch-law; remove it",
            ));
        }
        let min_mass_kg = min_mass_kg(&self.satellites);
        let key = match check_law_fits(&law, &self.config, min_mass_kg) {
            Err(SimError::CommandKindMismatch { .. }) => "dynamics.model",
            Err(SimError::ControlPeriodTooLong { .. }) => "control.period_s",
            Err(SimError::StepTooLong { .. } | SimError::AdaptiveStepTooLong { .. }) => {
                "dynamics.step_s"
            }
            _ => "law",
        };
        self.law = law::check_law(
            &c,
            key,
            law,
            &self.config,
            self.satellites.len(),
            min_mass_kg,
        )?;
        self.law_source = Some(source.to_string());
        self.warnings.retain(|w| !w.starts_with("law."));
        Ok(())
    }
}

/// Where errors are reported: the scenario's file (and its controller's), for every section check.
pub(super) struct Checker<'a> {
    file: &'a str,
}

impl Checker<'_> {
    /// `invalid` in this file.
    pub(super) fn err(&self, invalid: Invalid) -> ScenarioError {
        ScenarioError::invalid(self.file, invalid)
    }

    /// `invalid` in this file, caused by the system's error `source`.
    pub(super) fn io(&self, invalid: Invalid, source: std::io::Error) -> ScenarioError {
        ScenarioError::invalid_io(self.file, invalid, source)
    }

    /// `value` of `key` is out of the `allowed` range.
    pub(super) fn range(
        &self,
        key: &str,
        value: impl std::fmt::Display,
        allowed: impl Into<String>,
    ) -> ScenarioError {
        self.err(Invalid::range(key, value, allowed))
    }

    /// `value` of `key` has `problem`; `allowed` says what would do.
    pub(super) fn bad(
        &self,
        key: &str,
        value: impl std::fmt::Display,
        problem: impl std::fmt::Display,
        allowed: impl Into<String>,
    ) -> ScenarioError {
        self.err(Invalid::new(key, value, problem, allowed))
    }

    /// `key` has `problem`, no single value at fault (keys that do not go together).
    pub(super) fn keys(
        &self,
        key: &str,
        problem: impl Into<String>,
        allowed: impl Into<String>,
    ) -> ScenarioError {
        self.err(Invalid::keys(key, problem, allowed))
    }

    /// `value` must be finite and > 0.
    pub(super) fn positive(&self, key: &str, value: f64) -> Result<f64, ScenarioError> {
        if value.is_finite() && value > 0.0 {
            Ok(value)
        } else {
            Err(self.range(key, value, "finite, > 0"))
        }
    }

    /// A step or period \[s\]: finite and at least [`MIN_STEP_S`] (a shorter one is below the engine's
    /// time tolerance and would never be taken).
    pub(super) fn step(&self, key: &str, value: f64) -> Result<f64, ScenarioError> {
        if value.is_finite() && value >= MIN_STEP_S {
            Ok(value)
        } else {
            Err(self.range(
                key,
                format!("{value:e} s"),
                format!(
                    "finite, >= {MIN_STEP_S:e} s: a shorter step is below the engine's time \
                     tolerance and would never be integrated"
                ),
            ))
        }
    }

    /// `value` must be finite and >= 0.
    pub(super) fn non_negative(&self, key: &str, value: f64) -> Result<f64, ScenarioError> {
        if value.is_finite() && value >= 0.0 {
            Ok(value)
        } else {
            Err(self.range(key, value, "finite, >= 0"))
        }
    }

    /// Every one of `values` must be finite.
    pub(super) fn finite(&self, key: &str, values: &[f64]) -> Result<(), ScenarioError> {
        match values.iter().find(|v| !v.is_finite()) {
            Some(v) => Err(self.bad(key, v, "is not a finite number", "finite numbers")),
            None => Ok(()),
        }
    }

    /// `index` must name one of `count` satellites.
    pub(super) fn index(
        &self,
        key: &str,
        index: usize,
        count: usize,
    ) -> Result<usize, ScenarioError> {
        if index < count {
            Ok(index)
        } else {
            Err(self.bad(
                key,
                format!("satellite {index}"),
                "does not exist",
                format!("0..={}", count.saturating_sub(1)),
            ))
        }
    }
}

/// Validates and translates a scenario: one function per section, in the order below (a scenario with
/// several faults reports the first in that order). A new section is one function and one call here.
pub fn prepare(scenario: &Scenario) -> Result<Prepared, ScenarioError> {
    let f = &scenario.file;
    let sources = scenario.sources();
    let c = Checker { file: &sources };
    let times = settings::run_times(&c, f)?;
    let earth = settings::earth(&c, &f.earth)?;
    let integration = settings::integration(&c, &f.dynamics)?;
    let inputs = orbit_inputs::read(&c, scenario)?;
    let epoch = orbit_inputs::epoch(&c, f, &inputs)?;
    let (reference, elements) = reference::reference_orbit(&c, scenario, &earth, &inputs, epoch)?;
    let mean_motion_rad_s = earth.mean_motion_rad_s(elements.semi_major_axis_m);
    let dynamics = settings::dynamics_model(&c, &f.dynamics, &earth, &elements, epoch)?;
    let period_s = std::f64::consts::TAU / mean_motion_rad_s;
    settings::check_step(&c, &f.dynamics, &integration, &times, period_s)?;
    let control = settings::control(&c, &f.control, f.dynamics.model, period_s)?;
    let count = satellites::count(&c, &f.satellites)?;
    settings::output_size(&c, f, &times, control, integration.step_s, count)?;
    let origin = reference::origin(&c, &f.reference, count)?;
    let swarm = satellites::Swarm {
        count,
        dynamics: &dynamics,
        control,
        step_s: integration.step_s,
        mean_motion_rad_s,
        reference: &reference,
        earth: &earth,
        origin,
    };
    let mut warnings = Vec::new();
    let (satellites, reference_properties) =
        satellites::satellites(&c, scenario, &swarm, &inputs, epoch, &mut warnings)?;
    satellites::check_start(&c, f, &swarm, &satellites, integration.max_distance_m)?;
    let sensing = settings::sensing(&c, &f.sensing, mean_motion_rad_s)?;
    let process_noise_m_s2 = settings::process_noise(&c, &f.dynamics, &dynamics)?;
    let environment::Environment {
        threats,
        obstacles,
        tracked_objects,
    } = environment::environment(
        &c,
        &f.threats,
        &f.obstacles,
        &inputs.threats,
        &inputs.obstacles,
        &environment::Placing {
            dynamics: &dynamics,
            earth: &earth,
            reference: &reference,
            reference_properties: &reference_properties,
            epoch,
        },
    )?;
    if !f.satellites.allow_start_in_obstacle {
        satellites::check_initial_outside_obstacles(&c, &satellites, origin, &obstacles)?;
    }

    let config = SimulationConfig {
        earth,
        dynamics,
        integrator: f.dynamics.integrator,
        step_s: integration.step_s,
        tolerances: integration.tolerances,
        control,
        origin,
        reference,
        reference_properties,
        mean_motion_rad_s,
        duration_s: times.duration_s,
        record_interval_s: times.record_interval_s,
        sensing,
        process_noise_m_s2,
        threats,
        obstacles,
        tracked_objects,
        max_distance_m: integration.max_distance_m,
        seed: f.seed,
    };

    // Law and events, each law and parameter set checked against the timing now, not when it applies.
    let min_mass_kg = min_mass_kg(&satellites);
    let law = law::build_law(&c, "law", &f.law, &config, count, min_mass_kg)?;
    let events = events::events(&c, scenario, count, &config, min_mass_kg)?;
    warnings.extend(law::law_warnings(&f.law, &satellites));
    Ok(Prepared {
        epoch,
        name: f.name.clone(),
        config,
        satellites,
        law,
        events,
        write_trajectory: f.output.trajectory,
        conjunction_threshold_m: conjunctions::threshold_m(&c, f.conjunctions.as_ref())?,
        tags: f.output.tags.clone(),
        law_source: None,
        warnings,
    })
}

/// The smallest satellite mass \[kg\] (the laws' force limits are checked against it).
fn min_mass_kg(satellites: &[SatelliteInit]) -> f64 {
    satellites
        .iter()
        .map(|s| s.properties.mass_kg)
        .fold(f64::INFINITY, f64::min)
}
