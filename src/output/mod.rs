//! Writers of run outputs: the streamed CSV recorder (`metrics.csv`, `trajectory.csv`) and the JSON
//! run summary (`summary.json`).

pub mod csv_recorder;
pub mod summary;

pub use csv_recorder::{CsvColumns, CsvRecorder};
pub use summary::{DeltaVSummary, RunStatus, RunSummary};
