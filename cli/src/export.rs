//! `satflock export oem|czml RUN_DIR`: a finished (or stopped) run's trajectory as a CCSDS OEM or a CZML
//! document, written from the run directory by the library's `output::oem` and `output::czml`. An
//! output path that is one of the files the export reads (`summary.json`, `scene.json`, the metrics or
//! trajectory table) is refused (exit 2): the export would write over its own input.

use std::path::{Path, PathBuf};

use anyhow::Result;
use clap::builder::RangedU64ValueParser;
use clap::Subcommand;

use satflock::output::czml::{self, CzmlOptions};
use satflock::output::oem::{self, OemLayout};
use satflock::output::{ExportError, RunData};

use crate::usage;

/// The export formats.
#[derive(Subcommand)]
pub enum ExportCommand {
    /// CCSDS OEM 2.0 (KVN) of every satellite's inertial (EME2000) states, in km and km/s, one segment
    /// per satellite. CREATION_DATE is now, or $SOURCE_DATE_EPOCH (seconds since 1970) when set.
    Oem {
        /// A run's output directory (as written by `satflock run`; needs its trajectory, trajectory.csv
        /// or trajectory.parquet).
        run_dir: PathBuf,
        /// One file per satellite, sat-NNNNN.oem, in a directory (default RUN_DIR/oem).
        #[arg(long)]
        per_satellite: bool,
        /// Output file (default RUN_DIR/swarm.oem), or directory with --per-satellite.
        #[arg(long)]
        out: Option<PathBuf>,
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
            per_satellite,
            out,
        } => {
            let run = read_run(&run_dir)?;
            let creation = oem::creation_date().map_err(usage)?;
            let layout = match (out, per_satellite) {
                (None, _) => OemLayout::in_run_dir(&run_dir, per_satellite),
                (Some(dir), true) => OemLayout::PerSatellite(dir),
                (Some(file), false) => {
                    if file.is_dir() {
                        return Err(usage(format!(
                            "--out {}: is a directory (allowed: a file path, or a directory with \
                             --per-satellite)",
                            file.display()
                        )));
                    }
                    refuse_own_file(&run, &file)?;
                    OemLayout::OneFile(file)
                }
            };
            let (files, segments) =
                oem::write_run_oem(&run, &layout, creation).map_err(export_error)?;
            let target = match &layout {
                OemLayout::OneFile(path) => path.display().to_string(),
                OemLayout::PerSatellite(dir) => {
                    format!("{} files in {}", files.len(), dir.display())
                }
            };
            eprintln!("OEM: {segments} satellites (EME2000, km and km/s, UTC) written to {target}");
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
