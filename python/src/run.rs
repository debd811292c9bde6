//! `satflock._native.run`: a whole run through the library's `run_prepared` (the command line's own
//! path: the same files in the output directory), with the GIL released on chosen threads, stopped
//! cleanly by Ctrl-C, and read back from its files (`RunData`: CSV or Parquet) into numpy arrays.
//! `satflock.run` (python/satflock/_run.py) wraps it: temporary output folder, progress display,
//! `RunResult`.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

use satflock::output::RunData;
use satflock::run::{run_prepared, RunError, RunOptions};
use satflock::scenario::Scenario;

use crate::detached::run_detached;
use crate::detached::threads_argument;
use crate::errors::{scenario_error, SimulationError};
use crate::law::{prepare, take_raised, type_name, PythonLawObject};
use crate::records::{metrics_columns, trajectory_arrays};
use crate::scenario::PyScenario;

/// The scenario of an argument `scenario`: a `Scenario`, or a path (`str` or `os.PathLike`) or a
/// built-in name, loaded as `Scenario.load` does.
pub fn scenario_argument(scenario: &Bound<'_, PyAny>) -> PyResult<Scenario> {
    let loaded = match scenario.extract::<PyRef<'_, PyScenario>>() {
        Ok(s) => s.scenario(),
        Err(_) => {
            let py = scenario.py();
            let text = py
                .import("os")?
                .call_method1("fspath", (scenario,))
                .ok()
                .filter(|p| p.is_instance_of::<PyString>())
                .ok_or_else(|| {
                    PyValueError::new_err(format!(
                        "scenario is a {} (allowed: a satflock.Scenario, a built-in scenario name or a \
                         path)",
                        type_name(scenario)
                    ))
                })?;
            Scenario::load(&text.extract::<String>()?)
        }
    };
    loaded.map_err(|e| scenario_error(&e))
}

/// A run's error as the Python exception: `ScenarioError` for an invalid scenario, `ValueError` for an
/// output directory that cannot be used, `SimulationError` (the message the CLI prints) otherwise.
pub fn run_error(e: &RunError) -> PyErr {
    match e {
        RunError::Scenario(e) => scenario_error(e),
        RunError::OutputDirectory { .. } => PyValueError::new_err(format!("out: {e}")),
        _ => SimulationError::new_err(e.to_string()),
    }
}

/// Runs `scenario` into the folder `out` and reads the result back: a dict with `summary` (the text
/// of summary.json), `metrics` (see `records::metrics_columns`) and `trajectory` (see
/// `records::trajectory_arrays`, or None). `progress(t_s)` is called with the simulated time [s] each
/// time it passes a whole percent of the run; an exception it raises stops the run and is raised.
#[pyfunction]
#[pyo3(signature = (scenario, out, threads = None, progress = None, law = None))]
pub fn run<'py>(
    py: Python<'py>,
    scenario: &Bound<'py, PyAny>,
    out: PathBuf,
    threads: Option<&Bound<'py, PyAny>>,
    progress: Option<Py<PyAny>>,
    law: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let threads = threads_argument(threads)?;
    let law = law.map(PythonLawObject::new).transpose()?;
    let raised = law.as_ref().map(PythonLawObject::raised);
    let scenario = scenario_argument(scenario)?;
    let prepared = prepare(&scenario, law)?;
    let duration_s = prepared.config.duration_s;
    let cancel = Arc::new(AtomicBool::new(false));
    let options = RunOptions {
        cancel: Some(cancel.clone()),
        format: None,
    };
    let mut callback_error: Option<PyErr> = None;
    let mut percent_reported = -1.0;
    let mut report = |t_s: f64| {
        let Some(callback) = &progress else {
            return;
        };
        let percent = (100.0 * t_s / duration_s).floor();
        if percent == percent_reported || callback_error.is_some() {
            return;
        }
        percent_reported = percent;
        if let Err(e) = Python::attach(|py| callback.bind(py).call1((t_s,)).map(|_| ())) {
            callback_error = Some(e);
            cancel.store(true, Ordering::Relaxed);
        }
    };
    let outcome = run_detached(py, threads, &cancel, || {
        run_prepared(&scenario, prepared, &out, &options, &mut report)
    })?;
    if let Some(e) = callback_error.or_else(|| raised.as_ref().and_then(take_raised)) {
        return Err(e);
    }
    outcome.map_err(|e| run_error(&e))?;
    let data = RunData::read(&out).map_err(|e| SimulationError::new_err(e.to_string()))?;
    let result = PyDict::new(py);
    result.set_item("summary", data.summary.to_string())?;
    result.set_item("metrics", metrics_columns(py, &data.metrics, data.epoch)?)?;
    let trajectory = match &data.trajectory {
        Some(table) => {
            let n = data.summary["n_satellites"].as_u64().unwrap_or(0) as usize;
            let times = data.metrics.column("t_s").unwrap_or_default();
            Some(trajectory_arrays(py, table, times, n)?)
        }
        None => None,
    };
    result.set_item("trajectory", trajectory)?;
    Ok(result)
}

/// Every scalar outcome of a run's `summary.json` text, by dotted name (sorted by name), as
/// `satflock compare` and campaigns tabulate them (`satflock::output::scalar_outcomes`; the
/// machine-dependent keys such as `timing` and `threads` left out).
#[pyfunction]
pub fn scalar_outcomes(summary_json: &str) -> PyResult<Vec<(String, f64)>> {
    let summary: serde_json::Value = serde_json::from_str(summary_json)
        .map_err(|e| PyValueError::new_err(format!("summary.json is not JSON: {e}")))?;
    Ok(satflock::output::scalar_outcomes(&summary))
}
