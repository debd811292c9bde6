//! `satflock campaign` end to end, on short runs: bad keys refused before anything runs, results that do
//! not depend on `--jobs`, a campaign run equal to a plain `satflock run` of the same scenario, the
//! Parquet table read back, and `--resume` (finished runs skipped, failed and missing runs run again).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Output;

use satflock::output::outcomes::{scalar_outcomes, RunTable};

mod common;
use common::{satflock, scratch_dir, stderr};

/// Outcomes that measure the machine, not the run.
const WALL_TIME: &[&str] = &["wall_time_s", "satellite_steps_per_s"];

fn campaign(file: &Path, out: &Path, extra: &[&str]) -> Output {
    satflock()
        .arg("campaign")
        .arg(file)
        .arg("--out")
        .arg(out)
        .arg("--quiet")
        .args(extra)
        .output()
        .unwrap()
}

/// 4 satellites holding their slots for 60 s with navigation noise (so the seed matters): a Latin
/// hypercube over a log range of the stiffness × a list of dampings × 2 seeds = 12 runs.
const HOLD: &str = r#"
scenario = "hold"
seeds = [7, 11]
[set]
duration_s = 60.0
"satellites.count" = 4
events = []
"sensing.position_noise_m" = 0.5
[vary]
"law.stiffness_per_s2" = { min = 5e-5, max = 5e-4, scale = "log" }
"law.damping_per_s" = [0.01, 0.02]
[sampling]
method = "latin-hypercube"
samples = 3
"#;

/// 4 satellites drifting for 1200 s from a 200 m ball: with `dynamics.max_distance_m = 205` every run
/// stops when a satellite drifts beyond 205 m (a failed run), with 1e6 it completes.
const DRIFT: &str = r#"
scenario = "free-drift"
seeds = { count = 2, first = 1 }
[set]
duration_s = 1200.0
"satellites.count" = 4
"satellites.initial.radius_m" = 200.0
[vary]
"dynamics.max_distance_m" = [1e6, 205.0]
"#;

#[test]
fn regress_bad_keys_exit_2_naming_file_and_key_and_write_nothing() {
    let dir = scratch_dir("bad");
    let out = dir.join("out");
    for (name, vary, key, says) in [
        (
            "unknown",
            "\"law.no_such_gain\" = [1.0]",
            "vary.law.no_such_gain",
            "unknown field",
        ),
        (
            "range",
            "\"sensing.range_m\" = [100.0, -5.0]",
            "vary.sensing.range_m",
            "allowed",
        ),
        (
            "type",
            "\"satellites.mass_kg\" = [10.0, \"heavy\"]",
            "vary.satellites.mass_kg",
            "invalid type",
        ),
        (
            "index",
            "\"threats.0.speed_mps\" = [1.0]",
            "vary.threats.0.speed_mps",
            "no `threats`",
        ),
    ] {
        let file = dir.join(format!("{name}.toml"));
        let text = DRIFT.replace(
            "\"dynamics.max_distance_m\" = [1e6, 205.0]",
            &format!("{vary}\n"),
        );
        std::fs::write(&file, text).unwrap();
        let o = campaign(&file, &out, &[]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{name}: {e}");
        assert!(
            e.contains(&file.display().to_string()) && e.contains(&format!("key `{key}`")),
            "{name}: {e}"
        );
        assert!(e.contains(says), "{name}: {e}");
        assert!(!out.exists(), "{name}: nothing may be written");
    }
}

/// Every column of two tables, bitwise, except the wall-time outcomes.
fn assert_same_tables(a: &RunTable, b: &RunTable) {
    assert_eq!(a.text, b.text);
    let names = |t: &RunTable| t.numbers.iter().map(|c| c.0.clone()).collect::<Vec<_>>();
    assert_eq!(names(a), names(b));
    for ((name, x), (_, y)) in a.numbers.iter().zip(&b.numbers) {
        if WALL_TIME.contains(&name.as_str()) {
            continue;
        }
        let bits = |v: &[f64]| v.iter().map(|f| f.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(x), bits(y), "column {name}");
    }
}

#[test]
fn val_table_is_the_same_with_one_or_two_jobs_and_a_run_equals_a_plain_run() {
    let dir = scratch_dir("jobs");
    let file = dir.join("hold.toml");
    std::fs::write(&file, HOLD).unwrap();
    let (one, two) = (dir.join("one"), dir.join("two"));
    for (out, jobs) in [(&one, "1"), (&two, "2")] {
        let o = campaign(&file, out, &["--jobs", jobs]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    // Read back by the arrow Parquet reader.
    let a = RunTable::read_parquet(&one.join("campaign.parquet")).unwrap();
    let b = RunTable::read_parquet(&two.join("campaign.parquet")).unwrap();
    assert_same_tables(&a, &b);
    assert_eq!(a.rows(), 12);
    assert!(a.text("status").unwrap().iter().all(|s| s == "completed"));
    let seeds: Vec<&str> = a.text("seed").unwrap().iter().map(String::as_str).collect();
    assert_eq!(seeds, ["7", "11"].repeat(6));
    assert_eq!(
        a.numbers("run").unwrap(),
        (0..12).map(f64::from).collect::<Vec<_>>()
    );
    // Damping (listed, first in key order) varies slowest; the 3 stiffness samples are shared by both
    // dampings, one in each third of the log range [5e-5, 5e-4].
    let damping = a.numbers("parameter.law.damping_per_s").unwrap();
    assert_eq!(damping[..6], [0.01; 6]);
    assert_eq!(damping[6..], [0.02; 6]);
    let stiffness = a.numbers("parameter.law.stiffness_per_s2").unwrap();
    assert_eq!(stiffness[..6], stiffness[6..]);
    let mut thirds: Vec<usize> = (0..3)
        .map(|p| ((stiffness[2 * p] / 5e-5).log10() * 3.0).floor() as usize)
        .collect();
    thirds.sort_unstable();
    assert_eq!(thirds, [0, 1, 2]);
    // The two seeds of a point differ (noise), the runs are real.
    let dv = a.numbers("delta_v_mps.mean").unwrap();
    assert_ne!(dv[0].to_bits(), dv[1].to_bits());
    assert!(dv.iter().all(|v| *v > 0.0));
    // By default a run keeps its summary and scenario only.
    let mut kept: Vec<String> = std::fs::read_dir(one.join("runs/00001"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    kept.sort();
    assert_eq!(kept, ["scenario.toml", "summary.json"]);
    for name in ["manifest.jsonl", "summary.md"] {
        assert!(one.join(name).is_file(), "{name}");
    }
    // The figure: 2 parameters × 2 outcomes per row of 4 panels (420 px each), the log range on a
    // log10 axis, and something drawn.
    let png = image::open(one.join("plots/outcomes.png"))
        .unwrap()
        .to_rgb8();
    assert_eq!(png.width(), 4 * 420);
    let drawn = png.pixels().filter(|p| p.0 != [255, 255, 255]).count();
    assert!(drawn as f64 > 0.01 * f64::from(png.width() * png.height()));
    let svg = std::fs::read_to_string(one.join("plots/outcomes.svg")).unwrap();
    // Axis labels carry units.
    assert!(
        svg.contains("\nlog10 law.stiffness [1/s²]\n</text>"),
        "x label"
    );
    assert!(svg.contains("\nlaw.damping [1/s]\n</text>"), "x label");
    assert!(svg.contains("\ndelta_v.mean [m/s]\n</text>"), "y label");

    // Run 1 (damping 0.01, first stiffness sample, seed 11) as a plain `satflock run` of the built-in
    // scenario edited by hand.
    let builtin = satflock()
        .args(["scenarios", "show", "hold"])
        .output()
        .unwrap();
    let text = String::from_utf8(builtin.stdout).unwrap();
    let text = text[..text.find("[[events]]").unwrap()]
        .replace("seed = 7", "seed = 11")
        .replace("duration_s = 4000.0", "duration_s = 60.0")
        .replace("count = 20", "count = 4")
        .replace(
            "stiffness_per_s2 = 1e-4",
            &format!("stiffness_per_s2 = {:?}", stiffness[1]),
        )
        .replace("damping_per_s = 2e-2", "damping_per_s = 0.01")
        + "\n[sensing]\nposition_noise_m = 0.5\n";
    let scenario = dir.join("run1.toml");
    std::fs::write(&scenario, &text).unwrap();
    let plain = dir.join("plain");
    let o = satflock()
        .args(["run", "--quiet", "--no-plots", "--out"])
        .arg(&plain)
        .arg(&scenario)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let read = |path: PathBuf| -> BTreeMap<String, f64> {
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        scalar_outcomes(&summary)
            .into_iter()
            .filter(|(n, _)| !WALL_TIME.contains(&n.as_str()))
            .collect()
    };
    let expected = read(plain.join("summary.json"));
    assert!(expected.len() > 10);
    let from_run_dir = read(one.join("runs/00001/summary.json"));
    assert_eq!(from_run_dir.len(), expected.len());
    for (name, value) in &expected {
        assert_eq!(value.to_bits(), from_run_dir[name].to_bits(), "{name}");
        let column = a.numbers(name).unwrap_or_else(|| panic!("column {name}"));
        assert_eq!(value.to_bits(), column[1].to_bits(), "table {name}");
    }
}

/// The manifest's run lines, by run index: how many each has, and the last one's status.
fn manifest_runs(out: &Path) -> BTreeMap<u64, (usize, String)> {
    let text = std::fs::read_to_string(out.join("manifest.jsonl")).unwrap();
    let mut lines = text.lines();
    let header: serde_json::Value = serde_json::from_str(lines.next().unwrap()).unwrap();
    assert_eq!(header["runs"], 4);
    assert_eq!(header["campaign_sha256"].as_str().unwrap().len(), 64);
    let mut runs = BTreeMap::new();
    for line in lines {
        let record: serde_json::Value = serde_json::from_str(line).unwrap();
        let entry = runs
            .entry(record["run"].as_u64().unwrap())
            .or_insert((0, String::new()));
        entry.0 += 1;
        entry.1 = record["status"].as_str().unwrap().to_string();
    }
    runs
}

#[test]
fn val_resume_skips_finished_runs_and_reruns_failed_and_missing_ones() {
    let dir = scratch_dir("resume");
    let file = dir.join("drift.toml");
    std::fs::write(&file, DRIFT).unwrap();
    let out = dir.join("out");
    let o = campaign(&file, &out, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("2 of 4 runs did not complete"),
        "{}",
        stderr(&o)
    );
    let first = manifest_runs(&out);
    let statuses: Vec<&str> = first.values().map(|(_, s)| s.as_str()).collect();
    assert_eq!(statuses, ["completed", "completed", "failed", "failed"]);
    let table = RunTable::read_parquet(&out.join("campaign.parquet")).unwrap();
    let errors = table.text("error").unwrap();
    assert!(errors[0].is_empty());
    assert!(errors[2].contains("diverged"), "{}", errors[2]);

    // A finished run's line lost, and a line cut short by a kill.
    let text = std::fs::read_to_string(out.join("manifest.jsonl")).unwrap();
    let kept: Vec<&str> = text
        .lines()
        .filter(|l| !l.starts_with("{\"run\":1,"))
        .collect();
    assert_eq!(kept.len(), 4);
    std::fs::write(
        out.join("manifest.jsonl"),
        kept.join("\n") + "\n{\"run\":0,\"po",
    )
    .unwrap();

    // Without --resume the directory is refused; a changed campaign file cannot resume.
    let o = campaign(&file, &out, &[]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--resume"), "{}", stderr(&o));
    let changed = dir.join("changed.toml");
    std::fs::write(&changed, format!("{DRIFT}# edited\n")).unwrap();
    let o = campaign(&changed, &out, &["--resume"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("campaign file changed"),
        "{}",
        stderr(&o)
    );

    let o = campaign(&file, &out, &["--resume", "--jobs", "2"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let second = manifest_runs(&out);
    // Run 0 kept (one line), run 1 run again (its line was lost), runs 2 and 3 run again (failed).
    assert_eq!(second[&0], (1, "completed".to_string()));
    assert_eq!(second[&1], (1, "completed".to_string()));
    assert_eq!(second[&2], (2, "failed".to_string()));
    assert_eq!(second[&3], (2, "failed".to_string()));
    let resumed = RunTable::read_parquet(&out.join("campaign.parquet")).unwrap();
    assert_same_tables(&table, &resumed);

    // Failed runs are not fatal unless asked.
    let o = campaign(&file, &dir.join("strict"), &["--fail-on-run-failure"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
}

#[test]
fn regress_a_refused_combination_is_recorded_and_the_others_run() {
    // Each value is valid alone on the scenario; record_interval_s = 30 s with duration_s = 20 s is not.
    let dir = scratch_dir("refused");
    let file = dir.join("c.toml");
    std::fs::write(
        &file,
        "scenario = \"hold\"\nseeds = [1]\n[set]\n\"satellites.count\" = 4\nevents = []\n[vary]\n\
         duration_s = [20.0, 60.0]\nrecord_interval_s = [10.0, 30.0]\n",
    )
    .unwrap();
    let out = dir.join("out");
    let o = campaign(&file, &out, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let table = RunTable::read_parquet(&out.join("campaign.parquet")).unwrap();
    let status: Vec<&str> = table
        .text("status")
        .unwrap()
        .iter()
        .map(String::as_str)
        .collect();
    // Keys in order: duration_s (slowest), record_interval_s.
    assert_eq!(status, ["completed", "refused", "completed", "completed"]);
    let error = &table.text("error").unwrap()[1];
    assert!(error.contains("record_interval_s"), "{error}");
    assert!(table.numbers("delta_v_mps.mean").unwrap()[1].is_nan());
    assert!(!out.join("runs/00001").exists());
}

/// The manifest's lines, as JSON.
fn manifest_lines(out: &Path) -> Vec<serde_json::Value> {
    std::fs::read_to_string(out.join("manifest.jsonl"))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

#[test]
fn regress_resume_checks_every_manifest_line_against_its_run_and_says_what_it_dropped() {
    let dir = scratch_dir("forged");
    let file = dir.join("drift.toml");
    std::fs::write(&file, DRIFT).unwrap();
    let out = dir.join("out");
    let o = campaign(&file, &out, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let table = RunTable::read_parquet(&out.join("campaign.parquet")).unwrap();
    let lines = manifest_lines(&out);
    let line_of = |run: u64| lines[1..].iter().find(|l| l["run"] == run).unwrap().clone();
    // Forged lines appended by hand: a seed that is not the run's, an outcome that is not its
    // summary's, a failed run said completed, a run the campaign does not have, and garbage.
    let mut seed = line_of(0);
    seed["seed"] = 999.into();
    let mut outcome = line_of(1);
    outcome["outcomes"]["delta_v_mps.mean"] = 42.0.into();
    let mut status = line_of(2);
    status["status"] = "completed".into();
    status["error"] = serde_json::Value::Null;
    let mut foreign = line_of(3);
    foreign["run"] = 17.into();
    let mut text = std::fs::read_to_string(out.join("manifest.jsonl")).unwrap();
    for forged in [&seed, &outcome, &status] {
        text.push_str(&format!("{forged}\n"));
    }
    text.push_str("not a record\n");
    text.push_str(&format!("{foreign}\n"));
    std::fs::write(out.join("manifest.jsonl"), text).unwrap();

    let o = campaign(&file, &out, &["--resume"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let e = stderr(&o);
    for says in [
        "manifest.jsonl line 6: run 0: seed 999 (the campaign's run 0 has seed 1)",
        "manifest.jsonl line 7: run 1: outcome delta_v_mps.mean = 42",
        "manifest.jsonl line 8: run 2: status completed, but",
        "manifest.jsonl line 9: not a run record",
        "manifest.jsonl line 10: run 17: not a run of this campaign (allowed: runs 0 to 3)",
        "dropped 5 manifest line(s)",
    ] {
        assert!(e.contains(says), "{says}: {e}");
    }
    let summary = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(summary.contains("## Manifest lines dropped by `--resume`"));
    assert!(summary.contains("- manifest.jsonl line 8: run 2: status completed"));
    // Runs 0 and 1 kept from their genuine lines; run 2 (failed, forged completed) and run 3 run
    // again; the table is the one the runs made.
    let runs = manifest_runs(&out);
    assert_eq!(runs[&0], (1, "completed".to_string()));
    assert_eq!(runs[&1], (1, "completed".to_string()));
    assert_eq!(runs[&2], (2, "failed".to_string()));
    assert_eq!(runs[&3], (2, "failed".to_string()));
    let resumed = RunTable::read_parquet(&out.join("campaign.parquet")).unwrap();
    assert_same_tables(&table, &resumed);
}

#[test]
fn val_every_row_records_the_parameters_its_run_used() {
    // Nested dotted keys (one in a table the scenario does not write), an integer on a float key.
    let dir = scratch_dir("applied");
    let file = dir.join("c.toml");
    std::fs::write(
        &file,
        "scenario = \"hold\"\nseeds = [3]\n[set]\nduration_s = 20.0\n\"satellites.count\" = 4\n\
         events = []\n[vary]\n\"satellites.initial.radius_m\" = [150.0, 180]\n\
         \"sensing.position_noise_m\" = [0.0, 0.25]\n\"law.stiffness_per_s2\" = { min = 5e-5, max = 5e-4 }\n\
         [sampling]\nmethod = \"random\"\nsamples = 2\n",
    )
    .unwrap();
    let out = dir.join("out");
    let o = campaign(&file, &out, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let table = RunTable::read_parquet(&out.join("campaign.parquet")).unwrap();
    assert_eq!(table.rows(), 8);
    let records: BTreeMap<u64, serde_json::Value> = manifest_lines(&out)[1..]
        .iter()
        .map(|l| (l["run"].as_u64().unwrap(), l.clone()))
        .collect();
    let keys = [
        "law.stiffness_per_s2",
        "satellites.initial.radius_m",
        "sensing.position_noise_m",
    ];
    for run in 0..8usize {
        let scenario: toml::Table = toml::from_str(
            &std::fs::read_to_string(out.join(format!("runs/{run:05}/scenario.toml"))).unwrap(),
        )
        .unwrap();
        let applied = |key: &str| -> f64 {
            let mut node = toml::Value::Table(scenario.clone());
            for part in key.split('.') {
                node = match node {
                    toml::Value::Table(t) => t[part].clone(),
                    toml::Value::Array(a) => a[part.parse::<usize>().unwrap()].clone(),
                    other => panic!("{key}: {other}"),
                };
            }
            node.as_float().unwrap()
        };
        for key in keys {
            let column = table.numbers(&format!("parameter.{key}")).unwrap()[run];
            assert_eq!(applied(key).to_bits(), column.to_bits(), "run {run} {key}");
            let recorded = records[&(run as u64)]["parameters"][key].as_f64().unwrap();
            assert_eq!(recorded.to_bits(), column.to_bits(), "run {run} {key}");
        }
    }
    // The intended grid: radius slowest, then the noise, then the samples.
    let radius = table
        .numbers("parameter.satellites.initial.radius_m")
        .unwrap();
    assert_eq!(
        radius,
        [150.0, 150.0, 150.0, 150.0, 180.0, 180.0, 180.0, 180.0]
    );
    let noise = table.numbers("parameter.sensing.position_noise_m").unwrap();
    assert_eq!(noise, [0.0, 0.0, 0.25, 0.25, 0.0, 0.0, 0.25, 0.25]);
}

#[test]
fn regress_an_unknown_outcome_is_refused_listing_the_known_ones() {
    let dir = scratch_dir("outcomes");
    let file = dir.join("c.toml");
    std::fs::write(&file, format!("outcomes = [\"delta_v_mps.meen\"]\n{DRIFT}")).unwrap();
    let out = dir.join("out");
    let o = campaign(&file, &out, &[]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("key `outcomes`") && e.contains("`delta_v_mps.meen`"),
        "{e}"
    );
    assert!(
        e.contains("delta_v_mps.mean,") && e.contains("law.NAME"),
        "{e}"
    );
    assert!(!out.exists());
    // Known names pass, a law's own included.
    std::fs::write(
        &file,
        format!("outcomes = [\"delta_v_mps.mean\", \"final.five_elements.r_o_m.0\"]\n{DRIFT}"),
    )
    .unwrap();
    let o = campaign(&file, &out, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    // Every outcome the runs wrote is a known one (the list follows summary.json).
    let table = RunTable::read_parquet(&out.join("campaign.parquet")).unwrap();
    for (name, _) in &table.numbers {
        if ["run", "point"].contains(&name.as_str()) || name.starts_with("parameter.") {
            continue;
        }
        assert!(
            satflock::campaign::summary::is_known_outcome(name),
            "{name} is not in KNOWN_OUTCOMES"
        );
    }
}
