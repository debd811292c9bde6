//! `satflock propagate --forces FILE.toml`: the force file of `docs/dynamics.md` end to end. A circular
//! orbit under drag loses altitude at the orbit-averaged analytic rate; a force file of gravity alone
//! gives the `--gravity` output byte for byte; bad force files exit 2 naming the file and the key.

mod common;
use common::{satflock, scratch_dir};

fn propagate(dir: &std::path::Path, forces: Option<&str>, name: &str) -> (i32, String, String) {
    let out = dir.join(format!("{name}.csv"));
    let mut command = satflock();
    command.args([
        "propagate",
        "--elements",
        "6778137,0,51.6,0,0,0",
        "--duration-s",
        "5400",
        "--output-step-s",
        "5400",
        "--integrator",
        "dop853",
        "--step-s",
        "60",
        "--epoch-utc",
        "2026-03-20T12:00:00Z",
        "--out",
    ]);
    command.arg(&out);
    if let Some(text) = forces {
        let path = dir.join(format!("{name}.toml"));
        std::fs::write(&path, text).unwrap();
        command.arg("--forces").arg(&path);
    }
    let output = command.output().unwrap();
    (
        output.status.code().unwrap_or(-1),
        std::fs::read_to_string(&out).unwrap_or_default(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

fn final_radius_m(csv: &str) -> f64 {
    let last: Vec<f64> = csv
        .lines()
        .last()
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    (last[1] * last[1] + last[2] * last[2] + last[3] * last[3]).sqrt()
}

#[test]
fn val_propagate_forces_file_drag_decay_and_gravity_alone() {
    let dir = scratch_dir("propagate-forces");
    let (code, gravity_flag, _) = propagate(&dir, None, "flag");
    assert_eq!(code, 0);
    let (code, gravity_file, stderr) = propagate(&dir, Some("[gravity]\nmodel = \"j2\"\n"), "file");
    assert_eq!(code, 0, "{stderr}");
    assert_eq!(gravity_flag, gravity_file);

    // Point mass and drag only, no co-rotation, on a circular 400 km orbit: the along-track drag
    // a_y = -rho B v^2 / 2 is constant to first order, and the forced HCW solution (Clohessy &
    // Wiltshire 1960) gives the radial offset x(t) = (2 a_y / n^2)(n t - sin n t) from the drag-free
    // orbit, i.e. x(t) = (da/dt)(t - sin(n t)/n) with da/dt = -rho B sqrt(mu a). Neglected: the
    // 17 m change of altitude (density 3e-4 relative) and second-order terms (x/a ~ 3e-6).
    let drag = "[gravity]\nmodel = \"point-mass\"\n[drag]\natmosphere = \"exponential\"\n\
                reference_density_kg_per_m3 = 3.725e-12\nreference_altitude_m = 400e3\n\
                scale_height_m = 58515.0\ncorotation = false\n\
                [satellite]\nmass_kg = 4.0\ndrag_area_m2 = 0.03\ndrag_coefficient = 2.2\n";
    let (code, point_mass, _) = propagate(&dir, Some("[gravity]\nmodel = \"point-mass\"\n"), "pm");
    assert_eq!(code, 0);
    let (code, decayed, stderr) = propagate(&dir, Some(drag), "drag");
    assert_eq!(code, 0, "{stderr}");
    let mu: f64 = 3.986004418e14;
    let a = 6_778_137.0_f64;
    let rate = -3.725e-12 * (2.2 * 0.03 / 4.0) * (mu * a).sqrt();
    let n = (mu / (a * a * a)).sqrt();
    let t = 5400.0;
    let expected = rate * (t - (n * t).sin() / n);
    let got = final_radius_m(&decayed) - final_radius_m(&point_mass);
    assert!(
        (got / expected - 1.0).abs() < 0.005,
        "radius change {got} m, analytic {expected} m"
    );
}

#[test]
fn val_propagate_bad_force_files_exit_2_naming_the_key() {
    let dir = scratch_dir("propagate-forces-bad");
    for (text, key) in [
        (
            "[drag]\natmosphere = \"exponential\"\n",
            "reference_density_kg_per_m3",
        ),
        (
            "[drag]\natmosphere = \"harris-priester\"\n[satellite]\nmass_kg = 4.0\n",
            "satellite.drag_area_m2",
        ),
        ("[drag]\natmosphere = \"fog\"\n", "atmosphere"),
        (
            "[srp]\nshadow = \"conical\"\n[satellite]\nmass_kg = 4.0\nsrp_area_m2 = -1.0\n",
            "srp_area_m2",
        ),
        (
            "[gravity]\nmodel = \"zonal\"\ndegree = 99\n",
            "gravity.degree",
        ),
        (
            "[satellite]\ndrag_area_m2 = 0.1\n",
            "satellite.drag_area_m2",
        ),
    ] {
        let (code, csv, stderr) = propagate(&dir, Some(text), "bad");
        assert_eq!(code, 2, "{text}: {stderr}");
        assert!(csv.is_empty(), "{text}: wrote {csv}");
        assert!(
            stderr.contains("bad.toml") && stderr.contains(key),
            "{text}: {stderr}"
        );
    }
}
