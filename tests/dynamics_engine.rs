//! The force set inside the engine, through the scenario layer: a `[dynamics.forces]` table of gravity
//! alone gives today's bits; drag acts on every satellite and on the virtual reference as the scenario
//! says; the fused and generic paths agree on a drag scenario within the integrator's error; a
//! satellite that sinks below the atmosphere's floor stops the run naming it; bad force parameters are
//! refused with the file, the key and the allowed range.

use std::path::Path;

use satflock::run::build_simulation;
use satflock::scenario::{Scenario, ScenarioError};
use satflock::swarm::{Divergence, NullRecorder, SimError};

/// A sampled free-drift case at `altitude_m` with `forces` appended (TOML) and `satellites` keys.
fn case(altitude_m: f64, integrator: &str, forces: &str, satellites: &str) -> String {
    format!(
        r#"
name = "forces"
seed = 3
epoch_utc = "2026-03-20T12:00:00Z"
duration_s = 3000.0
record_interval_s = 100.0

[dynamics]
model = "j2"
integrator = "{integrator}"
step_s = 5.0
{forces}

[reference]
altitude_m = {altitude_m}
inclination_deg = 51.6

[control]
mode = "sampled"
period_s = 10.0

[satellites]
count = 6
mass_kg = 4.0
{satellites}
initial = {{ distribution = "sphere", radius_m = 300.0, velocity = "hcw-no-drift" }}

[law]
name = "none"

[sensing]
range_m = 500.0
"#
    )
}

const EXPONENTIAL_DRAG: &str = r#"
[dynamics.forces.drag]
atmosphere = "exponential"
reference_density_kg_per_m3 = 3.725e-12
reference_altitude_m = 400e3
scale_height_m = 58515.0
"#;

fn final_states(text: &str) -> Vec<[f64; 6]> {
    let scenario = Scenario::from_toml(text, "case.toml", Path::new(".")).unwrap();
    let mut sim = build_simulation(&scenario).unwrap();
    sim.run(&mut NullRecorder, &mut |_| {}).unwrap();
    sim.states_eci()
        .iter()
        .map(|s| {
            let (p, v) = (s.position_m, s.velocity_mps);
            [p.x, p.y, p.z, v.x, v.y, v.z]
        })
        .collect()
}

fn prepare(text: &str) -> Result<satflock::scenario::Prepared, ScenarioError> {
    Scenario::from_toml(text, "case.toml", Path::new(".")).and_then(|s| s.prepare())
}

/// With drag and SRP off, the force-set path equals today's `model = "j2"` bit for bit (fused kernel
/// and generic adaptive path alike); `gravity.model = "point-mass"` equals `model = "two-body"`.
#[test]
fn gravity_alone_through_the_force_table_gives_todays_bits() {
    for integrator in ["rk4", "dop853"] {
        let today = final_states(&case(500e3, integrator, "", ""));
        let table = final_states(&case(
            500e3,
            integrator,
            "[dynamics.forces.gravity]\nmodel = \"j2\"\n",
            "",
        ));
        assert_eq!(today, table, "{integrator}");
        let two_body = final_states(
            &case(500e3, integrator, "", "").replace("model = \"j2\"", "model = \"two-body\""),
        );
        let point_mass = final_states(&case(
            500e3,
            integrator,
            "[dynamics.forces.gravity]\nmodel = \"point-mass\"\n",
            "",
        ));
        assert_eq!(two_body, point_mass, "{integrator}");
        assert_ne!(today, two_body);
    }
}

/// Drag on the fused kernel (RK4, exponential, spherical altitude) and on the generic adaptive path
/// (DOP853, rtol 1e-10) differ by no more than the two integrators differ without drag (the RK4
/// truncation error of a 5 s step, well under a millimetre here; drag adds a smooth force of 1e-7
/// m/s^2, which changes that error by far less than 10 %), and drag really moves the satellites:
/// every one ends lower (ECI radius) than without drag, by metres (`da/dt = -rho B sqrt(mu a)`, about
/// 3 m over 3000 s for the smallest area). The names of the path and of the force set say which ran.
#[test]
fn drag_moves_every_satellite_and_both_paths_agree() {
    let areas = "drag_area_m2 = [0.01, 0.015, 0.02, 0.025, 0.03, 0.035]";
    let fused_text = case(400e3, "rk4", EXPONENTIAL_DRAG, areas);
    let generic_text = case(400e3, "dop853", EXPONENTIAL_DRAG, areas);
    let fused = final_states(&fused_text);
    let generic = final_states(&generic_text);
    let no_drag = final_states(&case(400e3, "rk4", "", ""));
    let no_drag_generic = final_states(&case(400e3, "dop853", "", ""));
    let distance =
        |a: &[f64; 6], b: &[f64; 6]| (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt();
    for i in 0..6 {
        let r = |s: &[f64; 6]| (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt();
        let gap = distance(&fused[i], &generic[i]);
        let gravity_gap = distance(&no_drag[i], &no_drag_generic[i]);
        assert!(
            gap <= 1.1 * gravity_gap + 1e-6,
            "satellite {i}: fused and generic differ by {gap} m with drag, {gravity_gap} m without"
        );
        let sink = r(&no_drag[i]) - r(&fused[i]);
        assert!(
            sink > 1.0,
            "satellite {i}: drag lowered it by only {sink} m"
        );
    }
    let scenario = Scenario::from_toml(&fused_text, "case.toml", Path::new(".")).unwrap();
    let mut sim = build_simulation(&scenario).unwrap();
    sim.run(&mut NullRecorder, &mut |_| {}).unwrap();
    assert_eq!(
        sim.stage_timings().propagation_path,
        "fused RK4 kernel (gravity + exponential drag)"
    );
    let forces = sim.config().dynamics.forces().unwrap().summary();
    assert_eq!(forces.models.len(), 2, "{forces:?}");
    assert!(
        forces.models[1].starts_with("drag (exponential"),
        "{forces:?}"
    );
    let scenario = Scenario::from_toml(&generic_text, "case.toml", Path::new(".")).unwrap();
    let sim = build_simulation(&scenario).unwrap();
    assert_eq!(
        sim.stage_timings().propagation_path,
        "generic per-satellite stepper"
    );
}

/// The satellites of larger ballistic coefficient sink faster and move ahead along-track relative to
/// those of smaller (the differential drag of Leonard et al. 1989): after 3000 s the satellite with
/// 3.5x the area of another has lost more orbital energy.
#[test]
fn larger_ballistic_coefficients_lose_more_energy() {
    let areas = "drag_area_m2 = [0.01, 0.015, 0.02, 0.025, 0.03, 0.035]";
    let with = final_states(&case(400e3, "rk4", EXPONENTIAL_DRAG, areas));
    let without = final_states(&case(400e3, "rk4", "", ""));
    let mu = satflock::orbit::EarthModel::WGS84_EGM96.mu_m3_s2;
    let energy = |s: &[f64; 6]| {
        let r = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt();
        0.5 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]) - mu / r
    };
    let lost: Vec<f64> = (0..6)
        .map(|i| energy(&without[i]) - energy(&with[i]))
        .collect();
    for w in lost.windows(2) {
        assert!(
            w[1] > w[0],
            "energy lost not increasing with area: {lost:?}"
        );
    }
    // Orbit-averaged loss rate dE/dt = -rho B v^3 / 2 with v^2 = mu/a: the ratio of the losses of the
    // largest and smallest areas is the ratio of their areas (same mass and C_d), to the few per cent
    // by which the satellites' densities differ (their altitudes differ by up to 300 m, H = 58.5 km).
    let ratio = lost[5] / lost[0];
    assert!((ratio / 3.5 - 1.0).abs() < 0.03, "loss ratio {ratio}");
}

/// A satellite that sinks below the atmosphere's floor stops the run as diverged, naming the
/// satellite, the time and the altitude (101 km, a large area: it falls within minutes).
#[test]
fn the_atmosphere_floor_stops_the_run() {
    let text = case(
        101e3,
        "rk4",
        "[dynamics.forces.drag]\natmosphere = \"exponential-table\"\n",
        "drag_area_m2 = 0.5",
    )
    .replace("duration_s = 3000.0", "duration_s = 20000.0");
    let scenario = Scenario::from_toml(&text, "case.toml", Path::new(".")).unwrap();
    let mut sim = build_simulation(&scenario).unwrap();
    match sim.run(&mut NullRecorder, &mut |_| {}) {
        Err(SimError::Diverged {
            reason:
                Divergence::BelowAtmosphere {
                    altitude_m,
                    floor_m,
                },
            time_s,
            ..
        }) => {
            assert!(
                altitude_m < floor_m && floor_m == 100e3,
                "{altitude_m} {floor_m}"
            );
            assert!(time_s > 0.0 && time_s < 20000.0);
        }
        other => panic!("expected a stop below the floor, got {other:?}"),
    }
}

/// Bad force parameters and property keys are refused at load with the key and what is allowed.
#[test]
fn bad_force_parameters_are_refused_naming_the_key() {
    let cases = [
        (
            EXPONENTIAL_DRAG.replace("58515.0", "-1.0"),
            "drag_area_m2 = 0.01",
            "dynamics.forces.drag.scale_height_m",
        ),
        (EXPONENTIAL_DRAG.to_string(), "", "satellites.drag_area_m2"),
        (
            EXPONENTIAL_DRAG.to_string(),
            "drag_area_m2 = -0.1",
            "drag_area_m2",
        ),
        (
            EXPONENTIAL_DRAG.to_string(),
            "drag_area_m2 = [0.1, 0.1]",
            "satellites.drag_area_m2",
        ),
        (
            String::new(),
            "drag_area_m2 = 0.1",
            "satellites.drag_area_m2",
        ),
        (
            "[dynamics.forces.srp]\nshadow = \"conical\"\n".into(),
            "srp_area_m2 = 0.1\nreflectivity_coefficient = 3.0",
            "reflectivity_coefficient",
        ),
        (
            "[dynamics.forces.gravity]\nmodel = \"zonal\"\ndegree = 40\n".into(),
            "",
            "dynamics.forces.gravity.degree",
        ),
        (
            "[dynamics.forces.third_body]\nbodies = [\"sun\", \"sun\"]\n".into(),
            "",
            "dynamics.forces.third_body.bodies",
        ),
        (
            "[dynamics.forces.satellite]\nmass_kg = 1.0\n".into(),
            "",
            "dynamics.forces.satellite",
        ),
    ];
    for (forces, satellites, key) in cases {
        let text = case(400e3, "rk4", &forces, satellites);
        match prepare(&text) {
            Err(e @ ScenarioError::Invalid { .. }) => {
                let ScenarioError::Invalid {
                    file,
                    key: got,
                    allowed,
                    ..
                } = &e
                else {
                    unreachable!("matched above")
                };
                assert_eq!(file, "case.toml");
                assert!(got.contains(key), "{key}: got key {got}: {e}");
                assert!(!allowed.is_empty(), "{key}: {e}");
                assert!(e.to_string().contains("allowed"), "{key}: {e}");
            }
            other => panic!("{key}: expected an Invalid error, got {:?}", other.err()),
        }
    }
    // A force table on a relative model is refused.
    let text = case(400e3, "rk4", EXPONENTIAL_DRAG, "drag_area_m2 = 0.01")
        .replace("model = \"j2\"", "model = \"hcw\"");
    assert!(matches!(
        prepare(&text),
        Err(ScenarioError::Invalid { key, .. }) if key == "dynamics.forces"
    ));
}
