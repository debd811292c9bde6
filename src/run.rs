//! Running a scenario end to end: validate it, build the simulation, stream the recordings to files, and
//! write `summary.json` — also when the run stops early, so every file in the output directory stays valid.

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::Instant;

use thiserror::Error;

use crate::output::oem::{self, OemLayout};
use crate::output::summary::{DynamicsSummary, EnvironmentSummary, FinalState, Frames};
use crate::output::{cdm, conjunctions, czml, frames, EventLog, ExportError, RunData, StoppedBy};
use crate::output::{
    DeltaVSummary, OutputColumns, OutputFormat, RunMetadata, RunRecorder, RunStatus, RunSummary,
    Scene, TableFormats,
};
use crate::scenario::{Prepared, Scenario, ScenarioError};
use crate::swarm::{Firing, Recorder, SimError, Simulation, Snapshot};

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
    /// The output directory cannot be used: it is not a directory, or it holds files that are not a
    /// previous satflock run's (the user's input: nothing was written or removed).
    #[error("output directory `{path}`: {message}")]
    OutputDirectory {
        /// The path.
        path: String,
        /// What is wrong and what is allowed.
        message: String,
    },
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
    build_prepared(scenario, scenario.prepare()?)
}

/// [`build_simulation`] from a scenario already prepared, e.g. with a caller's law
/// ([`crate::scenario::Prepared::replace_law`]). The simulation records the control history when the
/// scenario asks for it (`[output] control_history`).
pub fn build_prepared(scenario: &Scenario, prepared: Prepared) -> Result<Simulation, RunError> {
    let threshold_m = prepared.conjunction_threshold_m;
    let mut simulation = Simulation::from_owned(
        prepared.config,
        prepared.satellites,
        prepared.law,
        prepared.events,
    )
    .map_err(|e| setup_error(scenario, e))?;
    configure(scenario, &mut simulation, threshold_m)?;
    Ok(simulation)
}

/// What a simulation takes from the scenario beyond its configuration: the control history
/// (`[output] control_history`) and the conjunction monitor (`[conjunctions] threshold_m`, validated).
fn configure(
    scenario: &Scenario,
    simulation: &mut Simulation,
    conjunction_threshold_m: Option<f64>,
) -> Result<(), RunError> {
    simulation.set_control_history(scenario.file.output.control_history);
    simulation
        .set_conjunction_threshold_m(conjunction_threshold_m)
        .map_err(|e| {
            RunError::Scenario(ScenarioError::invalid(
                &scenario.sources(),
                crate::invalid::Invalid::keys("conjunctions.threshold_m", e.to_string(), ""),
            ))
        })
}

/// A refusal of the engine's setup (after validation) is the scenario's fault: it becomes a
/// [`ScenarioError::Invalid`] naming the file and the key, like the validation's own errors.
fn setup_error(scenario: &Scenario, e: SimError) -> RunError {
    let key = match &e {
        SimError::Law(_) => "law",
        SimError::NoSatellites => "satellites.count",
        SimError::SensingRange { .. } => "sensing.range_m",
        SimError::OriginMember { .. } => "reference.origin_member",
        SimError::EventOutsideRun { .. }
        | SimError::EventTarget { .. }
        | SimError::EventCondition { .. } => "events",
        SimError::ControlPeriodTooLong { .. } => "control.period_s",
        SimError::StepTooLong { .. } | SimError::AdaptiveStepTooLong { .. } => "dynamics.step_s",
        SimError::CommandKindMismatch { .. } => "dynamics.model",
        SimError::ProcessNoise { .. } => "dynamics",
        _ => return RunError::Simulation(e),
    };
    RunError::Scenario(ScenarioError::invalid(
        &scenario.sources(),
        crate::invalid::Invalid::keys(key, e.to_string(), ""),
    ))
}

/// The files a run writes into its output directory, and those written there later (`swarm.oem`,
/// `swarm.czml` by the exports, `report.html` by the CLI's `satflock report`). A directory holding only
/// these and the folder [`oem::RUN_DIR_NAME`] of per-satellite OEM files (or nothing) is a previous
/// run's, which [`run_scenario`] clears before it starts.
pub const RUN_FILES: &[&str] = &[
    "summary.json",
    "metrics.csv",
    "trajectory.csv",
    "metrics.parquet",
    "trajectory.parquet",
    "scene.json",
    "conjunctions.csv",
    "conjunctions.parquet",
    "scenario.toml",
    crate::output::events_log::RUN_FILE,
    "report.html",
    oem::RUN_FILE,
    czml::RUN_FILE,
];

/// The sub-directories a previous run may hold, each with the file extensions allowed in it: `plots`
/// (the figures `satflock run` and `satflock plot` draw) and [`oem::RUN_DIR_NAME`] (per-satellite OEM
/// files of `satflock export oem --per-satellite`). [`prepare_output_dir`] removes them with the
/// [`RUN_FILES`].
pub const RUN_DIRS: &[(&str, &[&str])] = &[
    ("plots", &["png", "svg"]),
    (oem::RUN_DIR_NAME, &["oem"]),
    (cdm::RUN_DIR_NAME, &["cdm"]),
];

/// How a run is driven beyond its scenario.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// A flag another thread (a signal handler) may set to stop the run after the current segment; the
    /// files are then closed and `summary.json` says `interrupted`.
    pub cancel: Option<Arc<AtomicBool>>,
    /// The tables' file format, overriding the scenario's `[output] format` (see
    /// [`TableFormats::choose`]).
    pub format: Option<OutputFormat>,
}

/// Makes `dir` ready for a run: creates it if needed; if it exists, it must be a directory holding
/// nothing but a previous run's files ([`RUN_FILES`]) and sub-directories ([`RUN_DIRS`], holding only
/// files with their extensions), which are removed (`summary.json` first, so a run killed later never
/// leaves an old summary beside new CSV files). Anything else is refused with
/// [`RunError::OutputDirectory`], and nothing is removed.
pub fn prepare_output_dir(dir: &Path) -> Result<(), RunError> {
    let refuse = |message: String| RunError::OutputDirectory {
        path: dir.display().to_string(),
        message,
    };
    let output_error = |path: &Path, e: std::io::Error| RunError::Output {
        path: path.display().to_string(),
        message: e.to_string(),
    };
    match std::fs::metadata(dir) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return std::fs::create_dir_all(dir).map_err(|e| output_error(dir, e));
        }
        Err(e) => return Err(output_error(dir, e)),
        Ok(m) if !m.is_dir() => return Err(refuse(
            "exists and is not a directory (allowed: a new path, an empty directory or a previous \
                 satflock run's directory)"
                .into(),
        )),
        Ok(_) => {}
    }
    let allowed = || {
        let dirs: Vec<String> = RUN_DIRS
            .iter()
            .map(|(d, ext)| format!("{d}/ (only .{} files)", ext.join(", .")))
            .collect();
        format!("{}, {}", RUN_FILES.join(", "), dirs.join(", "))
    };
    if let Some(foreign) = foreign_run_entry(dir).map_err(|e| output_error(dir, e))? {
        return Err(refuse(format!(
            "is not empty and not a previous satflock run: it holds `{foreign}` (allowed: a new path, \
             an empty directory, or a directory holding only {})",
            allowed()
        )));
    }
    for name in RUN_FILES {
        let path = dir.join(name);
        if path.is_file() {
            std::fs::remove_file(&path).map_err(|e| output_error(&path, e))?;
        }
    }
    for (name, _) in RUN_DIRS {
        let path = dir.join(name);
        if path.is_dir() {
            std::fs::remove_dir_all(&path).map_err(|e| output_error(&path, e))?;
        }
    }
    Ok(())
}

/// The first entry of the directory `dir` that a previous run did not write, as a path relative to
/// `dir` (`notes.txt`, `plots/notes.txt`): anything but the files [`RUN_FILES`] and the folders
/// [`RUN_DIRS`] holding only files with their extensions. `None`: `dir` holds only a previous run's
/// outputs, or nothing. Tools that keep runs in folders of their own (`satflock compare`) check them
/// with it before clearing them.
pub fn foreign_run_entry(dir: &Path) -> std::io::Result<Option<String>> {
    let mut entries: Vec<std::fs::DirEntry> =
        std::fs::read_dir(dir)?.collect::<std::io::Result<_>>()?;
    entries.sort_by_key(|e| e.file_name());
    for entry in entries {
        let name = entry.file_name().to_string_lossy().into_owned();
        let file_type = entry.file_type()?;
        if file_type.is_file() && RUN_FILES.contains(&name.as_str()) {
            continue;
        }
        match RUN_DIRS.iter().find(|(d, _)| *d == name) {
            Some((_, extensions)) if file_type.is_dir() => {
                if let Some(foreign) = foreign_entry(&entry.path(), extensions)? {
                    return Ok(Some(format!("{name}/{foreign}")));
                }
            }
            _ => return Ok(Some(name)),
        }
    }
    Ok(None)
}

/// The first entry of `dir` that is not a file with one of `extensions` (`None`: there is none).
fn foreign_entry(dir: &Path, extensions: &[&str]) -> std::io::Result<Option<String>> {
    let mut names = Vec::new();
    for entry in std::fs::read_dir(dir)? {
        let entry = entry?;
        let path = entry.path();
        let ours = entry.file_type()?.is_file()
            && path
                .extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| extensions.contains(&e));
        if !ours {
            names.push(entry.file_name().to_string_lossy().into_owned());
        }
    }
    names.sort();
    Ok(names.into_iter().next())
}

/// Refuses output keys the scenario validation does not cover: `[output] delta_v_budget_mps` must be
/// finite and > 0.
fn check_output_keys(scenario: &Scenario) -> Result<Option<f64>, RunError> {
    match scenario.file.output.delta_v_budget_mps {
        Some(b) if !(b.is_finite() && b > 0.0) => Err(ScenarioError::invalid(
            &scenario.sources(),
            crate::invalid::Invalid::range("output.delta_v_budget_mps", b, "finite, > 0 m/s"),
        )
        .into()),
        budget => Ok(budget),
    }
}

/// Runs a scenario, writing the metrics and trajectory tables (the trajectory unless the scenario turns
/// it off; CSV or Parquet, see [`TableFormats::choose`]), `scene.json`, `scenario.toml` and
/// `summary.json` into `out_dir` (created if needed). `progress` receives the simulated time \[s\].
/// Returns the summary; on a simulation failure the summary is written with status `failed` and the
/// error is returned.
pub fn run_scenario(
    scenario: &Scenario,
    out_dir: &Path,
    progress: &mut dyn FnMut(f64),
) -> Result<RunSummary, RunError> {
    run_scenario_with(scenario, out_dir, &RunOptions::default(), progress)
}

/// [`run_scenario`] with options. The output directory is prepared by [`prepare_output_dir`] once the
/// run can start. A run stopped by the cancel flag writes `summary.json` with status `interrupted` and
/// returns [`SimError::Interrupted`]. The scenario's load-time warnings ([`Prepared::warnings`]),
/// collisions and a delta-v budget exceeded are warnings in the summary's `warnings` (the run still
/// completes).
pub fn run_scenario_with(
    scenario: &Scenario,
    out_dir: &Path,
    options: &RunOptions,
    progress: &mut dyn FnMut(f64),
) -> Result<RunSummary, RunError> {
    run_prepared(scenario, scenario.prepare()?, out_dir, options, progress)
}

/// [`run_scenario_with`] of a scenario already prepared: `prepared` is `scenario.prepare()`, possibly
/// with a caller's law ([`crate::scenario::Prepared::replace_law`], said in `scenario.toml` and as the
/// summary's `controller`).
pub fn run_prepared(
    scenario: &Scenario,
    prepared: Prepared,
    out_dir: &Path,
    options: &RunOptions,
    progress: &mut dyn FnMut(f64),
) -> Result<RunSummary, RunError> {
    let budget_mps = check_output_keys(scenario)?;
    let n = prepared.satellites.len();
    let conjunction_threshold_m = prepared.conjunction_threshold_m;
    let mut metadata: BTreeMap<String, String> = prepared.tags.clone();
    metadata.insert("satflock_version".into(), env!("CARGO_PKG_VERSION").into());
    metadata.insert(
        "platform".into(),
        format!("{}-{}", std::env::consts::ARCH, std::env::consts::OS),
    );
    let context = SummaryContext {
        scenario: prepared.name.clone(),
        source: scenario.source.clone(),
        controller: prepared
            .law_source
            .clone()
            .or_else(|| scenario.controller.as_ref().map(|c| c.source.clone())),
        seed: prepared.config.seed,
        epoch: prepared.epoch,
        duration_s: prepared.config.duration_s,
        budget_mps,
        metadata,
        load_warnings: prepared.warnings.clone(),
        event_keys: (0..scenario.file.events.len())
            .map(|k| scenario.event_key(k))
            .collect(),
    };
    let mut simulation = Simulation::from_owned(
        prepared.config,
        prepared.satellites,
        prepared.law,
        prepared.events,
    )
    .map_err(|e| setup_error(scenario, e))?;
    configure(scenario, &mut simulation, conjunction_threshold_m)?;
    if let Some(flag) = &options.cancel {
        simulation.set_cancel_flag(flag.clone());
    }
    // The output directory is created (or a previous run's cleared) only once the run can start.
    prepare_output_dir(out_dir)?;
    // The summary first, saying `failed` until the run's end replaces it: a process killed or a disk
    // filled before then leaves a summary that says the run did not finish.
    let not_finished =
        "the run did not finish: this summary was written when it started and was never \
                        replaced (the process was killed, or its disk was full)";
    write_summary(
        out_dir,
        &context.summary(&simulation, BTreeMap::new(), Some(&not_finished), 0.0),
    )?;
    // A file that cannot be written before the run starts fails it, said in the summary.
    let inputs = RunInputs {
        law_source: prepared.law_source.as_deref(),
        write_trajectory: prepared.write_trajectory,
        n,
    };
    let mut recorder =
        match write_inputs(scenario, &inputs, &context, &simulation, options, out_dir) {
            Ok(recorder) => recorder,
            Err(e) => {
                let summary = context.summary(&simulation, BTreeMap::new(), Some(&e), 0.0);
                write_summary(out_dir, &summary)?;
                return Err(e);
            }
        };
    let started = Instant::now();
    let outcome = simulation.run(&mut recorder, progress);
    let wall_time_s = started.elapsed().as_secs_f64();
    // The files are closed however the run ended; a file that cannot be closed (or was removed because
    // it could not be) fails the run, said with the error that stopped it.
    let outcome = match (outcome, recorder.finish()) {
        (Ok(_), Err(e)) => Err(SimError::Recording(e)),
        (Err(SimError::Recording(e)), Err(f)) => Err(SimError::Recording(std::io::Error::new(
            e.kind(),
            format!("{e}; {f}"),
        ))),
        (Err(e), Err(f)) => Err(SimError::Recording(std::io::Error::new(
            f.kind(),
            format!("{e}; closing the tables: {f}"),
        ))),
        (outcome, Ok(())) => outcome,
    };

    // The conjunctions found, however the run ended (a run stopped early has those up to its end).
    let outcome = match (
        outcome,
        write_conjunctions(&simulation, out_dir, &context, options, scenario),
    ) {
        (Ok(_), Err(e)) => Err(SimError::Recording(std::io::Error::other(e.to_string()))),
        (outcome, _) => outcome,
    };
    let error = outcome.as_ref().err().map(|e| e as &dyn ErrorText);
    let law_results = simulation.law_results();
    let summary = context.summary(&simulation, law_results, error, wall_time_s);
    write_summary(out_dir, &summary).map_err(|e| match e {
        RunError::Output { path, message } => RunError::Output {
            path,
            message: format!(
                "{message} (the run ended {}; summary.json still says `failed`, as written when the \
                 run started)",
                match &outcome {
                    Ok(_) => "completed".to_string(),
                    Err(e) => format!("with: {e}"),
                }
            ),
        },
        other => other,
    })?;
    outcome?;
    if scenario.file.output.oem {
        write_oem(out_dir)?;
    }
    Ok(summary)
}

/// The encounters sorted by (TCA, primary, secondary): the order of the table and the summary.
fn sorted_encounters(
    encounters: &[crate::conjunction::Encounter],
) -> Vec<crate::conjunction::Encounter> {
    let mut sorted = encounters.to_vec();
    sorted.sort_by(|x, y| {
        x.tca_s
            .total_cmp(&y.tca_s)
            .then(x.primary.cmp(&y.primary))
            .then(x.secondary.cmp(&y.secondary))
    });
    sorted
}

/// Writes `conjunctions.csv` or `.parquet` (the metrics table's format) when the run monitors
/// conjunctions.
fn write_conjunctions(
    simulation: &Simulation,
    out_dir: &Path,
    context: &SummaryContext,
    options: &RunOptions,
    scenario: &Scenario,
) -> Result<(), ExportError> {
    let Some(monitor) = simulation.conjunction_monitor() else {
        return Ok(());
    };
    let format = TableFormats::choose(
        options.format.or(scenario.file.output.format),
        simulation.satellite_count(),
        false,
    )
    .metrics;
    let run = RunMetadata {
        scenario: context.scenario.clone(),
        seed: context.seed,
        epoch: context.epoch,
    };
    conjunctions::write_table(
        out_dir,
        format,
        &sorted_encounters(monitor.encounters()),
        &run,
    )?;
    Ok(())
}

/// What the summary states about a run besides the simulation's own numbers.
struct SummaryContext {
    scenario: String,
    source: String,
    controller: Option<String>,
    seed: u64,
    epoch: crate::time::Epoch,
    duration_s: f64,
    budget_mps: Option<f64>,
    metadata: BTreeMap<String, String>,
    /// The warnings found when the scenario was prepared ([`Prepared::warnings`]), first in the
    /// summary's `warnings`.
    load_warnings: Vec<String>,
    /// The key of each event of the scenario (`events[K]`, `controller events[K]`).
    event_keys: Vec<String>,
}

/// What [`write_inputs`] takes from the prepared scenario.
struct RunInputs<'a> {
    law_source: Option<&'a str>,
    write_trajectory: bool,
    n: usize,
}

impl SummaryContext {
    /// The summary of `simulation` as it stands, with the law's `results` (none before the run):
    /// `completed` without an `error`, `interrupted` for [`SimError::Interrupted`], `failed` with the
    /// error's text otherwise.
    fn summary(
        &self,
        simulation: &Simulation,
        law_results: BTreeMap<String, serde_json::Value>,
        error: Option<&dyn ErrorText>,
        wall_time_s: f64,
    ) -> RunSummary {
        let n = simulation.active().len();
        let budget_mps = self.budget_mps;
        let totals = simulation.totals().clone();
        let (state, active) = (simulation.state(), simulation.active());
        let ledger: Vec<([f64; 3], f64)> = (0..n).map(|i| state.ledger(i)).collect();
        let live: Vec<usize> = (0..n).filter(|&i| active[i]).collect();
        let count = live.len().max(1) as f64;
        let mut mean_axes = [0.0; 3];
        for &i in &live {
            for (k, m) in mean_axes.iter_mut().enumerate() {
                *m += ledger[i].0[k] / count;
            }
        }
        RunSummary {
            scenario: self.scenario.clone(),
            source: self.source.clone(),
            controller: self.controller.clone(),
            seed: self.seed,
            epoch_utc: crate::time::utc_iso(self.epoch),
            time_system: frames::TIME_SYSTEM.into(),
            tai_minus_utc_s: crate::time::tai_minus_utc_s(self.epoch),
            tt_minus_utc_s: crate::time::tt_minus_utc_s(self.epoch),
            frames: Frames::default(),
            status: match error {
                None if simulation.stopped_by().is_some() => RunStatus::Stopped,
                None => RunStatus::Completed,
                Some(e) if e.is_interruption() => RunStatus::Interrupted,
                Some(_) => RunStatus::Failed,
            },
            error: error.map(|e| e.text()),
            stopped_by: simulation.stopped_by().map(|f| StoppedBy {
                event: f.event,
                key: self
                    .event_keys
                    .get(f.event)
                    .cloned()
                    .unwrap_or_else(|| format!("events[{}]", f.event)),
                time_s: f.time_s,
                trigger: f.trigger.to_string(),
                value: f.value,
            }),
            events: simulation.fired_events().to_vec(),
            warnings: {
                let mut warnings = self.load_warnings.clone();
                warnings.extend(run_warnings(
                    totals.max_collisions,
                    totals.min_separation_m,
                    &ledger,
                    budget_mps,
                ));
                warnings.extend(obstacle_warning(simulation));
                warnings
            },
            n_satellites: n,
            duration_s: self.duration_s,
            simulated_s: simulation.time_s(),
            wall_time_s,
            satellite_steps_per_s: totals.satellite_steps as f64 / wall_time_s.max(1e-9),
            threads: rayon::current_num_threads(),
            timing: simulation.stage_timings(),
            dynamics: DynamicsSummary {
                model: simulation.config().dynamics.name().to_owned(),
                forces: simulation.config().dynamics.forces().map(|f| f.summary()),
            },
            delta_v_mps: DeltaVSummary {
                per_satellite: ledger.iter().map(|l| l.1).collect(),
                max: live.iter().map(|&i| ledger[i].1).fold(0.0, f64::max),
                mean: live.iter().map(|&i| ledger[i].1).sum::<f64>() / count,
                mean_per_axis_hill: mean_axes,
            },
            drag: simulation.drag_delta_v_mps().map(|delta_v| {
                let switches = simulation.drag_switches();
                let altitude = simulation.mean_altitude_first_and_last_orbit_m();
                crate::output::summary::DragSummary {
                    switches_total: switches.iter().sum(),
                    switches_per_satellite: switches,
                    delta_v_per_satellite_mps: delta_v,
                    mean_altitude_first_orbit_m: altitude.map(|a| a.0),
                    mean_altitude_last_orbit_m: altitude.map(|a| a.1),
                    mean_altitude_decay_m: altitude.map(|a| a.0 - a.1),
                }
            }),
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
            conjunctions: simulation.conjunction_monitor().map(|m| {
                crate::output::summary::ConjunctionSummary::new(
                    m.threshold_m(),
                    &sorted_encounters(m.encounters()),
                    simulation.config().sensing.position_noise_m,
                    simulation.config().sensing.velocity_noise_mps,
                )
            }),
            law: law_results,
            metadata: self.metadata.clone(),
        }
    }
}

/// The error text of a summary: any run error, or a fixed reason.
trait ErrorText {
    /// The text of `error` in `summary.json`.
    fn text(&self) -> String;
    /// Whether the run was stopped by the cancel flag (status `interrupted`).
    fn is_interruption(&self) -> bool {
        false
    }
}

impl ErrorText for SimError {
    fn text(&self) -> String {
        self.to_string()
    }
    fn is_interruption(&self) -> bool {
        matches!(self, SimError::Interrupted { .. })
    }
}

impl ErrorText for RunError {
    fn text(&self) -> String {
        self.to_string()
    }
}

impl ErrorText for &str {
    fn text(&self) -> String {
        (*self).to_string()
    }
}

/// Writes `dir/summary.json` whole (a temporary file renamed over it: a full disk never leaves a
/// partial summary, and a summary already there stays until the new one is complete).
fn write_summary(dir: &Path, summary: &RunSummary) -> Result<(), RunError> {
    let text = serde_json::to_string_pretty(summary).expect("the summary serialises");
    write_file(&dir.join("summary.json"), (text + "\n").as_bytes())
}

/// [`crate::output::export::write_whole`] as a [`RunError::Output`].
fn write_file(path: &Path, bytes: &[u8]) -> Result<(), RunError> {
    crate::output::export::write_whole(path, bytes).map_err(output_error)
}

/// A whole-file write's error as a [`RunError::Output`] (`write_whole` fails only with
/// [`ExportError::Output`]).
fn output_error(e: ExportError) -> RunError {
    match e {
        ExportError::Output { path, message } => RunError::Output { path, message },
        other => RunError::Output {
            path: String::new(),
            message: other.to_string(),
        },
    }
}

/// What a run streams into its directory: the tables and `events.jsonl`.
struct RunOutputs {
    tables: RunRecorder,
    events: EventLog,
}

impl Recorder for RunOutputs {
    fn record(&mut self, snapshot: &Snapshot<'_>) -> std::io::Result<()> {
        self.tables.record(snapshot)
    }

    fn event_fired(&mut self, firing: &Firing) -> std::io::Result<()> {
        self.events.write(firing)
    }
}

impl RunOutputs {
    /// Closes the tables and the event log (the first error, if any).
    fn finish(self) -> std::io::Result<()> {
        let tables = self.tables.finish();
        let events = self.events.finish();
        tables.and(events)
    }
}

/// Writes `scene.json` and `scenario.toml` (each whole) and creates the tables' files and
/// `events.jsonl`.
fn write_inputs(
    scenario: &Scenario,
    inputs: &RunInputs<'_>,
    context: &SummaryContext,
    simulation: &Simulation,
    options: &RunOptions,
    out_dir: &Path,
) -> Result<RunOutputs, RunError> {
    let scene = Scene {
        target_formation_lvlh_m: simulation
            .law()
            .target_formation_hill_m()
            .map(|points| points.iter().map(|p| [p.x, p.y, p.z]).collect()),
        ..Scene::from_config(simulation.config())
    };
    scene.write(out_dir).map_err(|e| RunError::Output {
        path: out_dir.join("scene.json").display().to_string(),
        message: e.to_string(),
    })?;
    let scenario_path = out_dir.join("scenario.toml");
    let scenario_text = toml::to_string(&scenario.file).map_err(|e| RunError::Output {
        path: scenario_path.display().to_string(),
        message: e.to_string(),
    })?;
    // A replaced controller or law is said in a comment; the tables below are the scenario as run.
    let scenario_text = match (&scenario.controller, inputs.law_source) {
        (_, Some(law)) => format!(
            "# As run: the scenario {} with the caller's law {law} instead of its [law].\n{scenario_text}",
            scenario.sources()
        ),
        (Some(c), None) => format!(
            "# As run: the case {} with the controller {} (its law, law events and control timing).\n{scenario_text}",
            scenario.source, c.source
        ),
        (None, None) => scenario_text,
    };
    write_file(&scenario_path, scenario_text.as_bytes())?;
    let formats = TableFormats::choose(
        options.format.or(scenario.file.output.format),
        inputs.n,
        inputs.write_trajectory,
    );
    let run_metadata = RunMetadata {
        scenario: context.scenario.clone(),
        seed: context.seed,
        epoch: context.epoch,
    };
    let tables = RunRecorder::create(
        out_dir,
        formats,
        OutputColumns::of(simulation),
        &run_metadata,
    )
    .map_err(|e| RunError::Output {
        path: out_dir.display().to_string(),
        message: e.to_string(),
    })?;
    let events = EventLog::create(out_dir).map_err(|e| RunError::Output {
        path: out_dir
            .join(crate::output::events_log::RUN_FILE)
            .display()
            .to_string(),
        message: e.to_string(),
    })?;
    Ok(RunOutputs { tables, events })
}

/// `[output] oem = true`: writes `oem/sat-NNNNN.oem` from the finished run's directory.
fn write_oem(out_dir: &Path) -> Result<(), RunError> {
    let fail = |path: String, message: String| RunError::Output { path, message };
    let file = out_dir.join(oem::RUN_DIR_NAME);
    let creation = oem::creation_date().map_err(|m| fail(file.display().to_string(), m))?;
    let run = RunData::read(out_dir).map_err(|e| fail(e.path, e.message))?;
    let layout = OemLayout::in_run_dir(out_dir, false);
    match oem::write_run_oem(&run, &layout, creation, oem::OemVersion::V2) {
        Ok(_) => Ok(()),
        Err(ExportError::Input(e)) => Err(fail(e.path, e.message)),
        Err(ExportError::Output { path, message }) => Err(fail(path, message)),
        Err(e @ ExportError::Option { .. }) => Err(fail(file.display().to_string(), e.to_string())),
    }
}

/// The warnings of a run: collisions (largest simultaneous count, smallest separation) and satellites
/// whose delta-v exceeds the scenario's budget.
fn run_warnings(
    collisions: usize,
    min_separation_m: f64,
    ledger: &[([f64; 3], f64)],
    budget_mps: Option<f64>,
) -> Vec<String> {
    let mut warnings = Vec::new();
    if collisions > 0 {
        warnings.push(format!(
            "collisions: up to {collisions} pair(s) of satellites closer than the sum of their radii at \
             once (smallest separation {min_separation_m:.4} m)"
        ));
    }
    if let Some(budget) = budget_mps {
        let over: Vec<usize> = (0..ledger.len())
            .filter(|&i| ledger[i].1 > budget)
            .collect();
        if let Some(&worst) = over
            .iter()
            .max_by(|&&a, &&b| ledger[a].1.total_cmp(&ledger[b].1))
        {
            warnings.push(format!(
                "delta-v budget exceeded: {} satellite(s) spent more than output.delta_v_budget_mps = \
                 {budget} m/s (largest: satellite {worst}, {:.4} m/s)",
                over.len(),
                ledger[worst].1
            ));
        }
    }
    warnings
}

/// The warning of satellites that entered obstacles (the monitor's count, and the deepest point).
fn obstacle_warning(simulation: &Simulation) -> Option<String> {
    let monitor = simulation.approach_monitor();
    let incursions = monitor.total_obstacle_incursions();
    let deepest = monitor.swarm_obstacle_minimum()?;
    (incursions > 0).then(|| {
        format!(
            "obstacle incursions: {incursions} entr{} of satellites into obstacles (deepest: satellite \
             {} in `{}`, {:.4} m inside at t = {} s)",
            if incursions == 1 { "y" } else { "ies" },
            deepest.satellite,
            simulation.config().obstacles[deepest.object].name(),
            -deepest.minimum.clearance_m,
            deepest.minimum.time_s
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regress_run_warnings_collisions_and_budget() {
        let ledger = vec![([0.0; 3], 1.0), ([0.0; 3], 5.0), ([0.0; 3], 3.0)];
        assert!(run_warnings(0, 10.0, &ledger, None).is_empty());
        assert!(run_warnings(0, 10.0, &ledger, Some(5.0)).is_empty());
        let w = run_warnings(2, -0.5, &ledger, Some(2.0));
        assert_eq!(w.len(), 2);
        assert!(w[0].contains("up to 2 pair(s)"), "{}", w[0]);
        assert!(
            w[1].contains("2 satellite(s)") && w[1].contains("satellite 1"),
            "{}",
            w[1]
        );
    }

    /// Issue 25: a satellite crossing an obstacle was counted in `environment` only; it is a warning
    /// of the summary (and so of stderr) too.
    #[test]
    fn regress_obstacle_incursion_is_a_warning() {
        let text = "name = \"rock\"\nseed = 1\nduration_s = 100.0\nrecord_interval_s = 10.0\n\
                    [reference]\naltitude_m = 600e3\ninclination_deg = 97.8\n\
                    [satellites]\ncount = 1\nmass_kg = 1.0\n\
                    initial = { distribution = \"list\", states = [[0.0, 0.0, 0.0, 0.0, 1.0, 0.0]] }\n\
                    [law]\nname = \"none\"\n\
                    [[obstacles]]\nname = \"rock\"\ncenter_hill_m = [0.0, 50.0, 0.0]\nradius_m = 10.0\n";
        let scenario = Scenario::from_toml(text, "rock.toml", Path::new(".")).unwrap();
        let dir = std::env::temp_dir().join(format!("satflock-rock-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let summary = run_scenario(&scenario, &dir, &mut |_| {}).unwrap();
        let warning = summary
            .warnings
            .iter()
            .find(|w| w.starts_with("obstacle incursions"))
            .unwrap_or_else(|| panic!("no obstacle warning in {:?}", summary.warnings));
        assert!(
            warning.contains("1 entry") && warning.contains("satellite 0 in `rock`"),
            "{warning}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Issue 25: a command above ~1e154 m/s^2 overflowed the norm and was applied as zero thrust (the run
    /// "completed" with delta-v 0). Now the run stops as failed, naming the satellite, tick and law, in
    /// both control timings.
    #[test]
    fn regress_overflowing_command_fails_the_run() {
        for control in ["", "[control]\nmode = \"sampled\"\nperiod_s = 1.0\n"] {
            let text = format!(
                "name = \"huge\"\nseed = 1\nduration_s = 20.0\nrecord_interval_s = 10.0\n\
                 [reference]\naltitude_m = 600e3\ninclination_deg = 97.8\n\
                 [satellites]\ncount = 3\nmass_kg = 1.0\n\
                 initial = {{ distribution = \"sphere\", radius_m = 50.0 }}\n\
                 [law]\nname = \"hold\"\nstiffness_per_s2 = 1e-4\ndamping_per_s = 2e-2\n\
                 slot_offset_hill_m = [1e160, 0.0, 0.0]\n{control}"
            );
            let scenario = Scenario::from_toml(&text, "huge.toml", Path::new(".")).unwrap();
            let dir = std::env::temp_dir().join(format!("satflock-huge-{}", std::process::id()));
            let _ = std::fs::remove_dir_all(&dir);
            let e = run_scenario(&scenario, &dir, &mut |_| {}).unwrap_err();
            match &e {
                RunError::Simulation(SimError::BadCommand {
                    satellite: 0,
                    tick: 0,
                    law,
                    ..
                }) => assert_eq!(law, "hold"),
                other => panic!("{control}: expected BadCommand of satellite 0, got {other:?}"),
            }
            let summary: serde_json::Value =
                serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap())
                    .unwrap();
            assert_eq!(summary["status"], "failed");
            let reason = summary["error"].as_str().unwrap();
            assert!(
                reason.contains("law `hold` commanded satellite 0") && reason.contains("tick 0"),
                "{reason}"
            );
            std::fs::remove_dir_all(&dir).unwrap();
        }
    }

    #[test]
    fn regress_output_dir_refuses_foreign_and_clears_previous_run() {
        let dir = std::env::temp_dir().join(format!("satflock-outdir-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("summary.json"), "{}").unwrap();
        std::fs::write(dir.join("metrics.csv"), "t_s\n").unwrap();
        std::fs::create_dir(dir.join("plots")).unwrap();
        std::fs::write(dir.join("plots/trajectories.png"), "png").unwrap();
        std::fs::write(dir.join("plots/trajectories.svg"), "svg").unwrap();
        prepare_output_dir(&dir).unwrap();
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
        // A plots folder holding something else is not a previous run's.
        std::fs::create_dir(dir.join("plots")).unwrap();
        std::fs::write(dir.join("plots/notes.txt"), "mine").unwrap();
        let e = prepare_output_dir(&dir).unwrap_err();
        assert!(e.to_string().contains("plots/notes.txt"), "{e}");
        assert!(dir.join("plots/notes.txt").exists());
        std::fs::remove_dir_all(dir.join("plots")).unwrap();
        std::fs::write(dir.join("notes.txt"), "mine").unwrap();
        std::fs::write(dir.join("summary.json"), "{}").unwrap();
        let e = prepare_output_dir(&dir).unwrap_err();
        assert!(matches!(e, RunError::OutputDirectory { .. }));
        assert!(e.to_string().contains("notes.txt"), "{e}");
        // Nothing removed on refusal.
        assert!(dir.join("summary.json").exists());
        let file = dir.join("notes.txt");
        assert!(matches!(
            prepare_output_dir(&file),
            Err(RunError::OutputDirectory { .. })
        ));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
