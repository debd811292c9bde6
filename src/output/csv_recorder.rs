//! A [`Recorder`] that streams snapshots to `metrics.csv` (one row per recording time) and
//! `trajectory.csv` (one row per live satellite per recording time), or to one of them; the columns and
//! the row values are those of [`crate::output::columns`]. Each snapshot is flushed as soon as it is
//! written, so the files are complete, valid CSV up to the last recorded time even if a run stops.
//!
//! Whole records: each snapshot's rows are formatted into one buffer per file and handed to the system in
//! one `write` (no `BufWriter` splitting a row across flushes), so a process killed outright (SIGKILL)
//! loses whole records at the end of a file, never part of a row. A write that fails (a full disk, a
//! file-size limit) cuts the file back to its last whole record before the error is returned. A value that does not exist (NaN: a
//! ratio at t = 0, a metric of an empty set) is an empty cell, never `NaN`.

use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::output::columns::{Column, ColumnKind, OutputColumns, Record, Tables};
use crate::swarm::{Recorder, Snapshot};
use crate::time::Epoch;

/// Streams snapshots to CSV files in a directory.
pub struct CsvRecorder {
    metrics: Option<CsvTable>,
    trajectory: Option<CsvTable>,
    columns: OutputColumns,
    epoch: Epoch,
    record: Record,
    block: String,
}

/// One CSV file being written, with the length of its whole records \[bytes\].
struct CsvTable {
    path: PathBuf,
    file: File,
    columns: Vec<Column>,
    whole_len: u64,
}

impl CsvTable {
    /// Creates `path` and writes the header line of `columns` (a header that cannot be written
    /// removes the file).
    fn create(path: PathBuf, columns: Vec<Column>) -> std::io::Result<Self> {
        let file = File::create(&path)?;
        let mut table = Self {
            path,
            file,
            columns,
            whole_len: 0,
        };
        let names: Vec<&str> = table.columns.iter().map(|c| c.name).collect();
        let header = format!("{}\n", names.join(","));
        if let Err(e) = table.append(header.as_bytes()) {
            let _ = std::fs::remove_file(&table.path);
            return Err(std::io::Error::new(
                e.kind(),
                format!("{e}; the file was removed"),
            ));
        }
        Ok(table)
    }

    /// Appends whole records in one write; if that fails, cuts the file back to its previous whole
    /// records and returns the error naming the file.
    fn append(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        match self.file.write_all(bytes) {
            Ok(()) => {
                self.whole_len += bytes.len() as u64;
                Ok(())
            }
            Err(e) => {
                let kept = match self.file.set_len(self.whole_len) {
                    Ok(()) => "it was cut back to its last whole record".to_string(),
                    Err(t) => format!("it could not be cut back to its last whole record: {t}"),
                };
                Err(std::io::Error::new(
                    e.kind(),
                    format!("{}: {e} ({kept})", self.path.display()),
                ))
            }
        }
    }
}

impl CsvRecorder {
    /// Creates `dir/metrics.csv` and `dir/trajectory.csv` (those of `tables`), with the variable
    /// `columns`, and writes their headers; `epoch` is the instant of t = 0 (for the `time_utc` column).
    pub fn create(
        dir: &Path,
        tables: Tables,
        columns: OutputColumns,
        epoch: Epoch,
    ) -> std::io::Result<Self> {
        let metrics = tables
            .metrics
            .then(|| CsvTable::create(dir.join("metrics.csv"), columns.metrics()))
            .transpose()?;
        let trajectory = tables
            .trajectory
            .then(|| CsvTable::create(dir.join("trajectory.csv"), columns.trajectory()))
            .transpose()?;
        Ok(Self {
            metrics,
            trajectory,
            columns,
            epoch,
            record: Record::default(),
            block: String::new(),
        })
    }
}

/// Appends one row: `t_s,time_utc`, then the values of the columns after those two.
fn push_row(block: &mut String, record: &Record, columns: &[Column], values: &[f64]) {
    use std::fmt::Write as _;
    let _ = write!(block, "{},{}", record.time_s, record.time_utc);
    for (column, &value) in columns[2..].iter().zip(values) {
        match column.kind {
            ColumnKind::Count if value.is_finite() => {
                let _ = write!(block, ",{}", value as u64);
            }
            _ => push(block, value),
        }
    }
    block.push('\n');
}

/// Formats a float so that it reads back to the same value (Rust's shortest round-trip form); NaN (a
/// value that does not exist) is an empty cell.
fn push(line: &mut String, value: f64) {
    use std::fmt::Write as _;
    line.push(',');
    if value.is_finite() {
        let _ = write!(line, "{value}");
    } else if value.is_nan() {
        // Empty cell.
    } else if value > 0.0 {
        line.push_str("inf");
    } else {
        line.push_str("-inf");
    }
}

impl Recorder for CsvRecorder {
    fn record(&mut self, s: &Snapshot<'_>) -> std::io::Result<()> {
        let record = &mut self.record;
        record.fill(&self.columns, self.epoch, s, self.trajectory.is_some());
        if let Some(table) = &mut self.metrics {
            self.block.clear();
            push_row(&mut self.block, record, &table.columns, &record.metrics);
            table.append(self.block.as_bytes())?;
        }
        if let Some(table) = &mut self.trajectory {
            self.block.clear();
            for row in record.trajectory_rows() {
                push_row(&mut self.block, record, &table.columns, row);
            }
            // The whole record in one piece.
            table.append(self.block.as_bytes())?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regress_nan_is_an_empty_cell_never_nan() {
        let mut line = String::from("0");
        push(&mut line, f64::NAN);
        push(&mut line, 1.5);
        push(&mut line, f64::INFINITY);
        push(&mut line, -f64::NAN);
        assert_eq!(line, "0,,1.5,inf,");
        assert!(!line.to_ascii_lowercase().contains("nan"));
    }
}
