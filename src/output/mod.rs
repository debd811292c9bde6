//! A run's outputs: the columns and row values of its tables, their streamed writers (CSV:
//! `metrics.csv`, `trajectory.csv`; Parquet: `metrics.parquet`, `trajectory.parquet`), the JSON run
//! summary (`summary.json`), the names of their frames and time system, the scene geometry
//! (`scene.json`), and the reader of a run directory.

pub mod columns;
pub mod csv_recorder;
pub mod frames;
pub mod parquet_recorder;
pub mod recorder;
pub mod run_data;
pub mod scene;
pub mod summary;

pub use columns::OutputColumns;
pub use csv_recorder::CsvRecorder;
pub use parquet_recorder::{ParquetRecorder, RunMetadata};
pub use recorder::{OutputFormat, RunRecorder, TableFormats};
pub use run_data::{RunData, RunDataError, Table};
pub use scene::Scene;
pub use summary::{DeltaVSummary, RunStatus, RunSummary};
