//! `[[threats]]` and `[[obstacles]]`: the environment's objects.

use nalgebra::Vector3;

use crate::environment::{Obstacle, Threat};
use crate::scenario::schema::{ObstacleSection, ThreatSection};
use crate::scenario::ScenarioError;

use super::Checker;

/// The threats of the scenario.
pub(super) fn threats(
    c: &Checker<'_>,
    sections: &[ThreatSection],
) -> Result<Vec<Threat>, ScenarioError> {
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
                (false, true) => {
                    if s.at_time_s.is_some() {
                        return Err(c.keys(
                            &key("at_time_s"),
                            "is given with an aim",
                            "at_time_s with position_hill_m, not with an aim",
                        ));
                    }
                    let (Some(aim), Some(direction), Some(speed), Some(arrival)) =
                        (s.aim_point_hill_m, s.direction_hill, s.speed_mps, s.arrival_time_s)
                    else {
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
                        "gives neither a state nor an aim, or both",
                        "either position_hill_m + velocity_hill_mps (+ at_time_s) or \
                         aim_point_hill_m + direction_hill + speed_mps + arrival_time_s",
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
        })
        .collect()
}

/// The obstacles of the scenario.
pub(super) fn obstacles(
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
                .map_err(|e| c.keys(&format!("obstacles[{k}]"), e.to_string(), ""))?;
            match s.detection_range_m {
                Some(r) => obstacle
                    .with_detection_range_m(c.positive(&key("detection_range_m"), r)?)
                    .map_err(|e| c.keys(&key("detection_range_m"), e.to_string(), "")),
                None => Ok(obstacle),
            }
        })
        .collect()
}
