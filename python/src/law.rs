//! A guidance law written in Python: any object with a method `command(ctx)` returning the commanded
//! accelerations of the whole swarm, an (N, 3) array \[m/s^2\] in the Hill LVLH frame (x radial out, y
//! along-track, z orbit normal).
//!
//! In the engine it is a [`GuidanceLaw`] without per-satellite state whose centralised step runs at
//! every control tick: it takes the GIL, builds a [`PyLawContext`] from the truth states of the whole
//! swarm (no navigation noise, no link outages: a whole-swarm step sees the truth), calls `command`,
//! checks the shape and the values, and stores the commands; its per-satellite command is the stored
//! row, which the actuators then limit like any law's. Sampled control only: in continuous mode a law is
//! evaluated at every Runge–Kutta stage, where no centralised step runs.

use std::sync::{Arc, Mutex};

use nalgebra::Vector3;
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray2};
use pyo3::exceptions::{PyKeyboardInterrupt, PySystemExit, PyTypeError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::PyString;

use satflock::grid::NeighbourGrid;
use satflock::scenario::{Prepared, Scenario, ScenarioError};
use satflock::swarm::{
    Centralised, ControlTiming, GuidanceLaw, Law, LawContext, LawError, SatelliteView, SwarmView,
};

use crate::errors::scenario_error;
use crate::records::readonly;

/// What a Python law's `command(ctx)` receives at a control tick: the whole swarm's truth states
/// (Hill LVLH frame: x radial out, y along-track, z orbit normal, relative to the LVLH origin) and its
/// neighbour lists. Arrays are read-only copies; row i is satellite i. The law sees the truth, without
/// navigation noise or link outages, because it is a whole-swarm (centralised) step. A removed
/// satellite has `active[i] == False`, rows of NaN and no neighbours; its command row is ignored.
#[pyclass(module = "satflock._native", name = "LawContext", frozen)]
pub struct PyLawContext {
    /// Time of the tick, seconds since the scenario start [s].
    #[pyo3(get)]
    time_s: f64,
    /// Index of the control tick, from 0.
    #[pyo3(get)]
    tick: u64,
    /// Control period [s]: the commands are held (zero-order hold) until the next tick.
    #[pyo3(get)]
    period_s: f64,
    /// Positions relative to the LVLH origin, Hill frame, shape (N, 3) [m] (NaN rows: removed).
    #[pyo3(get)]
    positions_hill: Py<PyAny>,
    /// Velocities relative to the rotating Hill frame, shape (N, 3) [m/s] (NaN rows: removed).
    #[pyo3(get)]
    velocities_hill: Py<PyAny>,
    /// Whether each satellite is still in the swarm, shape (N,) bool.
    #[pyo3(get)]
    active: Py<PyAny>,
    /// Masses, shape (N,) [kg].
    #[pyo3(get)]
    mass_kg: Py<PyAny>,
    /// Range of the sensors and links [m]: the neighbour lists hold the satellites within it.
    #[pyo3(get)]
    sensing_range_m: f64,
    /// Positions by axis, for the neighbour lists.
    axes_m: [Vec<f64>; 3],
    /// The neighbour lists in CSR form (offsets, indices), made on first use.
    neighbours: PyOnceLock<(Py<PyAny>, Py<PyAny>)>,
    /// Mean motion of the reference orbit [rad/s] (for HCW feed-forward terms).
    #[pyo3(get)]
    mean_motion_rad_per_s: f64,
}

impl PyLawContext {
    /// The CSR neighbour lists: a neighbour grid over the positions with the sensing range as radius
    /// (the engine's, built over the same truth positions), live satellites only, each list ascending.
    fn neighbours(&self, py: Python<'_>) -> PyResult<&(Py<PyAny>, Py<PyAny>)> {
        self.neighbours.get_or_try_init(py, || {
            let active: Vec<bool> = self.active.bind(py).extract()?;
            let n = active.len();
            let [x, y, z] = &self.axes_m;
            let mut grid = NeighbourGrid::new();
            // A non-finite position leaves the grid empty, as in the engine (no neighbours; the run
            // then stops as diverged).
            let built = grid.build(x, y, z, self.sensing_range_m).is_ok();
            let mut offsets: Vec<i64> = Vec::with_capacity(n + 1);
            let mut indices: Vec<i64> = Vec::new();
            offsets.push(0);
            for (i, live) in active.iter().enumerate() {
                let start = indices.len();
                if *live && built {
                    grid.for_each_neighbour(i, |nb| {
                        if active[nb.index] {
                            indices.push(nb.index as i64);
                        }
                    });
                }
                indices[start..].sort_unstable();
                offsets.push(indices.len() as i64);
            }
            let array = |values: Vec<i64>| -> PyResult<Py<PyAny>> {
                Ok(readonly(PyArray1::from_vec(py, values).into_any())?.unbind())
            };
            Ok((array(offsets)?, array(indices)?))
        })
    }
}

#[pymethods]
impl PyLawContext {
    /// CSR offsets, shape (N + 1,) int64: satellite i's neighbours are
    /// `neighbour_indices[neighbour_offsets[i]:neighbour_offsets[i + 1]]`. Made on first use (with
    /// `neighbour_indices`): a law that needs no neighbours does not pay for them.
    #[getter]
    fn neighbour_offsets(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        Ok(self.neighbours(py)?.0.clone_ref(py))
    }

    /// CSR indices, shape (M,) int64: the live satellites within `sensing_range_m` of each live
    /// satellite (itself excluded), ascending, found with the engine's neighbour grid
    /// (`satflock::grid`), not by testing all pairs.
    #[getter]
    fn neighbour_indices(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        Ok(self.neighbours(py)?.1.clone_ref(py))
    }

    /// Number of satellites N (removed ones included).
    #[getter]
    fn n_satellites(&self, py: Python<'_>) -> PyResult<usize> {
        self.active.bind(py).len()
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        Ok(format!(
            "LawContext(time_s={}, tick={}, n_satellites={})",
            self.time_s,
            self.tick,
            self.n_satellites(py)?
        ))
    }
}

/// The user's law object, checked: it has a callable `command`; `name` is its `name` attribute (a str)
/// or its class name.
pub struct PythonLawObject {
    object: Py<PyAny>,
    name: String,
    raised: Raised,
}

/// Where a Python law leaves a `KeyboardInterrupt` (or `SystemExit`) that `command(ctx)` raised: the run
/// stops as failed, and the caller raises this exception itself instead of `SimulationError`.
pub type Raised = Arc<Mutex<Option<PyErr>>>;

/// The exception a Python law left in `raised`, if any (taken out).
pub fn take_raised(raised: &Raised) -> Option<PyErr> {
    raised.lock().unwrap_or_else(|e| e.into_inner()).take()
}

impl PythonLawObject {
    /// Checks `law` (the argument `law=`).
    pub fn new(law: &Bound<'_, PyAny>) -> PyResult<Self> {
        let class = type_name(law);
        let callable = law
            .getattr_opt("command")?
            .is_some_and(|command| command.is_callable());
        if !callable {
            return Err(PyTypeError::new_err(format!(
                "law: an object of type `{class}` has no method command(ctx) (allowed: any object \
                 with a method command(ctx) returning an (N, 3) array of commanded accelerations, Hill \
                 frame, m/s^2)"
            )));
        }
        let name = match law.getattr_opt("name")? {
            Some(name) if name.is_instance_of::<PyString>() => name.extract::<String>()?,
            Some(name) if !name.is_none() => {
                return Err(PyTypeError::new_err(format!(
                    "law.name is a {} (allowed: a str, or no attribute `name`: the class name is \
                     used)",
                    type_name(&name)
                )))
            }
            _ => class,
        };
        Ok(Self {
            object: law.clone().unbind(),
            name,
            raised: Raised::default(),
        })
    }

    /// The slot where the law leaves a `KeyboardInterrupt` or `SystemExit` it raised ([`take_raised`]).
    pub fn raised(&self) -> Raised {
        self.raised.clone()
    }
}

/// The engine's side of a Python law.
struct PythonLaw {
    law: PythonLawObject,
    period_s: f64,
    /// Index of the next control tick.
    tick: u64,
    /// The commands of the current tick, one per satellite, Hill frame \[m/s^2\].
    commands: Vec<Vector3<f64>>,
}

impl PythonLaw {
    /// Calls `command(ctx)` with the swarm now and stores the commands; an error is the message of the
    /// run's failure.
    fn evaluate(&mut self, py: Python<'_>, swarm: &SwarmView<'_>) -> Result<(), String> {
        let ctx = context(py, swarm, self.tick, self.period_s).map_err(|e| describe(py, &e))?;
        let returned = self
            .law
            .object
            .bind(py)
            .call_method1("command", (ctx,))
            .map_err(|e| {
                let message = format!("command(ctx) raised an exception:\n{}", describe(py, &e));
                // Ctrl-C and sys.exit() are the caller's, not the law's failure: raised as they are.
                if e.is_instance_of::<PyKeyboardInterrupt>(py)
                    || e.is_instance_of::<PySystemExit>(py)
                {
                    *self.law.raised.lock().unwrap_or_else(|e| e.into_inner()) = Some(e);
                }
                message
            })?;
        let n = swarm.len();
        let expected = format!(
            "expected an array of shape ({n}, 3): one commanded acceleration per satellite, Hill frame, \
             m/s^2"
        );
        let array = py
            .import("numpy")
            .and_then(|np| np.call_method1("asarray", (&returned, "float64")))
            .map_err(|e| {
                format!(
                    "command(ctx) returned a {}, which is not an array of numbers ({expected}): {}",
                    type_name(&returned),
                    describe(py, &e)
                )
            })?;
        let shape = array.getattr("shape").map_err(|e| describe(py, &e))?;
        if shape.extract::<(usize, usize)>().ok() != Some((n, 3)) {
            // The shape as Python writes it: (20, 2), (60,), ().
            let shape = shape.repr().map_or_else(|_| "?".into(), |s| s.to_string());
            let what = if returned.is(&array) {
                format!("an array of shape {shape}")
            } else {
                format!("a {} (as an array: shape {shape})", type_name(&returned))
            };
            return Err(format!("command(ctx) returned {what} ({expected})"));
        }
        let array: PyReadonlyArray2<'_, f64> = array
            .extract()
            .map_err(|e| format!("command(ctx) returned an array numpy cannot lend: {e}"))?;
        let view = array.as_array();
        self.commands.clear();
        for (i, row) in view.rows().into_iter().enumerate() {
            let u = Vector3::new(row[0], row[1], row[2]);
            if swarm.active[i] && !(u.x.is_finite() && u.y.is_finite() && u.z.is_finite()) {
                return Err(format!(
                    "command(ctx) returned a non-finite command for satellite {i}: [{}, {}, {}] \
                     (allowed: finite accelerations, m/s^2; rows of removed satellites are ignored)",
                    u.x, u.y, u.z
                ));
            }
            self.commands.push(u);
        }
        Ok(())
    }
}

/// The name of an object's type.
pub fn type_name(object: &Bound<'_, PyAny>) -> String {
    object
        .get_type()
        .name()
        .map_or_else(|_| "?".into(), |n| n.to_string())
}

/// A Python exception as text: its traceback and message.
fn describe(py: Python<'_>, e: &PyErr) -> String {
    let formatted = py.import("traceback").and_then(|tb| {
        tb.call_method1(
            "format_exception",
            (e.get_type(py), e.value(py), e.traceback(py)),
        )?
        .extract::<Vec<String>>()
    });
    match formatted {
        Ok(lines) => lines.concat().trim_end().to_string(),
        Err(_) => e.to_string(),
    }
}

/// The context of a tick: the truth states of the whole swarm (its neighbour lists are made on use).
fn context<'py>(
    py: Python<'py>,
    swarm: &SwarmView<'_>,
    tick: u64,
    period_s: f64,
) -> PyResult<Bound<'py, PyLawContext>> {
    let n = swarm.len();
    let mut positions = Vec::with_capacity(3 * n);
    let mut velocities = Vec::with_capacity(3 * n);
    let mut axes_m = [
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
    ];
    for (s, live) in swarm.relative_states.iter().zip(swarm.active) {
        let row = |v: &Vector3<f64>| v.map(|x| if *live { x } else { f64::NAN });
        positions.extend(row(&s.position_m).iter());
        velocities.extend(row(&s.velocity_mps).iter());
        // The grid takes every position as the engine's does (finite for removed satellites too).
        for (axis, value) in axes_m.iter_mut().zip(s.position_m.iter()) {
            axis.push(*value);
        }
    }
    let matrix = |values: Vec<f64>| -> PyResult<Py<PyAny>> {
        Ok(readonly(PyArray1::from_vec(py, values).reshape([n, 3])?.into_any())?.unbind())
    };
    let vector =
        |array: Bound<'py, PyAny>| -> PyResult<Py<PyAny>> { Ok(readonly(array)?.unbind()) };
    Bound::new(
        py,
        PyLawContext {
            time_s: swarm.shared.time_s,
            tick,
            period_s,
            positions_hill: matrix(positions)?,
            velocities_hill: matrix(velocities)?,
            active: vector(PyArray1::from_slice(py, swarm.active).into_any())?,
            mass_kg: vector(PyArray1::from_slice(py, swarm.masses_kg).into_any())?,
            sensing_range_m: swarm.shared.sensing_range_m,
            axes_m,
            neighbours: PyOnceLock::new(),
            mean_motion_rad_per_s: swarm.shared.mean_motion_rad_s,
        },
    )
}

impl GuidanceLaw for PythonLaw {
    type State = ();
    type Parameters = ();
    satflock::capabilities!(Centralised);

    /// Registry name; the user's name is in every message of the law's own errors.
    fn name(&self) -> &'static str {
        "python"
    }

    fn command(
        &self,
        satellite: &SatelliteView<'_>,
        _state: &(),
        _context: &LawContext,
    ) -> Vector3<f64> {
        // Every tick starts with the centralised step, which fills the commands.
        self.commands
            .get(satellite.id())
            .copied()
            .unwrap_or_else(Vector3::zeros)
    }

    fn set_parameters(&mut self, _parameters: &()) -> Result<(), LawError> {
        Ok(())
    }
}

impl Centralised for PythonLaw {
    fn centralised_due(&self, _time_s: f64) -> bool {
        true
    }

    fn centralised_update(&mut self, swarm: &SwarmView<'_>) -> Result<(), LawError> {
        Python::attach(|py| self.evaluate(py, swarm)).map_err(|message| LawError::Failed {
            law: format!("python:{}", self.law.name),
            time_s: swarm.shared.time_s,
            message: format!("tick {}: {message}", self.tick),
        })?;
        self.tick += 1;
        Ok(())
    }
}

/// Validates the scenario and, with a Python law, puts it in place of the scenario's law (sampled
/// control only: a continuous-mode scenario is refused with `ScenarioError` on the key `control`).
pub fn prepare(scenario: &Scenario, law: Option<PythonLawObject>) -> PyResult<Prepared> {
    prepared_with(scenario, law).map_err(|e| scenario_error(&e))
}

/// [`prepare`] with the library's error (for the campaign runner, which records it in the run's row).
pub fn prepared_with(
    scenario: &Scenario,
    law: Option<PythonLawObject>,
) -> Result<Prepared, ScenarioError> {
    let mut prepared = scenario.prepare()?;
    let Some(law) = law else {
        return Ok(prepared);
    };
    let ControlTiming::Sampled { period_s } = prepared.config.control else {
        return Err(ScenarioError::invalid(
            &scenario.sources(),
            satflock::invalid::Invalid::new(
                "control",
                "mode = \"continuous\"",
                format!(
                    "cannot run the Python law `{}`, which is evaluated once per control tick",
                    law.name
                ),
                "with law=: mode = \"sampled\" with a period_s",
            ),
        ));
    };
    let source = format!("python:{}", law.name);
    let law = Law::new(PythonLaw {
        law,
        period_s,
        tick: 0,
        commands: Vec::new(),
    });
    prepared.replace_law(scenario, law, &source)?;
    Ok(prepared)
}
