//! `[[threats]]` and `[[obstacles]]`: the environment's objects — lines and static spheres in the
//! Hill frame, and real objects given by their orbit (`omm`, `tle`, `state_eme2000`), placed in the
//! Hill frame at t = 0 as the engine places them ([`crate::swarm::hill_state_at_start`]) and tracked
//! during the run ([`TrackedObject`]).

use nalgebra::Vector3;

use crate::dynamics::PhysicalProperties;
use crate::environment::{Obstacle, Threat, TrackedPath};
use crate::orbit::{CartesianState, EarthModel};
use crate::scenario::schema::{ObjectPropagation, ObstacleSection, ThreatSection};
use crate::scenario::ScenarioError;
use crate::swarm::{
    hill_state_at_start, DynamicsModel, EnvironmentObject, TrackedObject, TrackedOrbit,
};
use crate::time::Epoch;

use super::orbit_inputs::OrbitInput;
use super::Checker;

/// What places a real object in the Hill frame at t = 0.
pub(super) struct Placing<'a> {
    pub dynamics: &'a DynamicsModel,
    pub earth: &'a EarthModel,
    /// The reference orbit at t = 0, EME2000.
    pub reference: &'a CartesianState,
    /// The virtual reference's physical properties (also a truth-propagated object's).
    pub reference_properties: &'a PhysicalProperties,
    /// The scenario epoch (t = 0).
    pub epoch: Epoch,
}

/// A real object's orbit keys, shared by threats and obstacles.
struct OrbitKeys<'a> {
    /// `threats[k]` or `obstacles[k]`.
    prefix: String,
    /// Its `omm` or `tle`, read.
    input: Option<&'a OrbitInput>,
    state_eme2000: Option<[f64; 6]>,
    propagation: Option<ObjectPropagation>,
}

/// A real object's path at t = 0 and its orbit (`None` when the keys give no orbit).
fn real_object(
    c: &Checker<'_>,
    keys: &OrbitKeys<'_>,
    place: &Placing<'_>,
) -> Result<Option<(TrackedPath, TrackedOrbit)>, ScenarioError> {
    let prefix = &keys.prefix;
    let (state, orbit) = match (keys.input, keys.state_eme2000) {
        (None, None) => {
            if keys.propagation.is_some() {
                return Err(c.keys(
                    &format!("{prefix}.propagation"),
                    "is given without an orbit",
                    "propagation with omm, tle or state_eme2000",
                ));
            }
            return Ok(None);
        }
        (Some(_), Some(_)) => {
            return Err(c.keys(
                prefix,
                "gives both an element set (omm or tle) and state_eme2000",
                "one orbit",
            ))
        }
        (Some(input), None) => {
            let elements = input
                .sgp4_object()
                .expect("an object's omm or tle holds an SGP4 element set");
            let state = input.states_eme2000(c, place.epoch)?[0];
            let orbit = match keys.propagation.unwrap_or(ObjectPropagation::Sgp4) {
                ObjectPropagation::Sgp4 => TrackedOrbit::Sgp4 {
                    elements: Box::new(elements.clone()),
                    epoch: place.epoch,
                },
                ObjectPropagation::Truth => TrackedOrbit::Truth {
                    state_eme2000: state,
                    properties: *place.reference_properties,
                },
            };
            (state, orbit)
        }
        (None, Some(s)) => {
            let key = format!("{prefix}.state_eme2000");
            c.finite(&key, &s)?;
            if keys.propagation == Some(ObjectPropagation::Sgp4) {
                return Err(c.keys(
                    &format!("{prefix}.propagation"),
                    "is sgp4 for a state (SGP4 needs an element set)",
                    "truth with state_eme2000, or sgp4 with omm or tle",
                ));
            }
            let state = CartesianState::new(
                Vector3::new(s[0], s[1], s[2]),
                Vector3::new(s[3], s[4], s[5]),
            );
            let r_m = state.position_m.norm();
            if r_m < place.earth.equatorial_radius_m {
                return Err(c.bad(
                    &key,
                    format!("|r| = {r_m} m"),
                    format!(
                        "is inside the Earth (radius {} m); this looks like kilometres written as \
                         metres",
                        place.earth.equatorial_radius_m
                    ),
                    "a position above the Earth's surface, in metres",
                ));
            }
            let orbit = TrackedOrbit::Truth {
                state_eme2000: state,
                properties: *place.reference_properties,
            };
            (state, orbit)
        }
    };
    let hill = hill_state_at_start(
        place.dynamics,
        place.earth,
        place.reference,
        place.reference_properties,
        &state,
    );
    let path = TrackedPath::new(0.0, hill.position_m, hill.velocity_mps)
        .map_err(|e| c.keys(prefix, e.to_string(), "a finite state"))?;
    Ok(Some((path, orbit)))
}

/// The threats, obstacles and tracked real objects of the scenario.
pub(super) struct Environment {
    pub threats: Vec<Threat>,
    pub obstacles: Vec<Obstacle>,
    pub tracked_objects: Vec<TrackedObject>,
}

/// The scenario's environment: its threats and obstacles (`threat_inputs` / `obstacle_inputs`: their
/// `omm` or `tle`, read, by index).
pub(super) fn environment(
    c: &Checker<'_>,
    threat_sections: &[ThreatSection],
    obstacle_sections: &[ObstacleSection],
    threat_inputs: &[Option<OrbitInput>],
    obstacle_inputs: &[Option<OrbitInput>],
    place: &Placing<'_>,
) -> Result<Environment, ScenarioError> {
    let mut tracked_objects = Vec::new();
    // A real object's path at t = 0, its orbit kept as the object's tracked orbit.
    let mut track = |object: EnvironmentObject, keys: OrbitKeys<'_>| {
        Ok::<_, ScenarioError>(real_object(c, &keys, place)?.map(|(path, orbit)| {
            tracked_objects.push(TrackedObject { object, orbit });
            path
        }))
    };
    let threats = threat_sections
        .iter()
        .enumerate()
        .map(|(k, s)| {
            let keys = OrbitKeys {
                prefix: format!("threats[{k}]"),
                input: threat_inputs.get(k).and_then(Option::as_ref),
                state_eme2000: s.state_eme2000,
                propagation: s.propagation,
            };
            threat(c, k, s, track(EnvironmentObject::Threat(k), keys)?)
        })
        .collect::<Result<_, _>>()?;
    let obstacles = obstacle_sections
        .iter()
        .enumerate()
        .map(|(k, s)| {
            let keys = OrbitKeys {
                prefix: format!("obstacles[{k}]"),
                input: obstacle_inputs.get(k).and_then(Option::as_ref),
                state_eme2000: s.state_eme2000,
                propagation: s.propagation,
            };
            obstacle(c, k, s, track(EnvironmentObject::Obstacle(k), keys)?)
        })
        .collect::<Result<_, _>>()?;
    Ok(Environment {
        threats,
        obstacles,
        tracked_objects,
    })
}

/// Threat `k`: on a line (by state or by aim), or on the tracked path of a real object.
fn threat(
    c: &Checker<'_>,
    k: usize,
    s: &ThreatSection,
    tracked: Option<TrackedPath>,
) -> Result<Threat, ScenarioError> {
    let key = |name: &str| format!("threats[{k}].{name}");
    let name = s.name.clone().unwrap_or_else(|| format!("threat-{k}"));
    let danger = c.non_negative(&key("danger_radius_m"), s.danger_radius_m)?;
    let by_state = s.position_hill_m.is_some() || s.velocity_hill_mps.is_some();
    let by_aim = s.aim_point_hill_m.is_some()
        || s.direction_hill.is_some()
        || s.speed_mps.is_some()
        || s.arrival_time_s.is_some();
    let threat = match (by_state, by_aim, tracked) {
        (false, false, Some(path)) => Threat::tracked(name, path, danger),
        (_, _, Some(_)) => {
            return Err(c.keys(
                &format!("threats[{k}]"),
                "gives a line (a state or an aim) and an orbit",
                "either a line in the Hill frame or a real object's orbit (omm, tle, \
                         state_eme2000)",
            ))
        }
        (true, false, None) => {
            let (Some(p), Some(v)) = (s.position_hill_m, s.velocity_hill_mps) else {
                return Err(c.keys(
                    &key("position_hill_m"),
                    "is given without velocity_hill_mps, or the other way round",
                    "position_hill_m and velocity_hill_mps together",
                ));
            };
            c.finite(&key("position_hill_m"), &p)?;
            c.finite(&key("velocity_hill_mps"), &v)?;
            let at = s.at_time_s.unwrap_or(0.0);
            c.finite(&key("at_time_s"), &[at])?;
            Threat::from_state(name, at, Vector3::from(p), Vector3::from(v), danger)
        }
        (false, true, None) => {
            if s.at_time_s.is_some() {
                return Err(c.keys(
                    &key("at_time_s"),
                    "is given with an aim",
                    "at_time_s with position_hill_m, not with an aim",
                ));
            }
            let (Some(aim), Some(direction), Some(speed), Some(arrival)) = (
                s.aim_point_hill_m,
                s.direction_hill,
                s.speed_mps,
                s.arrival_time_s,
            ) else {
                return Err(c.keys(
                    &key("aim_point_hill_m"),
                    "an aimed threat misses some of its keys",
                    "aim_point_hill_m, direction_hill, speed_mps and arrival_time_s together",
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
            return Err(c.keys(
                &format!("threats[{k}]"),
                "gives neither a state nor an aim nor an orbit, or both a state and an aim",
                "either position_hill_m + velocity_hill_mps (+ at_time_s), \
                         aim_point_hill_m + direction_hill + speed_mps + arrival_time_s, or a real \
                         object's omm, tle or state_eme2000",
            ))
        }
    }
    .map_err(|e| c.keys(&format!("threats[{k}]"), e.to_string(), ""))?;
    match s.detection_range_m {
        Some(r) => threat
            .with_detection_range_m(c.positive(&key("detection_range_m"), r)?)
            .map_err(|e| c.keys(&key("detection_range_m"), e.to_string(), "")),
        None => Ok(threat),
    }
}

/// Obstacle `k`: static at `center_hill_m`, or centred on the tracked path of a real object.
fn obstacle(
    c: &Checker<'_>,
    k: usize,
    s: &ObstacleSection,
    tracked: Option<TrackedPath>,
) -> Result<Obstacle, ScenarioError> {
    let key = |name: &str| format!("obstacles[{k}].{name}");
    let name = s.name.clone().unwrap_or_else(|| format!("obstacle-{k}"));
    let radius = c.positive(&key("radius_m"), s.radius_m)?;
    let obstacle = match (s.center_hill_m, tracked) {
        (Some(centre), None) => {
            c.finite(&key("center_hill_m"), &centre)?;
            Obstacle::new(name, Vector3::from(centre), radius)
        }
        (None, Some(path)) => Obstacle::tracked(name, path, radius),
        (Some(_), Some(_)) => {
            return Err(c.keys(
                &format!("obstacles[{k}]"),
                "gives center_hill_m and an orbit",
                "either center_hill_m or a real object's orbit (omm, tle, state_eme2000)",
            ))
        }
        (None, None) => {
            return Err(c.keys(
                &key("center_hill_m"),
                "is missing",
                "center_hill_m, or a real object's omm, tle or state_eme2000",
            ))
        }
    }
    .map_err(|e| c.keys(&format!("obstacles[{k}]"), e.to_string(), ""))?;
    match s.detection_range_m {
        Some(r) => obstacle
            .with_detection_range_m(c.positive(&key("detection_range_m"), r)?)
            .map_err(|e| c.keys(&key("detection_range_m"), e.to_string(), "")),
        None => Ok(obstacle),
    }
}
