//! `satflock._native`: the compiled half of the Python package `satflock` (pyo3). The pure-Python package
//! (`python/satflock/`) re-exports it with docstrings and adds what is Python's own (pyarrow tables, the
//! Ray backend of campaigns).
//!
//! | module | holds |
//! | --- | --- |
//! | `errors.rs` | the Python exceptions and the conversion of satflock's errors into them |
//! | `convert.rs` | TOML values <-> Python objects |
//! | `detached.rs` | Rust work off the GIL, on chosen threads, stopped by Ctrl-C |
//! | `scenario.rs` | `Scenario`: load, from TOML or a dict, dotted-key access, validation |
//! | `analysis.rs` | `characterize` (the five elements) and `propagate` (orbits without control) |
//! | `budget.rs` | `budget`: the perturbation budget of a satellite pair |
//! | `campaign.rs` | `CampaignPlan`, `CampaignOutput`: campaigns, locally or step by step for Ray |
//! | `law.rs` | a guidance law written in Python (`law=`), and its `LawContext` |
//! | `records.rs` | the in-memory recorder of `Simulation`; tables as numpy arrays |
//! | `run.rs` | `run`: a whole run into an output folder, read back |
//! | `simulation.rs` | `Simulation`: a scenario stepped from Python |

mod analysis;
mod budget;
mod campaign;
mod convert;
mod detached;
mod errors;
mod law;
mod records;
mod run;
mod scenario;
mod simulation;

use pyo3::prelude::*;

/// The compiled module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    errors::register(m)?;
    m.add_class::<scenario::PyScenario>()?;
    m.add_function(wrap_pyfunction!(analysis::characterize, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::propagate, m)?)?;
    m.add_function(wrap_pyfunction!(budget::budget, m)?)?;
    m.add_class::<campaign::CampaignPlan>()?;
    m.add_class::<campaign::CampaignOutput>()?;
    m.add_class::<simulation::PySimulation>()?;
    m.add_class::<law::PyLawContext>()?;
    m.add_function(wrap_pyfunction!(run::run, m)?)?;
    m.add_function(wrap_pyfunction!(run::scalar_outcomes, m)?)?;
    m.add_function(wrap_pyfunction!(scenario::controller_label, m)?)?;
    Ok(())
}
