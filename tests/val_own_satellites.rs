//! Bring your own satellites (issue 27): a swarm and a reference orbit started from inertial states,
//! OEM, OMM and TLE files. Checked against things independent of the code under test: the same swarm
//! given in Hill coordinates, the first run's own trajectory (an OEM round trip to a later epoch, to
//! the interpolation error), SGP4 run directly on the element sets, and the files' epochs.

use std::path::{Path, PathBuf};

use satflock::orbit::{CartesianState, RelativeStateHill};
use satflock::orbit_files;
use satflock::run::{build_simulation, run_scenario};
use satflock::scenario::Scenario;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("satflock-own-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Five satellites within 300 m of a 550 km reference, `initial` and `model` as given.
fn swarm(model: &str, initial: &str, extra: &str) -> String {
    format!(
        "name = \"own\"\nseed = 3\nduration_s = 120.0\nrecord_interval_s = 60.0\n\
         epoch_utc = \"2026-06-01T00:00:00Z\"\n\
         [dynamics]\nmodel = \"{model}\"\nintegrator = \"rk4\"\nstep_s = 1.0\n\
         [reference]\naltitude_m = 550e3\ninclination_deg = 53.0\nraan_deg = 20.0\n\
         [satellites]\ncount = 5\nmass_kg = 6.0\ninitial = {initial}\n\
         [law]\nname = \"none\"\n{extra}"
    )
}

const HILL: [[f64; 6]; 5] = [
    [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [120.0, -40.0, 10.0, 0.01, -0.26, 0.02],
    [-80.0, 210.0, -30.0, -0.03, 0.17, 0.0],
    [15.0, -300.0, 60.0, 0.0, -0.03, -0.05],
    [-50.0, 90.0, 140.0, 0.05, 0.11, 0.01],
];

fn list(frame: &str, states: &[[f64; 6]]) -> String {
    let rows: Vec<String> = states.iter().map(|s| format!("{s:?}")).collect();
    format!(
        "{{ distribution = \"list\", frame = \"{frame}\", states = [{}] }}",
        rows.join(", ")
    )
}

fn scenario(text: &str, dir: &Path) -> Scenario {
    Scenario::from_toml(text, "own.toml", dir).unwrap()
}

fn as_array(s: &CartesianState) -> [f64; 6] {
    s.to_array()
}

/// |a − b| over the six components, positions and velocities scaled apart: (position m, velocity m/s).
fn gap(a: &RelativeStateHill, b: &[f64; 6]) -> (f64, f64) {
    let dp = (a.position_m - nalgebra::Vector3::new(b[0], b[1], b[2])).norm();
    let dv = (a.velocity_mps - nalgebra::Vector3::new(b[3], b[4], b[5])).norm();
    (dp, dv)
}

#[test]
fn val_inertial_list_equals_the_same_swarm_in_hill() {
    // The Hill list's EME2000 states at t = 0 (as the engine places them), given back as an
    // `eme2000` list, give the Hill states back to rounding, on an inertial and a linear model.
    let dir = scratch("list");
    for model in ["j2", "hcw"] {
        let hill =
            build_simulation(&scenario(&swarm(model, &list("hill", &HILL), ""), &dir)).unwrap();
        let eci: Vec<[f64; 6]> = hill.states_eci().iter().map(as_array).collect();
        let inertial =
            build_simulation(&scenario(&swarm(model, &list("eme2000", &eci), ""), &dir)).unwrap();
        for (k, (s, h)) in inertial.states_hill().iter().zip(&HILL).enumerate() {
            let (dp, dv) = gap(s, h);
            // Rounding of a 7e6 m position: a few ulp of 7e6 (1 ulp = 9.3e-10 m).
            assert!(
                dp < 1e-7 && dv < 1e-10,
                "{model} satellite {k}: {dp} m, {dv} m/s"
            );
        }
        for (k, (a, b)) in inertial.states_eci().iter().zip(&eci).enumerate() {
            let d: f64 = (0..6)
                .map(|i| (a.to_array()[i] - b[i]).abs())
                .fold(0.0, f64::max);
            assert!(d < 1e-7, "{model} satellite {k}: EME2000 back to {d}");
        }
    }
}

#[test]
fn val_trajectory_eme2000_columns_at_t0_hold_the_states_given() {
    let dir = scratch("columns");
    let reference = build_simulation(&scenario(&swarm("j2", &list("hill", &HILL), ""), &dir))
        .unwrap()
        .states_eci();
    let given: Vec<[f64; 6]> = reference.iter().map(as_array).collect();
    // As a CSV with a sat column (rows out of order) and a frame column.
    let mut csv = String::from("sat,x_m,y_m,z_m,vx_mps,vy_mps,vz_mps,frame\n");
    for k in [3usize, 0, 4, 1, 2] {
        let s = given[k];
        csv.push_str(&format!(
            "{k},{:?},{:?},{:?},{:?},{:?},{:?},eme2000\n",
            s[0], s[1], s[2], s[3], s[4], s[5]
        ));
    }
    std::fs::write(dir.join("states.csv"), csv).unwrap();
    let text = swarm(
        "j2",
        "{ distribution = \"csv\", file = \"states.csv\" }",
        "[output]\nformat = \"csv\"\n",
    );
    let out = dir.join("run");
    run_scenario(&scenario(&text, &dir), &out, &mut |_| {}).unwrap();
    let run = satflock::output::RunData::read(&out).unwrap();
    let tracks = run.inertial_tracks().unwrap();
    for (k, track) in tracks.iter().enumerate() {
        assert_eq!(track.t_s[0], 0.0);
        let s = track.states[0];
        let d: f64 = (0..6)
            .map(|i| (s[i] - given[k][i]).abs() / given[k][i].abs().max(1.0))
            .fold(0.0, f64::max);
        assert!(d < 1e-12, "satellite {k}: relative gap {d}");
    }
}

#[test]
fn val_oem_round_trip_starts_a_new_run_at_a_later_epoch() {
    // Run 1 writes one OEM per satellite every 60 s; run 2 starts from those files 630 s after run
    // 1's epoch (between two samples), its reference orbit satellite 0's OEM. Its initial EME2000
    // states equal run 1's states at 630 s (recorded every 10 s in a twin run) to the interpolation
    // error: Lagrange of degree 5 on 60 s samples, about 3 mm mid-window for this orbit (bound
    // r (nh)^6 3.5/720 ≈ 3.4 mm at 550 km, see tests/val_orbit_files.rs), taken as 1 cm, and
    // velocities to 1e-5 m/s.
    let dir = scratch("oem");
    let first = |interval: &str, oem: bool| {
        let extra = if oem { "[output]\noem = true\n" } else { "" };
        let text = swarm("j2", &list("hill", &HILL), extra)
            .replace("duration_s = 120.0", "duration_s = 1200.0")
            .replace("record_interval_s = 60.0", interval);
        scenario(&text, &dir)
    };
    let coarse = dir.join("coarse");
    run_scenario(
        &first("record_interval_s = 60.0", true),
        &coarse,
        &mut |_| {},
    )
    .unwrap();
    let fine = dir.join("fine");
    run_scenario(
        &first("record_interval_s = 10.0", false),
        &fine,
        &mut |_| {},
    )
    .unwrap();
    let files: Vec<String> = (0..5)
        .map(|k| format!("coarse/oem/sat-{k:05}.oem"))
        .collect();
    let text = format!(
        "name = \"own-oem\"\nseed = 3\nduration_s = 60.0\nrecord_interval_s = 60.0\n\
         epoch_utc = \"2026-06-01T00:10:30Z\"\n\
         [dynamics]\nmodel = \"j2\"\nintegrator = \"rk4\"\nstep_s = 1.0\n\
         [reference]\noem = \"coarse/oem/sat-00000.oem\"\n\
         [satellites]\ncount = 5\nmass_kg = 6.0\nallow_initial_overlap = true\n\
         initial = {{ distribution = \"oem\", files = {files:?} }}\n[law]\nname = \"none\"\n"
    );
    let second = build_simulation(&scenario(&text, &dir)).unwrap();
    let run = satflock::output::RunData::read(&fine).unwrap();
    let tracks = run.inertial_tracks().unwrap();
    for (k, (s, track)) in second.states_eci().iter().zip(&tracks).enumerate() {
        let row = track.t_s.iter().position(|t| *t == 630.0).unwrap();
        let want = track.states[row];
        let s = s.to_array();
        let dp = (0..3).map(|i| (s[i] - want[i]).powi(2)).sum::<f64>().sqrt();
        let dv = (3..6).map(|i| (s[i] - want[i]).powi(2)).sum::<f64>().sqrt();
        assert!(dp < 1e-2 && dv < 1e-5, "satellite {k}: {dp} m, {dv} m/s");
    }
    // Satellite 0 is the reference: at the origin.
    let origin = second.states_hill()[0];
    assert!(origin.position_m.norm() < 1e-6, "{origin:?}");
}

#[test]
fn val_omm_flock_builtin_starts_where_sgp4_says_at_the_files_epoch() {
    let scenario = Scenario::load("omm-flock").unwrap();
    let prepared = scenario.prepare().unwrap();
    // epoch_utc is absent: the file's epoch.
    assert_eq!(
        satflock::time::utc_iso(prepared.epoch),
        "2026-11-30T12:00:00.000000Z"
    );
    let sim = build_simulation(&scenario).unwrap();
    let text = satflock::scenario::builtin::file("omm-flock", "omm-flock.xml").unwrap();
    let sets = orbit_files::parse_omm(text, "omm-flock.xml").unwrap();
    assert_eq!(sets.len(), 12);
    for (k, (s, set)) in sim.states_eci().iter().zip(&sets).enumerate() {
        let want = set.state_eme2000(prepared.epoch).unwrap();
        let dp = (s.position_m - want.position_m).norm();
        assert!(dp < 1e-6, "satellite {k}: {dp} m from SGP4");
    }
    // The reference is satellite 0's own element set (as a TLE); the flock is spread along-track,
    // about 480 m apart (0.004 deg of mean anomaly on a 6.88e6 m orbit).
    let hill = sim.states_hill();
    assert!(hill[0].position_m.norm() < 1e-6, "{:?}", hill[0]);
    for (k, state) in hill.iter().enumerate().skip(1) {
        let spacing_m = state.position_m.y / k as f64;
        assert!(
            (spacing_m - 480.0).abs() < 50.0,
            "satellite {k}: {spacing_m} m apart"
        );
    }
}

/// The omm-flock built-in's OMM and a reference TLE with a different epoch, both without epoch_utc.
#[test]
fn regress_files_of_different_epochs_are_refused_naming_both() {
    let dir = scratch("epochs");
    std::fs::write(
        dir.join("flock.xml"),
        satflock::scenario::builtin::file("omm-flock", "omm-flock.xml").unwrap(),
    )
    .unwrap();
    // The ISS example TLE (2008).
    let tle = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/orbit_files/iss.tle"),
    )
    .unwrap();
    let lines: Vec<&str> = tle.lines().filter(|l| l.starts_with(['1', '2'])).collect();
    let text = format!(
        "name = \"epochs\"\nseed = 1\nduration_s = 60.0\nrecord_interval_s = 60.0\n\
         [reference]\ntle = {lines:?}\n\
         [satellites]\ncount = 12\nmass_kg = 4.0\n\
         initial = {{ distribution = \"omm\", file = \"flock.xml\" }}\n[law]\nname = \"none\"\n"
    );
    let e = match scenario(&text, &dir).prepare() {
        Ok(_) => panic!("accepted files of two epochs"),
        Err(e) => e.to_string(),
    };
    for needle in [
        "epoch_utc",
        "reference.tle",
        "satellites.initial.file",
        "2008-09-20",
        "2026-11-30",
    ] {
        assert!(e.contains(needle), "`{needle}` missing: {e}");
    }
}

#[test]
fn regress_bad_orbit_inputs_are_refused_naming_the_file_and_key() {
    let dir = scratch("bad");
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/orbit_files");
    let iss_tle = std::fs::read_to_string(data.join("iss.tle")).unwrap();
    // A bad checksum: the last digit of line 1 changed.
    let bad_checksum: String = iss_tle
        .lines()
        .map(|l| {
            if l.starts_with('1') {
                let mut l = l.to_string();
                let last = l.pop().unwrap();
                l.push(if last == '0' { '1' } else { '0' });
                l
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    std::fs::write(dir.join("checksum.tle"), bad_checksum).unwrap();
    // An OMM without its EPOCH.
    let omm = std::fs::read_to_string(data.join("iss.omm")).unwrap();
    let no_epoch: String = omm
        .lines()
        .filter(|l| !l.starts_with("EPOCH"))
        .collect::<Vec<_>>()
        .join("\n");
    std::fs::write(dir.join("no-epoch.omm"), no_epoch).unwrap();
    // An OEM whose time axis runs backwards: two data lines swapped.
    let oem = std::fs::read_to_string(data.join("two-objects-2.0.oem")).unwrap();
    let mut lines: Vec<&str> = oem.lines().collect();
    let data_rows: Vec<usize> = (0..lines.len())
        .filter(|&i| lines[i].starts_with("20"))
        .collect();
    lines.swap(data_rows[0], data_rows[1]);
    std::fs::write(dir.join("reversed.oem"), lines.join("\n")).unwrap();
    std::fs::write(dir.join("ok.oem"), &oem).unwrap();
    // A file past the size limit (sparse: nothing is written), e.g. 10^9 lines.
    std::fs::File::create(dir.join("huge.tle"))
        .unwrap()
        .set_len(orbit_files::MAX_ORBIT_FILE_BYTES + 1)
        .unwrap();
    let base = |initial: &str, count: usize, epoch: &str| {
        format!(
            "name = \"bad\"\nseed = 1\nduration_s = 60.0\nrecord_interval_s = 60.0\n{epoch}\
             [reference]\naltitude_m = 500e3\ninclination_deg = 51.6\n\
             [satellites]\ncount = {count}\nmass_kg = 4.0\ninitial = {initial}\n\
             [law]\nname = \"none\"\n"
        )
    };
    let cases = [
        (
            base("{ distribution = \"tle\", file = \"checksum.tle\" }", 1, ""),
            vec!["satellites.initial.file", "checksum.tle", "checksum"],
        ),
        (
            base("{ distribution = \"omm\", file = \"no-epoch.omm\" }", 1, ""),
            vec!["satellites.initial.file", "no-epoch.omm", "EPOCH"],
        ),
        (
            base("{ distribution = \"oem\", files = [\"reversed.oem\"] }", 2, ""),
            vec!["satellites.initial.files", "reversed.oem"],
        ),
        (
            base(
                "{ distribution = \"oem\", files = [\"ok.oem\"] }",
                2,
                "epoch_utc = \"2030-01-01T00:00:00Z\"\n",
            ),
            vec!["satellites.initial.files", "ok.oem", "outside its ephemeris"],
        ),
        (
            // LEO-A has no state between 12:09 and 12:21 (a gap between its two segments).
            base(
                "{ distribution = \"oem\", files = [\"ok.oem\"] }",
                2,
                "epoch_utc = \"2026-03-20T12:15:00Z\"\n",
            ),
            vec![
                "satellites.initial.files",
                "LEO-A",
                "outside its ephemeris",
                "12:21:00",
            ],
        ),
        (
            base(
                "{ distribution = \"list\", frame = \"itrf\", states = [[7e6, 0.0, 0.0, 0.0, 7.5e3, 0.0]] }",
                1,
                "",
            ),
            vec!["itrf", "eme2000"],
        ),
        (
            base("{ distribution = \"tle\", file = \"../outside.tle\" }", 1, ""),
            vec!["satellites.initial.file", "outside.tle"],
        ),
        (
            base("{ distribution = \"tle\", file = \"huge.tle\" }", 1, ""),
            vec!["satellites.initial.file", "huge.tle", "bytes"],
        ),
        (
            base("{ distribution = \"oem\", files = [\"ok.oem\"] }", 5, ""),
            vec!["satellites.initial.files", "holds 2 objects but satellites.count = 5"],
        ),
    ];
    for (text, needles) in cases {
        let e = match Scenario::from_toml(&text, "bad.toml", &dir).and_then(|s| s.prepare()) {
            Ok(_) => panic!("accepted: {text}"),
            Err(e) => e.to_string(),
        };
        for needle in needles {
            assert!(e.contains(needle), "`{needle}` missing: {e}");
        }
    }
}

/// `count` satellites in a 400 m ball under J2 + exponential drag, `properties` added to
/// `[satellites]` (which has no mass_kg of its own).
fn with_drag(count: usize, properties: &str) -> String {
    format!(
        "name = \"props\"\nseed = 11\nduration_s = 60.0\nrecord_interval_s = 60.0\n\
         [dynamics]\nmodel = \"j2\"\nintegrator = \"rk4\"\nstep_s = 5.0\n\
         [dynamics.forces.gravity]\nmodel = \"j2\"\n\
         [dynamics.forces.drag]\natmosphere = \"exponential\"\nreference_density_kg_per_m3 = 3.725e-12\n\
         reference_altitude_m = 400e3\nscale_height_m = 58515.0\n\
         [reference]\naltitude_m = 400e3\ninclination_deg = 51.6\n\
         [satellites]\ncount = {count}\n{properties}\n\
         initial = {{ distribution = \"sphere\", radius_m = 400.0 }}\n[law]\nname = \"none\"\n"
    )
}

#[test]
fn val_properties_file_gives_each_satellite_its_row() {
    let dir = scratch("props-file");
    std::fs::write(
        dir.join("props.csv"),
        "sat,mass_kg,drag_area_m2,drag_coefficient,radius_m,srp_area_m2\n\
         2,6.0,0.03,2.3,0.15,0.02\n0,4.0,0.01,2.1,0.1,0.02\n1,5.0,0.02,2.2,0.12,0.02\n",
    )
    .unwrap();
    let prepared = scenario(&with_drag(3, "properties_file = \"props.csv\""), &dir)
        .prepare()
        .unwrap();
    let got: Vec<[f64; 4]> = prepared
        .satellites
        .iter()
        .map(|s| {
            let p = s.properties;
            [p.mass_kg, p.drag_area_m2, p.drag_coefficient, s.radius_m]
        })
        .collect();
    assert_eq!(
        got,
        vec![
            [4.0, 0.01, 2.1, 0.1],
            [5.0, 0.02, 2.2, 0.12],
            [6.0, 0.03, 2.3, 0.15]
        ]
    );
    // srp_area_m2 is read although no SRP model acts: said in the warnings.
    assert!(
        prepared.warnings.iter().any(|w| w.contains("srp_area_m2")),
        "{:?}",
        prepared.warnings
    );
    // A property given both as a key and as a column, and a missing row, are refused.
    for (properties, needle) in [
        (
            "properties_file = \"props.csv\"\nmass_kg = 5.0",
            "key `satellites.mass_kg`",
        ),
        (
            "properties_file = \"props.csv\"",
            "has no row for satellite 3",
        ),
    ] {
        let count = if needle.contains("row") { 4 } else { 3 };
        let e = match scenario(&with_drag(count, properties), &dir).prepare() {
            Ok(_) => panic!("accepted {properties}"),
            Err(e) => e.to_string(),
        };
        assert!(e.contains(needle), "{e}");
    }
}

#[test]
fn val_drawn_properties_follow_their_distribution_and_the_seed() {
    // 2000 satellites: the uniform draws' mean within 4 standard errors of (min + max)/2, every
    // draw inside its bounds, the truncated normal's inside [min, max]; the same seed gives the same
    // draws, another seed other draws.
    let dir = scratch("props-drawn");
    let n = 2000;
    let properties = "mass_kg = { distribution = \"uniform\", min = 4.0, max = 6.0 }\n\
                      drag_area_m2 = { distribution = \"normal\", mean = 0.02, sigma = 0.005, min = 0.012, max = 0.03 }";
    let text = with_drag(n, properties).replace("radius_m = 400.0", "radius_m = 4000.0");
    let draws = |seed: u64| -> (Vec<f64>, Vec<f64>) {
        let mut s = scenario(&text, &dir);
        s.file.seed = seed;
        let p = s.prepare().unwrap();
        p.satellites
            .iter()
            .map(|s| (s.properties.mass_kg, s.properties.drag_area_m2))
            .unzip()
    };
    let (mass, area) = draws(11);
    assert!(mass.iter().all(|m| (4.0..=6.0).contains(m)));
    assert!(area.iter().all(|a| (0.012..=0.03).contains(a)));
    let mean = mass.iter().sum::<f64>() / n as f64;
    let standard_error = (2.0f64 / 12f64.sqrt()) / (n as f64).sqrt();
    assert!((mean - 5.0).abs() < 4.0 * standard_error, "mean {mean}");
    let area_mean = area.iter().sum::<f64>() / n as f64;
    // Truncation at about -1.6 and +2 sigma moves the mean by less than 0.1 sigma.
    assert!((area_mean - 0.02).abs() < 0.001, "area mean {area_mean}");
    assert_eq!(draws(11), (mass.clone(), area.clone()));
    let (other, _) = draws(12);
    assert!(other.iter().zip(&mass).filter(|(a, b)| a == b).count() < 5);
    let e = match scenario(
        &with_drag(3, "mass_kg = { distribution = \"normal\", mean = 9.0, sigma = 1.0, min = 4.0, max = 6.0 }"),
        &dir,
    )
    .prepare()
    {
        Ok(_) => panic!("accepted a mean outside its bounds"),
        Err(e) => e.to_string(),
    };
    assert!(e.contains("satellites.mass_kg.mean"), "{e}");
}
