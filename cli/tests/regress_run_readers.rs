//! Regression cases of issue 25 (robustness, part A): every file satflock reads goes through one bounded
//! reader (regular files only, a stated size limit), and every run-directory reader (`characterize`,
//! `plot`, `report`, `export oem|czml`) reads through one checked `RunData`: the same verdict for the
//! same files, exit 2 naming the file and the column or key, never a panic or an abort; nothing is
//! allocated from a count a file states; a figure draws a bounded number of objects; an export never
//! writes over the run it reads.

use std::ffi::OsString;
use std::path::Path;
use std::process::Output;

mod common;
use common::{copy_run, forge_parquet_footer, satflock, scratch_dir, small_run, stderr};

/// The five run-directory readers on `run` (outputs into `out`); `characterize` only when `with_file`
/// (it reads the trajectory file alone, not the run directory).
fn readers(run: &Path, out: &Path, with_file: bool) -> Vec<Vec<OsString>> {
    let os = |items: &[&dyn AsRef<std::ffi::OsStr>]| -> Vec<OsString> {
        items.iter().map(|i| i.as_ref().to_os_string()).collect()
    };
    let mut commands = vec![
        os(&[&"plot", &run]),
        os(&[&"report", &run]),
        os(&[&"export", &"oem", &run, &"--out", &out.join("o.oem")]),
        os(&[&"export", &"czml", &run, &"--out", &out.join("o.czml")]),
    ];
    if with_file {
        let file = ["trajectory.csv", "trajectory.parquet"]
            .map(|f| run.join(f))
            .into_iter()
            .find(|f| f.exists())
            .expect("a trajectory file");
        commands.push(os(&[&"characterize", &file]));
    }
    commands
}

fn run_command(args: &[OsString]) -> Output {
    satflock().args(args).output().unwrap()
}

/// Every reader exits 2 with a message holding every one of `words`.
fn all_refuse(run: &Path, out: &Path, with_file: bool, words: &[&str]) {
    for args in readers(run, out, with_file) {
        let o = run_command(&args);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        for w in words {
            assert!(err.contains(w), "{args:?}: no `{w}` in {err}");
        }
    }
}

/// `trajectory.csv` with its data line `line` (from 1, after the header) changed by `edit` on its cells.
fn edit_csv_row(path: &Path, line: usize, edit: impl Fn(&mut Vec<String>)) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let mut cells: Vec<String> = lines[line].split(',').map(str::to_string).collect();
    edit(&mut cells);
    lines[line] = cells.join(",");
    std::fs::write(path, lines.join("\n") + "\n").unwrap();
}

/// The index of column `name` in a CSV header.
fn col(path: &Path, name: &str) -> usize {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .next()
        .unwrap()
        .split(',')
        .position(|c| c == name)
        .unwrap()
}

#[test]
fn regress_forged_parquet_footers_are_refused_not_trusted() {
    let dir = scratch_dir("forged");
    let base = small_run(&dir, "base", "parquet");
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    for (k, (rows, chunk)) in [
        (1_000_000_000, None),
        (1_000_000_000_000_000, None),
        (1_000_000_000, Some(1 << 40)),
    ]
    .into_iter()
    .enumerate()
    {
        for table in ["trajectory", "metrics"] {
            let run = copy_run(&base, &dir.join(format!("forged-{table}-{k}")));
            let file = run.join(format!("{table}.parquet"));
            std::fs::write(&file, forge_parquet_footer(&file, rows, chunk)).unwrap();
            all_refuse(
                &run,
                &out,
                table == "trajectory",
                &[&format!("{table}.parquet")],
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn regress_report_refuses_a_nan_time_and_a_huge_satellite_count() {
    let dir = scratch_dir("report");
    let base = small_run(&dir, "base", "csv");
    let nan = copy_run(&base, &dir.join("nan"));
    let trajectory = nan.join("trajectory.csv");
    let t = col(&trajectory, "t_s");
    edit_csv_row(&trajectory, 3, |c| c[t] = "NaN".into());
    let o = satflock().arg("report").arg(&nan).output().unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("trajectory.csv: line 4, column `t_s`"),
        "{}",
        stderr(&o)
    );
    let huge = copy_run(&base, &dir.join("huge"));
    let summary = huge.join("summary.json");
    let text = std::fs::read_to_string(&summary).unwrap();
    assert!(text.contains("\"n_satellites\": 4"));
    std::fs::write(
        &summary,
        text.replace("\"n_satellites\": 4", "\"n_satellites\": 1000000000000000"),
    )
    .unwrap();
    let o = satflock().arg("report").arg(&huge).output().unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("summary.json: `n_satellites` = 1000000000000000 is not allowed"),
        "{}",
        stderr(&o)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn regress_every_file_reader_refuses_a_device() {
    let zero = Path::new("/dev/zero");
    if !zero.exists() {
        return;
    }
    let dir = scratch_dir("devices");
    let base = small_run(&dir, "base", "csv");
    let scenario = dir.join("base.toml");
    let cases: Vec<Vec<OsString>> = vec![
        vec![
            "run".into(),
            zero.into(),
            "--out".into(),
            dir.join("a").into(),
        ],
        vec![
            "run".into(),
            scenario.clone().into(),
            "--law".into(),
            zero.into(),
            "--out".into(),
            dir.join("b").into(),
        ],
        vec![
            "campaign".into(),
            zero.into(),
            "--out".into(),
            dir.join("c").into(),
        ],
        vec![
            "propagate".into(),
            "--forces".into(),
            zero.into(),
            "--elements".into(),
            "7000000,0.001,97.8,0,0,0".into(),
            "--duration-s".into(),
            "60".into(),
            "--output-step-s".into(),
            "10".into(),
            "--out".into(),
            dir.join("d.csv").into(),
        ],
        vec!["characterize".into(), zero.into()],
    ];
    for args in cases {
        let o = run_command(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("/dev/zero") && stderr(&o).contains("not a regular file"),
            "{args:?}: {}",
            stderr(&o)
        );
    }
    // A run directory whose summary.json, scene.json or table is a device.
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    for file in [
        "summary.json",
        "scene.json",
        "metrics.csv",
        "trajectory.csv",
    ] {
        let run = copy_run(&base, &dir.join(format!("dev-{file}")));
        std::fs::remove_file(run.join(file)).unwrap();
        std::os::unix::fs::symlink(zero, run.join(file)).unwrap();
        all_refuse(
            &run,
            &out,
            file == "trajectory.csv",
            &[file, "not a regular file"],
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn regress_plot_draws_a_bounded_number_of_threats() {
    let dir = scratch_dir("threats");
    let run = small_run(&dir, "base", "csv");
    let threats: Vec<serde_json::Value> = (0..200_000)
        .map(|k| {
            serde_json::json!({
                "name": format!("t{k}"),
                "danger_radius_m": 5.0,
                "position_at_t0_lvlh_m": [k as f64, 0.0, 0.0],
                "velocity_lvlh_mps": [0.0, 1.0, 0.0],
            })
        })
        .collect();
    let scene = serde_json::json!({
        "threats": threats,
        "obstacles": [],
        "target_formation_lvlh_m": null,
    });
    std::fs::write(run.join("scene.json"), scene.to_string()).unwrap();
    let o = satflock().arg("plot").arg(&run).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("200 of 200000 threats drawn"),
        "{}",
        stderr(&o)
    );
    for name in ["trajectories", "snapshots"] {
        let svg = run.join("plots").join(format!("{name}.svg"));
        let bytes = std::fs::metadata(&svg).unwrap().len();
        // Before the cap, trajectories.svg was past 200 MiB.
        assert!(bytes < 10 << 20, "{}: {bytes} bytes", svg.display());
    }
    let svg = std::fs::read_to_string(run.join("plots/trajectories.svg")).unwrap();
    assert!(svg.contains("200 of 200000 threats drawn"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn regress_export_never_writes_over_the_run_it_reads() {
    let dir = scratch_dir("overwrite");
    let run = small_run(&dir, "base", "csv");
    let before: Vec<Vec<u8>> = [
        "summary.json",
        "trajectory.csv",
        "scene.json",
        "metrics.csv",
    ]
    .iter()
    .map(|f| std::fs::read(run.join(f)).unwrap())
    .collect();
    let dotted = run.join("..").join("base").join("scene.json");
    for (format, out) in [
        ("oem", run.join("summary.json")),
        ("czml", run.join("trajectory.csv")),
        ("oem", dotted.clone()),
        ("czml", run.join("metrics.csv")),
    ] {
        let single = if format == "oem" {
            "--single-file"
        } else {
            "--paths"
        };
        let o = satflock()
            .args(["export", format, single])
            .arg(&run)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2), "{format} {}", stderr(&o));
        assert!(
            stderr(&o).contains("is a file of the run directory the export reads"),
            "{}",
            stderr(&o)
        );
    }
    let after: Vec<Vec<u8>> = [
        "summary.json",
        "trajectory.csv",
        "scene.json",
        "metrics.csv",
    ]
    .iter()
    .map(|f| std::fs::read(run.join(f)).unwrap())
    .collect();
    assert!(before == after, "the run's files changed");
    // Any other path is written.
    let o = satflock()
        .args(["export", "oem", "--single-file"])
        .arg(&run)
        .arg("--out")
        .arg(dir.join("swarm.oem"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn regress_every_reader_gives_the_same_verdict() {
    let dir = scratch_dir("verdict");
    let base = small_run(&dir, "base", "csv");
    let parquet = small_run(&dir, "parquet", "parquet");
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    let trajectory = base.join("trajectory.csv");
    let (t, id, x) = (
        col(&trajectory, "t_s"),
        col(&trajectory, "id"),
        col(&trajectory, "x_lvlh_m"),
    );
    type Edit = Box<dyn Fn(&Path)>;
    let row = |line: usize, column: usize, value: &'static str| -> Edit {
        Box::new(move |run: &Path| {
            edit_csv_row(&run.join("trajectory.csv"), line, |c| {
                c[column] = value.into()
            })
        })
    };
    // (name, change, characterize reads it too, words of the message)
    let cases: Vec<(&str, Edit, bool, Vec<&str>)> = vec![
        (
            "nan-time",
            row(2, t, "NaN"),
            true,
            vec!["trajectory.csv", "line 3", "`t_s`"],
        ),
        (
            "reversed-time",
            row(6, t, "0.5"),
            true,
            vec!["trajectory.csv", "line 7", "t_s = 0.5", "non-decreasing"],
        ),
        (
            "fractional-id",
            row(2, id, "0.5"),
            true,
            vec!["trajectory.csv", "line 3", "id = 0.5"],
        ),
        (
            "negative-id",
            row(2, id, "-1"),
            true,
            vec!["trajectory.csv", "line 3", "id = -1"],
        ),
        (
            "id-beyond-n",
            row(4, id, "4"),
            false,
            vec!["trajectory.csv", "line 5", "id = 4", "n_satellites = 4"],
        ),
        (
            "infinite-position",
            row(2, x, "inf"),
            true,
            vec!["trajectory.csv", "line 3", "`x_lvlh_m`", "finite"],
        ),
        (
            "header-only",
            Box::new(|run: &Path| {
                let path = run.join("trajectory.csv");
                let text = std::fs::read_to_string(&path).unwrap();
                let header = text.lines().next().unwrap().to_string();
                std::fs::write(&path, header + "\n").unwrap();
            }),
            true,
            vec!["trajectory.csv", "has no rows"],
        ),
        (
            "summary-array",
            Box::new(|run: &Path| std::fs::write(run.join("summary.json"), "[]").unwrap()),
            false,
            vec!["summary.json", "is not a JSON object"],
        ),
    ];
    for (name, edit, with_file, words) in cases {
        let run = copy_run(&base, &dir.join(name));
        edit(&run);
        all_refuse(&run, &out, with_file, &words);
    }
    // Half a CSV beside the whole Parquet table.
    let run = copy_run(&parquet, &dir.join("half-csv"));
    let text = std::fs::read_to_string(base.join("trajectory.csv")).unwrap();
    let half: Vec<&str> = text.lines().take(text.lines().count() / 2).collect();
    std::fs::write(run.join("trajectory.csv"), half.join("\n") + "\n").unwrap();
    for args in readers(&run, &out, false) {
        let o = run_command(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("holds both trajectory.csv and trajectory.parquet"),
            "{args:?}: {}",
            stderr(&o)
        );
    }
    // The untouched runs are read by every reader.
    for run in [&base, &parquet] {
        for args in readers(run, &out, true) {
            let o = run_command(&args);
            assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn regress_export_help_names_both_trajectory_formats() {
    for format in ["oem", "czml"] {
        let o = satflock()
            .args(["export", format, "--help"])
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&o.stdout);
        assert!(
            text.contains("trajectory.csv or trajectory.parquet"),
            "{text}"
        );
    }
}
