//! The command line's table formats and `characterize` on a run's trajectory file: `run --format`,
//! `[output] format` and the default by swarm size; `characterize DIR/trajectory.{csv,parquet}
//! [--time-s T]` against the positions-file form fed with the same rows (read by the `csv` crate); and
//! files `characterize` must refuse without reading them (a device, a file beyond its size cap).

use std::path::{Path, PathBuf};
use std::process::Output;

mod common;
use common::{satflock, scratch_dir, stderr};

/// A built-in scenario's text with replacements (each must apply), written to `dir/NAME.toml`.
fn builtin_file(dir: &Path, name: &str, replacements: &[(&str, &str)]) -> PathBuf {
    let b = satflock::scenario::builtin::BUILTINS
        .iter()
        .find(|b| b.name == name)
        .unwrap();
    let mut text = b.toml.to_string();
    for (from, to) in replacements {
        assert!(text.contains(from), "{name}: `{from}` not found");
        text = text.replace(from, to);
    }
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

fn run(scenario: &Path, out: &Path, extra: &[&str]) -> Output {
    let output = satflock()
        .args(["run", "--quiet", "--out"])
        .arg(out)
        .arg(scenario)
        .args(extra)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

fn characterize(file: &Path, extra: &[&str]) -> Output {
    satflock()
        .arg("characterize")
        .arg(file)
        .args(extra)
        .output()
        .unwrap()
}

fn json(o: &Output) -> serde_json::Value {
    assert!(o.status.success(), "{}", stderr(o));
    serde_json::from_slice(&o.stdout).unwrap()
}

/// The rows of `trajectory.csv` at `t_s` (the CSV's own text) as an `x_m,y_m,z_m` positions file.
fn positions_at(trajectory: &Path, t_s: &str, out: &Path) -> usize {
    let mut reader = csv::Reader::from_path(trajectory).unwrap();
    let header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    let (t, x, y, z) = (
        col("t_s"),
        col("x_lvlh_m"),
        col("y_lvlh_m"),
        col("z_lvlh_m"),
    );
    let mut text = String::from("x_m,y_m,z_m\n");
    let mut rows = 0;
    for record in reader.records() {
        let r = record.unwrap();
        if &r[t] == t_s {
            text.push_str(&format!("{},{},{}\n", &r[x], &r[y], &r[z]));
            rows += 1;
        }
    }
    std::fs::write(out, text).unwrap();
    rows
}

#[test]
fn val_characterize_a_trajectory_at_a_recorded_time_in_both_formats() {
    let dir = scratch_dir("characterize");
    let scenario = builtin_file(
        &dir,
        "es-e3a",
        &[("duration_s = 430.0", "duration_s = 140.0")],
    );
    let csv_run = dir.join("csv");
    let parquet_run = dir.join("parquet");
    run(&scenario, &csv_run, &["--format", "csv"]);
    run(&scenario, &parquet_run, &["--format", "parquet"]);
    let csv_file = csv_run.join("trajectory.csv");
    let parquet_file = parquet_run.join("trajectory.parquet");
    assert!(parquet_file.exists() && parquet_run.join("metrics.parquet").exists());
    assert!(!parquet_run.join("trajectory.csv").exists());

    // The same rows given as a positions file: the reference.
    let positions = dir.join("positions-120.csv");
    assert_eq!(positions_at(&csv_file, "120", &positions), 6);
    let expected = json(&characterize(&positions, &[]));

    let exact = characterize(&csv_file, &["--time-s", "120"]);
    assert_eq!(json(&exact), expected);
    assert!(stderr(&exact).contains("t_s = 120 s"), "{}", stderr(&exact));
    let nearest = characterize(&parquet_file, &["--time-s", "120.3"]);
    assert_eq!(json(&nearest), expected);
    assert!(
        stderr(&nearest).contains("t_s = 120 s") && stderr(&nearest).contains("nearest"),
        "{}",
        stderr(&nearest)
    );

    // Without --time-s: the last recorded time.
    let positions = dir.join("positions-140.csv");
    assert_eq!(positions_at(&csv_file, "140", &positions), 6);
    let last = characterize(&parquet_file, &[]);
    assert_eq!(json(&last), json(&characterize(&positions, &[])));
    assert!(stderr(&last).contains("t_s = 140 s"), "{}", stderr(&last));

    // Outside the recorded times: exit 2 naming the range.
    for t in ["141", "-1"] {
        let o = characterize(&csv_file, &["--time-s", t]);
        assert_eq!(o.status.code(), Some(2), "{t}");
        assert!(stderr(&o).contains("[0, 140]"), "{}", stderr(&o));
    }
    // --time-s on a positions file is refused.
    let o = characterize(&positions, &["--time-s", "1"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--time-s"), "{}", stderr(&o));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn regress_characterize_refuses_devices_and_oversized_files() {
    let o = characterize(Path::new("/dev/zero"), &[]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("not a regular file"), "{}", stderr(&o));
    // A sparse file one byte over the 4 GiB cap of tables (no disk space used).
    let dir = scratch_dir("huge");
    let huge = dir.join("huge.csv");
    let file = std::fs::File::create(&huge).unwrap();
    file.set_len(satflock::input_file::MAX_TABLE_BYTES + 1)
        .unwrap();
    let o = characterize(&huge, &[]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("4294967296"), "{}", stderr(&o));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn val_format_from_the_scenario_and_the_default_by_swarm_size() {
    let dir = scratch_dir("default");
    // 1001 satellites and no format: metrics as CSV, trajectory as Parquet.
    let large = builtin_file(
        &dir,
        "free-drift",
        &[
            ("count = 50", "count = 1001"),
            ("duration_s = 5800.0", "duration_s = 40.0"),
        ],
    );
    let out = dir.join("large");
    run(&large, &out, &[]);
    assert!(out.join("metrics.csv").exists() && out.join("trajectory.parquet").exists());
    assert!(!out.join("trajectory.csv").exists() && !out.join("metrics.parquet").exists());
    // --format csv overrides the default; a second run into the same directory clears the first.
    run(&large, &out, &["--format", "csv"]);
    assert!(out.join("trajectory.csv").exists() && !out.join("trajectory.parquet").exists());

    // [output] format = "parquet" in the scenario; --format csv overrides it.
    let small = builtin_file(
        &dir,
        "free-drift",
        &[("[law]", "[output]\nformat = \"parquet\"\n\n[law]")],
    );
    let out = dir.join("small");
    run(&small, &out, &[]);
    assert!(out.join("metrics.parquet").exists() && out.join("trajectory.parquet").exists());
    run(&small, &out, &["--format", "csv"]);
    assert!(out.join("metrics.csv").exists() && !out.join("metrics.parquet").exists());

    // An unknown format is refused with the allowed values, and nothing is written.
    let bad = builtin_file(
        &dir,
        "free-drift",
        &[("[law]", "[output]\nformat = \"xlsx\"\n\n[law]")],
    );
    let out = dir.join("bad");
    let o = satflock()
        .args(["run", "--quiet", "--out"])
        .arg(&out)
        .arg(&bad)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("xlsx") && stderr(&o).contains("csv") && stderr(&o).contains("parquet"),
        "{}",
        stderr(&o)
    );
    assert!(!out.exists());
    let _ = std::fs::remove_dir_all(&dir);
}
