//! The run summary written to `summary.json`: what ran, how fast, and the swarm-level results.

use std::collections::BTreeMap;

use serde::Serialize;

use crate::metrics::FiveElements;

/// How the run ended.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum RunStatus {
    /// Reached the end of the scenario.
    Completed,
    /// Stopped early; `error` says why.
    Failed,
}

/// Delta-v statistics over the live satellites \[m/s\].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DeltaVSummary {
    /// ∫‖a‖dt of every satellite, by index (removed satellites included, frozen at removal) \[m/s\].
    pub per_satellite: Vec<f64>,
    /// Largest \[m/s\].
    pub max: f64,
    /// Mean \[m/s\].
    pub mean: f64,
    /// Mean ∫|a_k|dt per Hill axis (x radial, y along-track, z normal) \[m/s\].
    pub mean_per_axis_hill: [f64; 3],
}

/// Final five elements (the `final` object).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FinalState {
    /// Five-element characterisation at the end (absent with fewer than two live satellites).
    pub five_elements: Option<FiveElements>,
}

/// The content of `summary.json`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RunSummary {
    /// Scenario name.
    pub scenario: String,
    /// Where the scenario came from (path or `builtin:NAME`).
    pub source: String,
    /// Seed of every random draw.
    pub seed: u64,
    /// How the run ended.
    pub status: RunStatus,
    /// The error that stopped the run, if any.
    pub error: Option<String>,
    /// Number of satellites at the start.
    pub n_satellites: usize,
    /// Scenario duration \[s\].
    pub duration_s: f64,
    /// Simulated time reached \[s\].
    pub simulated_s: f64,
    /// Wall-clock time of the run \[s\].
    pub wall_time_s: f64,
    /// Satellite-steps per wall-clock second.
    pub satellite_steps_per_s: f64,
    /// Threads used.
    pub threads: usize,
    /// Delta-v statistics.
    pub delta_v_mps: DeltaVSummary,
    /// Smallest separation between two live satellites seen at any step \[m\].
    pub min_separation_m: f64,
    /// Largest number of simultaneous collisions (pairs closer than the sum of radii) at any step.
    pub collisions: usize,
    /// Final swarm state.
    #[serde(rename = "final")]
    pub final_state: FinalState,
    /// The law-specific results, by key.
    pub law: BTreeMap<String, serde_json::Value>,
    /// Scenario tags and run metadata (crate version, platform).
    pub metadata: BTreeMap<String, String>,
}
