//! A run's outputs: the streamed CSV recorder (`metrics.csv`, `trajectory.csv`), the JSON run summary
//! (`summary.json`), the names of their frames and time system, the scene geometry
//! (`scene.json`), and the reader of a run directory.

pub mod csv_recorder;
pub mod frames;
pub mod run_data;
pub mod scene;
pub mod summary;

pub use csv_recorder::{CsvColumns, CsvRecorder};
pub use run_data::{RunData, RunDataError, Table};
pub use scene::Scene;
pub use summary::{DeltaVSummary, RunStatus, RunSummary};
