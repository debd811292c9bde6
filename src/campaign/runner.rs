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
//!
//! A record's `parameters` are the varied keys' values as the run used them, read back from its own
//! `scenario.toml` (a run that used another value than the campaign's is recorded as failed). Resuming
//! trusts no manifest line ([`check_record`]): a line that does not read, or a record that the
//! campaign (its runs, points and seeds) or its run's directory (`scenario.toml`, `summary.json`:
//! seed, status, outcomes) contradicts, is dropped and said ([`Prepared::dropped`], stderr,
//! `summary.md`); a run no kept line records as completed runs again.

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use super::file::{Campaign, RunSpec};
use super::manifest::{self, Header, RunRecord, Status};
use super::{overrides, pool, summary, table, CampaignError};
use crate::output::outcomes::{scalar_outcomes, RunTable};
use crate::run::{run_prepared, RunError, RunOptions};
use crate::scenario::{Prepared as PreparedScenario, Scenario, ScenarioError};
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
    /// Manifest lines that `resume` dropped, each with why ([`Prepared::dropped`]).
    pub dropped: Vec<String>,
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
        dropped,
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
    let (records, table) = finish(campaign, out, previous, ran, &dropped)?;
    Ok(CampaignReport {
        outcomes: summary::headline_outcomes(campaign, &table),
        dropped,
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
    /// The manifest lines that were not kept, each as `manifest.jsonl line N: why` (a line that does not
    /// read as a record, or a record that [`check_record`] refuses); give them to [`finish`].
    pub dropped: Vec<String>,
}

/// Prepares `out` for `campaign`: without `resume` it must be a new path or an empty directory; with
/// it, it may also hold a manifest of this campaign, whose completed runs are kept (each line checked
/// by [`check_record`]; the others dropped and listed). Writes the manifest's header (and the kept
/// records) and says which runs are left.
pub fn prepare(campaign: &Campaign, out: &Path, resume: bool) -> Result<Prepared, CampaignError> {
    let (previous, dropped) = prepare_output(campaign, out, resume)?;
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
        dropped,
    })
}

/// Writes `campaign.parquet` (when a run finished) and `summary.md` into `out` from the records of
/// the runs: `previous` (a resumed manifest's) and `ran` (this invocation's, in any order; a run in
/// both counts as in `ran`); `dropped` ([`Prepared::dropped`]) is listed in the summary. Returns every
/// run's last record in run order, and the table.
pub fn finish(
    campaign: &Campaign,
    out: &Path,
    previous: Vec<RunRecord>,
    ran: Vec<RunRecord>,
    dropped: &[String],
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
    std::fs::write(
        &summary_path,
        summary::markdown(campaign, &records, &table, dropped),
    )
    .map_err(|e| output(&summary_path, e))?;
    Ok((records, table))
}

/// Manifest records of every run (the last line of each that [`check_record`] keeps), and the lines
/// dropped with why.
type Kept = (BTreeMap<usize, RunRecord>, Vec<String>);

/// Checks the output directory and returns, when resuming, the manifest's last kept record per run and
/// the dropped lines. Without `resume` the directory must be new or empty; with it, it must be new,
/// empty or hold a manifest of this campaign.
fn prepare_output(campaign: &Campaign, out: &Path, resume: bool) -> Result<Kept, CampaignError> {
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
            return Ok(Kept::default());
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
        return Ok(Kept::default());
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
    let contents = manifest::read(&manifest_path)?;
    if let Some(why) = contents.header.mismatch(campaign) {
        return Err(CampaignError::Resume {
            path: manifest_path.display().to_string(),
            message: format!(
                "cannot resume: {why}; run the campaign into a new --out, or restore the file"
            ),
        });
    }
    let mut dropped: Vec<(usize, String)> = contents
        .unreadable
        .iter()
        .map(|&line| (line, "not a run record (cut short, or edited)".to_string()))
        .collect();
    let mut kept = BTreeMap::new();
    for (line, record) in contents.records {
        match check_record(campaign, out, &record) {
            Ok(()) => {
                kept.insert(record.run, record);
            }
            Err(why) => dropped.push((line, format!("run {}: {why}", record.run))),
        }
    }
    dropped.sort();
    let dropped = dropped
        .into_iter()
        .map(|(line, why)| format!("{} line {line}: {why}", manifest::FILE_NAME))
        .collect();
    Ok((kept, dropped))
}

/// Whether a manifest record is what its run did: the run is one of the campaign's, with its point and
/// seed; its parameters are the values its `scenario.toml` holds (or the campaign's, for a run that
/// wrote none); its `summary.json` (absent only for a run that did not complete and has no outcomes)
/// has its seed, says `completed` exactly when the record does, and has its outcomes. The error says
/// the first thing that does not match.
pub fn check_record(campaign: &Campaign, out: &Path, record: &RunRecord) -> Result<(), String> {
    let runs = campaign.run_count();
    if record.run >= runs {
        return Err(format!(
            "not a run of this campaign (allowed: runs 0 to {})",
            runs - 1
        ));
    }
    let spec = campaign.run(record.run);
    if record.point != spec.point {
        return Err(format!(
            "point {} (the campaign's run {} is point {})",
            record.point, spec.index, spec.point
        ));
    }
    if record.seed != spec.seed {
        return Err(format!(
            "seed {} (the campaign's run {} has seed {})",
            record.seed, spec.index, spec.seed
        ));
    }
    let dir = run_dir(out, record.run);
    let parameters = applied_parameters(campaign, spec.point, &dir)?
        .unwrap_or_else(|| intended_parameters(campaign, spec.point));
    if record.parameters != parameters {
        return Err(format!(
            "parameters {} (the run used {})",
            serde_json::Value::from(serde_json::Map::from_iter(record.parameters.clone())),
            serde_json::Value::from(serde_json::Map::from_iter(parameters))
        ));
    }
    let summary_path = dir.join("summary.json");
    let summary = crate::input_file::read_document(&summary_path)
        .ok()
        .and_then(|text| serde_json::from_str::<serde_json::Value>(&text).ok());
    let Some(summary) = summary else {
        return if record.status == Status::Completed || !record.outcomes.is_empty() {
            Err(format!(
                "status {} with {} outcome(s), but {} is missing or unreadable",
                record.status.as_str(),
                record.outcomes.len(),
                summary_path.display()
            ))
        } else {
            Ok(())
        };
    };
    if summary["seed"].as_u64() != Some(spec.seed) {
        return Err(format!(
            "{} has seed {}, not the campaign's {}",
            summary_path.display(),
            summary["seed"],
            spec.seed
        ));
    }
    // A run ended by its own `stop-run` event completed as its scenario asked.
    let completed = matches!(summary["status"].as_str(), Some("completed" | "stopped"));
    if completed != (record.status == Status::Completed) {
        return Err(format!(
            "status {}, but {} says {}",
            record.status.as_str(),
            summary_path.display(),
            summary["status"]
        ));
    }
    let outcomes: BTreeMap<String, f64> = scalar_outcomes(&summary).into_iter().collect();
    if let Some((name, value)) = record
        .outcomes
        .iter()
        .find(|(name, value)| outcomes.get(*name).map(|v| v.to_bits()) != Some(value.to_bits()))
    {
        return Err(format!(
            "outcome {name} = {value}, but {} has {}",
            summary_path.display(),
            outcomes
                .get(name)
                .map_or("none".to_string(), f64::to_string)
        ));
    }
    if let Some(name) = outcomes.keys().find(|n| !record.outcomes.contains_key(*n)) {
        return Err(format!(
            "outcome {name} of {} is missing",
            summary_path.display()
        ));
    }
    Ok(())
}

/// The directory of run `index`: `out/runs/NNNNN`.
fn run_dir(out: &Path, index: usize) -> std::path::PathBuf {
    out.join(RUNS_DIR).join(format!("{index:05}"))
}

/// The varied keys' values of point `point` as the campaign sets them, as JSON.
fn intended_parameters(campaign: &Campaign, point: usize) -> BTreeMap<String, serde_json::Value> {
    campaign
        .point_values(point)
        .into_iter()
        .map(|(k, v)| (k.to_string(), toml_to_json(v)))
        .collect()
}

/// A TOML value as JSON (a TOML date, which JSON has not, as its text).
fn toml_to_json(value: &toml::Value) -> serde_json::Value {
    serde_json::to_value(value).unwrap_or_else(|_| serde_json::Value::String(value.to_string()))
}

/// The varied keys' values of point `point` as the run in `dir` used them, read back from its
/// `scenario.toml` (`Ok(None)`: the run wrote none, it was refused before it started). The error names
/// the file and a varied key it lacks or holds with another value than the campaign's.
pub fn applied_parameters(
    campaign: &Campaign,
    point: usize,
    dir: &Path,
) -> Result<Option<BTreeMap<String, serde_json::Value>>, String> {
    let path = dir.join("scenario.toml");
    let text = match crate::input_file::read_document(&path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(format!("{}: {e}", path.display())),
        Ok(text) => text,
    };
    let table: toml::Table =
        toml::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    campaign
        .point_values(point)
        .into_iter()
        .map(|(key, intended)| match overrides::get(&table, key) {
            None => Err(format!(
                "{} has no `{key}` (the campaign sets it to {intended})",
                path.display()
            )),
            Some(found) if !overrides::holds(found, intended) => Err(format!(
                "{} has `{key}` = {found}, not the campaign's {intended}",
                path.display()
            )),
            Some(found) => Ok((key.to_string(), toml_to_json(found))),
        })
        .collect::<Result<_, _>>()
        .map(Some)
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
    execute_with(campaign, spec, out, keep_runs, cancel, Scenario::prepare)
}

/// [`execute`] with the run's scenario prepared by `prepare`: [`Scenario::prepare`], or a caller's
/// law put in the scenario's place with [`crate::scenario::Prepared::replace_law`] (the Python
/// package's laws written in Python). A preparation that fails refuses the run.
pub fn execute_with(
    campaign: &Campaign,
    spec: &RunSpec,
    out: &Path,
    keep_runs: bool,
    cancel: Option<Arc<AtomicBool>>,
    prepare: impl FnOnce(&Scenario) -> Result<PreparedScenario, ScenarioError>,
) -> RunRecord {
    let dir = run_dir(out, spec.index);
    let prepared = campaign
        .scenario(spec)
        .and_then(|scenario| prepare(&scenario).map(|prepared| (scenario, prepared)));
    let (status, error) = match prepared {
        Err(e) => (Status::Refused, Some(e.to_string())),
        Ok((scenario, prepared)) => {
            let options = RunOptions {
                cancel,
                format: None,
            };
            match run_prepared(&scenario, prepared, &dir, &options, &mut |_| {}) {
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
    let outcomes = crate::input_file::read_document(&dir.join("summary.json"))
        .ok()
        .and_then(|text| serde_json::from_str::<serde_json::Value>(&text).ok())
        .map(|summary| scalar_outcomes(&summary).into_iter().collect())
        .unwrap_or_default();
    // The parameters as the run used them (its own scenario.toml), the campaign's for a run that wrote
    // none; a run that used other values did not run the campaign's point.
    let (parameters, status, error) = match applied_parameters(campaign, spec.point, &dir) {
        Ok(Some(applied)) => (applied, status, error),
        Ok(None) => (intended_parameters(campaign, spec.point), status, error),
        Err(why) => (
            intended_parameters(campaign, spec.point),
            Status::Failed,
            Some(format!("the run did not use the campaign's values: {why}")),
        ),
    };
    if !keep_runs {
        thin_run_dir(&dir);
    }
    RunRecord {
        run: spec.index,
        point: spec.point,
        seed: spec.seed,
        parameters,
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn applied_parameters_are_read_back_and_a_value_the_run_did_not_use_is_named() {
        let campaign = Campaign::from_toml(
            "scenario = \"hold\"\nseeds = [1]\n[vary]\n\"satellites.initial.radius_m\" = [150]\n",
            "c.toml",
            Path::new("."),
        )
        .unwrap();
        let dir = std::env::temp_dir().join(format!("satflock-applied-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        assert_eq!(applied_parameters(&campaign, 0, &dir), Ok(None));
        let write = |radius: &str| {
            std::fs::write(
                dir.join("scenario.toml"),
                format!("[satellites.initial]\nradius_m = {radius}\n"),
            )
            .unwrap()
        };
        write("150.0");
        let applied = applied_parameters(&campaign, 0, &dir).unwrap().unwrap();
        assert_eq!(
            applied["satellites.initial.radius_m"],
            serde_json::json!(150.0)
        );
        write("151.0");
        let e = applied_parameters(&campaign, 0, &dir).unwrap_err();
        assert!(
            e.contains("`satellites.initial.radius_m` = 151.0, not the campaign's 150"),
            "{e}"
        );
        std::fs::write(dir.join("scenario.toml"), "[satellites]\n").unwrap();
        let e = applied_parameters(&campaign, 0, &dir).unwrap_err();
        assert!(e.contains("has no `satellites.initial.radius_m`"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
