//! `satflock.characterize` (the five elements of a set of positions, `satflock::metrics::five_elements`,
//! as `satflock characterize` prints them) and `satflock.propagate` (orbits without control,
//! `satflock::propagate`, as `satflock propagate` writes them), numpy arrays in and out.
//!
//! Arguments are read with `numpy.asarray(x, dtype=float64)`, so lists and integer arrays work too; a
//! wrong shape or a value that is not finite raises `ValueError` naming the argument (and the row) and
//! what is allowed.

use std::str::FromStr;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use numpy::{PyArray, PyArray1, PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;

use satflock::dynamics::{ForceSet, ForcesConfig, PhysicalProperties};
use satflock::integrate::{IntegratorMethod, Tolerances};
use satflock::metrics::{five_elements, FiveElementsWorkspace, MetricsError};
use satflock::orbit::{CartesianState, EarthModel, GravityModel, Vector3};
use satflock::propagate::{self as library, OutputFrame, PropagateError, PropagationSettings};

use crate::detached::{run_detached, threads_argument};

/// An array argument as float64: its shape and its values in C order.
fn float_array(arg: &Bound<'_, PyAny>, name: &str) -> PyResult<(Vec<usize>, Vec<f64>)> {
    let py = arg.py();
    let numpy = py.import("numpy")?;
    let kwargs = PyDict::new(py);
    kwargs.set_item("dtype", "float64")?;
    let array = numpy
        .call_method("asarray", (arg,), Some(&kwargs))
        .map_err(|e| {
            PyValueError::new_err(format!(
                "{name}: cannot be read as an array of numbers: {}",
                e.value(py)
            ))
        })?;
    let array = array.cast_into::<PyArrayDyn<f64>>()?;
    let shape = array.shape().to_vec();
    let values = array.readonly().as_array().iter().copied().collect();
    Ok((shape, values))
}

/// A shape as Python writes it: `(4, 3)`, `(6,)`, `()`.
fn shape_text(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// `(N, 3)` rows of an argument, refused (naming it) for another shape.
fn rows3(arg: &Bound<'_, PyAny>, name: &str, unit: &str) -> PyResult<Vec<[f64; 3]>> {
    let (shape, values) = float_array(arg, name)?;
    if shape.len() != 2 || shape[1] != 3 {
        return Err(PyValueError::new_err(format!(
            "{name} has shape {} (allowed: (N, 3), one row x, y, z per satellite, {unit})",
            shape_text(&shape)
        )));
    }
    Ok(values.chunks_exact(3).map(|r| [r[0], r[1], r[2]]).collect())
}

/// A metrics error as `ValueError` naming the argument (and the row) at fault.
fn metrics_error(e: &MetricsError, radii_scalar: bool) -> PyErr {
    let argument = |what: &str| match what {
        "velocity" | "velocities" => "velocities",
        "radii" => "radii",
        _ => "positions",
    };
    let at = match e {
        MetricsError::NonFinite { what, index } | MetricsError::OutOfRange { what, index, .. } => {
            format!("{}[{index}]", argument(what))
        }
        MetricsError::InvalidRadius { .. } if radii_scalar => "radii".into(),
        MetricsError::InvalidRadius { index, .. } => format!("radii[{index}]"),
        MetricsError::LengthMismatch { what, .. } => argument(what).into(),
        _ => "positions".into(),
    };
    PyValueError::new_err(format!("{at}: {e}"))
}

/// The five elements of a cluster (Gao, Li & Wei 2022, §2.1; `docs/methods/bifurcating.md` §2), as
/// `satflock characterize` prints them.
///
/// Arguments:
///     positions: (N, 3) satellite positions in m, N >= 2, in any one Cartesian frame (Hill LVLH,
///         EME2000 ...); the vectors of the result are in that frame.
///     radii: the satellites' physical radii in m (finite, >= 0) for d_min_m: a scalar for all, or
///         (N,); None: point satellites.
///     velocities: (N, 3) velocities in m/s, same frame; None: v_o_mps is left out.
///
/// Returns a dict:
///     n: number of satellites (element 1);
///     r_o_m: (3,) mean position in m (element 2);
///     v_o_mps: (3,) mean velocity in m/s (element 2; only when velocities are given);
///     d_max_m: outer boundary, the largest distance from a satellite to r_o_m, in m (element 3);
///     diameter_m: the largest distance between two satellites, in m;
///     d_min_m: inner boundary, the smallest surface gap |r_i - r_j| - a_i - a_j, in m (element 4;
///         negative when bodies overlap);
///     uniformity_l: distribution uniformity L = sum m_i^3 / M^3, dimensionless (element 5), with
///         m_i half the distance to satellite i's nearest neighbour and M = max_ij (|r_i - r_j| + m_i
///         + m_j) / 2.
///
/// Raises ValueError naming the argument (and the row) for a wrong shape, fewer than 2 satellites, a
/// value that is not finite or a negative radius. The GIL is released while it computes.
#[pyfunction]
#[pyo3(signature = (positions, radii = None, velocities = None))]
pub fn characterize<'py>(
    py: Python<'py>,
    positions: &Bound<'py, PyAny>,
    radii: Option<&Bound<'py, PyAny>>,
    velocities: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let positions = rows3(positions, "positions", "m")?;
    let n = positions.len();
    if n < 2 {
        return Err(PyValueError::new_err(format!(
            "positions has {n} rows (allowed: 2 satellites or more)"
        )));
    }
    let velocity_rows = velocities
        .map(|v| rows3(v, "velocities", "m/s"))
        .transpose()?;
    if let Some(v) = &velocity_rows {
        if v.len() != n {
            return Err(PyValueError::new_err(format!(
                "velocities has {} rows, positions {n} (allowed: one velocity per position)",
                v.len()
            )));
        }
    }
    let (radii_m, radii_scalar) = match radii {
        None => (None, false),
        Some(r) => {
            let (shape, values) = float_array(r, "radii")?;
            match shape.as_slice() {
                [] => (Some(vec![values[0]; n]), true),
                [k] if *k == n => (Some(values), false),
                _ => {
                    return Err(PyValueError::new_err(format!(
                        "radii has shape {} (allowed: a scalar or ({n},), one radius in m \
                         per satellite)",
                        shape_text(&shape)
                    )))
                }
            }
        }
    };
    let zeros;
    let velocities_mps = match &velocity_rows {
        Some(v) => v.as_slice(),
        None => {
            zeros = vec![[0.0; 3]; n];
            zeros.as_slice()
        }
    };
    let cancel = Arc::new(AtomicBool::new(false));
    let elements = run_detached(py, None, &cancel, || {
        five_elements(
            &positions,
            velocities_mps,
            radii_m.as_deref(),
            &mut FiveElementsWorkspace::new(),
        )
    })?
    .map_err(|e| metrics_error(&e, radii_scalar))?;
    let d = PyDict::new(py);
    d.set_item("n", elements.n)?;
    d.set_item("r_o_m", PyArray1::from_vec(py, elements.r_o_m.to_vec()))?;
    if velocity_rows.is_some() {
        d.set_item("v_o_mps", PyArray1::from_vec(py, elements.v_o_mps.to_vec()))?;
    }
    d.set_item("d_max_m", elements.d_max_m)?;
    d.set_item("diameter_m", elements.diameter_m)?;
    d.set_item("d_min_m", elements.d_min_m)?;
    d.set_item("uniformity_l", elements.uniformity_l)?;
    Ok(d)
}

/// One EME2000 state from six values.
fn state(v: &[f64]) -> CartesianState {
    CartesianState::new(
        Vector3::new(v[0], v[1], v[2]),
        Vector3::new(v[3], v[4], v[5]),
    )
}

/// A propagation error as `ValueError` (a setting or an orbit, named) or `SimulationError` (the
/// integrator failed).
fn propagate_error(e: &PropagateError, orbit: &str) -> PyErr {
    match e {
        PropagateError::InvalidSetting { .. } => PyValueError::new_err(e.to_string()),
        PropagateError::InvalidOrbit { reason, .. } => PyValueError::new_err(format!(
            "{orbit}: {reason} (allowed: a closed orbit with perigee altitude >= {} km; were \
             kilometres given as metres?)",
            library::MIN_PERIGEE_ALTITUDE_M / 1e3
        )),
        _ => crate::errors::SimulationError::new_err(format!("{orbit}: {e}")),
    }
}

/// What `propagate` returns: the output times `(R,)` and the states `(R, N, 6)` or `(R, 6)`.
type Propagated<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArrayDyn<f64>>);

/// Propagates orbits without control, as `satflock propagate` does (the same integrators, gravity
/// and frames, the same numbers).
///
/// Arguments:
///     states_eci: (6,) or (N, 6) EME2000 states x, y, z in m, vx, vy, vz in m/s. Each is propagated
///         alone (with the reference, for the LVLH frames), as `satflock propagate --state` propagates
///         one orbit, so its numbers do not depend on the other rows.
///     duration_s: length of the propagation in s (> 0).
///     step_s: RK4 step, or longest step of an adaptive integrator, in s (> 0).
///     output_step_s: spacing of the outputs in s: t = 0, output_step_s, 2 output_step_s ... up to
///         duration_s, and duration_s itself when it is not a multiple. None: step_s.
///     gravity: "j2" (point mass + J2) or "two-body" (point mass; also spelled "point-mass").
///     frame: "eme2000" (inertial; also spelled "inertial"), "lvlh-hill" (Hill LVLH of the reference:
///         x radial out, y along-track, z orbit normal) or "lvlh-gao" (Gao's o-xyz LVLH: x
///         along-track, y minus orbit normal, z nadir). LVLH velocities are seen in the rotating frame.
///     reference: (6,) EME2000 state of the reference orbit (m, m/s), propagated with the same
///         settings; required by the LVLH frames, refused with "eme2000".
///     threads: rows propagated at once (None: one per core).
///     integrator: "rk78" (adaptive Runge-Kutta-Fehlberg 7(8)), "dop853" (adaptive Dormand-Prince
///         8(5,3)) or "rk4" (fixed step).
///     rtol: relative tolerance of the adaptive integrators, in (0, 1).
///     atol: absolute tolerance of the adaptive integrators, in m and m/s (> 0).
///     mu_m3_s2, earth_radius_m, j2: the Earth's constants (None: WGS 84 mu and radius, EGM96 J2).
///
/// Returns (t_s, states): t_s (R,) output times in s, and states (R, N, 6) in the frame asked for (m,
/// m/s), or (R, 6) when states_eci is a single (6,) state.
///
/// Raises ValueError naming the argument (and the row) for a wrong shape, a value out of range or an
/// orbit that is not closed or whose perigee is below 100 km; SimulationError if the integrator fails.
/// The GIL is released while it runs; Ctrl-C stops it between rows.
#[pyfunction]
#[pyo3(signature = (
    states_eci, duration_s, step_s, output_step_s = None, gravity = "j2", frame = "eme2000",
    reference = None, threads = None, *, integrator = "rk78", rtol = 1e-12, atol = 1e-6,
    mu_m3_s2 = None, earth_radius_m = None, j2 = None, forces = None,
    epoch_utc = "2000-01-01T12:00:00Z"
))]
#[allow(clippy::too_many_arguments)]
pub fn propagate<'py>(
    py: Python<'py>,
    states_eci: &Bound<'py, PyAny>,
    duration_s: f64,
    step_s: f64,
    output_step_s: Option<f64>,
    gravity: &str,
    frame: &str,
    reference: Option<&Bound<'py, PyAny>>,
    threads: Option<&Bound<'py, PyAny>>,
    integrator: &str,
    rtol: f64,
    atol: f64,
    mu_m3_s2: Option<f64>,
    earth_radius_m: Option<f64>,
    j2: Option<f64>,
    forces: Option<&Bound<'py, PyDict>>,
    epoch_utc: &str,
) -> PyResult<Propagated<'py>> {
    let (shape, values) = float_array(states_eci, "states_eci")?;
    let single = match shape.as_slice() {
        [6] => true,
        [n, 6] if *n >= 1 => false,
        _ => {
            return Err(PyValueError::new_err(format!(
                "states_eci has shape {} (allowed: (6,) or (N, 6) with N >= 1: x, y, z in m, \
                 vx, vy, vz in m/s, EME2000)",
                shape_text(&shape)
            )))
        }
    };
    let orbits: Vec<CartesianState> = values.chunks_exact(6).map(state).collect();
    let row_name = |i: usize| {
        if single {
            "states_eci".to_string()
        } else {
            format!("states_eci[{i}]")
        }
    };
    let gravity_model = match gravity {
        "point-mass" => GravityModel::TwoBody,
        name => GravityModel::from_str(name).map_err(|_| {
            PyValueError::new_err(format!(
                "gravity = {name:?} (allowed: \"j2\", \"two-body\" or \"point-mass\")"
            ))
        })?,
    };
    let output_frame = match frame {
        "eme2000" | "inertial" => OutputFrame::Inertial,
        "lvlh-hill" => OutputFrame::LvlhHill,
        "lvlh-gao" => OutputFrame::LvlhGao,
        name => {
            return Err(PyValueError::new_err(format!(
                "frame = {name:?} (allowed: \"eme2000\" (or \"inertial\"), \"lvlh-hill\" or \
                 \"lvlh-gao\")"
            )))
        }
    };
    let integrator = IntegratorMethod::from_str(integrator).map_err(|_| {
        PyValueError::new_err(format!(
            "integrator = {integrator:?} (allowed: {})",
            IntegratorMethod::NAMES
                .map(|n| format!("\"{n}\""))
                .join(", ")
        ))
    })?;
    let reference =
        match (reference, output_frame.needs_reference()) {
            (Some(r), true) => {
                let (shape, values) = float_array(r, "reference")?;
                if shape != [6] {
                    return Err(PyValueError::new_err(format!(
                        "reference has shape {} (allowed: (6,): x, y, z in m, vx, vy, vz in m/s, \
                     EME2000)",
                        shape_text(&shape)
                    )));
                }
                Some(state(&values))
            }
            (None, true) => {
                return Err(PyValueError::new_err(format!(
                    "frame = {frame:?} needs a reference orbit: reference = its (6,) EME2000 state"
                )))
            }
            (Some(_), false) => return Err(PyValueError::new_err(
                "reference is used only with frame = \"lvlh-hill\" or \"lvlh-gao\" (allowed: None \
                 with frame = \"eme2000\")",
            )),
            (None, false) => None,
        };
    let defaults = EarthModel::WGS84_EGM96;
    let earth = EarthModel {
        mu_m3_s2: mu_m3_s2.unwrap_or(defaults.mu_m3_s2),
        equatorial_radius_m: earth_radius_m.unwrap_or(defaults.equatorial_radius_m),
        j2: j2.unwrap_or(defaults.j2),
    };
    let epoch = satflock::time::parse_epoch_utc(epoch_utc)
        .map_err(|m| PyValueError::new_err(format!("epoch_utc: {m}")))?;
    let (force_set, properties) = match forces {
        Some(table) => {
            if gravity != "j2" {
                return Err(PyValueError::new_err(
                    "gravity and forces both given (allowed: the gravity model inside forces, as \
                     forces = {\"gravity\": {\"model\": ...}})",
                ));
            }
            let table =
                crate::convert::dict_to_table(table, "forces").map_err(PyValueError::new_err)?;
            let config: ForcesConfig = toml::Value::Table(table)
                .try_into()
                .map_err(|e| PyValueError::new_err(format!("forces: {e}")))?;
            let invalid = |e: satflock::dynamics::ForceConfigError| {
                PyValueError::new_err(format!("forces: {e}"))
            };
            let set = ForceSet::from_config(&config, &earth, epoch).map_err(invalid)?;
            (set, config.satellite_properties().map_err(invalid)?)
        }
        None => (
            ForceSet::gravity(gravity_model, earth),
            PhysicalProperties::point_mass(1.0),
        ),
    };
    let settings = PropagationSettings {
        earth,
        forces: Arc::new(force_set),
        properties,
        integrator,
        step_s,
        tolerances: Tolerances {
            relative: rtol,
            absolute: atol,
        },
        duration_s,
        output_step_s: output_step_s.unwrap_or(step_s),
    };
    settings
        .check()
        .map_err(|e| propagate_error(&e, "settings"))?;
    for (i, orbit) in orbits.iter().enumerate() {
        settings
            .check_orbit(i, orbit)
            .map_err(|e| propagate_error(&e, &row_name(i)))?;
    }
    if let Some(r) = &reference {
        settings
            .check_orbit(0, r)
            .map_err(|e| propagate_error(&e, "reference"))?;
    }
    let cancel = Arc::new(AtomicBool::new(false));
    // Each row alone (with the reference): its times and its states in the output frame.
    type Track = (Vec<f64>, Vec<[f64; 6]>);
    let tracks: Vec<Option<Result<Track, PropagateError>>> =
        run_detached(py, threads_argument(threads)?, &cancel, || {
            orbits
                .par_iter()
                .map(|orbit| {
                    if cancel.load(Ordering::Relaxed) {
                        return None;
                    }
                    let mut initial = vec![*orbit];
                    initial.extend(reference);
                    let (mut t_s, mut rows) = (Vec::new(), Vec::new());
                    let result = library::propagate(&initial, &settings, |t, states| {
                        t_s.push(t);
                        rows.push(output_frame.express(&states[0], states.get(1)));
                    });
                    Some(result.map(|()| (t_s, rows)))
                })
                .collect()
        })?;
    let mut t_s = Vec::new();
    let mut columns = Vec::with_capacity(tracks.len());
    for (i, track) in tracks.into_iter().enumerate() {
        // Ctrl-C made run_detached return KeyboardInterrupt above: every row ran.
        let (t, rows) = track
            .ok_or_else(|| PyValueError::new_err("propagation stopped"))?
            .map_err(|e| propagate_error(&e, &row_name(i)))?;
        t_s = t;
        columns.push(rows);
    }
    let records = t_s.len();
    let n = columns.len();
    let mut flat = Vec::with_capacity(records * n * 6);
    for r in 0..records {
        for rows in &columns {
            flat.extend_from_slice(&rows[r]);
        }
    }
    let shape: Vec<usize> = if single {
        vec![records, 6]
    } else {
        vec![records, n, 6]
    };
    let states = PyArray::from_vec(py, flat).reshape(shape)?;
    Ok((PyArray1::from_vec(py, t_s), states))
}
