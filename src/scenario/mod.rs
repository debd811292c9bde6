//! Scenario files: loading (a path or a built-in name), validation with errors that name the file, the key
//! and the allowed range, and the translation into a runnable [`crate::swarm::Simulation`].
//!
//! The format is documented in the README ("Scenario format") and by [`schema::ScenarioFile`].

pub mod builtin;
pub mod controller;
pub mod initial;
pub mod schema;
mod validate;

use std::path::{Path, PathBuf};

use thiserror::Error;

pub use controller::{Controller, ControllerFile, ControllerOrigin};
pub use schema::ScenarioFile;
pub use validate::{merge_law_parameters, Prepared, MAX_SATELLITES};

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
    /// A value is out of its allowed range or inconsistent with another: a [`crate::invalid::Invalid`]
    /// in a file. The text reads `FILE: key \`KEY\`: VALUE PROBLEM (allowed: ALLOWED)`.
    #[error("{file}: key `{key}`: {}", crate::invalid::detail(value, allowed))]
    Invalid {
        /// The file.
        file: String,
        /// Dotted path of the key.
        key: String,
        /// The value as given, written back, and what is wrong with it (`-1 is out of range`,
        /// `missing`): [`crate::invalid::Invalid::value`].
        value: String,
        /// What is allowed.
        allowed: String,
        /// The system's error, when a file the key names could not be read.
        source: Option<std::sync::Arc<std::io::Error>>,
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

/// The parser's message, made precise where the parser only knows the table: a law or event table is
/// read as a whole (its `name` or `action` key selects the type), so the parser's span covers the table,
/// not the offending key. An unknown key is then pointed at by its own line, and the table is named by
/// its dotted path (`law`, `events[2]`, `events[2].law`).
fn parse_error_message(text: &str, e: &toml::de::Error) -> String {
    let plain = || e.to_string().trim_end().to_string();
    let Some(span) = e.span() else {
        return plain();
    };
    let lines: Vec<&str> = text.lines().collect();
    let header_line = text[..span.start.min(text.len())].matches('\n').count();
    let Some(header) = lines.get(header_line).map(|l| l.trim()) else {
        return plain();
    };
    if !header.starts_with('[') {
        return plain();
    }
    let table = table_path(&lines, header_line);
    let message = e.message();
    let unknown = message
        .strip_prefix("unknown field `")
        .and_then(|rest| rest.split('`').next());
    if let Some(key) = unknown {
        // The key's own line: the first `key =` after the header, before a header of another table.
        let found = lines
            .iter()
            .enumerate()
            .skip(header_line + 1)
            .take_while(|(k, l)| {
                let l = l.trim();
                !l.starts_with('[') || table_path(&lines, *k).starts_with(&table)
            })
            .find(|(_, l)| {
                l.trim()
                    .strip_prefix(key)
                    .is_some_and(|rest| rest.trim_start().starts_with('='))
            });
        if let Some((k, line)) = found {
            // The table the key sits in (a sub-table such as `[events.law]` may hold it).
            let own_header = (header_line..=k)
                .rev()
                .find(|&h| lines[h].trim().starts_with('['))
                .unwrap_or(header_line);
            let table = table_path(&lines, own_header);
            return format!(
                "TOML parse error at line {}, column 1\n   |\n{:>2} | {line}\n   |\n{message} (in `{table}`)",
                k + 1,
                k + 1
            );
        }
    }
    format!("{} (in `{table}`)", plain())
}

/// The dotted path of the table whose header is on line `at` (0-based): `[a.b]` is `a.b`; the k-th
/// `[[events]]` (0-based) is `events[k]`, and `[events.law]` below it is `events[k].law`.
fn table_path(lines: &[&str], at: usize) -> String {
    let header = lines[at].trim();
    let name = |h: &str| {
        h.trim_start_matches('[')
            .split(']')
            .next()
            .unwrap_or("")
            .trim()
            .to_string()
    };
    let own = name(header);
    // The innermost array of tables this header belongs to, and its index.
    let array_index = |array: &str| {
        lines[..=at]
            .iter()
            .filter(|l| l.trim().starts_with("[[") && name(l.trim()) == array)
            .count()
            .checked_sub(1)
    };
    if header.starts_with("[[") {
        return match array_index(&own) {
            Some(k) => format!("{own}[{k}]"),
            None => own,
        };
    }
    // A sub-table of the latest array element (`[events.law]` after `[[events]]`).
    if let Some((array, rest)) = own.split_once('.') {
        if let Some(k) = array_index(array) {
            return format!("{array}[{k}].{rest}");
        }
    }
    own
}

impl ScenarioError {
    /// `invalid` found in `file`.
    pub fn invalid(file: &str, invalid: crate::invalid::Invalid) -> Self {
        let crate::invalid::Invalid {
            key,
            value,
            allowed,
        } = invalid;
        Self::Invalid {
            file: file.to_string(),
            key,
            value,
            allowed,
            source: None,
        }
    }

    /// `invalid` found in `file`, caused by the system's error `source` reading a file the key names.
    pub fn invalid_io(
        file: &str,
        invalid: crate::invalid::Invalid,
        source: std::io::Error,
    ) -> Self {
        let mut e = Self::invalid(file, invalid);
        if let Self::Invalid { source: s, .. } = &mut e {
            *s = Some(std::sync::Arc::new(source));
        }
        e
    }
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
    /// The controller that replaced the file's own ([`Scenario::with_controller`]), if any.
    pub controller: Option<ControllerOrigin>,
}

impl Scenario {
    /// Parses scenario text. `source` names it in errors; `base_dir` resolves relative paths.
    pub fn from_toml(text: &str, source: &str, base_dir: &Path) -> Result<Self, ScenarioError> {
        let file: ScenarioFile = toml::from_str(text).map_err(|e| ScenarioError::Parse {
            file: source.to_string(),
            message: parse_error_message(text, &e),
        })?;
        Ok(Self::of_file(file, source, base_dir))
    }

    /// A scenario from its TOML table (as edited by dotted-key overrides): keys and types are checked, not
    /// yet the ranges ([`Scenario::prepare`] does). `source` names it in errors; `base_dir` resolves
    /// relative paths.
    pub fn from_table(
        table: toml::Table,
        source: &str,
        base_dir: &Path,
    ) -> Result<Self, ScenarioError> {
        let file: ScenarioFile =
            toml::Value::Table(table)
                .try_into()
                .map_err(|e: toml::de::Error| ScenarioError::Parse {
                    file: source.to_string(),
                    message: e.message().trim_end().to_string(),
                })?;
        Ok(Self::of_file(file, source, base_dir))
    }

    /// The scenario of a parsed file named `source`, relative paths resolved from `base_dir`.
    fn of_file(file: ScenarioFile, source: &str, base_dir: &Path) -> Self {
        Self {
            file,
            source: source.to_string(),
            base_dir: base_dir.to_path_buf(),
            controller: None,
        }
    }

    /// Loads a scenario file from a path.
    pub fn from_path(path: &Path) -> Result<Self, ScenarioError> {
        let source = path.display().to_string();
        let text = crate::input_file::read_document(path).map_err(|e| ScenarioError::Io {
            file: source.clone(),
            message: e.to_string(),
        })?;
        // A bare file name's parent is the empty path: the current directory.
        let base = path
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
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
