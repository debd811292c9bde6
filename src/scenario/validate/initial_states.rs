//! `satellites.initial`: the initial states of the swarm, relative to the LVLH origin (Hill frame) —
//! random draws, averaged-J2 parameters, a dispenser, lists and CSV files (Hill, Gao or EME2000), and
//! the OEM, OMM and TLE files of real satellites (EME2000 at the epoch, placed in the Hill frame).

use nalgebra::Vector3;

use crate::orbit::{gao_to_hill, CartesianState, RelativeStateHill};
use crate::relative::SchweighartSedwick;
use crate::scenario::initial;
use crate::scenario::schema::{InitialSection, ListFrame};
use crate::scenario::{Scenario, ScenarioError};
use crate::swarm::{DynamicsModel, Origin};
use crate::time::Epoch;

use super::orbit_inputs::OrbitInputs;
use super::satellites::Swarm;
use super::{states_csv, Checker};

/// The Schweighart–Sedwick model of the reference orbit at t = 0, as the engine gives it to laws: for
/// the averaged-J2 draws.
fn reference_model(swarm: &Swarm<'_>) -> SchweighartSedwick {
    match swarm.dynamics {
        DynamicsModel::J2Linear(model) => *model,
        dynamics => {
            let reference = swarm.reference;
            let h = reference.specific_angular_momentum_m2_s();
            let j2 = if dynamics.reference_has_j2() {
                swarm.earth.j2
            } else {
                0.0
            };
            SchweighartSedwick::new(
                reference.position_m.norm(),
                (h.z / h.norm()).acos(),
                swarm.earth.mu_m3_s2,
                swarm.earth.equatorial_radius_m,
                j2,
            )
        }
    }
}

/// The satellites' states at t = 0, Hill frame; `inertial` places an EME2000 state at t = 0 in it
/// ([`crate::swarm::hill_state_at_start`]), `inputs` holds the orbit files read, `epoch` is t = 0.
pub(super) fn initial_states(
    c: &Checker<'_>,
    scenario: &Scenario,
    swarm: &Swarm<'_>,
    inputs: &OrbitInputs,
    epoch: Epoch,
    inertial: &dyn Fn(&CartesianState) -> RelativeStateHill,
) -> Result<Vec<RelativeStateHill>, ScenarioError> {
    let count = swarm.count;
    let mean_motion_rad_s = swarm.mean_motion_rad_s;
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
                return Err(c.bad(
                    &format!("{key}.inner_radius_m"),
                    inner,
                    format!("is larger than outer_radius_m = {outer}"),
                    "[0, outer_radius_m]",
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
                &crate::relative::j2_averaged::AveragedJ2::new(reference_model(swarm)),
                c1,
                c4,
                a,
                match swarm.origin {
                    Origin::Member(k) => Some(k),
                    Origin::VirtualReference => None,
                },
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
                return Err(c.bad(
                    &format!("{key}.states"),
                    format!("{} states", states.len()),
                    format!("listed but satellites.count = {count}"),
                    "one state per satellite",
                ));
            }
            let mut out = Vec::with_capacity(count);
            for (i, s) in states.iter().enumerate() {
                c.finite(&format!("{key}.states[{i}]"), s)?;
                out.push(to_hill(*frame, s, inertial));
            }
            out
        }
        InitialSection::Csv { file, frame } => {
            let file_key = format!("{key}.file");
            let full = states_csv::resolve(c, &file_key, &scenario.base_dir, file)?;
            let rows = states_csv::read_states_csv(c, &file_key, &full)?;
            if rows.len() != count {
                return Err(c.bad(
                    &file_key,
                    full.display(),
                    format!("has {} rows but satellites.count = {count}", rows.len()),
                    "one row per satellite",
                ));
            }
            rows.iter()
                .map(|row| to_hill(row.frame.unwrap_or(*frame), &row.state, inertial))
                .collect()
        }
        InitialSection::Oem { .. } | InitialSection::Omm { .. } | InitialSection::Tle { .. } => {
            let input = inputs
                .swarm
                .as_ref()
                .expect("the orbit inputs hold the swarm's files");
            if input.len() != count {
                return Err(c.bad(
                    input.key(),
                    input.files(),
                    format!(
                        "holds {} objects but satellites.count = {count}",
                        input.len()
                    ),
                    "one object (element set) per satellite",
                ));
            }
            input
                .states_eme2000(c, epoch)?
                .iter()
                .map(inertial)
                .collect()
        }
    })
}

/// A listed state `s` in `frame` as a Hill-frame relative state (`inertial` places an EME2000 one).
fn to_hill(
    frame: ListFrame,
    s: &[f64; 6],
    inertial: &dyn Fn(&CartesianState) -> RelativeStateHill,
) -> RelativeStateHill {
    let p = Vector3::new(s[0], s[1], s[2]);
    let v = Vector3::new(s[3], s[4], s[5]);
    match frame {
        ListFrame::Eme2000 => inertial(&CartesianState::new(p, v)),
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
