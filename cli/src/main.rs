//! The `satflock` command-line tool: a thin layer over the library's public API.
//!
//! Exit codes: 0 success, 1 a run that failed (diverged, could not write; collisions with
//! `--fail-on-collision`), 2 bad arguments or input, 130 / 143 a run interrupted by SIGINT / SIGTERM
//! (its files closed and `summary.json` written with status `interrupted`).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;

use anyhow::{bail, Context, Result};
use clap::{Parser, Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};

use satflock::integrate::{IntegratorMethod, Tolerances};
use satflock::metrics::{five_elements, FiveElementsWorkspace};
use satflock::orbit::{
    hill_to_gao, CartesianState, EarthModel, GravityModel, KeplerianElements, LvlhFrame, Vector3,
};
use satflock::propagate::{propagate, PropagationSettings};
use satflock::run::{run_scenario_with, RunError, RunOptions};
use satflock::scenario::{builtin, Scenario};
use satflock::swarm::SimError;

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
    /// Run a scenario (a TOML file or a built-in name) and write summary.json, metrics.csv,
    /// trajectory.csv, scene.json and scenario.toml into the output directory, then draw its figures
    /// into OUT/plots/ (unless --no-plots).
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
        /// Do not draw the figures into OUT/plots/ after the run (`satflock plot OUT` draws them later).
        #[arg(long)]
        no_plots: bool,
    },
    /// Draw the figures of a run directory into RUN_DIR/plots/ (PNG and SVG): trajectories and
    /// snapshots in Hill LVLH, metrics over time, delta-v. `satflock run` draws them too.
    Plot {
        /// A run's output directory (as written by `satflock run`).
        run_dir: PathBuf,
    },
    /// List the built-in scenarios.
    Scenarios,
    /// Print the five-element characterisation of a set of positions as JSON.
    Characterize {
        /// CSV with columns x_m,y_m,z_m and optionally radius_m (any common frame).
        positions: PathBuf,
    },
    /// Propagate one orbit (no control) and write its states to CSV.
    #[command(allow_negative_numbers = true)]
    Propagate(PropagateArgs),
    /// Run a full-length reproduction (papers, analytic references) and print reported vs reproduced
    /// as a Markdown table. Targets: `core`, `gao`, `pigeon`, `scatter`, `takahashi` (see `satflock validate
    /// --list`).
    Validate {
        /// Target name: `core`, `gao`, `pigeon`, `scatter` or `takahashi`.
        #[arg(required_unless_present = "list")]
        target: Option<String>,
        /// List the targets.
        #[arg(long)]
        list: bool,
        /// Print JSON instead of Markdown.
        #[arg(long)]
        json: bool,
    },
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
enum GravityArg {
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
    /// Gravity model.
    #[arg(long, value_enum, default_value = "j2")]
    gravity: GravityArg,
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
}

/// Largest `--threads`.
const MAX_THREADS: i64 = 1024;

/// An error in the user's input: exit code 2.
#[derive(Debug)]
struct UsageError(String);

/// A run stopped by a signal (its summary is written): exit code 128 + the signal number.
#[derive(Debug)]
struct Interrupted {
    signal: i32,
    message: String,
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

fn usage(message: impl Into<String>) -> anyhow::Error {
    UsageError(message.into()).into()
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run {
            scenario,
            out,
            threads,
            quiet,
            fail_on_collision,
            no_plots,
        } => run(
            &scenario,
            &out,
            threads.map(usize::from),
            quiet,
            fail_on_collision,
            !no_plots,
        ),
        Command::Plot { run_dir } => plot_command(&run_dir),
        Command::Scenarios => {
            scenarios();
            Ok(())
        }
        Command::Characterize { positions } => characterize(&positions),
        Command::Propagate(args) => propagate_command(&args),
        Command::Validate { target, list, json } => validate_command(target.as_deref(), list, json),
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
fn install_signal_handlers() -> Result<(Arc<AtomicBool>, Arc<AtomicUsize>)> {
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

fn run(
    scenario: &str,
    out: &Path,
    threads: Option<usize>,
    quiet: bool,
    fail_on_collision: bool,
    plots: bool,
) -> Result<()> {
    let scenario = Scenario::load(scenario).map_err(|e| usage(e.to_string()))?;
    // Validate before anything is created on disk.
    let duration_s = scenario
        .prepare()
        .map_err(|e| usage(e.to_string()))?
        .config
        .duration_s;
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
    };
    let outcome = pool.install(|| run_scenario_with(&scenario, out, &options, &mut progress));
    bar.finish_and_clear();
    // The figures, also of a run that stopped, from whatever it wrote (not when nothing was written).
    let wrote = match &outcome {
        Ok(_) => true,
        Err(RunError::Simulation(e)) => !e.is_setup(),
        Err(_) => false,
    };
    if plots && wrote {
        match satflock_cli::plot::draw_run(out) {
            Ok(report) if !quiet => eprintln!("{}", report.describe(out)),
            Ok(_) => {}
            Err(e) => eprintln!("warning: plots not drawn: {e}"),
        }
    }
    match outcome {
        Ok(summary) => {
            for warning in &summary.warnings {
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
            Err(usage(format!("{}: {e}", scenario.source)))
        }
        Err(e) => Err(e.into()),
    }
}

fn plot_command(dir: &Path) -> Result<()> {
    let report = satflock_cli::plot::draw_run(dir).map_err(|e| match e {
        satflock_cli::plot::PlotError::RunData(e) => usage(e.to_string()),
        other => anyhow::Error::from(other),
    })?;
    eprintln!("{}", report.describe(dir));
    Ok(())
}

fn validate_command(target: Option<&str>, list: bool, json: bool) -> Result<()> {
    if list {
        for (name, what) in satflock_cli::validate::TARGETS {
            println!("{name:<12} {what}");
        }
        return Ok(());
    }
    let target = target.unwrap_or_default();
    let report = satflock_cli::validate::run(target).map_err(|e| match e {
        satflock_cli::validate::ValidateError::UnknownTarget { .. } => usage(e.to_string()),
        other => anyhow::Error::from(other),
    })?;
    if json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print!("{}", report.to_markdown());
    }
    Ok(())
}

fn scenarios() {
    for b in builtin::BUILTINS {
        let description = Scenario::from_toml(b.toml, b.name, Path::new("."))
            .map(|s| s.file.description)
            .unwrap_or_default();
        let first = description.split(". ").next().unwrap_or("").trim();
        println!("{:<24} {first}", b.name);
    }
}

fn characterize(path: &Path) -> Result<()> {
    let mut reader =
        csv::Reader::from_path(path).map_err(|e| usage(format!("{}: {e}", path.display())))?;
    let header: Vec<String> = reader
        .headers()
        .map_err(|e| usage(format!("{}: {e}", path.display())))?
        .iter()
        .map(|h| h.trim().to_string())
        .collect();
    let with_radius = match header.iter().map(String::as_str).collect::<Vec<_>>()[..] {
        ["x_m", "y_m", "z_m"] => false,
        ["x_m", "y_m", "z_m", "radius_m"] => true,
        _ => {
            return Err(usage(format!(
                "{}: header is `{}` (required: `x_m,y_m,z_m` or `x_m,y_m,z_m,radius_m`)",
                path.display(),
                header.join(",")
            )))
        }
    };
    let mut positions = Vec::new();
    let mut radii = Vec::new();
    for (row, record) in reader.records().enumerate() {
        let record = record.map_err(|e| usage(format!("{}: {e}", path.display())))?;
        let values: Vec<f64> = record
            .iter()
            .map(|v| v.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .ok()
            .filter(|v: &Vec<f64>| v.len() == header.len() && v.iter().all(|x| x.is_finite()))
            .ok_or_else(|| {
                usage(format!(
                    "{} line {}: expected {} finite numbers",
                    path.display(),
                    row + 2,
                    header.len()
                ))
            })?;
        positions.push([values[0], values[1], values[2]]);
        if with_radius {
            if values[3] < 0.0 {
                return Err(usage(format!(
                    "{} line {}: radius_m = {} is out of range (allowed: >= 0)",
                    path.display(),
                    row + 2,
                    values[3]
                )));
            }
            radii.push(values[3]);
        }
    }
    let velocities = vec![[0.0; 3]; positions.len()];
    let mut workspace = FiveElementsWorkspace::new();
    let elements = five_elements(
        &positions,
        &velocities,
        with_radius.then_some(&radii[..]),
        &mut workspace,
    )
    .map_err(|e| usage(format!("{}: {e}", path.display())))?;
    println!("{}", serde_json::to_string_pretty(&elements)?);
    Ok(())
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

fn propagate_command(args: &PropagateArgs) -> Result<()> {
    if args.out.is_dir() {
        return Err(usage(format!(
            "--out {}: is a directory (allowed: a file path, e.g. {})",
            args.out.display(),
            args.out.join("orbit.csv").display()
        )));
    }
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
    let settings = PropagationSettings {
        earth,
        gravity: match args.gravity {
            GravityArg::TwoBody => GravityModel::TwoBody,
            GravityArg::J2 => GravityModel::J2,
        },
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
    let mut text = String::from("t_s,x_m,y_m,z_m,vx_mps,vy_mps,vz_mps\n");
    propagate(&orbits, &settings, |t, states| {
        let (p, v) = match args.frame {
            FrameArg::Inertial => (states[0].position_m, states[0].velocity_mps),
            FrameArg::LvlhHill | FrameArg::LvlhGao => {
                let rel = LvlhFrame::from_reference(&states[1]).to_hill(&states[0]);
                if args.frame == FrameArg::LvlhHill {
                    (rel.position_m, rel.velocity_mps)
                } else {
                    (hill_to_gao(&rel.position_m), hill_to_gao(&rel.velocity_mps))
                }
            }
        };
        text.push_str(&format!(
            "{t},{},{},{},{},{},{}\n",
            p.x, p.y, p.z, v.x, v.y, v.z
        ));
    })
    .map_err(|e| match e {
        satflock::propagate::PropagateError::InvalidSetting { .. }
        | satflock::propagate::PropagateError::InvalidOrbit { .. } => usage(e.to_string()),
        other => anyhow::Error::from(other),
    })?;
    // Write to a temporary file beside the target, then rename: no partial file on failure.
    let tmp = args.out.with_extension("csv.partial");
    let written = std::fs::File::create(&tmp)
        .with_context(|| format!("cannot create {}", tmp.display()))
        .and_then(|mut file| {
            file.write_all(text.as_bytes())
                .and_then(|_| file.sync_all())
                .with_context(|| format!("cannot write {}", tmp.display()))
        })
        .and_then(|_| {
            std::fs::rename(&tmp, &args.out)
                .with_context(|| format!("cannot write {}", args.out.display()))
        });
    if written.is_err() {
        // Never leave the partial file behind.
        let _ = std::fs::remove_file(&tmp);
    }
    written
}
