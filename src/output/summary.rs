//! The run summary written to `summary.json`: what ran, how fast, and the swarm-level results.

use std::collections::BTreeMap;

use serde::Serialize;

use crate::conjunction::{Encounter, Secondary};
use crate::environment::{Approach, ApproachMonitor, Clearance, PairMinimum};
use crate::metrics::FiveElements;
use crate::swarm::StageTimings;

/// How the run ended.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum RunStatus {
    /// Reached the end of the scenario.
    Completed,
    /// Stopped early; `error` says why.
    Failed,
    /// Stopped by a signal (SIGINT, SIGTERM) after a whole segment; every file is valid up to
    /// `simulated_s`.
    Interrupted,
    /// Ended early by a `stop-run` event (`stopped_by` names it); every file is valid up to
    /// `simulated_s`.
    Stopped,
}

/// The `stop-run` event that ended a run.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StoppedBy {
    /// The event's index in the scenario's `[[events]]`.
    pub event: usize,
    /// Its key (`events[K]`, or `controller events[K]` for a controller file's).
    pub key: String,
    /// When it fired \[s\].
    pub time_s: f64,
    /// What triggered it: `time_s`, or the condition's key.
    pub trigger: String,
    /// The condition's value when it fired (absent for a timed event).
    pub value: Option<f64>,
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

/// The conjunctions of a run (the `conjunctions` object): the threshold, how many encounters, the
/// closest, and each satellite's count.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ConjunctionSummary {
    /// Miss-distance threshold \[m\].
    pub threshold_m: f64,
    /// Encounters found (rows of `conjunctions.csv` / `.parquet`).
    pub count: usize,
    /// The encounter with the smallest miss distance (the earliest among ties); `None` without any.
    pub closest: Option<Encounter>,
    /// Encounters per satellite id, as primary or as secondary (only the satellites with one or
    /// more; keys are the ids as text).
    pub per_satellite: BTreeMap<String, u64>,
    /// The satellites' navigation noise, one sigma per Hill axis \[m\] (0 without noise): the
    /// diagonal covariance the CDM export states for a satellite.
    pub position_sigma_m: f64,
    /// The same for the velocity \[m/s\].
    pub velocity_sigma_mps: f64,
}

impl ConjunctionSummary {
    /// The summary of `encounters` found below `threshold_m` \[m\], in a run whose navigation noise
    /// has the sigmas `position_sigma_m` \[m\] and `velocity_sigma_mps` \[m/s\].
    pub fn new(
        threshold_m: f64,
        encounters: &[Encounter],
        position_sigma_m: f64,
        velocity_sigma_mps: f64,
    ) -> Self {
        let mut counts: BTreeMap<usize, u64> = BTreeMap::new();
        for e in encounters {
            *counts.entry(e.primary).or_default() += 1;
            if let Secondary::Satellite(k) = e.secondary {
                *counts.entry(k).or_default() += 1;
            }
        }
        let closest = encounters.iter().copied().reduce(|best, e| {
            let earlier = (e.miss_distance_m, e.tca_s) < (best.miss_distance_m, best.tca_s);
            if earlier {
                e
            } else {
                best
            }
        });
        Self {
            threshold_m,
            count: encounters.len(),
            closest,
            per_satellite: counts
                .into_iter()
                .map(|(id, n)| (id.to_string(), n))
                .collect(),
            position_sigma_m,
            velocity_sigma_mps,
        }
    }
}

/// The frames of the outputs, by name and in one sentence each (the `frames` object).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Frames {
    /// The inertial frame's CCSDS name (`EME2000`).
    pub inertial: String,
    /// What the inertial frame is and what its approximation costs.
    pub inertial_description: String,
    /// What the LVLH columns are.
    pub lvlh: String,
}

impl Default for Frames {
    fn default() -> Self {
        Self {
            inertial: super::frames::INERTIAL_FRAME.into(),
            inertial_description: super::frames::INERTIAL_FRAME_DESCRIPTION.into(),
            lvlh: super::frames::LVLH_FRAME_DESCRIPTION.into(),
        }
    }
}

/// Final five elements (the `final` object).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FinalState {
    /// Five-element characterisation at the end (absent with fewer than two live satellites).
    pub five_elements: Option<FiveElements>,
}

/// Drag as an actuator over a run (satellites with drag attitudes).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DragSummary {
    /// Changes of each satellite's drag area, by id.
    pub switches_per_satellite: Vec<u64>,
    /// Their sum.
    pub switches_total: u64,
    /// Each satellite's drag Δv, ∫‖a_drag‖dt \[m/s\], by id (left-point sum at the control ticks;
    /// not propellant: `delta_v_mps` counts thrust only).
    pub delta_v_per_satellite_mps: Vec<f64>,
    /// The live satellites' mean altitude above the equatorial radius averaged over the first orbit
    /// of the run \[m\] (absent for a run shorter than an orbit).
    pub mean_altitude_first_orbit_m: Option<f64>,
    /// The same over the last orbit of the run \[m\].
    pub mean_altitude_last_orbit_m: Option<f64>,
    /// First minus last: the mean decay over the run \[m\].
    pub mean_altitude_decay_m: Option<f64>,
}

/// The content of `summary.json`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RunSummary {
    /// Scenario name.
    pub scenario: String,
    /// Where the scenario came from (path or `builtin:NAME`).
    pub source: String,
    /// Where the controller came from when `--law` replaced the scenario's own (path or
    /// `builtin:NAME`), or the caller's law that replaced the scenario's law (`python:NAME`, see
    /// [`crate::scenario::Prepared::replace_law`]); absent otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub controller: Option<String>,
    /// Seed of every random draw.
    pub seed: u64,
    /// The instant of t = 0, ISO 8601 in [`Self::time_system`]; every output time is this plus `t_s`
    /// elapsed SI seconds.
    pub epoch_utc: String,
    /// The time system of absolute times in the text outputs (`UTC`).
    pub time_system: String,
    /// TAI − UTC at the epoch \[s\] (leap seconds, from hifitime).
    pub tai_minus_utc_s: f64,
    /// TT − UTC at the epoch \[s\].
    pub tt_minus_utc_s: f64,
    /// What the frames of the outputs are.
    pub frames: Frames,
    /// How the run ended.
    pub status: RunStatus,
    /// The error that stopped the run, if any.
    pub error: Option<String>,
    /// The `stop-run` event that ended the run (status `stopped`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stopped_by: Option<StoppedBy>,
    /// Every event firing, in firing order (as in `events.jsonl`).
    pub events: Vec<crate::swarm::Firing>,
    /// What the user should know about although the run completed, one sentence each: first what was
    /// found when the scenario was loaded (e.g. a `pigeon` law's initial link graph that is not
    /// connected, [`crate::scenario::Prepared::warnings`]), then what the run did (collisions, a
    /// delta-v budget exceeded); the same sentences go to stderr.
    pub warnings: Vec<String>,
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
    /// Wall-clock time per stage of the engine \[s\] (measures the machine, like `wall_time_s`) and
    /// the propagation path taken.
    pub timing: StageTimings,
    /// The truth dynamics: the model's name and, for inertial truth, the force models summed (in
    /// ECI = EME2000, instants in TT) and the ephemerides they read.
    pub dynamics: DynamicsSummary,
    /// Delta-v statistics (thrust only).
    pub delta_v_mps: DeltaVSummary,
    /// Drag as an actuator, when the satellites have drag attitudes (absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub drag: Option<DragSummary>,
    /// Smallest separation between two live satellites seen at any step \[m\].
    pub min_separation_m: f64,
    /// Largest number of simultaneous collisions (pairs closer than the sum of radii) at any step.
    pub collisions: usize,
    /// Final swarm state.
    #[serde(rename = "final")]
    pub final_state: FinalState,
    /// Threat approach and obstacle clearance over the whole run (present when the scenario has threats
    /// or obstacles).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub environment: Option<EnvironmentSummary>,
    /// The conjunctions (`[conjunctions]`; absent without the section).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub conjunctions: Option<ConjunctionSummary>,
    /// The law-specific results, by key.
    pub law: BTreeMap<String, serde_json::Value>,
    /// Scenario tags and run metadata (crate version, platform).
    pub metadata: BTreeMap<String, String>,
}

/// What `summary.json` says of the truth dynamics.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DynamicsSummary {
    /// The model (`j2`, `two-body`, `forces`, `hcw`, `j2-linear`, `kinematic`).
    pub model: String,
    /// The force set of inertial truth (absent for the relative and kinematic models).
    pub forces: Option<crate::dynamics::ForceSetSummary>,
}

/// The continuous threat and obstacle monitors over a run (truth states, Hill frame; satellites as points).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EnvironmentSummary {
    /// Threat names, in scenario order.
    pub threats: Vec<String>,
    /// Obstacle names, in scenario order.
    pub obstacles: Vec<String>,
    /// The swarm's closest approach to any threat: satellite, threat, time \[s\] and distance \[m\].
    pub closest_threat_approach: Option<PairMinimum<Approach>>,
    /// Per satellite: its smallest distance to any threat \[m\] (null: no threat, or removed before any).
    pub min_threat_distance_per_satellite_m: Vec<Option<f64>>,
    /// Entries of satellites into threat danger spheres.
    pub threat_incursions: u64,
    /// The swarm's smallest clearance to an obstacle's surface: satellite, obstacle, time \[s\] and
    /// clearance \[m\] (negative: inside).
    pub min_obstacle_clearance: Option<PairMinimum<Clearance>>,
    /// Per satellite: its smallest clearance to any obstacle's surface \[m\].
    pub min_obstacle_clearance_per_satellite_m: Vec<Option<f64>>,
    /// Entries of satellites into obstacles.
    pub obstacle_incursions: u64,
}

impl EnvironmentSummary {
    /// The summary of a run's monitor, with the objects' names.
    pub fn new(monitor: &ApproachMonitor, threats: Vec<String>, obstacles: Vec<String>) -> Self {
        let n = monitor.satellite_count();
        Self {
            threats,
            obstacles,
            closest_threat_approach: monitor.swarm_threat_minimum(),
            min_threat_distance_per_satellite_m: (0..n)
                .map(|i| {
                    monitor
                        .satellite_threat_minimum(i)
                        .map(|m| m.minimum.distance_m)
                })
                .collect(),
            threat_incursions: monitor.total_threat_incursions(),
            min_obstacle_clearance: monitor.swarm_obstacle_minimum(),
            min_obstacle_clearance_per_satellite_m: (0..n)
                .map(|i| {
                    monitor
                        .satellite_obstacle_minimum(i)
                        .map(|m| m.minimum.clearance_m)
                })
                .collect(),
            obstacle_incursions: monitor.total_obstacle_incursions(),
        }
    }
}
