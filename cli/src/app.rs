//! The `satflock` command line ([`crate::main_with`]): a thin layer over the library's public API.
//!
//! Exit codes: 0 success, 1 a run that failed (diverged, could not write; collisions with
//! `--fail-on-collision`), 2 bad arguments or input, 130 / 143 a run interrupted by SIGINT / SIGTERM
//! (its files closed and `summary.json` written with status `interrupted`). `satflock campaign` exits 0
//! when the campaign ran even if some of its runs failed (see `campaign.rs`).

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;

use anyhow::{bail, Context, Result};
use clap::{Parser, Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};

use satflock::dynamics::{ForceSet, ForcesConfig, PhysicalProperties};
use satflock::guidance::LawRegistry;
use satflock::integrate::{IntegratorMethod, Tolerances};
use satflock::orbit::{CartesianState, EarthModel, GravityModel, KeplerianElements, Vector3};
use satflock::output::export::write_whole;
use satflock::output::oem::{self, OemMessage, OemObject};
use satflock::output::OutputFormat;
use satflock::output::{frames, InertialTrack};
use satflock::propagate::{propagate, OutputFrame, PropagationSettings};
use satflock::run::{run_prepared, RunError, RunOptions};
use satflock::scenario::{builtin, Controller, Scenario};
use satflock::swarm::SimError;

use crate::{bench, budget, campaign, characterize, export};

#[derive(Parser)]
#[command(
    name = "satflock",
    version,
    about = "Simulate and steer satellite swarms under J2"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Performance measurements, one JSON line per case. Without a subcommand, the suite: propagation and
    /// the guided step of each law at N = 1e3 … 1e6, five elements on 1e5 positions (throughput, wall
    /// time, peak memory, the engine's stage split), then a Markdown table; each case runs in a child
    /// process. `satflock bench propagate`: N independent satellites through the fused RK4 kernel.
    Bench(bench::BenchArgs),
    /// Run a scenario (a TOML file or a built-in name) and write summary.json, the metrics and
    /// trajectory tables (CSV or Parquet), scene.json and scenario.toml into the output directory, then
    /// draw its figures into OUT/plots/ (unless --no-plots).
    ///
    /// SIGINT or SIGTERM stops the run after the current step: the files are closed, summary.json says
    /// `interrupted`, and the exit code is 130 or 143 (a second signal exits at once).
    #[command(allow_negative_numbers = true)]
    Run {
        /// Scenario file, or the name of a built-in scenario (see `satflock scenarios`).
        scenario: String,
        /// Output directory: a new path, an empty directory, or a previous satflock run's directory
        /// (holding only the files a run writes), whose files are removed before the
        /// run starts. A directory holding anything else is refused.
        #[arg(long)]
        out: PathBuf,
        /// Worker threads, 1 to 1024 (default: all cores). Results do not depend on it.
        #[arg(long, value_parser = clap::value_parser!(u16).range(1..=MAX_THREADS))]
        threads: Option<u16>,
        /// No progress bar.
        #[arg(long)]
        quiet: bool,
        /// Exit with code 1 if satellites collided (by default a collision is a warning on stderr and in
        /// summary.json's `warnings`, and the run exits 0).
        #[arg(long)]
        fail_on_collision: bool,
        /// File format of the metrics and trajectory tables, overriding the scenario's `[output]
        /// format` (default: CSV, except a trajectory of more than 1000 satellites, which is Parquet).
        #[arg(long, value_enum)]
        format: Option<FormatArg>,
        /// Also write the offline HTML report, OUT/report.html (as `satflock report OUT`), when the run
        /// wrote its summary (also after a run that stopped).
        #[arg(long)]
        report: bool,
        /// Do not draw the figures into OUT/plots/ after the run (`satflock plot OUT` draws them later).
        #[arg(long)]
        no_plots: bool,
        /// Steer the scenario with another controller: a controller file (a `[law]` table, optionally
        /// `[control]` and law `[[events]]`) or `builtin:NAME` (a built-in scenario's law, law events
        /// and control timing). It replaces the scenario's law, law events and (if it gives one) control
        /// timing; the rest of the scenario (the case) is kept.
        #[arg(long, value_name = "FILE.toml|builtin:NAME")]
        law: Option<String>,
    },
    /// Run every controller (law) on the same case and the same seeds, in parallel, and write a
    /// side-by-side table: OUT/compare.md (also on stdout), OUT/compare.parquet (one row per run),
    /// overlay plots in OUT/plots/ and each run's directory in OUT/runs/LABEL/seed-N/.
    ///
    /// Every law starts from the same initial states (they depend only on the case and the seed). A run
    /// that fails or that the case refuses for a law is a row with its status and error. Exit 0 when
    /// the table is written (runs not completed are said on stderr), 2 for bad input.
    Compare {
        /// The case: a scenario file or a built-in name (its law, law events and control timing are
        /// replaced by each --law's).
        case: String,
        /// A controller, once per law: a file (a `[law]` table, optionally `[control]` and law
        /// `[[events]]`) or `builtin:NAME` (a built-in scenario's controller). Its label in the table
        /// is the file name without extension, or NAME.
        #[arg(long = "law", required = true, value_name = "FILE.toml|builtin:NAME")]
        laws: Vec<String>,
        /// Seeds: `A..B` (A to B, both included), a list `A,B,C`, or one seed (default: the case's
        /// seed).
        #[arg(long)]
        seeds: Option<String>,
        /// Output directory: a new path, an empty directory or a previous comparison's directory
        /// (whose outputs are removed first). A directory holding anything else is refused.
        #[arg(long)]
        out: PathBuf,
        /// Runs at once, 1 to 1024 (default: the number of cores); each run uses one thread. Results
        /// do not depend on it.
        #[arg(long, value_parser = clap::value_parser!(u16).range(1..=MAX_THREADS))]
        jobs: Option<u16>,
        /// Keep each run's trajectory table too (default: each run keeps its summary, metrics,
        /// scene.json and scenario.toml).
        #[arg(long)]
        keep_runs: bool,
        /// No progress bar.
        #[arg(long)]
        quiet: bool,
    },
    /// Write RUN_DIR/report.html: one self-contained page (works offline) with the scenario, a summary
    /// table, the plots in RUN_DIR/plots/ and an animated 3-D view of the swarm in Hill LVLH.
    Report {
        /// A run's output directory (as written by `satflock run`).
        run_dir: PathBuf,
    },
    /// Draw the figures of a run directory into RUN_DIR/plots/ (PNG and SVG): relative motion in
    /// the three RTN/Hill projections and snapshots, the nearest-neighbour separations at the end,
    /// metrics over time, delta-v. `satflock run` draws them too.
    Plot {
        /// A run's output directory (as written by `satflock run`).
        run_dir: PathBuf,
        /// Draw the tracks of these satellites only (ids, comma-separated; default: all, an evenly
        /// spaced subsample beyond 200).
        #[arg(long, value_delimiter = ',')]
        satellites: Option<Vec<usize>>,
    },
    /// List the built-in scenarios with the first sentence of each description; `scenarios show NAME`
    /// prints one as TOML, to copy and edit.
    Scenarios {
        #[command(subcommand)]
        action: Option<ScenariosAction>,
    },
    /// Print the five-element characterisation of a set of positions as JSON.
    ///
    /// The positions come from a CSV file with columns x_m,y_m,z_m and optionally radius_m, or from a
    /// run's trajectory file (trajectory.csv or trajectory.parquet): the Hill LVLH positions of the
    /// satellites at one recorded time (stderr says which).
    #[command(allow_negative_numbers = true)]
    Characterize {
        /// CSV with columns x_m,y_m,z_m[,radius_m] (any common frame), or a run's trajectory file.
        positions: PathBuf,
        /// With a trajectory file: the recorded time nearest to this [s] (default: the last one).
        #[arg(long)]
        time_s: Option<f64>,
    },
    /// Propagate one orbit (no control) and write its states to CSV (and, with --oem, a CCSDS OEM).
    #[command(allow_negative_numbers = true)]
    Propagate(PropagateArgs),
    /// Print the perturbation budget of a satellite pair on a circular orbit: for J2..J6, drag, SRP,
    /// the Sun, the Moon and the HCW linearisation error, the acceleration on satellite 1, the
    /// differential acceleration and the along-track drift it causes per orbit and per day (orders of
    /// magnitude for deciding what to neglect; see docs/dynamics.md).
    #[command(allow_negative_numbers = true)]
    Budget(budget::BudgetArgs),
    /// Export a run directory: its trajectory as `oem` (CCSDS OEM, one file per satellite) or `czml`
    /// (CesiumJS), its conjunctions as `cdm` (CCSDS CDM, one file per encounter).
    Export {
        #[command(subcommand)]
        format: export::ExportCommand,
    },
    /// Run a campaign: one scenario over seeds and parameters varied by dotted key (value lists as a
    /// grid, ranges by Latin hypercube or at random), in parallel, into OUT: manifest.jsonl,
    /// runs/NNNNN/summary.json, campaign.parquet, summary.md and plots/ (see docs/campaigns.md).
    Campaign(campaign::CampaignArgs),
    /// Run a full-length reproduction (papers, analytic references) and print reported vs reproduced
    /// as a Markdown table. Targets: `core`, `gao`, `pigeon`, `scatter`, `takahashi`, `takahashi-split`
    /// (see `satflock validate --list`). A paper's outcomes, values and criteria are the data files of
    /// `validation/`; `--json` gives the measurement, which `--from` renders again without running.
    Validate {
        /// Target name: `core`, `gao`, `pigeon`, `scatter`, `takahashi` or `takahashi-split`.
        #[arg(required_unless_present = "list")]
        target: Option<String>,
        /// List the targets.
        #[arg(long)]
        list: bool,
        /// Print JSON (the measurement, e.g. for `validation/measured/TARGET.json`) instead of Markdown.
        #[arg(long, conflicts_with = "markdown")]
        json: bool,
        /// Print Markdown (the default).
        #[arg(long)]
        markdown: bool,
        /// Render a saved measurement (a `--json` output) with today's data files instead of running.
        #[arg(long, value_name = "FILE")]
        from: Option<PathBuf>,
    },
}

#[derive(Subcommand)]
enum ScenariosAction {
    /// Print a built-in scenario's TOML (`satflock scenarios show gao-circle > mine.toml`).
    Show {
        /// Built-in scenario name.
        name: String,
        /// Print this file the scenario reads (an orbit file embedded with it) instead of its TOML.
        #[arg(long, value_name = "FILE")]
        file: Option<String>,
    },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum FormatArg {
    /// metrics.csv, trajectory.csv.
    Csv,
    /// metrics.parquet, trajectory.parquet.
    Parquet,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum FrameArg {
    /// ECI.
    Inertial,
    /// Hill/RSW LVLH of the reference orbit (x radial, y along-track, z orbit normal).
    LvlhHill,
    /// Gao o-xyz LVLH of the reference orbit (x along-track, y minus orbit normal, z nadir).
    LvlhGao,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum GravityArg {
    /// Point mass.
    TwoBody,
    /// Point mass + J2.
    J2,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum IntegratorArg {
    /// Fixed-step RK4 (step --step-s).
    Rk4,
    /// Adaptive Runge-Kutta-Fehlberg 7(8) (--rtol, --atol, longest step --step-s).
    Rk78,
    /// Adaptive Dormand-Prince 8(5,3) (--rtol, --atol, longest step --step-s).
    Dop853,
}

#[derive(clap::Args)]
struct PropagateArgs {
    /// Classical elements: a_m,e,i_deg,raan_deg,argp_deg,nu_deg.
    #[arg(
        long,
        allow_hyphen_values = true,
        conflicts_with = "state",
        required_unless_present = "state"
    )]
    elements: Option<String>,
    /// ECI state: x_m,y_m,z_m,vx_mps,vy_mps,vz_mps.
    #[arg(long, allow_hyphen_values = true)]
    state: Option<String>,
    /// Length of the propagation [s].
    #[arg(long)]
    duration_s: f64,
    /// Output spacing [s]: rows at exact multiples from t = 0.
    #[arg(long)]
    output_step_s: f64,
    /// Gravity model (default j2), when no --forces file gives the force set.
    #[arg(long, value_enum, conflicts_with = "forces")]
    gravity: Option<GravityArg>,
    /// A force file (TOML: [gravity], [drag], [srp], [third_body] and the satellite's [satellite]
    /// properties, as a scenario's [dynamics.forces]; see docs/dynamics.md). The epoch of t = 0 is
    /// --epoch-utc.
    #[arg(long)]
    forces: Option<PathBuf>,
    /// Integrator.
    #[arg(long, value_enum, default_value = "rk78")]
    integrator: IntegratorArg,
    /// RK4 step, or longest adaptive step [s].
    #[arg(long, default_value_t = 10.0)]
    step_s: f64,
    /// Relative tolerance of rk78.
    #[arg(long, default_value_t = 1e-12)]
    rtol: f64,
    /// Absolute tolerance of rk78 [m, m/s].
    #[arg(long, default_value_t = 1e-6)]
    atol: f64,
    /// Earth gravitational parameter [m^3/s^2] (default WGS 84 / EGM96).
    #[arg(long)]
    mu: Option<f64>,
    /// Earth equatorial radius [m] (default WGS 84 / EGM96).
    #[arg(long)]
    earth_radius_m: Option<f64>,
    /// J2 (default WGS 84 / EGM96).
    #[arg(long)]
    j2: Option<f64>,
    /// Output frame. The LVLH frames need a reference orbit (--reference-elements or --reference-state),
    /// propagated with the same settings.
    #[arg(long, value_enum, default_value = "inertial")]
    frame: FrameArg,
    /// Reference orbit for LVLH output, as classical elements a_m,e,i_deg,raan_deg,argp_deg,nu_deg.
    #[arg(long, allow_hyphen_values = true, conflicts_with = "reference_state")]
    reference_elements: Option<String>,
    /// Reference orbit for LVLH output, as an ECI state x_m,y_m,z_m,vx_mps,vy_mps,vz_mps.
    #[arg(long, allow_hyphen_values = true)]
    reference_state: Option<String>,
    /// Output CSV file (written only if the propagation succeeds).
    #[arg(long)]
    out: PathBuf,
    /// Also write the orbit as a CCSDS OEM 2.0 file (EME2000, km and km/s, UTC epochs from
    /// --epoch-utc); needs --frame inertial.
    #[arg(long)]
    oem: Option<PathBuf>,
    /// The instant of t = 0 (ISO 8601 UTC): the OEM's epochs and the force models' time (Sun, Moon,
    /// the atmosphere's diurnal bulge).
    #[arg(long, default_value = satflock::time::DEFAULT_EPOCH_UTC)]
    epoch_utc: String,
}

/// Largest `--threads`.
pub(crate) const MAX_THREADS: i64 = 1024;

/// An error in the user's input: exit code 2.
#[derive(Debug)]
struct UsageError(String);

/// A run stopped by a signal (its summary is written): exit code 128 + the signal number.
#[derive(Debug)]
pub(crate) struct Interrupted {
    pub(crate) signal: i32,
    pub(crate) message: String,
}

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Interrupted {}

impl std::fmt::Display for UsageError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for UsageError {}

/// An error in the user's input (exit code 2).
/// Writes `text` to standard output. A reader that closed the pipe early (`satflock scenarios | head`)
/// has all it wanted: the process ends quietly with exit 0, as Unix filters do, instead of panicking in
/// `println!`.
pub(crate) fn print_out(text: &str) -> Result<()> {
    use std::io::Write as _;
    let mut stdout = std::io::stdout().lock();
    match stdout
        .write_all(text.as_bytes())
        .and_then(|()| stdout.flush())
    {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => std::process::exit(0),
        other => other.context("cannot write to standard output"),
    }
}

pub(crate) fn usage(message: impl Into<String>) -> anyhow::Error {
    UsageError(message.into()).into()
}

/// The `satflock` command line on `args` (the program name first), with the laws of `registry`
/// installed as the process's ([`LawRegistry::install`]).
pub(crate) fn main_with_args<I, T>(registry: LawRegistry, args: I) -> ExitCode
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    registry.install();
    let cli = Cli::parse_from(args);
    // A file-size limit (`ulimit -f`) would kill the process with SIGXFSZ mid-write, leaving broken
    // files and no summary: with a handler the write fails with EFBIG instead, and the run stops with
    // its files closed and `summary.json` saying why.
    if let Err(e) = signal_hook::flag::register(
        signal_hook::consts::SIGXFSZ,
        Arc::new(AtomicBool::new(false)),
    ) {
        eprintln!("error: cannot install the SIGXFSZ handler: {e}");
        return ExitCode::from(1);
    }
    let result = match cli.command {
        Command::Run {
            scenario,
            out,
            threads,
            quiet,
            fail_on_collision,
            report,
            format,
            no_plots,
            law,
        } => {
            let outcome = load_scenario(&scenario, law.as_deref()).and_then(|scenario| {
                run(
                    &scenario,
                    &out,
                    threads.map(usize::from),
                    quiet,
                    fail_on_collision,
                    format.map(|f| match f {
                        FormatArg::Csv => OutputFormat::Csv,
                        FormatArg::Parquet => OutputFormat::Parquet,
                    }),
                    !no_plots,
                )
            });
            // A run that started (completed, stopped or interrupted) has valid files and a summary;
            // refused input never touched the directory.
            let started = outcome
                .as_ref()
                .map_or_else(|e| e.downcast_ref::<UsageError>().is_none(), |()| true);
            if report && started && out.join("summary.json").is_file() {
                match (outcome, report_command(&out, quiet)) {
                    (Err(e), Err(r)) => {
                        eprintln!("error: {r:#}");
                        Err(e)
                    }
                    (outcome, written) => outcome.and(written),
                }
            } else {
                outcome
            }
        }
        Command::Compare {
            case,
            laws,
            seeds,
            out,
            jobs,
            keep_runs,
            quiet,
        } => compare_command(
            crate::compare::CompareOptions {
                case,
                laws,
                seeds: None,
                out,
                jobs: jobs.map_or_else(
                    || std::thread::available_parallelism().map_or(1, usize::from),
                    usize::from,
                ),
                keep_runs,
                progress: !quiet,
                cancel: None,
            },
            seeds.as_deref(),
        ),
        Command::Report { run_dir } => report_command(&run_dir, false),
        Command::Plot {
            run_dir,
            satellites,
        } => plot_command(&run_dir, satellites.as_deref()),
        Command::Scenarios { action: None } => scenarios(),
        Command::Scenarios {
            action: Some(ScenariosAction::Show { name, file }),
        } => match (builtin::find(&name), file) {
            (Some(b), None) => print_out(b.toml),
            (Some(b), Some(file)) => match builtin::file(b.name, &file) {
                Some(text) => print_out(text),
                None => Err(usage(format!(
                    "the built-in scenario `{name}` embeds no file `{file}` (it embeds: {})",
                    match builtin::files(b.name).join(", ") {
                        none if none.is_empty() => "none".to_string(),
                        some => some,
                    }
                ))),
            },
            (None, _) => Err(usage(format!(
                "no built-in scenario `{name}` (built-in: {})",
                builtin::names().join(", ")
            ))),
        },
        Command::Characterize { positions, time_s } => characterize::run(&positions, time_s),
        Command::Propagate(args) => propagate_command(&args),
        Command::Budget(args) => budget::budget_command(&args),
        Command::Export { format } => export::export_command(format),
        Command::Validate {
            target,
            list,
            json,
            markdown: _,
            from,
        } => validate_command(target.as_deref(), list, json, from.as_deref()),
        Command::Campaign(args) => campaign::campaign_command(&args),
        Command::Bench(args) => bench::bench_command(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            if let Some(i) = e.downcast_ref::<Interrupted>() {
                ExitCode::from((128 + i.signal) as u8)
            } else if e.downcast_ref::<UsageError>().is_some() {
                ExitCode::from(2)
            } else {
                ExitCode::from(1)
            }
        }
    }
}

/// Routes SIGINT and SIGTERM to a cancel flag the run polls after every segment (and records which
/// signal came); a second signal exits at once with code 1.
pub(crate) fn install_signal_handlers() -> Result<(Arc<AtomicBool>, Arc<AtomicUsize>)> {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let cancel = Arc::new(AtomicBool::new(false));
    let which = Arc::new(AtomicUsize::new(0));
    for signal in [SIGINT, SIGTERM] {
        // Registered first, so it sees the flag as the previous signal left it.
        signal_hook::flag::register_conditional_shutdown(signal, 1, cancel.clone())
            .context("cannot install the signal handlers")?;
        signal_hook::flag::register_usize(signal, which.clone(), signal as usize)
            .context("cannot install the signal handlers")?;
        signal_hook::flag::register(signal, cancel.clone())
            .context("cannot install the signal handlers")?;
    }
    Ok((cancel, which))
}

/// A scenario by path or built-in name, steered by the controller `law` if given (`--law`).
fn load_scenario(scenario: &str, law: Option<&str>) -> Result<Scenario> {
    for (option, value) in [("SCENARIO", Some(scenario)), ("--law", law)] {
        if value.is_some_and(|v| v.trim().is_empty()) {
            return Err(usage(format!(
                "{option}: the path is empty (allowed: a file path or a built-in name)"
            )));
        }
    }
    let scenario = Scenario::load(scenario).map_err(|e| usage(e.to_string()))?;
    match law {
        Some(spec) => {
            let controller = Controller::load(spec).map_err(|e| usage(e.to_string()))?;
            Ok(scenario.with_controller(&controller))
        }
        None => Ok(scenario),
    }
}

fn run(
    scenario: &Scenario,
    out: &Path,
    threads: Option<usize>,
    quiet: bool,
    fail_on_collision: bool,
    format: Option<OutputFormat>,
    plots: bool,
) -> Result<()> {
    // Validate before anything is created on disk; say at once what the load found.
    // Prepared once: the same preparation is handed to the run (a second one would hold two copies
    // of every satellite's description through the run).
    let prepared = scenario.prepare().map_err(|e| usage(e.to_string()))?;
    let duration_s = prepared.config.duration_s;
    let load_warnings = prepared.warnings.clone();
    for warning in &load_warnings {
        eprintln!("warning: {warning}");
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
        .context("cannot start the thread pool")?;
    let bar = if quiet {
        ProgressBar::hidden()
    } else {
        let bar = ProgressBar::new((duration_s * 1000.0).round() as u64);
        bar.set_style(
            ProgressStyle::with_template(
                "{spinner} {msg} [{bar:30}] {percent:>3}% sim-time, {elapsed} elapsed, ETA {eta}",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        bar
    };
    let started = std::time::Instant::now();
    let mut progress = |t_s: f64| {
        bar.set_position((t_s * 1000.0).round() as u64);
        let rate = t_s / started.elapsed().as_secs_f64().max(1e-9);
        bar.set_message(format!("t = {t_s:.0} s ({rate:.1} sim-s/s)"));
    };
    let (cancel, which) = install_signal_handlers()?;
    let options = RunOptions {
        cancel: Some(cancel),
        format,
    };
    let outcome = pool.install(|| run_prepared(scenario, prepared, out, &options, &mut progress));
    bar.finish_and_clear();
    // The figures, also of a run that stopped, from whatever it wrote (not when nothing was written).
    let wrote = match &outcome {
        Ok(_) => true,
        Err(RunError::Simulation(e)) => !e.is_setup(),
        Err(_) => false,
    };
    if plots && wrote {
        match crate::plot::draw_run(out) {
            Ok(report) if !quiet => eprintln!("{}", report.describe(out)),
            Ok(_) => {}
            Err(e) => eprintln!("warning: plots not drawn: {e}"),
        }
    }
    match outcome {
        Ok(summary) => {
            // The load-time warnings lead the summary's; they were printed at load.
            for warning in summary
                .warnings
                .iter()
                .filter(|w| !load_warnings.contains(w))
            {
                eprintln!("warning: {warning}");
            }
            if !quiet {
                eprintln!(
                    "{}: {} satellites, {} s simulated in {:.2} s ({:.3e} satellite-steps/s); outputs in {}",
                    summary.scenario,
                    summary.n_satellites,
                    summary.simulated_s,
                    summary.wall_time_s,
                    summary.satellite_steps_per_s,
                    out.display()
                );
            }
            if fail_on_collision && summary.collisions > 0 {
                bail!(
                    "{}: satellites collided (--fail-on-collision); see {}",
                    summary.scenario,
                    out.join("summary.json").display()
                );
            }
            Ok(())
        }
        Err(RunError::Simulation(e @ SimError::Interrupted { .. })) => Err(Interrupted {
            signal: which.load(Ordering::Relaxed) as i32,
            message: format!(
                "{e}; the files in {} are valid up to that time and summary.json says `interrupted`",
                out.display()
            ),
        }
        .into()),
        Err(RunError::Scenario(e)) => Err(usage(e.to_string())),
        Err(e @ RunError::OutputDirectory { .. }) => Err(usage(e.to_string())),
        // A setup the engine refuses is the user's input (exit 2); a run that stopped is exit 1.
        Err(RunError::Simulation(e)) if e.is_setup() => {
            Err(usage(format!("{}: {e}", scenario.sources())))
        }
        // The run error's text already holds its cause (`recording failed: <the system's error>`):
        // said once, not again as a chain.
        Err(e) => Err(anyhow::anyhow!("{e}")),
    }
}

/// `satflock compare`: the table on stdout, runs not completed on stderr.
fn compare_command(mut options: crate::compare::CompareOptions, seeds: Option<&str>) -> Result<()> {
    use crate::compare::{compare, parse_seeds, CompareError};
    options.seeds = seeds.map(parse_seeds).transpose().map_err(usage)?;
    let (cancel, which) = install_signal_handlers()?;
    options.cancel = Some(cancel);
    let report = compare(&options).map_err(|e| match e {
        CompareError::Input(_) => usage(e.to_string()),
        other => anyhow::Error::from(other),
    })?;
    print_out(&report.markdown)?;
    if report.not_completed > 0 {
        eprintln!(
            "warning: {} of {} runs did not complete (see the list under the table in {})",
            report.not_completed,
            report.table.rows(),
            options.out.join("compare.md").display()
        );
    }
    if report.interrupted {
        return Err(Interrupted {
            signal: which.load(Ordering::Relaxed) as i32,
            message: format!(
                "comparison interrupted; the table in {} holds the runs that finished",
                options.out.display()
            ),
        }
        .into());
    }
    Ok(())
}

/// Writes `dir/report.html`; a run directory that cannot be read is the user's input (exit 2).
fn report_command(dir: &Path, quiet: bool) -> Result<()> {
    use crate::report::{self, ReportError};
    let path = report::write(dir).map_err(|e| match e {
        ReportError::Read(_) => usage(e.to_string()),
        ReportError::Write { .. } => anyhow::Error::from(e),
    })?;
    if !quiet {
        eprintln!("report: {}", path.display());
    }
    Ok(())
}

fn plot_command(dir: &Path, satellites: Option<&[usize]>) -> Result<()> {
    let report = crate::plot::draw_run_of(dir, satellites).map_err(|e| match e {
        crate::plot::PlotError::RunData(e) => usage(e.to_string()),
        crate::plot::PlotError::Satellites(message) => usage(format!("--satellites: {message}")),
        other => anyhow::Error::from(other),
    })?;
    eprintln!("{}", report.describe(dir));
    Ok(())
}

fn validate_command(
    target: Option<&str>,
    list: bool,
    json: bool,
    from: Option<&Path>,
) -> Result<()> {
    use crate::validate::{self, ValidateError};
    if list {
        for (name, what) in validate::TARGETS {
            print_out(&format!("{name:<16} {what}\n"))?;
        }
        return Ok(());
    }
    let target = target.unwrap_or_default();
    if !validate::TARGETS.iter().any(|t| t.0 == target) {
        return Err(usage(
            ValidateError::UnknownTarget {
                name: target.to_string(),
                allowed: validate::TARGETS
                    .iter()
                    .map(|t| t.0)
                    .collect::<Vec<_>>()
                    .join(", "),
            }
            .to_string(),
        ));
    }
    let report = match from {
        Some(path) => {
            let text = satflock::input_file::read_document(path)
                .map_err(|e| usage(format!("{}: {e}", path.display())))?;
            validate::render_saved(target, &text)
                .map_err(|e| usage(format!("{}: {e}", path.display())))?
        }
        None => validate::run(target)?,
    };
    if json {
        print_out(&(serde_json::to_string_pretty(&report)? + "\n"))?;
    } else {
        print_out(&report.to_markdown())?;
    }
    Ok(())
}

fn scenarios() -> Result<()> {
    for b in builtin::BUILTINS {
        let description = Scenario::from_toml(b.toml, b.name, Path::new("."))
            .map(|s| s.file.description)
            .unwrap_or_default();
        print_out(&format!(
            "{:<24} {}\n",
            b.name,
            first_sentence(&description)
        ))?;
    }
    Ok(())
}

/// The first sentence of a text: up to the first `. ` that does not follow an abbreviation (`Fig.`,
/// `Eq.`, `et al.`, `e.g.` …) or a lone initial, with line breaks joined.
fn first_sentence(text: &str) -> String {
    const ABBREVIATIONS: &[&str] = &[
        "fig", "figs", "eq", "eqs", "al", "e.g", "i.e", "cf", "vs", "sec", "tab", "no", "approx",
        "ref", "refs", "resp", "incl",
    ];
    let flat = text.split_whitespace().collect::<Vec<_>>().join(" ");
    let mut from = 0;
    while let Some(k) = flat[from..].find(". ") {
        let end = from + k;
        let word = flat[..end]
            .rsplit([' ', '(', '/'])
            .next()
            .unwrap_or("")
            .to_ascii_lowercase();
        let initial = word.chars().count() == 1 && word.chars().all(char::is_alphabetic);
        if !(ABBREVIATIONS.contains(&word.as_str()) || initial) {
            return flat[..=end].to_string();
        }
        from = end + 2;
    }
    flat
}

/// Parses six comma-separated numbers.
fn six(flag: &str, text: &str) -> Result<[f64; 6]> {
    let values: Vec<f64> = text
        .split(',')
        .map(|v| v.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| {
            usage(format!(
                "{flag} `{text}`: expected six comma-separated numbers"
            ))
        })?;
    let array: [f64; 6] = values.try_into().map_err(|_| {
        usage(format!(
            "{flag} `{text}`: expected six comma-separated numbers"
        ))
    })?;
    if array.iter().any(|v| !v.is_finite()) {
        return Err(usage(format!("{flag} `{text}`: numbers must be finite")));
    }
    Ok(array)
}

/// An orbit from `--elements`-style or `--state`-style text.
fn orbit(flag: &str, text: &str, by_elements: bool, mu: f64) -> Result<CartesianState> {
    let v = six(flag, text)?;
    if by_elements {
        if !(0.0..=180.0).contains(&v[2]) {
            return Err(usage(format!(
                "{flag}: i_deg = {} is out of range (allowed: [0, 180])",
                v[2]
            )));
        }
        let elements = KeplerianElements {
            semi_major_axis_m: v[0],
            eccentricity: v[1],
            inclination_rad: v[2].to_radians(),
            raan_rad: v[3].to_radians(),
            arg_perigee_rad: v[4].to_radians(),
            true_anomaly_rad: v[5].to_radians(),
        };
        elements
            .to_cartesian(mu)
            .map_err(|e| usage(format!("{flag}: {e}")))
    } else {
        let s = CartesianState::new(
            Vector3::new(v[0], v[1], v[2]),
            Vector3::new(v[3], v[4], v[5]),
        );
        if s.position_m.norm() == 0.0 {
            return Err(usage(format!("{flag}: the position must not be zero")));
        }
        Ok(s)
    }
}

/// The command-line spelling of an option's value (`two-body`, `rk78`).
fn arg_name(value: impl ValueEnum) -> String {
    value
        .to_possible_value()
        .map_or_else(String::new, |v| v.get_name().to_string())
}

fn propagate_command(args: &PropagateArgs) -> Result<()> {
    for (option, path, example) in [
        ("--out", Some(&args.out), "orbit.csv"),
        ("--oem", args.oem.as_ref(), "orbit.oem"),
    ] {
        if let Some(path) = path.filter(|p| p.is_dir()) {
            return Err(usage(format!(
                "{option} {}: is a directory (allowed: a file path, e.g. {})",
                path.display(),
                path.join(example).display()
            )));
        }
    }
    if args.oem.as_ref() == Some(&args.out) {
        return Err(usage(format!(
            "--oem {}: is also the --out file (allowed: another path)",
            args.out.display()
        )));
    }
    if args.oem.is_some() && args.frame != FrameArg::Inertial {
        return Err(usage(
            "--oem needs --frame inertial (an OEM holds inertial EME2000 states; LVLH states are not an \
             ephemeris)",
        ));
    }
    let epoch = satflock::time::parse_epoch_utc(&args.epoch_utc)
        .map_err(|m| usage(format!("--epoch-utc: {m}")))?;
    let defaults = EarthModel::WGS84_EGM96;
    let earth = EarthModel {
        mu_m3_s2: args.mu.unwrap_or(defaults.mu_m3_s2),
        equatorial_radius_m: args.earth_radius_m.unwrap_or(defaults.equatorial_radius_m),
        j2: args.j2.unwrap_or(defaults.j2),
    };
    for (name, value) in [
        ("--mu", earth.mu_m3_s2),
        ("--earth-radius-m", earth.equatorial_radius_m),
    ] {
        if !(value.is_finite() && value > 0.0) {
            return Err(usage(format!(
                "{name} {value} is out of range (allowed: finite, > 0)"
            )));
        }
    }
    if !(earth.j2.is_finite() && earth.j2 >= 0.0) {
        return Err(usage(format!(
            "--j2 {} is out of range (allowed: finite, >= 0)",
            earth.j2
        )));
    }
    let satellite = match (&args.elements, &args.state) {
        (Some(e), None) => orbit("--elements", e, true, earth.mu_m3_s2)?,
        (None, Some(s)) => orbit("--state", s, false, earth.mu_m3_s2)?,
        _ => bail!(usage("give exactly one of --elements or --state")),
    };
    let reference = match (&args.reference_elements, &args.reference_state) {
        (Some(e), None) => Some(orbit("--reference-elements", e, true, earth.mu_m3_s2)?),
        (None, Some(s)) => Some(orbit("--reference-state", s, false, earth.mu_m3_s2)?),
        _ => None,
    };
    if args.frame != FrameArg::Inertial && reference.is_none() {
        return Err(usage(
            "--frame lvlh-hill and lvlh-gao need a reference orbit: --reference-elements or --reference-state",
        ));
    }
    if args.frame == FrameArg::Inertial && reference.is_some() {
        return Err(usage(
            "a reference orbit is used only with --frame lvlh-hill or lvlh-gao",
        ));
    }
    let (forces, properties) = match &args.forces {
        Some(path) => {
            let config = ForcesConfig::from_file(path).map_err(|e| usage(e.to_string()))?;
            let invalid =
                |e: satflock::dynamics::ForceConfigError| usage(format!("{}: {e}", path.display()));
            let forces = ForceSet::from_config(&config, &earth, epoch).map_err(invalid)?;
            (forces, config.satellite_properties().map_err(invalid)?)
        }
        None => (
            ForceSet::gravity(
                match args.gravity.unwrap_or(GravityArg::J2) {
                    GravityArg::TwoBody => GravityModel::TwoBody,
                    GravityArg::J2 => GravityModel::J2,
                },
                earth,
            ),
            PhysicalProperties::point_mass(1.0),
        ),
    };
    let forces_named = forces.summary().models.join(" + ");
    let settings = PropagationSettings {
        earth,
        forces: std::sync::Arc::new(forces),
        properties,
        integrator: match args.integrator {
            IntegratorArg::Rk4 => IntegratorMethod::Rk4,
            IntegratorArg::Rk78 => IntegratorMethod::Rk78,
            IntegratorArg::Dop853 => IntegratorMethod::Dop853,
        },
        step_s: args.step_s,
        tolerances: Tolerances {
            relative: args.rtol,
            absolute: args.atol,
        },
        duration_s: args.duration_s,
        output_step_s: args.output_step_s,
    };
    let mut orbits = vec![satellite];
    orbits.extend(reference);
    for (index, orbit) in orbits.iter().enumerate() {
        let option = if index == 0 {
            "--elements/--state"
        } else {
            "--reference-elements/--reference-state"
        };
        settings
            .check_orbit(index, orbit)
            .map_err(|e| usage(format!("{option}: {e}")))?;
    }
    let output_frame = match args.frame {
        FrameArg::Inertial => OutputFrame::Inertial,
        FrameArg::LvlhHill => OutputFrame::LvlhHill,
        FrameArg::LvlhGao => OutputFrame::LvlhGao,
    };
    let mut text = String::from("t_s,x_m,y_m,z_m,vx_mps,vy_mps,vz_mps\n");
    let mut rows = 0usize;
    let mut last = (0.0, [0.0; 6]);
    let mut inertial = InertialTrack {
        id: 0,
        t_s: Vec::new(),
        states: Vec::new(),
    };
    propagate(&orbits, &settings, |t, states| {
        if args.oem.is_some() {
            let (p, v) = (states[0].position_m, states[0].velocity_mps);
            inertial.t_s.push(t);
            inertial.states.push([p.x, p.y, p.z, v.x, v.y, v.z]);
        }
        let s = output_frame.express(&states[0], states.get(1));
        text.push_str(&format!(
            "{t},{},{},{},{},{},{}\n",
            s[0], s[1], s[2], s[3], s[4], s[5]
        ));
        rows += 1;
        last = (t, s);
    })
    .map_err(|e| match e {
        satflock::propagate::PropagateError::InvalidSetting { .. }
        | satflock::propagate::PropagateError::InvalidOrbit { .. } => usage(e.to_string()),
        satflock::propagate::PropagateError::Integration(
            satflock::integrate::IntegrateError::StepSizeUnderflow { .. },
        ) => usage(format!(
            "{e}: --rtol {:e} and --atol {:e} cannot be met in double precision on this orbit \
             (suggested: --rtol in [1e-13, 1e-6], --atol in [1e-9, 1e-3] m)",
            settings.tolerances.relative, settings.tolerances.absolute
        )),
        other => anyhow::Error::from(other),
    })?;
    // Each file is written whole (a temporary file renamed): no partial file on failure.
    write_whole(&args.out, text.as_bytes())?;
    let mut written = args.out.display().to_string();
    if let Some(path) = &args.oem {
        let creation_date = oem::creation_date().map_err(usage)?;
        let message = OemMessage {
            creation_date,
            epoch,
            header_comments: vec![format!(
                "Written by satflock {} propagate: one orbit, forces {}, --integrator {}, \
                 mu = {} m^3/s^2, Re = {} m, J2 = {}.",
                env!("CARGO_PKG_VERSION"),
                forces_named,
                arg_name(args.integrator),
                earth.mu_m3_s2,
                earth.equatorial_radius_m,
                earth.j2,
            )],
            segment_comments: Vec::new(),
            objects: vec![OemObject {
                name: "SATELLITE".into(),
                id: "SATFLOCK-PROPAGATE".into(),
                track: &inertial,
            }],
            version: oem::OemVersion::V2,
            message_id: String::new(),
        };
        write_whole(path, message.to_kvn().as_bytes())?;
        written.push_str(&format!(" and {} (OEM)", path.display()));
    }
    let frame = match args.frame {
        FrameArg::Inertial => format!("inertial {}", frames::INERTIAL_FRAME),
        FrameArg::LvlhHill => "Hill LVLH of the reference orbit".into(),
        FrameArg::LvlhGao => "Gao LVLH of the reference orbit".into(),
    };
    let s = last.1;
    eprintln!(
        "propagate: {rows} rows, t = 0 to {} s, written to {written}; final state ({frame}): \
         r = [{:.3}, {:.3}, {:.3}] m, v = [{:.6}, {:.6}, {:.6}] m/s",
        last.0, s[0], s[1], s[2], s[3], s[4], s[5]
    );
    Ok(())
}
