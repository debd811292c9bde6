//! Campaigns: one scenario run many times, over seeds and over parameters varied by dotted key (value
//! lists as a grid, ranges sampled by Latin hypercube or at random), in parallel, with a manifest that
//! lets an interrupted or partly failed campaign resume, one Parquet table of every run's outcomes,
//! and per-point statistics. `satflock campaign` is the command; `docs/campaigns.md` the reference.
//!
//! | file | holds |
//! | --- | --- |
//! | `file.rs` | the campaign file: schema, validation of every key before any run, expansion into runs |
//! | `overrides.rs` | dotted keys (`law.k_f_kg_per_m_s2`, `threats.0.speed_mps`) set in a scenario's TOML |
//! | `sampling.rs` | grid products; Latin hypercube and random samples of ranges, linear or log |
//! | `pool.rs` | the bounded pool of whole runs, each on one thread (also used by `satflock validate`) |
//! | `manifest.rs` | `manifest.jsonl`: header and one record per finished run, read back to resume |
//! | `runner.rs` | the runner: output directory, runs in parallel, records, table and summary (also as separate steps, for other executors) |
//! | `table.rs` | `campaign.parquet`: one row per run |
//! | `summary.rs` | percentiles and `summary.md` |

pub mod file;
pub mod manifest;
pub mod overrides;
pub mod pool;
pub mod runner;
pub mod sampling;
pub mod summary;
pub mod table;

use thiserror::Error;

pub use file::{Campaign, Parameter, RunSpec, Values};
pub use manifest::{RunRecord, Status};
pub use runner::{run_campaign, CampaignReport, Prepared, RunEvent, RunnerOptions};

/// A campaign that cannot be read or run.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum CampaignError {
    /// The campaign file cannot be read.
    #[error("{file}: cannot read the file: {message}")]
    Io {
        /// The file.
        file: String,
        /// What the system said.
        message: String,
    },
    /// The campaign file is not valid TOML, has an unknown key, or a value of the wrong type.
    #[error("{file}: {message}")]
    Parse {
        /// The file.
        file: String,
        /// The parser's message, with line and column.
        message: String,
    },
    /// A key of the campaign file is invalid: out of range, not in the scenario, or refused by the
    /// scenario's validation.
    #[error("{file}: key `{key}`: {message}")]
    Invalid {
        /// The campaign file.
        file: String,
        /// The campaign key (`seeds`, `set.duration_s`, `vary.law.k_f_kg_per_m_s2` …).
        key: String,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// The output directory cannot hold this campaign (not empty, or a file).
    #[error("output directory `{path}`: {message}")]
    OutputDirectory {
        /// The directory.
        path: String,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// `--resume` cannot continue: the manifest is unreadable or belongs to another campaign file.
    #[error("{path}: {message}")]
    Resume {
        /// The manifest.
        path: String,
        /// Why.
        message: String,
    },
    /// An output file cannot be written.
    #[error("output `{path}`: {message}")]
    Output {
        /// The path.
        path: String,
        /// What the system said.
        message: String,
    },
    /// The run pool could not start.
    #[error(transparent)]
    Pool(#[from] pool::PoolError),
}

impl CampaignError {
    /// Whether the error is the user's input (the file, the output directory, a manifest to resume)
    /// rather than the system's.
    pub fn is_input(&self) -> bool {
        !matches!(self, CampaignError::Output { .. } | CampaignError::Pool(_))
    }
}
