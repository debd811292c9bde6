//! Reading a run's output directory back: `summary.json` and the metrics and trajectory tables, for the
//! tools that work from a finished (or stopped) run's files — plots, the report, the OEM and CZML
//! exports, `characterize` on a trajectory.
//!
//! Tables are numeric columns by name (the `time_utc` text column is left out: it is the summary's
//! `epoch_utc` plus `t_s`); an empty cell (a value that does not exist) reads as NaN. A last line
//! without its newline (a run killed outright) is not a whole record and is left out.

use std::path::{Path, PathBuf};

use thiserror::Error;

use crate::time::{self, Epoch};

/// A file of a run directory that cannot be read.
#[derive(Debug, Error)]
#[error("{path}: {message}")]
pub struct RunDataError {
    /// The file (or directory).
    pub path: String,
    /// What is wrong.
    pub message: String,
}

impl RunDataError {
    fn new(path: &Path, message: impl Into<String>) -> Self {
        Self {
            path: path.display().to_string(),
            message: message.into(),
        }
    }
}

/// Numeric columns by name, all of one length.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Table {
    names: Vec<String>,
    columns: Vec<Vec<f64>>,
}

/// Columns that hold text, not numbers (left out of a [`Table`]).
const TEXT_COLUMNS: &[&str] = &["time_utc"];

impl Table {
    /// A table from its column names and columns (all of one length).
    pub fn new(names: Vec<String>, columns: Vec<Vec<f64>>) -> Self {
        assert_eq!(names.len(), columns.len(), "one name per column");
        assert!(
            columns.windows(2).all(|w| w[0].len() == w[1].len()),
            "columns of one length"
        );
        Self { names, columns }
    }

    /// Reads a CSV file written by satflock (header line, then numbers or empty cells).
    pub fn read_csv(path: &Path) -> Result<Self, RunDataError> {
        let text =
            std::fs::read_to_string(path).map_err(|e| RunDataError::new(path, e.to_string()))?;
        Self::parse_csv(&text).map_err(|m| RunDataError::new(path, m))
    }

    fn parse_csv(text: &str) -> Result<Self, String> {
        let mut lines: Vec<&str> = text.split('\n').collect();
        // The piece after the last newline is empty for a whole file, or a partial record.
        lines.pop();
        let Some((header, rows)) = lines.split_first() else {
            return Err("empty file (no header line)".into());
        };
        let header: Vec<&str> = header.split(',').collect();
        let keep: Vec<bool> = header.iter().map(|h| !TEXT_COLUMNS.contains(h)).collect();
        let names: Vec<String> = header
            .iter()
            .zip(&keep)
            .filter(|(_, k)| **k)
            .map(|(h, _)| h.to_string())
            .collect();
        let mut columns = vec![Vec::with_capacity(rows.len()); names.len()];
        for (row, line) in rows.iter().enumerate() {
            let cells: Vec<&str> = line.split(',').collect();
            if cells.len() != header.len() {
                return Err(format!(
                    "line {}: {} cells, the header has {}",
                    row + 2,
                    cells.len(),
                    header.len()
                ));
            }
            let mut c = 0;
            for (cell, k) in cells.iter().zip(&keep) {
                if !k {
                    continue;
                }
                let value = match *cell {
                    "" => f64::NAN,
                    v => v.parse::<f64>().map_err(|_| {
                        format!(
                            "line {}, column `{}`: `{v}` is not a number",
                            row + 2,
                            names[c]
                        )
                    })?,
                };
                columns[c].push(value);
                c += 1;
            }
        }
        Ok(Self { names, columns })
    }

    /// Column names, in file order.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// A column by name.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.names
            .iter()
            .position(|n| n == name)
            .map(|k| self.columns[k].as_slice())
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.columns.first().map_or(0, Vec::len)
    }
}

/// A run directory read back.
#[derive(Clone, Debug)]
pub struct RunData {
    /// The directory.
    pub dir: PathBuf,
    /// `summary.json` as JSON (its fields are documented by [`crate::output::RunSummary`]).
    pub summary: serde_json::Value,
    /// The instant of t = 0 (the summary's `epoch_utc`).
    pub epoch: Epoch,
    /// `metrics.csv`: one row per recording time.
    pub metrics: Table,
    /// `trajectory.csv`, when the run wrote one: one row per live satellite per recording time.
    pub trajectory: Option<Table>,
    /// `scene.json`: threats, obstacles, target formation.
    pub scene: super::Scene,
}

impl RunData {
    /// Reads `dir/summary.json`, `dir/metrics.csv` and, if present, `dir/trajectory.csv`.
    pub fn read(dir: &Path) -> Result<Self, RunDataError> {
        if !dir.is_dir() {
            return Err(RunDataError::new(
                dir,
                "is not a directory (expected a run's output directory, as written by `satflock run`)",
            ));
        }
        let summary_path = dir.join("summary.json");
        let text = std::fs::read_to_string(&summary_path).map_err(|e| {
            RunDataError::new(
                &summary_path,
                format!("{e} (a run directory holds summary.json)"),
            )
        })?;
        let summary: serde_json::Value = serde_json::from_str(&text)
            .map_err(|e| RunDataError::new(&summary_path, e.to_string()))?;
        let epoch_text = summary
            .get("epoch_utc")
            .and_then(|v| v.as_str())
            .unwrap_or(time::DEFAULT_EPOCH_UTC);
        let epoch = time::parse_epoch_utc(epoch_text)
            .map_err(|m| RunDataError::new(&summary_path, format!("epoch_utc: {m}")))?;
        let metrics = Table::read_csv(&dir.join("metrics.csv"))?;
        let trajectory_path = dir.join("trajectory.csv");
        let trajectory = if trajectory_path.exists() {
            Some(Table::read_csv(&trajectory_path)?)
        } else {
            None
        };
        let scene = super::Scene::read(dir)?;
        Ok(Self {
            scene,
            dir: dir.to_path_buf(),
            summary,
            epoch,
            metrics,
            trajectory,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_numbers_empty_cells_and_drops_a_partial_last_record() {
        let t = Table::parse_csv("t_s,time_utc,a\n0,2000-01-01T12:00:00.000000,1.5\n1,x,\n2,x,3")
            .unwrap();
        assert_eq!(t.names(), ["t_s", "a"]);
        assert_eq!(t.rows(), 2);
        assert_eq!(t.column("t_s").unwrap(), [0.0, 1.0]);
        assert!(t.column("a").unwrap()[1].is_nan());
        assert!(Table::parse_csv("t_s,a\n0,zz\n")
            .unwrap_err()
            .contains("`a`"));
        assert!(Table::parse_csv("t_s,a\n0\n")
            .unwrap_err()
            .contains("line 2"));
    }
}
