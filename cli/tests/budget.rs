//! `satflock budget`: the table and `--json` end to end (the default second satellite has twice the
//! drag area, so its differential drag equals satellite 1's drag), and every bad value exits 2 naming
//! its flag and the allowed range.

mod common;
use common::{satflock, stderr};

const ORBIT: [&str; 9] = [
    "budget",
    "--altitude-km",
    "400",
    "--inclination-deg",
    "51.6",
    "--mass-kg",
    "100",
    "--drag-area-m2",
    "1",
];

fn json(extra: &[&str]) -> serde_json::Value {
    let output = satflock()
        .args(ORBIT)
        .args(extra)
        .arg("--json")
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    serde_json::from_slice(&output.stdout).unwrap()
}

fn drag(budget: &serde_json::Value) -> (f64, f64) {
    let row = &budget["terms"][5];
    assert_eq!(row["term"], "drag");
    (
        row["acceleration_mps2"].as_f64().unwrap(),
        row["differential_acceleration_mps2"].as_f64().unwrap(),
    )
}

#[test]
fn budget_table_and_json() {
    let output = satflock().args(ORBIT).output().unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let text = String::from_utf8(output.stdout).unwrap();
    let rows: Vec<&str> = text
        .lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| ---"))
        .collect();
    assert_eq!(rows.len(), 11, "{text}");
    assert!(rows[0].contains("drift per day [m]"));
    let terms: Vec<&str> = rows[1..]
        .iter()
        .map(|r| r.split('|').nth(1).unwrap().trim())
        .collect();
    assert_eq!(
        terms,
        [
            "J2",
            "J3",
            "J4",
            "J5",
            "J6",
            "drag",
            "srp",
            "sun",
            "moon",
            "hcw-linearisation"
        ]
    );
    assert!(rows[10].contains("| — |"), "{}", rows[10]);

    // Twice the area by default: the difference of the ballistic coefficients is satellite 1's.
    let (absolute, differential) = drag(&json(&[]));
    assert!((differential / absolute - 1.0).abs() < 1e-3);
    // Equal satellites on one orbit: (almost) no differential drag, and no drag drift.
    let equal = json(&["--drag-area-2-m2", "1"]);
    let (absolute, differential) = drag(&equal);
    assert!(differential < 1e-3 * absolute, "{differential} {absolute}");
    assert!(equal["terms"][5]["drift_per_day_m"].as_f64().unwrap() < 1e-3);
    let radial = json(&["--direction", "radial", "--atmosphere", "exponential-table"]);
    assert_eq!(radial["direction"], "radial");
    assert_eq!(radial["atmosphere"], "exponential-table");
}

#[test]
fn budget_bad_values_exit_2_naming_the_flag() {
    for (flag, value, allowed) in [
        ("--altitude-km", "99", "100 to 2000 km"),
        ("--altitude-km", "2500", "100 to 2000 km"),
        ("--inclination-deg", "181", "0 to 180 deg"),
        ("--separation-m", "0", "at most 100000 m"),
        ("--separation-m", "1e6", "at most 100000 m"),
        ("--mass-kg", "-1", "a mass > 0 kg"),
        ("--drag-area-m2", "-1", "an area >= 0 m^2"),
        ("--drag-area-2-m2", "NaN", "an area >= 0 m^2"),
        ("--srp-area-2-m2", "-3", "an area >= 0 m^2"),
        ("--drag-coefficient", "11", "from 0 to 10"),
        ("--reflectivity-coefficient", "2.5", "from 0 to 2"),
        ("--epoch-utc", "yesterday", "ISO 8601"),
    ] {
        let mut args: Vec<&str> = ORBIT.to_vec();
        match args.iter().position(|a| *a == flag) {
            Some(i) => args[i + 1] = value,
            None => args.extend([flag, value]),
        }
        let output = satflock().args(&args).output().unwrap();
        let message = stderr(&output);
        assert_eq!(output.status.code(), Some(2), "{flag} {value}: {message}");
        assert!(
            message.contains(flag) && message.contains(allowed),
            "{flag} {value}: {message}"
        );
    }
}
