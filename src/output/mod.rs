//! A run's outputs: the streamed CSV recorder (`metrics.csv`, `trajectory.csv`), the JSON run summary
//! (`summary.json`), the names of their frames and time system, the scene geometry
//! (`scene.json`), the reader of a run directory, and the exports made from it: CCSDS OEM (`oem`) and
//! CZML (`czml`).

pub mod csv_recorder;
pub mod czml;
pub mod export;
pub mod frames;
pub mod oem;
pub mod run_data;
pub mod scene;
pub mod summary;

pub use csv_recorder::{CsvColumns, CsvRecorder};
pub use export::{ExportError, InertialTrack};
pub use run_data::{RunData, RunDataError, Table};
pub use scene::Scene;
pub use summary::{DeltaVSummary, RunStatus, RunSummary};
