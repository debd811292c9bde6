//! `[reference]`: the reference orbit at t = 0 (classical elements, an inertial state or an orbit file), the LVLH
//! origin and the virtual reference's physical properties.

use nalgebra::Vector3;

use crate::dynamics::PhysicalProperties;
use crate::orbit::{CartesianState, EarthModel, KeplerianElements};
use crate::scenario::schema::{OriginName, ReferenceSection};
use crate::scenario::{Scenario, ScenarioError};
use crate::swarm::{Origin, SatelliteInit};
use crate::time::Epoch;

use super::orbit_inputs::OrbitInputs;
use super::satellites::unused_property;
use super::settings::force_error;
use super::{Checker, MAX_APOGEE_RADIUS_M, MIN_PERIGEE_ALTITUDE_M};

/// The reference orbit's inertial (EME2000) state at t = 0 and its osculating elements: from classical
/// elements, an inertial state (`position_eci_m` + `velocity_eci_mps`, or `state_eme2000`), or an orbit
/// file (`oem`, `omm`, `tle`, read into `inputs`) at the scenario `epoch`.
pub(super) fn reference_orbit(
    c: &Checker<'_>,
    scenario: &Scenario,
    earth: &EarthModel,
    inputs: &OrbitInputs,
    epoch: Epoch,
) -> Result<(CartesianState, KeplerianElements), ScenarioError> {
    let r = &scenario.file.reference;
    let by_eci = r.position_eci_m.is_some() || r.velocity_eci_mps.is_some();
    let by_elements = r.semi_major_axis_m.is_some()
        || r.altitude_m.is_some()
        || r.eccentricity.is_some()
        || r.inclination_deg.is_some()
        || r.raan_deg.is_some()
        || r.arg_perigee_deg.is_some()
        || r.true_anomaly_deg.is_some();
    let given: Vec<&str> = [
        ("classical elements", by_elements),
        ("position_eci_m + velocity_eci_mps", by_eci),
        ("state_eme2000", r.state_eme2000.is_some()),
        (
            "an orbit file (oem, omm or tle)",
            inputs.reference.is_some(),
        ),
    ]
    .into_iter()
    .filter_map(|(what, is)| is.then_some(what))
    .collect();
    if given.len() > 1 {
        return Err(c.keys(
            "reference",
            format!("gives {}", given.join(" and ")),
            "one of: classical elements, position_eci_m + velocity_eci_mps, state_eme2000, oem, omm, tle",
        ));
    }
    if let Some(input) = &inputs.reference {
        let state = input.states_eme2000(c, epoch)?[0];
        return reference_state(c, input.key(), state, earth);
    }
    if let Some(s) = r.state_eme2000 {
        c.finite("reference.state_eme2000", &s)?;
        let state = CartesianState::new(
            Vector3::new(s[0], s[1], s[2]),
            Vector3::new(s[3], s[4], s[5]),
        );
        return reference_state(c, "reference.state_eme2000", state, earth);
    }
    if by_eci {
        let (Some(p), Some(v)) = (r.position_eci_m, r.velocity_eci_mps) else {
            return Err(c.keys(
                "reference",
                "gives one of position_eci_m and velocity_eci_mps without the other",
                "position_eci_m and velocity_eci_mps together",
            ));
        };
        c.finite("reference.position_eci_m", &p)?;
        c.finite("reference.velocity_eci_mps", &v)?;
        let state = CartesianState::new(Vector3::from(p), Vector3::from(v));
        return reference_state(c, "reference.position_eci_m", state, earth);
    }
    let elements = reference_elements(c, r, earth)?;
    let state = elements
        .to_cartesian(earth.mu_m3_s2)
        .map_err(|err| c.keys("reference", err.to_string(), "an elliptic orbit"))?;
    Ok((state, elements))
}

/// A reference orbit given by its inertial state (the key `key`): above the Earth, inside its Hill
/// sphere, with its osculating elements.
fn reference_state(
    c: &Checker<'_>,
    key: &str,
    state: CartesianState,
    earth: &EarthModel,
) -> Result<(CartesianState, KeplerianElements), ScenarioError> {
    let r_m = state.position_m.norm();
    if r_m < earth.equatorial_radius_m {
        return Err(c.bad(
            key,
            format!("|r| = {r_m} m"),
            format!(
                "is inside the Earth (radius {} m); this looks like kilometres written as metres",
                earth.equatorial_radius_m
            ),
            format!("a perigee altitude >= {MIN_PERIGEE_ALTITUDE_M} m"),
        ));
    }
    if r_m > MAX_APOGEE_RADIUS_M {
        return Err(c.bad(
            key,
            format!("|r| = {r_m:.6e} m"),
            "is beyond the Earth's Hill sphere",
            format!("<= {MAX_APOGEE_RADIUS_M:e} m"),
        ));
    }
    let elements = KeplerianElements::from_cartesian(&state, earth.mu_m3_s2)
        .map_err(|e| c.keys(key, e.to_string(), "a bound orbit"))?;
    check_orbit_size(c, key, &elements, earth)?;
    Ok((state, elements))
}

/// The reference orbit's classical elements.
fn reference_elements(
    c: &Checker<'_>,
    r: &ReferenceSection,
    earth: &EarthModel,
) -> Result<KeplerianElements, ScenarioError> {
    let a = match (r.semi_major_axis_m, r.altitude_m) {
        (Some(a), None) => {
            let a = c.positive("reference.semi_major_axis_m", a)?;
            if a < earth.equatorial_radius_m {
                return Err(c.bad(
                    "reference.semi_major_axis_m",
                    format!("{a} m"),
                    format!(
                        "is inside the Earth (radius {} m); this looks like kilometres written as \
                         metres (did you mean {:e} m?)",
                        earth.equatorial_radius_m,
                        a * 1e3
                    ),
                    format!("a perigee altitude >= {MIN_PERIGEE_ALTITUDE_M} m"),
                ));
            }
            a
        }
        (None, Some(h)) => {
            let h = c.positive("reference.altitude_m", h)?;
            if h < 1000.0 {
                return Err(c.bad(
                    "reference.altitude_m",
                    format!("{h} m"),
                    format!(
                        "looks like kilometres written as metres (did you mean {:e} m?)",
                        h * 1e3
                    ),
                    format!(">= {MIN_PERIGEE_ALTITUDE_M} m"),
                ));
            }
            earth.equatorial_radius_m + h
        }
        (Some(_), Some(_)) => {
            return Err(c.keys(
                "reference.altitude_m",
                "is given with semi_major_axis_m",
                "semi_major_axis_m or altitude_m, not both",
            ))
        }
        (None, None) => {
            return Err(c.err(crate::invalid::Invalid::missing(
                "reference.semi_major_axis_m",
                "semi_major_axis_m or altitude_m (or position_eci_m + velocity_eci_mps)",
            )))
        }
    };
    let e = r.eccentricity.unwrap_or(0.0);
    if !(0.0..1.0).contains(&e) {
        return Err(c.range("reference.eccentricity", e, "[0, 1)"));
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
        return Err(c.err(crate::invalid::Invalid::missing(
            "reference.inclination_deg",
            "[0, 180]",
        )));
    };
    if !(0.0..=180.0).contains(&inc) {
        return Err(c.range("reference.inclination_deg", inc, "[0, 180]"));
    }
    let angle = |key: &str, v: Option<f64>| -> Result<f64, ScenarioError> {
        let v = v.unwrap_or(0.0);
        c.finite(key, &[v])?;
        Ok(v.to_radians())
    };
    Ok(KeplerianElements {
        semi_major_axis_m: a,
        eccentricity: e,
        inclination_rad: inc.to_radians(),
        raan_rad: angle("reference.raan_deg", r.raan_deg)?,
        arg_perigee_rad: angle("reference.arg_perigee_deg", r.arg_perigee_deg)?,
        true_anomaly_rad: angle("reference.true_anomaly_deg", r.true_anomaly_deg)?,
    })
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
        return Err(c.bad(
            key,
            format!("the perigee altitude a (1 - e) - R = {perigee_altitude_m:.1} m (a = {a} m, e = {e})"),
            format!(
                "is below {MIN_PERIGEE_ALTITUDE_M} m, where drag (not modelled) ends the orbit"
            ),
            format!(
                "a (1 - e) >= {} m",
                earth.equatorial_radius_m + MIN_PERIGEE_ALTITUDE_M
            ),
        ));
    }
    let apogee_m = a * (1.0 + e);
    if !(e < 1.0 && apogee_m <= MAX_APOGEE_RADIUS_M) {
        return Err(c.bad(
            key,
            format!("the apogee radius a (1 + e) = {apogee_m:.6e} m (a = {a:e} m, e = {e})"),
            "is beyond the Earth's Hill sphere, where the Sun governs the motion",
            format!("a (1 + e) <= {MAX_APOGEE_RADIUS_M:e} m, e < 1"),
        ));
    }
    Ok(())
}

/// `[reference] origin` and `origin_member`: the LVLH origin among `count` satellites.
pub(super) fn origin(
    c: &Checker<'_>,
    r: &ReferenceSection,
    count: usize,
) -> Result<Origin, ScenarioError> {
    match (r.origin, r.origin_member) {
        (OriginName::Virtual, None) => Ok(Origin::VirtualReference),
        (OriginName::Virtual, Some(_)) => Err(c.keys(
            "reference.origin_member",
            "applies only to origin = \"member\"",
            "remove it, or set origin = \"member\"",
        )),
        (OriginName::Member, None) => Err(c.err(crate::invalid::Invalid::missing(
            "reference.origin_member",
            "a satellite index, with origin = \"member\"",
        ))),
        (OriginName::Member, Some(k)) => Ok(Origin::Member(c.index(
            "reference.origin_member",
            k,
            count,
        )?)),
    }
}

/// The virtual reference orbit's physical properties: each `[reference]` key given, else the swarm's
/// mean of that property (keys refused when no force model reads them).
pub(super) fn reference_properties(
    c: &Checker<'_>,
    reference: &ReferenceSection,
    satellites: &[SatelliteInit],
    (drag, srp): (bool, bool),
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
