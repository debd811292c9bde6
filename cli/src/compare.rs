//! `satflock compare CASE --law A --law B … [--seeds 1..10] --out DIR [--jobs J] [--keep-runs]`: every
//! controller (law) on the same case and the same seeds, side by side.
//!
//! Each (law, seed) run is the case steered by the law's controller
//! ([`satflock::scenario::Scenario::with_controller`]) with the case's seed replaced: the initial states
//! depend only on the case and the seed, so every law starts from the same states, bit for bit. Runs
//! execute in a bounded pool ([`satflock::campaign::pool::run_bounded`]), each on one thread, results in job order:
//! the outputs do not depend on `--jobs`. A run that fails (diverges) or that the engine refuses for this
//! case (the controller does not fit it) is a row with its status and error, not the end of the
//! comparison.
//!
//! Outputs in `DIR`:
//!
//! | file | holds |
//! | --- | --- |
//! | `runs/LABEL/seed-N/` | each run's directory: `summary.json`, the metrics table, `scene.json`, `scenario.toml` (the trajectory only with `--keep-runs`) |
//! | `compare.parquet` | one row per run ([`RunTable`]): `law`, `controller`, `law_name`, `status`, `error`, `seed` and every scalar outcome of its `summary.json` ([`scalar_outcomes`]) |
//! | `compare.md` | the side-by-side table (also on stdout): per law, median and 5–95 % spread ([`Spread`]) of each outcome |
//! | `plots/` | overlays ([`crate::plot::overlay`]): the median over seeds of one metric over time, every law on one axis |

use std::borrow::Cow;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;

use indicatif::{ProgressBar, ProgressStyle};
use thiserror::Error;

use satflock::campaign::pool::run_bounded;
use satflock::output::{scalar_outcomes, RunData, RunTable, Spread};
use satflock::run::{foreign_run_entry, run_scenario_with, RunError, RunOptions};
use satflock::scenario::schema::{ActionSection, ControlMode};
use satflock::scenario::{merge_law_parameters, Controller, Scenario};
use satflock::swarm::Headline;

use crate::plot::overlay::{draw_overlays, Curve, Overlay};

/// The files `compare` writes at the top of its directory (besides `runs/` and `plots/`).
pub const COMPARE_FILES: &[&str] = &["compare.parquet", "compare.md"];

/// Most runs (laws × seeds) one comparison accepts: beyond it a seed range is almost surely a typo.
pub const MAX_RUNS: usize = 100_000;

/// Why a comparison could not be made.
#[derive(Debug, Error)]
pub enum CompareError {
    /// The user's input: the case, a controller file, the seeds, the output directory (exit 2).
    #[error("{0}")]
    Input(String),
    /// A file could not be written or read back (exit 1).
    #[error("{path}: {message}")]
    Output {
        /// The file or directory.
        path: String,
        /// What went wrong.
        message: String,
    },
}

/// What to compare and how.
#[derive(Clone, Debug, Default)]
pub struct CompareOptions {
    /// The case: a scenario file or a built-in name (its own controller is replaced by each law's).
    pub case: String,
    /// The controllers: files, or `builtin:NAME`.
    pub laws: Vec<String>,
    /// The seeds (`None`: the case's own seed).
    pub seeds: Option<Vec<u64>>,
    /// The output directory.
    pub out: PathBuf,
    /// Runs at once (at least 1).
    pub jobs: usize,
    /// Keep each run's trajectory too.
    pub keep_runs: bool,
    /// Show a progress bar on stderr.
    pub progress: bool,
    /// A flag that stops the comparison: running runs stop after their segment (status
    /// `interrupted`), runs not started are recorded as `interrupted` without running.
    pub cancel: Option<Arc<AtomicBool>>,
}

/// What a comparison produced.
#[derive(Clone, Debug)]
pub struct CompareReport {
    /// One row per run, as written to `compare.parquet`.
    pub table: RunTable,
    /// The side-by-side Markdown table (as written to `compare.md`).
    pub markdown: String,
    /// Runs that did not complete (failed, refused or interrupted).
    pub not_completed: usize,
    /// Whether the cancel flag stopped it.
    pub interrupted: bool,
    /// The overlay figures written.
    pub plots: Vec<PathBuf>,
}

/// Parses `--seeds`: `A..B` (every seed from A to B, both included), a comma-separated list, or one seed.
pub fn parse_seeds(text: &str) -> Result<Vec<u64>, String> {
    let number = |s: &str| {
        s.trim().parse::<u64>().map_err(|_| {
            format!("--seeds `{text}`: `{s}` is not a seed (allowed: A..B, a list A,B,C or one seed; seeds are integers >= 0)")
        })
    };
    let seeds: Vec<u64> = if let Some((a, b)) = text.split_once("..") {
        let (a, b) = (number(a)?, number(b.trim_start_matches('='))?);
        if a > b {
            return Err(format!(
                "--seeds `{text}`: the range is empty (allowed: A..B with A <= B, both included)"
            ));
        }
        if b - a >= MAX_RUNS as u64 {
            return Err(format!(
                "--seeds `{text}`: {} seeds (allowed: at most {MAX_RUNS})",
                u128::from(b - a) + 1
            ));
        }
        (a..=b).collect()
    } else {
        text.split(',').map(number).collect::<Result<_, _>>()?
    };
    let mut sorted = seeds.clone();
    sorted.sort_unstable();
    if let Some(w) = sorted.windows(2).find(|w| w[0] == w[1]) {
        return Err(format!(
            "--seeds `{text}`: seed {} is given twice (allowed: distinct seeds)",
            w[0]
        ));
    }
    Ok(seeds)
}

/// One law of the comparison.
struct Law {
    label: String,
    controller: Controller,
    /// The headline outcomes its law (at t = 0) declares.
    headlines: &'static [Headline],
}

/// One run's result (job order: law-major, then seed).
struct RunResult {
    status: String,
    error: String,
    outcomes: Vec<(String, f64)>,
    /// The metrics table's columns of the overlays (`t_s` first), when the run wrote one.
    series: Option<Vec<Vec<f64>>>,
}

/// Metrics columns drawn as overlays, with their figure names and captions (those the case has).
const OVERLAYS: &[(&str, &str, &str)] = &[
    (
        "min_separation_m",
        "min_separation",
        "minimum separation (centres)",
    ),
    (
        "d_max_m",
        "d_max",
        "d_max: largest distance from the centre",
    ),
    ("delta_v_mean_mps", "delta_v_mean", "mean Δv so far"),
    (
        "min_threat_distance_m",
        "min_threat_distance",
        "closest threat approach so far",
    ),
    (
        "min_obstacle_clearance_m",
        "min_obstacle_clearance",
        "smallest obstacle clearance so far",
    ),
];

/// Runs the comparison and writes its outputs (see the module docs).
pub fn compare(options: &CompareOptions) -> Result<CompareReport, CompareError> {
    let input = CompareError::Input;
    let case = Scenario::load(&options.case).map_err(|e| input(e.to_string()))?;
    // The case must be a valid scenario with its own controller: its errors are its own, not a law's.
    case.prepare().map_err(|e| {
        input(format!(
            "the case is not a valid scenario (with its own controller): {e}"
        ))
    })?;
    if options.laws.is_empty() {
        return Err(input(
            "no --law given (allowed: one or more controller files or builtin:NAME)".into(),
        ));
    }
    let mut laws: Vec<Law> = Vec::new();
    for spec in &options.laws {
        let controller = Controller::load(spec).map_err(|e| input(e.to_string()))?;
        let headlines = check_controller(&controller).map_err(input)?;
        let label = controller.label();
        if let Some(other) = laws.iter().find(|l| l.label == label) {
            return Err(input(format!(
                "--law {spec}: its label `{label}` is also that of --law {} (labels are file names \
                 without extension, or the built-in's name; rename one file)",
                other.controller.source
            )));
        }
        laws.push(Law {
            label,
            controller,
            headlines,
        });
    }
    let seeds = options
        .seeds
        .clone()
        .unwrap_or_else(|| vec![case.file.seed]);
    if seeds.is_empty() {
        return Err(input("--seeds: no seed given".into()));
    }
    if laws.len() * seeds.len() > MAX_RUNS {
        return Err(input(format!(
            "{} laws × {} seeds = {} runs (allowed: at most {MAX_RUNS})",
            laws.len(),
            seeds.len(),
            laws.len() * seeds.len()
        )));
    }
    prepare_compare_dir(&options.out)?;

    let jobs: Vec<(usize, u64)> = (0..laws.len())
        .flat_map(|l| seeds.iter().map(move |&s| (l, s)))
        .collect();
    let bar = progress_bar(options.progress, jobs.len());
    let failed = AtomicUsize::new(0);
    let running = AtomicUsize::new(0);
    let cancel = options.cancel.clone();
    let results = run_bounded(jobs.clone(), options.jobs.max(1), |(l, seed)| {
        let stopped = cancel.as_ref().is_some_and(|c| c.load(Ordering::Relaxed));
        let result = if stopped {
            RunResult {
                status: "interrupted".into(),
                error: "not started: the comparison was interrupted".into(),
                outcomes: Vec::new(),
                series: None,
            }
        } else {
            running.fetch_add(1, Ordering::Relaxed);
            let r = run_one(&case, &laws[l], seed, options);
            running.fetch_sub(1, Ordering::Relaxed);
            r
        };
        if result.status != "completed" {
            failed.fetch_add(1, Ordering::Relaxed);
        }
        bar.set_message(format!(
            "{} not completed, {} running",
            failed.load(Ordering::Relaxed),
            running.load(Ordering::Relaxed)
        ));
        bar.inc(1);
        result
    })
    .map_err(|e| CompareError::Output {
        path: options.out.display().to_string(),
        message: e.to_string(),
    })?;
    bar.finish_and_clear();

    let table = run_table(&laws, &jobs, &results);
    let parquet = options.out.join("compare.parquet");
    let metadata = [
        ("satflock_version", env!("CARGO_PKG_VERSION").to_string()),
        ("case", case.source.clone()),
        (
            "seeds",
            seeds
                .iter()
                .map(u64::to_string)
                .collect::<Vec<_>>()
                .join(","),
        ),
        (
            "laws",
            laws.iter()
                .map(|l| format!("{}={}", l.label, l.controller.source))
                .collect::<Vec<_>>()
                .join(","),
        ),
    ];
    table
        .write_parquet(&parquet, &metadata)
        .map_err(|e| output_error(&parquet, e))?;
    let markdown = markdown(&case, &laws, &seeds, &table);
    let md = options.out.join("compare.md");
    std::fs::write(&md, &markdown).map_err(|e| output_error(&md, e))?;
    let overlays = overlays(&case, &laws, &jobs, &results, seeds.len());
    let plots =
        draw_overlays(&options.out.join("plots"), &overlays).map_err(|e| CompareError::Output {
            path: options.out.join("plots").display().to_string(),
            message: e.to_string(),
        })?;
    Ok(CompareReport {
        not_completed: results.iter().filter(|r| r.status != "completed").count(),
        interrupted: cancel.is_some_and(|c| c.load(Ordering::Relaxed)),
        table,
        markdown,
        plots,
    })
}

fn output_error(path: &Path, e: impl std::fmt::Display) -> CompareError {
    CompareError::Output {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

fn progress_bar(show: bool, runs: usize) -> ProgressBar {
    if !show {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(runs as u64);
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} runs {pos}/{len} [{bar:30}] {msg}, {elapsed} elapsed, ETA {eta}",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
    bar
}

/// The directory of one run.
fn run_dir(out: &Path, label: &str, seed: u64) -> PathBuf {
    out.join("runs").join(label).join(format!("seed-{seed}"))
}

/// Checks what a controller says by itself, whatever the case (once, before any run: a controller
/// wrong in itself would be refused by every run): its law's parameters, its control period, and each
/// law event's parameters or law (replayed in time order). The error names the file, the key and the
/// allowed range, as `satflock run --law` does; what depends on the case (a law too stiff for its
/// step, a formation of another size) is left to each run, which records it as refused. Returns the
/// headline outcomes of its law at t = 0.
fn check_controller(controller: &Controller) -> Result<&'static [Headline], String> {
    let file = &controller.file;
    let fail =
        |key: &str, message: String| format!("{}: key `{key}`: {message}", controller.source);
    let headlines = file
        .law
        .build()
        .map_err(|e| fail("law", e.to_string()))?
        .headlines();
    if let Some(control) = &file.control {
        match (control.mode, control.period_s) {
            (_, Some(p)) if !(p.is_finite() && p > 0.0) => {
                return Err(fail(
                    "control.period_s",
                    format!("{p} is out of range (allowed: finite, > 0)"),
                ))
            }
            (ControlMode::Sampled, None) => {
                return Err(fail(
                    "control.period_s",
                    "is required with mode = \"sampled\"".into(),
                ))
            }
            _ => {}
        }
    }
    let mut order: Vec<usize> = (0..file.events.len()).collect();
    // Timed events in time order, then the condition events (whose time is not known before a run).
    let time = |k: usize| file.events[k].time_s.unwrap_or(f64::INFINITY);
    order.sort_by(|&a, &b| time(a).total_cmp(&time(b)));
    let mut current = file.law.clone();
    for k in order {
        match &file.events[k].action {
            ActionSection::SetLawParameters { parameters } => {
                let key = format!("events[{k}].parameters");
                current = merge_law_parameters(&current, parameters)
                    .map_err(|m| fail(&key, format!("law `{}`: {m}", current.name())))?;
                current.build().map_err(|e| fail(&key, e.to_string()))?;
            }
            ActionSection::SwitchLaw { law } => {
                law.build()
                    .map_err(|e| fail(&format!("events[{k}].law"), e.to_string()))?;
                current = law.clone();
            }
            _ => {}
        }
    }
    Ok(headlines)
}

/// Runs law `law` on the case with `seed`, into its directory, and reads back what it wrote.
fn run_one(case: &Scenario, law: &Law, seed: u64, options: &CompareOptions) -> RunResult {
    let mut scenario = case.with_controller(&law.controller);
    scenario.file.seed = seed;
    if !options.keep_runs {
        scenario.file.output.trajectory = false;
        scenario.file.output.oem = false;
    }
    let dir = run_dir(&options.out, &law.label, seed);
    let run_options = RunOptions {
        cancel: options.cancel.clone(),
        format: None,
    };
    let outcome = run_scenario_with(&scenario, &dir, &run_options, &mut |_| {});
    let (status, error) = match &outcome {
        Ok(_) => ("completed".to_string(), String::new()),
        // Refused before anything ran: the controller does not fit this case.
        Err(e @ RunError::Scenario(_)) => ("refused".to_string(), e.to_string()),
        Err(RunError::Simulation(e)) if e.is_setup() => ("refused".to_string(), e.to_string()),
        Err(e) => ("failed".to_string(), e.to_string()),
    };
    // What the run wrote (also when it stopped): its summary says how it ended.
    match RunData::read(&dir) {
        Ok(run) if status != "refused" => RunResult {
            status: run
                .summary
                .get("status")
                .and_then(|s| s.as_str())
                .unwrap_or(&status)
                .to_string(),
            error,
            outcomes: scalar_outcomes(&run.summary),
            series: run.metrics.column("t_s").map(|t| {
                std::iter::once(t.to_vec())
                    .chain(OVERLAYS.iter().map(|(c, _, _)| {
                        run.metrics
                            .column(c)
                            .map_or_else(|| vec![f64::NAN; t.len()], <[f64]>::to_vec)
                    }))
                    .collect()
            }),
        },
        _ => RunResult {
            status,
            error,
            outcomes: Vec::new(),
            series: None,
        },
    }
}

/// The table of runs: text columns, then `seed` (exact, `UInt64`) and the outcomes.
fn run_table(laws: &[Law], jobs: &[(usize, u64)], results: &[RunResult]) -> RunTable {
    let text: Vec<Vec<(String, String)>> = jobs
        .iter()
        .zip(results)
        .map(|(&(l, _), r)| {
            let law = &laws[l];
            vec![
                ("law".to_string(), law.label.clone()),
                ("controller".to_string(), law.controller.source.clone()),
                (
                    "law_name".to_string(),
                    law.controller.file.law.name().to_string(),
                ),
                ("status".to_string(), r.status.clone()),
                ("error".to_string(), r.error.clone()),
            ]
        })
        .collect();
    let numbers: Vec<Vec<(String, f64)>> = results.iter().map(|r| r.outcomes.clone()).collect();
    let mut table = RunTable::from_rows(&text, &numbers);
    table.push_integers("seed", jobs.iter().map(|&(_, seed)| seed).collect());
    table
}

/// A row of the side-by-side table: its label and the outcome column it summarises.
#[derive(Clone)]
struct Row {
    label: Cow<'static, str>,
    column: Cow<'static, str>,
}

const fn row(label: &'static str, column: &'static str) -> Row {
    Row {
        label: Cow::Borrowed(label),
        column: Cow::Borrowed(column),
    }
}

/// Outcomes of every run.
const COMMON_ROWS: &[Row] = &[
    row("Δv per satellite, mean [m/s]", "delta_v_mps.mean"),
    row("Δv per satellite, largest [m/s]", "delta_v_mps.max"),
    row("minimum separation [m]", "min_separation_m"),
    row("collisions (largest simultaneous) [-]", "collisions"),
];

/// Outcomes of a case with threats.
const THREAT_ROWS: &[Row] = &[
    row(
        "closest threat approach [m]",
        "environment.closest_threat_approach.minimum.distance_m",
    ),
    row("danger-sphere entries [-]", "environment.threat_incursions"),
];

/// Outcomes of a case with obstacles.
const OBSTACLE_ROWS: &[Row] = &[
    row(
        "smallest obstacle clearance [m]",
        "environment.min_obstacle_clearance.minimum.clearance_m",
    ),
    row("obstacle entries [-]", "environment.obstacle_incursions"),
];

/// The final five elements.
const FINAL_ROWS: &[Row] = &[
    row("final d_max [m]", "final.five_elements.d_max_m"),
    row("final d_min [m]", "final.five_elements.d_min_m"),
    row("final uniformity L [-]", "final.five_elements.uniformity_l"),
];

/// The rows of the side-by-side table for this case and these laws, in order: the outcomes of every
/// run, those of the case's threats and obstacles, the final five elements, then each law's headline
/// outcomes ([`satflock::swarm::Reports::headlines`], declared by the law; once per law name, in
/// the order of the first `--law` with it), and the wall time.
fn rows(case: &Scenario, laws: &[Law]) -> Vec<Row> {
    let mut rows: Vec<Row> = COMMON_ROWS.to_vec();
    if !case.file.threats.is_empty() {
        rows.extend_from_slice(THREAT_ROWS);
    }
    if !case.file.obstacles.is_empty() {
        rows.extend_from_slice(OBSTACLE_ROWS);
    }
    rows.extend_from_slice(FINAL_ROWS);
    let mut named: Vec<&str> = Vec::new();
    for law in laws {
        let name = law.controller.file.law.name();
        if named.contains(&name) {
            continue;
        }
        named.push(name);
        rows.extend(law.headlines.iter().map(|h| Row {
            label: Cow::Owned(h.row_label(name)),
            column: Cow::Owned(h.column()),
        }));
    }
    rows.push(WALL_TIME);
    rows
}

/// Wall-clock time of a run (the last row).
const WALL_TIME: Row = row("wall time per run [s]", "wall_time_s");

/// A number with 4 significant digits: fixed between 10⁻³ and 10⁵, scientific outside.
pub fn format_number(v: f64) -> String {
    if !v.is_finite() {
        return "—".into();
    }
    let a = v.abs();
    if a == 0.0 {
        return "0".into();
    }
    if (1e-3..1e5).contains(&a) {
        let decimals = (3 - a.log10().floor() as i32).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.3e}")
    }
}

/// A cell: `median [p05, p95]` over the law's runs that have the value (the median alone when the
/// percentiles are equal to 4 significant digits), with `(k of n)` when only k of its n runs have it; `—` when none has.
pub fn format_cell(spread: &Spread, runs: usize) -> String {
    if spread.count == 0 {
        return "—".into();
    }
    let mut cell = format_number(spread.median);
    let (p05, p95) = (format_number(spread.p05), format_number(spread.p95));
    if p05 != p95 {
        cell.push_str(&format!(" [{p05}, {p95}]"));
    }
    if spread.count < runs {
        cell.push_str(&format!(" ({} of {runs})", spread.count));
    }
    cell
}

/// The side-by-side table: one column per law, one row per outcome.
fn markdown(case: &Scenario, laws: &[Law], seeds: &[u64], table: &RunTable) -> String {
    let labels = table.text("law").unwrap_or_default();
    let status = table.text("status").unwrap_or_default();
    let of_law = |l: &Law| -> Vec<usize> {
        (0..table.rows())
            .filter(|&k| labels[k] == l.label)
            .collect()
    };
    let mut text = format!(
        "## satflock compare: {} ({} seed{}: {})\n\n\
         Per law: median [5 %, 95 %] over its runs (percentiles by linear interpolation between order \
         statistics); `(k of n)`: only k of its n runs have the value; `—`: none has.\n\n",
        case.source,
        seeds.len(),
        if seeds.len() == 1 { "" } else { "s" },
        seed_list(seeds)
    );
    let cells = |f: &dyn Fn(&Law) -> String| -> String {
        laws.iter().map(|l| format!(" {} |", f(l))).collect()
    };
    text.push_str(&format!("| |{}\n", cells(&|l| format!("`{}`", l.label))));
    text.push_str(&format!("| --- |{}\n", cells(&|_| "---".into())));
    text.push_str(&format!(
        "| controller |{}\n",
        cells(&|l| format!("`{}`", l.controller.source))
    ));
    text.push_str(&format!(
        "| law |{}\n",
        cells(&|l| l.controller.file.law.name().to_string())
    ));
    text.push_str(&format!(
        "| runs completed / not completed |{}\n",
        cells(&|l| {
            let runs = of_law(l);
            let done = runs.iter().filter(|&&k| status[k] == "completed").count();
            format!("{done} / {}", runs.len() - done)
        })
    ));
    for row in rows(case, laws) {
        let column = table.numbers(&row.column);
        text.push_str(&format!(
            "| {} |{}\n",
            row.label,
            cells(&|l| {
                let runs = of_law(l);
                let values: Vec<f64> = runs
                    .iter()
                    .map(|&k| column.map_or(f64::NAN, |c| c[k]))
                    .collect();
                format_cell(&Spread::of(&values), runs.len())
            })
        ));
    }
    // Runs not completed, one line per law and (status, error), with their seeds.
    let errors = table.text("error").unwrap_or_default();
    let seed = table.integers("seed").unwrap_or_default();
    let mut lines: Vec<(NotCompleted, Vec<String>)> = Vec::new();
    for l in laws {
        for k in of_law(l).into_iter().filter(|&k| status[k] != "completed") {
            let what = (l.label.as_str(), status[k].as_str(), errors[k].as_str());
            match lines.iter_mut().find(|(w, _)| *w == what) {
                Some((_, seeds)) => seeds.push(seed[k].to_string()),
                None => lines.push((what, vec![seed[k].to_string()])),
            }
        }
    }
    if !lines.is_empty() {
        text.push_str("\nRuns not completed:\n\n");
        for ((label, status, error), seeds) in lines {
            text.push_str(&format!(
                "- `{label}` seed{} {}: {status}: {error}\n",
                if seeds.len() == 1 { "" } else { "s" },
                seeds.join(", ")
            ));
        }
    }
    text
}

/// A law's runs not completed with one status and error: (label, status, error).
type NotCompleted<'a> = (&'a str, &'a str, &'a str);

/// Seeds as written: `A..B` when consecutive, else a list.
fn seed_list(seeds: &[u64]) -> String {
    let consecutive = seeds.windows(2).all(|w| w[1] == w[0] + 1);
    match (seeds.first(), seeds.last()) {
        (Some(a), Some(b)) if consecutive && seeds.len() > 2 => format!("{a}..{b}"),
        _ => seeds
            .iter()
            .map(u64::to_string)
            .collect::<Vec<_>>()
            .join(", "),
    }
}

/// The overlay figures: per metric the case has, each law's median and 5–95 % band over its runs at
/// each recording time.
fn overlays(
    case: &Scenario,
    laws: &[Law],
    jobs: &[(usize, u64)],
    results: &[RunResult],
    seeds: usize,
) -> Vec<Overlay> {
    let present = |column: &str| match column {
        "min_threat_distance_m" => !case.file.threats.is_empty(),
        "min_obstacle_clearance_m" => !case.file.obstacles.is_empty(),
        _ => true,
    };
    OVERLAYS
        .iter()
        .enumerate()
        .filter(|(_, (column, _, _))| present(column))
        .map(|(c, (column, name, caption))| Overlay {
            name: name.to_string(),
            title: format!(
                "{}: {caption}, median and 5–95 % over {seeds} seed{}",
                case.file.name,
                if seeds == 1 { "" } else { "s" }
            ),
            column: column.to_string(),
            curves: laws
                .iter()
                .enumerate()
                .map(|(l, law)| {
                    let series: Vec<&Vec<Vec<f64>>> = jobs
                        .iter()
                        .zip(results)
                        .filter(|((jl, _), _)| *jl == l)
                        .filter_map(|(_, r)| r.series.as_ref())
                        .collect();
                    curve(&law.label, &series, c + 1)
                })
                .collect(),
        })
        .collect()
}

/// One law's curve of column `k` of its runs' series (column 0 is `t_s`): at each recording time of its
/// longest run, the spread over the runs that reached it. Runs of one case record at the same times.
fn curve(label: &str, series: &[&Vec<Vec<f64>>], k: usize) -> Curve {
    let t_s = series
        .iter()
        .map(|s| &s[0])
        .max_by_key(|t| t.len())
        .cloned()
        .unwrap_or_default();
    let spreads: Vec<Spread> = (0..t_s.len())
        .map(|i| {
            let values: Vec<f64> = series.iter().filter_map(|s| s[k].get(i).copied()).collect();
            Spread::of(&values)
        })
        .collect();
    Curve {
        label: label.to_string(),
        median: spreads.iter().map(|s| s.median).collect(),
        p05: spreads.iter().map(|s| s.p05).collect(),
        p95: spreads.iter().map(|s| s.p95).collect(),
        t_s,
    }
}

/// Makes `dir` ready: creates it, or clears a previous comparison's outputs. Anything that is not one
/// (a file other than [`COMPARE_FILES`], `plots/` holding other than PNG and SVG files, `runs/LABEL/`
/// holding other than `seed-N` run directories) is refused and nothing is removed.
fn prepare_compare_dir(dir: &Path) -> Result<(), CompareError> {
    let io = |path: &Path, e: std::io::Error| output_error(path, e);
    match std::fs::metadata(dir) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return std::fs::create_dir_all(dir).map_err(|e| io(dir, e));
        }
        Err(e) => return Err(io(dir, e)),
        Ok(m) if !m.is_dir() => {
            return Err(CompareError::Input(format!(
            "--out {}: exists and is not a directory (allowed: a new path, an empty directory or \
                 a previous comparison's directory)",
            dir.display()
        )))
        }
        Ok(_) => {}
    }
    if let Some(foreign) = foreign_compare_entry(dir).map_err(|e| io(dir, e))? {
        return Err(CompareError::Input(format!(
            "--out {}: is not empty and not a previous comparison: it holds `{foreign}` (allowed: a \
             new path, an empty directory, or a directory holding only {}, plots/ (PNG and SVG files) \
             and runs/LABEL/seed-N/ run directories)",
            dir.display(),
            COMPARE_FILES.join(", ")
        )));
    }
    for name in COMPARE_FILES {
        let path = dir.join(name);
        if path.is_file() {
            std::fs::remove_file(&path).map_err(|e| io(&path, e))?;
        }
    }
    for name in ["runs", "plots"] {
        let path = dir.join(name);
        if path.is_dir() {
            std::fs::remove_dir_all(&path).map_err(|e| io(&path, e))?;
        }
    }
    Ok(())
}

/// The first entry of `dir` a comparison did not write (a path relative to `dir`), if any.
fn foreign_compare_entry(dir: &Path) -> std::io::Result<Option<String>> {
    let sorted = |dir: &Path| -> std::io::Result<Vec<std::fs::DirEntry>> {
        let mut entries: Vec<std::fs::DirEntry> =
            std::fs::read_dir(dir)?.collect::<std::io::Result<_>>()?;
        entries.sort_by_key(|e| e.file_name());
        Ok(entries)
    };
    let name = |e: &std::fs::DirEntry| e.file_name().to_string_lossy().into_owned();
    for entry in sorted(dir)? {
        let top = name(&entry);
        let kind = entry.file_type()?;
        match top.as_str() {
            n if kind.is_file() && COMPARE_FILES.contains(&n) => {}
            "plots" if kind.is_dir() => {
                for file in sorted(&entry.path())? {
                    let path = file.path();
                    let figure = file.file_type()?.is_file()
                        && matches!(
                            path.extension().and_then(|e| e.to_str()),
                            Some("png" | "svg")
                        );
                    if !figure {
                        return Ok(Some(format!("plots/{}", name(&file))));
                    }
                }
            }
            "runs" if kind.is_dir() => {
                for law in sorted(&entry.path())? {
                    let label = name(&law);
                    if !law.file_type()?.is_dir() {
                        return Ok(Some(format!("runs/{label}")));
                    }
                    for seed in sorted(&law.path())? {
                        let seed_name = name(&seed);
                        let run_like = seed.file_type()?.is_dir()
                            && seed_name
                                .strip_prefix("seed-")
                                .is_some_and(|n| n.parse::<u64>().is_ok());
                        if !run_like {
                            return Ok(Some(format!("runs/{label}/{seed_name}")));
                        }
                        if let Some(foreign) = foreign_run_entry(&seed.path())? {
                            return Ok(Some(format!("runs/{label}/{seed_name}/{foreign}")));
                        }
                    }
                }
            }
            _ => return Ok(Some(top)),
        }
    }
    Ok(None)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seeds_parse_as_ranges_lists_and_single_seeds() {
        assert_eq!(parse_seeds("1..4").unwrap(), vec![1, 2, 3, 4]);
        assert_eq!(parse_seeds("1..=3").unwrap(), vec![1, 2, 3]);
        assert_eq!(parse_seeds("9, 5,1").unwrap(), vec![9, 5, 1]);
        assert_eq!(parse_seeds("7").unwrap(), vec![7]);
        for bad in ["4..1", "a..3", "1,,2", "1,1", "-1", "0..100000"] {
            assert!(parse_seeds(bad).is_err(), "{bad}");
        }
        assert_eq!(parse_seeds("0..99999").unwrap().len(), 100_000);
    }

    #[test]
    fn numbers_and_cells_are_formatted_with_four_significant_digits() {
        assert_eq!(format_number(1234.567), "1235");
        assert_eq!(format_number(0.012345), "0.01235");
        assert_eq!(format_number(-2.5), "-2.500");
        assert_eq!(format_number(1.5e-5), "1.500e-5");
        assert_eq!(format_number(2.0e6), "2.000e6");
        assert_eq!(format_number(0.0), "0");
        assert_eq!(format_number(f64::NAN), "—");
        let spread = Spread::of(&[1.0, 2.0, 3.0]);
        assert_eq!(format_cell(&spread, 3), "2.000 [1.100, 2.900]");
        assert_eq!(format_cell(&spread, 4), "2.000 [1.100, 2.900] (3 of 4)");
        assert_eq!(format_cell(&Spread::of(&[5.0]), 1), "5.000");
        assert_eq!(format_cell(&Spread::of(&[0.0, 0.0]), 2), "0");
        assert_eq!(format_cell(&Spread::of(&[]), 2), "—");
    }

    /// The headline rows of the built-in laws, now declared by each law, are those `compare` always
    /// showed (labels and columns, in order, after the final five elements and before the wall time),
    /// once per law name; `hold` and `none` have none.
    #[test]
    fn built_in_laws_declare_the_headline_rows_compare_always_showed() {
        let case = Scenario::load("hold").unwrap();
        let law = |spec: &str, label: &str| {
            let controller = Controller::load(spec).unwrap();
            Law {
                label: label.into(),
                headlines: check_controller(&controller).unwrap(),
                controller,
            }
        };
        let laws = [
            law("builtin:hold", "hold"),
            law("builtin:gao-circle", "gao-circle"),
            law("builtin:es-e1", "es-e1"),
            law("builtin:pigeon-baseline", "pigeon-baseline"),
            law("builtin:ts-plane-1", "ts-plane-1"),
            law("builtin:gao-disk", "gao-disk"),
            law("builtin:free-drift", "free-drift"),
        ];
        let rows = rows(&case, &laws);
        let at = rows
            .iter()
            .position(|r| r.column == "final.five_elements.uniformity_l")
            .unwrap();
        let headline: Vec<(&str, &str)> = rows[at + 1..rows.len() - 1]
            .iter()
            .map(|r| (&*r.label, &*r.column))
            .collect();
        assert_eq!(
            headline,
            [
                ("bifurcating: time to shape [s]", "law.time_to_shape_s"),
                (
                    "bifurcating: final shape residual [m]",
                    "law.shape_max_residual_m"
                ),
                (
                    "equilibrium-shaping: final formation error [m]",
                    "law.es_formation_error_m"
                ),
                (
                    "equilibrium-shaping: miss distance to its threat [m]",
                    "law.es_min_threat_distance_m"
                ),
                ("pigeon: order parameter [-]", "law.pigeon_order_parameter"),
                (
                    "pigeon: stabilisation time [s]",
                    "law.pigeon_stabilisation_time_s"
                ),
                ("j2-distance: max abs C1 [m]", "law.max_abs_c1_m"),
                ("j2-distance: max abs C4 [m]", "law.max_abs_c4_m"),
                (
                    "j2-distance: min connectable time [h]",
                    "law.min_connectable_time_h"
                ),
            ]
        );
        assert_eq!(rows.last().unwrap().column, "wall_time_s");
    }

    #[test]
    fn seed_lists_are_written_compactly() {
        assert_eq!(seed_list(&[1, 2, 3, 4]), "1..4");
        assert_eq!(seed_list(&[1, 5, 9]), "1, 5, 9");
        assert_eq!(seed_list(&[3]), "3");
    }
}
