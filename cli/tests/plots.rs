//! The figures of a run (`satflock plot`, and `satflock run` unless `--no-plots`): a run with a threat
//! (es-e0) and one with obstacles (pigeon-switching, shortened, with its trajectory written) are drawn;
//! every PNG decodes (by the `image` crate, not plotters) to the documented size and is not blank, every
//! SVG is well-formed enough (one root, balanced text elements) and carries the axis labels with their
//! units and the scene's object names; drawing twice gives the same bytes. The CLI draws after a run,
//! also after a failed one, skips with `--no-plots`, reruns into a directory holding plots, and refuses a
//! directory that is not a run's (exit 2).

use std::path::{Path, PathBuf};

use satflock::run::run_scenario;
use satflock::scenario::builtin::BUILTINS;
use satflock::scenario::Scenario;
use satflock_cli::plot::draw_run;

mod common;
use common::satflock;

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("satflock-plots-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs a built-in scenario with some `key = value` lines replaced into `dir/run`.
fn run_builtin(dir: &Path, name: &str, replacements: &[(&str, &str)]) -> PathBuf {
    let mut text = BUILTINS
        .iter()
        .find(|b| b.name == name)
        .unwrap()
        .toml
        .to_string();
    for (from, to) in replacements {
        assert!(text.contains(from), "{name} has no `{from}`");
        text = text.replacen(from, to, 1);
    }
    let scenario = Scenario::from_toml(&text, name, Path::new(".")).unwrap();
    let out = dir.join("run");
    run_scenario(&scenario, &out, &mut |_| {}).unwrap();
    out
}

/// Every figure a run with a trajectory and law metrics gets, with its documented size [px]: the
/// tracks figure 1800 × 680, delta-v 1400 × 520, the metric grids 4 panels of 420 × 290 per row plus a
/// 50 px title, the snapshots 4 panels of 480 × 480 per row plus 50 px, the nearest-neighbour
/// separations 1000 × 560.
fn expected_sizes(
    metric_panels: u32,
    law_panels: u32,
    snapshots: u32,
) -> Vec<(&'static str, (u32, u32))> {
    let grid = |n: u32, w: u32, h: u32| (n.min(4) * w, n.div_ceil(4) * h + 50);
    vec![
        ("trajectories", (1800, 680)),
        ("snapshots", grid(snapshots, 480, 480)),
        ("separations", (1000, 560)),
        ("swarm_metrics", grid(metric_panels, 420, 290)),
        ("law_metrics", grid(law_panels, 420, 290)),
        ("delta_v", (1400, 520)),
    ]
}

/// Checks the PNG and SVG of every figure; returns every file's bytes.
fn check_figures(
    run: &Path,
    sizes: &[(&str, (u32, u32))],
    svg_texts: &[(&str, &[&str])],
) -> Vec<(PathBuf, Vec<u8>)> {
    let plots = run.join("plots");
    let mut files = Vec::new();
    for (name, (w, h)) in sizes {
        let png = plots.join(format!("{name}.png"));
        let image = image::open(&png)
            .unwrap_or_else(|e| panic!("{}: {e}", png.display()))
            .to_rgb8();
        assert_eq!(image.dimensions(), (*w, *h), "{name}.png");
        let background = image.get_pixel(0, 0);
        assert_eq!(background.0, [255, 255, 255], "{name}.png background");
        let drawn = image.pixels().filter(|p| *p != background).count();
        let share = drawn as f64 / f64::from(w * h);
        assert!(share > 0.01, "{name}.png is nearly blank: {share}");
        let svg_path = plots.join(format!("{name}.svg"));
        let svg = std::fs::read_to_string(&svg_path).unwrap();
        assert!(
            svg.starts_with(&format!("<svg width=\"{w}\" height=\"{h}\"")),
            "{name}.svg: {}",
            &svg[..80.min(svg.len())]
        );
        assert_eq!(svg.matches("<svg").count(), 1, "{name}.svg");
        assert!(svg.trim_end().ends_with("</svg>"), "{name}.svg");
        assert_eq!(
            svg.matches("<text").count(),
            svg.matches("</text>").count(),
            "{name}.svg"
        );
        assert!(svg.matches("<text").count() > 5, "{name}.svg has no text");
        for (figure, texts) in svg_texts {
            if figure == name {
                for text in *texts {
                    assert!(svg.contains(text), "{name}.svg lacks `{text}`");
                }
            }
        }
        files.push((png.clone(), std::fs::read(&png).unwrap()));
        files.push((svg_path, svg.into_bytes()));
    }
    files
}

const TRACK_AXES: &[&str] = &["x radial [m]", "y along-track [m]", "z orbit normal [m]"];

#[test]
fn val_plots_of_a_threat_run_are_complete_labelled_and_deterministic() {
    let dir = temp_dir("threat");
    let run = run_builtin(&dir, "es-e0", &[]);
    let report = draw_run(&run).unwrap();
    assert_eq!(report.written.len(), 12, "{report:?}");
    assert!(report.skipped.is_empty(), "{report:?}");
    // 7 standard panels + the two threat monitors; the law's 6 metrics; no events: 4 snapshots.
    let sizes = expected_sizes(9, 6, 4);
    let texts: &[(&str, &[&str])] = &[
        ("trajectories", TRACK_AXES),
        (
            "trajectories",
            &[
                "es-e0",
                "kinetic-threat",
                "target formation",
                // Not "danger sphere": at its closest recorded approach es-e0's threat is farther
                // out of the orbital plane than its danger radius, so the x–y panel (the one with
                // the legend) no longer draws it (issue 30); the y–z and x–z panels do, named.
            ],
        ),
        ("snapshots", &["t = 0 s (start)", "t = 40 s (end)"]),
        (
            "separations",
            &["nearest-neighbour distance [m]", "smallest", "median"],
        ),
        (
            "swarm_metrics",
            &[
                "t [s]",
                "d_max [m]",
                "diameter [m]",
                "d_min [m]",
                "uniformity_l [-]",
                "min_separation [m]",
                "min_threat_distance [m]",
            ],
        ),
        (
            "law_metrics",
            &["t [s]", "es_formation_error [m]", "es_nominal [-]"],
        ),
        ("delta_v", &["Δv [m/s]", "satellite id [-]", "t [s]"]),
    ];
    let first = check_figures(&run, &sizes, texts);
    // The scene's target formation (the rhombus nodes) was written for the figures.
    let scene: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(run.join("scene.json")).unwrap()).unwrap();
    assert_eq!(
        scene["target_formation_lvlh_m"].as_array().unwrap().len(),
        4
    );
    draw_run(&run).unwrap();
    for (path, bytes) in &first {
        assert!(
            std::fs::read(path).unwrap() == *bytes,
            "{} differs when drawn again",
            path.display()
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn val_plots_of_an_obstacle_run_show_the_obstacles() {
    let dir = temp_dir("obstacles");
    let run = run_builtin(
        &dir,
        "pigeon-switching",
        &[
            ("duration_s = 6000.0", "duration_s = 300.0"),
            ("record_interval_s = 1.0", "record_interval_s = 5.0"),
            ("trajectory = false", "trajectory = true"),
        ],
    );
    let report = draw_run(&run).unwrap();
    assert_eq!(report.written.len(), 12, "{report:?}");
    let sizes = expected_sizes(9, 6, 4);
    let texts: &[(&str, &[&str])] = &[
        ("trajectories", TRACK_AXES),
        (
            "trajectories",
            &[
                "pigeon-switching",
                "obstacle-1",
                "obstacle-2",
                "obstacle (sphere)",
            ],
        ),
        ("snapshots", &["obstacle-1"]),
        (
            "swarm_metrics",
            &["min_obstacle_clearance [m]", "obstacle_incursions [-]"],
        ),
        (
            "law_metrics",
            &["pigeon_order_parameter [-]", "pigeon_mean_distance [m]"],
        ),
        ("delta_v", &["Δv [m/s]"]),
    ];
    let first = check_figures(&run, &sizes, texts);
    draw_run(&run).unwrap();
    for (path, bytes) in &first {
        assert!(std::fs::read(path).unwrap() == *bytes, "{}", path.display());
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn val_large_swarms_show_an_evenly_spaced_subsample_and_say_so() {
    let dir = temp_dir("subsample");
    let run = run_builtin(
        &dir,
        "free-drift",
        &[
            ("count = 50", "count = 450"),
            ("duration_s = 5800.0", "duration_s = 40.0"),
        ],
    );
    draw_run(&run).unwrap();
    let svg = std::fs::read_to_string(run.join("plots/trajectories.svg")).unwrap();
    assert!(svg.contains("200 of 450 satellites shown (evenly spaced ids)"));
    // 200 start and 200 end markers per panel, three panels, and the legend's two (plotters writes a
    // circle per marker).
    assert_eq!(svg.matches("<circle").count(), 3 * 2 * 200 + 2);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn val_cli_draws_after_runs_skips_with_no_plots_and_refuses_other_directories() {
    let dir = temp_dir("cli");
    let out = dir.join("out");
    for _ in 0..2 {
        // The second run goes into the first's directory, plots/ included.
        let o = satflock()
            .args(["run", "es-e0", "--quiet", "--out"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert!(out.join("plots/trajectories.png").is_file());
        assert!(out.join("plots/delta_v.svg").is_file());
    }
    let o = satflock()
        .args(["run", "es-e0", "--quiet", "--no-plots", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success());
    assert!(
        !out.join("plots").exists(),
        "--no-plots left a plots folder"
    );
    let o = satflock().arg("plot").arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stderr).contains("6 figures"));
    assert!(out.join("plots/law_metrics.png").is_file());

    // Not a run directory: exit 2, naming what is missing.
    let o = satflock().arg("plot").arg(&dir).output().unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("summary.json"));
    let o = satflock()
        .arg("plot")
        .arg(dir.join("nowhere"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));

    // A run that fails (divergence at t = 11 s) still gets its figures, from what it wrote.
    let file = dir.join("diverge.toml");
    std::fs::write(
        &file,
        "name = \"diverge\"\nseed = 1\nduration_s = 100.0\nrecord_interval_s = 1.0\n[dynamics]\nmax_distance_m = 600.0\n[reference]\naltitude_m = 600e3\ninclination_deg = 97.8\n[satellites]\ncount = 2\nmass_kg = 1.0\ninitial = { distribution = \"list\", states = [[0,0,0,0,0,0],[0,589.5,0,0,1.0,0]] }\n[law]\nname = \"none\"\n",
    )
    .unwrap();
    let failed = dir.join("failed");
    let o = satflock()
        .args(["run", "--quiet", "--out"])
        .arg(&failed)
        .arg(&file)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    let svg = std::fs::read_to_string(failed.join("plots/trajectories.svg")).unwrap();
    assert!(
        svg.contains("run failed at t = 11 s"),
        "title of a failed run"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A run whose satellites have drag attitudes also gets the `drag` figure (phase, altitude, drag area);
/// a run without them does not (it does not apply: nothing is skipped).
#[test]
fn val_drag_figure_of_a_drag_attitude_run() {
    let dir = temp_dir("drag");
    let run = run_builtin(&dir, "dd-pair-keeping", &[]);
    let report = draw_run(&run).unwrap();
    assert!(report.skipped.is_empty(), "{report:?}");
    check_figures(
        &run,
        &[("drag", (1400, 1200))],
        &[(
            "drag",
            &[
                "phase [deg]",
                "altitude [km]",
                "area [m²]",
                "2 of 2 satellites",
            ],
        )],
    );
    let threat = run_builtin(&dir, "es-e0", &[]);
    draw_run(&threat).unwrap();
    assert!(!threat.join("plots/drag.png").exists());
}

/// A run that records its control history (`[output] control_history`) also gets the `control` figure
/// (applied and commanded acceleration norms of the first five satellites, saturation timeline), which
/// the HTML report shows; a run without the history does not get it (nothing is skipped).
#[test]
fn val_control_figure_of_a_control_history_run() {
    let dir = temp_dir("control");
    let run = run_builtin(
        &dir,
        "hold",
        &[
            ("duration_s = 4000.0", "duration_s = 1100.0"),
            (
                "record_interval_s = 10.0",
                "record_interval_s = 10.0\n\n[output]\ncontrol_history = true",
            ),
            ("time_s = 2000.0", "time_s = 1050.0"),
        ],
    );
    let report = draw_run(&run).unwrap();
    assert!(report.skipped.is_empty(), "{report:?}");
    check_figures(
        &run,
        &[("control", (1400, 900))],
        &[(
            "control",
            &[
                "‖u‖ [m/s²]",
                "satellite id [-]",
                "t [s]",
                "the first 5 of 20 satellites",
                "satellite 4",
                "saturation timeline",
            ],
        )],
    );
    let first = std::fs::read(run.join("plots/control.png")).unwrap();
    draw_run(&run).unwrap();
    assert_eq!(first, std::fs::read(run.join("plots/control.png")).unwrap());
    let html = satflock_cli::report::render(&run).unwrap();
    assert!(html.contains("<figcaption>control.svg</figcaption>"));
    let threat = run_builtin(&dir, "es-e0", &[]);
    draw_run(&threat).unwrap();
    assert!(!threat.join("plots/control.png").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn val_conjunction_timeline_of_a_run_with_a_conjunction_monitor() {
    // es-e0's threat passes through the cluster: with a threshold the pass is an encounter with the
    // threat, and satellites that close on each other make pair encounters.
    let dir = temp_dir("conjunctions");
    let run = run_builtin(
        &dir,
        "es-e0",
        &[("[law]", "[conjunctions]\nthreshold_m = 300.0\n\n[law]")],
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(run.join("summary.json")).unwrap()).unwrap();
    let count = summary["conjunctions"]["count"].as_u64().unwrap();
    assert!(count > 0, "no encounter to draw");
    draw_run(&run).unwrap();
    check_figures(
        &run,
        &[("conjunctions", (1000, 560))],
        &[(
            "conjunctions",
            &[
                "conjunction timeline",
                &format!("{count} encounters below 300 m"),
                "miss distance [m]",
                "threshold 300 m",
            ],
        )],
    );
    let first = std::fs::read(run.join("plots/conjunctions.png")).unwrap();
    draw_run(&run).unwrap();
    assert_eq!(
        first,
        std::fs::read(run.join("plots/conjunctions.png")).unwrap()
    );
    let html = satflock_cli::report::render(&run).unwrap();
    assert!(html.contains("<figcaption>conjunctions.svg</figcaption>"));
    let without = run_builtin(&dir, "es-e0", &[]);
    draw_run(&without).unwrap();
    assert!(!without.join("plots/conjunctions.png").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}
