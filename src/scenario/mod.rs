//! Scenario files: loading (a path or a built-in name), validation with errors that name the file, the key
//! and the allowed range, and the translation into a runnable [`crate::swarm::Simulation`].
//!
//! The format is documented in the README ("Scenario format") and by [`schema::ScenarioFile`].

pub mod builtin;
pub mod initial;
pub mod schema;
mod validate;

use std::path::{Path, PathBuf};

use thiserror::Error;

pub use schema::ScenarioFile;
pub use validate::{merge_law_parameters, Prepared};

/// A scenario that cannot be loaded or run.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ScenarioError {
    /// The file cannot be read.
    #[error("{file}: cannot read the file: {message}")]
    Io {
        /// The file.
        file: String,
        /// What the system said.
        message: String,
    },
    /// The TOML is malformed, a key is unknown or missing, or a value has the wrong type.
    #[error("{file}: {message}")]
    Parse {
        /// The file.
        file: String,
        /// The parser's message, with line and column and the offending key.
        message: String,
    },
    /// A value is out of its allowed range or inconsistent with another.
    #[error("{file}: key `{key}`: {message}")]
    Invalid {
        /// The file.
        file: String,
        /// Dotted path of the key.
        key: String,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// No built-in scenario has that name, and no file has that path.
    #[error("no scenario file `{name}` and no built-in scenario of that name (built-in: {known})")]
    Unknown {
        /// What was asked for.
        name: String,
        /// The built-in names.
        known: String,
    },
}

/// A scenario loaded from somewhere, with the name of where (for error messages and relative paths).
#[derive(Clone, Debug)]
pub struct Scenario {
    /// The parsed file.
    pub file: ScenarioFile,
    /// Where it came from (a path, or `builtin:NAME`).
    pub source: String,
    /// Directory that relative paths in the file are resolved against.
    pub base_dir: PathBuf,
}

impl Scenario {
    /// Parses scenario text. `source` names it in errors; `base_dir` resolves relative paths.
    pub fn from_toml(text: &str, source: &str, base_dir: &Path) -> Result<Self, ScenarioError> {
        let file: ScenarioFile = toml::from_str(text).map_err(|e| ScenarioError::Parse {
            file: source.to_string(),
            message: e.to_string().trim_end().to_string(),
        })?;
        Ok(Self {
            file,
            source: source.to_string(),
            base_dir: base_dir.to_path_buf(),
        })
    }

    /// Loads a scenario file from a path.
    pub fn from_path(path: &Path) -> Result<Self, ScenarioError> {
        let source = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| ScenarioError::Io {
            file: source.clone(),
            message: e.to_string(),
        })?;
        let base = path.parent().unwrap_or(Path::new("."));
        Self::from_toml(&text, &source, base)
    }

    /// Loads a path if it exists, otherwise a built-in scenario of that name.
    pub fn load(name_or_path: &str) -> Result<Self, ScenarioError> {
        let path = Path::new(name_or_path);
        if path.exists() {
            return Self::from_path(path);
        }
        match builtin::find(name_or_path) {
            Some(b) => Self::from_toml(b.toml, &format!("builtin:{}", b.name), Path::new(".")),
            None => Err(ScenarioError::Unknown {
                name: name_or_path.to_string(),
                known: builtin::names().join(", "),
            }),
        }
    }

    /// Validates every value and builds what the engine needs.
    pub fn prepare(&self) -> Result<Prepared, ScenarioError> {
        validate::prepare(self)
    }
}
