//! A [`Recorder`] that streams snapshots to `metrics.parquet` and `trajectory.parquet` (or one of them):
//! the same columns, names and values as the CSV files ([`crate::output::columns`]), typed.
//!
//! Types: `t_s` and the measured values are `Float64` (null where the CSV cell is empty: a value that
//! does not exist), counts (`n`, `collisions`, `id`, `*_incursions`) are `UInt64`, and `time_utc` is
//! `Utf8`, the CSV's ISO 8601 text: an Arrow timestamp counts Unix seconds, which have no 23:59:60, so a
//! run across a leap second could not be stated exactly; `t_s` is the numeric time.
//!
//! Metadata: every column (Arrow field metadata) has `unit` (`m`, `m/s`, `s`, `deg`, `h`; `1` for counts
//! and dimensionless numbers; `UTC` for `time_utc`) and, for vector components, `frame`
//! ([`crate::output::frames::LVLH_FRAME`] or [`crate::output::frames::INERTIAL_FRAME`]); the file's
//! key-value metadata and the Arrow schema's metadata have `scenario`, `seed`, `epoch_utc` and
//! `satflock_version`.
//!
//! Streaming: rows are handed to the Parquet writer as they are recorded (a record of many satellites
//! in pieces of at most [`ROW_GROUP_ROWS`] rows) and it writes a row group every [`ROW_GROUP_ROWS`]
//! rows, so memory stays bounded whatever the run's length. The footer that makes a Parquet file
//! readable is written by [`ParquetRecorder::finish`], which a run calls when it ends, also when it was
//! interrupted (SIGINT, SIGTERM) or diverged. A process killed outright (SIGKILL, power loss) leaves no
//! footer and an unreadable file: CSV is the format that survives that. A write that fails (a full disk,
//! a file-size limit) leaves a file with no valid footer possible: [`ParquetRecorder::finish`] then
//! removes it (and any file whose footer cannot be written) and says so, and closes the other table.

use std::collections::HashMap;
use std::fs::File;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use arrow_array::{ArrayRef, Float64Array, RecordBatch, StringArray, UInt64Array};
use arrow_schema::{DataType, Field, Schema, SchemaRef};
use parquet::arrow::ArrowWriter;
use parquet::basic::Compression;
use parquet::file::metadata::KeyValue;
use parquet::file::properties::WriterProperties;

use crate::output::columns::{Column, ColumnKind, OutputColumns, Record, Tables};
use crate::swarm::{Recorder, Snapshot};
use crate::time::{self, Epoch};

/// Rows per row group (about 64 k: a few megabytes of a trajectory's columns in memory at most).
pub const ROW_GROUP_ROWS: usize = 1 << 16;

/// What a Parquet file states about its run (file key-value metadata).
#[derive(Clone, Debug)]
pub struct RunMetadata {
    /// The scenario's name.
    pub scenario: String,
    /// Its random seed.
    pub seed: u64,
    /// The instant of t = 0.
    pub epoch: Epoch,
}

/// One Parquet file being written.
struct ParquetTable {
    path: PathBuf,
    writer: ArrowWriter<File>,
    schema: SchemaRef,
    columns: Vec<Column>,
    /// A write failed: the file cannot be closed into a valid Parquet file.
    failed: bool,
}

/// An error of the Parquet or Arrow writer as an I/O error naming the file.
fn io_error(path: &Path, e: impl std::fmt::Display) -> std::io::Error {
    std::io::Error::other(format!("{}: {e}", path.display()))
}

/// The Arrow field of a column: its type, whether it can be null, and its `unit` and `frame`.
fn field(column: &Column) -> Field {
    let (data_type, nullable) = match column.kind {
        ColumnKind::Text => (DataType::Utf8, false),
        ColumnKind::Count => (DataType::UInt64, false),
        ColumnKind::Float => (DataType::Float64, column.name != "t_s"),
    };
    let mut metadata = HashMap::from([("unit".to_string(), column.unit().to_string())]);
    if let Some(frame) = column.frame() {
        metadata.insert("frame".into(), frame.into());
    }
    Field::new(column.name, data_type, nullable).with_metadata(metadata)
}

impl ParquetTable {
    fn create(path: PathBuf, columns: Vec<Column>, run: &RunMetadata) -> std::io::Result<Self> {
        let run_keys = HashMap::from([
            ("scenario".to_string(), run.scenario.clone()),
            ("seed".to_string(), run.seed.to_string()),
            ("epoch_utc".to_string(), time::utc_iso(run.epoch)),
            (
                "satflock_version".to_string(),
                env!("CARGO_PKG_VERSION").to_string(),
            ),
        ]);
        let mut key_values: Vec<KeyValue> = run_keys
            .iter()
            .map(|(k, v)| KeyValue::new(k.clone(), v.clone()))
            .collect();
        key_values.sort_by(|a, b| a.key.cmp(&b.key));
        // In the file's key-value metadata (any Parquet reader) and in the Arrow schema's (the schema
        // of a table read by pyarrow, polars or arrow-rs).
        let schema = Arc::new(Schema::new_with_metadata(
            columns.iter().map(field).collect::<Vec<_>>(),
            run_keys,
        ));
        let properties = WriterProperties::builder()
            .set_compression(Compression::SNAPPY)
            .set_max_row_group_row_count(Some(ROW_GROUP_ROWS))
            .set_key_value_metadata(Some(key_values))
            .build();
        let file = File::create(&path)?;
        let writer = ArrowWriter::try_new(file, schema.clone(), Some(properties))
            .map_err(|e| io_error(&path, e))?;
        Ok(Self {
            path,
            writer,
            schema,
            columns,
            failed: false,
        })
    }

    /// Writes rows of one record: `values` holds whole rows of the columns after `t_s` and `time_utc`.
    fn write(&mut self, record: &Record, values: &[f64]) -> std::io::Result<()> {
        let width = self.columns.len() - 2;
        for piece in values.chunks(ROW_GROUP_ROWS * width) {
            let rows = piece.len() / width;
            let mut arrays: Vec<ArrayRef> = Vec::with_capacity(self.columns.len());
            arrays.push(Arc::new(Float64Array::from(vec![record.time_s; rows])));
            arrays.push(Arc::new(StringArray::from_iter_values(
                std::iter::repeat_n(&record.time_utc, rows),
            )));
            for (c, column) in self.columns[2..].iter().enumerate() {
                let cells = piece.iter().skip(c).step_by(width).copied();
                arrays.push(match column.kind {
                    ColumnKind::Count => {
                        Arc::new(UInt64Array::from_iter_values(cells.map(|v| v as u64)))
                    }
                    ColumnKind::Float | ColumnKind::Text => Arc::new(Float64Array::from_iter(
                        cells.map(|v| (!v.is_nan()).then_some(v)),
                    )),
                });
            }
            let batch = RecordBatch::try_new(self.schema.clone(), arrays)
                .map_err(|e| io_error(&self.path, e))?;
            if let Err(e) = self.writer.write(&batch) {
                self.failed = true;
                return Err(io_error(&self.path, e));
            }
        }
        Ok(())
    }

    /// Writes the last row group and the footer. A table whose write failed, or whose footer cannot be
    /// written, is removed (it could not be read) and the error says so.
    fn finish(self) -> std::io::Result<()> {
        let closed = if self.failed {
            Err(io_error(&self.path, "a write failed"))
        } else {
            self.writer
                .close()
                .map(|_| ())
                .map_err(|e| io_error(&self.path, e))
        };
        closed.map_err(|e| {
            let removed = match std::fs::remove_file(&self.path) {
                Ok(()) => "the file was removed (a Parquet file without its footer cannot be read)"
                    .to_string(),
                Err(r) => format!("the unreadable file could not be removed: {r}"),
            };
            std::io::Error::new(e.kind(), format!("{e}; {removed}"))
        })
    }
}

/// Streams snapshots to Parquet files in a directory.
pub struct ParquetRecorder {
    metrics: Option<ParquetTable>,
    trajectory: Option<ParquetTable>,
    columns: OutputColumns,
    epoch: Epoch,
    record: Record,
}

impl ParquetRecorder {
    /// Creates `dir/metrics.parquet` and `dir/trajectory.parquet` (those of `tables`) with the variable
    /// `columns`; `run` names the run in the files' metadata.
    pub fn create(
        dir: &Path,
        tables: Tables,
        columns: OutputColumns,
        run: &RunMetadata,
    ) -> std::io::Result<Self> {
        let metrics = tables
            .metrics
            .then(|| ParquetTable::create(dir.join("metrics.parquet"), columns.metrics(), run))
            .transpose()?;
        let trajectory = tables
            .trajectory
            .then(|| {
                ParquetTable::create(dir.join("trajectory.parquet"), columns.trajectory(), run)
            })
            .transpose()?;
        Ok(Self {
            metrics,
            trajectory,
            columns,
            epoch: run.epoch,
            record: Record::default(),
        })
    }

    /// Writes the last row groups and the footers. A run calls it when it ends, however it ends;
    /// without it the files cannot be read. A table that cannot be closed into a readable file is
    /// removed; the error names each such file.
    pub fn finish(self) -> std::io::Result<()> {
        let metrics = self.metrics.map_or(Ok(()), ParquetTable::finish);
        let trajectory = self.trajectory.map_or(Ok(()), ParquetTable::finish);
        match (metrics, trajectory) {
            (Err(m), Err(t)) => Err(std::io::Error::new(m.kind(), format!("{m}; {t}"))),
            (m, t) => m.and(t),
        }
    }
}

impl Recorder for ParquetRecorder {
    fn record(&mut self, s: &Snapshot<'_>) -> std::io::Result<()> {
        let record = &mut self.record;
        record.fill(&self.columns, self.epoch, s, self.trajectory.is_some());
        if let Some(table) = &mut self.metrics {
            table.write(record, &record.metrics)?;
        }
        if let Some(table) = &mut self.trajectory {
            table.write(record, &record.trajectory)?;
        }
        Ok(())
    }
}
