//! Real objects as threats and obstacles (issue 27): an object from a TLE or OMM propagated by SGP4
//! during the run, or from an EME2000 state by the truth dynamics, placed in the Hill frame at every
//! segment end. Checked against things independent of the placement: the distance between two objects
//! does not depend on the frame (so the Hill distance of a satellite to an SGP4 threat equals the
//! EME2000 distance from SGP4 run directly by the `sgp4` crate), an object started on the reference
//! orbit stays at the LVLH origin, and the continuous closest approach equals a brute-force minimum
//! over a dense sampling of the same run.

use nalgebra::Vector3;
use satflock::environment::Motion;
use satflock::orbit::CartesianState;
use satflock::run::build_simulation;
use satflock::scenario::Scenario;
use satflock::swarm::NullRecorder;

const ISS_TLE: [&str; 2] = [
    "1 25544U 98067A   08264.51782528 -.00002182  00000-0 -11606-4 0  2927",
    "2 25544  51.6416 247.4627 0006703 130.5360 325.0288 15.72125391563537",
];

/// Four satellites within 300 m of a 400 km reference, epoch 35 min after the ISS element set's.
fn scenario(extra: &str) -> String {
    format!(
        "name = \"tracked\"\nseed = 5\nduration_s = 600.0\nrecord_interval_s = 60.0\n\
         epoch_utc = \"2008-09-20T13:00:00Z\"\n\
         [dynamics]\nmodel = \"j2\"\nintegrator = \"rk4\"\nstep_s = 1.0\n\
         [control]\nmode = \"sampled\"\nperiod_s = 10.0\n\
         [reference]\nstate_eme2000 = [6778137.0, 0.0, 0.0, 0.0, 4763.0, 6010.0]\n\
         [satellites]\ncount = 4\nmass_kg = 6.0\n\
         initial = {{ distribution = \"list\", states = [[0.0, 0.0, 0.0, 0.0, 0.0, 0.0], \
         [100.0, -50.0, 10.0, 0.0, -0.2, 0.0], [-60.0, 200.0, -30.0, 0.0, 0.13, 0.0], \
         [20.0, -300.0, 60.0, 0.0, 0.0, 0.0]] }}\n\
         [law]\nname = \"none\"\n{extra}"
    )
}

fn load(text: &str) -> Scenario {
    Scenario::from_toml(text, "tracked.toml", std::path::Path::new(".")).unwrap()
}

/// The scenario's refusal, as text (`None`: it is accepted).
fn refusal(text: &str) -> Option<String> {
    Scenario::from_toml(text, "tracked.toml", std::path::Path::new("."))
        .and_then(|s| s.prepare().map(|_| ()))
        .err()
        .map(|e| e.to_string())
}

fn simulation(text: &str) -> satflock::swarm::Simulation {
    build_simulation(&load(text)).unwrap()
}

/// The ISS's EME2000 position at `t_s` after the scenario epoch, by the `sgp4` crate directly (WGS-72,
/// AFSPC mode, as the catalogue's element sets are made; WGS-84 constants move it by about 20 m).
fn iss_eme2000_m(t_s: f64) -> Vector3<f64> {
    let elements =
        sgp4::Elements::from_tle(None, ISS_TLE[0].as_bytes(), ISS_TLE[1].as_bytes()).unwrap();
    let constants = sgp4::Constants::from_elements_afspc_compatibility_mode(&elements).unwrap();
    // The element set's epoch is 2008 day 264.51782528 UTC; the scenario's 2008-09-20T13:00:00Z.
    let epoch_day = 264.51782528_f64;
    let scenario_day = 264.0 + 13.0 / 24.0;
    let minutes = (scenario_day - epoch_day) * 1440.0 + t_s / 60.0;
    let p = constants
        .propagate_afspc_compatibility_mode(sgp4::MinutesSinceEpoch(minutes))
        .unwrap();
    let teme = CartesianState::new(
        Vector3::from(p.position) * 1e3,
        Vector3::from(p.velocity) * 1e3,
    );
    let at = satflock::time::at(
        satflock::time::parse_epoch_utc("2008-09-20T13:00:00Z").unwrap(),
        t_s,
    );
    satflock::orbit_files::teme_to_eme2000(at, &teme).position_m
}

#[test]
fn an_sgp4_threat_is_as_far_from_each_satellite_in_hill_as_in_eme2000() {
    let extra = format!(
        "[[threats]]\nname = \"iss\"\ndanger_radius_m = 50.0\ntle = [\"{}\", \"{}\"]\n",
        ISS_TLE[0], ISS_TLE[1]
    );
    let mut sim = simulation(&scenario(&extra));
    assert!(sim.config().threats[0].motion().is_tracked());
    let mut worst: f64 = 0.0;
    for t in [0.0, 10.0, 125.0, 300.0, 600.0] {
        sim.advance_to(t, &mut NullRecorder).unwrap();
        let threat_hill = sim.config().threats[0].position_hill_m(t);
        let iss = iss_eme2000_m(t);
        for (hill, eci) in sim.states_hill().iter().zip(sim.states_eci()) {
            let in_hill = (threat_hill - hill.position_m).norm();
            let inertial = (iss - eci.position_m).norm();
            // Thousands of km apart: the frame changes nothing but rounding.
            worst = worst.max((in_hill - inertial).abs() / inertial);
        }
    }
    assert!(worst < 1e-12, "worst relative gap {worst:e}");
}

#[test]
fn an_object_started_on_the_reference_orbit_stays_at_the_lvlh_origin() {
    let extra = "[[threats]]\nname = \"twin\"\ndanger_radius_m = 1.0\n\
                 state_eme2000 = [6778137.0, 0.0, 0.0, 0.0, 4763.0, 6010.0]\n\
                 propagation = \"truth\"\n\
                 [[obstacles]]\nname = \"twin-sphere\"\nradius_m = 1.0\n\
                 state_eme2000 = [6778137.0, 0.0, 0.0, 0.0, 4763.0, 6010.0]\n";
    // The satellite at the origin starts inside the sphere: allowed explicitly.
    let text = scenario(extra).replace(
        "[satellites]\ncount = 4\n",
        "[satellites]\ncount = 4\nallow_start_in_obstacle = true\n",
    );
    let mut sim = simulation(&text);
    sim.advance_to(600.0, &mut NullRecorder).unwrap();
    let p = sim.config().threats[0].position_hill_m(600.0);
    let v = sim.config().threats[0].velocity_hill_mps(600.0);
    let c = sim.config().obstacles[0].center_hill_m(600.0);
    // The same dynamics and steps as the reference orbit itself: only rounding separates them.
    assert!(p.norm() < 1e-6 && c.norm() < 1e-6, "{p:?} {c:?}");
    assert!(v.norm() < 1e-9, "{v:?}");
}

/// A truth-propagated object 2 km behind the reference, 25 m above and 20 m/s faster along-track: it
/// passes the swarm at about t = 100 s.
fn crossing(period_s: f64) -> String {
    // The reference's state plus the offset, rotated out of the LVLH frame at t = 0 (the engine's own
    // frame is the accelerated one; the start differs from this one by far less than the checks).
    let reference = CartesianState::new(
        Vector3::new(6778137.0, 0.0, 0.0),
        Vector3::new(0.0, 4763.0, 6010.0),
    );
    let frame = satflock::orbit::LvlhFrame::from_reference(&reference);
    let s = frame.from_hill(&satflock::orbit::RelativeStateHill {
        position_m: Vector3::new(25.0, -2000.0, 5.0),
        velocity_mps: Vector3::new(0.0, 20.0, 0.0),
    });
    let state = s.to_array();
    scenario(&format!(
        "[[threats]]\nname = \"crossing\"\ndanger_radius_m = 10.0\nstate_eme2000 = {state:?}\n\
         [[obstacles]]\nname = \"crossing-sphere\"\nradius_m = 10.0\nstate_eme2000 = {state:?}\n\
         propagation = \"truth\"\n"
    ))
    .replace("period_s = 10.0", &format!("period_s = {period_s}"))
}

#[test]
fn the_continuous_closest_approach_to_a_tracked_threat_is_the_dense_minimum() {
    let mut sim = simulation(&crossing(10.0));
    sim.set_conjunction_threshold_m(Some(400.0)).unwrap();
    sim.advance_to(300.0, &mut NullRecorder).unwrap();
    // Brute force: the same run stepped every 0.02 s, the distance taken at every step.
    let mut dense = simulation(&crossing(10.0));
    let n = sim.satellite_count();
    let mut sampled = vec![f64::INFINITY; n];
    for k in 1..=15_000 {
        let t = k as f64 * 0.02;
        dense.advance_to(t, &mut NullRecorder).unwrap();
        let threat = dense.config().threats[0].position_hill_m(t);
        for (i, s) in dense.states_hill().iter().enumerate() {
            sampled[i] = sampled[i].min((s.position_m - threat).norm());
        }
    }
    let monitor = sim.approach_monitor();
    let conjunctions = sim.conjunction_monitor().unwrap();
    for (i, brute) in sampled.iter().enumerate() {
        let approach = monitor.threat_approach(i, 0).unwrap();
        // Sampling at 0.02 s and 20 m/s overestimates a 130–360 m minimum by < 1e-3 m; the Hermite
        // paths over 10 s segments err by < 1e-6 m.
        assert!(
            (approach.distance_m - brute).abs() < 2e-3,
            "satellite {i}: monitored {} m, sampled {brute} m",
            approach.distance_m
        );
        // The obstacle centred on the same object: its clearance is the distance less its radius.
        let clearance = monitor.obstacle_clearance(i, 0).unwrap();
        assert!((clearance.clearance_m - (approach.distance_m - 10.0)).abs() < 1e-9);
        // The conjunction screen finds the same encounter, with the threat as secondary.
        let encounter = conjunctions
            .encounters()
            .iter()
            .filter(|e| {
                e.primary == i && e.secondary == satflock::conjunction::Secondary::Threat(0)
            })
            .min_by(|a, b| a.miss_distance_m.total_cmp(&b.miss_distance_m))
            .unwrap_or_else(|| panic!("satellite {i}: no encounter with the threat"));
        assert!((encounter.miss_distance_m - approach.distance_m).abs() < 1e-6);
    }
    assert!(sampled.iter().all(|d| *d < 400.0), "{sampled:?}");
}

#[test]
fn a_tracked_threat_is_sensed_where_it_is() {
    let sim = simulation(&crossing(10.0));
    let Motion::Tracked(path) = sim.config().threats[0].motion() else {
        panic!("a threat from a state is tracked")
    };
    assert_eq!(path.latest_time_s(), 0.0);
    // At t = 0 the object sits where the scenario put it (25, −2000, 5) m, to the difference between
    // the frame used above and the engine's accelerated frame.
    let p = path.position_hill_m(0.0);
    assert!((p - Vector3::new(25.0, -2000.0, 5.0)).norm() < 0.5, "{p:?}");
}

#[test]
fn bad_real_objects_are_refused_naming_the_key() {
    let tle = format!("tle = [\"{}\", \"{}\"]", ISS_TLE[0], ISS_TLE[1]);
    let bad_checksum = tle.replace("0  2927", "0  2928");
    let cases = [
        (
            format!("[[threats]]\ndanger_radius_m = 1.0\n{bad_checksum}\n"),
            "threats[0].tle",
        ),
        (
            format!("[[threats]]\ndanger_radius_m = 1.0\n{tle}\nomm = \"x.xml\"\n"),
            "names both omm and tle",
        ),
        (
            "[[threats]]\ndanger_radius_m = 1.0\nstate_eme2000 = [7e6, 0, 0, 0, 7.5e3, 0]\n\
             propagation = \"sgp4\"\n"
                .to_string(),
            "threats[0].propagation",
        ),
        (
            "[[threats]]\ndanger_radius_m = 1.0\nstate_eme2000 = [7e3, 0, 0, 0, 7.5, 0]\n"
                .to_string(),
            "kilometres written as metres",
        ),
        (
            format!(
                "[[threats]]\ndanger_radius_m = 1.0\n{tle}\nposition_hill_m = [0, 0, 0]\n\
                 velocity_hill_mps = [1, 0, 0]\n"
            ),
            "a line (a state or an aim) and an orbit",
        ),
        (
            "[[threats]]\ndanger_radius_m = 1.0\npropagation = \"truth\"\n\
             position_hill_m = [0, 0, 0]\nvelocity_hill_mps = [1, 0, 0]\n"
                .to_string(),
            "is given without an orbit",
        ),
        (
            "[[obstacles]]\nradius_m = 1.0\n".to_string(),
            "obstacles[0].center_hill_m",
        ),
        (
            format!("[[obstacles]]\nradius_m = 1.0\ncenter_hill_m = [500, 0, 0]\n{tle}\n"),
            "center_hill_m and an orbit",
        ),
        (
            "[[obstacles]]\nradius_m = 1.0\nomm = \"../outside.xml\"\n".to_string(),
            "obstacles[0].omm",
        ),
    ];
    for (extra, expected) in cases {
        let error = refusal(&scenario(&extra)).unwrap_or_else(|| panic!("accepted: {extra}"));
        assert!(error.contains(expected), "{extra}\n→ {error}");
    }
}
