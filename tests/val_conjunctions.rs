//! Validation of the conjunction monitor against a brute-force fine-step computation independent of it:
//! the same swarm advanced in 0.05 s steps (the engine's own truth states, read between steps), every
//! pair's distance sampled there, each local minimum of the samples below the threshold refined by the
//! parabola through the squared distances of its three samples (exact for straight relative motion,
//! which the motion is over 0.1 s to far better than the tolerances). Threats are straight lines, so their
//! positions come from the scenario's numbers written out here. Also: the encounters are the same bytes
//! on 1 and 2 threads, and the RTN relative state is the inertial one rotated.

use std::path::Path;

use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};
use satflock::conjunction::{Encounter, Secondary};
use satflock::run::build_simulation;
use satflock::scenario::Scenario;
use satflock::swarm::NullRecorder;

/// The threshold of the test scenario \[m\].
const THRESHOLD_M: f64 = 60.0;
/// Its control period (the monitor's segments) \[s\].
const PERIOD_S: f64 = 10.0;
/// The brute force's sampling step \[s\].
const FINE_S: f64 = 0.05;
/// The run's length \[s\].
const DURATION_S: f64 = 1200.0;

/// The threat: at t = 0 at this Hill position \[m\] (60 m behind satellite 0's start, 20 m above
/// it), moving at this Hill velocity \[m/s\].
const THREAT_P0: [f64; 3] = [THREAT_AIM[0], THREAT_AIM[1] - 60.0, THREAT_AIM[2] + 20.0];
/// Satellite 0's initial Hill position \[m\] (set in [`scenario`]).
const THREAT_AIM: [f64; 3] = [0.0, 0.0, 0.0];
const THREAT_V: [f64; 3] = [0.0, 0.6, 0.0];

/// Sixteen satellites in a 120 m ball (satellite 0 at the centre) with velocities of about 0.15 m/s (free drift under J2), and one
/// threat crossing the ball along-track.
fn scenario() -> Scenario {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut states = String::new();
    for k in 0..16 {
        let mut p: Vec<f64> = (0..3).map(|_| rng.random_range(-120.0..120.0)).collect();
        if k == 0 {
            p = THREAT_AIM.to_vec();
        }
        let v: Vec<f64> = (0..3).map(|_| rng.random_range(-0.15..0.15)).collect();
        states.push_str(&format!(
            "[{:?}, {:?}, {:?}, {:?}, {:?}, {:?}],",
            p[0], p[1], p[2], v[0], v[1], v[2]
        ));
    }
    let text = format!(
        "name = \"conjunctions\"\nseed = 1\nduration_s = {DURATION_S:?}\nrecord_interval_s = {DURATION_S:?}\n\
         [dynamics]\nmodel = \"j2\"\nintegrator = \"rk4\"\nstep_s = 1.0\n\
         [reference]\naltitude_m = 600e3\ninclination_deg = 98.0\n\
         [control]\nmode = \"sampled\"\nperiod_s = {PERIOD_S:?}\n\
         [satellites]\ncount = 16\nmass_kg = 5.0\nradius_m = 0.1\n\
         initial = {{ distribution = \"list\", frame = \"hill\", states = [{states}] }}\n\
         [sensing]\nrange_m = 100.0\n[law]\nname = \"none\"\n\
         [[threats]]\nname = \"crossing\"\ndanger_radius_m = 1.0\nposition_hill_m = {THREAT_P0:?}\n\
         velocity_hill_mps = {THREAT_V:?}\nat_time_s = 0.0\n\
         [conjunctions]\nthreshold_m = {THRESHOLD_M:?}\n[output]\ntrajectory = false\n"
    );
    Scenario::from_toml(&text, "test:conjunctions", Path::new(".")).unwrap()
}

/// The monitor's encounters over the whole run.
fn monitored() -> Vec<Encounter> {
    let mut sim = build_simulation(&scenario()).unwrap();
    sim.run(&mut NullRecorder, &mut |_| {}).unwrap();
    sim.conjunction_monitor().unwrap().encounters().to_vec()
}

/// A brute-force minimum: (primary, secondary, TCA \[s\], miss distance \[m\]).
type Minimum = (usize, Secondary, f64, f64);

/// A pair's relative position (secondary − primary, Hill frame, m) at sample k.
type Relative<'a> = Box<dyn Fn(usize) -> [f64; 3] + 'a>;

/// Every local minimum below the threshold of every pair's distance sampled every [`FINE_S`].
fn brute_force() -> Vec<Minimum> {
    let mut sim = build_simulation(&scenario()).unwrap();
    let mut samples: Vec<(f64, Vec<[f64; 3]>)> = Vec::new();
    let steps = (DURATION_S / FINE_S).round() as usize;
    for k in 0..=steps {
        let t = k as f64 * FINE_S;
        if k > 0 {
            sim.advance_to(t, &mut NullRecorder).unwrap();
        }
        let p = sim
            .states_hill()
            .iter()
            .map(|s| s.position_m.into())
            .collect();
        samples.push((t, p));
    }
    let n = samples[0].1.len();
    let threat = |t: f64| -> [f64; 3] { std::array::from_fn(|a| THREAT_P0[a] + THREAT_V[a] * t) };
    let mut pairs: Vec<(usize, Secondary, Relative<'_>)> = Vec::new();
    for i in 0..n {
        for j in i + 1..n {
            let s = &samples;
            pairs.push((
                i,
                Secondary::Satellite(j),
                Box::new(move |k| std::array::from_fn(|a| s[k].1[j][a] - s[k].1[i][a])),
            ));
        }
        let s = &samples;
        pairs.push((
            i,
            Secondary::Threat(0),
            Box::new(move |k| std::array::from_fn(|a| threat(s[k].0)[a] - s[k].1[i][a])),
        ));
    }
    let mut minima = Vec::new();
    for (primary, secondary, relative) in &pairs {
        let d2: Vec<f64> = (0..samples.len())
            .map(|k| relative(k).iter().map(|x| x * x).sum())
            .collect();
        for k in 1..d2.len() - 1 {
            if d2[k] < d2[k - 1] && d2[k] <= d2[k + 1] {
                // The parabola through (−h, d2[k−1]), (0, d2[k]), (h, d2[k+1]).
                let (a, b, c) = (d2[k - 1], d2[k], d2[k + 1]);
                let curvature = a - 2.0 * b + c;
                let offset = 0.5 * (a - c) / curvature;
                let tca = samples[k].0 + offset * FINE_S;
                let miss = (b - 0.25 * (a - c) * offset).max(0.0).sqrt();
                if miss < THRESHOLD_M {
                    minima.push((*primary, *secondary, tca, miss));
                }
            }
        }
    }
    minima.sort_by(|x, y| x.2.total_cmp(&y.2));
    minima
}

#[test]
fn encounters_match_a_brute_force_fine_step_computation() {
    let found = monitored();
    let expected = brute_force();
    assert!(
        expected.len() >= 4 && expected.iter().any(|m| matches!(m.1, Secondary::Threat(_))),
        "the scenario should hold several encounters, one with the threat: {expected:?}"
    );
    assert_eq!(
        found.len(),
        expected.len(),
        "monitor: {:?}\nbrute force: {expected:?}",
        found
            .iter()
            .map(|e| (e.primary, e.secondary, e.tca_s, e.miss_distance_m))
            .collect::<Vec<_>>()
    );
    for (e, (primary, secondary, tca_s, miss_m)) in found.iter().zip(&expected) {
        assert_eq!((e.primary, e.secondary), (*primary, *secondary));
        assert!(
            (e.tca_s - tca_s).abs() < 1e-3,
            "TCA {} s against {tca_s} s",
            e.tca_s
        );
        assert!(
            (e.miss_distance_m - miss_m).abs() < 1e-4,
            "miss distance {} m against {miss_m} m",
            e.miss_distance_m
        );
    }
}

#[test]
fn the_rtn_relative_state_is_the_inertial_one_in_the_primarys_axes() {
    for e in monitored() {
        let (p, s) = (e.primary_eme2000, e.secondary_eme2000);
        let dr: Vec<f64> = (0..3).map(|a| s[a] - p[a]).collect();
        let dv: Vec<f64> = (0..3).map(|a| s[3 + a] - p[3 + a]).collect();
        let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        // Rotations keep norms: |dr| is the miss distance, |dv| the relative speed.
        assert!((norm(&dr) - e.miss_distance_m).abs() < 1e-6, "{e:?}");
        assert!((norm(&e.relative_position_rtn_m) - e.miss_distance_m).abs() < 1e-6);
        assert!((norm(&dv) - e.relative_speed_mps).abs() < 1e-12);
        assert!((norm(&e.relative_velocity_rtn_mps) - e.relative_speed_mps).abs() < 1e-9);
        // The radial component: dr · r / |r|.
        let radial = (0..3).map(|a| dr[a] * p[a]).sum::<f64>() / norm(&p[..3]);
        assert!((radial - e.relative_position_rtn_m[0]).abs() < 1e-6);
        // At a minimum of the distance the relative velocity is perpendicular to the relative position
        // (to within the inertial velocity's frame-rotation term ω × dr, ~1e-3 · dr).
        let along: f64 = (0..3).map(|a| dr[a] * dv[a]).sum::<f64>() / e.miss_distance_m;
        assert!(along.abs() < 2e-3 * e.miss_distance_m, "{e:?}");
    }
}

#[test]
fn encounters_are_the_same_bytes_on_one_and_two_threads() {
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(monitored)
    };
    let (one, two) = (on(1), on(2));
    assert!(!one.is_empty());
    assert_eq!(format!("{one:?}"), format!("{two:?}"));
}
