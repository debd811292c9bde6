//! Range checks of a parsed scenario and its translation into the engine's types. Every error names the
//! file, the dotted key and what is allowed.

use std::path::Path;

use nalgebra::Vector3;
use serde::Deserialize;

use crate::environment::{Obstacle, Threat};
use crate::guidance::LawConfig;
use crate::integrate::Tolerances;
use crate::orbit::{
    gao_to_hill, CartesianState, EarthModel, GravityModel, KeplerianElements, RelativeStateHill,
};
use crate::relative::{Hcw, SchweighartSedwick};
use crate::scenario::initial;
use crate::scenario::schema::{
    ActionSection, AxisName, ControlMode, InitialSection, ListFrame, ModelName, ObstacleSection,
    OriginName, SelectionSection, ThreatSection,
};
use crate::scenario::{Scenario, ScenarioError};
use crate::swarm::{
    check_law_fits, Actuator, ControlTiming, DynamicsModel, Event, EventAction, Law, Origin,
    SatelliteInit, Selection, Sensing, SimError, SimulationConfig, ThrustAxis,
};

/// Largest eccentricity accepted for the circular-orbit linear models (HCW, Schweighart–Sedwick).
const LINEAR_MODEL_MAX_ECCENTRICITY: f64 = 0.01;

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
    let c = Checker {
        file: &scenario.source,
    };
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
    let step_s = c.positive("dynamics.step_s", dy.step_s)?;
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
    let dynamics = match dy.model {
        ModelName::J2 => DynamicsModel::Inertial(GravityModel::J2),
        ModelName::TwoBody => DynamicsModel::Inertial(GravityModel::TwoBody),
        ModelName::Kinematic => DynamicsModel::Kinematic,
        ModelName::Hcw | ModelName::J2Linear => {
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
        (ControlMode::Sampled, Some(p)) => ControlTiming::Sampled {
            period_s: c.positive("control.period_s", p)?,
        },
    };

    // Satellites.
    let s = &f.satellites;
    let count = s.count;
    if count == 0 {
        return Err(c.invalid("satellites.count", "0 is out of range (allowed: >= 1)"));
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
            let j2 = match dynamics {
                DynamicsModel::Inertial(GravityModel::J2) => earth.j2,
                _ => 0.0,
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
        .map(|relative_state| SatelliteInit {
            relative_state,
            mass_kg,
            radius_m,
            actuator: Actuator::new(max_accel, s.accel_limit),
        })
        .collect();
    for (k, o) in s.overrides.iter().enumerate() {
        let key = |name: &str| format!("satellites.overrides[{k}].{name}");
        for &id in &o.ids {
            c.index(&key("ids"), id, count)?;
            let sat = &mut satellites[id];
            if let Some(m) = o.mass_kg {
                sat.mass_kg = c.positive(&key("mass_kg"), m)?;
            }
            if let Some(r) = o.radius_m {
                sat.radius_m = c.non_negative(&key("radius_m"), r)?;
            }
            if let Some(a) = o.max_accel_mps2 {
                sat.actuator.max_accel_m_s2 = c.positive(&key("max_accel_mps2"), a)?;
            }
        }
    }

    // Sensing.
    let sensing = Sensing {
        range_m: c.positive("sensing.range_m", f.sensing.range_m)?,
        position_noise_m: c.non_negative("sensing.position_noise_m", f.sensing.position_noise_m)?,
        velocity_noise_mps: c
            .non_negative("sensing.velocity_noise_mps", f.sensing.velocity_noise_mps)?,
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
        .map(|s| s.mass_kg)
        .fold(f64::INFINITY, f64::min);
    let law = build_law(&c, "law", &f.law, &config, min_mass_kg)?;
    let events = events(&c, scenario, count, &config, min_mass_kg)?;
    Ok(Prepared {
        name: f.name.clone(),
        config,
        satellites,
        law,
        events,
        write_trajectory: f.output.trajectory,
        tags: f.output.tags.clone(),
    })
}

/// Builds a law and checks that it fits the dynamics and timing; an error names `key` (the law's table,
/// or the event that sets it) and, for a timing that cannot resolve the law, the timing key too.
fn build_law(
    c: &Checker<'_>,
    key: &str,
    law: &LawConfig,
    config: &SimulationConfig,
    min_mass_kg: f64,
) -> Result<Law, ScenarioError> {
    let built = law.build().map_err(|e| c.invalid(key, e.to_string()))?;
    check_law_fits(&built, config, min_mass_kg).map_err(|e| {
        let hint = match e {
            SimError::ControlPeriodTooLong { .. } => "; shorten control.period_s or soften the law",
            SimError::StepTooLong { .. } => "; shorten dynamics.step_s or soften the law",
            SimError::CommandKindMismatch { .. } => "; choose another dynamics.model or law",
            _ => "",
        };
        c.invalid(key, format!("{e}{hint}"))
    })?;
    Ok(built)
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
    LawConfig::deserialize(table).map_err(|e| e.to_string())
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
        let elements = KeplerianElements::from_cartesian(&state, mu)
            .map_err(|e| c.invalid("reference.position_eci_m", e.to_string()))?;
        if elements.semi_major_axis_m * (1.0 - elements.eccentricity) <= earth.equatorial_radius_m {
            return Err(c.invalid(
                "reference.position_eci_m",
                "the orbit's perigee is inside the Earth",
            ));
        }
        return Ok((state, elements));
    }
    let a = match (r.semi_major_axis_m, r.altitude_m) {
        (Some(a), None) => c.positive("reference.semi_major_axis_m", a)?,
        (None, Some(h)) => earth.equatorial_radius_m + c.positive("reference.altitude_m", h)?,
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
    if a * (1.0 - e) <= earth.equatorial_radius_m {
        return Err(c.invalid(
            "reference.semi_major_axis_m",
            format!(
                "perigee radius {:.1} m is inside the Earth (allowed: a (1 - e) > {} m)",
                a * (1.0 - e),
                earth.equatorial_radius_m
            ),
        ));
    }
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
            let full = scenario.base_dir.join(path);
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

/// Reads a CSV of states with header `x_m,y_m,z_m,vx_mps,vy_mps,vz_mps`.
fn read_states_csv(path: &Path) -> Result<Vec<[f64; 6]>, String> {
    const HEADER: [&str; 6] = ["x_m", "y_m", "z_m", "vx_mps", "vy_mps", "vz_mps"];
    let mut reader =
        csv::Reader::from_path(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let header = reader
        .headers()
        .map_err(|e| format!("{}: {e}", path.display()))?
        .clone();
    let columns: Vec<&str> = header.iter().map(str::trim).collect();
    if columns != HEADER {
        return Err(format!(
            "{}: header is `{}` (required: `{}`)",
            path.display(),
            columns.join(","),
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
                    "{} line {}: column {} = `{field}` is not a number",
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

fn selection(
    c: &Checker<'_>,
    key: &str,
    s: &SelectionSection,
    count: usize,
) -> Result<Selection, ScenarioError> {
    match s {
        SelectionSection::Word(w) if w == "all" => Ok(Selection::All),
        SelectionSection::Word(w) => Err(c.invalid(
            key,
            format!("`{w}` is not allowed (allowed: \"all\" or a list of satellite indices)"),
        )),
        SelectionSection::Ids(ids) => {
            for &i in ids {
                c.index(key, i, count)?;
            }
            Ok(Selection::Satellites(ids.clone()))
        }
    }
}

/// Translates the timeline, checking times, indices and — by replaying the law changes in time order —
/// every parameter update and law switch: each resulting law is built and checked against the dynamics
/// and timing, so that a bad or too stiff update fails before the run, not when its event fires.
fn events(
    c: &Checker<'_>,
    scenario: &Scenario,
    count: usize,
    config: &SimulationConfig,
    min_mass_kg: f64,
) -> Result<Vec<Event>, ScenarioError> {
    let f = &scenario.file;
    let duration_s = config.duration_s;
    let mut order: Vec<usize> = (0..f.events.len()).collect();
    order.sort_by(|&a, &b| f.events[a].time_s.total_cmp(&f.events[b].time_s));
    let mut current = f.law.clone();
    let mut out = Vec::with_capacity(f.events.len());
    for k in order {
        let e = &f.events[k];
        let key = |name: &str| format!("events[{k}].{name}");
        if !(e.time_s.is_finite() && (0.0..=duration_s).contains(&e.time_s)) {
            return Err(c.invalid(
                &key("time_s"),
                format!(
                    "{} is out of range (allowed: [0, duration_s = {duration_s}])",
                    e.time_s
                ),
            ));
        }
        let action = match &e.action {
            ActionSection::SetLawParameters { parameters } => {
                let merged = merge_law_parameters(&current, parameters).map_err(|err| {
                    c.invalid(
                        &key("parameters"),
                        format!("law `{}`: {err}", current.name()),
                    )
                })?;
                build_law(c, &key("parameters"), &merged, config, min_mass_kg)?;
                current = merged.clone();
                EventAction::SetLawParameters(merged.into_parameters())
            }
            ActionSection::SwitchLaw { law } => {
                let built = build_law(c, &key("law"), law, config, min_mass_kg)?;
                current = law.clone();
                EventAction::SwitchLaw(built)
            }
            ActionSection::ThreatWarning { threat, active } => EventAction::ThreatWarning {
                threat: if *threat < config.threats.len() {
                    *threat
                } else {
                    return Err(c.invalid(
                        &key("threat"),
                        format!(
                            "threat {threat} does not exist (allowed: 0..{}, the [[threats]] of the scenario)",
                            config.threats.len()
                        ),
                    ));
                },
                active: *active,
            },
            ActionSection::CutLinks { satellites } => {
                EventAction::CutLinks(selection(c, &key("satellites"), satellites, count)?)
            }
            ActionSection::RestoreLinks { satellites } => {
                EventAction::RestoreLinks(selection(c, &key("satellites"), satellites, count)?)
            }
            ActionSection::RemoveSatellite { satellite } => {
                EventAction::RemoveSatellite(c.index(&key("satellite"), *satellite, count)?)
            }
            ActionSection::FailThruster { satellite, axis } => EventAction::FailThruster {
                satellite: c.index(&key("satellite"), *satellite, count)?,
                axis: match axis {
                    AxisName::X => ThrustAxis::X,
                    AxisName::Y => ThrustAxis::Y,
                    AxisName::Z => ThrustAxis::Z,
                    AxisName::All => ThrustAxis::All,
                },
            },
        };
        out.push(Event {
            time_s: e.time_s,
            action,
        });
    }
    Ok(out)
}
