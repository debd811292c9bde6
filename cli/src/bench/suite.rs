//! `satflock bench` (the suite): a fixed list of cases, each measured in a child process of this binary
//! (`satflock bench case NAME N`, hidden) so that its peak resident memory (VmHWM of
//! `/proc/self/status`) is its own. One JSON line per case on stdout (`setup_s`: the wall clock of building
//! the case's simulation, from its scenario text to the law's set-up), then a Markdown table.
//!
//! Cases (N = 10^3 … 10^6 unless `--max-n` says less; a few steps at the largest N; `satflock bench case`
//! runs the sphere cases at any N up to the scenario layer's 10^7, e.g. `bench case bifurcating 10000000
//! --steps 100`):
//! * `propagation`: the engine with no law (`name = "none"`, free drift) (J2 truth, RK4 and sampled control at 1 s);
//! * `hold-repel`: the `hold` law plus a pairwise spring repulsion through the neighbour grid, ~10
//!   neighbours each (also the criterion benchmark `cli/benches/engine_step.rs`);
//! * `bifurcating`: the `gao-circle` law and timing (RK4 at 0.05 s) on a ball sized for ~10 neighbours in
//!   its 500 m sensing range;
//! * `equilibrium-shaping`: the moving-centroid strategy on a triangular lattice 6 m apart, 0.025 s
//!   (its set-up is O(N k) through a neighbour grid over the nodes: the rate bound sums the pairs
//!   within a cutoff radius, k ≈ 57 here; its scenario text lists every node inline, and building the
//!   case from that text dominates the set-up at 10^6);
//! * `pigeon`: the `pigeon-switching` law on J2 truth at 0.1 s, ~10 neighbours in 150 m (the suite steps
//!   without a recorder, so the law's O(N²) record-time metrics, `Pigeon::swarm_measures`, never run);
//! * `five-elements`: the five-element characterisation of 10^5 positions (one call).
//!
//! The `j2-distance` law is not in the suite: its grouping step is centralised over the whole swarm.
//! The simulations are built in `crate::bench_cases`. Timings are wall clock; nothing here is
//! asserted by tests.

use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

use crate::bench_cases::simulation;
use anyhow::{bail, Context, Result};
use nalgebra::Vector3;
use satflock::metrics::{five_elements, FiveElementsWorkspace};
use satflock::scenario::{initial, MAX_SATELLITES};

/// The cases: name, the law that runs (if any), and the largest N the case takes (the suite measures
/// [`SIZES`] up to it; `satflock bench case` takes any N up to it).
const CASES: &[(&str, Option<&str>, usize)] = &[
    ("propagation", Some("none"), MAX_SATELLITES),
    ("hold-repel", Some("hold+repulsion"), MAX_SATELLITES),
    ("bifurcating", Some("bifurcating"), MAX_SATELLITES),
    (
        "equilibrium-shaping",
        Some("equilibrium-shaping"),
        1_000_000,
    ),
    ("pigeon", Some("pigeon"), MAX_SATELLITES),
    ("five-elements", None, 100_000),
];

/// Sizes of the guided cases.
const SIZES: [usize; 4] = [1_000, 10_000, 100_000, 1_000_000];

/// The stage names of the split, in the order of the JSON keys and table columns.
const STAGES: [&str; 5] = ["sensing", "law", "propagation", "monitors", "recording"];

/// Runs the suite: every case (or only `only`) at every size up to `max_n` (`quick`: N = 1000 only).
pub fn run_suite(quick: bool, only: Option<&str>, max_n: Option<usize>) -> Result<()> {
    if let Some(name) = only {
        case_entry(name)?;
    }
    let max_n = match max_n {
        Some(n) if !(1_000..=1_000_000).contains(&n) => {
            return Err(crate::usage(format!(
                "--max-n must be between 1000 and 1000000 satellites, got {n}"
            )))
        }
        Some(n) => n,
        None if quick => 1_000,
        None => 1_000_000,
    };
    let exe = std::env::current_exe().context("cannot find this program's own path")?;
    let mut rows = Vec::new();
    for &(name, _, largest) in CASES {
        if only.is_some_and(|o| o != name) {
            continue;
        }
        let sizes: Vec<usize> = if name == "five-elements" {
            vec![if quick { 1_000 } else { 100_000 }]
        } else {
            SIZES.into_iter().filter(|&n| n <= largest).collect()
        };
        for n in sizes.into_iter().filter(|&n| n <= max_n) {
            let line = run_child(&exe, name, n)?;
            println!("{line}");
            rows.push(serde_json::from_str::<serde_json::Value>(&line)?);
        }
    }
    println!();
    print!("{}", table(&rows));
    Ok(())
}

/// Runs one case in a child process of `exe` and returns its JSON line.
fn run_child(exe: &Path, name: &str, n: usize) -> Result<String> {
    let output = Command::new(exe)
        .args(["bench", "case", name, &n.to_string()])
        .output()
        .with_context(|| format!("cannot start the case {name} at N = {n}"))?;
    if !output.status.success() {
        bail!(
            "the case {name} at N = {n} failed: {}",
            String::from_utf8_lossy(&output.stderr).trim()
        );
    }
    let text = String::from_utf8(output.stdout).context("a case printed invalid UTF-8")?;
    Ok(text.trim().to_string())
}

fn case_entry(name: &str) -> Result<&'static (&'static str, Option<&'static str>, usize)> {
    CASES.iter().find(|c| c.0 == name).ok_or_else(|| {
        let names: Vec<&str> = CASES.iter().map(|c| c.0).collect();
        crate::usage(format!(
            "unknown bench case `{name}`; the cases are {}",
            names.join(", ")
        ))
    })
}

/// Steps timed at `n` satellites (after one untimed warm-up step).
fn steps_for(n: usize) -> usize {
    match n {
        0..=1_000 => 50,
        1_001..=10_000 => 20,
        10_001..=100_000 => 5,
        _ => 2,
    }
}

/// Measures one case at `n` satellites in this process over `steps` timed steps (the suite's default for
/// `n` when `None`), re-sorting the storage every `resort_every` ticks (the engine's default when
/// `None`), and prints its JSON line (`satflock bench case`).
pub fn run_case(
    name: &str,
    n: usize,
    steps: Option<usize>,
    resort_every: Option<u64>,
) -> Result<()> {
    let &(name, law, largest) = case_entry(name)?;
    if !(2..=largest).contains(&n) {
        return Err(crate::usage(format!(
            "the case {name} takes N from 2 to {largest} satellites, got {n}"
        )));
    }
    let mut setup_s = None;
    let (steps, wall_s, split) = if name == "five-elements" {
        let positions = initial::sphere(1, n, 1000.0, Vector3::zeros());
        let points: Vec<[f64; 3]> = positions.iter().map(|p| (*p).into()).collect();
        let velocities = vec![[0.0; 3]; n];
        let mut workspace = FiveElementsWorkspace::new();
        let clock = Instant::now();
        five_elements(&points, &velocities, None, &mut workspace)?;
        (1, clock.elapsed().as_secs_f64(), None)
    } else {
        let clock = Instant::now();
        let mut simulation = simulation(name, n)?;
        setup_s = Some(clock.elapsed().as_secs_f64());
        if let Some(ticks) = resort_every {
            simulation.set_resort_period_ticks(ticks);
        }
        simulation.step()?;
        let before = simulation.stage_timings();
        let steps = steps.unwrap_or_else(|| steps_for(n));
        let clock = Instant::now();
        for _ in 0..steps {
            simulation.step()?;
        }
        let wall_s = clock.elapsed().as_secs_f64();
        let after = simulation.stage_timings();
        let spent = [
            after.sensing_s - before.sensing_s,
            after.law_s - before.law_s,
            after.propagation_s - before.propagation_s,
            after.monitors_s - before.monitors_s,
            after.recording_s - before.recording_s,
        ];
        (steps, wall_s, Some(spent.map(|s| s / wall_s.max(1e-12))))
    };
    let peak = peak_rss_bytes();
    let mut line = serde_json::json!({
        "case": name,
        "law": law,
        "n": n,
        "steps": steps,
        "sat_steps_per_s": (n * steps) as f64 / wall_s.max(1e-12),
        "wall_s": wall_s,
        "setup_s": setup_s,
        "peak_rss_bytes": peak,
        "bytes_per_satellite": peak.map(|b| b as f64 / n as f64),
    });
    if let Some(split) = split {
        line["split"] = STAGES
            .iter()
            .zip(split)
            .map(|(k, v)| (k.to_string(), serde_json::json!(v)))
            .collect::<serde_json::Map<_, _>>()
            .into();
    }
    println!("{line}");
    Ok(())
}

/// Peak resident set size of this process \[bytes\] (VmHWM), where `/proc` has it.
fn peak_rss_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// The Markdown table of the suite's rows.
fn table(rows: &[serde_json::Value]) -> String {
    let mut out = String::from(
        "| case | law | N | steps | sat-steps/s | wall [s] | peak RSS [MB] | B/sat | sensing | law | propagation | monitors | recording |\n\
         | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n",
    );
    for row in rows {
        let number = |key: &str| row[key].as_f64().unwrap_or(f64::NAN);
        let split: Vec<String> = STAGES
            .iter()
            .map(|s| match row["split"][s].as_f64() {
                Some(f) => format!("{:.0} %", 100.0 * f),
                None => "".into(),
            })
            .collect();
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {:.3e} | {:.3} | {:.1} | {:.0} | {} |",
            row["case"].as_str().unwrap_or(""),
            row["law"].as_str().unwrap_or(""),
            number("n"),
            number("steps"),
            number("sat_steps_per_s"),
            number("wall_s"),
            number("peak_rss_bytes") / 1e6,
            number("bytes_per_satellite"),
            split.join(" | ")
        );
    }
    out
}
