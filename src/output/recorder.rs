//! The recorder of a run: each table (`metrics`, `trajectory`) in its file format, CSV or Parquet, and
//! the choice of formats when the scenario and the command line name none.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::output::columns::{OutputColumns, Tables};
use crate::output::csv_recorder::CsvRecorder;
use crate::output::parquet_recorder::{ParquetRecorder, RunMetadata};
use crate::swarm::{Recorder, Snapshot};

/// The file format of a run's tables (`[output] format`, `satflock run --format`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum OutputFormat {
    /// `metrics.csv`, `trajectory.csv`: text, readable up to the last whole record even after SIGKILL.
    Csv,
    /// `metrics.parquet`, `trajectory.parquet`: typed columns with units and frames, compressed.
    Parquet,
}

/// Without a format given, a trajectory of more satellites than this is written as Parquet.
pub const CSV_TRAJECTORY_MAX_SATELLITES: usize = 1000;

/// The format of each table of a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TableFormats {
    /// Format of the metrics table.
    pub metrics: OutputFormat,
    /// Format of the trajectory table (`None`: not written).
    pub trajectory: Option<OutputFormat>,
}

impl TableFormats {
    /// The formats of a run: `format` for both tables if given; otherwise CSV for the metrics and for a
    /// trajectory of up to [`CSV_TRAJECTORY_MAX_SATELLITES`] satellites, Parquet above.
    pub fn choose(format: Option<OutputFormat>, satellites: usize, trajectory: bool) -> Self {
        let trajectory_format = format.unwrap_or(if satellites > CSV_TRAJECTORY_MAX_SATELLITES {
            OutputFormat::Parquet
        } else {
            OutputFormat::Csv
        });
        Self {
            metrics: format.unwrap_or(OutputFormat::Csv),
            trajectory: trajectory.then_some(trajectory_format),
        }
    }

    /// The tables written in `format`.
    fn tables(&self, format: OutputFormat) -> Tables {
        Tables {
            metrics: self.metrics == format,
            trajectory: self.trajectory == Some(format),
        }
    }
}

/// Streams a run's tables, each in its format. [`Self::finish`] closes the files.
pub struct RunRecorder {
    csv: Option<CsvRecorder>,
    parquet: Option<ParquetRecorder>,
}

impl RunRecorder {
    /// Creates the table files in `dir` in the `formats`, with the variable `columns`.
    pub fn create(
        dir: &Path,
        formats: TableFormats,
        columns: OutputColumns,
        run: &RunMetadata,
    ) -> std::io::Result<Self> {
        let wanted = |t: Tables| (t.metrics || t.trajectory).then_some(t);
        let csv = wanted(formats.tables(OutputFormat::Csv))
            .map(|t| CsvRecorder::create(dir, t, columns.clone(), run.epoch))
            .transpose()?;
        let parquet = wanted(formats.tables(OutputFormat::Parquet))
            .map(|t| ParquetRecorder::create(dir, t, columns, run))
            .transpose()?;
        Ok(Self { csv, parquet })
    }

    /// Closes the files (the Parquet footers are written here). A Parquet table that cannot be closed
    /// into a readable file (its write failed: a full disk) is removed, and the error says so.
    pub fn finish(self) -> std::io::Result<()> {
        self.parquet.map_or(Ok(()), ParquetRecorder::finish)
    }
}

impl Recorder for RunRecorder {
    fn record(&mut self, snapshot: &Snapshot<'_>) -> std::io::Result<()> {
        if let Some(csv) = &mut self.csv {
            csv.record(snapshot)?;
        }
        if let Some(parquet) = &mut self.parquet {
            parquet.record(snapshot)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_formats_switch_the_trajectory_to_parquet_above_1000_satellites() {
        use OutputFormat::{Csv, Parquet};
        let f = TableFormats::choose(None, 1000, true);
        assert_eq!((f.metrics, f.trajectory), (Csv, Some(Csv)));
        let f = TableFormats::choose(None, 1001, true);
        assert_eq!((f.metrics, f.trajectory), (Csv, Some(Parquet)));
        let f = TableFormats::choose(Some(Csv), 10_000, true);
        assert_eq!((f.metrics, f.trajectory), (Csv, Some(Csv)));
        let f = TableFormats::choose(Some(Parquet), 3, false);
        assert_eq!((f.metrics, f.trajectory), (Parquet, None));
        assert_eq!(
            f.tables(Parquet),
            Tables {
                metrics: true,
                trajectory: false
            }
        );
    }
}
