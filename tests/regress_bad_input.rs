//! Regression cases of issue 12 (scenario layer and library): inputs that panicked, aborted, or ran as
//! if they were fine. Each must now be refused with an error naming the file, the dotted key and the
//! allowed range — never a panic.

use std::path::Path;

use satflock::grid::NeighbourGrid;
use satflock::metrics::{five_elements, FiveElementsWorkspace, MetricsError};
use satflock::scenario::{Scenario, ScenarioError};

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
radius_m = 0.5
initial = { distribution = "sphere", radius_m = 50.0 }

[law]
name = "hold"
stiffness_per_s2 = 1e-4
damping_per_s = 2e-2
"#;

const SPHERE: &str = "initial = { distribution = \"sphere\", radius_m = 50.0 }";

fn load_in(text: &str, dir: &Path) -> Result<satflock::scenario::Prepared, ScenarioError> {
    Scenario::from_toml(text, "case.toml", dir).and_then(|s| s.prepare())
}

/// `VALID` with `from` replaced by `to`; the result must be an `Invalid` error in `case.toml` naming
/// `key` and containing every fragment. Returns the message.
#[track_caller]
fn refused(from: &str, to: &str, key: &str, fragments: &[&str]) -> String {
    assert!(VALID.contains(from), "`{from}` is not in VALID");
    refused_text(&VALID.replace(from, to), Path::new("."), key, fragments)
}

#[track_caller]
fn refused_text(text: &str, dir: &Path, key: &str, fragments: &[&str]) -> String {
    let err = match load_in(text, dir) {
        Ok(_) => panic!("accepted, expected an error on `{key}`"),
        Err(e) => e,
    };
    let message = err.to_string();
    match &err {
        ScenarioError::Invalid { file, key: k, .. } => {
            assert_eq!(file, "case.toml", "{message}");
            assert_eq!(k, key, "{message}");
        }
        other => panic!("expected Invalid on `{key}`, got {other:?}"),
    }
    for f in fragments {
        assert!(message.contains(f), "`{f}` missing from: {message}");
    }
    message
}

#[test]
fn regress_base_case_still_loads() {
    let p = load_in(VALID, Path::new(".")).unwrap();
    assert_eq!(p.satellites.len(), 4);
}

// ---- 1. Panics ----

#[test]
fn regress_huge_altitude_is_refused_not_a_panic() {
    // Schweighart–Sedwick panicked on the infinite radius of 1e200 m.
    refused(
        "altitude_m = 600e3",
        "altitude_m = 1e200",
        "reference.altitude_m",
        &["Hill sphere", "allowed: a (1 + e) <= 1.5e9 m"],
    );
    refused(
        "altitude_m = 600e3",
        "semi_major_axis_m = 1e160",
        "reference.semi_major_axis_m",
        &["Hill sphere"],
    );
}

#[test]
fn regress_huge_satellite_count_is_refused_before_allocating() {
    for count in ["9223372036854775807", "1000000000", "10000001"] {
        refused(
            "count = 4",
            &format!("count = {count}"),
            "satellites.count",
            &["allowed: >= 1 and <= 10000000"],
        );
    }
}

#[test]
fn regress_subnormal_sphere_radius_does_not_break_the_grid() {
    // A 1e-308 m sphere put every satellite within a subnormal distance of the others: the grid's
    // cell count wrapped to 0 and indexing panicked. Now the grid works and the overlap check refuses
    // the start (the satellites have 0.5 m radii).
    refused(
        SPHERE,
        "initial = { distribution = \"sphere\", radius_m = 1e-308 }",
        "satellites.allow_initial_overlap",
        &["overlap at t = 0"],
    );
}

#[test]
fn regress_grid_with_subnormal_radius_and_spacing_is_exact() {
    // Points 1e-310 m apart and a query radius of 1e-308 m (both subnormal).
    let x: Vec<f64> = (0..50).map(|i| i as f64 * 1e-310).collect();
    let y = vec![0.0; 50];
    let z = vec![0.0; 50];
    let mut grid = NeighbourGrid::new();
    grid.build(&x, &y, &z, 1e-308).unwrap();
    assert!(grid.cell_size_m().is_normal());
    for i in 0..50 {
        let mut found = Vec::new();
        grid.for_each_neighbour(i, |nb| found.push(nb.index));
        found.sort_unstable();
        let brute: Vec<usize> = (0..50)
            .filter(|&j| j != i && (x[j] - x[i]).abs() <= 1e-308)
            .collect();
        assert_eq!(found, brute, "satellite {i}");
        let nn = grid.nearest_neighbour(i).unwrap();
        let brute_nn = (0..50)
            .filter(|&j| j != i)
            // The grid's documented rule, sqrt(dx² + dy² + dz²) in f64 (here dx² underflows to 0).
            .map(|j| ((x[j] - x[i]) * (x[j] - x[i])).sqrt())
            .fold(f64::INFINITY, f64::min);
        assert_eq!(nn.distance_m, brute_nn, "satellite {i}");
    }
}

// ---- 2. Physical sense checks ----

#[test]
fn regress_reference_perigee_below_100_km_is_refused() {
    refused(
        "altitude_m = 600e3",
        "altitude_m = 80e3",
        "reference.altitude_m",
        &["perigee altitude", "100000 m", "allowed"],
    );
    refused(
        "altitude_m = 600e3",
        "semi_major_axis_m = 20000e3\neccentricity = 0.9",
        "reference.semi_major_axis_m",
        &["perigee altitude", "allowed"],
    );
    // An ECI state on an orbit whose perigee is inside the atmosphere (1 km/s short of circular).
    refused(
        "altitude_m = 600e3\ninclination_deg = 97.8",
        "position_eci_m = [6978137.0, 0.0, 0.0]\nvelocity_eci_mps = [0.0, 6500.0, 0.0]",
        "reference.position_eci_m",
        &["perigee altitude", "allowed"],
    );
}

#[test]
fn regress_kilometres_written_as_metres_are_named() {
    refused(
        "altitude_m = 600e3",
        "altitude_m = 550",
        "reference.altitude_m",
        &["kilometres written as metres", "5.5e5 m"],
    );
    refused(
        "altitude_m = 600e3",
        "semi_major_axis_m = 6978.137",
        "reference.semi_major_axis_m",
        &["kilometres written as metres", "allowed"],
    );
    refused(
        "altitude_m = 600e3\ninclination_deg = 97.8",
        "position_eci_m = [6978.137, 0.0, 0.0]\nvelocity_eci_mps = [0.0, 7.5, 0.0]",
        "reference.position_eci_m",
        &["kilometres written as metres"],
    );
}

#[test]
fn regress_rk4_step_longer_than_a_hundredth_of_the_period_is_refused() {
    // Free drift (no law rate) with step_s = 2900 s ran a wrong orbit.
    let text = VALID
        .replace("duration_s = 100.0", "duration_s = 5800.0")
        .replace("record_interval_s = 10.0", "record_interval_s = 2900.0")
        .replace(
            "[law]\nname = \"hold\"\nstiffness_per_s2 = 1e-4\ndamping_per_s = 2e-2",
            "[law]\nname = \"none\"\n\n[dynamics]\nmodel = \"j2\"\nintegrator = \"rk4\"\nstep_s = 2900.0",
        );
    refused_text(
        &text,
        Path::new("."),
        "dynamics.step_s",
        &["1/100 of the period", "allowed: (0, 58."],
    );
}

#[test]
fn regress_control_period_longer_than_a_hundredth_of_the_period_is_refused() {
    let text = VALID
        .replace("duration_s = 100.0", "duration_s = 5800.0")
        .replace("record_interval_s = 10.0", "record_interval_s = 600.0")
        .replace(
            "[law]\nname = \"hold\"\nstiffness_per_s2 = 1e-4\ndamping_per_s = 2e-2",
            "[law]\nname = \"none\"\n\n[control]\nmode = \"sampled\"\nperiod_s = 600.0",
        );
    refused_text(
        &text,
        Path::new("."),
        "control.period_s",
        &["1/100 of the period", "allowed: (0, 58."],
    );
}

#[test]
fn regress_record_interval_below_the_step_is_refused() {
    refused(
        "record_interval_s = 10.0",
        "record_interval_s = 1e-9",
        "record_interval_s",
        &[
            "shorter than dynamics.step_s",
            "allowed: [dynamics.step_s, duration_s]",
        ],
    );
}

#[test]
fn regress_sensing_noise_beyond_the_range_is_refused() {
    refused(
        "[law]",
        "[sensing]\nrange_m = 200.0\nposition_noise_m = 1e300\n\n[law]",
        "sensing.position_noise_m",
        &["allowed: [0, sensing.range_m]"],
    );
    refused(
        "[law]",
        "[sensing]\nrange_m = 200.0\nvelocity_noise_mps = 1e3\n\n[law]",
        "sensing.velocity_noise_mps",
        &["allowed: [0, ", "10 n R"],
    );
    // Within the bounds, noise is still accepted.
    let ok = VALID.replace(
        "[law]",
        "[sensing]\nrange_m = 200.0\nposition_noise_m = 0.5\nvelocity_noise_mps = 1e-3\n\n[law]",
    );
    load_in(&ok, Path::new(".")).unwrap();
}

#[test]
fn regress_satellites_overlapping_at_t0_are_refused_unless_allowed() {
    let text = VALID.replace("count = 4", "count = 20").replace(
        SPHERE,
        "initial = { distribution = \"box\", size_hill_m = [0.0, 0.0, 0.0] }",
    );
    let message = refused_text(
        &text,
        Path::new("."),
        "satellites.allow_initial_overlap",
        &["overlap at t = 0", "allow_initial_overlap = true"],
    );
    assert!(message.contains("satellites 0 and 1"), "{message}");
    // Point satellites (radius 0) that coincide are refused too.
    refused_text(
        &text.replace("radius_m = 0.5\n", ""),
        Path::new("."),
        "satellites.allow_initial_overlap",
        &["overlap at t = 0"],
    );
    let allowed = text.replace(
        "radius_m = 0.5\n",
        "radius_m = 0.5\nallow_initial_overlap = true\n",
    );
    assert_eq!(
        load_in(&allowed, Path::new(".")).unwrap().satellites.len(),
        20
    );
}

#[test]
fn regress_initial_state_beyond_max_distance_is_refused_at_load() {
    refused(
        "[law]",
        "[dynamics]\nmax_distance_m = 10.0\n\n[law]",
        "dynamics.max_distance_m",
        &["beyond dynamics.max_distance_m = 10 m", "allowed"],
    );
}

#[test]
fn regress_removing_the_origin_member_is_refused_at_load() {
    let text = VALID.replace(
        "inclination_deg = 97.8",
        "inclination_deg = 97.8\norigin = \"member\"\norigin_member = 2",
    ) + "\n[[events]]\ntime_s = 50.0\naction = \"remove-satellite\"\nsatellite = 2\n";
    refused_text(
        &text,
        Path::new("."),
        "events[0].satellite",
        &["origin_member", "freeze the frame", "allowed"],
    );
    // Removing another member is fine.
    load_in(
        &text.replace("satellite = 2\n", "satellite = 1\n"),
        Path::new("."),
    )
    .unwrap();
}

// ---- 3. CSV initial states ----

fn csv_dir(tag: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir()
        .join(format!("satflock-regress-{}-{tag}", std::process::id()))
        .join("scenario");
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn csv_text(path: &str) -> String {
    VALID.replace("count = 4", "count = 2").replace(
        SPHERE,
        &format!("initial = {{ distribution = \"csv\", file = \"{path}\" }}"),
    )
}

#[test]
fn regress_csv_path_outside_the_scenario_folder_is_refused_without_echo() {
    let dir = csv_dir("escape");
    let secret = "SECRET-CONTENT-LINE";
    std::fs::write(
        dir.parent().unwrap().join("outside.csv"),
        format!("{secret}\n1,2\n"),
    )
    .unwrap();
    let message = refused_text(
        &csv_text("../outside.csv"),
        &dir,
        "satellites.initial.file",
        &["outside the scenario's folder", "allowed"],
    );
    assert!(!message.contains(secret), "{message}");
    refused_text(
        &csv_text("../../../../../../../../etc/passwd"),
        &dir,
        "satellites.initial.file",
        &["outside the scenario's folder"],
    );
    refused_text(
        &csv_text("/dev/zero"),
        &dir,
        "satellites.initial.file",
        &["outside the scenario's folder"],
    );
}

#[test]
fn regress_csv_non_regular_file_is_refused() {
    let dir = csv_dir("dir");
    std::fs::create_dir_all(dir.join("sub.csv")).unwrap();
    refused_text(
        &csv_text("sub.csv"),
        &dir,
        "satellites.initial.file",
        &["not a regular file"],
    );
}

#[test]
fn regress_csv_errors_never_echo_the_content() {
    let dir = csv_dir("echo");
    let secret = "root:x:0:0:SECRET";
    std::fs::write(
        dir.join("bad-header.csv"),
        format!("{secret}\n1,2,3,4,5,6\n"),
    )
    .unwrap();
    let message = refused_text(
        &csv_text("bad-header.csv"),
        &dir,
        "satellites.initial.file",
        &["line 1 is not the required header"],
    );
    assert!(!message.contains("SECRET"), "{message}");
    std::fs::write(
        dir.join("bad-cell.csv"),
        "x_m,y_m,z_m,vx_mps,vy_mps,vz_mps\n1,2,SECRET,0,0,0\n-1,0,0,0,0,0\n",
    )
    .unwrap();
    let message = refused_text(
        &csv_text("bad-cell.csv"),
        &dir,
        "satellites.initial.file",
        &["line 2: column z_m is not a number"],
    );
    assert!(!message.contains("SECRET"), "{message}");
    // A well-formed file inside the folder still loads.
    std::fs::write(
        dir.join("good.csv"),
        "x_m,y_m,z_m,vx_mps,vy_mps,vz_mps\n10,0,0,0,0,0\n-10,0,0,0,0,0\n",
    )
    .unwrap();
    assert_eq!(
        load_in(&csv_text("good.csv"), &dir)
            .unwrap()
            .satellites
            .len(),
        2
    );
}

// ---- 4. characterize, library side ----

#[test]
fn regress_huge_finite_coordinates_give_a_clear_metrics_error() {
    let p = vec![[1e200, 0.0, 0.0], [0.0, 1e200, 0.0], [0.0, 0.0, 0.0]];
    let v = vec![[0.0; 3]; 3];
    let err = five_elements(&p, &v, None, &mut FiveElementsWorkspace::new()).unwrap_err();
    assert!(
        matches!(err, MetricsError::OutOfRange { index: 0, .. }),
        "{err:?}"
    );
    let message = err.to_string();
    assert!(
        message.contains("allowed: |coordinate| <= 1e150"),
        "{message}"
    );
    assert!(!message.contains("not finite"), "{message}");
}

#[test]
fn regress_many_identical_points_are_not_quadratic() {
    // 10^5 identical points took 12.5 s (quadratic); a linear pass takes milliseconds. The bound is
    // generous (slow CI machines) but far below the quadratic time.
    let n = 100_000;
    let p = vec![[7e6, 1.0, -2.0]; n];
    let v = vec![[0.0, 7.5e3, 0.0]; n];
    let start = std::time::Instant::now();
    let e = five_elements(&p, &v, None, &mut FiveElementsWorkspace::new()).unwrap();
    let elapsed = start.elapsed();
    assert_eq!(e.n, n);
    assert_eq!(e.d_min_m, 0.0);
    assert_eq!(e.d_max_m, 0.0);
    assert_eq!(e.diameter_m, 0.0);
    assert!(elapsed.as_secs_f64() < 2.0, "{elapsed:?}");
    // Duplicates mixed with distinct points: exact against brute force.
    let mut p: Vec<[f64; 3]> = (0..200)
        .map(|i| [(i % 50) as f64, (i / 50) as f64 * 3.0, 0.0])
        .collect();
    p.extend(std::iter::repeat_n([10.5, 0.0, 0.0], 300));
    let v = vec![[0.0; 3]; p.len()];
    let radii: Vec<f64> = (0..p.len()).map(|i| (i % 7) as f64 * 0.01).collect();
    let e = five_elements(&p, &v, Some(&radii), &mut FiveElementsWorkspace::new()).unwrap();
    let mut d_min = f64::INFINITY;
    let mut diameter: f64 = 0.0;
    for i in 0..p.len() {
        for j in i + 1..p.len() {
            let d = ((p[i][0] - p[j][0]).powi(2) + (p[i][1] - p[j][1]).powi(2)).sqrt();
            d_min = d_min.min(d - radii[i] - radii[j]);
            diameter = diameter.max(d);
        }
    }
    assert_eq!(e.d_min_m, d_min);
    assert!((e.diameter_m - diameter).abs() <= 1e-9 * diameter);
}

/// A tiny step over a long run (`step_s = 1e-10` "never finishes") and a tiny record interval that
/// would write hundreds of GB are refused with the size they imply, unless `[output] allow_large`.
#[test]
fn regress_runaway_step_and_output_size_are_refused_unless_allowed() {
    // 4 satellites × 1e6 s / 1e-4 s = 4e10 satellite-steps > 1e10 (and the 1e-4 s step is within every
    // other bound: below period/100, no law rate to violate with these soft gains).
    let long = VALID
        .replace("duration_s = 100.0", "duration_s = 1e6")
        .replace("[law]", "[dynamics]\nstep_s = 1e-4\n\n[law]");
    let message = refused_text(
        &long.replace("record_interval_s = 10.0", "record_interval_s = 1e5"),
        Path::new("."),
        "dynamics.step_s",
        &["satellite-steps", "allow_large"],
    );
    assert!(message.contains("4.000e10"), "{message}");
    // 1e6 s recorded every 0.01 s for 4 satellites with a trajectory: 4e8 rows > 5e7.
    let rows = VALID
        .replace("duration_s = 100.0", "duration_s = 1e6")
        .replace("record_interval_s = 10.0", "record_interval_s = 1.0");
    refused_text(
        &rows
            .replace("count = 4", "count = 200")
            .replace("radius_m = 50.0", "radius_m = 500.0"),
        Path::new("."),
        "record_interval_s",
        &["rows", "allow_large"],
    );
    // The explicit key lets the size through (the scenario is otherwise valid).
    let allowed = format!(
        "{}\n[output]\nallow_large = true\n",
        rows.replace("count = 4", "count = 200")
            .replace("radius_m = 50.0", "radius_m = 500.0")
    );
    load_in(&allowed, Path::new(".")).expect("allow_large accepts the large output");
}

/// `propagate` (library and `satflock propagate`): an orbit with its perigee inside the atmosphere or the
/// Earth (e.g. elements in kilometres given as metres), an `rtol` of 10 and an output step that would
/// produce 10^10 rows are refused with the numbers, before any work.
#[test]
fn regress_propagate_refuses_nonsense_orbits_and_settings() {
    use satflock::integrate::{IntegratorMethod, Tolerances};
    use satflock::orbit::{CartesianState, EarthModel, GravityModel};
    use satflock::propagate::{propagate, PropagateError, PropagationSettings};
    let earth = EarthModel::WGS84_EGM96;
    let settings = PropagationSettings {
        earth,
        forces: std::sync::Arc::new(satflock::dynamics::ForceSet::gravity(
            GravityModel::J2,
            earth,
        )),
        properties: satflock::dynamics::PhysicalProperties::point_mass(1.0),
        integrator: IntegratorMethod::Rk4,
        step_s: 10.0,
        tolerances: Tolerances {
            relative: 1e-10,
            absolute: 1e-6,
        },
        duration_s: 100.0,
        output_step_s: 10.0,
    };
    let circular = |r_m: f64| {
        CartesianState::new(
            nalgebra::Vector3::new(r_m, 0.0, 0.0),
            nalgebra::Vector3::new(0.0, (earth.mu_m3_s2 / r_m).sqrt(), 0.0),
        )
    };
    // 6978.137 "m" (km meant): far inside the Earth (the check `satflock propagate` applies).
    match settings.check_orbit(0, &circular(6978.137)) {
        Err(e @ PropagateError::InvalidOrbit { index: 0, .. }) => {
            assert!(e.to_string().contains("perigee altitude"), "{e}")
        }
        other => panic!("accepted: {other:?}"),
    }
    // 50 km altitude: below the 100 km floor.
    assert!(matches!(
        settings.check_orbit(0, &circular(earth.equatorial_radius_m + 50e3)),
        Err(PropagateError::InvalidOrbit { .. })
    ));
    let good = circular(earth.equatorial_radius_m + 600e3);
    settings.check_orbit(0, &good).unwrap();
    let mut bad_rtol = settings.clone();
    bad_rtol.tolerances.relative = 10.0;
    assert!(matches!(
        propagate(&[good], &bad_rtol, |_, _| {}),
        Err(PropagateError::InvalidSetting {
            setting: "rtol",
            ..
        })
    ));
    let mut tiny_output = settings.clone();
    tiny_output.duration_s = 86_400.0;
    tiny_output.output_step_s = 1e-6;
    assert!(matches!(
        propagate(&[good], &tiny_output, |_, _| {}),
        Err(PropagateError::InvalidSetting {
            setting: "output_step_s",
            ..
        })
    ));
    propagate(&[good], &settings, |_, _| {}).expect("a 600 km circular orbit propagates");
}

/// A misspelled law key is pointed at by its own line (the parser alone names the `[law]` header).
#[test]
fn regress_misspelled_law_key_points_at_its_line() {
    let text = VALID.replace(
        "damping_per_s = 2e-2",
        "damping_per_s = 2e-2\ndampnig_per_s = 1.0",
    );
    let line = text
        .lines()
        .position(|l| l.starts_with("dampnig_per_s"))
        .unwrap()
        + 1;
    let Err(ScenarioError::Parse { file, message }) =
        Scenario::from_toml(&text, "case.toml", Path::new("."))
    else {
        panic!("expected a parse error");
    };
    assert_eq!(file, "case.toml");
    assert!(message.contains(&format!("line {line},")), "{message}");
    assert!(
        message.contains("dampnig_per_s") && message.contains("(in `law`)"),
        "{message}"
    );
    assert!(
        message.contains("stiffness_per_s2"),
        "lists the allowed keys: {message}"
    );
}

/// A `switch-law` event with a missing key names the event by its index; an unknown key in the event's
/// law names the sub-table and its line.
#[test]
fn regress_switch_law_errors_name_the_event() {
    let event = |body: &str| {
        format!(
            "{VALID}\n[[events]]\ntime_s = 10.0\naction = \"cut-links\"\nsatellites = \"all\"\n\n[[events]]\ntime_s = 20.0\naction = \"switch-law\"\n{body}"
        )
    };
    let parse = |text: &str| match Scenario::from_toml(text, "case.toml", Path::new(".")) {
        Err(ScenarioError::Parse { message, .. }) => message,
        other => panic!("expected a parse error, got {other:?}"),
    };
    let missing = parse(&event(""));
    assert!(
        missing.contains("missing field `law`") && missing.contains("(in `events[1]`)"),
        "{missing}"
    );
    let text = event("[events.law]\nname = \"hold\"\nstiffnes_per_s2 = 1.0\n");
    let typo = parse(&text);
    let line = text
        .lines()
        .position(|l| l.starts_with("stiffnes_per_s2"))
        .unwrap()
        + 1;
    assert!(typo.contains(&format!("line {line},")), "{typo}");
    assert!(typo.contains("(in `events[1].law`)"), "{typo}");
}

/// A law set by an event is checked against the swarm (here: the bifurcating avoidance radius against
/// the sensing range) when the scenario loads: exit 2 naming the event's key, not a failure when the
/// event fires.
#[test]
fn regress_event_law_beyond_the_sensing_range_is_refused_at_load() {
    let base = satflock::scenario::builtin::find("gao-circle")
        .unwrap()
        .toml;
    let text = format!(
        "{base}\n[[events]]\ntime_s = 10.0\naction = \"set-law-parameters\"\nparameters = {{ avoidance_radius_m = 1000.0 }}\n"
    );
    let Err(err) = load_in(&text, Path::new(".")) else {
        panic!("accepted, expected a refusal");
    };
    let message = err.to_string();
    let ScenarioError::Invalid { file, key, .. } = &err else {
        panic!("expected Invalid, got {err:?}");
    };
    assert_eq!(
        (file.as_str(), key.as_str()),
        ("case.toml", "events[0].parameters")
    );
    assert!(
        message.contains("exceeds the sensing range 500 m"),
        "{message}"
    );
    assert!(message.contains("allowed"), "{message}");
}

// ---- Issue 25: silent acceptance ----

/// A step below the engine's time tolerance (`step_s = 1e-10` over 1e-6 s) was never integrated and the
/// run "completed"; a control period likewise. Both are refused at load, naming the key and the range.
#[test]
fn regress_step_below_the_time_tolerance_is_refused() {
    let tiny = VALID
        .replace("duration_s = 100.0", "duration_s = 1e-6")
        .replace("record_interval_s = 10.0", "record_interval_s = 1e-6");
    refused_text(
        &tiny.replace("[law]", "[dynamics]\nstep_s = 1e-10\n\n[law]"),
        Path::new("."),
        "dynamics.step_s",
        &[
            "1e-10 s is out of range",
            "allowed: finite, >= 1e-6 s",
            "tolerance",
        ],
    );
    refused_text(
        &tiny.replace(
            "[law]",
            "[dynamics]\nstep_s = 1e-6\n\n[control]\nmode = \"sampled\"\nperiod_s = 1e-8\n\n[law]",
        ),
        Path::new("."),
        "control.period_s",
        &["allowed: finite, >= 1e-6 s"],
    );
    // The smallest step allowed still loads.
    load_in(
        &tiny.replace("[law]", "[dynamics]\nstep_s = 1e-6\n\n[law]"),
        Path::new("."),
    )
    .unwrap();
}

/// A sphere of initial states centred inside the Earth ran to `completed`: refused at load.
#[test]
fn regress_initial_states_inside_the_earth_are_refused() {
    refused(
        SPHERE,
        "initial = { distribution = \"sphere\", radius_m = 50.0, center_hill_m = [-7e6, 0.0, 0.0] }",
        "satellites.initial",
        &["starts inside the Earth", "allowed: every satellite at least the Earth's radius"],
    );
    // 600 km below the reference is still above the ground.
    load_in(
        &VALID.replace(
            SPHERE,
            "initial = { distribution = \"sphere\", radius_m = 50.0, center_hill_m = [-500e3, 0.0, 0.0] }",
        ),
        Path::new("."),
    )
    .unwrap();
}

/// Satellites starting inside an obstacle were accepted (overlapping satellites are refused): refused
/// at load unless `satellites.allow_start_in_obstacle = true`.
#[test]
fn regress_start_inside_an_obstacle_is_refused_unless_allowed() {
    let rock =
        "\n[[obstacles]]\nname = \"rock\"\ncenter_hill_m = [0.0, 0.0, 0.0]\nradius_m = 500.0\n";
    let text = format!("{VALID}{rock}");
    let message = refused_text(
        &text,
        Path::new("."),
        "satellites.allow_start_in_obstacle",
        &[
            "inside obstacles[0] (`rock`)",
            "allow_start_in_obstacle = true",
        ],
    );
    assert!(message.contains("satellite 0"), "{message}");
    let allowed = text.replace(
        "radius_m = 0.5\n",
        "radius_m = 0.5\nallow_start_in_obstacle = true\n",
    );
    load_in(&allowed, Path::new(".")).unwrap();
    // An obstacle away from the swarm is fine.
    load_in(
        &text.replace(
            "center_hill_m = [0.0, 0.0, 0.0]",
            "center_hill_m = [0.0, 5e3, 0.0]",
        ),
        Path::new("."),
    )
    .unwrap();
}

/// Issue 25: a threat warning in a scenario without `[[threats]]` was refused with "allowed: 0..0".
#[test]
fn regress_threat_warning_without_threats_says_there_are_none() {
    let message = refused(
        "[law]",
        "[[events]]\ntime_s = 10.0\naction = \"threat-warning\"\nthreat = 0\nactive = true\n\n[law]",
        "events[0].threat",
        &["no [[threats]] to warn about"],
    );
    assert!(!message.contains("0..0"), "{message}");
}
