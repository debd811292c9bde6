//! `satflock run --law` and `satflock compare` end to end, on a small case (3 satellites, HCW, 300 s,
//! one threat): controller files refused for case keys, the law and law events replaced and the case's
//! events kept, the same initial states for every law, failures recorded as rows, the Parquet table
//! read back against the Markdown numbers, and outputs independent of `--jobs`.

use std::path::{Path, PathBuf};
use std::process::Output;

use satflock::output::RunTable;

mod common;
use common::satflock;

/// The case: process noise so that runs differ by seed beyond their initial states; a threat with a
/// warning (a case event) and a slot change (a law event of the case's own `hold` law).
const CASE: &str = r#"
name = "compare-test"
seed = 1
duration_s = 300.0
record_interval_s = 10.0

[dynamics]
model = "hcw"
integrator = "rk4"
step_s = 0.1
process_noise_mps2 = 1e-6
max_distance_m = 400.0

[reference]
altitude_m = 600e3
inclination_deg = 97.8

[satellites]
count = 3
mass_kg = 10.0
radius_m = 0.2
initial = { distribution = "sphere", radius_m = 50.0 }

[sensing]
range_m = 500.0

[law]
name = "hold"
stiffness_per_s2 = 1e-3
damping_per_s = 5e-2

[[threats]]
danger_radius_m = 5.0
aim_point_hill_m = [0.0, 0.0, 0.0]
direction_hill = [0.0, 0.0, -1.0]
speed_mps = 10.0
arrival_time_s = 150.0

[[events]]
time_s = 100.0
action = "threat-warning"
threat = 0
active = true

[[events]]
time_s = 200.0
action = "set-law-parameters"
parameters = { slot_offset_hill_m = [0.0, 10.0, 0.0] }
"#;

/// Controllers: a stiffer hold, free drift, and a hold whose slots are 2 km away, so the satellites
/// pass `dynamics.max_distance_m` = 400 m and the run fails.
const CONTROLLERS: &[(&str, &str)] = &[
    (
        "stiff-hold.toml",
        "description = \"a stiffer hold\"\n[law]\nname = \"hold\"\nstiffness_per_s2 = 4e-3\ndamping_per_s = 0.1\n",
    ),
    ("drift.toml", "[law]\nname = \"none\"\n"),
    (
        "runaway.toml",
        "[law]\nname = \"hold\"\nstiffness_per_s2 = 1e-2\ndamping_per_s = 0.2\nslot_offset_hill_m = [0.0, 2000.0, 0.0]\n",
    ),
];

/// A fresh temporary directory with the case and the controller files.
fn setup(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("satflock-compare-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("laws")).unwrap();
    std::fs::write(dir.join("case.toml"), CASE).unwrap();
    for (file, text) in CONTROLLERS {
        std::fs::write(dir.join("laws").join(file), text).unwrap();
    }
    dir
}

/// `satflock compare` of the case with every controller and `builtin:es-e1` (the equilibrium-shaping
/// rhombus: 4 nodes for 3 satellites, refused), seeds 1..3.
fn compare(dir: &Path, out: &str, extra: &[&str]) -> Output {
    let mut command = satflock();
    command.arg("compare").arg(dir.join("case.toml"));
    for (file, _) in CONTROLLERS {
        command.arg("--law").arg(dir.join("laws").join(file));
    }
    command
        .args([
            "--law",
            "builtin:es-e1",
            "--seeds",
            "1..3",
            "--quiet",
            "--out",
        ])
        .arg(dir.join(out))
        .args(extra)
        .output()
        .unwrap()
}

fn text(o: &Output) -> (String, String) {
    (
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// The rows of a CSV file at time `t_s` (the `time_utc` column included: same time, same text).
fn rows_at(path: &Path, t_s: &str) -> Vec<String> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .skip(1)
        .filter(|l| l.split(',').next() == Some(t_s))
        .map(str::to_string)
        .collect()
}

#[test]
fn a_controller_file_with_a_case_key_is_refused_naming_file_and_key() {
    let dir = setup("refused");
    let bad = dir.join("laws").join("bad.toml");
    std::fs::write(
        &bad,
        "[law]\nname = \"none\"\n\n[sensing]\nrange_m = 10.0\n",
    )
    .unwrap();
    let out = satflock()
        .arg("run")
        .arg(dir.join("case.toml"))
        .arg("--law")
        .arg(&bad)
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .unwrap();
    let (_, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains(&bad.display().to_string()) && stderr.contains("`sensing`"),
        "{stderr}"
    );
    assert!(!dir.join("out").exists());
    // A case event in a controller file: refused, naming the event's key.
    std::fs::write(
        &bad,
        "[law]\nname = \"none\"\n\n[[events]]\ntime_s = 1.0\naction = \"threat-warning\"\nthreat = 0\nactive = false\n",
    )
    .unwrap();
    let out = satflock()
        .arg("compare")
        .arg(dir.join("case.toml"))
        .arg("--law")
        .arg(&bad)
        .arg("--out")
        .arg(dir.join("cmp-bad"))
        .output()
        .unwrap();
    let (_, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("key `events[0].action`"), "{stderr}");
    assert!(!dir.join("cmp-bad").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn run_law_replaces_the_law_and_law_events_and_keeps_case_events() {
    let dir = setup("run-law");
    let out_dir = dir.join("out");
    let out = satflock()
        .arg("run")
        .arg(dir.join("case.toml"))
        .arg("--law")
        .arg(dir.join("laws/stiff-hold.toml"))
        .args(["--quiet", "--no-plots", "--out"])
        .arg(&out_dir)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out).1);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("summary.json")).unwrap())
            .unwrap();
    assert_eq!(
        summary["controller"],
        dir.join("laws/stiff-hold.toml").display().to_string()
    );
    // The scenario as run: the controller's law, the case's threat warning, no set-law-parameters.
    let as_run = std::fs::read_to_string(out_dir.join("scenario.toml")).unwrap();
    assert!(as_run.starts_with("# As run: the case "), "{as_run}");
    let file: toml::Table = as_run.parse().unwrap();
    assert_eq!(file["law"]["stiffness_per_s2"].as_float(), Some(4e-3));
    let events = file["events"].as_array().unwrap();
    assert_eq!(events.len(), 1);
    assert_eq!(events[0]["action"].as_str(), Some("threat-warning"));
    // Without --law the summary has no controller key.
    let out = satflock()
        .arg("run")
        .arg(dir.join("case.toml"))
        .args(["--quiet", "--no-plots", "--out"])
        .arg(&out_dir)
        .output()
        .unwrap();
    assert!(out.status.success());
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("summary.json")).unwrap())
            .unwrap();
    assert!(summary.get("controller").is_none());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn compare_starts_every_law_from_the_same_states_and_records_failures() {
    let dir = setup("states");
    let out = compare(&dir, "cmp", &["--keep-runs", "--jobs", "2"]);
    let (stdout, stderr) = text(&out);
    assert!(out.status.success(), "{stderr}");
    assert!(stdout.starts_with("## satflock compare: "), "{stdout}");
    assert!(stderr.contains("6 of 12 runs did not complete"), "{stderr}");
    let runs = dir.join("cmp/runs");
    for seed in 1..=3 {
        let first = |label: &str| {
            rows_at(
                &runs.join(label).join(format!("seed-{seed}/trajectory.csv")),
                "0",
            )
        };
        let reference = first("stiff-hold");
        assert_eq!(reference.len(), 3);
        // The failed run's states at t = 0 too: it diverged later.
        for label in ["drift", "runaway"] {
            assert_eq!(first(label), reference, "{label}, seed {seed}");
        }
        // Seeds differ.
        if seed > 1 {
            assert_ne!(
                reference,
                rows_at(&runs.join("stiff-hold/seed-1/trajectory.csv"), "0")
            );
        }
    }
    // The refused law ran nothing.
    assert!(!runs.join("es-e1").exists());
    let table = RunTable::read_parquet(&dir.join("cmp/compare.parquet")).unwrap();
    assert_eq!(table.rows(), 12);
    let status = table.text("status").unwrap();
    let law = table.text("law").unwrap();
    for k in 0..12 {
        let expected = match law[k].as_str() {
            "stiff-hold" | "drift" => "completed",
            "runaway" => "failed",
            "es-e1" => "refused",
            other => panic!("law {other}"),
        };
        assert_eq!(status[k], expected, "{} seed {}", law[k], k);
    }
    let error = table.text("error").unwrap();
    assert!(
        error[6].contains("max_distance") || error[6].contains("diverg"),
        "{}",
        error[6]
    );
    assert!(
        error[9].contains("with the controller builtin:es-e1"),
        "{}",
        error[9]
    );
    // The plots: one overlay per metric, the threat's included.
    for name in [
        "min_separation",
        "d_max",
        "delta_v_mean",
        "min_threat_distance",
    ] {
        assert!(
            dir.join(format!("cmp/plots/{name}.png")).is_file(),
            "{name}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The p-quantile by linear interpolation between order statistics, written out again for the test.
fn quantile(values: &[f64], p: f64) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    let h = (v.len() - 1) as f64 * p;
    let (lo, hi) = (h.floor() as usize, h.ceil() as usize);
    v[lo] + (h - h.floor()) * (v[hi] - v[lo])
}

/// The numbers of a cell: `—` none; `m`; `m [a, b]`; either with `(k of n)`.
fn cell_numbers(cell: &str) -> Vec<f64> {
    let cell = cell.split(" (").next().unwrap().trim();
    if cell == "—" {
        return Vec::new();
    }
    cell.replace(['[', ']', ','], " ")
        .split_whitespace()
        .map(|n| n.parse().unwrap_or_else(|_| panic!("`{n}` in `{cell}`")))
        .collect()
}

#[test]
fn the_parquet_table_read_back_equals_the_markdown_numbers() {
    let dir = setup("markdown");
    let out = compare(&dir, "cmp", &[]);
    assert!(out.status.success(), "{}", text(&out).1);
    let markdown = std::fs::read_to_string(dir.join("cmp/compare.md")).unwrap();
    assert_eq!(markdown, text(&out).0);
    let table = RunTable::read_parquet(&dir.join("cmp/compare.parquet")).unwrap();
    let labels = table.text("law").unwrap();
    let lines: Vec<&str> = markdown.lines().filter(|l| l.starts_with("| ")).collect();
    let header: Vec<String> = lines[0]
        .split('|')
        .skip(2)
        .map(|c| c.trim().trim_matches('`').to_string())
        .filter(|c| !c.is_empty())
        .collect();
    assert_eq!(header, ["stiff-hold", "drift", "runaway", "es-e1"]);
    // Row label → summary column.
    let rows = [
        ("Δv per satellite, mean [m/s]", "delta_v_mps.mean"),
        ("Δv per satellite, largest [m/s]", "delta_v_mps.max"),
        ("minimum separation [m]", "min_separation_m"),
        (
            "closest threat approach [m]",
            "environment.closest_threat_approach.minimum.distance_m",
        ),
        ("final d_max [m]", "final.five_elements.d_max_m"),
        ("final uniformity L [-]", "final.five_elements.uniformity_l"),
    ];
    let mut checked = 0;
    for (label, column) in rows {
        let line = lines
            .iter()
            .find(|l| l.starts_with(&format!("| {label} |")))
            .unwrap_or_else(|| panic!("no row {label}"));
        let cells: Vec<&str> = line.split('|').skip(2).map(str::trim).collect();
        let values = table.numbers(column).unwrap();
        for (k, law) in header.iter().enumerate() {
            let of_law: Vec<f64> = (0..table.rows())
                .filter(|&r| labels[r] == *law)
                .map(|r| values[r])
                .filter(|v| v.is_finite())
                .collect();
            let shown = cell_numbers(cells[k]);
            if of_law.is_empty() {
                assert!(shown.is_empty(), "{label} {law}: {}", cells[k]);
                continue;
            }
            let expected = [
                quantile(&of_law, 0.5),
                quantile(&of_law, 0.05),
                quantile(&of_law, 0.95),
            ];
            let expected = if shown.len() == 1 {
                &expected[..1]
            } else {
                &expected[..]
            };
            assert_eq!(shown.len(), expected.len(), "{label} {law}: {}", cells[k]);
            for (s, e) in shown.iter().zip(expected) {
                // Four significant digits.
                assert!(
                    (s - e).abs() <= 5e-4 * e.abs() + 1e-12,
                    "{label} {law}: shown {s}, from the table {e}"
                );
                checked += 1;
            }
        }
    }
    assert!(checked >= 20, "{checked}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_table_does_not_depend_on_jobs() {
    let dir = setup("jobs");
    for (out, jobs) in [("one", "1"), ("two", "2")] {
        let o = compare(&dir, out, &["--jobs", jobs]);
        assert!(o.status.success(), "{}", text(&o).1);
    }
    let one = RunTable::read_parquet(&dir.join("one/compare.parquet")).unwrap();
    let two = RunTable::read_parquet(&dir.join("two/compare.parquet")).unwrap();
    assert_eq!(one.text, two.text);
    let timing = ["wall_time_s", "satellite_steps_per_s"];
    let names =
        |t: &RunTable| -> Vec<String> { t.numbers.iter().map(|(n, _)| n.clone()).collect() };
    assert_eq!(names(&one), names(&two));
    let mut compared = 0;
    for ((name, a), (_, b)) in one.numbers.iter().zip(&two.numbers) {
        if timing.contains(&name.as_str()) {
            continue;
        }
        for (x, y) in a.iter().zip(b) {
            assert_eq!(x.to_bits(), y.to_bits(), "{name}");
        }
        compared += 1;
    }
    assert!(compared > 20, "{compared}");
    // A second comparison into a previous one's directory replaces it.
    let o = compare(&dir, "one", &["--jobs", "2"]);
    assert!(o.status.success(), "{}", text(&o).1);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn regress_seeds_beyond_2_to_the_53_are_stored_exactly() {
    let dir = setup("big-seeds");
    let seeds = [u64::MAX, (1u64 << 53) + 1];
    let out = satflock()
        .arg("compare")
        .arg(dir.join("case.toml"))
        .arg("--law")
        .arg(dir.join("laws/drift.toml"))
        .arg("--seeds")
        .arg(format!("{},{}", seeds[0], seeds[1]))
        .args(["--quiet", "--out"])
        .arg(dir.join("cmp"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out).1);
    let table = RunTable::read_parquet(&dir.join("cmp/compare.parquet")).unwrap();
    assert_eq!(table.integers("seed"), Some(&seeds[..]));
    assert!(table.numbers("seed").is_none());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn regress_a_controller_invalid_in_itself_exits_2_before_any_run() {
    let dir = setup("invalid-controller");
    for (name, controller, key) in [
        (
            "nan.toml",
            "[law]\nname = \"hold\"\nstiffness_per_s2 = nan\ndamping_per_s = 0.1\n",
            "law",
        ),
        (
            "period.toml",
            "[law]\nname = \"none\"\n[control]\nmode = \"sampled\"\nperiod_s = -1.0\n",
            "control.period_s",
        ),
        (
            "event.toml",
            "[law]\nname = \"hold\"\nstiffness_per_s2 = 1e-3\ndamping_per_s = 0.1\n[[events]]\n\
             time_s = 10.0\naction = \"set-law-parameters\"\nparameters = { damping_per_s = -1.0 }\n",
            "events[0].parameters",
        ),
    ] {
        let bad = dir.join("laws").join(name);
        std::fs::write(&bad, controller).unwrap();
        let out_dir = dir.join(format!("cmp-{name}"));
        let out = satflock()
            .arg("compare")
            .arg(dir.join("case.toml"))
            .arg("--law")
            .arg(dir.join("laws/drift.toml"))
            .arg("--law")
            .arg(&bad)
            .args(["--seeds", "1..2", "--quiet", "--out"])
            .arg(&out_dir)
            .output()
            .unwrap();
        let (_, stderr) = text(&out);
        assert_eq!(out.status.code(), Some(2), "{name}: {stderr}");
        assert!(
            stderr.contains(&bad.display().to_string()) && stderr.contains(&format!("key `{key}`")),
            "{name}: {stderr}"
        );
        assert!(stderr.contains("allowed"), "{name}: {stderr}");
        assert!(!out_dir.exists(), "{name}: nothing may run");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
