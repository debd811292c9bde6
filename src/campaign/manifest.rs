//! `manifest.jsonl`, the campaign's record of what ran: a header line (the campaign file's and the
//! scenario's SHA-256, the satflock version, the seeds, the run count), then one JSON line per finished
//! run, appended and flushed as each run finishes (in the order they finish; a run run again by
//! `--resume` gets a new line, and the last line of a run wins).
//!
//! `--resume` trusts no line: a line that does not read as a record (cut short by a kill, or edited) and
//! a record that its run's directory or the campaign contradicts are dropped, said on stderr and in
//! `summary.md`, and their runs run again ([`super::runner::prepare`]).

use std::collections::BTreeMap;
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::Path;

use serde::{Deserialize, Serialize};

use super::file::Campaign;
use super::CampaignError;

/// Name of the manifest in the output directory.
pub const FILE_NAME: &str = "manifest.jsonl";

/// Version of the manifest's layout.
pub const FORMAT: u32 = 1;

/// The first line of the manifest.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Header {
    /// Layout version ([`FORMAT`]).
    pub format: u32,
    /// The campaign file as given.
    pub campaign: String,
    /// SHA-256 of the campaign file.
    pub campaign_sha256: String,
    /// The scenario (`builtin:NAME` or a path).
    pub scenario: String,
    /// SHA-256 of the scenario's text.
    pub scenario_sha256: String,
    /// The satflock version that wrote it.
    pub satflock_version: String,
    /// Seeds of every parameter point.
    pub seeds: Vec<u64>,
    /// Parameter points.
    pub points: usize,
    /// Runs: points × seeds.
    pub runs: usize,
}

impl Header {
    /// The header of `campaign`.
    pub fn of(campaign: &Campaign) -> Self {
        Self {
            format: FORMAT,
            campaign: campaign.file.clone(),
            campaign_sha256: campaign.sha256.clone(),
            scenario: campaign.scenario.source.clone(),
            scenario_sha256: campaign.scenario.sha256.clone(),
            satflock_version: env!("CARGO_PKG_VERSION").into(),
            seeds: campaign.seeds.clone(),
            points: campaign.points.len(),
            runs: campaign.run_count(),
        }
    }

    /// Why a manifest with this header cannot be resumed by `campaign` (`None`: it can).
    pub fn mismatch(&self, campaign: &Campaign) -> Option<String> {
        let ours = Self::of(campaign);
        if self.format != ours.format {
            return Some(format!(
                "manifest layout {} (this satflock reads layout {})",
                self.format, ours.format
            ));
        }
        if self.campaign_sha256 != ours.campaign_sha256 {
            return Some(format!(
                "the campaign file changed since the manifest was written (SHA-256 {} then, {} now)",
                self.campaign_sha256, ours.campaign_sha256
            ));
        }
        if self.scenario_sha256 != ours.scenario_sha256 {
            return Some(format!(
                "the scenario {} changed since the manifest was written (SHA-256 {} then, {} now)",
                ours.scenario, self.scenario_sha256, ours.scenario_sha256
            ));
        }
        if self.satflock_version != ours.satflock_version {
            return Some(format!(
                "the manifest was written by satflock {}, this is {} (results could differ)",
                self.satflock_version, ours.satflock_version
            ));
        }
        None
    }
}

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Status {
    /// Ran to its end.
    Completed,
    /// Stopped early (diverged, or its outputs could not be written); its summary holds what it
    /// reached.
    Failed,
    /// The scenario or the engine refused this combination of values before it started.
    Refused,
    /// Stopped by a signal; `--resume` runs it again.
    Interrupted,
}

impl Status {
    /// The status as written (`completed`, `failed`, `refused`, `interrupted`).
    pub fn as_str(self) -> &'static str {
        match self {
            Status::Completed => "completed",
            Status::Failed => "failed",
            Status::Refused => "refused",
            Status::Interrupted => "interrupted",
        }
    }
}

/// One finished run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunRecord {
    /// Run index.
    pub run: usize,
    /// Parameter point index.
    pub point: usize,
    /// Scenario seed.
    pub seed: u64,
    /// The varied keys' values.
    pub parameters: BTreeMap<String, serde_json::Value>,
    /// How it ended.
    pub status: Status,
    /// Why it did not complete.
    pub error: Option<String>,
    /// Every scalar outcome of its `summary.json` ([`crate::output::outcomes::scalar_outcomes`]); empty
    /// when it wrote none.
    pub outcomes: BTreeMap<String, f64>,
}

/// The manifest, open for appending.
pub struct Writer {
    file: File,
    path: String,
}

impl Writer {
    /// Starts a manifest at `path` with `header` and `records` (written whole, then opened for
    /// appending).
    pub fn create(
        path: &Path,
        header: &Header,
        records: &[RunRecord],
    ) -> Result<Self, CampaignError> {
        let mut text = serde_json::to_string(header).expect("the header serialises") + "\n";
        for r in records {
            text.push_str(&(serde_json::to_string(r).expect("a record serialises") + "\n"));
        }
        let output = |e: std::io::Error| CampaignError::Output {
            path: path.display().to_string(),
            message: e.to_string(),
        };
        let partial = path.with_extension("jsonl.partial");
        std::fs::write(&partial, text).map_err(output)?;
        std::fs::rename(&partial, path).map_err(output)?;
        let file = OpenOptions::new().append(true).open(path).map_err(output)?;
        Ok(Self {
            file,
            path: path.display().to_string(),
        })
    }

    /// Appends one record in one write, and flushes it.
    pub fn append(&mut self, record: &RunRecord) -> Result<(), CampaignError> {
        let line = serde_json::to_string(record).expect("a record serialises") + "\n";
        self.file
            .write_all(line.as_bytes())
            .and_then(|()| self.file.flush())
            .map_err(|e| CampaignError::Output {
                path: self.path.clone(),
                message: e.to_string(),
            })
    }
}

/// A manifest read back by [`read`].
#[derive(Clone, Debug)]
pub struct Contents {
    /// The header.
    pub header: Header,
    /// Every line that reads as a record, with its line number (from 1), in file order.
    pub records: Vec<(usize, RunRecord)>,
    /// Line numbers (from 1) of the lines after the header that do not read as a record (a line cut
    /// short by a kill, or anything else).
    pub unreadable: Vec<usize>,
}

/// Reads a manifest: its header, every line that reads as a record, and the lines that do not.
pub fn read(path: &Path) -> Result<Contents, CampaignError> {
    let fail = |message: String| CampaignError::Resume {
        path: path.display().to_string(),
        message,
    };
    let text = crate::input_file::read_to_string(path, crate::input_file::MAX_TABLE_BYTES)
        .map_err(|e| fail(e.to_string()))?;
    let mut lines = text.lines();
    let header: Header = lines
        .next()
        .and_then(|l| serde_json::from_str(l).ok())
        .ok_or_else(|| fail("the first line is not a campaign manifest header".into()))?;
    let mut records = Vec::new();
    let mut unreadable = Vec::new();
    for (k, line) in lines.enumerate() {
        match serde_json::from_str::<RunRecord>(line) {
            Ok(record) => records.push((k + 2, record)),
            Err(_) => unreadable.push(k + 2),
        }
    }
    Ok(Contents {
        header,
        records,
        unreadable,
    })
}
