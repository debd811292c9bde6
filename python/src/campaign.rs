//! Campaigns from Python: `CampaignPlan`, a validated campaign (`satflock::campaign::Campaign`) with
//! the library runner's steps, driven by `satflock/_campaign.py` (`satflock.campaign`).
//!
//! * the local backend is the library's `run_campaign` ([`CampaignPlan::run_local`]);
//! * another executor (the Ray backend) uses the same runner's three steps: [`CampaignPlan::prepare`]
//!   the output directory (a [`CampaignOutput`]: the runs left and the manifest), run each with
//!   [`CampaignPlan::run_one`] (the runner's `execute`, wherever the executor puts it; its record comes
//!   back as JSON text), [`CampaignOutput::append`] each record as it comes, then
//!   [`CampaignOutput::finish`] (`campaign.parquet` and `summary.md`).

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use satflock::campaign::{
    manifest, run_campaign, runner, Campaign, CampaignError as RustCampaignError, RunEvent,
    RunRecord, RunnerOptions,
};

use crate::convert::dict_to_table;
use crate::detached::run_detached;
use crate::errors::CampaignError;
use crate::law::{prepared_with, take_raised, PythonLawObject};

/// A campaign error as `satflock.CampaignError` (with the attributes `file` and `key`: the campaign
/// key at fault, dotted, or None), or `OSError` for an output that cannot be written.
fn campaign_error(e: &RustCampaignError) -> PyErr {
    let (file, key) = match e {
        RustCampaignError::Io { file, .. } | RustCampaignError::Parse { file, .. } => {
            (Some(file.clone()), None)
        }
        RustCampaignError::Invalid { file, key, .. } => (Some(file.clone()), Some(key.clone())),
        RustCampaignError::OutputDirectory { path, .. }
        | RustCampaignError::Resume { path, .. } => (Some(path.clone()), None),
        RustCampaignError::Output { .. } => return PyOSError::new_err(e.to_string()),
        _ => return PyRuntimeError::new_err(e.to_string()),
    };
    Python::attach(|py| {
        let err = CampaignError::new_err(e.to_string());
        let value = err.value(py);
        // Setting attributes on a fresh exception instance cannot fail short of memory exhaustion.
        let _ = value.setattr("file", file);
        let _ = value.setattr("key", key);
        err
    })
}

/// A validated campaign: every key checked (the campaign file's, then each `[set]` and `[vary]` value
/// through the scenario's validation) before anything runs. Built from a file, TOML text or a dict of
/// the file's keys; `text`, `file` and `base_dir` rebuild it elsewhere (a Ray worker).
#[pyclass(module = "satflock._native", name = "CampaignPlan", frozen)]
pub struct CampaignPlan {
    campaign: Campaign,
    text: String,
    base_dir: PathBuf,
}

impl CampaignPlan {
    fn parse(text: String, file: &str, base_dir: &Path) -> PyResult<Self> {
        let campaign =
            Campaign::from_toml(&text, file, base_dir).map_err(|e| campaign_error(&e))?;
        Ok(Self {
            campaign,
            text,
            base_dir: base_dir.to_path_buf(),
        })
    }
}

#[pymethods]
impl CampaignPlan {
    /// Reads a campaign file; a scenario path in it is relative to the file's folder. `file` names
    /// it in messages, the manifest and the table's metadata, as given.
    #[staticmethod]
    fn from_file(path: PathBuf) -> PyResult<Self> {
        let file = path.display().to_string();
        let text = satflock::input_file::read_document(&path).map_err(|e| {
            campaign_error(&RustCampaignError::Io {
                file: file.clone(),
                message: e.to_string(),
            })
        })?;
        let absolute = std::path::absolute(&path).map_err(|e| {
            campaign_error(&RustCampaignError::Io {
                file: file.clone(),
                message: e.to_string(),
            })
        })?;
        let base_dir = absolute.parent().unwrap_or(Path::new("/")).to_path_buf();
        Self::parse(text, &file, &base_dir)
    }

    /// Campaign TOML text; `file` names it in messages, `base_dir` resolves a scenario path.
    #[staticmethod]
    fn from_toml(text: String, file: &str, base_dir: PathBuf) -> PyResult<Self> {
        Self::parse(text, file, &base_dir)
    }

    /// A dict of the campaign file's keys (`scenario`, `seeds`, `set`, `vary`, `sampling`,
    /// `outcomes`, `keep_runs`, `description`); `file` names it, `base_dir` resolves a scenario path.
    #[staticmethod]
    fn from_dict(d: &Bound<'_, PyDict>, file: &str, base_dir: PathBuf) -> PyResult<Self> {
        let parse = |message: String| {
            campaign_error(&RustCampaignError::Parse {
                file: file.into(),
                message,
            })
        };
        let table = dict_to_table(d, "").map_err(parse)?;
        let text = toml::to_string(&table).map_err(|e| parse(e.to_string()))?;
        Self::parse(text, file, &base_dir)
    }

    /// The campaign's TOML text (for a dict, as written from it).
    #[getter]
    fn text(&self) -> &str {
        &self.text
    }

    /// The campaign file as given (`<dict>`, `<toml>` for those).
    #[getter]
    fn file(&self) -> &str {
        &self.campaign.file
    }

    /// The folder a scenario path resolves against (absolute).
    #[getter]
    fn base_dir(&self) -> PathBuf {
        self.base_dir.clone()
    }

    /// Number of runs: parameter points × seeds.
    #[getter]
    fn run_count(&self) -> usize {
        self.campaign.run_count()
    }

    /// Whether the campaign file says `keep_runs = true`.
    #[getter]
    fn keep_runs(&self) -> bool {
        self.campaign.keep_runs
    }

    /// Runs the campaign into `out` with the library's runner (`satflock campaign`): `jobs` runs at
    /// once (None: one per core), each on one thread. `on_event(kind, a, b)`, if given, is called
    /// from the worker threads: `("planned", runs to do, runs already complete)`, `("started", run,
    /// None)`, `("finished", run, status)`. The GIL is released; Ctrl-C stops the running runs
    /// (recorded as interrupted), writes the table and summary of what finished and raises
    /// `KeyboardInterrupt`. Returns the manifest lines `resume` dropped, each with why.
    #[pyo3(signature = (out, jobs = None, resume = false, keep_runs = false, on_event = None))]
    fn run_local(
        &self,
        py: Python<'_>,
        out: PathBuf,
        jobs: Option<usize>,
        resume: bool,
        keep_runs: bool,
        on_event: Option<Py<PyAny>>,
    ) -> PyResult<Vec<String>> {
        if jobs == Some(0) {
            return Err(PyValueError::new_err(
                "jobs = 0 (allowed: an integer >= 1, or None for one per core)",
            ));
        }
        let cancel = Arc::new(AtomicBool::new(false));
        let options = RunnerOptions {
            jobs,
            resume,
            keep_runs,
            cancel: Some(cancel.clone()),
        };
        let events = |event: RunEvent| {
            let Some(callback) = &on_event else { return };
            let (kind, a, b) = match event {
                RunEvent::Planned {
                    to_run,
                    already_complete,
                } => ("planned", to_run, Some(already_complete.to_string())),
                RunEvent::Started(run) => ("started", run, None),
                RunEvent::Finished(run, status) => ("finished", run, Some(status.as_str().into())),
            };
            Python::attach(|py| {
                if let Err(e) = callback.call1(py, (kind, a, b)) {
                    e.write_unraisable(py, None);
                }
            });
        };
        let report = run_detached(py, None, &cancel, || {
            run_campaign(&self.campaign, &out, &options, &events)
        })?
        .map_err(|e| campaign_error(&e))?;
        Ok(report.dropped)
    }

    /// Prepares `out` for the campaign (a new path or an empty folder; with `resume`, also this
    /// campaign's folder, whose completed runs are kept) and writes the manifest's header.
    #[pyo3(signature = (out, resume = false))]
    fn prepare(&self, out: PathBuf, resume: bool) -> PyResult<CampaignOutput> {
        let prepared =
            runner::prepare(&self.campaign, &out, resume).map_err(|e| campaign_error(&e))?;
        Ok(CampaignOutput {
            campaign: self.campaign.clone(),
            out,
            to_run: prepared.to_run.iter().map(|r| r.index).collect(),
            already_complete: prepared.already_complete,
            previous: prepared.previous,
            manifest: Some(prepared.manifest),
            dropped: prepared.dropped,
            ran: Vec::new(),
        })
    }

    /// Runs run `index` into `out/runs/NNNNN/` with the runner's own function, on `threads` rayon
    /// threads, and returns its record (`manifest.jsonl`'s line) as JSON text. A run that fails or is
    /// refused is recorded so, not raised. `keep_runs`: keep its full outputs (also when the campaign
    /// says so). The GIL is released; Ctrl-C stops the run (recorded as interrupted) and raises
    /// `KeyboardInterrupt`. `law`: a guidance law written in Python, run in place of the scenario's
    /// (as `satflock.run(law=...)`; one at a time under the GIL).
    #[pyo3(signature = (index, out, keep_runs = false, threads = 1, law = None))]
    fn run_one(
        &self,
        py: Python<'_>,
        index: usize,
        out: PathBuf,
        keep_runs: bool,
        threads: usize,
        law: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<String> {
        let count = self.campaign.run_count();
        if index >= count {
            return Err(PyValueError::new_err(format!(
                "run index {index} is out of range (allowed: 0 to {})",
                count - 1
            )));
        }
        let spec = self.campaign.run(index);
        let keep = keep_runs || self.campaign.keep_runs;
        let cancel = Arc::new(AtomicBool::new(false));
        let law = law.map(PythonLawObject::new).transpose()?;
        let raised = law.as_ref().map(PythonLawObject::raised);
        let record = run_detached(py, Some(threads), &cancel, || {
            runner::execute_with(
                &self.campaign,
                &spec,
                &out,
                keep,
                Some(cancel.clone()),
                |scenario| prepared_with(scenario, law),
            )
        })?;
        // A Python law that raised an exception failed its run (its row says so) and the campaign
        // goes on; a KeyboardInterrupt or SystemExit it raised is raised here, and stops it.
        if let Some(e) = raised.as_ref().and_then(take_raised) {
            return Err(e);
        }
        serde_json::to_string(&record).map_err(|e| PyRuntimeError::new_err(e.to_string()))
    }

    fn __repr__(&self) -> String {
        format!(
            "CampaignPlan(file={:?}, runs={})",
            self.campaign.file,
            self.campaign.run_count()
        )
    }
}

/// A campaign's output folder being filled by another executor: the runs left to do, the manifest
/// open for appending.
#[pyclass(module = "satflock._native", name = "CampaignOutput")]
pub struct CampaignOutput {
    campaign: Campaign,
    out: PathBuf,
    to_run: Vec<usize>,
    already_complete: usize,
    previous: Vec<RunRecord>,
    /// `None` once finished.
    manifest: Option<manifest::Writer>,
    dropped: Vec<String>,
    ran: Vec<RunRecord>,
}

#[pymethods]
impl CampaignOutput {
    /// Indices of the runs to do, in order (every run not recorded as completed).
    #[getter]
    fn to_run(&self) -> Vec<usize> {
        self.to_run.clone()
    }

    /// Runs the manifest recorded as completed before (resume).
    #[getter]
    fn already_complete(&self) -> usize {
        self.already_complete
    }

    /// The manifest lines `resume` dropped (unreadable, or contradicted by their run's folder or the
    /// campaign), each with why; their runs are in `to_run` unless another line completes them.
    #[getter]
    fn dropped(&self) -> Vec<String> {
        self.dropped.clone()
    }

    /// Appends a run's record (JSON text from `CampaignPlan.run_one`) to the manifest, flushed;
    /// returns its status (`completed`, `failed`, `refused`, `interrupted`).
    fn append(&mut self, record: &str) -> PyResult<String> {
        let record: RunRecord = serde_json::from_str(record)
            .map_err(|e| PyValueError::new_err(format!("record: not a run record: {e}")))?;
        let manifest = self.manifest.as_mut().ok_or_else(|| {
            PyValueError::new_err("the campaign output is finished (allowed: append before finish)")
        })?;
        manifest.append(&record).map_err(|e| campaign_error(&e))?;
        let status = record.status.as_str().to_string();
        self.ran.push(record);
        Ok(status)
    }

    /// Writes `campaign.parquet` and `summary.md` from the records (those kept from a resumed
    /// manifest, then the appended ones) and closes the manifest.
    fn finish(&mut self) -> PyResult<()> {
        if self.manifest.take().is_none() {
            return Err(PyValueError::new_err(
                "the campaign output is already finished (allowed: finish once)",
            ));
        }
        runner::finish(
            &self.campaign,
            &self.out,
            std::mem::take(&mut self.previous),
            std::mem::take(&mut self.ran),
            &self.dropped,
        )
        .map_err(|e| campaign_error(&e))?;
        Ok(())
    }
}
