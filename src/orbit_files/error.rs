//! [`OrbitFileError`]: why an orbit file (OEM, OMM, TLE) or a state from it cannot be had, with the
//! file, the line or keyword, the value and what is allowed.

use thiserror::Error;

/// ` line N` for a known line, nothing otherwise.
fn at_line(line: &Option<usize>) -> String {
    line.map_or_else(String::new, |l| format!(" line {l}"))
}

/// Why an orbit file cannot be read or gives no state. Every variant is the user's input (exit 2).
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum OrbitFileError {
    /// The file cannot be read: missing, not a regular file, larger than
    /// [`super::MAX_ORBIT_FILE_BYTES`], not UTF-8 (the message says what is allowed).
    #[error("{file}: cannot read the file: {source}")]
    Read {
        /// The file.
        file: String,
        /// What the system or [`crate::input_file`] said.
        #[source]
        source: std::io::Error,
    },
    /// A keyword's value, a data line or the file's structure is not what the format allows (the
    /// texts boxed to keep the error small).
    #[error("{file}{}: {keyword} = `{value}`: {problem} (allowed: {allowed})", at_line(.line))]
    Invalid {
        /// The file (or the caller's name for inline text).
        file: Box<str>,
        /// The line (1-based), when the input has lines.
        line: Option<usize>,
        /// The keyword, or what the line is (`data line`, `TLE line 1`, `structure`).
        keyword: Box<str>,
        /// The value found (shortened when long).
        value: Box<str>,
        /// What is wrong.
        problem: Box<str>,
        /// What is allowed.
        allowed: Box<str>,
    },
    /// A mandatory keyword is missing from a block.
    #[error("{file}{}: {block} has no {keyword} (a mandatory keyword{})", at_line(.line), .needed_for.as_ref().map_or_else(String::new, |n| format!(" for {n}")))]
    Missing {
        /// The file.
        file: String,
        /// The line where the block starts.
        line: Option<usize>,
        /// The block (`OEM segment metadata`, `OMM element set 2`, …).
        block: String,
        /// The missing keyword.
        keyword: String,
        /// What needs it, when it is mandatory only for that (e.g. `INTERPOLATION = LAGRANGE`).
        needed_for: Option<String>,
    },
    /// A TLE line's checksum (column 69) is not the sum of its digits (a minus sign counts 1) mod 10.
    #[error("{file} line {line}: TLE line {tle_line} has checksum {found} but its digits sum to {computed} mod 10 (allowed: a line whose column 69 is the mod-10 sum of its first 68 columns' digits, a minus sign counting 1)")]
    Checksum {
        /// The file.
        file: String,
        /// The line in the file (1-based).
        line: usize,
        /// 1 or 2.
        tle_line: u8,
        /// The checksum the line carries.
        found: char,
        /// The checksum of its first 68 columns.
        computed: u8,
    },
    /// The requested epoch is outside every segment (or useable window) of an OEM object.
    #[error(
        "{file}: object {object}: epoch {epoch} is outside its ephemeris (allowed: {allowed})"
    )]
    EpochOutside {
        /// The file(s) of the object.
        file: String,
        /// `OBJECT_NAME (OBJECT_ID)`.
        object: String,
        /// The requested epoch (UTC).
        epoch: String,
        /// The windows that hold states, each with its file and line.
        allowed: String,
    },
    /// SGP4 cannot propagate the element set to the requested epoch (the orbit has decayed or
    /// diverged there).
    #[error("{source_name}: element set of {object}: SGP4 cannot propagate to {epoch} ({message}; allowed: an epoch at which the element set gives an orbit)")]
    Propagation {
        /// The file and line of the element set, or the caller's name for it.
        source_name: String,
        /// The object's name and catalogue number.
        object: String,
        /// The requested epoch (UTC).
        epoch: String,
        /// What SGP4 said.
        message: String,
    },
}

impl OrbitFileError {
    /// An [`OrbitFileError::Invalid`] from its parts.
    pub(crate) fn invalid(
        file: &str,
        line: Option<usize>,
        keyword: &str,
        value: &str,
        problem: impl Into<String>,
        allowed: impl Into<String>,
    ) -> Self {
        const LONGEST_VALUE: usize = 80;
        let value = if value.chars().count() > LONGEST_VALUE {
            let cut: String = value.chars().take(LONGEST_VALUE).collect();
            format!("{cut}…")
        } else {
            value.to_string()
        };
        OrbitFileError::Invalid {
            file: file.into(),
            line,
            keyword: keyword.into(),
            value: value.into(),
            problem: problem.into().into(),
            allowed: allowed.into().into(),
        }
    }

    /// A file with no element set in it (OMM, TLE).
    pub(crate) fn no_element_set(file: &str, allowed: &str) -> Self {
        Self::invalid(
            file,
            None,
            "structure",
            "",
            "no element set in the file",
            allowed,
        )
    }

    /// An [`OrbitFileError::Missing`] from its parts.
    pub(crate) fn missing(
        file: &str,
        line: Option<usize>,
        block: &str,
        keyword: &str,
        needed_for: Option<String>,
    ) -> Self {
        OrbitFileError::Missing {
            file: file.to_string(),
            line,
            block: block.to_string(),
            keyword: keyword.to_string(),
            needed_for,
        }
    }
}
