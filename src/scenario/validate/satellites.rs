//! `[satellites]`: the count, the physical properties (values, lists, distributions and the
//! properties file, read by `properties.rs`; overrides), the drag attitudes, the actuators, and the checks of the start at t = 0 (above the ground, within
//! `dynamics.max_distance_m`, no overlap, outside the obstacles).

use nalgebra::Vector3;

use crate::dynamics::PhysicalProperties;
use crate::environment::Obstacle;
use crate::orbit::{CartesianState, EarthModel, RelativeStateHill};
use crate::scenario::schema::{PerSatellite, SatellitesSection, ScenarioFile};
use crate::scenario::{Scenario, ScenarioError};
use crate::swarm::{
    hill_state_at_start, Actuator, ControlTiming, DragAttitudes, DynamicsModel, Origin,
    SatelliteInit, MAX_DRAG_MODES,
};
use crate::time::Epoch;

use super::orbit_inputs::OrbitInputs;
use super::properties::{self, Property};
use super::settings::{base_step_s, force_error};
use super::{initial_states, reference, Checker, MAX_SATELLITES};

/// What the satellites' checks need to know of the run: the swarm's size, the truth model, the timing,
/// the reference orbit and the LVLH origin.
pub(super) struct Swarm<'a> {
    pub(super) count: usize,
    pub(super) dynamics: &'a DynamicsModel,
    pub(super) control: ControlTiming,
    pub(super) step_s: f64,
    pub(super) mean_motion_rad_s: f64,
    /// The reference orbit's inertial (EME2000) state at t = 0.
    pub(super) reference: &'a CartesianState,
    pub(super) earth: &'a EarthModel,
    pub(super) origin: Origin,
}

impl Swarm<'_> {
    /// Whether a force model reads the drag properties, and the SRP properties.
    pub(super) fn uses(&self) -> (bool, bool) {
        let forces = self.dynamics.forces();
        (
            forces.is_some_and(|f| f.uses_drag_properties()),
            forces.is_some_and(|f| f.uses_srp_properties()),
        )
    }
}

/// `satellites.count`.
pub(super) fn count(c: &Checker<'_>, s: &SatellitesSection) -> Result<usize, ScenarioError> {
    if (1..=MAX_SATELLITES).contains(&s.count) {
        Ok(s.count)
    } else {
        Err(c.range(
            "satellites.count",
            s.count,
            format!(
                ">= 1 and <= {MAX_SATELLITES}; beyond 10^7 satellites the run needs more memory and \
                 time than one machine has"
            ),
        ))
    }
}

/// The satellites at t = 0: their initial states, physical properties, radii and actuators, with
/// the `[[satellites.overrides]]` applied; and the virtual reference's properties (`[reference]`'s,
/// else the satellites' mean). `inputs` holds the orbit files read, `epoch` is t = 0; a property
/// column no force model reads is said in `warnings`.
pub(super) fn satellites(
    c: &Checker<'_>,
    scenario: &Scenario,
    swarm: &Swarm<'_>,
    inputs: &OrbitInputs,
    epoch: Epoch,
    warnings: &mut Vec<String>,
) -> Result<(Vec<SatelliteInit>, PhysicalProperties), ScenarioError> {
    let s = &scenario.file.satellites;
    let count = swarm.count;
    let (drag, srp) = swarm.uses();
    let file = properties::read_file(c, scenario, count)?;
    let seed = scenario.file.seed;
    let drag_attitudes = drag_attitudes(c, s, drag, base_step_s(swarm.control, swarm.step_s))?;
    let mut values = |name: &'static str, key: &Option<PerSatellite>, used, default| {
        let property = Property {
            name,
            key: key.as_ref(),
            used,
            default,
        };
        properties::values(c, &property, file.as_ref(), count, seed, warnings)
    };
    let masses_kg = values("mass_kg", &s.mass_kg, true, None)?;
    let radii_m = values("radius_m", &s.radius_m, true, Some(0.0))?;
    let drag_areas = values(
        "drag_area_m2",
        &s.drag_area_m2,
        drag,
        drag_attitudes.map(|a| a.min_area_m2()),
    )?;
    let drag_coefficients = values("drag_coefficient", &s.drag_coefficient, drag, Some(2.2))?;
    let srp_areas = values("srp_area_m2", &s.srp_area_m2, srp, None)?;
    let reflectivities = values(
        "reflectivity_coefficient",
        &s.reflectivity_coefficient,
        srp,
        Some(1.5),
    )?;
    for (id, (m, r)) in masses_kg.iter().zip(&radii_m).enumerate() {
        let at = |name: &str| format!("satellites.{name} (satellite {id})");
        c.positive(&at("mass_kg"), *m)?;
        c.non_negative(&at("radius_m"), *r)?;
    }
    if let Some(attitudes) = &drag_attitudes {
        if let Some((id, area)) = drag_areas
            .iter()
            .enumerate()
            .find(|(_, a)| !attitudes.admits(**a))
        {
            return Err(c.bad(
                "satellites.drag_area_m2",
                format!("{area} m^2 (satellite {id})"),
                "is not one of the drag attitudes",
                attitudes.describe(),
            ));
        }
    }
    let max_accel = match s.max_accel_mps2 {
        Some(a) => c.positive("satellites.max_accel_mps2", a)?,
        None => f64::INFINITY,
    };
    // The initial states come last: an inertial one is placed in the reference orbit's frame,
    // which depends on the virtual reference's properties, the mean of the satellites' by default.
    let mut satellites: Vec<SatelliteInit> = (0..count)
        .map(|id| SatelliteInit {
            relative_state: RelativeStateHill::default(),
            properties: PhysicalProperties {
                mass_kg: masses_kg[id],
                drag_area_m2: drag_areas[id],
                drag_coefficient: drag_coefficients[id],
                srp_area_m2: srp_areas[id],
                reflectivity_coefficient: reflectivities[id],
            },
            radius_m: radii_m[id],
            actuator: Actuator::new(max_accel, s.accel_limit),
            drag_attitudes,
        })
        .collect();
    overrides(c, s, (drag, srp), &mut satellites)?;
    for (id, sat) in satellites.iter().enumerate() {
        sat.properties
            .validate("satellites.")
            .map_err(|e| force_error(c, e, "", Some(id)))?;
    }
    let reference_properties =
        reference::reference_properties(c, &scenario.file.reference, &satellites, swarm.uses())?;
    let to_hill = |state: &CartesianState| {
        hill_state_at_start(
            swarm.dynamics,
            swarm.earth,
            swarm.reference,
            &reference_properties,
            state,
        )
    };
    let states = initial_states::initial_states(c, scenario, swarm, inputs, epoch, &to_hill)?;
    for (sat, state) in satellites.iter_mut().zip(states) {
        sat.relative_state = state;
    }
    Ok((satellites, reference_properties))
}

/// `[[satellites.overrides]]`: properties, radius and thrust of the satellites each lists.
fn overrides(
    c: &Checker<'_>,
    s: &SatellitesSection,
    (drag, srp): (bool, bool),
    satellites: &mut [SatelliteInit],
) -> Result<(), ScenarioError> {
    let count = satellites.len();
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
                        return Err(unused_property(c, &key(name)));
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
    Ok(())
}

/// The checks of the start at t = 0 that `[satellites]` can waive or that need the whole swarm:
/// above the ground (dynamic models), within `dynamics.max_distance_m`, no overlap.
pub(super) fn check_start(
    c: &Checker<'_>,
    f: &ScenarioFile,
    swarm: &Swarm<'_>,
    satellites: &[SatelliteInit],
    max_distance_m: f64,
) -> Result<(), ScenarioError> {
    if *swarm.dynamics != DynamicsModel::Kinematic {
        check_initial_above_ground(
            c,
            satellites,
            swarm.reference.position_m.norm(),
            swarm.earth.equatorial_radius_m,
        )?;
    }
    check_initial_distances(c, satellites, swarm.origin, max_distance_m)?;
    if !f.satellites.allow_initial_overlap {
        check_initial_overlap(c, satellites)?;
    }
    Ok(())
}

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
            Some(d) => Err(c.bad(
                "satellites.drag_min_dwell_s",
                format!("{d} s"),
                "is shorter than one control tick",
                format!(">= {tick_s} s, finite: the area can change only at a tick"),
            )),
        }
    };
    let allowed =
        format!("1 to {MAX_DRAG_MODES} distinct areas > 0 m^2, or [min, max] with 0 < min < max");
    let (key, built) = match (&s.drag_modes_m2, s.drag_area_range_m2) {
        (Some(_), Some(_)) => {
            return Err(c.keys(
                "satellites.drag_area_range_m2",
                "cannot be given with satellites.drag_modes_m2",
                "named modes or a range",
            ))
        }
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
                return Err(c.keys(
                    "satellites.drag_min_dwell_s",
                    "is given without drag attitudes",
                    "only with satellites.drag_modes_m2 or satellites.drag_area_range_m2",
                ));
            }
            return Ok(None);
        }
    };
    built
        .map(Some)
        .map_err(|e| c.keys(key, e.to_string(), allowed))
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
            return Err(c.bad(
                "satellites.initial",
                format!("the initial state of satellite {i}"),
                "is not finite",
                "finite states",
            ));
        }
        let d = (p - centre).norm();
        if d > max_distance_m {
            return Err(c.bad(
                "dynamics.max_distance_m",
                format!("satellite {i}"),
                format!(
                    "starts {d:.6e} m from the frame's origin, beyond dynamics.max_distance_m = \
                     {max_distance_m} m"
                ),
                "every initial distance <= dynamics.max_distance_m; raise it or move the satellite",
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
            return Err(c.bad(
                "satellites.initial",
                format!("satellite {i}"),
                format!(
                    "starts inside the Earth: {r:.6e} m from its centre (the reference orbit's radius \
                     {reference_radius_m:.6e} m plus the Hill offset [{:.6e}, {:.6e}, {:.6e}] m)",
                    p.x, p.y, p.z
                ),
                format!(
                    "every satellite at least the Earth's radius {earth_radius_m:.6e} m from its \
                     centre; check the offsets and their unit, metres"
                ),
            ));
        }
    }
    Ok(())
}

/// Refuses a satellite that starts inside an obstacle (its position, a point, closer to the obstacle's
/// centre than its radius, in the frame of the run's origin): the obstacle monitor would count an
/// incursion at t = 0.
pub(super) fn check_initial_outside_obstacles(
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
            let clearance =
                obstacle.surface_distance_m(&(sat.relative_state.position_m - centre), 0.0);
            if clearance < 0.0 {
                return Err(c.bad(
                    "satellites.allow_start_in_obstacle",
                    format!("satellite {i}"),
                    format!(
                        "starts inside obstacles[{k}] (`{}`), {:.6e} m below its surface",
                        obstacle.name(),
                        -clearance
                    ),
                    "every satellite outside every obstacle at t = 0; move the initial distribution \
                     or the obstacle, or set satellites.allow_start_in_obstacle = true to run it anyway",
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
        .map_err(|e| c.keys("satellites.initial", e.to_string(), ""))?;
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
            return Err(c.bad(
                "satellites.allow_initial_overlap",
                format!("satellites {i} and {j}"),
                format!(
                    "overlap at t = 0: their centres are {d:.6e} m apart, not more than the sum of \
                     their radii {:.6e} m",
                    satellites[i].radius_m + satellites[j].radius_m
                ),
                "every pair farther apart than the sum of its radii; spread the initial \
                 distribution, shrink satellites.radius_m, or set satellites.allow_initial_overlap = \
                 true to run it anyway",
            ));
        }
    }
    Ok(())
}

/// A property key given although no force model reads it.
pub(super) fn unused_property(c: &Checker<'_>, key: &str) -> ScenarioError {
    c.keys(
        key,
        "is given but no force model reads it",
        "drag keys with [dynamics.forces.drag], SRP keys with [dynamics.forces.srp]",
    )
}
