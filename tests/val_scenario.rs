//! Scenario files: every built-in scenario is valid, and malformed files get an error naming the file,
//! the key and what is allowed (table-driven: each case is a change to a valid file and the fragments
//! its message must contain).

use std::path::Path;

use satflock::scenario::{builtin, Scenario, ScenarioError};

const VALID: &str = r#"
name = "t"
seed = 1
duration_s = 100.0
record_interval_s = 10.0

[reference]
altitude_m = 600e3
inclination_deg = 97.8

[satellites]
count = 4
mass_kg = 10.0
initial = { distribution = "sphere", radius_m = 50.0 }

[law]
name = "hold"
stiffness_per_s2 = 1e-4
damping_per_s = 2e-2
"#;

fn load(text: &str) -> Result<satflock::scenario::Prepared, ScenarioError> {
    Scenario::from_toml(text, "case.toml", Path::new("."))?.prepare()
}

#[test]
fn regress_every_builtin_scenario_is_valid() {
    for b in builtin::BUILTINS {
        let s = Scenario::load(b.name).unwrap_or_else(|e| panic!("{}: {e}", b.name));
        s.prepare().unwrap_or_else(|e| panic!("{}: {e}", b.name));
        assert!(
            !s.file.description.is_empty(),
            "{} has no description",
            b.name
        );
    }
}

/// A run copies its scenario into `scenario.toml`: serialising any built-in and parsing it back gives
/// the same scenario, so the copy reruns the same case.
#[test]
fn val_every_builtin_round_trips_through_its_toml_copy() {
    for b in builtin::BUILTINS {
        let original = Scenario::load(b.name).unwrap().file;
        let text = toml::to_string(&original).unwrap();
        let back = Scenario::from_toml(&text, "copy", Path::new("."))
            .unwrap_or_else(|e| panic!("{}: {e}\n{text}", b.name));
        assert_eq!(back.file, original, "{}", b.name);
    }
}

#[test]
fn val_valid_base_case_loads() {
    let p = load(VALID).unwrap();
    assert_eq!(p.satellites.len(), 4);
}

#[test]
fn val_malformed_scenarios_get_clear_errors() {
    // (what is changed, replace `from` by `to` in VALID, fragments the message must contain)
    let cases: &[(&str, &str, &str, &[&str])] = &[
        (
            "unknown top-level key",
            "seed = 1",
            "seed = 1\nsede = 2",
            &["case.toml", "unknown field `sede`", "line 4"],
        ),
        (
            "missing key",
            "seed = 1\n",
            "",
            &["case.toml", "missing field `seed`"],
        ),
        (
            "wrong type",
            "count = 4",
            "count = \"four\"",
            &["case.toml", "invalid type", "line"],
        ),
        (
            "negative count",
            "count = 4",
            "count = -4",
            &["case.toml", "count"],
        ),
        (
            "ring of no neighbours",
            "[law]",
            "[sensing]\nring_neighbours = 0\n\n[law]",
            &["case.toml", "sensing.ring_neighbours", "allowed: an integer >= 1"],
        ),
        (
            "negative release dispersion",
            "initial = { distribution = \"sphere\", radius_m = 50.0 }",
            "initial = { distribution = \"dispenser\", spacing_m = 2.0, release_speed_mps = [-0.1, 0.1], release_dispersion_mps = -0.01 }",
            &["case.toml", "satellites.initial.release_dispersion_mps", "allowed: finite, >= 0"],
        ),
        (
            "infinite release speed",
            "initial = { distribution = \"sphere\", radius_m = 50.0 }",
            "initial = { distribution = \"dispenser\", spacing_m = 2.0, release_speed_mps = [-0.1, inf] }",
            &["case.toml", "satellites.initial.release_speed_mps", "not a finite number"],
        ),
        (
            "zero satellites",
            "count = 4",
            "count = 0",
            &["case.toml", "satellites.count", "allowed: >= 1"],
        ),
        (
            "negative mass",
            "mass_kg = 10.0",
            "mass_kg = -1.0",
            &["case.toml", "satellites.mass_kg", "-1", "allowed: finite, > 0"],
        ),
        (
            "duration",
            "duration_s = 100.0",
            "duration_s = 0.0",
            &["duration_s", "allowed: finite, > 0"],
        ),
        (
            "record interval longer than the run",
            "record_interval_s = 10.0",
            "record_interval_s = 1000.0",
            &["record_interval_s", "allowed: (0, duration_s]"],
        ),
        (
            "inclination out of range",
            "inclination_deg = 97.8",
            "inclination_deg = 197.8",
            &["reference.inclination_deg", "197.8", "allowed: [0, 180]"],
        ),
        (
            "orbit inside the Earth",
            "altitude_m = 600e3",
            "semi_major_axis_m = 6000e3",
            &["reference.semi_major_axis_m", "inside the Earth"],
        ),
        (
            "elements and state together",
            "altitude_m = 600e3",
            "altitude_m = 600e3\nposition_eci_m = [7e6, 0, 0]\nvelocity_eci_mps = [0, 7.5e3, 0]",
            &["key `reference`", "gives classical elements and position_eci_m", "allowed: one of"],
        ),
        (
            "unknown law",
            "name = \"hold\"",
            "name = \"flock\"",
            &["unknown variant `flock`", "none", "hold"],
        ),
        (
            "unknown law parameter",
            "damping_per_s = 2e-2",
            "damping_per_s = 2e-2\ndamping = 1",
            &["unknown field `damping`"],
        ),
        (
            "law parameter out of range",
            "stiffness_per_s2 = 1e-4",
            "stiffness_per_s2 = -1e-4",
            &["key `law`", "stiffness_per_s2", "allowed: finite, > 0"],
        ),
        (
            "sampled without period",
            "[law]",
            "[control]\nmode = \"sampled\"\n\n[law]",
            &["control.period_s", "required"],
        ),
        (
            "period in continuous mode",
            "[law]",
            "[control]\nperiod_s = 1.0\n\n[law]",
            &["control.period_s", "applies only"],
        ),
        (
            "unknown distribution",
            "distribution = \"sphere\"",
            "distribution = \"cloud\"",
            &["unknown variant `cloud`"],
        ),
        (
            "list with wrong count",
            "initial = { distribution = \"sphere\", radius_m = 50.0 }",
            "initial = { distribution = \"list\", states = [[0,0,0,0,0,0]] }",
            &["satellites.initial.states", "1 states listed", "count = 4"],
        ),
        (
            "shell inverted",
            "initial = { distribution = \"sphere\", radius_m = 50.0 }",
            "initial = { distribution = \"shell\", inner_radius_m = 50.0, outer_radius_m = 10.0 }",
            &["satellites.initial.inner_radius_m", "allowed: [0, outer_radius_m]"],
        ),
        (
            "missing csv",
            "initial = { distribution = \"sphere\", radius_m = 50.0 }",
            "initial = { distribution = \"csv\", file = \"no-such-file.csv\" }",
            &["satellites.initial.file", "no-such-file.csv"],
        ),
        (
            "event after the end",
            "[law]",
            "[[events]]\ntime_s = 500.0\naction = \"threat-warning\"\nthreat = 0\nactive = true\n\n[law]",
            &["events[0].time_s", "500", "allowed: [0, duration_s = 100]"],
        ),
        (
            "event naming a missing satellite",
            "[law]",
            "[[events]]\ntime_s = 50.0\naction = \"remove-satellite\"\nsatellite = 9\n\n[law]",
            &["events[0].satellite", "satellite 9 does not exist", "0..=3"],
        ),
        (
            "bad law parameter update",
            "[law]",
            "[[events]]\ntime_s = 50.0\naction = \"set-law-parameters\"\nparameters = { stifness_per_s2 = 1.0 }\n\n[law]",
            &["events[0].parameters", "unknown field `stifness_per_s2`"],
        ),
        (
            "unknown event action",
            "[law]",
            "[[events]]\ntime_s = 50.0\naction = \"explode\"\n\n[law]",
            &["unknown variant `explode`"],
        ),
        (
            "bad selection word",
            "[law]",
            "[[events]]\ntime_s = 50.0\naction = \"cut-links\"\nsatellites = \"some\"\n\n[law]",
            &["events[0].satellites", "`some` is not allowed", "\"all\""],
        ),
        (
            "member origin out of range",
            "inclination_deg = 97.8",
            "inclination_deg = 97.8\norigin = \"member\"\norigin_member = 4",
            &["reference.origin_member", "satellite 4 does not exist"],
        ),
        (
            "eccentric orbit with HCW",
            "inclination_deg = 97.8",
            "inclination_deg = 97.8\neccentricity = 0.02\n\n[dynamics]\nmodel = \"hcw\"",
            &["dynamics.model", "circular", "0.02000"],
        ),
        (
            "negative sensing range",
            "[law]",
            "[sensing]\nrange_m = -5.0\n\n[law]",
            &["sensing.range_m", "allowed: finite, > 0"],
        ),
        (
            "override of a missing satellite",
            "[law]",
            "[[satellites.overrides]]\nids = [7]\nmass_kg = 3.0\n\n[law]",
            &["satellites.overrides[0].ids", "satellite 7 does not exist"],
        ),
    ];
    for (what, from, to, fragments) in cases {
        assert!(
            VALID.contains(from),
            "case `{what}`: `{from}` not in the base file"
        );
        let text = VALID.replacen(from, to, 1);
        let message = match load(&text) {
            Ok(_) => panic!("case `{what}` was accepted"),
            Err(e) => e.to_string(),
        };
        for fragment in *fragments {
            assert!(
                message.contains(fragment),
                "case `{what}`: message `{message}` lacks `{fragment}`"
            );
        }
    }
}

#[test]
fn val_unknown_scenario_name_lists_the_builtins() {
    let message = Scenario::load("no-such-scenario").unwrap_err().to_string();
    assert!(message.contains("no-such-scenario"));
    for name in builtin::names() {
        assert!(message.contains(name), "{message}");
    }
}

#[test]
fn val_csv_and_gao_frame_initial_states_are_converted_to_hill() {
    // A CSV in Gao's o-xyz frame (x along-track, y minus orbit normal, z nadir): the row
    // (10, 20, 30) must become Hill (x radial = −z_gao, y along-track = x_gao, z normal = −y_gao).
    let dir = std::env::temp_dir().join(format!("satflock-csv-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("states.csv"),
        "x_m,y_m,z_m,vx_mps,vy_mps,vz_mps\n10,20,30,0.1,0.2,0.3\n-1,0,0,0,0,0\n",
    )
    .unwrap();
    let text = VALID.replace("count = 4", "count = 2").replace(
        "initial = { distribution = \"sphere\", radius_m = 50.0 }",
        "initial = { distribution = \"csv\", file = \"states.csv\", frame = \"gao\" }",
    );
    let file = dir.join("s.toml");
    std::fs::write(&file, text).unwrap();
    let prepared = Scenario::from_path(&file).unwrap().prepare().unwrap();
    let s = prepared.satellites[0].relative_state;
    assert_eq!(s.position_m, nalgebra::Vector3::new(-30.0, 10.0, -20.0));
    assert_eq!(s.velocity_mps, nalgebra::Vector3::new(-0.3, 0.1, -0.2));
    assert_eq!(
        prepared.satellites[1].relative_state.position_m,
        nalgebra::Vector3::new(0.0, -1.0, 0.0)
    );
}

/// Case and controller: the initial states depend only on the case and the seed, never on the law that
/// steers it (bit for bit, relative and inertial), so `satflock compare` starts every law alike.
#[test]
fn val_initial_states_depend_only_on_the_case_and_the_seed() {
    use satflock::scenario::Controller;
    let case = Scenario::load("hold").unwrap();
    let controllers = [
        Controller::from_toml("[law]\nname = \"none\"\n", "laws/none.toml").unwrap(),
        Controller::from_toml(
            "[law]\nname = \"hold\"\nstiffness_per_s2 = 4e-4\ndamping_per_s = 4e-2\n\n[control]\nmode = \"continuous\"\n",
            "laws/continuous-hold.toml",
        )
        .unwrap(),
        Controller::load("builtin:hold").unwrap(),
    ];
    for seed in [1, 2] {
        let states: Vec<(Vec<u64>, Vec<u64>)> = controllers
            .iter()
            .map(|c| {
                let mut scenario = case.with_controller(c);
                scenario.file.seed = seed;
                let simulation =
                    satflock::run::build_simulation(&scenario).unwrap_or_else(|e| panic!("{e}"));
                let hill = simulation
                    .states_hill()
                    .iter()
                    .flat_map(|s| s.position_m.iter().chain(s.velocity_mps.iter()))
                    .map(|v| v.to_bits())
                    .collect();
                let eci = simulation
                    .states_eci()
                    .iter()
                    .flat_map(|s| s.position_m.iter().chain(s.velocity_mps.iter()))
                    .map(|v| v.to_bits())
                    .collect();
                (hill, eci)
            })
            .collect();
        assert_eq!(states[0].0.len(), 6 * 20);
        for other in &states[1..] {
            assert_eq!(*other, states[0], "seed {seed}");
        }
    }
}
