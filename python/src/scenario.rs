//! `satflock.Scenario`: a scenario as its TOML table, loaded from a built-in name, a file, TOML text or
//! a dict; read and changed by dotted key (`scenario["law.k_f_kg_per_m_s2"] = 0.01`) with the same
//! override rules as campaigns (`satflock::campaign::overrides`), and validated by the same code as the
//! command line: a change that makes the scenario invalid raises `ScenarioError` and is not kept.

use std::path::{Path, PathBuf};

use pyo3::prelude::*;
use pyo3::types::PyDict;

use satflock::campaign::overrides::{self, KeyPath, Segment};
use satflock::invalid::Invalid;
use satflock::scenario::{builtin, Controller, Scenario, ScenarioError};

use crate::convert::{dict_to_table, py_to_toml, table_to_py, toml_to_py};
use crate::errors::scenario_error;

/// A scenario: what `satflock run` reads, held as its TOML table.
#[pyclass(module = "satflock._native", name = "Scenario", from_py_object)]
#[derive(Clone)]
pub struct PyScenario {
    table: toml::Table,
    source: String,
    base_dir: PathBuf,
}

impl PyScenario {
    /// The library's scenario, typed and checked for unknown keys and types (not yet for ranges).
    pub fn scenario(&self) -> Result<Scenario, ScenarioError> {
        Scenario::from_table(self.table.clone(), &self.source, &self.base_dir)
    }

    /// Parses TOML text and validates it fully, the way `satflock run` does before it starts
    /// (line-precise messages; ranges such as a NaN `duration_s` refused here, not at the run).
    fn parse(text: &str, source: &str, base_dir: &Path) -> PyResult<Self> {
        Scenario::from_toml(text, source, base_dir).map_err(|e| scenario_error(&e))?;
        let table: toml::Table = toml::from_str(text).map_err(|e| {
            scenario_error(&ScenarioError::Parse {
                file: source.into(),
                message: e.to_string(),
            })
        })?;
        let scenario = Self {
            table,
            source: source.into(),
            base_dir: base_dir.to_path_buf(),
        };
        scenario.check().map_err(|e| scenario_error(&e))?;
        Ok(scenario)
    }

    /// The full validation (ranges and consistency, initial states), as before a run.
    fn check(&self) -> Result<(), ScenarioError> {
        self.scenario()?.prepare().map(|_| ())
    }

    /// Applies `(key, value)` pairs to a copy and validates it; the copy on success.
    fn with_values(&self, values: &[(String, toml::Value)]) -> Result<Self, ScenarioError> {
        let mut next = self.clone();
        for (key, value) in values {
            let invalid = |message: String| {
                ScenarioError::invalid(&self.source, Invalid::keys(key.clone(), message, ""))
            };
            let path = KeyPath::parse(key).map_err(invalid)?;
            overrides::apply(&mut next.table, &path, value).map_err(invalid)?;
        }
        // An unknown key or a wrong type is the key's fault: name it.
        if let Err(ScenarioError::Parse { message, .. }) = next.scenario() {
            let key = values.iter().map(|(k, _)| k.as_str()).collect::<Vec<_>>();
            return Err(ScenarioError::invalid(
                &self.source,
                Invalid::keys(key.join(", "), message, ""),
            ));
        }
        next.check()?;
        Ok(next)
    }
}

#[pymethods]
impl PyScenario {
    /// Loads a scenario file (a path that exists) or a built-in scenario by name (`"gao-circle"`).
    #[staticmethod]
    fn load(name_or_path: &str) -> PyResult<Self> {
        let path = Path::new(name_or_path);
        if path.exists() {
            let source = path.display().to_string();
            let text = satflock::input_file::read_document(path).map_err(|e| {
                scenario_error(&ScenarioError::Io {
                    file: source.clone(),
                    message: e.to_string(),
                })
            })?;
            return Self::parse(&text, &source, path.parent().unwrap_or(Path::new(".")));
        }
        match builtin::find(name_or_path) {
            Some(b) => Self::parse(b.toml, &format!("builtin:{}", b.name), Path::new(".")),
            None => Err(scenario_error(&ScenarioError::Unknown {
                name: name_or_path.into(),
                known: builtin::names().join(", "),
            })),
        }
    }

    /// A scenario from TOML text. `source` names it in error messages; `base_dir` resolves relative
    /// paths in it (default: the current directory).
    #[staticmethod]
    #[pyo3(signature = (text, source = "<toml>", base_dir = "."))]
    fn from_toml(text: &str, source: &str, base_dir: &str) -> PyResult<Self> {
        Self::parse(text, source, Path::new(base_dir))
    }

    /// A scenario from a dict of the TOML file's tables and keys (as `to_dict()` returns them).
    #[staticmethod]
    #[pyo3(signature = (d, source = "<dict>", base_dir = "."))]
    fn from_dict(d: &Bound<'_, PyDict>, source: &str, base_dir: &str) -> PyResult<Self> {
        let table = dict_to_table(d, "").map_err(|message| {
            scenario_error(&ScenarioError::Parse {
                file: source.into(),
                message,
            })
        })?;
        let text = toml::to_string(&table).map_err(|e| {
            scenario_error(&ScenarioError::Parse {
                file: source.into(),
                message: e.to_string(),
            })
        })?;
        Self::parse(&text, source, Path::new(base_dir))
    }

    /// Names the built-in scenarios.
    #[staticmethod]
    fn builtins() -> Vec<&'static str> {
        builtin::names()
    }

    /// The scenario as a dict of its tables and keys (a copy: change the scenario by item assignment).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        table_to_py(py, &self.table)
    }

    /// The scenario as TOML text (what `satflock run` reads).
    fn to_toml(&self) -> PyResult<String> {
        toml::to_string(&self.table).map_err(|e| {
            scenario_error(&ScenarioError::Parse {
                file: self.source.clone(),
                message: e.to_string(),
            })
        })
    }

    /// Checks every value (ranges, consistency, initial states) as `satflock run` does before it starts;
    /// raises `ScenarioError` naming the file, the key and the allowed range.
    fn validate(&self) -> PyResult<()> {
        self.check().map_err(|e| scenario_error(&e))
    }

    /// Sets several dotted keys at once (one validation for all: for values that must change together).
    fn update(&mut self, values: &Bound<'_, PyDict>) -> PyResult<()> {
        let mut pairs = Vec::new();
        for (key, value) in values.iter() {
            let key: String = key.extract()?;
            let value = py_to_toml(&value, &key).map_err(|message| {
                scenario_error(&ScenarioError::invalid(
                    &self.source,
                    Invalid::keys(key.clone(), message, ""),
                ))
            })?;
            pairs.push((key, value));
        }
        *self = self.with_values(&pairs).map_err(|e| scenario_error(&e))?;
        Ok(())
    }

    /// The value at a dotted key (`"law.name"`, `"threats.0.speed_mps"`); `KeyError` if it is not set.
    fn __getitem__<'py>(&self, py: Python<'py>, key: &str) -> PyResult<Bound<'py, PyAny>> {
        let missing = || pyo3::exceptions::PyKeyError::new_err(key.to_string());
        let path = KeyPath::parse(key).map_err(|_| missing())?;
        let mut node: Option<&toml::Value> = None;
        for segment in path.segments() {
            node = match (segment, node) {
                (Segment::Key(k), None) => self.table.get(k),
                (Segment::Key(k), Some(toml::Value::Table(t))) => t.get(k),
                (Segment::Index(i), Some(toml::Value::Array(a))) => a.get(*i),
                _ => None,
            };
            if node.is_none() {
                return Err(missing());
            }
        }
        toml_to_py(py, node.ok_or_else(missing)?)
    }

    /// Sets the value at a dotted key and validates the scenario; an invalid value raises
    /// `ScenarioError` (naming the key and the allowed range) and leaves the scenario unchanged.
    fn __setitem__(&mut self, key: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let value = py_to_toml(value, key).map_err(|message| {
            scenario_error(&ScenarioError::invalid(
                &self.source,
                Invalid::keys(key, message, ""),
            ))
        })?;
        *self = self
            .with_values(&[(key.to_string(), value)])
            .map_err(|e| scenario_error(&e))?;
        Ok(())
    }

    /// Whether a dotted key is set.
    fn __contains__(&self, py: Python<'_>, key: &str) -> bool {
        self.__getitem__(py, key).is_ok()
    }

    /// The scenario's `name`.
    #[getter]
    fn name(&self) -> String {
        self.table
            .get("name")
            .and_then(|v| v.as_str())
            .unwrap_or_default()
            .to_string()
    }

    /// Where the scenario came from (a path, `builtin:NAME`, `<toml>` or `<dict>`).
    #[getter]
    fn source(&self) -> &str {
        &self.source
    }

    /// This scenario (the case) steered by a controller: `spec` is a controller file (a law, its law
    /// events and optionally its control timing) or `builtin:NAME` (the controller of that built-in),
    /// as `satflock run CASE --law SPEC` takes it: the controller's law and law events replace the
    /// case's, the case's other events are kept. Validated; raises `ScenarioError` naming both files.
    fn with_controller(&self, spec: &str) -> PyResult<Self> {
        let controller = Controller::load(spec).map_err(|e| scenario_error(&e))?;
        let steered = self
            .scenario()
            .map_err(|e| scenario_error(&e))?
            .with_controller(&controller);
        steered.prepare().map_err(|e| scenario_error(&e))?;
        let table = toml::Table::try_from(&steered.file).map_err(|e| {
            scenario_error(&ScenarioError::Parse {
                file: self.source.clone(),
                message: e.to_string(),
            })
        })?;
        Ok(Self {
            table,
            source: self.source.clone(),
            base_dir: self.base_dir.clone(),
        })
    }

    /// An independent copy.
    fn copy(&self) -> Self {
        self.clone()
    }

    fn __copy__(&self) -> Self {
        self.clone()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.clone()
    }

    fn __repr__(&self) -> String {
        format!("Scenario(name={:?}, source={:?})", self.name(), self.source)
    }
}

/// The label `satflock compare` gives the controller `spec` (a file or `builtin:NAME`): the built-in's
/// name, or the file name without its extension (`Controller::label`). Raises `ScenarioError` for a
/// controller that cannot be loaded.
#[pyfunction]
pub fn controller_label(spec: &str) -> PyResult<String> {
    Controller::load(spec)
        .map(|c| c.label())
        .map_err(|e| scenario_error(&e))
}
