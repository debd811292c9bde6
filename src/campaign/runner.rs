//! Running a campaign: every run that is not already complete, at most `jobs` at once, each on one
//! thread ([`super::pool::run_bounded`]), so runs × threads per run ≤ jobs; then `campaign.parquet`
//! and `summary.md` from every run's record.
//!
//! [`run_campaign`] is three public steps, which another executor (the Python package's Ray backend:
//! one run per task, records gathered by the driver) uses as they are: [`prepare`] the output
//! directory (resume included), [`execute`] each run into its folder and get its [`RunRecord`]
//! (appended to the manifest as it comes), [`finish`] with the table and the summary.
//!
//! Output directory (`--out`):
//!
//! | path | what |
//! | --- | --- |
//! | `manifest.jsonl` | header, then one line per finished run, flushed as it finishes ([`super::manifest`]) |
//! | `runs/NNNNN/` | run NNNNN's `summary.json` and `scenario.toml` (a plain `satflock run` of that file reproduces the run); its tables, `scene.json` and OEM too with `keep_runs` |
//! | `campaign.parquet` | one row per finished run ([`super::table`]) |
//! | `summary.md` | per parameter point: median, 5 % and 95 % of each headline outcome, failures ([`super::summary`]) |
//!
//! A run's result depends only on its scenario and seed (the engine is deterministic on one thread),
//! never on which worker ran it, in which order or with how many jobs; a run that fails or is refused
//! is recorded with its status and error and the campaign goes on. With `resume`, the manifest's
//! completed runs are kept and the others (failed, refused, interrupted or missing) are run.

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use super::file::{Campaign, RunSpec};
use super::manifest::{self, Header, RunRecord, Status};
use super::{pool, summary, table, CampaignError};
use crate::output::outcomes::{scalar_outcomes, RunTable};
use crate::run::{run_scenario_with, RunError, RunOptions};
use crate::swarm::SimError;

/// Folder of the runs' directories.
pub const RUNS_DIR: &str = "runs";

/// Files a run's directory keeps when the campaign does not keep whole runs.
pub const KEPT_RUN_FILES: &[&str] = &["summary.json", "scenario.toml"];

/// How a campaign is run.
#[derive(Clone, Debug, Default)]
pub struct RunnerOptions {
    /// Runs at once (each on one thread); `None`: the machine's cores.
    pub jobs: Option<usize>,
    /// Continue the campaign in the output directory: keep its completed runs, run the rest.
    pub resume: bool,
    /// Keep every run's full outputs (also when the campaign file does not say `keep_runs = true`).
    pub keep_runs: bool,
    /// A flag (set by a signal handler) that stops the running runs after their current segment
    /// (recorded as `interrupted`) and starts no more.
    pub cancel: Option<Arc<AtomicBool>>,
}

/// What the runner tells its caller as runs start and finish (from the worker threads).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RunEvent {
    /// Runs to do in this invocation, and runs already complete (resumed).
    Planned {
        /// Runs to do.
        to_run: usize,
        /// Runs complete in the manifest.
        already_complete: usize,
    },
    /// A run started.
    Started(usize),
    /// A run finished, with its status.
    Finished(usize, Status),
}

/// What a campaign did.
#[derive(Clone, Debug)]
pub struct CampaignReport {
    /// The last record of every finished run, in run order (including those of a resumed manifest).
    pub records: Vec<RunRecord>,
    /// Runs run by this invocation.
    pub ran: usize,
    /// Runs complete in the manifest before this invocation (`resume`).
    pub already_complete: usize,
    /// Whether the cancel flag stopped the campaign (some runs may be missing).
    pub interrupted: bool,
    /// The table written to `campaign.parquet` (empty, and not written, when no run finished).
    pub table: RunTable,
    /// The headline outcomes of `summary.md`.
    pub outcomes: Vec<String>,
}

impl CampaignReport {
    /// Number of finished runs with `status`.
    pub fn count(&self, status: Status) -> usize {
        self.records.iter().filter(|r| r.status == status).count()
    }
}

/// The default number of runs at once: the machine's cores (each run uses one thread).
pub fn default_jobs() -> usize {
    std::thread::available_parallelism().map_or(1, usize::from)
}

/// Runs `campaign` into `out` (see the module documentation): [`prepare`], then every run to do through
/// [`execute`] in the bounded pool (each record appended to the manifest as it finishes), then
/// [`finish`]. `events` is called from the worker threads. Errors are the output directory's (not empty,
/// a manifest that does not match) or a file that cannot be written; a run's failure is not an error.
pub fn run_campaign(
    campaign: &Campaign,
    out: &Path,
    options: &RunnerOptions,
    events: &(dyn Fn(RunEvent) + Sync),
) -> Result<CampaignReport, CampaignError> {
    let Prepared {
        to_run,
        previous,
        already_complete,
        manifest,
    } = prepare(campaign, out, options.resume)?;
    events(RunEvent::Planned {
        to_run: to_run.len(),
        already_complete,
    });
    let writer = Mutex::new(manifest);
    let keep_runs = options.keep_runs || campaign.keep_runs;
    let cancelled = || {
        options
            .cancel
            .as_ref()
            .is_some_and(|c| c.load(Ordering::Relaxed))
    };
    let write_error: Mutex<Option<CampaignError>> = Mutex::new(None);
    let jobs = options.jobs.unwrap_or_else(default_jobs);
    let finished = pool::run_bounded(to_run, jobs, |spec| {
        if cancelled() || write_error.lock().expect("error lock").is_some() {
            return None;
        }
        events(RunEvent::Started(spec.index));
        let record = execute(campaign, &spec, out, keep_runs, options.cancel.clone());
        if let Err(e) = writer.lock().expect("manifest lock").append(&record) {
            write_error.lock().expect("error lock").get_or_insert(e);
        }
        events(RunEvent::Finished(spec.index, record.status));
        Some(record)
    })?;
    if let Some(e) = write_error.into_inner().expect("error lock") {
        return Err(e);
    }
    let ran: Vec<RunRecord> = finished.into_iter().flatten().collect();
    let ran_count = ran.len();
    let (records, table) = finish(campaign, out, previous, ran)?;
    Ok(CampaignReport {
        outcomes: summary::headline_outcomes(campaign, &table),
        records,
        ran: ran_count,
        already_complete,
        interrupted: cancelled(),
        table,
    })
}

/// A campaign's output directory made ready by [`prepare`]: what is left to run and the manifest, open
/// for appending each finished run's record.
pub struct Prepared {
    /// The runs to do, in index order: every run the manifest does not record as completed.
    pub to_run: Vec<RunSpec>,
    /// The manifest's last record of every run before this invocation (empty unless resuming).
    pub previous: Vec<RunRecord>,
    /// Runs the manifest recorded as completed before this invocation.
    pub already_complete: usize,
    /// The manifest, rewritten with its header and `previous` (a line cut short dropped); append each
    /// finished run's record to it ([`manifest::Writer::append`]).
    pub manifest: manifest::Writer,
}

/// Prepares `out` for `campaign`: without `resume` it must be a new path or an empty directory; with
/// it, it may also hold a manifest of this campaign, whose completed runs are kept. Writes the
/// manifest's header (and the kept records) and says which runs are left.
pub fn prepare(campaign: &Campaign, out: &Path, resume: bool) -> Result<Prepared, CampaignError> {
    let previous = prepare_output(campaign, out, resume)?;
    let previous: Vec<RunRecord> = previous.into_values().collect();
    let complete: Vec<usize> = previous
        .iter()
        .filter(|r| r.status == Status::Completed)
        .map(|r| r.run)
        .collect();
    let manifest = manifest::Writer::create(
        &out.join(manifest::FILE_NAME),
        &Header::of(campaign),
        &previous,
    )?;
    let to_run = campaign
        .runs()
        .into_iter()
        .filter(|r| complete.binary_search(&r.index).is_err())
        .collect();
    Ok(Prepared {
        to_run,
        already_complete: complete.len(),
        previous,
        manifest,
    })
}

/// Writes `campaign.parquet` (when a run finished) and `summary.md` into `out` from the records of
/// the runs: `previous` (a resumed manifest's) and `ran` (this invocation's, in any order; a run in
/// both counts as in `ran`). Returns every run's last record in run order, and the table.
pub fn finish(
    campaign: &Campaign,
    out: &Path,
    previous: Vec<RunRecord>,
    ran: Vec<RunRecord>,
) -> Result<(Vec<RunRecord>, RunTable), CampaignError> {
    let mut last: BTreeMap<usize, RunRecord> = previous.into_iter().map(|r| (r.run, r)).collect();
    last.extend(ran.into_iter().map(|r| (r.run, r)));
    let records: Vec<RunRecord> = last.into_values().collect();
    let table = table::build(campaign, &records);
    let output = |path: &Path, e: std::io::Error| CampaignError::Output {
        path: path.display().to_string(),
        message: e.to_string(),
    };
    let table_path = out.join(table::FILE_NAME);
    if !records.is_empty() {
        table
            .write_parquet(
                &table_path,
                &[
                    ("satflock_version", env!("CARGO_PKG_VERSION").into()),
                    ("campaign", campaign.file.clone()),
                    ("campaign_sha256", campaign.sha256.clone()),
                    ("scenario", campaign.scenario.source.clone()),
                ],
            )
            .map_err(|e| output(&table_path, e))?;
    }
    let summary_path = out.join(summary::FILE_NAME);
    std::fs::write(&summary_path, summary::markdown(campaign, &records, &table))
        .map_err(|e| output(&summary_path, e))?;
    Ok((records, table))
}

/// Checks the output directory and returns the manifest's last record per run when resuming. Without
/// `resume` the directory must be new or empty; with it, it must be new, empty or hold a manifest of
/// this campaign.
fn prepare_output(
    campaign: &Campaign,
    out: &Path,
    resume: bool,
) -> Result<BTreeMap<usize, RunRecord>, CampaignError> {
    let refuse = |message: String| CampaignError::OutputDirectory {
        path: out.display().to_string(),
        message,
    };
    let output = |e: std::io::Error| CampaignError::Output {
        path: out.display().to_string(),
        message: e.to_string(),
    };
    match std::fs::metadata(out) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            std::fs::create_dir_all(out).map_err(output)?;
            return Ok(BTreeMap::new());
        }
        Err(e) => return Err(output(e)),
        Ok(m) if !m.is_dir() => {
            return Err(refuse(
                "exists and is not a directory (allowed: a new path or an empty directory)".into(),
            ))
        }
        Ok(_) => {}
    }
    let manifest_path = out.join(manifest::FILE_NAME);
    let empty = std::fs::read_dir(out).map_err(output)?.next().is_none();
    if empty {
        return Ok(BTreeMap::new());
    }
    if !manifest_path.is_file() {
        return Err(refuse(
            "is not empty and holds no campaign manifest.jsonl (allowed: a new path or an empty \
             directory; --resume continues a campaign in a directory that has one)"
                .into(),
        ));
    }
    if !resume {
        return Err(refuse(
            "holds a campaign (manifest.jsonl): add --resume to continue it, or choose a new --out"
                .into(),
        ));
    }
    let (header, records) = manifest::read(&manifest_path)?;
    if let Some(why) = header.mismatch(campaign) {
        return Err(CampaignError::Resume {
            path: manifest_path.display().to_string(),
            message: format!(
                "cannot resume: {why}; run the campaign into a new --out, or restore the file"
            ),
        });
    }
    Ok(records
        .into_iter()
        .filter(|(k, _)| *k < campaign.run_count())
        .collect())
}

/// Runs one run into `out/runs/NNNNN/` and returns its record (never an error: a run that cannot run
/// is recorded as refused or failed). Runs on the calling thread's rayon pool (the runner gives each
/// run a single-thread pool; the engine's result does not depend on the thread count). `keep_runs`:
/// keep the run's full outputs (else only [`KEPT_RUN_FILES`]); `cancel` stops it after its current
/// segment (recorded as `interrupted`).
pub fn execute(
    campaign: &Campaign,
    spec: &RunSpec,
    out: &Path,
    keep_runs: bool,
    cancel: Option<Arc<AtomicBool>>,
) -> RunRecord {
    let dir = out.join(RUNS_DIR).join(format!("{:05}", spec.index));
    let (status, error) = match campaign.scenario(spec) {
        Err(e) => (Status::Refused, Some(e.to_string())),
        Ok(scenario) => {
            let options = RunOptions {
                cancel,
                format: None,
            };
            match run_scenario_with(&scenario, &dir, &options, &mut |_| {}) {
                Ok(_) => (Status::Completed, None),
                Err(RunError::Scenario(e)) => (Status::Refused, Some(e.to_string())),
                Err(RunError::Simulation(e @ SimError::Interrupted { .. })) => {
                    (Status::Interrupted, Some(e.to_string()))
                }
                Err(RunError::Simulation(e)) if e.is_setup() => {
                    (Status::Refused, Some(e.to_string()))
                }
                Err(e) => (Status::Failed, Some(e.to_string())),
            }
        }
    };
    // The outcomes as the run's summary.json says them (also those reached by a run that stopped).
    let outcomes = std::fs::read_to_string(dir.join("summary.json"))
        .ok()
        .and_then(|text| serde_json::from_str::<serde_json::Value>(&text).ok())
        .map(|summary| scalar_outcomes(&summary).into_iter().collect())
        .unwrap_or_default();
    if !keep_runs {
        thin_run_dir(&dir);
    }
    RunRecord {
        run: spec.index,
        point: spec.point,
        seed: spec.seed,
        parameters: campaign
            .point_values(spec.point)
            .into_iter()
            .map(|(k, v)| {
                (
                    k.to_string(),
                    serde_json::to_value(v).unwrap_or(serde_json::Value::Null),
                )
            })
            .collect(),
        status,
        error,
        outcomes,
    }
}

/// Removes from a run's directory everything but [`KEPT_RUN_FILES`] (the tables, `scene.json`, an OEM):
/// a large campaign keeps only what its table and a re-run need. Best effort: what cannot be removed
/// stays.
fn thin_run_dir(dir: &Path) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        if KEPT_RUN_FILES.iter().any(|k| name == *k) {
            continue;
        }
        let path = entry.path();
        let _ = if path.is_dir() {
            std::fs::remove_dir_all(&path)
        } else {
            std::fs::remove_file(&path)
        };
    }
}
