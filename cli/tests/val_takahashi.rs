//! Reproduction of Takahashi & Sakai (method page `docs/methods/j2-distance.md`) with the
//! `j2-distance` law, shortened to fit the test budget: the §4.1 comparison on the linear model (T1–T3
//! of method page §11.2, 12 h instead of 24 h), a 24 h truth-J2 deployment into plane Θ1 (the early part of
//! T4–T9 of §11.3; the full 120 h runs are in `satflock validate takahashi`), the outage experiment
//! of §8 (switch-off at 1 h, 5 h of free drift), and the connectivity-preserving grouping of §9.6 on
//! short Θ2 runs (the 20-seed split fraction is in `satflock validate takahashi-split`).

use satflock::guidance::j2_distance::Variant;
use satflock::scenario::Scenario;
use satflock_cli::validate::takahashi::{
    connectable_stats, outage_stats, plane_stats, scenario, traced_run, TracedRun,
};
use satflock_cli::validate::takahashi_split::split_run;

const ORIGIN: usize = 0;
const RANGE_M: f64 = 1.0;

#[test]
fn val_connectable_comparison_t1_t3_linear() {
    let mut stats = Vec::new();
    for name in ["ts-connectable-large", "ts-connectable-small"] {
        for variant in [Variant::Main, Variant::Opp] {
            let s = scenario(name, Some(variant), Some(12.0 * 3600.0)).unwrap();
            let run = traced_run(&s, 60.0, f64::INFINITY).unwrap();
            stats.push(connectable_stats(&run, ORIGIN, RANGE_M));
        }
    }
    let [main_large, opp_large, main_small, opp_small] = [0, 1, 2, 3].map(|k| stats[k].clone());
    // T1 (method page §11.2): both laws reach max|C1| < 1e-3 m and max|C4| < 1e-2 m within 6 h, and 1e-6 m
    // within 12 h (method page §11.2's bounds, which hold "with a wide margin" in our earlier prototype).
    for s in &stats {
        assert!(s.settle_h.is_some_and(|h| h <= 6.0), "T1: {s:?}");
        assert!(
            s.settle_1e6_h.is_some_and(|h| h <= 12.0),
            "T1 (1e-6): {s:?}"
        );
    }
    // T2: small C1, median T̂_conn at 1 h for main >= 20x opp; opp fraction with growing |C1| >= 0.85;
    // large C1: the median at 1 h is larger for main.
    assert!(
        main_small.median_tconn_1h_h >= 20.0 * opp_small.median_tconn_1h_h,
        "T2: {main_small:?} vs {opp_small:?}"
    );
    assert!(opp_small.growing_fraction >= 0.85, "T2: {opp_small:?}");
    // T2's large-C1 clause (median at 1 h larger for main) depends on the draw (our earlier prototype 6–52 h
    // vs 2.4–6.4 h over its seeds; ours on seeds 1–3 since the random-stream redesign: 25.0/2.6,
    // 12.9/4.4, 44.5/2.5 h; with the earlier draws seed 1 gave 1.8 vs 2.3 h); reported by
    // `satflock validate takahashi`, not asserted here.
    // T3: mean sign changes of C1 under main <= half of those under opp, in both cases.
    assert!(main_large.mean_sign_changes <= 0.5 * opp_large.mean_sign_changes);
    assert!(main_small.mean_sign_changes <= 0.5 * opp_small.mean_sign_changes);
}

#[test]
fn val_plane_1_truth_first_24_hours() {
    // Θ1 = (30°, 0°), 100 satellites, truth J2, defaults; the §9.5 schedule keeps its 120 h end, so the
    // first 24 h group every 5 min as in the full run. (Θ2 splits into two halves in the saturated
    // transient on 3 of seeds 1–8 — seeds 5, 7 and 8 with the current draws: see the validate report.)
    let s = scenario("ts-plane-1", None, Some(24.0 * 3600.0)).unwrap();
    let run = traced_run(&s, 1800.0, f64::INFINITY).unwrap();
    let st = plane_stats(&run, ORIGIN, RANGE_M, 1e-6);
    // T4: connected at every grouping update (method page §11.3; the saturation part applies after 24 h).
    assert!(st.always_connected, "{st:?}");
    // T5's bounds (method page §11.3, the looser γ_A-independent ones): the C1 loop settles within a few hours
    // (rate >= k_A λ2 / 2), so they already hold at 24 h.
    assert!(st.max_c1_m < 1e-2 && st.max_c4_m < 0.5, "{st:?}");
}

#[test]
fn val_outage_centre_exit_matches_connectable_time() {
    // Opposing law (short T̂_conn at 1 h, method page §11.2: median 4.0–8.2 h), links cut at 1 h, 5 h of free
    // drift under truth J2.
    let s = scenario("ts-outage", Some(Variant::Opp), Some(6.0 * 3600.0)).unwrap();
    let run = traced_run(&s, 60.0, 3600.0).unwrap();
    let o = outage_stats(&run, ORIGIN, 3600.0, RANGE_M);
    // Exits must be observed, and every predicted exit must be measured.
    assert!(o.predicted_exits > 0, "{o:?}");
    assert!(
        o.measured_centre_exits >= o.predicted_exits.saturating_sub(1),
        "{o:?}"
    );
    // The relaxed T̂_conn is exact on the linear model (method page §8); under truth J2 the measured centre
    // carries the short-period oscillation of C1 (±4e-3 r_xy, method page §3.5) and is sampled every 60 s:
    // half an hour covers the sampling and the drift-rate error over a few hours.
    assert!(o.median_centre_error_h < 0.5, "{o:?}");
}

#[test]
fn val_law_metrics_time_series_match_the_summary_at_the_end() {
    // Θ2, 100 satellites, truth J2, 1 h recorded every 30 min: metrics.csv must carry the law's time
    // series (method page §13), and its last row must equal what summary.json reports at the final time (the
    // recording at t = 1 h and the summary see the same swarm and the same grouping).
    let s = scenario("ts-plane-2", None, Some(3600.0)).unwrap();
    let dir = std::env::temp_dir().join(format!("satflock-ts-metrics-{}", std::process::id()));
    satflock::run::run_scenario(&s, &dir, &mut |_| {}).unwrap();
    let run = satflock::output::RunData::read(&dir).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    let summary = &run.summary;
    assert_eq!(run.metrics.rows(), 3, "t = 0, 0.5 h, 1 h");
    let column = |name: &str| {
        *run.metrics
            .column(name)
            .unwrap_or_else(|| panic!("no column {name} in {:?}", run.metrics.names()))
            .last()
            .unwrap()
    };
    let law = &summary["law"];
    let same = |csv: f64, json: &serde_json::Value, what: &str| {
        let j = json.as_f64().unwrap_or_else(|| panic!("{what}: {json}"));
        assert!(
            (csv - j).abs() <= 1e-12 * j.abs().max(1e-300),
            "{what}: {csv} vs {j}"
        );
    };
    same(column("ts_max_abs_c1_m"), &law["max_abs_c1_m"], "max|C1|");
    same(column("ts_max_abs_c4_m"), &law["max_abs_c4_m"], "max|C4|");
    same(
        column("ts_theta_p_min_deg"),
        &law["plane_theta_p_deg_range"][0],
        "Θ_P min",
    );
    same(
        column("ts_theta_p_max_deg"),
        &law["plane_theta_p_deg_range"][1],
        "Θ_P max",
    );
    same(
        column("ts_theta_zxy_min_deg"),
        &law["plane_theta_zxy_deg_range"][0],
        "Θz min",
    );
    same(
        column("ts_theta_zxy_max_deg"),
        &law["plane_theta_zxy_deg_range"][1],
        "Θz max",
    );
    for (k, name) in ["ts_edge_ratio_p5", "ts_edge_ratio_p50", "ts_edge_ratio_p95"]
        .into_iter()
        .enumerate()
    {
        same(column(name), &law["edge_ratio_p5_p50_p95"][k], name);
    }
    same(
        column("ts_min_connectable_time_h"),
        &law["min_connectable_time_h"],
        "T̂_conn",
    );
    same(
        column("ts_saturation_fraction"),
        &law["saturation_fraction"],
        "saturation",
    );
    same(column("ts_edges"), &law["edges"], "edges");
    same(
        column("ts_components"),
        &law["grouping"]["components"],
        "components",
    );
    same(
        column("ts_edge_changes_total"),
        &law["grouping"]["edge_changes"],
        "edge changes",
    );
    // A time series, not a constant: the first grouping happens after the t = 0 recording (no edges
    // yet), and max|C1| moves during the first hour.
    let edges = run.metrics.column("ts_edges").unwrap();
    assert_eq!(edges[0], 0.0);
    assert!(edges[1] > 0.0);
    let c1 = run.metrics.column("ts_max_abs_c1_m").unwrap();
    assert!(c1[0] != c1[2]);
}

/// `ts-plane-2` from its built-in TOML with `extra` added to its `[law]` table, seed `seed`, `hours`
/// long, recorded every 10 min.
fn plane_2(extra: &str, seed: u64, hours: f64) -> Scenario {
    let builtin = satflock::scenario::builtin::BUILTINS
        .iter()
        .find(|b| b.name == "ts-plane-2")
        .unwrap();
    let text = builtin
        .toml
        .replace("[law]\n", &format!("[law]\n{extra}\n"));
    let mut s = Scenario::from_toml(&text, "ts-plane-2", std::path::Path::new(".")).unwrap();
    s.file.seed = seed;
    s.file.duration_s = hours * 3600.0;
    s.file.record_interval_s = 600.0;
    s
}

/// Every recorded relative state of a traced run, as bits.
fn state_bits(run: &TracedRun) -> Vec<u64> {
    run.fine_states
        .iter()
        .flatten()
        .flat_map(|x| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>())
        .collect()
}

#[test]
fn val_preserving_grouping_off_or_idle_is_the_paper_path_bitwise() {
    // Θ2, seed 1, first hour (no split on this draw): the parameter absent (the paper's Algorithm 1),
    // `preserve_connectivity = false`, and `true` (which finds nothing to repair here) fly the same
    // trajectories bit for bit and report the same grouping.
    let paper = traced_run(&plane_2("", 1, 1.0), 600.0, 0.0).unwrap();
    assert_eq!(paper.fine_times_s.len(), 7);
    for extra in [
        "preserve_connectivity = false",
        "preserve_connectivity = true",
    ] {
        let run = traced_run(&plane_2(extra, 1, 1.0), 600.0, 0.0).unwrap();
        assert_eq!(run.law["grouping"]["connectivity_repairs"], 0, "{extra}");
        assert_eq!(state_bits(&run), state_bits(&paper), "{extra}");
        assert_eq!(run.law["edge_list"], paper.law["edge_list"], "{extra}");
        assert_eq!(run.law["grouping"], paper.law["grouping"], "{extra}");
    }
}

#[test]
fn val_preserving_grouping_keeps_theta_2_connected_deterministically() {
    // Seed 5 splits at 1.75 h with the paper's grouping (`validate takahashi`, `validate
    // takahashi-split`); with the preserving grouping the graph stays connected through 2 h, which
    // takes repairs (if a change of the initial draws stops seed 5 from splitting, the repair count
    // below fails: pick a splitting seed from `validate takahashi-split`). The same run on 1 and 2
    // threads is identical bit for bit.
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| traced_run(&plane_2("preserve_connectivity = true", 5, 2.0), 600.0, 0.0))
            .unwrap()
    };
    let one = on(1);
    let g = &one.law["grouping"];
    assert_eq!(g["always_connected"], true, "{g}");
    assert_eq!(g["max_components"], 1, "{g}");
    assert!(g["connectivity_repairs"].as_u64().unwrap() >= 1, "{g}");
    let two = on(2);
    assert_eq!(state_bits(&one), state_bits(&two));
    assert_eq!(one.law["edge_list"], two.law["edge_list"]);
    // The validate report's runner reads the same results (the paper's grouping here: the split).
    let paper = split_run(5, false, 2.0 * 3600.0).unwrap();
    assert!(paper.split(), "{paper:?}");
    assert_eq!(paper.repairs, 0);
}

#[test]
fn val_split_campaign_files_describe_the_report_runs() {
    // campaigns/ts-plane-2-split*.toml rerun `validate takahashi-split` with `satflock campaign`: the
    // same scenario, seeds, duration and grouping.
    use satflock_cli::validate::takahashi_split::{DURATION_S, SEEDS};
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../campaigns");
    for (file, preserve) in [
        ("ts-plane-2-split.toml", false),
        ("ts-plane-2-split-preserving.toml", true),
    ] {
        let text = std::fs::read_to_string(root.join(file)).unwrap();
        let c: toml::Table = toml::from_str(&text).unwrap();
        assert_eq!(c["scenario"].as_str(), Some("ts-plane-2"), "{file}");
        assert_eq!(
            c["seeds"]["count"].as_integer(),
            Some(SEEDS as i64),
            "{file}"
        );
        assert_eq!(c["seeds"]["first"].as_integer(), Some(1), "{file}");
        let set = c["set"].as_table().unwrap();
        assert_eq!(set["duration_s"].as_float(), Some(DURATION_S), "{file}");
        assert_eq!(
            set["law.preserve_connectivity"].as_bool(),
            Some(preserve),
            "{file}"
        );
        assert_eq!(set.len(), 2, "{file}");
    }
}
