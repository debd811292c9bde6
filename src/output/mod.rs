//! A run's outputs: the columns and row values of its tables, their streamed writers (CSV:
//! `metrics.csv`, `trajectory.csv`; Parquet: `metrics.parquet`, `trajectory.parquet`), the JSON run
//! summary (`summary.json`), the log of event firings (`events.jsonl`), the names of their frames and time system, the scene geometry
//! (`scene.json`), the reader of a run directory, and the exports made from it: CCSDS OEM (`oem`) and
//! CZML (`czml`).

pub mod cdm;
pub mod columns;
pub mod conjunctions;
pub mod csv_recorder;
pub mod czml;
pub mod events_log;
pub mod export;
pub mod frames;
pub mod oem;
pub mod outcomes;
pub mod parquet_recorder;
pub mod recorder;
pub mod run_data;
pub mod scene;
pub mod spread;
pub mod summary;

pub use columns::OutputColumns;
pub use csv_recorder::CsvRecorder;
pub use events_log::EventLog;
pub use export::{ExportError, InertialTrack};
pub use outcomes::{scalar_outcomes, RunTable};
pub use parquet_recorder::{ParquetRecorder, RunMetadata};
pub use recorder::{OutputFormat, RunRecorder, TableFormats};
pub use run_data::{RunData, RunDataError, Table};
pub use scene::Scene;
pub use spread::Spread;
pub use summary::{DeltaVSummary, DynamicsSummary, RunStatus, RunSummary, StoppedBy};
