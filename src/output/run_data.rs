//! Reading a run's output directory back: `summary.json`, `scene.json` and the metrics and trajectory
//! tables, for every tool that works from a finished (or stopped) run's files — plots, the report, the
//! OEM and CZML exports, `characterize` on a trajectory. One reader, one set of checks: whatever
//! command reads a run directory accepts and refuses the same files, with the same messages (the file,
//! the column or key, what is allowed).
//!
//! Each table is read from its CSV or its Parquet file, whichever the run wrote (a directory holding
//! both is refused: a run writes one). Tables are numeric columns by name (the `time_utc` text column is
//! left out: it is the summary's `epoch_utc` plus `t_s`); a number is finite, and an empty CSV cell or a
//! Parquet null (a value that does not exist) reads as NaN. A last CSV line without its newline (a run
//! killed outright) is not a whole record and is left out; a Parquet file of a run killed outright has no
//! footer and is refused, saying so. Every file is read through [`crate::input_file`] (regular files of
//! bounded size), and nothing is allocated from a count a file states (a Parquet footer's row count, the
//! summary's `n_satellites`): only from what was read.
//!
//! The checks ([`RunData::read`], [`Table::check_trajectory`]): `summary.json` is a JSON object with
//! `n_satellites` an integer from 1 to [`crate::scenario::MAX_SATELLITES`]; a table has at least one row
//! and a `t_s` column whose every row has a time from 0 to [`MAX_TIME_S`], in non-decreasing order; a
//! trajectory's `id` is an integer from 0 below `n_satellites`, its rows ordered by time then id (so no
//! satellite appears twice at one time), and its position columns have a value in every row; in
//! `scene.json` radii are at least 0.

use std::path::{Path, PathBuf};

use arrow_array::cast::AsArray;
use arrow_array::types::{Float64Type, UInt64Type};
use arrow_schema::DataType;
use parquet::arrow::arrow_reader::{ArrowReaderOptions, ParquetRecordBatchReaderBuilder};
use thiserror::Error;

use crate::input_file::{self, MAX_TABLE_BYTES};
use crate::scenario::MAX_SATELLITES;
use crate::time::{self, Epoch};

/// Latest time a run directory's tables and summary may state \[s\] (10¹¹ s, about 3 000 years).
pub const MAX_TIME_S: f64 = 1e11;

/// The position columns of a trajectory (each row has a value in each).
pub const TRAJECTORY_POSITION_COLUMNS: [&str; 3] = ["x_lvlh_m", "y_lvlh_m", "z_lvlh_m"];

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

/// Where a table's row `row` (from 0) is, for messages: its CSV line or its Parquet row.
pub(crate) fn row_name(path: &Path, row: usize) -> String {
    if path.extension().is_some_and(|e| e == "parquet") {
        format!("row {}", row + 1)
    } else {
        format!("line {}", row + 2)
    }
}

/// Numeric columns by name, all of one length.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Table {
    names: Vec<String>,
    columns: Vec<Vec<f64>>,
}

/// Columns that hold text, not numbers (left out of a [`Table`]).
const TEXT_COLUMNS: &[&str] = &["time_utc", "tca_utc"];

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

    /// Reads a CSV file written by satflock (header line, then finite numbers or empty cells).
    pub fn read_csv(path: &Path) -> Result<Self, RunDataError> {
        let text = input_file::read_to_string(path, MAX_TABLE_BYTES)
            .map_err(|e| RunDataError::new(path, e.to_string()))?;
        Self::parse_csv(&text).map_err(|m| RunDataError::new(path, m))
    }

    /// Reads a Parquet file written by satflock: its number columns (`Float64`, nulls as NaN, and
    /// `UInt64` counts), leaving out `time_utc`.
    pub fn read_parquet(path: &Path) -> Result<Self, RunDataError> {
        let error = |e: &dyn std::fmt::Display| RunDataError::new(path, e.to_string());
        let file = input_file::open_parquet(path, MAX_TABLE_BYTES).map_err(|e| error(&e))?;
        // The schema comes from the Parquet schema alone: the embedded Arrow schema (`ARROW:schema`)
        // is not decoded, as arrow-ipc panics on some damaged ones (found by `fuzz_run_dirs`).
        let options = ArrowReaderOptions::new().with_skip_arrow_metadata(true);
        let builder = ParquetRecordBatchReaderBuilder::try_new_with_options(file, options)
            .map_err(|e| {
                RunDataError::new(
                    path,
                    format!(
                        "{e} (a Parquet file is readable once its run has closed it; a run killed \
                         outright, e.g. by SIGKILL, leaves no footer: CSV is the format that survives \
                         that)"
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
        // Columns grow with the rows actually read: the footer's row count is never trusted for an
        // allocation, only compared with what was read.
        let claimed = builder.metadata().file_metadata().num_rows();
        let mut columns: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
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
        let read = columns.first().map_or(0, Vec::len);
        if !names.is_empty() && i64::try_from(read) != Ok(claimed) {
            return Err(RunDataError::new(
                path,
                format!(
                    "the footer claims {claimed} rows, the file holds {read} (a damaged Parquet file)"
                ),
            ));
        }
        for (name, column) in names.iter().zip(&columns) {
            if let Some(row) = column.iter().position(|v| v.is_infinite()) {
                return Err(RunDataError::new(
                    path,
                    format!(
                        "row {}, column `{name}`: {} is not finite (allowed: a finite number, or \
                         null for no value)",
                        row + 1,
                        column[row]
                    ),
                ));
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
                    v => v
                        .parse::<f64>()
                        .ok()
                        .filter(|x| x.is_finite())
                        .ok_or_else(|| {
                            format!(
                            "line {}, column `{}`: `{v}` is not a finite number (allowed: a finite \
                             number, or an empty cell for no value)",
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

    /// Checks a conjunction table: every column of [`super::conjunctions`], a `tca_s` from 0 to
    /// [`MAX_TIME_S`] and a value in every number column of every row (no time order: rows are sorted by
    /// TCA, but a table is checked as a set of encounters).
    pub fn check_conjunctions(&self, path: &Path) -> Result<(), RunDataError> {
        let tca = self.required(path, "tca_s", "conjunction table")?;
        if let Some(row) = tca.iter().position(|t| !(0.0..=MAX_TIME_S).contains(t)) {
            return Err(RunDataError::new(
                path,
                format!(
                    "{}, column `tca_s`: {} is out of range (allowed: 0 to {MAX_TIME_S:e} s)",
                    row_name(path, row),
                    tca[row]
                ),
            ));
        }
        for name in super::conjunctions::id_column_names()
            .iter()
            .chain(&super::conjunctions::value_column_names())
        {
            // The secondary's id columns are empty where it is of another kind.
            if name.starts_with("secondary") && !name.contains("_eme2000_") {
                if self.column(name).is_none() {
                    return Err(RunDataError::new(
                        path,
                        format!("has no column `{name}` (a conjunction table has one)"),
                    ));
                }
                continue;
            }
            self.required(path, name, "conjunction table")?;
        }
        Ok(())
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

    /// The column `name` of the table read from `path`, which must exist and have a value in every row.
    fn required(&self, path: &Path, name: &str, what: &str) -> Result<&[f64], RunDataError> {
        let column = self.column(name).ok_or_else(|| {
            RunDataError::new(
                path,
                format!("has no `{name}` column (a {what} written by `satflock run` has one)"),
            )
        })?;
        if let Some(row) = column.iter().position(|v| v.is_nan()) {
            return Err(RunDataError::new(
                path,
                format!(
                    "{}: `{name}` has no value (allowed: a finite number in every row)",
                    row_name(path, row)
                ),
            ));
        }
        Ok(column)
    }

    /// The checks of every table of a run directory, read from `path`: at least one row, and a `t_s`
    /// column of times from 0 to [`MAX_TIME_S`] in non-decreasing order. `what` names the table.
    fn check_times(&self, path: &Path, what: &str) -> Result<&[f64], RunDataError> {
        let t = self.required(path, "t_s", what)?;
        if t.is_empty() {
            return Err(RunDataError::new(
                path,
                format!(
                    "has no rows (allowed: a {what} with at least one row; a run records t = 0 \
                     before anything else)"
                ),
            ));
        }
        for (row, &v) in t.iter().enumerate() {
            let after = row.checked_sub(1).map_or(0.0, |r| t[r]);
            if !(0.0..=MAX_TIME_S).contains(&v) || v < after {
                return Err(RunDataError::new(
                    path,
                    format!(
                        "{}: t_s = {v} is not allowed (allowed: from {after} to {MAX_TIME_S:e} s: \
                         times from 0, in non-decreasing order)",
                        row_name(path, row)
                    ),
                ));
            }
        }
        Ok(t)
    }

    /// The checks of a metrics table read from `path` (see the module's documentation).
    pub fn check_metrics(&self, path: &Path) -> Result<(), RunDataError> {
        self.check_times(path, "metrics table").map(|_| ())
    }

    /// The checks of a trajectory table read from `path` (see the module's documentation); ids must be
    /// below `n_satellites` (the run's `summary.json`), or below [`MAX_SATELLITES`] for a trajectory
    /// file read alone.
    pub fn check_trajectory(
        &self,
        path: &Path,
        n_satellites: Option<usize>,
    ) -> Result<(), RunDataError> {
        const WHAT: &str = "trajectory";
        let t = self.check_times(path, WHAT)?;
        let id = self.required(path, "id", WHAT)?;
        for name in TRAJECTORY_POSITION_COLUMNS {
            self.required(path, name, WHAT)?;
        }
        let (limit, whose) = match n_satellites {
            Some(n) => (n, "summary.json n_satellites"),
            None => (MAX_SATELLITES, "the most satellites a scenario may have"),
        };
        for row in 0..t.len() {
            let v = id[row];
            if !(v >= 0.0 && v.fract() == 0.0 && v < limit as f64) {
                return Err(RunDataError::new(
                    path,
                    format!(
                        "{}: id = {v} is not a satellite index (allowed: an integer from 0 below \
                         {whose} = {limit})",
                        row_name(path, row)
                    ),
                ));
            }
            if row > 0 && t[row] == t[row - 1] && v <= id[row - 1] {
                return Err(RunDataError::new(
                    path,
                    format!(
                        "{}: id = {v} at t_s = {} follows id = {} (allowed: at each time, every \
                         satellite once, in increasing id order)",
                        row_name(path, row),
                        t[row],
                        id[row - 1]
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// `dir/NAME.csv` or `dir/NAME.parquet`, whichever exists (`None`: neither; both is refused: a run
/// writes a table in one format, so one of them is stale).
fn table_path(dir: &Path, name: &str) -> Result<Option<PathBuf>, RunDataError> {
    let [csv, parquet] = ["csv", "parquet"].map(|ext| dir.join(format!("{name}.{ext}")));
    match (csv.exists(), parquet.exists()) {
        (true, true) => Err(RunDataError::new(
            dir,
            format!(
                "holds both {name}.csv and {name}.parquet (allowed: one of them; a run writes each \
                 table in one format, so one is left from another run: remove it)"
            ),
        )),
        (true, false) => Ok(Some(csv)),
        (false, true) => Ok(Some(parquet)),
        (false, false) => Ok(None),
    }
}

/// A run directory read back and checked (see the module's documentation).
#[derive(Clone, Debug)]
pub struct RunData {
    /// The directory.
    pub dir: PathBuf,
    /// `summary.json` as JSON (its fields are documented by [`crate::output::RunSummary`]): an object.
    pub summary: serde_json::Value,
    /// The summary's `n_satellites`: every trajectory id is below it.
    pub n_satellites: usize,
    /// The instant of t = 0 (the summary's `epoch_utc`).
    pub epoch: Epoch,
    /// `metrics.csv` or `metrics.parquet`: one row per recording time.
    pub metrics: Table,
    /// `trajectory.csv` or `trajectory.parquet`, when the run wrote one: one row per live satellite per
    /// recording time.
    pub trajectory: Option<Table>,
    /// The trajectory's file, when the run wrote one (for messages).
    pub trajectory_path: Option<PathBuf>,
    /// `scene.json`: threats, obstacles, target formation.
    pub scene: super::Scene,
    /// `conjunctions.csv` or `conjunctions.parquet`, when the run monitored conjunctions: one row per
    /// encounter ([`super::conjunctions`]).
    pub conjunctions: Option<Table>,
    /// Every file read (an export must not write over one of them).
    pub files: Vec<PathBuf>,
}

impl RunData {
    /// Reads and checks `dir/summary.json`, `dir/scene.json`, the metrics table and, if present, the
    /// trajectory table (each from its `.csv` or its `.parquet` file).
    pub fn read(dir: &Path) -> Result<Self, RunDataError> {
        if !dir.is_dir() {
            return Err(RunDataError::new(
                dir,
                "is not a directory (expected a run's output directory, as written by `satflock run`)",
            ));
        }
        let summary_path = dir.join("summary.json");
        let (summary, n_satellites, epoch) = read_summary(&summary_path)?;
        let mut files = vec![summary_path];
        let metrics_path = table_path(dir, "metrics")?.ok_or_else(|| {
            RunDataError::new(
                dir,
                "holds neither metrics.csv nor metrics.parquet (a run directory holds one)",
            )
        })?;
        let metrics = Table::read(&metrics_path)?;
        metrics.check_metrics(&metrics_path)?;
        files.push(metrics_path);
        let trajectory_path = table_path(dir, "trajectory")?;
        let trajectory = match &trajectory_path {
            Some(path) => {
                let table = Table::read(path)?;
                table.check_trajectory(path, Some(n_satellites))?;
                files.push(path.clone());
                Some(table)
            }
            None => None,
        };
        let scene = super::Scene::read(dir)?;
        files.push(dir.join(super::scene::SCENE_FILE));
        let conjunctions = match table_path(dir, super::conjunctions::TABLE)? {
            Some(path) => {
                let table = Table::read(&path)?;
                table.check_conjunctions(&path)?;
                files.push(path);
                Some(table)
            }
            None => None,
        };
        Ok(Self {
            conjunctions,
            scene,
            dir: dir.to_path_buf(),
            summary,
            n_satellites,
            epoch,
            metrics,
            trajectory,
            trajectory_path,
            files,
        })
    }
}

/// Reads and checks `summary.json`: the JSON, `n_satellites` and the epoch of t = 0.
fn read_summary(path: &Path) -> Result<(serde_json::Value, usize, Epoch), RunDataError> {
    let text = input_file::read_document(path).map_err(|e| {
        RunDataError::new(path, format!("{e} (a run directory holds summary.json)"))
    })?;
    let summary: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| RunDataError::new(path, e.to_string()))?;
    let Some(object) = summary.as_object() else {
        return Err(RunDataError::new(
            path,
            "is not a JSON object (a summary written by `satflock run` is one)",
        ));
    };
    let n = object.get("n_satellites");
    let n_satellites = n
        .and_then(serde_json::Value::as_u64)
        .filter(|n| (1..=MAX_SATELLITES as u64).contains(n))
        .ok_or_else(|| {
            RunDataError::new(
                path,
                format!(
                    "`n_satellites` = {} is not allowed (allowed: an integer from 1 to {MAX_SATELLITES})",
                    n.map_or("(missing)".to_string(), |v| v.to_string())
                ),
            )
        })? as usize;
    for key in ["duration_s", "simulated_s"] {
        match object.get(key) {
            None | Some(serde_json::Value::Null) => {}
            Some(v) if v.as_f64().is_some_and(|x| (0.0..=MAX_TIME_S).contains(&x)) => {}
            Some(v) => {
                return Err(RunDataError::new(
                    path,
                    format!(
                    "`{key}` = {v} is not allowed (allowed: a number from 0 to {MAX_TIME_S:e} s)"
                ),
                ))
            }
        }
    }
    let epoch_text = match object.get("epoch_utc") {
        None => time::DEFAULT_EPOCH_UTC,
        Some(v) => v.as_str().ok_or_else(|| {
            RunDataError::new(
                path,
                format!("`epoch_utc` = {v} is not allowed (allowed: an ISO 8601 UTC text)"),
            )
        })?,
    };
    let epoch = time::parse_epoch_utc(epoch_text)
        .map_err(|m| RunDataError::new(path, format!("`epoch_utc`: {m}")))?;
    Ok((summary, n_satellites, epoch))
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

    #[test]
    fn numbers_are_finite_or_no_value() {
        for text in ["NaN", "inf", "-inf", "1e999"] {
            let e = Table::parse_csv(&format!("t_s,a\n0,{text}\n")).unwrap_err();
            assert!(
                e.contains("line 2, column `a`") && e.contains("finite"),
                "{e}"
            );
        }
    }

    fn trajectory(rows: &[[f64; 5]]) -> Table {
        let names = ["t_s", "id", "x_lvlh_m", "y_lvlh_m", "z_lvlh_m"];
        Table::new(
            names.iter().map(|n| n.to_string()).collect(),
            (0..5)
                .map(|c| rows.iter().map(|r| r[c]).collect())
                .collect(),
        )
    }

    #[test]
    fn a_trajectory_is_checked_row_by_row() {
        let path = Path::new("trajectory.csv");
        let good = [
            [0.0, 0.0, 1.0, 2.0, 3.0],
            [0.0, 1.0, 1.0, 2.0, 3.0],
            [5.0, 0.0, 1.0, 2.0, 3.0],
        ];
        trajectory(&good).check_trajectory(path, Some(2)).unwrap();
        let refused = |rows: &[[f64; 5]], n: Option<usize>, words: &[&str]| {
            let e = trajectory(rows).check_trajectory(path, n).unwrap_err();
            assert_eq!(e.path, "trajectory.csv");
            for w in words {
                assert!(e.message.contains(w), "{w}: {}", e.message);
            }
        };
        let mut bad = good;
        bad[1][1] = 2.0;
        refused(&bad, Some(2), &["line 3", "id = 2", "n_satellites = 2"]);
        bad[1][1] = 0.5;
        refused(&bad, None, &["id = 0.5", "integer"]);
        bad[1][1] = -1.0;
        refused(&bad, None, &["id = -1"]);
        bad = good;
        bad[1][1] = 0.0;
        refused(&bad, Some(2), &["line 3", "every satellite once"]);
        bad = good;
        bad[2][0] = f64::NAN;
        refused(&bad, Some(2), &["line 4", "`t_s` has no value"]);
        bad[2][0] = -1.0;
        refused(&bad, Some(2), &["line 4", "t_s = -1", "non-decreasing"]);
        bad = good;
        bad[0][0] = 1.0;
        refused(&bad, Some(2), &["line 3", "t_s = 0"]);
        bad = good;
        bad[1][3] = f64::NAN;
        refused(&bad, Some(2), &["line 3", "`y_lvlh_m` has no value"]);
        refused(&[], Some(2), &["has no rows"]);
    }
}
