//! Condition events (issue 30): an event whose `condition` on the swarm's truth holds fires at the
//! tick an independent brute-force evaluation says (the minimum separation over all pairs, the
//! distance to the threat, the uniformity L, the pairs' closest approaches, all from the states at
//! each tick), at the same tick and with the same
//! value on 1 and 2 threads; `stop-run` ends the run with `summary.json` `status = "stopped"`
//! naming the event, with every file valid; `record-snapshot` adds a row; bad conditions are
//! refused naming their key.

use std::path::Path;

use satflock::run::{build_simulation, run_scenario};
use satflock::scenario::Scenario;
use satflock::swarm::Firing;

/// Six satellites in a 60 m sphere at rest in the LVLH frame, free drift under J2 (the radial
/// offsets drift along-track, so pairs close and open), control ticks every 10 s.
fn drifting(extra: &str) -> Scenario {
    let text = format!(
        "name = \"drift-events\"\nseed = 7\nduration_s = 3000.0\nrecord_interval_s = 100.0\n\
         [reference]\naltitude_m = 500e3\ninclination_deg = 97.4\n\
         [control]\nmode = \"sampled\"\nperiod_s = 10.0\n\
         [satellites]\ncount = 6\nmass_kg = 5.0\n\
         initial = {{ distribution = \"sphere\", radius_m = 60.0 }}\n\
         [law]\nname = \"none\"\n{extra}"
    );
    Scenario::from_toml(&text, "drift-events.toml", Path::new(".")).unwrap()
}

/// Brute force over all pairs: the smallest distance between two live satellites \[m\].
fn min_pair_distance_m(positions: &[nalgebra::Vector3<f64>]) -> f64 {
    let mut best = f64::INFINITY;
    for i in 0..positions.len() {
        for j in i + 1..positions.len() {
            best = best.min((positions[i] - positions[j]).norm());
        }
    }
    best
}

/// Steps a simulation of `scenario` tick by tick and returns, for each tick end (tick 0 = t = 0),
/// `f` of the truth Hill positions and the time.
fn per_tick(
    scenario: &Scenario,
    f: impl Fn(&[nalgebra::Vector3<f64>], f64) -> f64,
) -> Vec<(u64, f64, f64)> {
    let mut sim = build_simulation(scenario).unwrap();
    let positions = |sim: &satflock::swarm::Simulation| -> Vec<nalgebra::Vector3<f64>> {
        sim.states_hill().iter().map(|s| s.position_m).collect()
    };
    let mut out = vec![(0, 0.0, f(&positions(&sim), 0.0))];
    let mut tick = 0;
    while sim.time_s() < scenario.file.duration_s - 1e-9 {
        sim.step().unwrap();
        tick += 1;
        out.push((tick, sim.time_s(), f(&positions(&sim), sim.time_s())));
    }
    out
}

/// The firings of `scenario` run on `threads` threads (through the scheduler of a full run).
fn firings_on(scenario: &Scenario, threads: usize) -> Vec<Firing> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let mut sim = build_simulation(scenario).unwrap();
        sim.run(&mut satflock::swarm::NullRecorder, &mut |_| {})
            .unwrap();
        sim.fired_events().to_vec()
    })
}

#[test]
fn val_min_separation_event_fires_at_the_brute_force_tick_on_1_and_2_threads() {
    let reference = per_tick(&drifting(""), |p, _| min_pair_distance_m(p));
    let initial_m = reference[0].2;
    let closest_m = reference.iter().map(|r| r.2).fold(f64::INFINITY, f64::min);
    assert!(
        closest_m < 0.8 * initial_m,
        "the drift must close a pair (initial {initial_m} m, closest {closest_m} m)"
    );
    let threshold_m = 0.5 * (initial_m + closest_m);
    let (tick, time_s, value_m) = *reference
        .iter()
        .find(|r| r.2 < threshold_m)
        .expect("crosses");
    let scenario = drifting(&format!(
        "[[events]]\ncondition = {{ min_separation_below_m = {threshold_m} }}\naction = \"stop-run\"\n"
    ));
    let one = firings_on(&scenario, 1);
    let two = firings_on(&scenario, 2);
    assert_eq!(one, two, "1 and 2 threads disagree");
    assert_eq!(one.len(), 1, "{one:?}");
    let f = &one[0];
    assert_eq!((f.event, f.tick, f.action), (0, tick, "stop-run"), "{f:?}");
    assert!((f.time_s - time_s).abs() < 1e-9, "{f:?} vs t = {time_s}");
    assert_eq!(f.trigger, "min_separation_below_m");
    // The engine's exact separation and the brute force agree to rounding.
    let value = f.value.unwrap();
    assert!(
        (value - value_m).abs() <= 1e-9 * value_m,
        "{value} vs {value_m}"
    );
    assert_eq!(
        one[0].value.map(f64::to_bits),
        two[0].value.map(f64::to_bits)
    );
}

#[test]
fn val_repeating_condition_fires_at_each_brute_force_crossing() {
    // Every crossing below the threshold (after the separation came back above it) fires a
    // record-snapshot; the brute force counts the same downward crossings at the same ticks. Two
    // orbits, and the threshold the separation crosses most often.
    let mut base = drifting("");
    base.file.duration_s = 12000.0;
    let reference = per_tick(&base, |p, _| min_pair_distance_m(p));
    let crossings = |threshold_m: f64| {
        let mut ticks = Vec::new();
        let mut armed = true;
        for &(tick, _, d) in &reference {
            if armed && d < threshold_m {
                ticks.push(tick);
                armed = false;
            } else if !armed && d >= threshold_m {
                armed = true;
            }
        }
        ticks
    };
    let threshold_m = reference
        .iter()
        .map(|r| r.2 * (1.0 + 1e-6))
        .max_by_key(|&t| crossings(t).len())
        .unwrap();
    let expected = crossings(threshold_m);
    let mut scenario = drifting(&format!(
        "[[events]]\ncondition = {{ min_separation_below_m = {threshold_m}, repeat = true }}\n\
         action = \"record-snapshot\"\n"
    ));
    scenario.file.duration_s = 12000.0;
    assert!(expected.len() >= 2, "one crossing only: {expected:?}");
    let fired: Vec<u64> = firings_on(&scenario, 2).iter().map(|f| f.tick).collect();
    assert_eq!(fired, expected);
}

#[test]
fn val_threat_within_fires_at_the_brute_force_tick() {
    // A threat crossing the swarm at 2 m/s along-track from 2 km away: the distance to the nearest
    // satellite decreases monotonically before its pass, so the continuous closest approach over a
    // segment is its end point, the distance at the tick.
    let threat = "[[threats]]\ndanger_radius_m = 5.0\nposition_hill_m = [0.0, 2000.0, 0.0]\n\
                  velocity_hill_mps = [0.0, -2.0, 0.0]\n";
    let line = |t: f64| nalgebra::Vector3::new(0.0, 2000.0 - 2.0 * t, 0.0);
    let reference = per_tick(&drifting(threat), |p, t| {
        p.iter()
            .map(|x| (x - line(t)).norm())
            .fold(f64::INFINITY, f64::min)
    });
    let within_m = 400.0;
    let (tick, time_s, _) = *reference
        .iter()
        .find(|r| r.2 <= within_m)
        .expect("the threat comes within 400 m");
    let scenario = drifting(&format!(
        "{threat}[[events]]\ncondition = {{ threat_within_m = {within_m} }}\n\
         action = \"threat-warning\"\nthreat = 0\nactive = true\n"
    ));
    let one = firings_on(&scenario, 1);
    assert_eq!(one, firings_on(&scenario, 2));
    assert_eq!(one.len(), 1, "{one:?}");
    assert_eq!(one[0].tick, tick, "{:?}", one[0]);
    assert!((one[0].time_s - time_s).abs() < 1e-9);
    assert!(one[0].value.unwrap() <= within_m);
}

#[test]
fn val_conjunction_event_fires_at_the_tick_of_the_brute_force_minimum() {
    // Brute force at the ticks (the monitor's segments): every pair's sampled distance; its local
    // minima. The threshold lies halfway between the two smallest minima, so exactly one encounter is
    // below it; its closest approach lies between the ticks either side of the sampled minimum k,
    // and the monitor finds it at the end of the segment holding it: tick k or k + 1. The refined
    // miss distance is at most the sampled one, and at least that minus the pair's relative travel
    // over one period (the relative speed at the minimum bounds it, with a margin for its change).
    let mut base = drifting("");
    base.file.duration_s = 6000.0;
    let period_s = 10.0;
    let mut sim = build_simulation(&base).unwrap();
    let mut ticks: Vec<Vec<satflock::orbit::RelativeStateHill>> = vec![sim.states_hill()];
    while sim.time_s() < base.file.duration_s - 1e-9 {
        sim.step().unwrap();
        ticks.push(sim.states_hill());
    }
    let n = ticks[0].len();
    let distance =
        |k: usize, i: usize, j: usize| (ticks[k][i].position_m - ticks[k][j].position_m).norm();
    // (sampled distance, tick, pair) of every interior local minimum.
    let mut minima: Vec<(f64, usize, usize, usize)> = Vec::new();
    for i in 0..n {
        for j in i + 1..n {
            for k in 1..ticks.len() - 1 {
                let d = distance(k, i, j);
                if distance(k - 1, i, j) > d && d <= distance(k + 1, i, j) {
                    minima.push((d, k, i, j));
                }
            }
        }
    }
    minima.sort_by(|a, b| a.0.total_cmp(&b.0));
    assert!(minima.len() >= 2, "too few close approaches: {minima:?}");
    let (closest_m, k, i, j) = minima[0];
    let threshold_m = 0.5 * (minima[0].0 + minima[1].0);
    assert!(
        minima[1].0 - closest_m > 0.1,
        "the two smallest minima are too close to separate: {minima:?}"
    );
    let relative_speed_mps = (ticks[k][i].velocity_mps - ticks[k][j].velocity_mps).norm();
    let mut scenario = drifting(&format!(
        "[conjunctions]\nthreshold_m = {threshold_m}\n\
         [[events]]\ncondition = {{ conjunction = true, repeat = true }}\naction = \"record-snapshot\"\n"
    ));
    scenario.file.duration_s = base.file.duration_s;
    let one = firings_on(&scenario, 1);
    let two = firings_on(&scenario, 2);
    assert_eq!(one, two, "1 and 2 threads disagree");
    assert_eq!(one.len(), 1, "one encounter below the threshold: {one:?}");
    let f = &one[0];
    assert_eq!(f.trigger, "conjunction");
    assert!(
        f.tick == k as u64 || f.tick == k as u64 + 1,
        "fired at tick {} (t = {} s), the sampled minimum is at tick {k}",
        f.tick,
        f.time_s
    );
    assert!((f.time_s - period_s * f.tick as f64).abs() < 1e-9, "{f:?}");
    let miss_m = f.value.unwrap();
    assert!(
        miss_m <= closest_m + 1e-9,
        "{miss_m} vs sampled {closest_m}"
    );
    assert!(
        miss_m >= closest_m - 1.5 * relative_speed_mps * period_s,
        "{miss_m} vs sampled {closest_m}, relative speed {relative_speed_mps} m/s"
    );
}

#[test]
fn val_stop_run_ends_the_run_with_valid_files() {
    let scenario = drifting(
        "[[events]]\ntime_s = 250.0\naction = \"record-snapshot\"\n\
         [[events]]\ncondition = { satellites_lost_at_least = 1 }\naction = \"stop-run\"\n\
         [[events]]\ntime_s = 1230.0\naction = \"remove-satellite\"\nsatellite = 3\n",
    );
    let dir = std::env::temp_dir().join(format!("satflock-stop-run-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let summary = run_scenario(&scenario, &dir, &mut |_| {}).unwrap();
    assert!((summary.simulated_s - 1230.0).abs() < 1e-9);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(json["status"], "stopped");
    assert_eq!(json["stopped_by"]["event"], 1);
    assert_eq!(json["stopped_by"]["key"], "events[1]");
    assert_eq!(json["stopped_by"]["time_s"], 1230.0);
    assert_eq!(json["stopped_by"]["value"], 1.0);
    // The log: the snapshot at 250 s, the removal and the stop at 1230 s (timed events first).
    let lines: Vec<serde_json::Value> = std::fs::read_to_string(dir.join("events.jsonl"))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let log: Vec<(u64, f64, &str)> = lines
        .iter()
        .map(|l| {
            (
                l["event"].as_u64().unwrap(),
                l["time_s"].as_f64().unwrap(),
                l["action"].as_str().unwrap(),
            )
        })
        .collect();
    assert_eq!(
        log,
        [
            (0, 250.0, "record-snapshot"),
            (2, 1230.0, "remove-satellite"),
            (1, 1230.0, "stop-run")
        ]
    );
    assert_eq!(json["events"].as_array().unwrap().len(), 3);
    // metrics.csv: the cadence up to the stop, the extra snapshot at 250 s and the last at 1230 s.
    let metrics = std::fs::read_to_string(dir.join("metrics.csv")).unwrap();
    let times: Vec<f64> = metrics
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect();
    let mut expected: Vec<f64> = (0..=12).map(|k| k as f64 * 100.0).collect();
    expected.insert(3, 250.0);
    expected.push(1230.0);
    assert_eq!(times, expected);
    // Every table reads back whole.
    satflock::output::RunData::read(&dir).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn regress_bad_conditions_are_refused_naming_the_key() {
    let cases = [
        (
            "[[events]]\ncondition = { min_separation_below_m = -5.0 }\naction = \"stop-run\"\n",
            "events[0].condition.min_separation_below_m",
            "allowed: finite, > 0",
        ),
        (
            "[[events]]\ntime_s = 10.0\ncondition = { min_separation_below_m = 5.0 }\naction = \"stop-run\"\n",
            "events[0].condition",
            "not both",
        ),
        (
            "[[events]]\ncondition = { law_outcome = \"no_such_outcome\", above = 1.0 }\naction = \"stop-run\"\n",
            "events[0].condition.law_outcome",
            "`no_such_outcome` is not an outcome",
        ),
        (
            "[[events]]\ncondition = { threat_within_m = 100.0 }\naction = \"stop-run\"\n",
            "events[0].condition.threat_within_m",
            "no [[threats]]",
        ),
        (
            "[[events]]\ncondition = { formation_reached = true }\naction = \"stop-run\"\n",
            "events[0].condition.formation_reached",
            "uniformity_l",
        ),
        (
            "[[events]]\ncondition = { min_separation_below_m = 5.0, hysteresis = 1.0 }\naction = \"stop-run\"\n",
            "events[0].condition.hysteresis",
            "hysteresis_m",
        ),
        (
            "[[events]]\ncondition = { satellites_lost_at_least = 9 }\naction = \"stop-run\"\n",
            "events[0].condition.satellites_lost_at_least",
            "allowed: 1..=6",
        ),
        (
            "[[events]]\ncondition = { min_separation_below_m = 5.0, repeat = true }\n\
             action = \"switch-law\"\nlaw = { name = \"none\" }\n",
            "events[0].condition.repeat",
            "fires once",
        ),
        (
            "[[events]]\naction = \"stop-run\"\n",
            "events[0].time_s",
            "missing",
        ),
        (
            "[[events]]\ncondition = { conjunction = true }\naction = \"stop-run\"\n",
            "events[0].condition.conjunction",
            "no conjunction monitor",
        ),
        (
            "[conjunctions]\nthreshold_m = 5.0\n\
             [[events]]\ncondition = { conjunction = false }\naction = \"stop-run\"\n",
            "events[0].condition.conjunction",
            "allowed: true",
        ),
        (
            "[conjunctions]\nthreshold_m = 5.0\n\
             [[events]]\ncondition = { conjunction = true, hysteresis_m = 1.0 }\naction = \"stop-run\"\n",
            "events[0].condition.hysteresis_m",
            "goes with a distance condition",
        ),
    ];
    for (extra, key, needle) in cases {
        let e = match drifting(extra).prepare() {
            Ok(_) => panic!("accepted: {extra}"),
            Err(e) => e.to_string(),
        };
        assert!(
            e.contains(&format!("key `{key}`")) && e.contains(needle),
            "{extra}: {e}"
        );
    }
}

/// The uniformity L of Gao's five elements, brute force: L = Σ m_i³ / M³ with m_i half the distance
/// to i's nearest neighbour and M = ½ max over pairs of (|r_i − r_j| + m_i + m_j).
fn uniformity_l(p: &[nalgebra::Vector3<f64>]) -> f64 {
    let n = p.len();
    let m: Vec<f64> = (0..n)
        .map(|i| {
            0.5 * (0..n)
                .filter(|&j| j != i)
                .map(|j| (p[i] - p[j]).norm())
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    let mut big_m = 0.0f64;
    for i in 0..n {
        for j in i + 1..n {
            big_m = big_m.max(0.5 * ((p[i] - p[j]).norm() + m[i] + m[j]));
        }
    }
    m.iter().map(|x| x.powi(3)).sum::<f64>() / big_m.powi(3)
}

#[test]
fn val_formation_reached_fires_when_the_brute_force_uniformity_is_within_tolerance() {
    let reference = per_tick(&drifting(""), |p, _| uniformity_l(p));
    // A target the drift reaches: L at two thirds of the run, with a tolerance of 1 % of it.
    let target = reference[2 * reference.len() / 3].2;
    let tolerance = 0.01 * target;
    let (tick, _, l) = *reference
        .iter()
        .find(|r| (r.2 - target).abs() <= tolerance)
        .expect("reached");
    let scenario = drifting(&format!(
        "[[events]]\ncondition = {{ formation_reached = true, uniformity_l = {target}, \
         uniformity_tolerance = {tolerance} }}\naction = \"stop-run\"\n"
    ));
    let fired = firings_on(&scenario, 2);
    assert_eq!(fired, firings_on(&scenario, 1));
    assert_eq!(fired.len(), 1, "{fired:?}");
    assert_eq!(
        (fired[0].tick, fired[0].trigger),
        (tick, "formation_reached")
    );
    let value = fired[0].value.unwrap();
    assert!((value - l).abs() <= 1e-9 * l, "{value} vs {l}");
}
