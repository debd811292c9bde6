//! Reading a run's output directory back: `summary.json` and the metrics and trajectory tables, for the
//! tools that work from a finished (or stopped) run's files — plots, the report, the OEM and CZML
//! exports, `characterize` on a trajectory.
//!
//! Each table is read from its CSV or its Parquet file, whichever the run wrote. Tables are numeric
//! columns by name (the `time_utc` text column is left out: it is the summary's `epoch_utc` plus `t_s`);
//! an empty CSV cell or a Parquet null (a value that does not exist) reads as NaN. A last CSV line
//! without its newline (a run killed outright) is not a whole record and is left out; a Parquet file of a
//! run killed outright has no footer and is refused, saying so.

use std::path::{Path, PathBuf};

use arrow_array::cast::AsArray;
use arrow_array::types::{Float64Type, UInt64Type};
use arrow_schema::DataType;
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
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

    /// Reads a table written by satflock: Parquet if the file name ends in `.parquet`, CSV otherwise.
    pub fn read(path: &Path) -> Result<Self, RunDataError> {
        if path.extension().is_some_and(|e| e == "parquet") {
            Self::read_parquet(path)
        } else {
            Self::read_csv(path)
        }
    }

    /// Reads a CSV file written by satflock (header line, then numbers or empty cells).
    pub fn read_csv(path: &Path) -> Result<Self, RunDataError> {
        let text = std::fs::read_to_string(regular_file(path)?)
            .map_err(|e| RunDataError::new(path, e.to_string()))?;
        Self::parse_csv(&text).map_err(|m| RunDataError::new(path, m))
    }

    /// Reads a Parquet file written by satflock: its number columns (`Float64`, nulls as NaN, and
    /// `UInt64` counts), leaving out `time_utc`.
    pub fn read_parquet(path: &Path) -> Result<Self, RunDataError> {
        let error = |e: &dyn std::fmt::Display| RunDataError::new(path, e.to_string());
        let file = std::fs::File::open(regular_file(path)?).map_err(|e| error(&e))?;
        let builder = ParquetRecordBatchReaderBuilder::try_new(file).map_err(|e| {
            RunDataError::new(
                path,
                format!(
                    "{e} (a Parquet file is readable once its run has closed it; a run killed \
                     outright, e.g. by SIGKILL, leaves no footer: CSV is the format that survives that)"
                ),
            )
        })?;
        let schema = builder.schema().clone();
        let mut names = Vec::new();
        let mut keep = Vec::new();
        for (k, field) in schema.fields().iter().enumerate() {
            if TEXT_COLUMNS.contains(&field.name().as_str()) {
                continue;
            }
            if !matches!(field.data_type(), DataType::Float64 | DataType::UInt64) {
                return Err(RunDataError::new(
                    path,
                    format!(
                        "column `{}` is {} (expected Float64 or UInt64 numbers)",
                        field.name(),
                        field.data_type()
                    ),
                ));
            }
            names.push(field.name().clone());
            keep.push(k);
        }
        let rows = builder.metadata().file_metadata().num_rows().max(0) as usize;
        let mut columns: Vec<Vec<f64>> = vec![Vec::with_capacity(rows); names.len()];
        let reader = builder.build().map_err(|e| error(&e))?;
        for batch in reader {
            let batch = batch.map_err(|e| error(&e))?;
            for (column, &k) in columns.iter_mut().zip(&keep) {
                let array = batch.column(k);
                if let Some(a) = array.as_primitive_opt::<Float64Type>() {
                    column.extend(a.iter().map(|v| v.unwrap_or(f64::NAN)));
                } else if let Some(a) = array.as_primitive_opt::<UInt64Type>() {
                    column.extend(a.iter().map(|v| v.map_or(f64::NAN, |v| v as f64)));
                }
            }
        }
        Ok(Self { names, columns })
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

/// `path` if it is a regular file (a device such as `/dev/zero` or a FIFO would be read forever).
fn regular_file(path: &Path) -> Result<&Path, RunDataError> {
    let metadata = std::fs::metadata(path).map_err(|e| RunDataError::new(path, e.to_string()))?;
    if metadata.is_file() {
        Ok(path)
    } else {
        Err(RunDataError::new(
            path,
            "is not a regular file (allowed: a table file written by satflock)",
        ))
    }
}

/// Reads `dir/NAME.csv` or, if there is none, `dir/NAME.parquet` (`None`: neither exists).
fn read_table(dir: &Path, name: &str) -> Result<Option<Table>, RunDataError> {
    for ext in ["csv", "parquet"] {
        let path = dir.join(format!("{name}.{ext}"));
        if path.exists() {
            return Table::read(&path).map(Some);
        }
    }
    Ok(None)
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
    /// `metrics.csv` or `metrics.parquet`: one row per recording time.
    pub metrics: Table,
    /// `trajectory.csv` or `trajectory.parquet`, when the run wrote one: one row per live satellite per
    /// recording time.
    pub trajectory: Option<Table>,
    /// `scene.json`: threats, obstacles, target formation.
    pub scene: super::Scene,
}

impl RunData {
    /// Reads `dir/summary.json`, `dir/scene.json`, the metrics table and, if present, the trajectory
    /// table (each from its `.csv` or its `.parquet` file).
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
        let metrics = read_table(dir, "metrics")?.ok_or_else(|| {
            RunDataError::new(
                dir,
                "holds neither metrics.csv nor metrics.parquet (a run directory holds one)",
            )
        })?;
        let trajectory = read_table(dir, "trajectory")?;
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
