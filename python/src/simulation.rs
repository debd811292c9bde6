//! `satflock.Simulation`: a scenario stepped from Python. The library's `Simulation`, built as
//! `satflock.run` builds it (the scenario's law, or a Python law in its place), advanced with the GIL
//! released on the simulation's own threads and stoppable by Ctrl-C, with an in-memory recorder that
//! keeps the rows the CLI writes (same columns, same values).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use satflock::output::OutputColumns;
use satflock::run::build_prepared;
use satflock::swarm::Simulation;
use satflock::time::Epoch;

use crate::detached::threads_argument;
use crate::detached::{run_in_pool, thread_pool};
use crate::errors::SimulationError;
use crate::law::{prepare, take_raised, PythonLawObject, Raised};
use crate::records::{metrics_columns, readonly, trajectory_arrays, MemoryRecorder};
use crate::run::{run_error, scenario_argument};

/// A scenario's simulation, advanced step by step from Python.
///
/// The arrays it returns are read-only copies (the engine keeps each satellite's state as one struct,
/// array-of-structures, so no numpy view of them is possible). Satellites removed by an event are rows
/// of NaN. Frames: Hill LVLH (x radial out, y along-track, z orbit normal) relative to the LVLH origin;
/// EME2000 inertial.
#[pyclass(module = "satflock._native", name = "Simulation", subclass)]
pub struct PySimulation {
    simulation: Simulation,
    recorder: MemoryRecorder,
    epoch: Epoch,
    pool: Option<rayon::ThreadPool>,
    cancel: Arc<AtomicBool>,
    /// Where a Python law leaves a `KeyboardInterrupt` it raised (raised as is by `advance`).
    raised: Option<Raised>,
}

impl PySimulation {
    /// Advances to `t_s` with the GIL released, recording; Ctrl-C raises `KeyboardInterrupt` and leaves
    /// the simulation at the time reached.
    fn advance(&mut self, py: Python<'_>, t_s: f64) -> PyResult<()> {
        self.cancel.store(false, Ordering::Relaxed);
        let Self {
            simulation,
            recorder,
            pool,
            cancel,
            ..
        } = self;
        simulation.set_cancel_flag(cancel.clone());
        let outcome = run_in_pool(py, pool.as_ref(), cancel, || {
            simulation.advance_to(t_s, recorder)
        })?;
        if let Some(e) = self.raised.as_ref().and_then(take_raised) {
            return Err(e);
        }
        outcome.map_err(|e| SimulationError::new_err(e.to_string()))
    }

    /// `values` (one per satellite, `width` numbers each) as an (N, width) read-only array, NaN rows
    /// for removed satellites.
    fn per_satellite<'py>(
        &self,
        py: Python<'py>,
        width: usize,
        values: impl Iterator<Item = f64>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let active = self.simulation.active();
        let mut data: Vec<f64> = values.collect();
        for (i, row) in data.chunks_mut(width).enumerate() {
            if !active[i] {
                row.fill(f64::NAN);
            }
        }
        readonly(
            PyArray1::from_vec(py, data)
                .reshape([active.len(), width])?
                .into_any(),
        )
    }
}

#[pymethods]
impl PySimulation {
    /// Builds the simulation of `scenario` (a `Scenario`, a built-in name or a path) at t = 0, with the
    /// scenario's law or the Python law `law` in its place (see `satflock.run`); `threads`: rayon
    /// threads for every advance (None: one per core). The record at t = 0 is taken at once.
    #[new]
    #[pyo3(signature = (scenario, law = None, threads = None))]
    fn new(
        scenario: &Bound<'_, PyAny>,
        law: Option<&Bound<'_, PyAny>>,
        threads: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let pool = thread_pool(threads_argument(threads)?)?;
        let law = law.map(PythonLawObject::new).transpose()?;
        let raised = law.as_ref().map(PythonLawObject::raised);
        let scenario = scenario_argument(scenario)?;
        let prepared = prepare(&scenario, law)?;
        let (epoch, with_trajectory) = (prepared.epoch, prepared.write_trajectory);
        let mut simulation = build_prepared(&scenario, prepared).map_err(|e| run_error(&e))?;
        let mut recorder =
            MemoryRecorder::new(OutputColumns::of(&simulation), epoch, with_trajectory);
        simulation
            .advance_to(0.0, &mut recorder)
            .map_err(|e| SimulationError::new_err(e.to_string()))?;
        Ok(Self {
            simulation,
            recorder,
            epoch,
            pool,
            cancel: Arc::new(AtomicBool::new(false)),
            raised,
        })
    }

    /// Advances to `t_s` [s] (allowed: from `time_s` to `duration_s`), through the same scheduler as a
    /// whole run: control ticks, events and records happen exactly as in `satflock.run`, and advancing
    /// to recording or tick times gives bit-identical results. The GIL is released; Ctrl-C raises
    /// `KeyboardInterrupt` and leaves the simulation usable at the time reached. A run that fails
    /// (divergence, a Python law that fails) raises `SimulationError`.
    fn advance_to(&mut self, py: Python<'_>, t_s: f64) -> PyResult<()> {
        let (now, end) = (self.simulation.time_s(), self.duration_s());
        if !(t_s >= now && t_s <= end) {
            return Err(PyValueError::new_err(format!(
                "t_s = {t_s} is out of range (allowed: [{now}, {end}] s, from the current time to the \
                 end of the run)"
            )));
        }
        self.advance(py, t_s)
    }

    /// Advances to the next control tick (the next integration step in continuous mode), recording on
    /// the way as a run does; does nothing at the end of the run.
    fn step(&mut self, py: Python<'_>) -> PyResult<()> {
        let next = self.simulation.next_tick_s().min(self.duration_s());
        self.advance(py, next)
    }

    /// Advances to the end of the run (`duration_s`).
    fn run(&mut self, py: Python<'_>) -> PyResult<()> {
        let end = self.duration_s();
        self.advance(py, end)
    }

    /// Current time, seconds since the scenario start [s].
    #[getter]
    fn time_s(&self) -> f64 {
        self.simulation.time_s()
    }

    /// Length of the run [s].
    #[getter]
    fn duration_s(&self) -> f64 {
        self.simulation.config().duration_s
    }

    /// Number of satellites N (removed ones included).
    #[getter]
    fn n_satellites(&self) -> usize {
        self.simulation.satellite_count()
    }

    /// Positions relative to the LVLH origin, Hill frame, (N, 3) [m]: a read-only copy, NaN rows for
    /// removed satellites.
    #[getter]
    fn positions_hill<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let states = self.simulation.states_hill();
        self.per_satellite(
            py,
            3,
            states.iter().flat_map(|s| s.position_m.iter().copied()),
        )
    }

    /// Velocities relative to the rotating Hill frame, (N, 3) [m/s]: a read-only copy, NaN rows for
    /// removed satellites.
    #[getter]
    fn velocities_hill<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let states = self.simulation.states_hill();
        self.per_satellite(
            py,
            3,
            states.iter().flat_map(|s| s.velocity_mps.iter().copied()),
        )
    }

    /// Positions, EME2000 inertial, (N, 3) [m]: a read-only copy, NaN rows for removed satellites.
    #[getter]
    fn positions_eci<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let states = self.simulation.states_eci();
        self.per_satellite(
            py,
            3,
            states.iter().flat_map(|s| s.position_m.iter().copied()),
        )
    }

    /// Velocities, EME2000 inertial, (N, 3) [m/s]: a read-only copy, NaN rows for removed satellites.
    #[getter]
    fn velocities_eci<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let states = self.simulation.states_eci();
        self.per_satellite(
            py,
            3,
            states.iter().flat_map(|s| s.velocity_mps.iter().copied()),
        )
    }

    /// Whether each satellite is still in the swarm, (N,) bool (a read-only copy).
    #[getter]
    fn active<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        readonly(PyArray1::from_vec(py, self.simulation.active()).into_any())
    }

    /// The running law's per-satellite outputs now: a dict name -> (N,) read-only array (units in the
    /// names), NaN for removed satellites. Empty for laws without outputs.
    #[getter]
    fn law_outputs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let names = self.simulation.law().output_names();
        let values = self.simulation.law_outputs();
        let dict = PyDict::new(py);
        for (k, name) in names.iter().enumerate() {
            let column = values.iter().skip(k).step_by(names.len().max(1)).copied();
            let array = self.per_satellite(py, 1, column)?;
            dict.set_item(name, array.call_method1("reshape", (self.n_satellites(),))?)?;
        }
        Ok(dict)
    }

    /// The trajectory recorded so far as a dict of arrays (`satflock.Simulation.trajectory` wraps it in
    /// a `Trajectory`); None when the scenario writes no trajectory.
    fn _trajectory_arrays<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(table) = self.recorder.trajectory() else {
            return Ok(None);
        };
        let metrics = self.recorder.metrics();
        let times = metrics.column("t_s").unwrap_or_default();
        trajectory_arrays(py, &table, times, self.n_satellites()).map(Some)
    }

    /// The metrics recorded so far as a dict of columns (`satflock.Simulation.metrics` makes it a
    /// `pyarrow.Table` where pyarrow imports).
    fn _metrics_columns<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        metrics_columns(py, &self.recorder.metrics(), self.epoch)
    }

    fn __repr__(&self) -> String {
        format!(
            "Simulation(time_s={}, duration_s={}, n_satellites={})",
            self.time_s(),
            self.duration_s(),
            self.n_satellites()
        )
    }
}
