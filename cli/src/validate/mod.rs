//! Reproduction reports: each target runs a set of checks at full length (longer than the test suite
//! affords) and reports, for every outcome, the reference value (a paper's, or an analytic one), ours,
//! and a verdict. `satflock validate TARGET` prints the report as a Markdown table for the README.

pub mod core;
pub mod data;
mod forces;
pub mod gao;
pub mod pigeon;
pub mod scatter;
pub mod takahashi;
pub mod takahashi_split;

use std::fmt;

use thiserror::Error;

/// How our value compares with the reference.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Verdict {
    /// Within the stated tolerance.
    Reproduced,
    /// Outside the tolerance, with the difference explained in the report.
    Differs,
    /// Cannot be reproduced from what the source gives (explained in the report).
    NotReproduced,
    /// The criterion's precondition did not occur in the runs (e.g. nothing left its node), so the
    /// outcome says nothing either way.
    NotTested,
    /// No longer judged (the data file says why); kept as a row so the history stays visible.
    Retired,
}

impl fmt::Display for Verdict {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Verdict::Reproduced => "reproduced",
            Verdict::Differs => "differs",
            Verdict::NotReproduced => "not reproduced",
            Verdict::NotTested => "not tested",
            Verdict::Retired => "retired",
        })
    }
}

/// One reproduced outcome.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Check {
    /// Short identifier (e.g. `O3`, `T5`).
    pub id: String,
    /// What is compared, with the tolerance.
    pub outcome: String,
    /// The reference value (paper or analytic), as text with units.
    pub paper: String,
    /// The acceptance criterion and when it was fixed (a paper's reproductions, from its data file in
    /// `validation/`); `None`: the criterion is part of `outcome`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub criterion: Option<String>,
    /// Our value, as text with units.
    pub ours: String,
    /// Verdict.
    pub verdict: Verdict,
}

/// A further table of a report (e.g. a strategy comparison beside the paper's).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Table {
    /// Title, printed as a heading above the table.
    pub title: String,
    /// Column headers.
    pub header: Vec<String>,
    /// Rows, each as many cells as `header`.
    pub rows: Vec<Vec<String>>,
}

/// When and how long a report was measured.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Measured {
    /// The command that measured it (`satflock validate pigeon`).
    pub command: String,
    /// The UTC date of the measurement (`2026-12-02`).
    pub date_utc: String,
    /// Wall time of the whole reproduction \[s\].
    pub wall_s: f64,
    /// Worker threads of the process (rayon's pool).
    pub threads: usize,
}

/// A report: a titled list of checks, further tables and notes.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Report {
    /// Title (the source being reproduced).
    pub title: String,
    /// Header of the reference column in Markdown: `reference`, or `paper` for a report whose
    /// references are a paper's.
    #[serde(default = "default_reference_header")]
    pub reference_header: String,
    /// When and how long it was measured (set by [`run`]; `None` for a report built in a test).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measured: Option<Measured>,
    /// The checks, in order.
    pub checks: Vec<Check>,
    /// Further tables, printed under the checks (omitted from the JSON when there are none).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub tables: Vec<Table>,
    /// Remarks printed under the tables (what differs and why).
    pub notes: Vec<String>,
}

fn default_reference_header() -> String {
    "reference".into()
}

impl Report {
    /// The report as Markdown: a heading, the measurement's date and wall time, a table
    /// `id | outcome | reference | [criterion |] ours | verdict` (the criterion column when the checks
    /// carry one), the further tables, notes.
    pub fn to_markdown(&self) -> String {
        let cell = |s: &str| s.replace('|', "\\|").replace('\n', " ");
        let mut out = format!("### {}\n\n", self.title);
        if let Some(m) = &self.measured {
            out.push_str(&format!(
                "Measured by `{}` on {} ({:.0} s wall, {} thread{}).\n\n",
                m.command,
                m.date_utc,
                m.wall_s,
                m.threads,
                if m.threads == 1 { "" } else { "s" }
            ));
        }
        let with_criterion = self.checks.iter().any(|c| c.criterion.is_some());
        if with_criterion {
            out.push_str(&format!(
                "| id | outcome | {} | criterion | ours | verdict |\n| --- | --- | --- | --- | --- | --- |\n",
                self.reference_header
            ));
        } else {
            out.push_str(&format!(
                "| id | outcome | {} | ours | verdict |\n| --- | --- | --- | --- | --- |\n",
                self.reference_header
            ));
        }
        for c in &self.checks {
            let criterion = if with_criterion {
                format!(" {} |", cell(c.criterion.as_deref().unwrap_or("–")))
            } else {
                String::new()
            };
            out.push_str(&format!(
                "| {} | {} | {} |{criterion} {} | {} |\n",
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

/// Runs one target and stamps the report with the command, the date and the wall time. A paper's
/// report takes its outcomes' texts and criteria from its data file ([`data`]).
pub fn run(target: &str) -> Result<Report, ValidateError> {
    let start = std::time::Instant::now();
    let mut report = match target {
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
    }?;
    report.measured = Some(Measured {
        command: format!("satflock validate {target}"),
        date_utc: satflock::time::Epoch::now()
            .map(|now| satflock::time::utc_iso(now)[..10].to_string())
            .map_err(|e| ValidateError::Failed {
                target: target.to_string(),
                message: format!("cannot read the system clock: {e}"),
            })?,
        wall_s: start.elapsed().as_secs_f64(),
        threads: rayon::current_num_threads(),
    });
    with_data(target, report)
}

/// A report with its paper's data re-applied (texts, criteria, order, retired rows); unchanged for a
/// target without a data file.
pub fn with_data(target: &str, mut report: Report) -> Result<Report, ValidateError> {
    if let Some(data) = data::PaperData::of(target) {
        let data = data?;
        report.checks = data::apply(&data, &report.checks)?;
        report.title = data.title;
        report.reference_header = "paper".into();
    }
    Ok(report)
}

/// A saved measurement (`satflock validate TARGET --json` output) re-rendered with today's data files,
/// without running anything: what `docs/validation.md` shows for that target.
pub fn render_saved(target: &str, json: &str) -> Result<Report, ValidateError> {
    let report: Report = serde_json::from_str(json).map_err(|e| ValidateError::Failed {
        target: target.to_string(),
        message: format!("saved measurement: {e}"),
    })?;
    with_data(target, report)
}

/// The markers around a target's generated section in `docs/validation.md`.
pub fn doc_markers(target: &str) -> (String, String) {
    (
        format!(
            "<!-- generated: satflock validate {target} --from validation/measured/{target}.json (edit validation/{target}.toml, not this section) -->"
        ),
        format!("<!-- end generated: satflock validate {target} -->"),
    )
}
