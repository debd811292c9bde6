//! The run's settings: the top-level times, `[earth]`, `[dynamics]` (integration, model and
//! force set, process noise), `[control]`, the run's size against `[output]`, and `[sensing]`.

use crate::dynamics::{ForceConfigError, ForceSet};
use crate::integrate::{IntegratorMethod, Tolerances};
use crate::orbit::{EarthModel, GravityModel, KeplerianElements};
use crate::relative::{Hcw, SchweighartSedwick};
use crate::scenario::schema::{
    ControlMode, ControlSection, DynamicsSection, EarthSection, ModelName, ScenarioFile,
    SensingSection,
};
use crate::scenario::ScenarioError;
use crate::swarm::{ControlTiming, DynamicsModel, Sensing};

use super::{
    Checker, LINEAR_MODEL_MAX_ECCENTRICITY, MAX_OUTPUT_ROWS, MAX_SATELLITE_STEPS,
    MAX_STEP_FRACTION_OF_PERIOD, MAX_VELOCITY_NOISE_FACTOR,
};

/// The run's length and recording cadence \[s\].
#[derive(Clone, Copy)]
pub(super) struct RunTimes {
    pub(super) duration_s: f64,
    pub(super) record_interval_s: f64,
}

/// The top level: `name`, `duration_s`, `record_interval_s`.
pub(super) fn run_times(c: &Checker<'_>, f: &ScenarioFile) -> Result<RunTimes, ScenarioError> {
    if f.name.trim().is_empty() {
        return Err(c.keys("name", "must not be empty", "any non-blank name"));
    }
    let duration_s = c.positive("duration_s", f.duration_s)?;
    let record_interval_s = c.positive("record_interval_s", f.record_interval_s)?;
    if record_interval_s > duration_s {
        return Err(c.bad(
            "record_interval_s",
            record_interval_s,
            format!("is longer than duration_s = {duration_s}"),
            "(0, duration_s]",
        ));
    }
    Ok(RunTimes {
        duration_s,
        record_interval_s,
    })
}

/// `[earth]`: each constant given, else WGS 84 / EGM96.
pub(super) fn earth(c: &Checker<'_>, e: &EarthSection) -> Result<EarthModel, ScenarioError> {
    let d = EarthModel::WGS84_EGM96;
    Ok(EarthModel {
        mu_m3_s2: c.positive("earth.mu_m3_s2", e.mu_m3_s2.unwrap_or(d.mu_m3_s2))?,
        equatorial_radius_m: c.positive(
            "earth.equatorial_radius_m",
            e.equatorial_radius_m.unwrap_or(d.equatorial_radius_m),
        )?,
        j2: c.non_negative("earth.j2", e.j2.unwrap_or(d.j2))?,
    })
}

/// The integration keys of `[dynamics]`.
pub(super) struct Integration {
    pub(super) step_s: f64,
    pub(super) tolerances: Tolerances,
    pub(super) max_distance_m: f64,
}

/// `[dynamics]` `step_s`, `rtol`, `atol`, `max_distance_m`.
pub(super) fn integration(
    c: &Checker<'_>,
    dy: &DynamicsSection,
) -> Result<Integration, ScenarioError> {
    let step_s = c.step("dynamics.step_s", dy.step_s)?;
    let rtol = c.positive("dynamics.rtol", dy.rtol)?;
    if rtol >= 1.0 {
        return Err(c.range("dynamics.rtol", rtol, "(0, 1)"));
    }
    let atol = c.positive("dynamics.atol", dy.atol)?;
    let max_distance_m = c.positive("dynamics.max_distance_m", dy.max_distance_m)?;
    Ok(Integration {
        step_s,
        tolerances: Tolerances {
            relative: rtol,
            absolute: atol,
        },
        max_distance_m,
    })
}

/// `[dynamics] model` and `[dynamics.forces]`, for the reference orbit's `elements`.
pub(super) fn dynamics_model(
    c: &Checker<'_>,
    dy: &DynamicsSection,
    earth: &EarthModel,
    elements: &KeplerianElements,
    epoch: crate::time::Epoch,
) -> Result<DynamicsModel, ScenarioError> {
    Ok(match (dy.model, &dy.forces) {
        (ModelName::J2 | ModelName::TwoBody, Some(forces)) => {
            force_set(c, dy.model, forces, earth, epoch)?
        }
        (_, Some(_)) => return Err(c.keys(
            "dynamics.forces",
            "force models act on inertial truth only",
            "with model = \"j2\" or \"two-body\"; the relative and kinematic models have their \
                 own equations",
        )),
        (ModelName::J2, None) => DynamicsModel::inertial(GravityModel::J2, *earth),
        (ModelName::TwoBody, None) => DynamicsModel::inertial(GravityModel::TwoBody, *earth),
        (ModelName::Kinematic, None) => DynamicsModel::Kinematic,
        (ModelName::Hcw | ModelName::J2Linear, None) => {
            if elements.eccentricity > LINEAR_MODEL_MAX_ECCENTRICITY {
                return Err(c.bad(
                    "dynamics.model",
                    format!(
                        "the reference orbit's eccentricity {:.5}",
                        elements.eccentricity
                    ),
                    "is too large: the linear relative models assume a circular reference orbit",
                    format!("<= {LINEAR_MODEL_MAX_ECCENTRICITY}"),
                ));
            }
            if dy.model == ModelName::Hcw {
                DynamicsModel::Hcw(Hcw::new(
                    earth.mean_motion_rad_s(elements.semi_major_axis_m),
                ))
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
        return Err(c.keys(
            "dynamics.forces.satellite",
            "is a `propagate --forces` table",
            "in a scenario: the properties as [satellites] keys, e.g. satellites.drag_area_m2, and \
             the virtual reference's as [reference] keys",
        ));
    }
    if model == ModelName::TwoBody && forces.gravity.model != GravityModelName::PointMass {
        return Err(c.bad(
            "dynamics.model",
            "\"two-body\"",
            "contradicts dynamics.forces.gravity.model",
            "model = \"j2\" (the default) with a [dynamics.forces] table, whose gravity.model then \
             decides",
        ));
    }
    let set = ForceSet::from_config(forces, earth, epoch)
        .map_err(|e| force_error(c, e, "dynamics.forces.", None))?;
    Ok(DynamicsModel::Inertial(std::sync::Arc::new(set)))
}

/// A force model's parameter error as the scenario's: the key under `prefix` (and the satellite's id
/// when the value came from a per-satellite list).
pub(super) fn force_error(
    c: &Checker<'_>,
    e: ForceConfigError,
    prefix: &str,
    id: Option<usize>,
) -> ScenarioError {
    let mut invalid = crate::invalid::Invalid::from(e).under(prefix);
    if let Some(id) = id {
        invalid.key = format!("{} (satellite {id})", invalid.key);
    }
    c.err(invalid)
}

/// Steps against the orbit period (the kinematic model has no orbital dynamics) and the recording
/// cadence against the step.
pub(super) fn check_step(
    c: &Checker<'_>,
    dy: &DynamicsSection,
    integration: &Integration,
    times: &RunTimes,
    period_s: f64,
) -> Result<(), ScenarioError> {
    let step_s = integration.step_s;
    let max_step_s = MAX_STEP_FRACTION_OF_PERIOD * period_s;
    if dy.model != ModelName::Kinematic
        && dy.integrator == IntegratorMethod::Rk4
        && step_s > max_step_s
    {
        return Err(c.bad(
            "dynamics.step_s",
            format!("{step_s} s"),
            format!(
                "is too long for the fixed-step RK4 integrator on an orbit of period {period_s:.1} s"
            ),
            format!(
                "(0, {max_step_s:.3}] s, 1/100 of the period, so that the integration error stays \
                 below about 1e-6 rad per orbit"
            ),
        ));
    }
    let record_interval_s = times.record_interval_s;
    if dy.integrator == IntegratorMethod::Rk4 && record_interval_s < step_s {
        return Err(c.bad(
            "record_interval_s",
            format!("{record_interval_s} s"),
            format!("is shorter than dynamics.step_s = {step_s} s"),
            "[dynamics.step_s, duration_s]: records are taken at steps",
        ));
    }
    Ok(())
}

/// `[control]`: the timing, the period against the orbit's.
pub(super) fn control(
    c: &Checker<'_>,
    control: &ControlSection,
    model: ModelName,
    period_s: f64,
) -> Result<ControlTiming, ScenarioError> {
    let max_step_s = MAX_STEP_FRACTION_OF_PERIOD * period_s;
    Ok(match (control.mode, control.period_s) {
        (ControlMode::Continuous, None) => ControlTiming::Continuous,
        (ControlMode::Continuous, Some(_)) => {
            return Err(c.keys(
                "control.period_s",
                "applies only to mode = \"sampled\"",
                "remove it, or set mode = \"sampled\"",
            ))
        }
        (ControlMode::Sampled, None) => {
            return Err(c.keys(
                "control.period_s",
                "is required with mode = \"sampled\"",
                "a period > 0 s",
            ))
        }
        (ControlMode::Sampled, Some(p)) => {
            let p = c.step("control.period_s", p)?;
            if model != ModelName::Kinematic && p > max_step_s {
                return Err(c.bad(
                    "control.period_s",
                    format!("{p} s"),
                    format!("is too long for an orbit of period {period_s:.1} s"),
                    format!(
                        "(0, {max_step_s:.3}] s, 1/100 of the period: a coarser control cannot \
                         follow the orbital dynamics it acts on"
                    ),
                ));
            }
            ControlTiming::Sampled { period_s: p }
        }
    })
}

/// The run's base step \[s\]: the shorter of the control period and the integration step.
pub(super) fn base_step_s(control: ControlTiming, step_s: f64) -> f64 {
    match control {
        ControlTiming::Sampled { period_s } => period_s.min(step_s),
        ControlTiming::Continuous => step_s,
    }
}

/// `[output]` and the run's size: a tiny step or record interval that would run or write far beyond
/// what a user means is refused unless `allow_large` asks for it.
pub(super) fn output_size(
    c: &Checker<'_>,
    f: &ScenarioFile,
    times: &RunTimes,
    control: ControlTiming,
    step_s: f64,
    count: usize,
) -> Result<(), ScenarioError> {
    if f.output.oem && !f.output.trajectory {
        return Err(c.bad(
            "output.oem",
            "true",
            "needs output.trajectory = true",
            "output.oem = true with output.trajectory = true: the OEM is written from trajectory.csv",
        ));
    }
    if f.output.allow_large {
        return Ok(());
    }
    let RunTimes {
        duration_s,
        record_interval_s,
    } = *times;
    let base_step_s = base_step_s(control, step_s);
    let satellite_steps = duration_s / base_step_s * count as f64;
    if satellite_steps > MAX_SATELLITE_STEPS {
        let key = match control {
            ControlTiming::Sampled { period_s } if period_s < step_s => "control.period_s",
            _ => "dynamics.step_s",
        };
        return Err(c.bad(
            key,
            format!("{base_step_s} s"),
            format!(
                "over duration_s = {duration_s} s for {count} satellites is \
                 {satellite_steps:.3e} satellite-steps"
            ),
            format!("<= {MAX_SATELLITE_STEPS:.0e} unless [output] allow_large = true"),
        ));
    }
    let rows = (duration_s / record_interval_s + 1.0)
        * if f.output.trajectory {
            count as f64
        } else {
            1.0
        };
    if rows > MAX_OUTPUT_ROWS {
        return Err(c.bad(
            "record_interval_s",
            format!("{record_interval_s} s"),
            format!("over duration_s = {duration_s} s writes {rows:.3e} rows"),
            format!(
                "<= {MAX_OUTPUT_ROWS:.0e} unless [output] allow_large = true; or turn [output] \
                 trajectory off"
            ),
        ));
    }
    Ok(())
}

/// `[sensing]`, the velocity noise against the orbit's mean motion \[rad/s\].
pub(super) fn sensing(
    c: &Checker<'_>,
    s: &SensingSection,
    mean_motion_rad_s: f64,
) -> Result<Sensing, ScenarioError> {
    let range_m = c.positive("sensing.range_m", s.range_m)?;
    let position_noise_m = c.non_negative("sensing.position_noise_m", s.position_noise_m)?;
    if position_noise_m > range_m {
        return Err(c.bad(
            "sensing.position_noise_m",
            format!("{position_noise_m} m"),
            format!("is larger than sensing.range_m = {range_m} m"),
            "[0, sensing.range_m]: a 1-sigma error beyond the range makes every sensed position noise",
        ));
    }
    let velocity_noise_mps = c.non_negative("sensing.velocity_noise_mps", s.velocity_noise_mps)?;
    let max_velocity_noise = MAX_VELOCITY_NOISE_FACTOR * mean_motion_rad_s * range_m;
    if velocity_noise_mps > max_velocity_noise {
        return Err(c.range(
            "sensing.velocity_noise_mps",
            format!("{velocity_noise_mps} m/s"),
            format!(
                "[0, {max_velocity_noise:.3e}] m/s, 10 n R with n = {mean_motion_rad_s:.3e} rad/s \
                 and R = sensing.range_m: orbital relative velocities across the sensing range are \
                 about 2 n R"
            ),
        ));
    }
    let ring_neighbours = match s.ring_neighbours {
        Some(0) => return Err(c.range(
            "sensing.ring_neighbours",
            0,
            "an integer >= 1, the satellites sensed on each side along the orbit; leave the key \
                 out to sense by range",
        )),
        k => k.map(|k| k as usize),
    };
    Ok(Sensing {
        range_m,
        position_noise_m,
        velocity_noise_mps,
        ring_neighbours,
    })
}

/// `[dynamics] process_noise_mps2` \[m/s^2\] (the kinematic model has no forces to disturb).
pub(super) fn process_noise(
    c: &Checker<'_>,
    dy: &DynamicsSection,
    dynamics: &DynamicsModel,
) -> Result<f64, ScenarioError> {
    let noise = c.non_negative("dynamics.process_noise_mps2", dy.process_noise_mps2)?;
    if noise > 0.0 && *dynamics == DynamicsModel::Kinematic {
        return Err(c.bad(
            "dynamics.process_noise_mps2",
            noise,
            "is given but the kinematic model has no forces to disturb",
            "0 with model = \"kinematic\"",
        ));
    }
    Ok(noise)
}
