//! Reproduction reports: each target runs a set of checks at full length (longer than the test suite
//! affords) and reports, for every outcome, the reference value (a paper's, or an analytic one), ours,
//! and a verdict. `satflock validate TARGET` prints the report as a Markdown table for the README.

pub mod core;
mod forces;
pub mod gao;
pub mod pigeon;
pub mod scatter;
pub mod takahashi;
pub mod takahashi_split;

use std::fmt;

use thiserror::Error;

/// How our value compares with the reference.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Verdict {
    /// Within the stated tolerance.
    Reproduced,
    /// Outside the tolerance, with the difference explained in the report.
    Differs,
    /// Cannot be reproduced from what the source gives (explained in the report).
    NotReproduced,
}

impl fmt::Display for Verdict {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Verdict::Reproduced => "reproduced",
            Verdict::Differs => "differs",
            Verdict::NotReproduced => "not reproduced",
        })
    }
}

/// One reproduced outcome.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Check {
    /// Short identifier (e.g. `O3`, `T5`).
    pub id: String,
    /// What is compared, with the tolerance.
    pub outcome: String,
    /// The reference value (paper or analytic), as text with units.
    pub paper: String,
    /// Our value, as text with units.
    pub ours: String,
    /// Verdict.
    pub verdict: Verdict,
}

/// A further table of a report (e.g. a strategy comparison beside the paper's).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Table {
    /// Title, printed as a heading above the table.
    pub title: String,
    /// Column headers.
    pub header: Vec<String>,
    /// Rows, each as many cells as `header`.
    pub rows: Vec<Vec<String>>,
}

/// A report: a titled list of checks, further tables and notes.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Report {
    /// Title (the source being reproduced).
    pub title: String,
    /// Header of the reference column in Markdown: `reference`, or `paper` for a report whose
    /// references are a paper's (not serialised: the JSON field of a check is always `paper`).
    #[serde(skip)]
    pub reference_header: String,
    /// The checks, in order.
    pub checks: Vec<Check>,
    /// Further tables, printed under the checks (omitted from the JSON when there are none).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub tables: Vec<Table>,
    /// Remarks printed under the tables (what differs and why).
    pub notes: Vec<String>,
}

impl Report {
    /// The report as Markdown: a heading, a table `id | outcome | reference | ours | verdict`, the
    /// further tables, notes.
    pub fn to_markdown(&self) -> String {
        let cell = |s: &str| s.replace('|', "\\|").replace('\n', " ");
        let mut out = format!(
            "### {}\n\n| id | outcome | {} | ours | verdict |\n| --- | --- | --- | --- | --- |\n",
            self.title, self.reference_header
        );
        for c in &self.checks {
            out.push_str(&format!(
                "| {} | {} | {} | {} | {} |\n",
                cell(&c.id),
                cell(&c.outcome),
                cell(&c.paper),
                cell(&c.ours),
                c.verdict
            ));
        }
        for table in &self.tables {
            out.push_str(&format!("\n#### {}\n\n", table.title));
            let row = |cells: &[String]| {
                let cells: Vec<String> = cells.iter().map(|c| cell(c)).collect();
                format!("| {} |\n", cells.join(" | "))
            };
            out.push_str(&row(&table.header));
            out.push_str(&format!("|{}\n", " --- |".repeat(table.header.len())));
            for r in &table.rows {
                out.push_str(&row(r));
            }
        }
        for note in &self.notes {
            out.push_str(&format!("\n{note}\n"));
        }
        out
    }
}

/// A target that could not run.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ValidateError {
    /// No target of that name.
    #[error("no validation target `{name}` (allowed: {allowed})")]
    UnknownTarget {
        /// What was asked for.
        name: String,
        /// The target names.
        allowed: String,
    },
    /// A reproduction failed to run.
    #[error("validation `{target}` failed: {message}")]
    Failed {
        /// The target.
        target: String,
        /// What went wrong.
        message: String,
    },
}

/// The validation targets: name and what they reproduce.
pub const TARGETS: &[(&str, &str)] = &[
    (
        "core",
        "orbital mechanics and relative motion: J2 secular rates, integrator accuracy, HCW and SS vs truth",
    ),
    (
        "gao",
        "Gao et al. 2022 bifurcating potential field: outcomes O1-O14 (shapes, speed-up, Table 5, delta-v)",
    ),
    (
        "pigeon",
        "Qiu et al. pigeon-flock switching formation: P1-P7, switching vs non-switching (20 seeds, 6000 s) and a damping extension",
    ),
    (
        "scatter",
        "Nag & Summerer 2013 behaviour-based scatter (equilibrium shaping): N1-N11, bounds B1-B2, Table 1-2 comparison",
    ),
    (
        "takahashi",
        "Takahashi & Sakai distance-based stabiliser under J2: §4.1 comparison, §4.2 planes, outages",
    ),
    (
        "takahashi-split",
        "Takahashi & Sakai Θ2 split over 20 seeds (4 h): the paper's grouping vs the connectivity-preserving extension",
    ),
];

/// Runs one target.
pub fn run(target: &str) -> Result<Report, ValidateError> {
    match target {
        "core" => core::report(),
        "gao" => gao::report(),
        "pigeon" => pigeon::report(),
        "scatter" => scatter::report(),
        "takahashi" => takahashi::report(),
        "takahashi-split" => takahashi_split::report(),
        _ => Err(ValidateError::UnknownTarget {
            name: target.to_string(),
            allowed: TARGETS.iter().map(|t| t.0).collect::<Vec<_>>().join(", "),
        }),
    }
}
