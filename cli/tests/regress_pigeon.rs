//! Regression of the pigeon-flock reproduction (H. Qiu, Q. Zhou, C. Sun, X. Wang, Y. Feng, "Distributed
//! Satellite Formation Based on Swarm Intelligence of Pigeon Flocks", IEEE conference paper),
//! shortened: P6 (obstacle clearance ≥ R_L^4 = 10 m, the engine's continuous monitor) and P7 (pair
//! separation in the pigeon plane ≥ the gate of `validation/pigeon.toml` at every tick) for Q1
//! (`pigeon-switching`, R_c^1 = 130 m) over seeds 1–20 and Q2 (`pigeon-baseline`, which draws no
//! pattern: one seed), and the whole Q1 run bitwise identical on 1 and 2 threads.
//!
//! Length: [`SHORT_S`] = 2000 s. The cluster starts 700–1010 m below the target in z, behind both
//! obstacles. "Past the obstacles" = every satellite nearer the target (in the plane) than the nearest
//! point of every obstacle's detection sphere (208 m here). With no absolute damping in the y–z plane
//! (the alignment term damps only relative velocities; the target acts through a position potential)
//! the group swings through the target region with slowly decaying amplitude, crossing obstacle 1's
//! detection zone again on the way; at R_c^1 = 130 m the first passage of every satellite past the
//! obstacles came at 504–1315 s (5–95 % over seeds 1–20 in `satflock validate pigeon`), so the window
//! is 2000 s, and the test asserts the passage happened rather than trusting those numbers. P7's
//! collisions at the former R_c^1 = 120 m came at 91–96 s (satellite 0 unlinked at the start), inside
//! the window. Later swings are covered by the full-length report (`satflock validate pigeon`).

use satflock_cli::validate::pigeon::{p7_min_separation_m, run_job, Job, Run, Q1, Q2};

/// Shortened length \[s\] (see the module documentation).
const SHORT_S: f64 = 2000.0;

fn job(builtin: &'static str, seed: u64) -> Job {
    Job {
        builtin,
        seed,
        duration_s: Some(SHORT_S),
        damping_per_s: None,
        egalitarian_range_m: None,
    }
}

fn run_on(threads: usize, job: &Job) -> Run {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("pool")
        .install(|| run_job(job))
        .expect("run")
}

fn check_p6_p7(run: &Run) {
    let name = format!("{} seed {}", run.job.builtin, run.job.seed);
    let gate = p7_min_separation_m().expect("validation/pigeon.toml");
    let passed = run.passed_obstacles_s.unwrap_or_else(|| {
        panic!("{name}: the group did not get past the obstacles in {SHORT_S} s")
    });
    assert!(passed < SHORT_S, "{name}: passed at {passed} s");
    let (clearance, satellite, obstacle, t) = run
        .min_clearance
        .unwrap_or_else(|| panic!("{name}: no obstacle observation"));
    assert!(
        clearance >= 10.0,
        "{name} P6: clearance {clearance:.3} m < R_L^4 = 10 m (satellite {satellite}, obstacle {obstacle}, {t:.1} s)"
    );
    assert!(
        run.min_separation_plane_m >= gate,
        "{name} P7: separation {:.3} m < {gate} m",
        run.min_separation_plane_m
    );
    eprintln!(
        "{name}, {SHORT_S} s: past the obstacles at {passed:.1} s, clearance {clearance:.3} m, separation {:.3} m",
        run.min_separation_plane_m
    );
}

#[test]
fn regress_pigeon_p6_p7_q2_seed1() {
    check_p6_p7(&run_on(1, &job(Q2, 1)));
}

/// P6 and P7 on Q1 over every seed of the report (2..=20 here; seed 1 below), two runs at a time.
#[test]
fn regress_pigeon_p6_p7_q1_seeds_2_to_20() {
    let jobs: Vec<Job> = (2..=20).map(|seed| job(Q1, seed)).collect();
    let runs = satflock_cli::validate::pigeon::run_jobs(&jobs).expect("runs");
    assert_eq!(runs.len(), 19);
    for run in &runs {
        check_p6_p7(run);
    }
}

/// P6 and P7 on Q1, and the same Q1 run on 1 and 2 threads: every measurement and the final states
/// bitwise identical.
#[test]
fn regress_pigeon_p6_p7_q1_seed1_and_thread_determinism() {
    let one = run_on(1, &job(Q1, 1));
    let two = run_on(2, &job(Q1, 1));
    assert_eq!(one.final_states.len(), 10);
    for (a, b) in one.final_states.iter().zip(&two.final_states) {
        for k in 0..3 {
            assert_eq!(a.0[k].to_bits(), b.0[k].to_bits(), "position");
            assert_eq!(a.1[k].to_bits(), b.1[k].to_bits(), "velocity");
        }
    }
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&one.mean_distance_m), bits(&two.mean_distance_m));
    assert_eq!(
        bits(&one.mean_target_distance_m),
        bits(&two.mean_target_distance_m)
    );
    assert_eq!(bits(&one.order_parameter), bits(&two.order_parameter));
    assert_eq!(bits(&one.delta_v_mps), bits(&two.delta_v_mps));
    assert_eq!(
        one.min_separation_plane_m.to_bits(),
        two.min_separation_plane_m.to_bits()
    );
    assert_eq!(one.switches, two.switches);
    assert_eq!(one, two);
    check_p6_p7(&one);
}
