//! `satflock.budget`: the perturbation budget of a satellite pair (`satflock::budget`, as `satflock
//! budget` prints it), as a dict of rows. Values out of range raise `ValueError` naming the argument
//! and the allowed range.

use std::str::FromStr;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use satflock::budget::{
    budget as library_budget, BudgetError, BudgetInput, SeparationDirection, MAX_ALTITUDE_M,
    MAX_SEPARATION_M, MIN_ALTITUDE_M,
};
use satflock::dynamics::PhysicalProperties;

/// A library error as `ValueError` naming the Python argument that set the value.
fn argument_error(e: &BudgetError) -> PyErr {
    let field = e.key.rsplit('.').next().unwrap_or(&e.key);
    let second = e.key.starts_with("satellite_2.");
    let argument = match field {
        "drag_area_m2" if second => "drag_area_2_m2",
        "srp_area_m2" if second => "srp_area_2_m2",
        "mass_kg"
        | "drag_area_m2"
        | "drag_coefficient"
        | "srp_area_m2"
        | "reflectivity_coefficient" => field,
        _ => return PyValueError::new_err(e.to_string()),
    };
    PyValueError::new_err(format!(
        "{argument} = {} is out of range (allowed: {})",
        e.value, e.allowed
    ))
}

/// The perturbation budget of a satellite pair on a circular orbit, as `satflock budget` prints it:
/// for each term (J2, J3, J4, J5, J6 each alone from EGM96, drag, SRP without shadow, the Sun, the
/// Moon, and the HCW linearisation error) the acceleration on satellite 1, the differential
/// acceleration and the along-track drift it causes. Orders of magnitude for deciding what to
/// neglect; the method is in docs/dynamics.md and the `satflock::budget` documentation.
///
/// Arguments:
///     altitude_m: altitude of satellite 1's circular orbit above the equatorial radius, m (100e3 to
///         2000e3).
///     inclination_deg: inclination, deg (0 to 180).
///     separation_m: distance between the satellites along the arc, m (> 0, at most 100e3).
///     direction: "along-track" (the same orbit, ahead), "radial" (a coplanar orbit, higher) or
///         "cross-track" (an orbit inclined more, about the same nodes).
///     mass_kg: each satellite's mass, kg (> 0).
///     drag_area_m2: satellite 1's drag area, m^2 (>= 0).
///     drag_area_2_m2: satellite 2's drag area, m^2 (None: twice drag_area_m2, so that the
///         differential drag shows).
///     drag_coefficient: C_d of both (0 to 10).
///     srp_area_m2: satellite 1's area facing the Sun, m^2 (None: its drag area).
///     srp_area_2_m2: satellite 2's, m^2 (None: its drag area).
///     reflectivity_coefficient: C_r of both (0 to 2).
///     atmosphere: "harris-priester" or "exponential-table" (Vallado's static table).
///     epoch_utc: the instant of the budget (ISO 8601 UTC): the Sun's and the Moon's positions, the
///         atmosphere's diurnal bulge.
///
/// Returns a dict, term name -> dict with "acceleration_mps2" (orbit mean of |a| on satellite 1,
/// m/s^2; None for "hcw-linearisation"), "differential_acceleration_mps2" (orbit mean of |a_2 - a_1|,
/// m/s^2), "drift_per_orbit_m" and "drift_per_day_m" (secular along-track drift, m).
#[pyfunction]
#[pyo3(signature = (
    altitude_m, inclination_deg, separation_m = 1000.0, direction = "along-track", *, mass_kg,
    drag_area_m2, drag_area_2_m2 = None, drag_coefficient = 2.2, srp_area_m2 = None,
    srp_area_2_m2 = None, reflectivity_coefficient = 1.5, atmosphere = "harris-priester",
    epoch_utc = "2000-01-01T12:00:00Z"
))]
#[allow(clippy::too_many_arguments)]
pub fn budget<'py>(
    py: Python<'py>,
    altitude_m: f64,
    inclination_deg: f64,
    separation_m: f64,
    direction: &str,
    mass_kg: f64,
    drag_area_m2: f64,
    drag_area_2_m2: Option<f64>,
    drag_coefficient: f64,
    srp_area_m2: Option<f64>,
    srp_area_2_m2: Option<f64>,
    reflectivity_coefficient: f64,
    atmosphere: &str,
    epoch_utc: &str,
) -> PyResult<Bound<'py, PyDict>> {
    // The default is written out (not the constant) so that the signature Python sees shows it; it
    // is `satflock::time::DEFAULT_EPOCH_UTC`, as the command line's.
    debug_assert_eq!(satflock::time::DEFAULT_EPOCH_UTC, "2000-01-01T12:00:00Z");
    let range = |name: &str, value: f64, ok: bool, allowed: &str| {
        if value.is_finite() && ok {
            Ok(())
        } else {
            Err(PyValueError::new_err(format!(
                "{name} = {value} is out of range (allowed: {allowed})"
            )))
        }
    };
    range(
        "altitude_m",
        altitude_m,
        (MIN_ALTITUDE_M..=MAX_ALTITUDE_M).contains(&altitude_m),
        "100e3 to 2000e3 m",
    )?;
    range(
        "inclination_deg",
        inclination_deg,
        (0.0..=180.0).contains(&inclination_deg),
        "0 to 180 deg",
    )?;
    range(
        "separation_m",
        separation_m,
        separation_m > 0.0 && separation_m <= MAX_SEPARATION_M,
        "> 0 and at most 100e3 m",
    )?;
    let direction = SeparationDirection::from_str(direction)
        .map_err(|m| PyValueError::new_err(format!("direction: {m}")))?;
    let drag = match atmosphere {
        "harris-priester" => BudgetInput::harris_priester(),
        "exponential-table" => BudgetInput::exponential_table(),
        other => {
            return Err(PyValueError::new_err(format!(
                "atmosphere = {other:?} (allowed: \"harris-priester\" or \"exponential-table\")"
            )))
        }
    };
    let epoch = satflock::time::parse_epoch_utc(epoch_utc)
        .map_err(|m| PyValueError::new_err(format!("epoch_utc: {m}")))?;
    let properties = |drag_area_m2: f64, srp_area_m2: Option<f64>| PhysicalProperties {
        mass_kg,
        drag_area_m2,
        drag_coefficient,
        srp_area_m2: srp_area_m2.unwrap_or(drag_area_m2),
        reflectivity_coefficient,
    };
    let input = BudgetInput {
        altitude_m,
        inclination_rad: inclination_deg.to_radians(),
        epoch,
        separation_m,
        direction,
        satellite_1: properties(drag_area_m2, srp_area_m2),
        satellite_2: properties(drag_area_2_m2.unwrap_or(2.0 * drag_area_m2), srp_area_2_m2),
        drag,
    };
    let b = library_budget(&input).map_err(|e| argument_error(&e))?;
    let out = PyDict::new(py);
    for row in &b.terms {
        let d = PyDict::new(py);
        d.set_item("acceleration_mps2", row.acceleration_mps2)?;
        d.set_item(
            "differential_acceleration_mps2",
            row.differential_acceleration_mps2,
        )?;
        d.set_item("drift_per_orbit_m", row.drift_per_orbit_m)?;
        d.set_item("drift_per_day_m", row.drift_per_day_m)?;
        out.set_item(row.term.name(), d)?;
    }
    Ok(out)
}
