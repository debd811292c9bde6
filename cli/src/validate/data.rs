//! The papers' reported outcomes as data: one TOML file per reproduced paper in `validation/` (compiled
//! into the binary), each outcome with its id, what is compared, the paper's value, the acceptance
//! criterion with the numbers it uses (units in their names) and whether the criterion was fixed before
//! the runs or changed after them (with the reason). A reproduction measures; this module supplies what
//! it is measured against, and builds each [`Check`] from the two.

use std::collections::BTreeMap;

use serde::Deserialize;

use crate::validate::{Check, Report, Table, ValidateError, Verdict};

/// The data files, by validation target.
const FILES: &[(&str, &str, &str)] = &[
    (
        "pigeon",
        "validation/pigeon.toml",
        include_str!("../../../validation/pigeon.toml"),
    ),
    (
        "scatter",
        "validation/scatter.toml",
        include_str!("../../../validation/scatter.toml"),
    ),
    (
        "takahashi",
        "validation/takahashi.toml",
        include_str!("../../../validation/takahashi.toml"),
    ),
    (
        "takahashi-split",
        "validation/takahashi-split.toml",
        include_str!("../../../validation/takahashi-split.toml"),
    ),
    (
        "gao",
        "validation/gao.toml",
        include_str!("../../../validation/gao.toml"),
    ),
];

/// When an acceptance criterion was set.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Fixed {
    /// Before any run of the reproduction.
    Before,
    /// After results were seen (the outcome's `reason` says why).
    After,
}

/// One reported outcome of a paper and how it is judged.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Outcome {
    /// Short identifier (`P3`, `N6`, …); unique in its file.
    pub id: String,
    /// What is compared.
    pub outcome: String,
    /// The paper's value or statement, with units.
    pub paper: String,
    /// The acceptance criterion, in words (its numbers are in `values`).
    pub criterion: String,
    /// Whether the criterion was fixed before the runs or changed after them.
    pub fixed: Fixed,
    /// Why the criterion, a default it depends on or the row itself changed after results were seen
    /// (required when `fixed = "after"`; allowed otherwise to record a changed default).
    #[serde(default)]
    pub reason: Option<String>,
    /// Set when the outcome is no longer judged: why (the row stays in the table, verdict `retired`).
    #[serde(default)]
    pub retired: Option<String>,
    /// The numbers the criterion uses, keyed by name with the unit in the name (`min_separation_m`).
    #[serde(default)]
    pub values: BTreeMap<String, f64>,
}

/// A paper's data file.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PaperData {
    /// The validation target it belongs to (`pigeon`, …).
    pub target: String,
    /// The paper, as cited in the report's heading.
    pub title: String,
    /// The outcomes, in the order of the report.
    #[serde(rename = "outcome")]
    pub outcomes: Vec<Outcome>,
    /// The paper's numbers of a report's further tables, by table name: rows of column → text as
    /// printed (e.g. the strategy comparison's Table 2 values beside ours).
    #[serde(default)]
    pub tables: BTreeMap<String, Vec<BTreeMap<String, String>>>,
}

fn bad_data(file: &str, message: impl std::fmt::Display) -> ValidateError {
    ValidateError::Failed {
        target: file.to_string(),
        message: message.to_string(),
    }
}

impl PaperData {
    /// The data of a target (`None`: the target has no data file, e.g. `core`).
    pub fn of(target: &str) -> Option<Result<Self, ValidateError>> {
        FILES
            .iter()
            .find(|(t, _, _)| *t == target)
            .map(|(_, file, text)| Self::parse(file, text))
    }

    /// Parses and checks a data file's text: unique ids, a reason for every criterion set after the
    /// runs, finite values.
    pub fn parse(file: &str, text: &str) -> Result<Self, ValidateError> {
        let data: PaperData = toml::from_str(text).map_err(|e| bad_data(file, e))?;
        let mut seen = std::collections::BTreeSet::new();
        for o in &data.outcomes {
            if !seen.insert(o.id.as_str()) {
                return Err(bad_data(
                    file,
                    format!("outcome id `{}` appears twice", o.id),
                ));
            }
            if o.fixed == Fixed::After && o.reason.as_deref().is_none_or(str::is_empty) {
                return Err(bad_data(
                    file,
                    format!("outcome `{}`: fixed = \"after\" needs a `reason`", o.id),
                ));
            }
            if let Some((key, v)) = o.values.iter().find(|(_, v)| !v.is_finite()) {
                return Err(bad_data(
                    file,
                    format!("outcome `{}`: values.{key} = {v} is not finite", o.id),
                ));
            }
        }
        Ok(data)
    }

    /// The rows of a further table's paper values.
    pub fn table(&self, name: &str) -> Result<&[BTreeMap<String, String>], ValidateError> {
        self.tables.get(name).map(Vec::as_slice).ok_or_else(|| {
            bad_data(
                &format!("validation/{}.toml", self.target),
                format!("no [[tables.{name}]]"),
            )
        })
    }

    /// The paper's report of the measured `checks` (texts and criteria re-applied from this data by
    /// [`crate::validate::with_data`]), further `tables` and `notes`.
    pub fn report(&self, checks: Vec<Check>, tables: Vec<Table>, notes: Vec<String>) -> Report {
        Report {
            title: self.title.clone(),
            reference_header: "paper".into(),
            measured: None,
            checks,
            tables,
            notes,
        }
    }

    /// The outcome of that id.
    pub fn outcome(&self, id: &str) -> Result<&Outcome, ValidateError> {
        self.outcomes.iter().find(|o| o.id == id).ok_or_else(|| {
            bad_data(
                &format!("validation/{}.toml", self.target),
                format!("no outcome `{id}`"),
            )
        })
    }
}

impl Outcome {
    /// A number of the criterion.
    pub fn value(&self, key: &str) -> Result<f64, ValidateError> {
        self.values.get(key).copied().ok_or_else(|| {
            bad_data(
                "validation data",
                format!("outcome `{}` has no values.{key}", self.id),
            )
        })
    }

    /// The check of this outcome: our value and the verdict, with the outcome's texts.
    pub fn check(&self, ours: String, verdict: Verdict) -> Check {
        Check {
            id: self.id.clone(),
            outcome: self.outcome.clone(),
            paper: self.paper.clone(),
            criterion: Some(self.criterion_text()),
            ours,
            verdict,
        }
    }

    /// The criterion with when it was fixed: "… (fixed before the runs)" or "… (changed after the
    /// results: reason)".
    pub fn criterion_text(&self) -> String {
        match (self.fixed, &self.reason) {
            (Fixed::Before, None) => format!("{} (fixed before the runs)", self.criterion),
            (Fixed::Before, Some(r)) => {
                format!("{} (fixed before the runs; {r})", self.criterion)
            }
            (Fixed::After, r) => format!(
                "{} (changed after the results: {})",
                self.criterion,
                r.as_deref().unwrap_or_default()
            ),
        }
    }

    /// The row of a retired outcome.
    pub fn retired_check(&self) -> Option<Check> {
        self.retired.as_ref().map(|why| Check {
            id: self.id.clone(),
            outcome: self.outcome.clone(),
            paper: self.paper.clone(),
            criterion: Some(self.criterion_text()),
            ours: format!("not judged: {why}"),
            verdict: Verdict::Retired,
        })
    }
}

/// Re-applies a paper's data to a measured report: every check takes its texts from the data (so a
/// saved measurement renders with today's data), retired outcomes are added, and the checks are put
/// in the data's order. Fails if a check has no outcome in the data or a live outcome has no check.
pub fn apply(data: &PaperData, checks: &[Check]) -> Result<Vec<Check>, ValidateError> {
    let file = format!("validation/{}.toml", data.target);
    if let Some(c) = checks.iter().find(|c| data.outcome(&c.id).is_err()) {
        return Err(bad_data(
            &file,
            format!(
                "the reproduction measured `{}`, which has no outcome here",
                c.id
            ),
        ));
    }
    data.outcomes
        .iter()
        .map(|o| match o.retired_check() {
            Some(row) => Ok(row),
            None => checks
                .iter()
                .find(|c| c.id == o.id)
                .map(|c| o.check(c.ours.clone(), c.verdict))
                .ok_or_else(|| bad_data(&file, format!("outcome `{}` was not measured", o.id))),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_data_file_parses_and_names_its_target() {
        for (target, file, text) in FILES {
            let data = PaperData::parse(file, text).unwrap();
            assert_eq!(data.target, *target, "{file}");
            assert!(!data.outcomes.is_empty(), "{file}");
        }
    }

    #[test]
    fn a_criterion_changed_after_the_runs_needs_a_reason_and_ids_are_unique() {
        let row = |id: &str, fixed: &str| {
            format!(
                "[[outcome]]\nid = \"{id}\"\noutcome = \"o\"\npaper = \"p\"\ncriterion = \"c\"\nfixed = \"{fixed}\"\n"
            )
        };
        let head = "target = \"t\"\ntitle = \"T\"\n";
        let after = format!("{head}{}", row("A", "after"));
        let e = PaperData::parse("t.toml", &after).unwrap_err().to_string();
        assert!(
            e.contains("needs a `reason`") && e.contains("t.toml"),
            "{e}"
        );
        let twice = format!("{head}{}{}", row("A", "before"), row("A", "before"));
        let e = PaperData::parse("t.toml", &twice).unwrap_err().to_string();
        assert!(e.contains("appears twice"), "{e}");
        let ok = format!("{head}{}reason = \"r\"\n", row("A", "after"));
        let data = PaperData::parse("t.toml", &ok).unwrap();
        assert_eq!(
            data.outcomes[0].criterion_text(),
            "c (changed after the results: r)"
        );
    }

    #[test]
    fn apply_orders_by_the_data_and_refuses_strays_and_gaps() {
        let text = "target = \"t\"\ntitle = \"T\"\n\
            [[outcome]]\nid = \"A\"\noutcome = \"oa\"\npaper = \"pa\"\ncriterion = \"ca\"\nfixed = \"before\"\n\
            [[outcome]]\nid = \"R\"\noutcome = \"or\"\npaper = \"pr\"\ncriterion = \"cr\"\nfixed = \"before\"\nretired = \"false bound\"\n\
            [[outcome]]\nid = \"B\"\noutcome = \"ob\"\npaper = \"pb\"\ncriterion = \"cb\"\nfixed = \"before\"\n";
        let data = PaperData::parse("t.toml", text).unwrap();
        let measured = |id: &str| {
            data.outcome(id)
                .unwrap()
                .check("x".into(), Verdict::Differs)
        };
        let rows = apply(&data, &[measured("B"), measured("A")]).unwrap();
        let ids: Vec<&str> = rows.iter().map(|c| c.id.as_str()).collect();
        assert_eq!(ids, ["A", "R", "B"]);
        assert_eq!(rows[1].verdict, Verdict::Retired);
        assert!(apply(&data, &[measured("A")]).is_err());
        let mut stray = measured("A");
        stray.id = "Z".into();
        assert!(apply(&data, &[measured("A"), measured("B"), stray]).is_err());
    }
}
