//! The OEM and CZML exports end to end, checked against the run's own `trajectory.csv` read here with the
//! `csv` crate: the OEM's keywords and their order (CCSDS 502.0-B-2, OEM 2.0 KVN), its units (the CSV's
//! metres divided by 1000, to the printed precision), a removed satellite's segment ending at its last
//! row; the CZML's structure (JSON array, `document` first, samples per satellite after decimation);
//! `propagate --oem`; `[output] oem = true`; and a run directory holding exports being reusable.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use satflock::scenario::builtin::BUILTINS;

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_satflock"));
    // 1 700 000 000 s after 1970-01-01T00:00:00Z is 2023-11-14T22:13:20Z.
    c.env("SOURCE_DATE_EPOCH", "1700000000");
    c
}

const CREATION_DATE: &str = "2023-11-14T22:13:20.000000";

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("satflock-export-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn ok(o: Output) -> Output {
    assert!(
        o.status.success(),
        "exit {:?}: {}",
        o.status.code(),
        String::from_utf8_lossy(&o.stderr)
    );
    o
}

/// `free-drift` cut to 6 satellites and 600 s, satellite 2 removed at 200 s, with `extra` appended.
fn scenario(dir: &Path, extra: &str) -> PathBuf {
    let mut text = BUILTINS
        .iter()
        .find(|b| b.name == "free-drift")
        .unwrap()
        .toml
        .to_string();
    for (from, to) in [
        ("count = 50", "count = 6"),
        ("duration_s = 5800.0", "duration_s = 600.0"),
    ] {
        assert!(text.contains(from));
        text = text.replacen(from, to, 1);
    }
    text += "\n[[events]]\ntime_s = 200.0\naction = \"remove-satellite\"\nsatellite = 2\n";
    text += extra;
    let path = dir.join("scenario.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// A run of [`scenario`] into `dir/run`.
fn run(dir: &Path, extra: &str) -> PathBuf {
    let out = dir.join("run");
    ok(bin()
        .arg("run")
        .arg(scenario(dir, extra))
        .arg("--out")
        .arg(&out)
        .arg("--quiet")
        .output()
        .unwrap());
    out
}

/// One trajectory row: its UTC text and the inertial state \[m, m/s\].
struct Row {
    t_s: f64,
    time_utc: String,
    state: [f64; 6],
}

/// `trajectory.csv` by satellite, read with the `csv` crate.
fn trajectory(run: &Path) -> BTreeMap<usize, Vec<Row>> {
    let mut reader = csv::Reader::from_path(run.join("trajectory.csv")).unwrap();
    let header = reader.headers().unwrap().clone();
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    let names = [
        "x_eme2000_m",
        "y_eme2000_m",
        "z_eme2000_m",
        "vx_eme2000_mps",
        "vy_eme2000_mps",
        "vz_eme2000_mps",
    ];
    let mut by_id: BTreeMap<usize, Vec<Row>> = BTreeMap::new();
    for record in reader.records() {
        let r = record.unwrap();
        by_id
            .entry(r[col("id")].parse().unwrap())
            .or_default()
            .push(Row {
                t_s: r[col("t_s")].parse().unwrap(),
                time_utc: r[col("time_utc")].to_string(),
                state: names.map(|n| r[col(n)].parse().unwrap()),
            });
    }
    by_id
}

/// An OEM segment: its metadata keywords in order (comments left out) and its data lines.
struct Segment {
    keywords: Vec<(String, String)>,
    data: Vec<Vec<String>>,
}

/// Splits an OEM into its header keywords and segments, checking the section markers on the way.
fn parse_oem(text: &str) -> (Vec<(String, String)>, Vec<Segment>) {
    let mut header = Vec::new();
    let mut segments: Vec<Segment> = Vec::new();
    let mut in_meta = false;
    for line in text.lines().map(str::trim) {
        if line.is_empty() || line.starts_with("COMMENT ") {
            continue;
        }
        match line {
            "META_START" => {
                assert!(!in_meta, "META_START inside metadata");
                in_meta = true;
                segments.push(Segment {
                    keywords: Vec::new(),
                    data: Vec::new(),
                });
            }
            "META_STOP" => {
                assert!(in_meta, "META_STOP without META_START");
                in_meta = false;
            }
            _ => {
                let kv = line
                    .split_once(" = ")
                    .map(|(k, v)| (k.to_string(), v.to_string()));
                match (segments.last_mut(), in_meta, kv) {
                    (None, _, Some(kv)) => header.push(kv),
                    (Some(s), true, Some(kv)) => s.keywords.push(kv),
                    (Some(s), false, None) => s
                        .data
                        .push(line.split_whitespace().map(String::from).collect()),
                    _ => panic!("unexpected line `{line}`"),
                }
            }
        }
    }
    assert!(!in_meta, "unterminated metadata");
    (header, segments)
}

fn keys(kv: &[(String, String)]) -> Vec<&str> {
    kv.iter().map(|(k, _)| k.as_str()).collect()
}

fn value<'a>(kv: &'a [(String, String)], key: &str) -> &'a str {
    &kv.iter().find(|(k, _)| k == key).unwrap().1
}

/// The standard's keyword order, mandatory ones and the interpolation pair we write.
const HEADER_KEYS: [&str; 3] = ["CCSDS_OEM_VERS", "CREATION_DATE", "ORIGINATOR"];
const META_KEYS: [&str; 9] = [
    "OBJECT_NAME",
    "OBJECT_ID",
    "CENTER_NAME",
    "REF_FRAME",
    "TIME_SYSTEM",
    "START_TIME",
    "STOP_TIME",
    "INTERPOLATION",
    "INTERPOLATION_DEGREE",
];

/// Every OEM state equals the CSV row in km and km/s to the printed precision (half of 1e-9 km and of
/// 1e-12 km/s, plus the rounding of the division).
fn assert_states_match(segment: &Segment, rows: &[Row]) {
    assert_eq!(segment.data.len(), rows.len());
    for (line, row) in segment.data.iter().zip(rows) {
        assert_eq!(line.len(), 7, "{line:?}");
        // The OEM's epochs are the CCSDS time code: `time_utc` without its zone letter.
        assert_eq!(line[0], row.time_utc.trim_end_matches('Z'));
        for k in 0..6 {
            let printed: f64 = line[k + 1].parse().unwrap();
            let tolerance = if k < 3 { 0.5e-9 } else { 0.5e-12 } * (1.0 + 1e-6);
            let expected = row.state[k] / 1000.0;
            assert!(
                (printed - expected).abs() <= tolerance + expected.abs() * 1e-15,
                "{} column {k}: {printed} vs {expected}",
                row.time_utc
            );
        }
    }
}

#[test]
fn val_oem_of_a_run_has_the_standard_keywords_in_order_and_the_csv_states_in_km() {
    let dir = temp_dir("oem");
    let out = run(&dir, "\n[output]\noem = true\n");
    // `[output] oem` writes one file per satellite; the single multi-object file (not CCSDS-compliant)
    // only when asked for.
    assert!(out.join("oem").join("sat-00000.oem").exists() && !out.join("swarm.oem").exists());
    let o = ok(bin()
        .args(["export", "oem"])
        .arg(&out)
        .arg("--single-file")
        .output()
        .unwrap());
    assert!(String::from_utf8_lossy(&o.stderr).contains("6 satellites"));
    let text = std::fs::read_to_string(out.join("swarm.oem")).unwrap();
    assert!(text.contains("NOT CCSDS-COMPLIANT"));
    assert!(text.starts_with("CCSDS_OEM_VERS = 2.0\n"));
    let (header, segments) = parse_oem(&text);
    assert_eq!(keys(&header), HEADER_KEYS);
    assert_eq!(value(&header, "CREATION_DATE"), CREATION_DATE);
    assert_eq!(value(&header, "ORIGINATOR"), "satflock");
    let rows = trajectory(&out);
    assert_eq!(segments.len(), 6);
    assert_eq!(rows.len(), 6);
    for (segment, (id, rows)) in segments.iter().zip(&rows) {
        assert_eq!(keys(&segment.keywords), META_KEYS);
        let kv = &segment.keywords;
        assert_eq!(value(kv, "OBJECT_NAME"), format!("SAT-{id:05}"));
        assert_eq!(value(kv, "CENTER_NAME"), "EARTH");
        assert_eq!(value(kv, "REF_FRAME"), "EME2000");
        assert_eq!(value(kv, "TIME_SYSTEM"), "UTC");
        assert_eq!(value(kv, "INTERPOLATION"), "LAGRANGE");
        assert_eq!(value(kv, "INTERPOLATION_DEGREE"), "5");
        assert_eq!(
            value(kv, "START_TIME"),
            rows[0].time_utc.trim_end_matches('Z')
        );
        assert_eq!(
            value(kv, "STOP_TIME"),
            rows.last().unwrap().time_utc.trim_end_matches('Z')
        );
        assert_states_match(segment, rows);
    }
    // The removed satellite's segment stops at its last row, before the run's end.
    let removed = &rows[&2];
    assert!(
        removed.last().unwrap().t_s <= 200.0,
        "satellite 2 was removed at 200 s"
    );
    assert_eq!(rows[&0].last().unwrap().t_s, 600.0);
    // The frame is said in words.
    assert!(text.contains("COMMENT Reference frame: EME2000"));

    // Per satellite (the default): one file and one segment each, the same states; version 3.0 adds a
    // MESSAGE_ID to the header.
    ok(bin()
        .args(["export", "oem"])
        .arg(&out)
        .args(["--oem-version", "3.0", "--out"])
        .arg(dir.join("v3"))
        .output()
        .unwrap());
    let v3 = std::fs::read_to_string(dir.join("v3").join("sat-00001.oem")).unwrap();
    assert!(v3.starts_with("CCSDS_OEM_VERS = 3.0\n"));
    assert!(v3.contains("\nMESSAGE_ID = SATFLOCK-"));
    for (id, rows) in &rows {
        let text =
            std::fs::read_to_string(out.join("oem").join(format!("sat-{id:05}.oem"))).unwrap();
        let (header, segments) = parse_oem(&text);
        assert_eq!(keys(&header), HEADER_KEYS);
        assert_eq!(segments.len(), 1);
        assert_states_match(&segments[0], rows);
    }
    // A run directory holding the exports (oem/ folder included) is a previous run's: reused.
    ok(bin().arg("export").arg("czml").arg(&out).output().unwrap());
    ok(bin()
        .arg("run")
        .arg(dir.join("scenario.toml"))
        .arg("--out")
        .arg(&out)
        .arg("--quiet")
        .output()
        .unwrap());
    assert!(!out.join("swarm.oem").exists() && !out.join("swarm.czml").exists());
    assert!(out.join("oem").join("sat-00000.oem").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn val_czml_is_a_document_packet_then_one_packet_per_kept_satellite() {
    let dir = temp_dir("czml");
    let out = run(&dir, "");
    let rows = trajectory(&out);
    let file = dir.join("swarm.czml");
    let o = ok(bin()
        .args(["export", "czml"])
        .arg(&out)
        .args(["--max-satellites", "3", "--max-samples", "10", "--out"])
        .arg(&file)
        .output()
        .unwrap());
    // 31 recorded times (0 to 600 s every 20 s): at most 10 samples means one in 4, 8 kept.
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains("3 of 6 satellites") && stderr.contains("8 of 31 recorded times"),
        "{stderr}"
    );
    let packets: Vec<serde_json::Value> =
        serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    let document = &packets[0];
    assert_eq!(document["id"], "document");
    assert_eq!(document["version"], "1.0");
    assert!(document["description"]
        .as_str()
        .unwrap()
        .contains("3 of 6 satellites"));
    let clock = &document["clock"];
    assert_eq!(clock["range"], "LOOP_STOP");
    assert_eq!(clock["step"], "SYSTEM_CLOCK_MULTIPLIER");
    assert_eq!(
        clock["interval"],
        "2000-01-01T12:00:00.000000Z/2000-01-01T12:09:20.000000Z"
    );
    // Evenly spaced indices 0, 2, 4 of 0..6.
    let ids: Vec<&str> = packets[1..]
        .iter()
        .map(|p| p["id"].as_str().unwrap())
        .collect();
    assert_eq!(ids, ["sat-00000", "sat-00002", "sat-00004"]);
    for (packet, id) in packets[1..].iter().zip([0, 2, 4]) {
        let position = &packet["position"];
        assert_eq!(position["referenceFrame"], "INERTIAL");
        assert_eq!(position["interpolationAlgorithm"], "LAGRANGE");
        assert_eq!(position["epoch"], "2000-01-01T12:00:00.000000Z");
        let cartesian: Vec<f64> = position["cartesian"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        // The CSV rows at t = 0, 80, 160, … s, in metres.
        let expected: Vec<f64> = rows[&id]
            .iter()
            .filter(|r| (r.t_s / 80.0).fract() == 0.0)
            .flat_map(|r| [r.t_s, r.state[0], r.state[1], r.state[2]])
            .collect();
        // Equal up to the last bit serde_json's default (not `float_roundtrip`) parser may miss here.
        assert_eq!(cartesian.len(), expected.len());
        for (a, b) in cartesian.iter().zip(&expected) {
            assert!((a - b).abs() <= b.abs() * 1e-15, "{a} vs {b}");
        }
        let samples = cartesian.len() / 4;
        // Satellite 2 was removed at 200 s: samples at 0, 80, 160 s only.
        assert_eq!(samples, if id == 2 { 3 } else { 8 });
        assert!(packet["point"].is_object());
        // 3 satellites: paths on by default.
        assert!(packet["path"].is_object());
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn val_propagate_oem_is_the_csv_in_km_and_refuses_lvlh() {
    let dir = temp_dir("propagate");
    let (csv_path, oem_path) = (dir.join("orbit.csv"), dir.join("orbit.oem"));
    let args = [
        "propagate",
        "--elements",
        "6978137,0.001,97.8,10,20,30",
        "--duration-s",
        "600",
        "--output-step-s",
        "60",
        "--epoch-utc",
        "2026-03-20T12:00:00Z",
    ];
    let o = ok(bin()
        .args(args)
        .arg("--out")
        .arg(&csv_path)
        .arg("--oem")
        .arg(&oem_path)
        .output()
        .unwrap());
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains("11 rows") && stderr.contains("EME2000") && stderr.contains(" m/s"),
        "{stderr}"
    );
    let (header, segments) = parse_oem(&std::fs::read_to_string(&oem_path).unwrap());
    assert_eq!(keys(&header), HEADER_KEYS);
    assert_eq!(segments.len(), 1);
    assert_eq!(keys(&segments[0].keywords), META_KEYS);
    let mut reader = csv::Reader::from_path(&csv_path).unwrap();
    let rows: Vec<Row> = reader
        .records()
        .enumerate()
        .map(|(k, r)| {
            let r = r.unwrap();
            let t_s: f64 = r[0].parse().unwrap();
            Row {
                t_s,
                // 60 s steps from 12:00:00.
                time_utc: format!("2026-03-20T12:{:02}:00.000000", k),
                state: std::array::from_fn(|i| r[i + 1].parse().unwrap()),
            }
        })
        .collect();
    assert_eq!(rows.last().unwrap().t_s, 600.0);
    assert_states_match(&segments[0], &rows);

    let refused = bin()
        .args(args)
        .args(["--reference-elements", "6978137,0.001,97.8,10,20,31"])
        .args(["--frame", "lvlh-hill", "--out"])
        .arg(dir.join("rel.csv"))
        .arg("--oem")
        .arg(dir.join("rel.oem"))
        .output()
        .unwrap();
    assert_eq!(refused.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&refused.stderr).contains("--frame inertial"));
    assert!(!dir.join("rel.oem").exists() && !dir.join("rel.csv").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn regress_export_bad_input_exits_2() {
    let dir = temp_dir("bad");
    // OEM needs the trajectory: refused at load time, naming the key.
    let o = bin()
        .arg("run")
        .arg(scenario(
            &dir,
            "\n[output]\noem = true\ntrajectory = false\n",
        ))
        .arg("--out")
        .arg(dir.join("run"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("output.oem"));
    // Not a run directory.
    for format in ["oem", "czml"] {
        let o = bin()
            .args(["export", format])
            .arg(dir.join("nothing-here"))
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2), "{format}");
    }
    // A run without trajectory.csv: the error names the file.
    let out = run(&dir, "\n[output]\ntrajectory = false\n");
    let o = bin().args(["export", "oem"]).arg(&out).output().unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("trajectory.csv"));
    let o = bin()
        .args(["export", "czml"])
        .arg(&out)
        .args(["--max-samples", "0"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    // A malformed SOURCE_DATE_EPOCH is named.
    let again = dir.join("again");
    std::fs::create_dir_all(&again).unwrap();
    let out = run(&again, "");
    let o = bin()
        .env("SOURCE_DATE_EPOCH", "yesterday")
        .args(["export", "oem"])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("SOURCE_DATE_EPOCH"));
    std::fs::remove_dir_all(&dir).unwrap();
}
