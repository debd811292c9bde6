//! Release-mode regression of the Nag & Summerer 2013 scatter reproduction (S. Nag and L. Summerer,
//! "Behaviour based, autonomous and distributed scatter manoeuvres for satellite swarms", Acta
//! Astronautica 82 (2013) 95–109), sized for CI: the same runs and the same `check_*` functions as
//! `satflock validate scatter` (`satflock_cli::validate::scatter`), on the built-in `es-*` scenarios.
//!
//! The outcomes, their criteria and numbers are `validation/scatter.toml`. Asserted: N3, N8, N10 and
//! the bounds B1 and B2 HCW (the exact HCW reach; the double-integrator B2 is retired: ½√2 a t² is not
//! a theorem on the HCW equations — an escape saturating two axes exceeds it through the Coriolis
//! coupling).
//!
//! N2 (parallel), N4 and N6 do not reproduce, and N7 cannot be tested at the paper's coefficients:
//! `validate scatter` reports them with the reason. Here a test asserts the mechanism our runs show,
//! derived from the equations, so that a change of behaviour is noticed.
//!
//! N5, N9 and N11 are benchmarks of tuning-dependent numbers and are only reported. The uncapped E1,
//! the kinematic E0 at its own 40 s, E3a continued to 1000 s and the −y escape variant are report
//! diagnostics and are not run here; every capped case is (B1).
//!
//! Every run needed here is made once, at full scenario length, in one batch of two parallel runs
//! ([`runs`]); the tests then read it (a few seconds in release mode).

use std::sync::OnceLock;

use satflock_cli::validate::data::{Outcome, PaperData};
use satflock_cli::validate::scatter::{
    check_b1, check_b2_hcw, check_n10, check_n3, check_n6, check_n7, check_n8, data,
    e0_continued_job, escape_bounds, find, parallel_standoff_m, passed_threat, run_cases, CaseJob,
    CaseRun, E0_CONTINUED, E2B3_SAMPLES_S,
};
use satflock_cli::validate::{Check, Verdict};

fn jobs() -> Vec<CaseJob> {
    vec![
        CaseJob::full("es-e1-capped"),
        CaseJob::full("es-e2a-h2000"),
        CaseJob::full("es-e4"),
        CaseJob::full("es-e3b"),
        CaseJob::full("es-e2a-h200"),
        CaseJob::noise_free_until("es-e3a", 500.0),
        CaseJob::full("es-e3a"),
        CaseJob::full("es-e2b-3").with_samples(&E2B3_SAMPLES_S),
        CaseJob::full("es-e2b-2"),
        CaseJob::noise_free_until("es-e4", 300.0),
        CaseJob::full("es-e2b-4"),
        CaseJob::full("es-e2b-2-electric"),
        CaseJob::noise_free_until("es-e2b-2", 200.0),
        CaseJob::noise_free_until("es-e2b-4", 200.0),
        CaseJob::noise_free_until("es-e2b-2-electric", 200.0),
        CaseJob::full("es-e2b-1"),
        CaseJob::noise_free_until("es-e2b-1", 50.0),
        e0_continued_job(paper()).expect("N2 (parallel) data"),
    ]
}

/// The paper's data file.
fn paper() -> &'static PaperData {
    static DATA: OnceLock<PaperData> = OnceLock::new();
    DATA.get_or_init(|| data().expect("validation/scatter.toml"))
}

fn outcome(id: &str) -> &'static Outcome {
    paper().outcome(id).expect("outcome")
}

/// Every run of this file, made once.
fn runs() -> &'static [CaseRun] {
    static RUNS: OnceLock<Vec<CaseRun>> = OnceLock::new();
    RUNS.get_or_init(|| run_cases(&jobs()).expect("the es-* runs"))
}

fn run(label: &str) -> &'static CaseRun {
    find(runs(), label).unwrap()
}

fn assert_reproduced(c: &Check) {
    assert_eq!(
        c.verdict,
        Verdict::Reproduced,
        "{}: {}\n  reference: {}\n  ours: {}",
        c.id,
        c.outcome,
        c.paper,
        c.ours
    );
}

/// Why N2 does not reproduce: a satellite on the threat's line flees along the threat's motion at
/// A e^(−d²/K), which is at least the threat's speed V while d ≤ √(K ln(A/V)) (9.05 m for A = 40 m/s,
/// K = 22.2 m², V = 1 m/s; the pair terms shift the balance a little), so in the kinematic model it stays
/// ahead of the threat inside the sensing radius, and the others follow: at 60 s every satellite is
/// still ahead of the threat along its motion and satellite 0 is still within the 10 m sensing radius.
#[test]
fn regress_n2_mechanism_rhombus_rides_ahead_of_the_threat() {
    let e0 = run(E0_CONTINUED);
    let m = passed_threat(e0, outcome("N2 (parallel)").value("past_m").unwrap()).unwrap();
    assert!(
        m.threat_past_satellites_m < 0.0,
        "the threat got past every satellite: {m:?}"
    );
    let law = &e0.law;
    let threat = e0.threat.as_ref().unwrap();
    let standoff = parallel_standoff_m(
        law.threat_scale_mps,
        2.0 * (law.physical_sensing_radius_m / 3.0).powi(2),
        threat.velocity_hill_mps(0.0).norm(),
    );
    assert!(
        standoff < law.physical_sensing_radius_m,
        "standoff {standoff} m"
    );
    let end = e0.end();
    let d0 = (end.positions_m[0] - threat.position_hill_m(end.time_s)).norm();
    assert!(
        d0 <= law.physical_sensing_radius_m,
        "satellite 0 is {d0} m from the threat, outside the sensing radius"
    );
    assert_eq!(m.recordings, 40, "recordings with the threat past node 0");
}

/// N3: Table 1 sims 2 and 4: the average miss depends on the headtime, not on the threat speed
/// (within 10 %).
#[test]
fn regress_n3_miss_independent_of_threat_speed() {
    assert_reproduced(&check_n3(outcome("N3"), run("es-e2b-2"), run("es-e2b-4")).unwrap());
}

/// Why N4 does not reproduce: the warning lasts until 400 s and the warned threat term keeps the
/// satellites thrusting outwards until then. Braking radially at no more than the per-axis cap a, a
/// satellite moving radially at v_x needs at least v_x / a to stop, which is more than the 300 s left
/// to the end of sim 3: the formation errors of sims 2 and 3 are both taken mid-braking, and every
/// satellite still moves outwards at 700 s. (The run also passes through 500 s with the state of sim 2:
/// sims 2 and 3 are the same scenario but for the length.)
#[test]
fn regress_n4_mechanism_still_braking_at_700_s() {
    let sim3 = run("es-e2b-3");
    let sim2 = run("es-e2b-2");
    let (a, _) = sim3.common_cap().unwrap();
    let at_400 = sim3.at(400.0).unwrap();
    for (i, v) in at_400.velocities_mps.iter().enumerate() {
        assert!(
            v.x / a > 700.0 - 400.0,
            "satellite {i} could stop by 700 s: v_x = {} m/s",
            v.x
        );
    }
    for (i, v) in sim3.end().velocities_mps.iter().enumerate() {
        assert!(
            v.x > 0.0,
            "satellite {i} has stopped by 700 s: v_x = {} m/s",
            v.x
        );
    }
    assert_eq!(
        sim3.at(500.0).unwrap().positions_m,
        sim2.end().positions_m,
        "sim 3 at 500 s is sim 2's end"
    );
}

/// Why N6 does not reproduce: the threat is aimed exactly at satellite 0's node (our reading of a gap)
/// and a parallel escape cannot outrun a threat that keeps coming, so both parallel runs end in direct
/// hits (minimum miss under a millimetre), far from the paper's 7 m and 9 m, while the perpendicular
/// escapes still miss by tens of metres (the original ratio criterion, now a secondary line).
#[test]
fn regress_n6_parallel_escapes_are_direct_hits() {
    let (e2a, e3b) = (run("es-e2a-h200"), run("es-e3b"));
    for (id, parallel, perpendicular) in [
        ("N6 S2", e2a, run("es-e2b-2").average_miss_m()),
        ("N6 S3", e3b, run("es-e3a").minimum_miss_m()),
    ] {
        let c = check_n6(
            outcome(id),
            parallel,
            ("ratio", perpendicular, parallel.minimum_miss_m()),
        )
        .unwrap();
        assert_eq!(c.verdict, Verdict::Differs, "{}: {}", c.id, c.ours);
        assert!(
            parallel.minimum_miss_m() < 1e-3,
            "{id}: {}",
            parallel.minimum_miss_m()
        );
        assert!(
            perpendicular > 10.0,
            "{id}: perpendicular miss {perpendicular} m"
        );
    }
}

/// Why N7 is not tested at the paper's coefficients: the dock well's peak speed d √(k₃/2) e^(−1/2)
/// exceeds the threat term's largest speed A, so no satellite leaves its node by even a metre and the
/// centroid cannot move; the check says "not tested".
#[test]
fn regress_n7_not_tested_when_the_dock_well_holds() {
    let (e3a, e3b) = (run("es-e3a"), run("es-e3b"));
    for r in [e3a, e3b] {
        let peak =
            satflock_cli::validate::scatter::dock_peak_mps(r.law.dock_per_s, r.law.dock_range_m2);
        assert!(
            peak > r.law.threat_scale_mps,
            "{}: peak {peak} m/s",
            r.job.label
        );
        assert!(
            r.max_node_distance_m() < 1.0,
            "{}: {} m",
            r.job.label,
            r.max_node_distance_m()
        );
    }
    let c = check_n7(outcome("N7"), e3a, e3b).unwrap();
    assert_eq!(c.verdict, Verdict::NotTested, "{}", c.ours);
}

/// N8: S2 (moving centroid) moves the centroid by more than 50 m (E2a-h200, E2b-2).
#[test]
fn regress_n8_moving_centroid_moves_the_centroid() {
    assert_reproduced(&check_n8(outcome("N8"), run("es-e2a-h200"), run("es-e2b-2")).unwrap());
}

/// N10: with the electric cap (14 µm/s²) the average miss exceeds the node offset by at most 1 m.
#[test]
fn regress_n10_electric_cap_buys_under_a_metre() {
    assert_reproduced(&check_n10(outcome("N10"), run("es-e2b-2-electric")).unwrap());
}

/// B1: every capped run of this file (all eleven capped cases at full length, and the noise-free runs)
/// keeps ∫‖u‖dt ≤ √3 a T and ∫|u_k|dt ≤ a T per satellite.
#[test]
fn regress_b1_delta_v_within_the_cap() {
    let all: Vec<&CaseRun> = runs().iter().collect();
    assert_reproduced(&check_b1(outcome("B1"), &all).unwrap());
}

/// B2: the control-only displacement perpendicular to the threat of every noise-free escape (headtimes
/// 50, 200, 300 and 500 s; chemical and electric caps) stays within the exact HCW reach of the per-axis
/// cap at every recording up to the headtime.
#[test]
fn regress_b2_escape_within_the_reachable_set() {
    let bounds = escape_bounds(runs()).unwrap();
    assert_eq!(bounds.len(), 6, "the six noise-free escape runs");
    assert_reproduced(&check_b2_hcw(outcome("B2 HCW"), &bounds).unwrap());
}
