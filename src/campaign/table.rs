//! `campaign.parquet`: one row per run that finished (in run order), as a [`RunTable`].
//!
//! Columns: text `status`, `error` (empty when none) and `seed` (decimal: a 64-bit seed does not fit a
//! double exactly), and `parameter.KEY` for a varied key whose values are not all numbers (their TOML
//! text); numbers `run`, `point`, `parameter.KEY` for a numeric varied key (the value the run used, from
//! its record: read back from its `scenario.toml`), then every scalar outcome of the runs'
//! `summary.json` by its dotted name (a run without it: null).

use super::file::Campaign;
use super::manifest::RunRecord;
use crate::output::outcomes::RunTable;

/// Name of the table in the output directory.
pub const FILE_NAME: &str = "campaign.parquet";

/// Prefix of the parameter columns (`parameter.law.k_f_kg_per_m_s2`).
pub const PARAMETER_PREFIX: &str = "parameter.";

/// A TOML value as a number, if it is one.
pub fn number(value: &toml::Value) -> Option<f64> {
    match value {
        toml::Value::Float(v) => Some(*v),
        toml::Value::Integer(i) => Some(*i as f64),
        _ => None,
    }
}

/// Whether every value of parameter `k` (over the campaign's points) is a number.
pub fn is_numeric(campaign: &Campaign, k: usize) -> bool {
    campaign.points.iter().all(|p| number(&p[k]).is_some())
}

/// The table of `records` (sorted by run index here).
pub fn build(campaign: &Campaign, records: &[RunRecord]) -> RunTable {
    let mut records: Vec<&RunRecord> = records.iter().collect();
    records.sort_by_key(|r| r.run);
    let numeric: Vec<bool> = (0..campaign.parameters.len())
        .map(|k| is_numeric(campaign, k))
        .collect();
    let mut text_rows = Vec::with_capacity(records.len());
    let mut number_rows = Vec::with_capacity(records.len());
    for r in records {
        let mut text = vec![
            ("status".to_string(), r.status.as_str().to_string()),
            ("error".to_string(), r.error.clone().unwrap_or_default()),
            ("seed".to_string(), r.seed.to_string()),
        ];
        let mut numbers = vec![
            ("run".to_string(), r.run as f64),
            ("point".to_string(), r.point as f64),
        ];
        for (k, (key, value)) in campaign.point_values(r.point).into_iter().enumerate() {
            let name = format!("{PARAMETER_PREFIX}{key}");
            // A number as the run used it (its record's, read from its scenario.toml).
            let applied = r.parameters.get(key.as_str()).and_then(|v| v.as_f64());
            match (numeric[k], applied.or(number(value))) {
                (true, Some(v)) => numbers.push((name, v)),
                _ => text.push((name, value.to_string())),
            }
        }
        numbers.extend(r.outcomes.iter().map(|(n, v)| (n.clone(), *v)));
        text_rows.push(text);
        number_rows.push(numbers);
    }
    RunTable::from_rows(&text_rows, &number_rows)
}
