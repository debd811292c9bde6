//! The command-line tool end to end: outputs, exit codes and what is (not) written on bad input.

mod common;
use common::{satflock, scratch_dir};

#[test]
fn val_propagate_writes_exact_output_times_and_the_documented_header() {
    let dir = scratch_dir("propagate");
    let out = dir.join("orbit.csv");
    let status = satflock()
        .args([
            "propagate",
            "--elements",
            "6978137,0.0002,98,10,20,30",
            "--duration-s",
            "600",
            "--output-step-s",
            "60",
            "--gravity",
            "j2",
            "--integrator",
            "rk78",
            "--out",
        ])
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success());
    let text = std::fs::read_to_string(&out).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "t_s,x_m,y_m,z_m,vx_mps,vy_mps,vz_mps"
    );
    let times: Vec<f64> = lines
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(times, (0..=10).map(|k| k as f64 * 60.0).collect::<Vec<_>>());
}

#[test]
fn val_propagate_lvlh_of_itself_is_zero() {
    let dir = scratch_dir("lvlh");
    let out = dir.join("rel.csv");
    let orbit = "7000000,0.001,51.6,0,0,0";
    let status = satflock()
        .args([
            "propagate",
            "--elements",
            orbit,
            "--reference-elements",
            orbit,
        ])
        .args([
            "--duration-s",
            "300",
            "--output-step-s",
            "100",
            "--frame",
            "lvlh-gao",
            "--out",
        ])
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success());
    for line in std::fs::read_to_string(&out).unwrap().lines().skip(1) {
        for v in line.split(',').skip(1) {
            assert_eq!(v.parse::<f64>().unwrap(), 0.0, "{line}");
        }
    }
}

#[test]
fn val_propagate_bad_arguments_exit_2_and_write_nothing() {
    let dir = scratch_dir("bad");
    let out = dir.join("never.csv");
    let cases: &[&[&str]] = &[
        &[
            "--elements",
            "7000000,1.5,10,0,0,0",
            "--duration-s",
            "60",
            "--output-step-s",
            "10",
        ],
        &[
            "--elements",
            "7000000,0.1,10,0,0",
            "--duration-s",
            "60",
            "--output-step-s",
            "10",
        ],
        &[
            "--elements",
            "7000000,0.1,10,0,0,0",
            "--duration-s",
            "-60",
            "--output-step-s",
            "10",
        ],
        &[
            "--elements",
            "7000000,0.1,10,0,0,0",
            "--duration-s",
            "60",
            "--output-step-s",
            "0",
        ],
        &[
            "--state",
            "0,0,0,0,0,0",
            "--duration-s",
            "60",
            "--output-step-s",
            "10",
        ],
        &[
            "--elements",
            "7000000,0.1,10,0,0,0",
            "--duration-s",
            "60",
            "--output-step-s",
            "10",
            "--frame",
            "lvlh-hill",
        ],
        &["--duration-s", "60", "--output-step-s", "10"],
    ];
    for args in cases {
        let output = satflock()
            .arg("propagate")
            .args(*args)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        assert_eq!(output.status.code(), Some(2), "{args:?}");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(stderr.contains("error"), "{args:?}: {stderr}");
        assert!(!out.exists(), "{args:?} left a file");
        assert!(!out.with_extension("csv.partial").exists());
    }
}

#[test]
fn val_run_builtin_writes_summary_metrics_and_trajectory() {
    let dir = scratch_dir("run");
    let output = satflock()
        .args(["run", "hold", "--quiet", "--threads", "2", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    for key in [
        "scenario",
        "seed",
        "n_satellites",
        "duration_s",
        "wall_time_s",
        "satellite_steps_per_s",
        "delta_v_mps",
        "min_separation_m",
        "collisions",
        "final",
    ] {
        assert!(summary.get(key).is_some(), "summary lacks {key}");
    }
    assert_eq!(summary["n_satellites"], 20);
    assert_eq!(
        summary["delta_v_mps"]["per_satellite"]
            .as_array()
            .unwrap()
            .len(),
        20
    );
    for key in [
        "n",
        "r_o_m",
        "v_o_mps",
        "d_max_m",
        "d_min_m",
        "uniformity_l",
    ] {
        assert!(
            summary["final"]["five_elements"].get(key).is_some(),
            "five_elements lacks {key}"
        );
    }
    let metrics = std::fs::read_to_string(dir.join("metrics.csv")).unwrap();
    // 4000 s at 10 s: 401 rows plus the header.
    assert_eq!(metrics.lines().count(), 402);
    let trajectory = std::fs::read_to_string(dir.join("trajectory.csv")).unwrap();
    assert_eq!(trajectory.lines().count(), 1 + 401 * 20);
}

#[test]
fn val_run_bad_scenario_exits_2_naming_file_and_key() {
    let dir = scratch_dir("badrun");
    let file = dir.join("bad.toml");
    std::fs::write(
        &file,
        "name = \"x\"\nseed = 1\nduration_s = 10.0\nrecord_interval_s = 1.0\n[reference]\naltitude_m = 600e3\ninclination_deg = 97.8\n[satellites]\ncount = 2\nmass_kg = -3.0\ninitial = { distribution = \"sphere\", radius_m = 5.0 }\n[law]\nname = \"none\"\n",
    )
    .unwrap();
    let out = dir.join("out");
    let output = satflock()
        .args(["run", "--quiet", "--out"])
        .arg(&out)
        .arg(&file)
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("bad.toml") && stderr.contains("satellites.mass_kg"),
        "{stderr}"
    );
    assert!(
        !out.exists(),
        "an invalid scenario created the output directory"
    );
}

#[test]
fn val_diverging_run_exits_1_and_leaves_valid_files() {
    let dir = scratch_dir("diverge");
    let file = dir.join("diverge.toml");
    // Satellites start 500 m out with a 100 m divergence bound: the run stops at the first step.
    std::fs::write(
        &file,
        "name = \"diverge\"\nseed = 1\nduration_s = 100.0\nrecord_interval_s = 1.0\n[dynamics]\nmax_distance_m = 600.0\n[reference]\naltitude_m = 600e3\ninclination_deg = 97.8\n[satellites]\ncount = 2\nmass_kg = 1.0\ninitial = { distribution = \"list\", states = [[0,0,0,0,0,0],[0,589.5,0,0,1.0,0]] }\n[law]\nname = \"none\"\n",
    )
    .unwrap();
    let out = dir.join("out");
    let output = satflock()
        .args(["run", "--quiet", "--out"])
        .arg(&out)
        .arg(&file)
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("satellite 1 diverged at t = 11 s"),
        "{stderr}"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["status"], "failed");
    let metrics = std::fs::read_to_string(out.join("metrics.csv")).unwrap();
    let rows: Vec<&str> = metrics.lines().collect();
    // header + t = 0..10 recorded before the failure, every row complete
    assert_eq!(rows.len(), 12);
    let columns = rows[0].split(',').count();
    assert!(rows.iter().all(|r| r.split(',').count() == columns));
}

#[test]
fn val_characterize_prints_the_closed_form_for_a_circle() {
    let dir = scratch_dir("characterize");
    let file = dir.join("circle.csv");
    let mut text = String::from("x_m,y_m,z_m\n");
    for k in 0..50 {
        let a = std::f64::consts::TAU * k as f64 / 50.0;
        text.push_str(&format!("{},{},0\n", 1000.0 * a.cos(), 1000.0 * a.sin()));
    }
    std::fs::write(&file, text).unwrap();
    let output = satflock().arg("characterize").arg(&file).output().unwrap();
    assert!(output.status.success());
    let v: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    let s = (std::f64::consts::PI / 50.0).sin();
    let exact = 50.0 * (s / (1.0 + s)).powi(3);
    let l = v["uniformity_l"].as_f64().unwrap();
    assert!((l - exact).abs() < 1e-9 * exact, "L = {l}, exact {exact}");
    assert_eq!(v["n"], 50);
    // Issue 25: positions carry no velocity, so the centre velocity is not given (null), not zero.
    assert!(v["v_o_mps"].is_null(), "{}", v["v_o_mps"]);
    assert!(String::from_utf8_lossy(&output.stderr).contains("not given"));
}

#[test]
fn val_scenarios_lists_every_builtin() {
    let output = satflock().arg("scenarios").output().unwrap();
    let text = String::from_utf8_lossy(&output.stdout);
    for name in satflock::scenario::builtin::names() {
        assert!(text.contains(name));
    }
    // The whole first sentence, not cut at an abbreviation such as "Figs." or "et al.".
    let circle = text.lines().find(|l| l.starts_with("gao-circle ")).unwrap();
    assert!(
        circle.contains("Figs. 12-14") && circle.ends_with("in the orbital plane."),
        "{circle}"
    );
}

#[test]
fn val_scenarios_show_prints_the_builtin_toml_and_unknown_names_exit_2() {
    let output = satflock()
        .args(["scenarios", "show", "gao-circle"])
        .output()
        .unwrap();
    assert!(output.status.success());
    let text = String::from_utf8(output.stdout).unwrap();
    let shown =
        satflock::scenario::Scenario::from_toml(&text, "shown", std::path::Path::new(".")).unwrap();
    let builtin = satflock::scenario::Scenario::load("gao-circle").unwrap();
    assert_eq!(shown.file, builtin.file);
    let output = satflock()
        .args(["scenarios", "show", "nope"])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("gao-circle"));
}

#[test]
fn val_scenarios_show_file_prints_a_builtins_orbit_file_and_a_copy_runs() {
    // omm-flock reads an OMM embedded with it: `--file` prints it, and the TOML and the file copied
    // into a folder run from there as the built-in does.
    let dir = scratch_dir("show-file");
    for (args, name) in [
        (&["scenarios", "show", "omm-flock"][..], "flock.toml"),
        (
            &["scenarios", "show", "omm-flock", "--file", "omm-flock.xml"][..],
            "omm-flock.xml",
        ),
    ] {
        let output = satflock().args(args).output().unwrap();
        assert!(output.status.success(), "{args:?}");
        std::fs::write(dir.join(name), output.stdout).unwrap();
    }
    let copy = satflock::scenario::Scenario::from_path(&dir.join("flock.toml")).unwrap();
    let builtin = satflock::scenario::Scenario::load("omm-flock").unwrap();
    let (a, b) = (copy.prepare().unwrap(), builtin.prepare().unwrap());
    assert_eq!(a.epoch, b.epoch);
    for (x, y) in a.satellites.iter().zip(&b.satellites) {
        assert_eq!(x.relative_state, y.relative_state);
    }
    let output = satflock()
        .args(["scenarios", "show", "omm-flock", "--file", "nope.xml"])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("it embeds: omm-flock.xml"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn regress_a_bad_orbit_file_exits_2_naming_the_file_line_and_key() {
    // Issue 27: a TLE whose line 1 checksum is wrong, as `satflock run` reports it.
    let dir = scratch_dir("bad-tle");
    let tle = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/orbit_files/iss.tle"),
    )
    .unwrap();
    let bad: Vec<String> = tle
        .lines()
        .map(
            |l| match l.strip_suffix('7').filter(|_| l.starts_with("1 ")) {
                Some(head) => format!("{head}8"),
                None => l.to_string(),
            },
        )
        .collect();
    assert_ne!(
        bad.join("\n"),
        tle.trim_end(),
        "the fixture's line 1 ends in 7"
    );
    std::fs::write(dir.join("bad.tle"), bad.join("\n")).unwrap();
    std::fs::write(
        dir.join("case.toml"),
        "name = \"bad-tle\"\nseed = 1\nduration_s = 60.0\nrecord_interval_s = 60.0\n\
         [reference]\naltitude_m = 400e3\ninclination_deg = 51.6\n\
         [satellites]\ncount = 1\nmass_kg = 4.0\n\
         initial = { distribution = \"tle\", file = \"bad.tle\" }\n[law]\nname = \"none\"\n",
    )
    .unwrap();
    let out = dir.join("out");
    let output = satflock()
        .arg("run")
        .arg(dir.join("case.toml"))
        .args(["--out"])
        .arg(&out)
        .arg("--quiet")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    for needle in [
        "case.toml",
        "key `satellites.initial.file`",
        "bad.tle line 2",
        "checksum 8",
    ] {
        assert!(stderr.contains(needle), "`{needle}` missing: {stderr}");
    }
    assert!(!out.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn val_a_real_object_as_threat_runs_and_a_bad_one_exits_2() {
    // Issue 27: a threat from an OMM file, propagated by SGP4 during the run; the same file without
    // its epoch is refused naming the key.
    let dir = scratch_dir("omm-threat");
    let omm = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/orbit_files/iss.omm"),
    )
    .unwrap();
    std::fs::write(dir.join("debris.omm"), &omm).unwrap();
    let no_epoch: Vec<&str> = omm.lines().filter(|l| !l.starts_with("EPOCH")).collect();
    std::fs::write(dir.join("broken.omm"), no_epoch.join("\n")).unwrap();
    let case = |file: &str| {
        format!(
            "name = \"omm-threat\"\nseed = 1\nduration_s = 120.0\nrecord_interval_s = 60.0\n\
             epoch_utc = \"2008-09-20T13:00:00Z\"\n\
             [reference]\naltitude_m = 400e3\ninclination_deg = 51.6\n\
             [satellites]\ncount = 2\nmass_kg = 4.0\n\
             initial = {{ distribution = \"list\", states = [[0, 0, 0, 0, 0, 0], [0, 50, 0, 0, 0, 0]] }}\n\
             [law]\nname = \"none\"\n\
             [[threats]]\nname = \"debris\"\ndanger_radius_m = 10.0\nomm = \"{file}\"\n"
        )
    };
    std::fs::write(dir.join("good.toml"), case("debris.omm")).unwrap();
    std::fs::write(dir.join("bad.toml"), case("broken.omm")).unwrap();
    let run = |name: &str, out: &std::path::Path| {
        satflock()
            .arg("run")
            .arg(dir.join(name))
            .args(["--out"])
            .arg(out)
            .arg("--quiet")
            .output()
            .unwrap()
    };
    let good = dir.join("good-out");
    let output = run("good.toml", &good);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let scene: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(good.join("scene.json")).unwrap()).unwrap();
    assert_eq!(
        scene["threats"][0]["tracked"],
        serde_json::Value::Bool(true)
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(good.join("summary.json")).unwrap()).unwrap();
    let environment = &summary["environment"];
    assert_eq!(environment["threats"][0], "debris");
    // The ISS is on another orbit: its closest approach is a finite distance of kilometres or more.
    let closest = environment["closest_threat_approach"]["minimum"]["distance_m"]
        .as_f64()
        .unwrap_or_else(|| panic!("no closest approach in {environment}"));
    assert!(closest.is_finite() && closest > 1e3, "{closest}");
    let bad = dir.join("bad-out");
    let output = run("bad.toml", &bad);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    for needle in ["bad.toml", "key `threats[0].omm`", "EPOCH"] {
        assert!(stderr.contains(needle), "`{needle}` missing: {stderr}");
    }
    assert!(!bad.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn val_validate_core_prints_a_table_and_unknown_targets_exit_2() {
    let output = satflock().args(["validate", "core"]).output().unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(text.contains("| id | outcome | reference | ours | verdict |"));
    // one row per check C1..C8 and the force models' F1..F9, each reproduced
    for id in [
        "C1", "C2", "C3", "C4", "C5", "C6", "C7", "C8", "F1", "F2", "F3a", "F3b", "F4", "F5",
        "F6a", "F6b", "F7", "F8a", "F8b", "F9",
    ] {
        let row = text
            .lines()
            .find(|l| l.starts_with(&format!("| {id} |")))
            .unwrap_or_else(|| panic!("{id} missing"));
        if id.starts_with('F') {
            assert!(row.contains("reproduced"), "{row}");
        }
    }
    let output = satflock().args(["validate", "nothing"]).output().unwrap();
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("core"));
}

#[test]
fn val_validate_scatter_prints_only_the_report_as_markdown_and_json() {
    // Markdown: the outcome table with the paper and criterion columns, every N and B row, the three
    // further tables.
    let output = satflock().args(["validate", "scatter"]).output().unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(text.starts_with("### Nag & Summerer 2013"), "{text}");
    assert!(text.contains("| id | outcome | paper | criterion | ours | verdict |"));
    for id in [
        "N1",
        "N2",
        "N2 (parallel)",
        "N3",
        "N4",
        "N5",
        "N5 (axis)",
        "N6 S2",
        "N7",
        "N8",
        "N10",
        "B1",
        "B2",
        "B2 HCW",
    ] {
        assert!(text.contains(&format!("| {id} |")), "{id} missing");
    }
    assert!(text.contains("| N9 S2 perpendicular |") && text.contains("| N11 sphere |"));
    assert!(
        text.contains("#### Strategy comparison")
            && text.contains("#### Cases of the reconstruction")
            && text.contains("#### S3 dock sweep")
    );
    // JSON: stdout is exactly one JSON document (nothing else printed on stdout).
    let output = satflock()
        .args(["validate", "scatter", "--json"])
        .output()
        .unwrap();
    assert!(output.status.success());
    let v: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(v["checks"].as_array().unwrap().len(), 25);
    assert_eq!(v["tables"].as_array().unwrap().len(), 3);
    assert!(v["checks"].as_array().unwrap().iter().all(|c| [
        "reproduced",
        "differs",
        "not-reproduced",
        "not-tested",
        "retired"
    ]
    .contains(&c["verdict"].as_str().unwrap())));
}

#[test]
fn val_gao_circle_reaches_its_ring_before_1000_s_and_records_the_shape_columns() {
    // O6 of `docs/methods/bifurcating.md` §6: the ring of G3 is established by ~1000 s (our prototype: within 5 % at 450 s).
    let dir = scratch_dir("gao-circle");
    let output = satflock()
        .args(["run", "gao-circle", "--quiet", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let t = summary["law"]["time_to_shape_s"].as_f64().unwrap();
    assert!(t > 0.0 && t < 1000.0, "time to shape {t} s");
    let metrics = std::fs::read_to_string(dir.join("metrics.csv")).unwrap();
    let header = metrics.lines().next().unwrap();
    assert!(header.ends_with("shape_max_residual_m,shape_max_out_of_plane_m,shape_reached"));
}

/// A reader that closes the pipe early (`satflock scenarios | head -1`) ends satflock quietly with exit
/// 0, never a panic ("failed printing to stdout").
#[test]
fn regress_closed_stdout_pipe_is_not_a_panic() {
    for args in [&["scenarios"][..], &["scenarios", "show", "gao-circle"]] {
        let mut child = satflock()
            .args(args)
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take());
        let output = child.wait_with_output().unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        assert_eq!(output.status.code(), Some(0), "{args:?}: {stderr}");
    }
}

/// `satflock run` of the pigeon switching scenario at R_c^1 = 120 m (the default before 2026-12-01):
/// the load-time warning of the initial link graph on stderr, once, and first in summary.json's
/// `warnings`; at the default 130 m, neither.
#[test]
fn val_run_pigeon_warns_of_a_disconnected_initial_link_graph_on_stderr_and_in_the_summary() {
    let text = include_str!("../../scenarios/pigeon-switching.toml");
    let dir = scratch_dir("pigeon-links");
    let short = |range: &str| {
        let edited = text
            .replacen("duration_s = 6000.0", "duration_s = 2.0", 1)
            .replacen(
                "egalitarian_range_m = 130.0",
                &format!("egalitarian_range_m = {range}"),
                1,
            );
        assert_ne!(edited, text, "pigeon-switching.toml changed shape");
        let path = dir.join(format!("pigeon-{range}.toml"));
        std::fs::write(&path, edited).unwrap();
        let out = dir.join(format!("out-{range}"));
        let output = satflock()
            .args(["run", "--quiet", "--no-plots", "--threads", "2", "--out"])
            .arg(&out)
            .arg(&path)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
        assert!(output.status.success(), "{stderr}");
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap())
                .unwrap();
        let warnings: Vec<String> = summary["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .map(|w| w.as_str().unwrap().to_string())
            .collect();
        (stderr, warnings)
    };
    let (stderr, warnings) = short("120.0");
    let warning = warnings
        .first()
        .unwrap_or_else(|| panic!("no warning in summary.json; stderr: {stderr}"));
    assert!(
        warning.starts_with("law.egalitarian_range_m − law.link_delay_m = 110 m:")
            && warning.contains("satellite 0 has no neighbour within 110 m, nearest 115.3 m"),
        "{warning}"
    );
    let line = format!("warning: {warning}");
    assert_eq!(stderr.lines().filter(|l| *l == line).count(), 1, "{stderr}");
    let (stderr, warnings) = short("130.0");
    assert!(
        !stderr.contains("link graph") && warnings.iter().all(|w| !w.contains("link graph")),
        "{stderr} {warnings:?}"
    );
}

/// `validate --from` renders a saved measurement without running; a missing or malformed file is a
/// usage error naming the file (exit 2).
#[test]
fn val_validate_from_renders_a_saved_measurement_and_refuses_a_bad_file() {
    let saved =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../validation/measured/pigeon.json");
    let output = satflock()
        .args(["validate", "pigeon", "--from"])
        .arg(&saved)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(
        text.contains("| P7 (R_c^1 = 120 m) |")
            && text.contains("Measured by `satflock validate pigeon`")
    );
    let dir = std::env::temp_dir().join(format!("satflock-validate-from-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.json");
    std::fs::write(&bad, "{ not json").unwrap();
    for path in [bad.clone(), dir.join("missing.json")] {
        let output = satflock()
            .args(["validate", "pigeon", "--from"])
            .arg(&path)
            .output()
            .unwrap();
        assert_eq!(output.status.code(), Some(2));
        let err = String::from_utf8_lossy(&output.stderr);
        assert!(err.contains(&*path.to_string_lossy()), "{err}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
