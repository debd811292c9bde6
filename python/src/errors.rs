//! The Python exceptions of `satflock` and the conversion of the library's errors into them. Every
//! exception carries the message the command-line tool would print; `ScenarioError` also carries the
//! file and the key as attributes.

use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

use satflock::scenario::ScenarioError as RustScenarioError;

create_exception!(
    _native,
    ScenarioError,
    PyValueError,
    "A scenario that cannot be read or is invalid: `file`, `key` (dotted; None when the whole file is \
     at fault) and the message with the allowed range."
);
create_exception!(
    _native,
    SimulationError,
    PyRuntimeError,
    "A run that could not finish: divergence (naming the satellite and time), a law that failed, or an \
     output that could not be written."
);
create_exception!(
    _native,
    CampaignError,
    PyValueError,
    "A campaign file or output directory that cannot be used (naming the file and the key)."
);

/// Adds the exceptions to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("ScenarioError", py.get_type::<ScenarioError>())?;
    m.add("SimulationError", py.get_type::<SimulationError>())?;
    m.add("CampaignError", py.get_type::<CampaignError>())?;
    Ok(())
}

/// A scenario error as `satflock.ScenarioError`, with the attributes `file` and `key`.
pub fn scenario_error(e: &RustScenarioError) -> PyErr {
    let (file, key) = match e {
        RustScenarioError::Io { file, .. } | RustScenarioError::Parse { file, .. } => {
            (Some(file.clone()), None)
        }
        RustScenarioError::Invalid { file, key, .. } => (Some(file.clone()), Some(key.clone())),
        RustScenarioError::Unknown { name, .. } => (Some(name.clone()), None),
        _ => (None, None),
    };
    Python::attach(|py| {
        let err = ScenarioError::new_err(e.to_string());
        let value = err.value(py);
        // Setting attributes on a fresh exception instance cannot fail short of memory exhaustion.
        let _ = value.setattr("file", file);
        let _ = value.setattr("key", key);
        err
    })
}
