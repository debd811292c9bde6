//! Regression of the pigeon-flock reproduction (H. Qiu, Q. Zhou, C. Sun, X. Wang, Y. Feng, "Distributed
//! Satellite Formation Based on Swarm Intelligence of Pigeon Flocks", IEEE conference paper) on seed 1,
//! shortened: P6 (obstacle clearance ≥ R_L^4 = 10 m, the engine's continuous monitor) and P7 (pair
//! separation in the pigeon plane ≥ 15 m at every tick) for Q1 (`pigeon-switching`) and Q2
//! (`pigeon-baseline`), and the whole Q1 run bitwise identical on 1 and 2 threads.
//!
//! Length: [`SHORT_S`] = 800 s. The cluster starts 700–1010 m below the target in z, behind both
//! obstacles. "Past the obstacles" = every satellite nearer the target (in the plane) than the nearest
//! point of every obstacle's detection sphere (208 m here). With no absolute damping the group keeps
//! the angular momentum of its centroid about the target (the target pull is central, the formation
//! and alignment terms internal), so it circles the target at 300–600 m, through obstacle 1's
//! detection zone, for a long time: measured on seed 1, Q1 is past at 169.5 s and Q2 only at 699 s.
//! 800 s covers both first passages with margin, and the test asserts the passage happened within the
//! run rather than trusting those numbers. (Later swings back near obstacle 1 are covered by the
//! full-length report, not here.)

use satflock_cli::validate::pigeon::{run_job, Job, Run, P7_MIN_SEPARATION_M, Q1, Q2};

/// Shortened length \[s\] (see the module documentation).
const SHORT_S: f64 = 800.0;

fn job(builtin: &'static str) -> Job {
    Job {
        builtin,
        seed: 1,
        duration_s: Some(SHORT_S),
        damping_per_s: None,
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
    let name = run.job.builtin;
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
        run.min_separation_plane_m >= P7_MIN_SEPARATION_M,
        "{name} P7: separation {:.3} m < {P7_MIN_SEPARATION_M} m",
        run.min_separation_plane_m
    );
    eprintln!(
        "{name} seed 1, {SHORT_S} s: past the obstacles at {passed:.1} s, clearance {clearance:.3} m, separation {:.3} m",
        run.min_separation_plane_m
    );
}

#[test]
fn regress_pigeon_p6_p7_q2_seed1() {
    check_p6_p7(&run_on(1, &job(Q2)));
}

/// P6 and P7 on Q1, and the same Q1 run on 1 and 2 threads: every measurement and the final states
/// bitwise identical.
#[test]
fn regress_pigeon_p6_p7_q1_seed1_and_thread_determinism() {
    let one = run_on(1, &job(Q1));
    let two = run_on(2, &job(Q1));
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
