//! `satflock export oem|czml|cdm RUN_DIR`: a finished (or stopped) run's trajectory as CCSDS OEMs (one
//! file per satellite) or a CZML document, or its conjunctions as CCSDS CDMs (one file per encounter),
//! written from the run directory by the library's `output::oem`, `output::czml` and `output::cdm`. An
//! output path that is one of the files the export reads (`summary.json`, `scene.json`, the metrics or
//! trajectory table) is refused (exit 2): the export would write over its own input.

use std::path::{Path, PathBuf};

use anyhow::Result;
use clap::builder::RangedU64ValueParser;
use clap::Subcommand;

use satflock::output::cdm;
use satflock::output::czml::{self, CzmlOptions};
use satflock::output::oem::{self, OemLayout};
use satflock::output::{ExportError, RunData};

use crate::usage;

/// The export formats.
#[derive(Subcommand)]
pub enum ExportCommand {
    /// CCSDS OEM (KVN) of every satellite's inertial (EME2000) states, in km and km/s: one file per
    /// satellite, sat-NNNNN.oem (the standard's one object per file). CREATION_DATE is now, or
    /// $SOURCE_DATE_EPOCH (seconds since 1970) when set.
    Oem {
        /// A run's output directory (as written by `satflock run`; needs its trajectory, trajectory.csv
        /// or trajectory.parquet).
        run_dir: PathBuf,
        /// NON-STANDARD: every satellite in one file, a segment each (RUN_DIR/swarm.oem by default).
        /// CCSDS 502.0-B-2/-B-3 define an OEM for a single object: readers that enforce it refuse it.
        #[arg(long)]
        single_file: bool,
        /// CCSDS_OEM_VERS: 2.0 (502.0-B-2) or 3.0 (502.0-B-3, with a MESSAGE_ID).
        #[arg(long, value_enum, default_value_t = OemVersionArg::V2)]
        oem_version: OemVersionArg,
        /// Output directory (default RUN_DIR/oem), or file with --single-file.
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// CCSDS CDM 508.0-B-1 (KVN), one file per encounter of the run's conjunction table: TCA in UTC,
    /// both objects' EME2000 states at TCA, the RTN relative state; a satellite's covariance is the
    /// diagonal of its navigation noise (zero without), said in COMMENT lines.
    Cdm {
        /// A run's output directory (its scenario needs `[conjunctions] threshold_m`).
        run_dir: PathBuf,
        /// Output directory (default RUN_DIR/cdm).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Only the K encounters with the smallest miss distances.
        #[arg(long, conflicts_with = "below",
              value_parser = RangedU64ValueParser::<usize>::new().range(1..))]
        top: Option<usize>,
        /// Only the encounters with a miss distance below M metres (M finite, > 0).
        #[arg(long, value_name = "M")]
        below: Option<f64>,
    },
    /// CZML for CesiumJS: the satellites' inertial positions in metres, decimated to stay loadable (what
    /// was kept is printed and written into the document's description).
    Czml {
        /// A run's output directory (as written by `satflock run`; needs its trajectory, trajectory.csv
        /// or trajectory.parquet).
        run_dir: PathBuf,
        /// Most satellites in the document, evenly spaced among the run's indices.
        #[arg(long, default_value_t = czml::DEFAULT_MAX_SATELLITES,
              value_parser = RangedU64ValueParser::<usize>::new().range(1..))]
        max_satellites: usize,
        /// Most samples per satellite: every k-th recorded time, the smallest k that fits.
        #[arg(long, default_value_t = czml::DEFAULT_MAX_SAMPLES,
              value_parser = RangedU64ValueParser::<usize>::new().range(1..))]
        max_samples: usize,
        /// Draw each satellite's path (by default drawn only for at most 100 satellites).
        #[arg(long)]
        paths: bool,
        /// Output file (default RUN_DIR/swarm.czml).
        #[arg(long)]
        out: Option<PathBuf>,
    },
}

/// `--oem-version`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum OemVersionArg {
    /// CCSDS 502.0-B-2.
    #[value(name = "2.0")]
    V2,
    /// CCSDS 502.0-B-3.
    #[value(name = "3.0")]
    V3,
}

/// An export error: a run directory that cannot be read or an option out of range is the user's input
/// (exit 2); a file that cannot be written is exit 1.
fn export_error(e: ExportError) -> anyhow::Error {
    match e {
        ExportError::Input(_) | ExportError::Option { .. } => usage(e.to_string()),
        other => other.into(),
    }
}

fn read_run(dir: &Path) -> Result<RunData> {
    RunData::read(dir).map_err(|e| usage(e.to_string()))
}

/// Refuses an output path that is one of the files `run` was read from (compared as canonical paths,
/// so `RUN/./summary.json` or a link to it is caught too).
fn refuse_own_file(run: &RunData, out: &Path) -> Result<()> {
    let Ok(target) = out.canonicalize() else {
        return Ok(()); // a path that does not exist yet is no file of the run
    };
    if run
        .files
        .iter()
        .any(|f| f.canonicalize().is_ok_and(|f| f == target))
    {
        return Err(usage(format!(
            "--out {}: is a file of the run directory the export reads (allowed: any other path; \
             the export would write over its own input)",
            out.display()
        )));
    }
    Ok(())
}

/// Runs one export command.
pub fn export_command(command: ExportCommand) -> Result<()> {
    match command {
        ExportCommand::Oem {
            run_dir,
            single_file,
            oem_version,
            out,
        } => {
            let run = read_run(&run_dir)?;
            let creation = oem::creation_date().map_err(usage)?;
            let layout = match (out, single_file) {
                (None, _) => OemLayout::in_run_dir(&run_dir, single_file),
                (Some(dir), false) => {
                    if dir.is_file() {
                        return Err(usage(format!(
                            "--out {}: is a file (allowed: a directory, or a file path with \
                             --single-file)",
                            dir.display()
                        )));
                    }
                    OemLayout::PerSatellite(dir)
                }
                (Some(file), true) => {
                    if file.is_dir() {
                        return Err(usage(format!(
                            "--out {}: is a directory (allowed: a file path with --single-file, or \
                             a directory without it)",
                            file.display()
                        )));
                    }
                    refuse_own_file(&run, &file)?;
                    OemLayout::OneFile(file)
                }
            };
            let version = match oem_version {
                OemVersionArg::V2 => oem::OemVersion::V2,
                OemVersionArg::V3 => oem::OemVersion::V3,
            };
            let (files, segments) =
                oem::write_run_oem(&run, &layout, creation, version).map_err(export_error)?;
            let target = match &layout {
                OemLayout::OneFile(path) => path.display().to_string(),
                OemLayout::PerSatellite(dir) => {
                    format!("{} files in {}", files.len(), dir.display())
                }
            };
            eprintln!("OEM: {segments} satellites (EME2000, km and km/s, UTC) written to {target}");
            Ok(())
        }
        ExportCommand::Cdm {
            run_dir,
            out,
            top,
            below,
        } => {
            let selection = match (top, below) {
                (Some(k), _) => cdm::Selection::Top(k),
                (None, Some(m)) if m.is_finite() && m > 0.0 => cdm::Selection::Below(m),
                (None, Some(m)) => {
                    return Err(usage(format!(
                        "--below {m}: is out of range (allowed: a finite miss distance > 0 m)"
                    )))
                }
                (None, None) => cdm::Selection::All,
            };
            let run = read_run(&run_dir)?;
            let creation = oem::creation_date().map_err(usage)?;
            let dir = out.unwrap_or_else(|| run_dir.join(cdm::RUN_DIR_NAME));
            if dir.is_file() {
                return Err(usage(format!(
                    "--out {}: is a file (allowed: a directory)",
                    dir.display()
                )));
            }
            let files =
                cdm::write_run_cdm(&run, &dir, selection, creation).map_err(export_error)?;
            eprintln!(
                "CDM: {} encounters (CCSDS 508.0-B-1, EME2000, km and km/s, UTC) written to {}",
                files.len(),
                dir.display()
            );
            Ok(())
        }
        ExportCommand::Czml {
            run_dir,
            max_satellites,
            max_samples,
            paths,
            out,
        } => {
            let run = read_run(&run_dir)?;
            let path = out.unwrap_or_else(|| run_dir.join(czml::RUN_FILE));
            if path.is_dir() {
                return Err(usage(format!(
                    "--out {}: is a directory (allowed: a file path)",
                    path.display()
                )));
            }
            refuse_own_file(&run, &path)?;
            let options = CzmlOptions {
                max_satellites,
                max_samples,
                paths: paths.then_some(true),
            };
            let kept = czml::write_run_czml(&run, &path, &options).map_err(export_error)?;
            eprintln!("CZML: {}; written to {}", kept.describe(), path.display());
            Ok(())
        }
    }
}
