//! Range checks of a parsed scenario and its translation into the engine's types. Every error names the
//! file, the dotted key and what is allowed.

use std::path::Path;

use nalgebra::Vector3;
use serde::Deserialize;

use crate::dynamics::{ForceConfigError, ForceSet, PhysicalProperties};
use crate::environment::{Obstacle, Threat};
use crate::guidance::LawConfig;
use crate::integrate::Tolerances;
use crate::orbit::{
    gao_to_hill, CartesianState, EarthModel, GravityModel, KeplerianElements, RelativeStateHill,
};
use crate::relative::{Hcw, SchweighartSedwick};
use crate::scenario::initial;

mod events;
use crate::scenario::schema::{
    ControlMode, InitialSection, ListFrame, ModelName, ObstacleSection, OriginName, PerSatellite,
    SatellitesSection, ThreatSection,
};
use crate::scenario::{Scenario, ScenarioError};
use crate::swarm::{
    check_law_fits, Actuator, ControlTiming, DragAttitudes, DynamicsModel, Event, Law, Origin,
    SatelliteInit, Sensing, SimError, SimulationConfig, SwarmFacts, MAX_DRAG_MODES,
};
use events::events;

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
            return Err(c.invalid(
                &scenario.event_key(k),
                format!(
                    "a law event of the scenario's own law cannot apply to the caller's law `{source}` \
                     (allowed with a caller's law: every event but set-law-parameters and switch-law; \
                     remove it)"
                ),
            ));
        }
        let min_mass_kg = self
            .satellites
            .iter()
            .map(|s| s.properties.mass_kg)
            .fold(f64::INFINITY, f64::min);
        let key = match check_law_fits(&law, &self.config, min_mass_kg) {
            Err(SimError::CommandKindMismatch { .. }) => "dynamics.model",
            Err(SimError::ControlPeriodTooLong { .. }) => "control.period_s",
            Err(SimError::StepTooLong { .. } | SimError::AdaptiveStepTooLong { .. }) => {
                "dynamics.step_s"
            }
            _ => "law",
        };
        self.law = check_law(
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

struct Checker<'a> {
    file: &'a str,
}

impl Checker<'_> {
    fn invalid(&self, key: &str, message: impl Into<String>) -> ScenarioError {
        ScenarioError::Invalid {
            file: self.file.to_string(),
            key: key.to_string(),
            message: message.into(),
        }
    }

    /// `value` must be finite and > 0.
    fn positive(&self, key: &str, value: f64) -> Result<f64, ScenarioError> {
        if value.is_finite() && value > 0.0 {
            Ok(value)
        } else {
            Err(self.invalid(
                key,
                format!("{value} is out of range (allowed: finite, > 0)"),
            ))
        }
    }

    /// A step or period \[s\]: finite and at least [`MIN_STEP_S`] (a shorter one is below the engine's
    /// time tolerance and would never be taken).
    fn step(&self, key: &str, value: f64) -> Result<f64, ScenarioError> {
        if value.is_finite() && value >= MIN_STEP_S {
            Ok(value)
        } else {
            Err(self.invalid(
                key,
                format!(
                    "{value:e} s is out of range (allowed: finite, >= {MIN_STEP_S:e} s: a shorter step \
                     is below the engine's time tolerance and would never be integrated)"
                ),
            ))
        }
    }

    /// `value` must be finite and >= 0.
    fn non_negative(&self, key: &str, value: f64) -> Result<f64, ScenarioError> {
        if value.is_finite() && value >= 0.0 {
            Ok(value)
        } else {
            Err(self.invalid(
                key,
                format!("{value} is out of range (allowed: finite, >= 0)"),
            ))
        }
    }

    fn finite(&self, key: &str, values: &[f64]) -> Result<(), ScenarioError> {
        match values.iter().find(|v| !v.is_finite()) {
            Some(v) => Err(self.invalid(key, format!("{v} is not a finite number"))),
            None => Ok(()),
        }
    }

    fn index(&self, key: &str, index: usize, count: usize) -> Result<usize, ScenarioError> {
        if index < count {
            Ok(index)
        } else {
            Err(self.invalid(
                key,
                format!(
                    "satellite {index} does not exist (allowed: 0..={})",
                    count.saturating_sub(1)
                ),
            ))
        }
    }
}

/// Validates and translates a scenario.
pub fn prepare(scenario: &Scenario) -> Result<Prepared, ScenarioError> {
    let f = &scenario.file;
    let sources = scenario.sources();
    let c = Checker { file: &sources };
    if f.name.trim().is_empty() {
        return Err(c.invalid("name", "must not be empty"));
    }
    let duration_s = c.positive("duration_s", f.duration_s)?;
    let record_interval_s = c.positive("record_interval_s", f.record_interval_s)?;
    if record_interval_s > duration_s {
        return Err(c.invalid(
            "record_interval_s",
            format!("{record_interval_s} is longer than duration_s = {duration_s} (allowed: (0, duration_s])"),
        ));
    }

    // Earth.
    let d = EarthModel::WGS84_EGM96;
    let earth = EarthModel {
        mu_m3_s2: c.positive("earth.mu_m3_s2", f.earth.mu_m3_s2.unwrap_or(d.mu_m3_s2))?,
        equatorial_radius_m: c.positive(
            "earth.equatorial_radius_m",
            f.earth.equatorial_radius_m.unwrap_or(d.equatorial_radius_m),
        )?,
        j2: c.non_negative("earth.j2", f.earth.j2.unwrap_or(d.j2))?,
    };

    // Dynamics and integration.
    let dy = &f.dynamics;
    let step_s = c.step("dynamics.step_s", dy.step_s)?;
    let rtol = c.positive("dynamics.rtol", dy.rtol)?;
    if rtol >= 1.0 {
        return Err(c.invalid(
            "dynamics.rtol",
            format!("{rtol} is out of range (allowed: (0, 1))"),
        ));
    }
    let atol = c.positive("dynamics.atol", dy.atol)?;
    let max_distance_m = c.positive("dynamics.max_distance_m", dy.max_distance_m)?;

    // Reference orbit.
    let (reference, elements) = reference_orbit(&c, scenario, &earth)?;
    let mean_motion_rad_s = earth.mean_motion_rad_s(elements.semi_major_axis_m);
    let epoch = crate::time::parse_epoch_utc(
        f.epoch_utc
            .as_deref()
            .unwrap_or(crate::time::DEFAULT_EPOCH_UTC),
    )
    .map_err(|e| c.invalid("epoch_utc", e))?;
    let dynamics = match (dy.model, &dy.forces) {
        (ModelName::J2 | ModelName::TwoBody, Some(forces)) => {
            force_set(&c, dy.model, forces, &earth, epoch)?
        }
        (_, Some(_)) => {
            return Err(c.invalid(
                "dynamics.forces",
                "force models act on inertial truth only (allowed: with model = \"j2\" or \
                 \"two-body\"; the relative and kinematic models have their own equations)",
            ))
        }
        (ModelName::J2, None) => DynamicsModel::inertial(GravityModel::J2, earth),
        (ModelName::TwoBody, None) => DynamicsModel::inertial(GravityModel::TwoBody, earth),
        (ModelName::Kinematic, None) => DynamicsModel::Kinematic,
        (ModelName::Hcw | ModelName::J2Linear, None) => {
            if elements.eccentricity > LINEAR_MODEL_MAX_ECCENTRICITY {
                return Err(c.invalid(
                    "dynamics.model",
                    format!(
                        "the linear relative models assume a circular reference orbit; its \
                         eccentricity is {:.5} (allowed: <= {LINEAR_MODEL_MAX_ECCENTRICITY})",
                        elements.eccentricity
                    ),
                ));
            }
            if dy.model == ModelName::Hcw {
                DynamicsModel::Hcw(Hcw::new(mean_motion_rad_s))
            } else {
                DynamicsModel::J2Linear(SchweighartSedwick::new(
                    elements.semi_major_axis_m,
                    elements.inclination_rad,
                    earth.mu_m3_s2,
                    earth.equatorial_radius_m,
                    earth.j2,
                ))
            }
        }
    };

    // Steps and periods against the orbit period (the kinematic model has no orbital dynamics).
    let period_s = std::f64::consts::TAU / mean_motion_rad_s;
    let max_step_s = MAX_STEP_FRACTION_OF_PERIOD * period_s;
    if dy.model != ModelName::Kinematic
        && dy.integrator == crate::integrate::IntegratorMethod::Rk4
        && step_s > max_step_s
    {
        return Err(c.invalid(
            "dynamics.step_s",
            format!(
                "{step_s} s is too long for the fixed-step RK4 integrator on an orbit of period \
                 {period_s:.1} s (allowed: (0, {max_step_s:.3}] s, 1/100 of the period, so that the \
                 integration error stays below about 1e-6 rad per orbit)"
            ),
        ));
    }
    if dy.integrator == crate::integrate::IntegratorMethod::Rk4 && record_interval_s < step_s {
        return Err(c.invalid(
            "record_interval_s",
            format!(
                "{record_interval_s} s is shorter than dynamics.step_s = {step_s} s (allowed: \
                 [dynamics.step_s, duration_s]: records are taken at steps)"
            ),
        ));
    }

    // Control timing.
    let control = match (f.control.mode, f.control.period_s) {
        (ControlMode::Continuous, None) => ControlTiming::Continuous,
        (ControlMode::Continuous, Some(_)) => {
            return Err(c.invalid(
                "control.period_s",
                "applies only to mode = \"sampled\" (remove it, or set mode = \"sampled\")",
            ))
        }
        (ControlMode::Sampled, None) => {
            return Err(c.invalid("control.period_s", "is required with mode = \"sampled\""))
        }
        (ControlMode::Sampled, Some(p)) => {
            let p = c.step("control.period_s", p)?;
            if dy.model != ModelName::Kinematic && p > max_step_s {
                return Err(c.invalid(
                    "control.period_s",
                    format!(
                        "{p} s is too long for an orbit of period {period_s:.1} s (allowed: (0, \
                         {max_step_s:.3}] s, 1/100 of the period: a coarser control cannot follow the \
                         orbital dynamics it acts on)"
                    ),
                ));
            }
            ControlTiming::Sampled { period_s: p }
        }
    };

    // Satellites.
    let s = &f.satellites;
    let count = s.count;
    if !(1..=MAX_SATELLITES).contains(&count) {
        return Err(c.invalid(
            "satellites.count",
            format!(
                "{count} is out of range (allowed: >= 1 and <= {MAX_SATELLITES}; beyond 10^7 satellites the \
                 run needs more memory and time than one machine has)"
            ),
        ));
    }
    if f.output.oem && !f.output.trajectory {
        return Err(c.invalid(
            "output.oem",
            "true needs output.trajectory = true (the OEM is written from trajectory.csv)",
        ));
    }
    // Run and output size: a tiny step or record interval that would run or write far beyond what a
    // user means is refused unless asked for explicitly.
    if !f.output.allow_large {
        let base_step_s = match control {
            ControlTiming::Sampled { period_s } => period_s.min(step_s),
            ControlTiming::Continuous => step_s,
        };
        let satellite_steps = duration_s / base_step_s * count as f64;
        if satellite_steps > MAX_SATELLITE_STEPS {
            let key = match control {
                ControlTiming::Sampled { period_s } if period_s < step_s => "control.period_s",
                _ => "dynamics.step_s",
            };
            return Err(c.invalid(
                key,
                format!(
                    "{base_step_s} s over duration_s = {duration_s} s for {count} satellites is \
                     {satellite_steps:.3e} satellite-steps (allowed: <= {MAX_SATELLITE_STEPS:.0e} unless \
                     [output] allow_large = true)"
                ),
            ));
        }
        let rows = (duration_s / record_interval_s + 1.0)
            * if f.output.trajectory {
                count as f64
            } else {
                1.0
            };
        if rows > MAX_OUTPUT_ROWS {
            return Err(c.invalid(
                "record_interval_s",
                format!(
                    "{record_interval_s} s over duration_s = {duration_s} s writes {rows:.3e} rows \
                     (allowed: <= {MAX_OUTPUT_ROWS:.0e} unless [output] allow_large = true; or turn \
                     [output] trajectory off)"
                ),
            ));
        }
    }
    let origin = match (f.reference.origin, f.reference.origin_member) {
        (OriginName::Virtual, None) => Origin::VirtualReference,
        (OriginName::Virtual, Some(_)) => {
            return Err(c.invalid(
                "reference.origin_member",
                "applies only to origin = \"member\"",
            ))
        }
        (OriginName::Member, None) => {
            return Err(c.invalid(
                "reference.origin_member",
                "is required with origin = \"member\"",
            ))
        }
        (OriginName::Member, Some(k)) => {
            Origin::Member(c.index("reference.origin_member", k, count)?)
        }
    };
    let mass_kg = c.positive("satellites.mass_kg", s.mass_kg)?;
    let forces = dynamics.forces();
    let drag = forces.is_some_and(|f| f.uses_drag_properties());
    let srp = forces.is_some_and(|f| f.uses_srp_properties());
    let tick_s = match control {
        ControlTiming::Sampled { period_s } => period_s.min(step_s),
        ControlTiming::Continuous => step_s,
    };
    let drag_attitudes = drag_attitudes(&c, s, drag, tick_s)?;
    let drag_areas = per_satellite(
        &c,
        "drag_area_m2",
        &s.drag_area_m2,
        drag,
        drag_attitudes.map(|a| a.min_area_m2()),
        count,
    )?;
    if let Some(attitudes) = &drag_attitudes {
        if let Some((id, area)) = drag_areas
            .iter()
            .enumerate()
            .find(|(_, a)| !attitudes.admits(**a))
        {
            return Err(c.invalid(
                "satellites.drag_area_m2",
                format!(
                    "{area} m^2 (satellite {id}) is not one of the drag attitudes (allowed: {})",
                    attitudes.describe()
                ),
            ));
        }
    }
    let drag_coefficients = per_satellite(
        &c,
        "drag_coefficient",
        &s.drag_coefficient,
        drag,
        Some(2.2),
        count,
    )?;
    let srp_areas = per_satellite(&c, "srp_area_m2", &s.srp_area_m2, srp, None, count)?;
    let reflectivities = per_satellite(
        &c,
        "reflectivity_coefficient",
        &s.reflectivity_coefficient,
        srp,
        Some(1.5),
        count,
    )?;
    let radius_m = c.non_negative("satellites.radius_m", s.radius_m)?;
    let max_accel = match s.max_accel_mps2 {
        Some(a) => c.positive("satellites.max_accel_mps2", a)?,
        None => f64::INFINITY,
    };
    // SS model of the reference orbit at t = 0 (as the engine gives laws): for averaged-J2 draws.
    let reference_model = match dynamics {
        DynamicsModel::J2Linear(model) => model,
        _ => {
            let h = reference.specific_angular_momentum_m2_s();
            let j2 = if dynamics.reference_has_j2() {
                earth.j2
            } else {
                0.0
            };
            SchweighartSedwick::new(
                reference.position_m.norm(),
                (h.z / h.norm()).acos(),
                earth.mu_m3_s2,
                earth.equatorial_radius_m,
                j2,
            )
        }
    };
    let origin_member = match origin {
        Origin::Member(k) => Some(k),
        Origin::VirtualReference => None,
    };
    let states = initial_states(
        &c,
        scenario,
        count,
        mean_motion_rad_s,
        (&reference_model, origin_member),
    )?;
    let mut satellites: Vec<SatelliteInit> = states
        .into_iter()
        .enumerate()
        .map(|(id, relative_state)| SatelliteInit {
            relative_state,
            properties: PhysicalProperties {
                mass_kg,
                drag_area_m2: drag_areas[id],
                drag_coefficient: drag_coefficients[id],
                srp_area_m2: srp_areas[id],
                reflectivity_coefficient: reflectivities[id],
            },
            radius_m,
            actuator: Actuator::new(max_accel, s.accel_limit),
            drag_attitudes,
        })
        .collect();
    for (k, o) in s.overrides.iter().enumerate() {
        let key = |name: &str| format!("satellites.overrides[{k}].{name}");
        for &id in &o.ids {
            c.index(&key("ids"), id, count)?;
            let sat = &mut satellites[id];
            if let Some(m) = o.mass_kg {
                sat.properties.mass_kg = c.positive(&key("mass_kg"), m)?;
            }
            let p = &mut sat.properties;
            for (name, value, target, used) in [
                ("drag_area_m2", o.drag_area_m2, &mut p.drag_area_m2, drag),
                (
                    "drag_coefficient",
                    o.drag_coefficient,
                    &mut p.drag_coefficient,
                    drag,
                ),
                ("srp_area_m2", o.srp_area_m2, &mut p.srp_area_m2, srp),
                (
                    "reflectivity_coefficient",
                    o.reflectivity_coefficient,
                    &mut p.reflectivity_coefficient,
                    srp,
                ),
            ] {
                if let Some(v) = value {
                    if !used {
                        return Err(unused_property(&c, &key(name)));
                    }
                    *target = v;
                }
            }
            if let Some(r) = o.radius_m {
                sat.radius_m = c.non_negative(&key("radius_m"), r)?;
            }
            if let Some(a) = o.max_accel_mps2 {
                sat.actuator.max_accel_m_s2 = c.positive(&key("max_accel_mps2"), a)?;
            }
        }
    }

    for (id, sat) in satellites.iter().enumerate() {
        sat.properties
            .validate("satellites.")
            .map_err(|e| force_error(&c, e, "", Some(id)))?;
    }
    let reference_properties = reference_properties(&c, &f.reference, &satellites, drag, srp)?;
    if dy.model != ModelName::Kinematic {
        check_initial_above_ground(
            &c,
            &satellites,
            reference.position_m.norm(),
            earth.equatorial_radius_m,
        )?;
    }
    check_initial_distances(&c, &satellites, origin, max_distance_m)?;
    if !s.allow_initial_overlap {
        check_initial_overlap(&c, &satellites)?;
    }

    // Sensing.
    let range_m = c.positive("sensing.range_m", f.sensing.range_m)?;
    let position_noise_m =
        c.non_negative("sensing.position_noise_m", f.sensing.position_noise_m)?;
    if position_noise_m > range_m {
        return Err(c.invalid(
            "sensing.position_noise_m",
            format!(
                "{position_noise_m} m is larger than sensing.range_m = {range_m} m (allowed: [0, \
                 sensing.range_m]: a 1-sigma error beyond the range makes every sensed position noise)"
            ),
        ));
    }
    let velocity_noise_mps =
        c.non_negative("sensing.velocity_noise_mps", f.sensing.velocity_noise_mps)?;
    let max_velocity_noise = MAX_VELOCITY_NOISE_FACTOR * mean_motion_rad_s * range_m;
    if velocity_noise_mps > max_velocity_noise {
        return Err(c.invalid(
            "sensing.velocity_noise_mps",
            format!(
                "{velocity_noise_mps} m/s is out of range (allowed: [0, {max_velocity_noise:.3e}] m/s, \
                 10 n R with n = {mean_motion_rad_s:.3e} rad/s and R = sensing.range_m: orbital \
                 relative velocities across the sensing range are about 2 n R)"
            ),
        ));
    }
    let ring_neighbours = match f.sensing.ring_neighbours {
        Some(0) => {
            return Err(c.invalid(
                "sensing.ring_neighbours",
                "0 is out of range (allowed: an integer >= 1, the satellites sensed on each side along \
                 the orbit; leave the key out to sense by range)",
            ))
        }
        k => k.map(|k| k as usize),
    };
    let sensing = Sensing {
        range_m,
        position_noise_m,
        velocity_noise_mps,
        ring_neighbours,
    };

    let process_noise_m_s2 =
        c.non_negative("dynamics.process_noise_mps2", dy.process_noise_mps2)?;
    if process_noise_m_s2 > 0.0 && dynamics == DynamicsModel::Kinematic {
        return Err(c.invalid(
            "dynamics.process_noise_mps2",
            "the kinematic model has no forces to disturb (allowed: 0 with model = \"kinematic\")",
        ));
    }
    let threats = threats(&c, &f.threats)?;
    let obstacles = obstacles(&c, &f.obstacles)?;
    if !s.allow_start_in_obstacle {
        check_initial_outside_obstacles(&c, &satellites, origin, &obstacles)?;
    }

    let config = SimulationConfig {
        earth,
        dynamics,
        integrator: dy.integrator,
        step_s,
        tolerances: Tolerances {
            relative: rtol,
            absolute: atol,
        },
        control,
        origin,
        reference,
        reference_properties,
        mean_motion_rad_s,
        duration_s,
        record_interval_s,
        sensing,
        process_noise_m_s2,
        threats,
        obstacles,
        max_distance_m,
        seed: f.seed,
    };

    // Law and events, each law and parameter set checked against the timing now, not when it applies.
    let min_mass_kg = satellites
        .iter()
        .map(|s| s.properties.mass_kg)
        .fold(f64::INFINITY, f64::min);
    let law = build_law(&c, "law", &f.law, &config, count, min_mass_kg)?;
    let events = events(&c, scenario, count, &config, min_mass_kg)?;
    let warnings = law_warnings(&f.law, &satellites);
    Ok(Prepared {
        epoch,
        name: f.name.clone(),
        config,
        satellites,
        law,
        events,
        write_trajectory: f.output.trajectory,
        tags: f.output.tags.clone(),
        law_source: None,
        warnings,
    })
}

/// The load-time warnings about the scenario's `[law]` at t = 0 (see [`Prepared::warnings`]): for the
/// `pigeon` law with pattern switching, an initial egalitarian link graph that is not connected
/// (pairs within `egalitarian_range_m − link_delay_m` in the law's y–z plane,
/// `docs/methods/pigeon.md`).
fn law_warnings(law: &LawConfig, satellites: &[SatelliteInit]) -> Vec<String> {
    match law {
        LawConfig::Pigeon(p) => {
            let positions: Vec<Vector3<f64>> = satellites
                .iter()
                .map(|s| s.relative_state.position_m)
                .collect();
            crate::guidance::pigeon::connectivity::initial_link_warning(&positions, p)
                .into_iter()
                .collect()
        }
        _ => Vec::new(),
    }
}

/// Builds a law and checks that it fits the dynamics and timing; an error names `key` (the law's table,
/// or the event that sets it) and, for a timing that cannot resolve the law, the timing key too.
fn build_law(
    c: &Checker<'_>,
    key: &str,
    law: &LawConfig,
    config: &SimulationConfig,
    count: usize,
    min_mass_kg: f64,
) -> Result<Law, ScenarioError> {
    let built = law.build().map_err(|e| c.invalid(key, e.to_string()))?;
    check_law(c, key, built, config, count, min_mass_kg)
}

/// Checks that a built law fits the dynamics and timing and the swarm; an error names `key` as
/// [`build_law`] does.
fn check_law(
    c: &Checker<'_>,
    key: &str,
    built: Law,
    config: &SimulationConfig,
    count: usize,
    min_mass_kg: f64,
) -> Result<Law, ScenarioError> {
    check_law_fits(&built, config, min_mass_kg).map_err(|e| {
        let hint = match e {
            SimError::ControlPeriodTooLong { .. } => "; shorten control.period_s or soften the law",
            SimError::StepTooLong { .. } => "; shorten dynamics.step_s or soften the law",
            SimError::AdaptiveStepTooLong { .. } => "",
            SimError::CommandKindMismatch { .. } => "; choose another dynamics.model or law",
            _ => "",
        };
        c.invalid(key, format!("{e}{hint}"))
    })?;
    built
        .check_swarm(&swarm_facts(config, count))
        .map_err(|e| c.invalid(key, e.to_string()))?;
    Ok(built)
}

/// What a law may check about the swarm, from the scenario (see [`SwarmFacts`]).
fn swarm_facts(config: &SimulationConfig, count: usize) -> SwarmFacts {
    SwarmFacts {
        sensing_range_m: config.sensing.range_m,
        count,
        threat_velocities_hill_mps: config
            .threats
            .iter()
            .map(|t| t.velocity_hill_mps())
            .collect(),
    }
}

/// `current` with the keys of a `set-law-parameters` table replaced, re-validated by deserialisation
/// (unknown keys and wrong types are refused with the deserialiser's message; the law's name cannot
/// change this way: that is `switch-law`).
pub fn merge_law_parameters(
    current: &LawConfig,
    update: &toml::Table,
) -> Result<LawConfig, String> {
    if update.contains_key("name") {
        return Err("`name` cannot be changed by set-law-parameters (use switch-law)".into());
    }
    let mut table = toml::Table::try_from(current).map_err(|e| e.to_string())?;
    for (key, value) in update {
        table.insert(key.clone(), value.clone());
    }
    <LawConfig as Deserialize>::deserialize(table).map_err(|e| e.to_string())
}

/// The threats of the scenario.
fn threats(c: &Checker<'_>, sections: &[ThreatSection]) -> Result<Vec<Threat>, ScenarioError> {
    sections
        .iter()
        .enumerate()
        .map(|(k, s)| {
            let key = |name: &str| format!("threats[{k}].{name}");
            let name = s.name.clone().unwrap_or_else(|| format!("threat-{k}"));
            let danger = c.non_negative(&key("danger_radius_m"), s.danger_radius_m)?;
            let by_state = s.position_hill_m.is_some() || s.velocity_hill_mps.is_some();
            let by_aim = s.aim_point_hill_m.is_some()
                || s.direction_hill.is_some()
                || s.speed_mps.is_some()
                || s.arrival_time_s.is_some();
            let threat = match (by_state, by_aim) {
                (true, false) => {
                    let (Some(p), Some(v)) = (s.position_hill_m, s.velocity_hill_mps) else {
                        return Err(c.invalid(
                            &key("position_hill_m"),
                            "position_hill_m and velocity_hill_mps go together (one is missing)",
                        ));
                    };
                    c.finite(&key("position_hill_m"), &p)?;
                    c.finite(&key("velocity_hill_mps"), &v)?;
                    let at = s.at_time_s.unwrap_or(0.0);
                    c.finite(&key("at_time_s"), &[at])?;
                    Threat::from_state(name, at, Vector3::from(p), Vector3::from(v), danger)
                }
                (false, true) => {
                    if s.at_time_s.is_some() {
                        return Err(c.invalid(&key("at_time_s"), "goes with position_hill_m, not with an aim"));
                    }
                    let (Some(aim), Some(direction), Some(speed), Some(arrival)) =
                        (s.aim_point_hill_m, s.direction_hill, s.speed_mps, s.arrival_time_s)
                    else {
                        return Err(c.invalid(
                            &key("aim_point_hill_m"),
                            "an aimed threat needs aim_point_hill_m, direction_hill, speed_mps and arrival_time_s",
                        ));
                    };
                    c.finite(&key("aim_point_hill_m"), &aim)?;
                    c.finite(&key("direction_hill"), &direction)?;
                    c.positive(&key("speed_mps"), speed)?;
                    c.finite(&key("arrival_time_s"), &[arrival])?;
                    Threat::from_aim(
                        name,
                        Vector3::from(aim),
                        Vector3::from(direction),
                        speed,
                        arrival,
                        danger,
                    )
                }
                _ => {
                    return Err(c.invalid(
                        &format!("threats[{k}]"),
                        "give either position_hill_m + velocity_hill_mps (+ at_time_s) or \
                         aim_point_hill_m + direction_hill + speed_mps + arrival_time_s",
                    ))
                }
            }
            .map_err(|e| c.invalid(&format!("threats[{k}]"), e.to_string()))?;
            match s.detection_range_m {
                Some(r) => threat
                    .with_detection_range_m(c.positive(&key("detection_range_m"), r)?)
                    .map_err(|e| c.invalid(&key("detection_range_m"), e.to_string())),
                None => Ok(threat),
            }
        })
        .collect()
}

/// The obstacles of the scenario.
fn obstacles(
    c: &Checker<'_>,
    sections: &[ObstacleSection],
) -> Result<Vec<Obstacle>, ScenarioError> {
    sections
        .iter()
        .enumerate()
        .map(|(k, s)| {
            let key = |name: &str| format!("obstacles[{k}].{name}");
            let name = s.name.clone().unwrap_or_else(|| format!("obstacle-{k}"));
            c.finite(&key("center_hill_m"), &s.center_hill_m)?;
            let radius = c.positive(&key("radius_m"), s.radius_m)?;
            let obstacle = Obstacle::new(name, Vector3::from(s.center_hill_m), radius)
                .map_err(|e| c.invalid(&format!("obstacles[{k}]"), e.to_string()))?;
            match s.detection_range_m {
                Some(r) => obstacle
                    .with_detection_range_m(c.positive(&key("detection_range_m"), r)?)
                    .map_err(|e| c.invalid(&key("detection_range_m"), e.to_string())),
                None => Ok(obstacle),
            }
        })
        .collect()
}

/// The reference orbit's ECI state at t = 0 and its osculating elements.
fn reference_orbit(
    c: &Checker<'_>,
    scenario: &Scenario,
    earth: &EarthModel,
) -> Result<(CartesianState, KeplerianElements), ScenarioError> {
    let r = &scenario.file.reference;
    let by_state = r.position_eci_m.is_some() || r.velocity_eci_mps.is_some();
    let by_elements = r.semi_major_axis_m.is_some()
        || r.altitude_m.is_some()
        || r.eccentricity.is_some()
        || r.inclination_deg.is_some()
        || r.raan_deg.is_some()
        || r.arg_perigee_deg.is_some()
        || r.true_anomaly_deg.is_some();
    let mu = earth.mu_m3_s2;
    if by_state && by_elements {
        return Err(c.invalid(
            "reference",
            "give either classical elements or position_eci_m + velocity_eci_mps, not both",
        ));
    }
    if by_state {
        let (Some(p), Some(v)) = (r.position_eci_m, r.velocity_eci_mps) else {
            return Err(c.invalid(
                "reference",
                "position_eci_m and velocity_eci_mps go together (one is missing)",
            ));
        };
        c.finite("reference.position_eci_m", &p)?;
        c.finite("reference.velocity_eci_mps", &v)?;
        let state = CartesianState::new(Vector3::from(p), Vector3::from(v));
        let r_m = state.position_m.norm();
        if r_m < earth.equatorial_radius_m {
            return Err(c.invalid(
                "reference.position_eci_m",
                format!(
                    "|r| = {r_m} m is inside the Earth (radius {} m); this looks like kilometres \
                     written as metres (allowed: a perigee altitude >= {MIN_PERIGEE_ALTITUDE_M} m)",
                    earth.equatorial_radius_m
                ),
            ));
        }
        if r_m > MAX_APOGEE_RADIUS_M {
            return Err(c.invalid(
                "reference.position_eci_m",
                format!(
                    "|r| = {r_m:.6e} m is beyond the Earth's Hill sphere (allowed: <= \
                     {MAX_APOGEE_RADIUS_M:e} m)"
                ),
            ));
        }
        let elements = KeplerianElements::from_cartesian(&state, mu)
            .map_err(|e| c.invalid("reference.position_eci_m", e.to_string()))?;
        check_orbit_size(c, "reference.position_eci_m", &elements, earth)?;
        return Ok((state, elements));
    }
    let a = match (r.semi_major_axis_m, r.altitude_m) {
        (Some(a), None) => {
            let a = c.positive("reference.semi_major_axis_m", a)?;
            if a < earth.equatorial_radius_m {
                return Err(c.invalid(
                    "reference.semi_major_axis_m",
                    format!(
                        "{a} m is inside the Earth (radius {} m); this looks like kilometres \
                         written as metres (did you mean {:e} m?) (allowed: a perigee altitude >= \
                         {MIN_PERIGEE_ALTITUDE_M} m)",
                        earth.equatorial_radius_m,
                        a * 1e3
                    ),
                ));
            }
            a
        }
        (None, Some(h)) => {
            let h = c.positive("reference.altitude_m", h)?;
            if h < 1000.0 {
                return Err(c.invalid(
                    "reference.altitude_m",
                    format!(
                        "{h} m looks like kilometres written as metres (did you mean {:e} m?) \
                         (allowed: >= {MIN_PERIGEE_ALTITUDE_M} m)",
                        h * 1e3
                    ),
                ));
            }
            earth.equatorial_radius_m + h
        }
        (Some(_), Some(_)) => {
            return Err(c.invalid(
                "reference.altitude_m",
                "give semi_major_axis_m or altitude_m, not both",
            ))
        }
        (None, None) => return Err(c.invalid(
            "reference.semi_major_axis_m",
            "missing: give semi_major_axis_m or altitude_m (or position_eci_m + velocity_eci_mps)",
        )),
    };
    let e = r.eccentricity.unwrap_or(0.0);
    if !(0.0..1.0).contains(&e) {
        return Err(c.invalid(
            "reference.eccentricity",
            format!("{e} is out of range (allowed: [0, 1))"),
        ));
    }
    let size_key = if r.altitude_m.is_some() {
        "reference.altitude_m"
    } else {
        "reference.semi_major_axis_m"
    };
    check_orbit_size(
        c,
        size_key,
        &KeplerianElements {
            semi_major_axis_m: a,
            eccentricity: e,
            inclination_rad: 0.0,
            raan_rad: 0.0,
            arg_perigee_rad: 0.0,
            true_anomaly_rad: 0.0,
        },
        earth,
    )?;
    let Some(inc) = r.inclination_deg else {
        return Err(c.invalid("reference.inclination_deg", "missing (allowed: [0, 180])"));
    };
    if !(0.0..=180.0).contains(&inc) {
        return Err(c.invalid(
            "reference.inclination_deg",
            format!("{inc} is out of range (allowed: [0, 180])"),
        ));
    }
    let angle = |key: &str, v: Option<f64>| -> Result<f64, ScenarioError> {
        let v = v.unwrap_or(0.0);
        c.finite(key, &[v])?;
        Ok(v.to_radians())
    };
    let elements = KeplerianElements {
        semi_major_axis_m: a,
        eccentricity: e,
        inclination_rad: inc.to_radians(),
        raan_rad: angle("reference.raan_deg", r.raan_deg)?,
        arg_perigee_rad: angle("reference.arg_perigee_deg", r.arg_perigee_deg)?,
        true_anomaly_rad: angle("reference.true_anomaly_deg", r.true_anomaly_deg)?,
    };
    let state = elements
        .to_cartesian(mu)
        .map_err(|err| c.invalid("reference", err.to_string()))?;
    Ok((state, elements))
}

/// Refuses a reference orbit whose perigee altitude is below [`MIN_PERIGEE_ALTITUDE_M`] or whose apogee
/// is beyond [`MAX_APOGEE_RADIUS_M`] (this also refuses an unbound orbit).
fn check_orbit_size(
    c: &Checker<'_>,
    key: &str,
    elements: &KeplerianElements,
    earth: &EarthModel,
) -> Result<(), ScenarioError> {
    let a = elements.semi_major_axis_m;
    let e = elements.eccentricity;
    let perigee_altitude_m = a * (1.0 - e) - earth.equatorial_radius_m;
    if perigee_altitude_m.is_nan() || perigee_altitude_m < MIN_PERIGEE_ALTITUDE_M {
        return Err(c.invalid(
            key,
            format!(
                "the perigee altitude a (1 - e) - R = {perigee_altitude_m:.1} m (a = {a} m, e = {e}) \
                 is below {MIN_PERIGEE_ALTITUDE_M} m, where drag (not modelled) ends the orbit \
                 (allowed: a (1 - e) >= {} m)",
                earth.equatorial_radius_m + MIN_PERIGEE_ALTITUDE_M
            ),
        ));
    }
    let apogee_m = a * (1.0 + e);
    if !(e < 1.0 && apogee_m <= MAX_APOGEE_RADIUS_M) {
        return Err(c.invalid(
            key,
            format!(
                "the apogee radius a (1 + e) = {apogee_m:.6e} m (a = {a:e} m, e = {e}) is beyond the \
                 Earth's Hill sphere, where the Sun governs the motion (allowed: a (1 + e) <= \
                 {MAX_APOGEE_RADIUS_M:e} m, e < 1)"
            ),
        ));
    }
    Ok(())
}

fn initial_states(
    c: &Checker<'_>,
    scenario: &Scenario,
    count: usize,
    mean_motion_rad_s: f64,
    (reference_model, origin_member): (&SchweighartSedwick, Option<usize>),
) -> Result<Vec<RelativeStateHill>, ScenarioError> {
    let seed = scenario.file.seed;
    let key = "satellites.initial";
    let v3 = Vector3::from;
    Ok(match &scenario.file.satellites.initial {
        InitialSection::Sphere {
            radius_m,
            center_hill_m,
            velocity,
        } => {
            let r = c.positive(&format!("{key}.radius_m"), *radius_m)?;
            c.finite(&format!("{key}.center_hill_m"), center_hill_m)?;
            initial::with_velocity(
                initial::sphere(seed, count, r, v3(*center_hill_m)),
                *velocity,
                mean_motion_rad_s,
            )
        }
        InitialSection::Box {
            size_hill_m,
            center_hill_m,
            velocity,
        } => {
            for (k, s) in size_hill_m.iter().enumerate() {
                c.non_negative(&format!("{key}.size_hill_m[{k}]"), *s)?;
            }
            c.finite(&format!("{key}.center_hill_m"), center_hill_m)?;
            initial::with_velocity(
                initial::cuboid(seed, count, v3(*size_hill_m), v3(*center_hill_m)),
                *velocity,
                mean_motion_rad_s,
            )
        }
        InitialSection::Shell {
            inner_radius_m,
            outer_radius_m,
            center_hill_m,
            velocity,
        } => {
            let inner = c.non_negative(&format!("{key}.inner_radius_m"), *inner_radius_m)?;
            let outer = c.positive(&format!("{key}.outer_radius_m"), *outer_radius_m)?;
            if inner > outer {
                return Err(c.invalid(
                    &format!("{key}.inner_radius_m"),
                    format!("{inner} is larger than outer_radius_m = {outer} (allowed: [0, outer_radius_m])"),
                ));
            }
            c.finite(&format!("{key}.center_hill_m"), center_hill_m)?;
            initial::with_velocity(
                initial::shell(seed, count, inner, outer, v3(*center_hill_m)),
                *velocity,
                mean_motion_rad_s,
            )
        }
        InitialSection::AveragedJ2 {
            c1_max_m,
            c4_max_m,
            amplitude_max_m,
        } => {
            let c1 = c.non_negative(&format!("{key}.c1_max_m"), *c1_max_m)?;
            let c4 = c.non_negative(&format!("{key}.c4_max_m"), *c4_max_m)?;
            let a = c.non_negative(&format!("{key}.amplitude_max_m"), *amplitude_max_m)?;
            initial::averaged_j2(
                seed,
                count,
                &crate::relative::j2_averaged::AveragedJ2::new(*reference_model),
                c1,
                c4,
                a,
                origin_member,
            )
        }
        InitialSection::Dispenser {
            spacing_m,
            release_speed_mps,
            release_dispersion_mps,
        } => {
            let spacing = c.non_negative(&format!("{key}.spacing_m"), *spacing_m)?;
            c.finite(&format!("{key}.release_speed_mps"), release_speed_mps)?;
            let dispersion = c.non_negative(
                &format!("{key}.release_dispersion_mps"),
                *release_dispersion_mps,
            )?;
            initial::dispenser(seed, count, spacing, *release_speed_mps, dispersion)
        }
        InitialSection::List { frame, states } => {
            if states.len() != count {
                return Err(c.invalid(
                    &format!("{key}.states"),
                    format!(
                        "{} states listed but satellites.count = {count}",
                        states.len()
                    ),
                ));
            }
            let mut out = Vec::with_capacity(count);
            for (i, s) in states.iter().enumerate() {
                c.finite(&format!("{key}.states[{i}]"), s)?;
                out.push(to_hill(*frame, s));
            }
            out
        }
        InitialSection::Csv { path, frame } => {
            let full = resolve_states_csv(&scenario.base_dir, path)
                .map_err(|m| c.invalid(&format!("{key}.path"), m))?;
            let rows = read_states_csv(&full).map_err(|m| c.invalid(&format!("{key}.path"), m))?;
            if rows.len() != count {
                return Err(c.invalid(
                    &format!("{key}.path"),
                    format!(
                        "{} has {} rows but satellites.count = {count}",
                        full.display(),
                        rows.len()
                    ),
                ));
            }
            rows.iter().map(|s| to_hill(*frame, s)).collect()
        }
    })
}

/// The inertial force set of `[dynamics.forces]`, for the gravity `model` named beside it (a
/// `two-body` model with a field of more than a point mass is a contradiction, refused).
fn force_set(
    c: &Checker<'_>,
    model: ModelName,
    forces: &crate::dynamics::ForcesConfig,
    earth: &EarthModel,
    epoch: crate::time::Epoch,
) -> Result<DynamicsModel, ScenarioError> {
    use crate::dynamics::GravityModelName;
    if forces.satellite.is_some() {
        return Err(c.invalid(
            "dynamics.forces.satellite",
            "is a `propagate --forces` table (allowed in a scenario: the properties as [satellites] \
             keys, e.g. satellites.drag_area_m2, and the virtual reference's as [reference] keys)",
        ));
    }
    if model == ModelName::TwoBody && forces.gravity.model != GravityModelName::PointMass {
        return Err(c.invalid(
            "dynamics.model",
            "\"two-body\" contradicts dynamics.forces.gravity.model (allowed: model = \"j2\" (the \
             default) with a [dynamics.forces] table, whose gravity.model then decides)",
        ));
    }
    let set = ForceSet::from_config(forces, earth, epoch)
        .map_err(|e| force_error(c, e, "dynamics.forces.", None))?;
    Ok(DynamicsModel::Inertial(std::sync::Arc::new(set)))
}

/// A force model's parameter error as the scenario's: the key under `prefix` (and the satellite's id
/// when the value came from a per-satellite list).
fn force_error(
    c: &Checker<'_>,
    e: ForceConfigError,
    prefix: &str,
    id: Option<usize>,
) -> ScenarioError {
    let key = match id {
        Some(id) => format!("{prefix}{} (satellite {id})", e.key),
        None => format!("{prefix}{}", e.key),
    };
    c.invalid(
        &key,
        format!("{} is out of range (allowed: {})", e.value, e.allowed),
    )
}

/// A property key given although no force model reads it.
fn unused_property(c: &Checker<'_>, key: &str) -> ScenarioError {
    c.invalid(
        key,
        "is given but no force model reads it (allowed: drag keys with [dynamics.forces.drag], SRP \
         keys with [dynamics.forces.srp])",
    )
}

/// One value per satellite of the `[satellites]` property `name`: a scalar for all, or a list of
/// `count`. Required (`default` None) or defaulted when a force model reads it (`used`); refused when
/// none does; 0 when absent and unused.
/// The satellites' drag attitudes (`drag_modes_m2` or `drag_area_range_m2`, with `drag_min_dwell_s`):
/// refused without drag in the force set, both at once, or a dwell shorter than one control tick.
fn drag_attitudes(
    c: &Checker<'_>,
    s: &SatellitesSection,
    drag: bool,
    tick_s: f64,
) -> Result<Option<DragAttitudes>, ScenarioError> {
    let dwell = |key: &str| -> Result<f64, ScenarioError> {
        if !drag {
            return Err(unused_property(c, key));
        }
        match s.drag_min_dwell_s {
            None => Ok(0.0),
            Some(d) if d.is_finite() && d >= tick_s => Ok(d),
            Some(d) => Err(c.invalid(
                "satellites.drag_min_dwell_s",
                format!(
                    "{d} s is shorter than one control tick (allowed: >= {tick_s} s, finite: the \
                     area can change only at a tick)"
                ),
            )),
        }
    };
    let allowed = format!(
        "allowed: 1 to {MAX_DRAG_MODES} distinct areas > 0 m^2, or [min, max] with 0 < min < max"
    );
    let (key, built) =
        match (&s.drag_modes_m2, s.drag_area_range_m2) {
            (Some(_), Some(_)) => return Err(c.invalid(
                "satellites.drag_area_range_m2",
                "cannot be given with satellites.drag_modes_m2 (allowed: named modes or a range)",
            )),
            (Some(modes), None) => {
                let key = "satellites.drag_modes_m2";
                let areas: Vec<f64> = modes.values().copied().collect();
                (key, DragAttitudes::modes(&areas, dwell(key)?))
            }
            (None, Some([min, max])) => {
                let key = "satellites.drag_area_range_m2";
                (key, DragAttitudes::range(min, max, dwell(key)?))
            }
            (None, None) => {
                if s.drag_min_dwell_s.is_some() {
                    return Err(c.invalid(
                    "satellites.drag_min_dwell_s",
                    "applies only with satellites.drag_modes_m2 or satellites.drag_area_range_m2",
                ));
                }
                return Ok(None);
            }
        };
    built
        .map(Some)
        .map_err(|e| c.invalid(key, format!("{e} ({allowed})")))
}

fn per_satellite(
    c: &Checker<'_>,
    name: &str,
    value: &Option<PerSatellite>,
    used: bool,
    default: Option<f64>,
    count: usize,
) -> Result<Vec<f64>, ScenarioError> {
    let key = format!("satellites.{name}");
    match (value, used) {
        (Some(_), false) => Err(unused_property(c, &key)),
        (None, false) => Ok(vec![0.0; count]),
        (None, true) => match default {
            Some(d) => Ok(vec![d; count]),
            None => Err(c.invalid(
                &key,
                "is required: a force model of [dynamics.forces] reads it (allowed: one value for \
                 every satellite, or a list of one per satellite)",
            )),
        },
        (Some(PerSatellite::All(v)), true) => Ok(vec![*v; count]),
        (Some(PerSatellite::Each(list)), true) => {
            if list.len() == count {
                Ok(list.clone())
            } else {
                Err(c.invalid(
                    &key,
                    format!(
                        "has {} values for {count} satellites (allowed: one value, or exactly one \
                         per satellite)",
                        list.len()
                    ),
                ))
            }
        }
    }
}

/// The virtual reference orbit's physical properties: each `[reference]` key given, else the swarm's
/// mean of that property (keys refused when no force model reads them).
fn reference_properties(
    c: &Checker<'_>,
    reference: &crate::scenario::schema::ReferenceSection,
    satellites: &[SatelliteInit],
    drag: bool,
    srp: bool,
) -> Result<PhysicalProperties, ScenarioError> {
    let all: Vec<PhysicalProperties> = satellites.iter().map(|s| s.properties).collect();
    let mut p = PhysicalProperties::mean(&all).unwrap_or(PhysicalProperties::point_mass(1.0));
    for (name, value, target, used) in [
        ("mass_kg", reference.mass_kg, &mut p.mass_kg, drag || srp),
        (
            "drag_area_m2",
            reference.drag_area_m2,
            &mut p.drag_area_m2,
            drag,
        ),
        (
            "drag_coefficient",
            reference.drag_coefficient,
            &mut p.drag_coefficient,
            drag,
        ),
        (
            "srp_area_m2",
            reference.srp_area_m2,
            &mut p.srp_area_m2,
            srp,
        ),
        (
            "reflectivity_coefficient",
            reference.reflectivity_coefficient,
            &mut p.reflectivity_coefficient,
            srp,
        ),
    ] {
        if let Some(v) = value {
            if !used {
                return Err(unused_property(c, &format!("reference.{name}")));
            }
            *target = v;
        }
    }
    p.validate("reference.")
        .map_err(|e| force_error(c, e, "", None))?;
    Ok(p)
}

/// Refuses an initial state farther from the frame's origin than `dynamics.max_distance_m` (the run
/// would stop at its first check with a divergence).
fn check_initial_distances(
    c: &Checker<'_>,
    satellites: &[SatelliteInit],
    origin: Origin,
    max_distance_m: f64,
) -> Result<(), ScenarioError> {
    let centre = match origin {
        Origin::Member(k) => satellites[k].relative_state.position_m,
        Origin::VirtualReference => Vector3::zeros(),
    };
    for (i, sat) in satellites.iter().enumerate() {
        let p = sat.relative_state.position_m;
        let v = sat.relative_state.velocity_mps;
        if !(p.iter().chain(v.iter()).all(|x| x.is_finite())) {
            return Err(c.invalid(
                "satellites.initial",
                format!("the initial state of satellite {i} is not finite"),
            ));
        }
        let d = (p - centre).norm();
        if d > max_distance_m {
            return Err(c.invalid(
                "dynamics.max_distance_m",
                format!(
                    "satellite {i} starts {d:.6e} m from the frame's origin, beyond \
                     dynamics.max_distance_m = {max_distance_m} m (allowed: every initial distance \
                     <= dynamics.max_distance_m; raise it or move the satellite)"
                ),
            ));
        }
    }
    Ok(())
}

/// Refuses a satellite that starts inside the Earth: its geocentric distance, the reference orbit's
/// radius `reference_radius_m` plus its Hill offset (x radial), below `earth_radius_m` \[m\].
fn check_initial_above_ground(
    c: &Checker<'_>,
    satellites: &[SatelliteInit],
    reference_radius_m: f64,
    earth_radius_m: f64,
) -> Result<(), ScenarioError> {
    for (i, sat) in satellites.iter().enumerate() {
        let p = sat.relative_state.position_m;
        let r = Vector3::new(reference_radius_m + p.x, p.y, p.z).norm();
        if r < earth_radius_m {
            return Err(c.invalid(
                "satellites.initial",
                format!(
                    "satellite {i} starts inside the Earth: {r:.6e} m from its centre (the reference \
                     orbit's radius {reference_radius_m:.6e} m plus the Hill offset [{:.6e}, {:.6e}, \
                     {:.6e}] m) (allowed: every satellite at least the Earth's radius \
                     {earth_radius_m:.6e} m from its centre; check the offsets and their unit, metres)",
                    p.x, p.y, p.z
                ),
            ));
        }
    }
    Ok(())
}

/// Refuses a satellite that starts inside an obstacle (its position, a point, closer to the obstacle's
/// centre than its radius, in the frame of the run's origin): the obstacle monitor would count an
/// incursion at t = 0.
fn check_initial_outside_obstacles(
    c: &Checker<'_>,
    satellites: &[SatelliteInit],
    origin: Origin,
    obstacles: &[Obstacle],
) -> Result<(), ScenarioError> {
    let centre = match origin {
        Origin::Member(k) => satellites[k].relative_state.position_m,
        Origin::VirtualReference => Vector3::zeros(),
    };
    for (k, obstacle) in obstacles.iter().enumerate() {
        for (i, sat) in satellites.iter().enumerate() {
            let clearance = obstacle.surface_distance_m(&(sat.relative_state.position_m - centre));
            if clearance < 0.0 {
                return Err(c.invalid(
                    "satellites.allow_start_in_obstacle",
                    format!(
                        "satellite {i} starts inside obstacles[{k}] (`{}`), {:.6e} m below its surface \
                         (allowed: every satellite outside every obstacle at t = 0; move the initial \
                         distribution or the obstacle, or set satellites.allow_start_in_obstacle = true \
                         to run it anyway)",
                        obstacle.name(),
                        -clearance
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Refuses satellites that overlap at t = 0: centres closer than (or as close as) the sum of their radii,
/// which counts coincident point satellites too. Exact, with the neighbour grid (O(N)).
fn check_initial_overlap(
    c: &Checker<'_>,
    satellites: &[SatelliteInit],
) -> Result<(), ScenarioError> {
    let n = satellites.len();
    if n < 2 {
        return Ok(());
    }
    let a_max = satellites.iter().map(|s| s.radius_m).fold(0.0, f64::max);
    let x: Vec<f64> = satellites
        .iter()
        .map(|s| s.relative_state.position_m.x)
        .collect();
    let y: Vec<f64> = satellites
        .iter()
        .map(|s| s.relative_state.position_m.y)
        .collect();
    let z: Vec<f64> = satellites
        .iter()
        .map(|s| s.relative_state.position_m.z)
        .collect();
    let mut grid = crate::grid::NeighbourGrid::new();
    // A radius of 2 a_max finds every overlapping pair; with point satellites, the smallest positive
    // radius still finds the coincident ones (the grid clamps its cell, not its inclusion rule).
    grid.build(&x, &y, &z, (2.0 * a_max).max(f64::MIN_POSITIVE))
        .map_err(|e| c.invalid("satellites.initial", e.to_string()))?;
    for i in 0..n {
        let mut hit: Option<(usize, f64)> = None;
        grid.for_each_neighbour(i, |nb| {
            if hit.is_none()
                && nb.index > i
                && nb.distance_m <= satellites[i].radius_m + satellites[nb.index].radius_m
            {
                hit = Some((nb.index, nb.distance_m));
            }
        });
        if let Some((j, d)) = hit {
            return Err(c.invalid(
                "satellites.allow_initial_overlap",
                format!(
                    "satellites {i} and {j} overlap at t = 0: their centres are {d:.6e} m apart, \
                     not more than the sum of their radii {:.6e} m (allowed: every pair farther apart \
                     than the sum of its radii; spread the initial distribution, shrink \
                     satellites.radius_m, or set satellites.allow_initial_overlap = true to run it anyway)",
                    satellites[i].radius_m + satellites[j].radius_m
                ),
            ));
        }
    }
    Ok(())
}

fn to_hill(frame: ListFrame, s: &[f64; 6]) -> RelativeStateHill {
    let p = Vector3::new(s[0], s[1], s[2]);
    let v = Vector3::new(s[3], s[4], s[5]);
    match frame {
        ListFrame::Hill => RelativeStateHill {
            position_m: p,
            velocity_mps: v,
        },
        ListFrame::Gao => RelativeStateHill {
            position_m: gao_to_hill(&p),
            velocity_mps: gao_to_hill(&v),
        },
    }
}

/// Resolves the `path` of a CSV of initial states: it must name a file inside the scenario's folder
/// (after following `..` and symbolic links); [`read_states_csv`] opens it through the bounded reader
/// (a regular file of at most [`MAX_STATES_CSV_BYTES`]).
fn resolve_states_csv(base_dir: &Path, path: &str) -> Result<std::path::PathBuf, String> {
    let base = base_dir
        .canonicalize()
        .map_err(|e| format!("the scenario's folder {}: {e}", base_dir.display()))?;
    let full = base_dir
        .join(path)
        .canonicalize()
        .map_err(|e| format!("`{path}`: {e}"))?;
    if !full.starts_with(&base) {
        return Err(format!(
            "`{path}` resolves to {}, outside the scenario's folder {} (allowed: a file in that \
             folder or below it)",
            full.display(),
            base.display()
        ));
    }
    Ok(full)
}

/// Reads a CSV of states with header `x_m,y_m,z_m,vx_mps,vy_mps,vz_mps`. Errors name the file, the line
/// and the column, never the file's content.
fn read_states_csv(path: &Path) -> Result<Vec<[f64; 6]>, String> {
    const HEADER: [&str; 6] = ["x_m", "y_m", "z_m", "vx_mps", "vy_mps", "vz_mps"];
    let mut reader = crate::input_file::open(path, MAX_STATES_CSV_BYTES)
        .map(csv::Reader::from_reader)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let header = reader
        .headers()
        .map_err(|e| format!("{}: {e}", path.display()))?
        .clone();
    let columns: Vec<&str> = header.iter().map(str::trim).collect();
    if columns != HEADER {
        return Err(format!(
            "{}: line 1 is not the required header `{}`",
            path.display(),
            HEADER.join(",")
        ));
    }
    let mut rows = Vec::new();
    for (line, record) in reader.records().enumerate() {
        let record = record.map_err(|e| format!("{}: {e}", path.display()))?;
        let mut row = [0.0; 6];
        for (k, field) in record.iter().enumerate().take(6) {
            row[k] = field.trim().parse::<f64>().map_err(|_| {
                format!(
                    "{} line {}: column {} is not a number",
                    path.display(),
                    line + 2,
                    HEADER[k]
                )
            })?;
        }
        if record.len() != 6 || row.iter().any(|v| !v.is_finite()) {
            return Err(format!(
                "{} line {}: expected 6 finite numbers",
                path.display(),
                line + 2
            ));
        }
        rows.push(row);
    }
    Ok(rows)
}
