//! The one typed error of a value that is not allowed: the key, the value as given with what is wrong
//! with it, and what is allowed. The scenario layer ([`crate::scenario::ScenarioError::Invalid`], which
//! adds the file and the system's error where a file could not be read), the laws' parameter checks
//! ([`crate::swarm::LawError::InvalidParameters`]) and the force models' parameter checks
//! ([`crate::dynamics::ForceConfigError`]) all report this one type.

use std::fmt;

/// A value that is not allowed.
///
/// Its text reads `VALUE PROBLEM (allowed: ALLOWED)`, e.g. `-1 is out of range (allowed: finite, > 0)`
/// or `missing (allowed: [0, 180])`; [`fmt::Display`] puts `key \`KEY\`: ` before it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Invalid {
    /// The dotted key, relative to the table being checked (`stiffness_per_s2`,
    /// `drag.scale_height_m`, `satellites.count`).
    pub key: String,
    /// The value as given, written back (with its unit where it has one), and what is wrong with it:
    /// `1e-10 s is out of range`, `200 is longer than duration_s = 100`; for a missing key or keys
    /// that do not go together, what is wrong alone (`missing`).
    pub value: String,
    /// What is allowed (and why, where that is not obvious); empty only where the value says it.
    pub allowed: String,
}

impl Invalid {
    /// `value` of `key` is outside what is `allowed`.
    pub fn range(
        key: impl Into<String>,
        value: impl fmt::Display,
        allowed: impl Into<String>,
    ) -> Self {
        Self::new(key, value, "is out of range", allowed)
    }

    /// `value` of `key` has `problem` (a phrase that follows the value: `is longer than duration_s =
    /// 100`); `allowed` says what would do.
    pub fn new(
        key: impl Into<String>,
        value: impl fmt::Display,
        problem: impl fmt::Display,
        allowed: impl Into<String>,
    ) -> Self {
        Self::keys(key, format!("{value} {problem}"), allowed)
    }

    /// `key` has `problem` (no single value is at fault: a missing key, keys that do not go together).
    pub fn keys(
        key: impl Into<String>,
        problem: impl Into<String>,
        allowed: impl Into<String>,
    ) -> Self {
        Self {
            key: key.into(),
            value: problem.into(),
            allowed: allowed.into(),
        }
    }

    /// `key` is missing; `allowed` says what to give.
    pub fn missing(key: impl Into<String>, allowed: impl Into<String>) -> Self {
        Self::keys(key, "missing", allowed)
    }

    /// The same error for the key `prefix` + `key` (`law.` + `stiffness_per_s2`).
    pub fn under(mut self, prefix: &str) -> Self {
        self.key = format!("{prefix}{}", self.key);
        self
    }

    /// The error's text without its key: `VALUE PROBLEM (allowed: ALLOWED)`.
    pub fn detail(&self) -> String {
        detail(&self.value, &self.allowed)
    }
}

/// `VALUE (allowed: ALLOWED)`, the allowed part left out when it is empty.
pub(crate) fn detail(value: &str, allowed: &str) -> String {
    if allowed.is_empty() {
        value.to_string()
    } else {
        format!("{value} (allowed: {allowed})")
    }
}

impl fmt::Display for Invalid {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "key `{}`: {}", self.key, self.detail())
    }
}

impl std::error::Error for Invalid {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_value_problem_allowed() {
        let e = Invalid::range("stiffness_per_s2", -1.0, "finite, > 0");
        assert_eq!(
            e.to_string(),
            "key `stiffness_per_s2`: -1 is out of range (allowed: finite, > 0)"
        );
        assert_eq!(
            Invalid::missing("reference.inclination_deg", "[0, 180]")
                .under("x.")
                .to_string(),
            "key `x.reference.inclination_deg`: missing (allowed: [0, 180])"
        );
        assert_eq!(
            Invalid::keys("name", "must not be empty", "").detail(),
            "must not be empty"
        );
    }
}
