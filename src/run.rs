//! Running a scenario end to end: validate it, build the simulation, stream the recordings to files, and
//! write `summary.json` — also when the run stops early, so every file in the output directory stays valid.

use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

use thiserror::Error;

use crate::output::summary::{EnvironmentSummary, FinalState};
use crate::output::{CsvColumns, CsvRecorder, DeltaVSummary, RunStatus, RunSummary};
use crate::scenario::{Scenario, ScenarioError};
use crate::swarm::{SimError, Simulation};

/// Why a run could not start or did not finish.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum RunError {
    /// The scenario is invalid.
    #[error(transparent)]
    Scenario(#[from] ScenarioError),
    /// The simulation could not be built or stopped early (the summary says so too).
    #[error(transparent)]
    Simulation(#[from] SimError),
    /// The output directory or a file in it cannot be written.
    #[error("output `{path}`: {message}")]
    Output {
        /// The path.
        path: String,
        /// What the system said.
        message: String,
    },
}

/// Builds the simulation of a scenario in one call (validated; nothing written): the embedding entry
/// point for tools that drive the run themselves with [`Simulation::advance_to`].
pub fn build_simulation(scenario: &Scenario) -> Result<Simulation, RunError> {
    let prepared = scenario.prepare()?;
    Ok(Simulation::new(
        prepared.config,
        &prepared.satellites,
        prepared.law,
        prepared.events,
    )?)
}

/// Runs a scenario, writing `metrics.csv`, `trajectory.csv` (unless the scenario turns it off) and
/// `summary.json` into `out_dir` (created if needed). `progress` receives the simulated time \[s\].
/// Returns the summary; on a simulation failure the summary is written with status `failed` and the
/// error is returned.
pub fn run_scenario(
    scenario: &Scenario,
    out_dir: &Path,
    progress: &mut dyn FnMut(f64),
) -> Result<RunSummary, RunError> {
    let prepared = scenario.prepare()?;
    let output_error = |path: &Path, e: std::io::Error| RunError::Output {
        path: path.display().to_string(),
        message: e.to_string(),
    };
    let n = prepared.satellites.len();
    let duration_s = prepared.config.duration_s;
    let seed = prepared.config.seed;
    let mut metadata: BTreeMap<String, String> = prepared.tags.clone();
    metadata.insert("satflock_version".into(), env!("CARGO_PKG_VERSION").into());
    metadata.insert(
        "platform".into(),
        format!("{}-{}", std::env::consts::ARCH, std::env::consts::OS),
    );
    let mut simulation = Simulation::new(
        prepared.config,
        &prepared.satellites,
        prepared.law,
        prepared.events,
    )?;
    // The output directory is created only once the run can start.
    std::fs::create_dir_all(out_dir).map_err(|e| output_error(out_dir, e))?;
    let columns = CsvColumns {
        threats: !simulation.config().threats.is_empty(),
        obstacles: !simulation.config().obstacles.is_empty(),
        law_metrics: simulation.law_metric_names(),
        law_outputs: simulation.law_output_names(),
    };
    let mut recorder = CsvRecorder::create(out_dir, prepared.write_trajectory, columns)
        .map_err(|e| output_error(out_dir, e))?;
    let started = Instant::now();
    let outcome = simulation.run(&mut recorder, progress);
    let wall_time_s = started.elapsed().as_secs_f64();
    drop(recorder);

    let law_results = simulation.law_results();
    let totals = simulation.totals().clone();
    let ledger: Vec<([f64; 3], f64)> = (0..n).map(|i| simulation.state().ledger(i)).collect();
    let live: Vec<usize> = (0..n).filter(|&i| simulation.active()[i]).collect();
    let count = live.len().max(1) as f64;
    let mut mean_axes = [0.0; 3];
    for &i in &live {
        for (k, m) in mean_axes.iter_mut().enumerate() {
            *m += ledger[i].0[k] / count;
        }
    }
    let summary = RunSummary {
        scenario: prepared.name,
        source: scenario.source.clone(),
        seed,
        status: if outcome.is_ok() {
            RunStatus::Completed
        } else {
            RunStatus::Failed
        },
        error: outcome.as_ref().err().map(|e| e.to_string()),
        n_satellites: n,
        duration_s,
        simulated_s: simulation.time_s(),
        wall_time_s,
        satellite_steps_per_s: totals.satellite_steps as f64 / wall_time_s.max(1e-9),
        threads: rayon::current_num_threads(),
        delta_v_mps: DeltaVSummary {
            per_satellite: ledger.iter().map(|l| l.1).collect(),
            max: live.iter().map(|&i| ledger[i].1).fold(0.0, f64::max),
            mean: live.iter().map(|&i| ledger[i].1).sum::<f64>() / count,
            mean_per_axis_hill: mean_axes,
        },
        min_separation_m: totals.min_separation_m,
        collisions: totals.max_collisions,
        final_state: FinalState {
            five_elements: totals.final_five_elements,
        },
        environment: {
            let config = simulation.config();
            (!(config.threats.is_empty() && config.obstacles.is_empty())).then(|| {
                EnvironmentSummary::new(
                    simulation.approach_monitor(),
                    config
                        .threats
                        .iter()
                        .map(|t| t.name().to_string())
                        .collect(),
                    config
                        .obstacles
                        .iter()
                        .map(|o| o.name().to_string())
                        .collect(),
                )
            })
        },
        law: law_results,
        metadata,
    };
    let path = out_dir.join("summary.json");
    let text = serde_json::to_string_pretty(&summary).expect("the summary serialises");
    std::fs::write(&path, text + "\n").map_err(|e| output_error(&path, e))?;
    outcome?;
    Ok(summary)
}
