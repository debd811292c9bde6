//! Regression cases of issue 12 (faults and honest outputs of `satflock run` and `propagate`): signals,
//! whole CSV rows after SIGKILL, the output directory, no NaN in metrics.csv, collision and delta-v
//! warnings, and the CLI's ranges for `--threads` and negative numbers; of issue 25: a full disk (a
//! file-size limit) leaves every file valid or removed and a `failed` summary.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use satflock::scenario::builtin::BUILTINS;

mod common;
use common::{satflock, scratch_dir, stderr};

/// A fresh temporary directory for one test.
/// A built-in scenario's TOML with some `key = value` lines replaced (each `from` must occur).
fn builtin_with(name: &str, replacements: &[(&str, &str)]) -> String {
    let mut text = BUILTINS
        .iter()
        .find(|b| b.name == name)
        .unwrap_or_else(|| panic!("no built-in {name}"))
        .toml
        .to_string();
    for (from, to) in replacements {
        assert!(text.contains(from), "{name} has no `{from}`");
        text = text.replacen(from, to, 1);
    }
    text
}

fn write_scenario(dir: &Path, text: &str) -> PathBuf {
    let path = dir.join("scenario.toml");
    std::fs::write(&path, text).unwrap();
    path
}

fn run_to(scenario: &Path, out: &Path, extra: &[&str]) -> Output {
    satflock()
        .arg("run")
        .arg(scenario)
        .arg("--out")
        .arg(out)
        .arg("--quiet")
        .args(extra)
        .output()
        .unwrap()
}

fn summary(out: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(out.join("summary.json")).expect("summary.json exists");
    serde_json::from_str(&text).expect("summary.json is valid JSON")
}

/// Asserts every line of a CSV file has the header's column count and the file ends with a newline.
/// Returns the number of data rows.
fn assert_whole_rows(path: &Path) -> usize {
    let text = std::fs::read_to_string(path).unwrap();
    assert!(
        text.ends_with('\n'),
        "{} ends in a torn row",
        path.display()
    );
    assert_whole_rows_but_an_unterminated_tail(path)
}

/// After a SIGKILL: every newline-terminated line has the header's column count; only a final,
/// unterminated line may be cut (the kernel may split one large write() when a fatal signal arrives, so
/// whole-record writes make a torn record rare, not impossible — readers drop an unterminated last line,
/// as docs/outputs.md says). Returns the number of whole data rows.
fn assert_whole_rows_but_an_unterminated_tail(path: &Path) -> usize {
    let text = std::fs::read_to_string(path).unwrap();
    let whole = match text.rfind('\n') {
        Some(k) => &text[..=k],
        None => "",
    };
    let mut lines = whole.lines();
    let columns = lines.next().expect("a header").split(',').count();
    let mut rows = 0;
    for (k, line) in lines.enumerate() {
        assert_eq!(
            line.split(',').count(),
            columns,
            "{} line {}: `{line}`",
            path.display(),
            k + 2
        );
        rows += 1;
    }
    rows
}

fn line_count(path: &Path) -> usize {
    std::fs::read(path)
        .map(|b| b.iter().filter(|&&c| c == b'\n').count())
        .unwrap_or(0)
}

/// A long free-drift run writing both CSV files at every second (killed long before its end).
fn long_free_drift(dir: &Path) -> PathBuf {
    write_scenario(
        dir,
        &builtin_with(
            "free-drift",
            &[
                ("duration_s = 5800.0", "duration_s = 23200.0"),
                ("record_interval_s = 20.0", "record_interval_s = 1.0"),
            ],
        ),
    )
}

/// Spawns a run and waits until `file` in its output has more than `lines` lines.
fn spawn_until(scenario: &Path, out: &Path, file: &str, lines: usize) -> Child {
    let child = satflock()
        .arg("run")
        .arg(scenario)
        .arg("--out")
        .arg(out)
        .arg("--quiet")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let started = Instant::now();
    while line_count(&out.join(file)) <= lines {
        assert!(
            started.elapsed() < Duration::from_secs(120),
            "the run never wrote {lines} lines of {file}"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    child
}

fn kill(child: &Child, signal: &str) {
    let status = Command::new("kill")
        .arg(format!("-{signal}"))
        .arg(child.id().to_string())
        .status()
        .unwrap();
    assert!(status.success());
}

#[test]
fn regress_sigterm_closes_files_and_writes_interrupted_summary() {
    let dir = scratch_dir("sigterm");
    let scenario = long_free_drift(&dir);
    let out = dir.join("out");
    let child = spawn_until(&scenario, &out, "metrics.csv", 3);
    kill(&child, "TERM");
    let output = child.wait_with_output().unwrap();
    assert_eq!(output.status.code(), Some(143), "{}", stderr(&output));
    assert!(
        stderr(&output).contains("interrupted"),
        "{}",
        stderr(&output)
    );
    let s = summary(&out);
    assert_eq!(s["status"], "interrupted");
    let simulated = s["simulated_s"].as_f64().unwrap();
    assert!(simulated > 0.0 && simulated < 23200.0, "{simulated}");
    let rows = assert_whole_rows(&out.join("metrics.csv"));
    assert!(rows >= 3);
    // The recorder got every record up to the time reached (one per second from t = 0).
    assert_eq!(rows, simulated.floor() as usize + 1);
    assert_whole_rows(&out.join("trajectory.csv"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn regress_sigint_exits_130_with_interrupted_summary() {
    let dir = scratch_dir("sigint");
    let scenario = long_free_drift(&dir);
    let out = dir.join("out");
    let child = spawn_until(&scenario, &out, "metrics.csv", 3);
    kill(&child, "INT");
    let output = child.wait_with_output().unwrap();
    assert_eq!(output.status.code(), Some(130), "{}", stderr(&output));
    assert_eq!(summary(&out)["status"], "interrupted");
    assert_whole_rows(&out.join("metrics.csv"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn regress_sigkill_leaves_only_whole_trajectory_rows() {
    // Each record (50 rows of trajectory.csv) is written in one piece: a SIGKILL loses whole records,
    // except that the kernel may cut one large write() short, leaving an unterminated last line (seen
    // once under heavy load). Repeated to land the kill at different points of the writing.
    let dir = scratch_dir("sigkill");
    let scenario = long_free_drift(&dir);
    for attempt in 0..3 {
        let out = dir.join(format!("out{attempt}"));
        let mut child = spawn_until(&scenario, &out, "trajectory.csv", 2000 + 3000 * attempt);
        kill(&child, "KILL");
        child.wait().unwrap();
        assert!(assert_whole_rows_but_an_unterminated_tail(&out.join("trajectory.csv")) >= 2000);
        assert_whole_rows_but_an_unterminated_tail(&out.join("metrics.csv"));
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn regress_out_dir_not_a_previous_run_is_refused() {
    let dir = scratch_dir("foreign");
    let out = dir.join("mine");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("notes.txt"), "keep me").unwrap();
    let o = satflock()
        .args(["run", "free-drift", "--quiet", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("mine") && stderr(&o).contains("notes.txt"),
        "{}",
        stderr(&o)
    );
    assert_eq!(
        std::fs::read_to_string(out.join("notes.txt")).unwrap(),
        "keep me"
    );
    assert!(!out.join("metrics.csv").exists());
    // A file given as --out is refused too.
    let o = satflock()
        .args(["run", "free-drift", "--quiet", "--out"])
        .arg(out.join("notes.txt"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn regress_out_dir_of_previous_run_is_cleared_first() {
    let dir = scratch_dir("previous");
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    // A previous run's files: an old completed summary and a trajectory the new run does not write.
    std::fs::write(
        out.join("summary.json"),
        "{\"status\": \"completed\", \"stale\": true}",
    )
    .unwrap();
    std::fs::write(out.join("trajectory.csv"), "t_s,id\n0,0\n").unwrap();
    std::fs::write(out.join("metrics.csv"), "t_s\n0\n").unwrap();
    let scenario = write_scenario(
        &dir,
        &(builtin_with(
            "free-drift",
            &[("duration_s = 5800.0", "duration_s = 100.0")],
        ) + "\n[output]\ntrajectory = false\n"),
    );
    let o = run_to(&scenario, &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = summary(&out);
    assert_eq!(s["status"], "completed");
    assert!(s.get("stale").is_none());
    assert!(!out.join("trajectory.csv").exists());
    assert_whole_rows(&out.join("metrics.csv"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn regress_propagate_out_directory_is_refused_without_partial_file() {
    let dir = scratch_dir("propagate-dir");
    let o = satflock()
        .args([
            "propagate",
            "--elements",
            "6978137,0.001,97.8,0,0,0",
            "--duration-s",
            "600",
            "--output-step-s",
            "60",
            "--out",
        ])
        .arg(&dir)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("directory"), "{}", stderr(&o));
    let parent = dir.parent().unwrap();
    for entry in std::fs::read_dir(parent).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        assert!(
            !(name.starts_with(dir.file_name().unwrap().to_str().unwrap())
                && name.ends_with(".partial")),
            "left behind: {name}"
        );
    }
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn regress_no_nan_in_metrics_of_j2_distance_first_row() {
    let dir = scratch_dir("nan");
    let scenario = write_scenario(
        &dir,
        &builtin_with(
            "ts-plane-1",
            &[
                ("duration_s = 432000.0", "duration_s = 20.0"),
                ("record_interval_s = 1800.0", "record_interval_s = 10.0"),
            ],
        ),
    );
    let out = dir.join("out");
    let o = run_to(&scenario, &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(out.join("metrics.csv")).unwrap();
    assert!(!text.to_ascii_lowercase().contains("nan"), "{text}");
    assert_whole_rows(&out.join("metrics.csv"));
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let first: Vec<&str> = lines.next().unwrap().split(',').collect();
    let p50 = header
        .iter()
        .position(|h| *h == "ts_edge_ratio_p50")
        .expect("the j2-distance law's columns");
    // No edge yet at t = 0: the ratio does not exist, so the cell is empty; later rows are numbers.
    assert_eq!(first[0], "0");
    assert!(first[p50].is_empty(), "t = 0: `{}`", first[p50]);
    // summary.json never holds NaN either (serde_json refuses to write it; null instead).
    assert!(!std::fs::read_to_string(out.join("summary.json"))
        .unwrap()
        .contains("NaN"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// ts-outage, shortened: its satellites overlap from t = 0, so the run has collisions.
fn colliding(dir: &Path, extra_output: &str) -> PathBuf {
    write_scenario(
        dir,
        &builtin_with(
            "ts-outage",
            &[
                ("duration_s = 86400.0", "duration_s = 120.0"),
                ("time_s = 3600.0", "time_s = 60.0"),
                (
                    "trajectory = false",
                    &format!("trajectory = false\n{extra_output}"),
                ),
            ],
        ),
    )
}

#[test]
fn regress_collisions_warn_and_complete_unless_fail_on_collision() {
    let dir = scratch_dir("collisions");
    let scenario = colliding(&dir, "");
    let out = dir.join("out");
    let o = run_to(&scenario, &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("warning: collisions"), "{}", stderr(&o));
    let s = summary(&out);
    assert_eq!(s["status"], "completed");
    assert!(s["collisions"].as_u64().unwrap() > 0);
    let warnings = s["warnings"].as_array().unwrap();
    assert!(warnings
        .iter()
        .any(|w| w.as_str().unwrap().starts_with("collisions")));

    let o = run_to(&scenario, &out, &["--fail-on-collision"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("--fail-on-collision"), "{}", stderr(&o));
    assert_eq!(summary(&out)["status"], "completed");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn regress_delta_v_budget_warns_and_is_range_checked() {
    let dir = scratch_dir("budget");
    let out = dir.join("out");
    let scenario = colliding(&dir, "delta_v_budget_mps = 1e-12");
    let o = run_to(&scenario, &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("warning: delta-v budget exceeded"),
        "{}",
        stderr(&o)
    );
    let s = summary(&out);
    assert!(s["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .any(|w| w.as_str().unwrap().contains("delta_v_budget_mps")));

    let scenario = colliding(&dir, "delta_v_budget_mps = -1.0");
    let out2 = dir.join("out2");
    let o = run_to(&scenario, &out2, &[]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("output.delta_v_budget_mps") && stderr(&o).contains("> 0"),
        "{}",
        stderr(&o)
    );
    assert!(!out2.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn regress_threads_out_of_range_refused_with_range() {
    let dir = scratch_dir("threads");
    for value in ["100000", "-1", "0", "1025"] {
        let o = satflock()
            .args(["run", "free-drift", "--quiet", "--threads", value, "--out"])
            .arg(dir.join("out"))
            .output()
            .unwrap();
        assert_eq!(
            o.status.code(),
            Some(2),
            "--threads {value}: {}",
            stderr(&o)
        );
        assert!(
            stderr(&o).contains("1..=1024"),
            "--threads {value}: {}",
            stderr(&o)
        );
        assert!(!dir.join("out").exists());
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn regress_negative_numbers_parsed_and_refused_with_range() {
    let dir = scratch_dir("negative");
    let out = dir.join("orbit.csv");
    for (flag, rest) in [
        ("--duration-s", ["--output-step-s", "60"]),
        ("--output-step-s", ["--duration-s", "600"]),
    ] {
        let o = satflock()
            .args(["propagate", "--elements", "6978137,0.001,97.8,0,0,0"])
            .args([flag, "-1"])
            .args(rest)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2), "{flag} -1: {}", stderr(&o));
        let e = stderr(&o);
        assert!(!e.contains("unexpected argument"), "{flag} -1: {e}");
        let key = flag.trim_start_matches("--").replace('-', "_");
        assert!(e.contains(&key) && e.contains("-1"), "{flag} -1: {e}");
        assert!(!out.exists());
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Runs `scenario` with a file-size limit of `limit_kib` KiB (`ulimit -f`), as a full disk would stop
/// it: the process gets EFBIG instead of being killed by SIGXFSZ.
fn run_under_file_limit(scenario: &Path, out: &Path, limit_kib: u32, extra: &str) -> Output {
    let binary = env!("CARGO_BIN_EXE_satflock");
    Command::new("bash")
        .arg("-c")
        .arg(format!(
            "ulimit -f {limit_kib}; exec '{binary}' run '{}' --out '{}' --quiet --no-plots {extra}",
            scenario.display(),
            out.display()
        ))
        .output()
        .unwrap()
}

/// Issue 25: a full disk (`ulimit -f`) used to kill the run with SIGXFSZ, leaving no summary, a 0-byte
/// metrics.parquet and a footer-less trajectory. Now the run stops with exit 1 and a message, summary.json
/// says `failed` with the reason, and every table left is readable (a broken Parquet file is removed).
#[test]
fn regress_file_size_limit_fails_the_run_with_every_file_valid() {
    let dir = scratch_dir("file-limit");
    let scenario = write_scenario(
        &dir,
        &builtin_with(
            "free-drift",
            &[
                ("duration_s = 5800.0", "duration_s = 2000.0"),
                ("record_interval_s = 20.0", "record_interval_s = 1.0"),
            ],
        ),
    );
    for format in ["csv", "parquet"] {
        let out = dir.join(format!("out-{format}"));
        let o = run_under_file_limit(&scenario, &out, 200, &format!("--format {format}"));
        assert_eq!(o.status.code(), Some(1), "{format}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("File too large") && stderr(&o).contains("trajectory"),
            "{format}: {}",
            stderr(&o)
        );
        let s = summary(&out);
        assert_eq!(s["status"], "failed", "{format}: {s}");
        let reason = s["error"].as_str().unwrap();
        assert!(reason.contains("File too large"), "{format}: {reason}");
        for name in ["scene.json", "summary.json"] {
            let text = std::fs::read_to_string(out.join(name)).unwrap();
            serde_json::from_str::<serde_json::Value>(&text).unwrap();
        }
        let mut tables = 0;
        for table in ["metrics", "trajectory"] {
            let path = out.join(format!("{table}.{format}"));
            if !path.exists() {
                assert!(reason.contains("removed"), "{format}: {reason}");
                continue;
            }
            tables += 1;
            if format == "csv" {
                assert!(assert_whole_rows(&path) > 0, "{}", path.display());
            }
            let read = satflock::output::Table::read(&path)
                .unwrap_or_else(|e| panic!("{} unreadable: {e}", path.display()));
            assert!(read.rows() > 0, "{}", path.display());
        }
        assert!(tables > 0, "{format}: no table left");
        let leftovers: Vec<_> = std::fs::read_dir(&out)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".partial"))
            .collect();
        assert!(leftovers.is_empty(), "{leftovers:?}");
    }
}

/// Issue 25: `propagate --integrator rk4 --step-s 1e-9` over 6000 s accepted 6e12 steps (scenarios bound
/// satellite-steps at 1e10); a too tight `--rtol` failed with "step size underflow" naming no option.
#[test]
fn regress_propagate_runaway_step_and_tight_rtol_name_the_option() {
    let dir = scratch_dir("propagate-bounds");
    let propagate = |extra: &[&str]| {
        satflock()
            .args(["propagate", "--elements", "6978137,0.001,97.8,0,0,0"])
            .args(["--duration-s", "6000", "--output-step-s", "60"])
            .args(extra)
            .arg("--out")
            .arg(dir.join("p.csv"))
            .output()
            .unwrap()
    };
    let o = propagate(&["--integrator", "rk4", "--step-s", "1e-9"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("step_s") && stderr(&o).contains("at most 1e10 RK4 steps"),
        "{}",
        stderr(&o)
    );
    let o = propagate(&[
        "--integrator",
        "dop853",
        "--rtol",
        "1e-25",
        "--atol",
        "1e-25",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("step size underflow")
            && stderr(&o).contains("--rtol 1e-25")
            && stderr(&o).contains("suggested: --rtol in [1e-13, 1e-6]"),
        "{}",
        stderr(&o)
    );
    assert!(!dir.join("p.csv").exists());
}

/// Issue 25: `--law ""` said ": cannot read the file"; an empty path is named as such.
#[test]
fn regress_empty_law_path_is_named() {
    let dir = scratch_dir("empty-law");
    let o = run_to(Path::new("free-drift"), &dir.join("out"), &["--law", ""]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("--law: the path is empty"),
        "{}",
        stderr(&o)
    );
    assert!(!dir.join("out").exists());
}
