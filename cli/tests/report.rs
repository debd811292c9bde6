//! `satflock report` and `satflock run --report` end to end: one self-contained page that loads nothing
//! from the network, whose embedded positions are the trajectory's (read back independently with the
//! `csv` crate), with a removed satellite missing after its removal, the same bytes every time.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use base64::Engine as _;

mod common;
use common::{satflock, scratch_dir};

/// Six satellites holding their slots for 200 s (21 records), a threat and an obstacle, satellite 2
/// removed at 100 s; the description holds markup and a template placeholder, which must stay text.
const SCENARIO: &str = r#"
name = "report-test"
description = "Six satellites hold their slots; satellite 2 is lost at 100 s. <b>not bold</b> & {{BODY}}"
seed = 3
duration_s = 200.0
record_interval_s = 10.0

[dynamics]
model = "hcw"
integrator = "rk4"
step_s = 1.0

[reference]
altitude_m = 600e3
inclination_deg = 97.8

[control]
mode = "sampled"
period_s = 1.0

[satellites]
count = 6
mass_kg = 10.0
radius_m = 0.2
max_accel_mps2 = 2e-3
initial = { distribution = "sphere", radius_m = 100.0, velocity = "hcw-no-drift" }

[law]
name = "hold"
stiffness_per_s2 = 1e-4
damping_per_s = 2e-2
feedforward = "hcw"

[[threats]]
name = "debris"
danger_radius_m = 20.0
aim_point_hill_m = [0.0, 0.0, 0.0]
direction_hill = [0.0, 0.0, -1.0]
speed_mps = 2.0
arrival_time_s = 100.0

[[obstacles]]
name = "rock"
center_hill_m = [0.0, 300.0, 0.0]
radius_m = 30.0

[[events]]
time_s = 100.0
action = "remove-satellite"
satellite = 2

[output]
trajectory = true
"#;

fn run(dir: &Path, scenario: &str, extra: &[&str]) -> PathBuf {
    let file = dir.join("scenario-in.toml");
    std::fs::write(&file, scenario).unwrap();
    let out = dir.join("out");
    let done = satflock()
        .arg("run")
        .arg(&file)
        .arg("--out")
        .arg(&out)
        .arg("--quiet")
        .args(extra)
        .output()
        .unwrap();
    assert!(
        done.status.success(),
        "{}",
        String::from_utf8_lossy(&done.stderr)
    );
    out
}

fn report(dir: &Path) -> std::process::Output {
    satflock().arg("report").arg(dir).output().unwrap()
}

/// The text of the page's JSON data element.
fn page_data(html: &str) -> serde_json::Value {
    let open = "<script type=\"application/json\" id=\"satflock-data\">";
    let start = html.find(open).expect("the data element") + open.len();
    let end = start + html[start..].find("</script>").unwrap();
    serde_json::from_str(&html[start..end]).unwrap()
}

/// The value of attribute `name` of the element with id `id`.
fn attribute(html: &str, id: &str, name: &str) -> String {
    let tag_start = html.find(&format!("id=\"{id}\"")).unwrap();
    let tag = &html[tag_start..tag_start + html[tag_start..].find('>').unwrap()];
    let key = format!("{name}=\"");
    let v = tag.find(&key).unwrap() + key.len();
    tag[v..v + tag[v..].find('"').unwrap()].to_string()
}

/// Little-endian f32 from base64, decoded by hand (not by the report's code).
fn f32s(text: &str) -> Vec<f32> {
    let bytes = base64::engine::general_purpose::STANDARD
        .decode(text)
        .unwrap();
    assert_eq!(bytes.len() % 4, 0);
    bytes
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}

fn file_names(dir: &Path) -> BTreeSet<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect()
}

#[test]
fn val_report_is_one_offline_file_with_the_trajectory_and_the_same_bytes_twice() {
    let dir = scratch_dir("page");
    let before_report = run(&dir, SCENARIO, &[]);
    let files_of_the_run = file_names(&before_report);
    std::fs::remove_dir_all(&before_report).unwrap();
    let out = run(&dir, SCENARIO, &["--report"]);

    // One file added, nothing beside it.
    let mut expected = files_of_the_run.clone();
    expected.insert("report.html".into());
    assert_eq!(file_names(&out), expected);
    let page = std::fs::read(out.join("report.html")).unwrap();
    let html = String::from_utf8(page.clone()).unwrap();

    // Nothing loaded from the network: no URL at all, every src/href a data URL or a fragment, and no
    // script API that fetches.
    for forbidden in [
        "http://",
        "https://",
        "//cdn",
        "<link",
        "<iframe",
        "@import",
        "url(",
        "fetch(",
        "XMLHttpRequest",
        "WebSocket",
        "import(",
    ] {
        assert!(!html.contains(forbidden), "the page holds `{forbidden}`");
    }
    for attr in ["src=", "href="] {
        for (at, _) in html.match_indices(attr) {
            let value = html[at + attr.len()..].trim_start_matches(['"', '\'']);
            assert!(
                value.starts_with("data:") || value.starts_with('#'),
                "{attr}{}",
                &value[..value.len().min(40)]
            );
        }
    }
    assert!(html.contains("Content-Security-Policy\" content=\"default-src 'none'"));

    // The description is text, not markup, and not a placeholder filled twice.
    assert!(html.contains("&lt;b&gt;not bold&lt;/b&gt; &amp; {{BODY}}"));
    assert!(!html.contains("<b>not bold</b>"));

    // The embedded data: satellites x kept times as stated on the page.
    let data = page_data(&html);
    let trajectory = &data["trajectory"];
    let sats: usize = attribute(&html, "viewer-kept", "data-satellites")
        .parse()
        .unwrap();
    let times: usize = attribute(&html, "viewer-kept", "data-times")
        .parse()
        .unwrap();
    assert_eq!((sats, times), (6, 21));
    assert!(html.contains("Showing 6 of 6 satellites at 21 of 21 recorded times."));
    assert_eq!(trajectory["satellite_ids"].as_array().unwrap().len(), sats);
    let times_s: Vec<f64> = trajectory["times_s"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert_eq!(times_s.len(), times);
    let positions = f32s(trajectory["positions_lvlh_m_f32le"].as_str().unwrap());
    assert_eq!(positions.len(), 3 * sats * times);
    assert_eq!(data["scene"]["threats"][0]["name"], "debris");
    assert_eq!(data["scene"]["obstacles"][0]["name"], "rock");

    // Every row of trajectory.csv is in the data, at its time and satellite, in f32.
    let mut reader = csv::Reader::from_path(out.join("trajectory.csv")).unwrap();
    let header = reader.headers().unwrap().clone();
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    let (ct, cu, ci, cx) = (col("t_s"), col("time_utc"), col("id"), col("x_lvlh_m"));
    let mut seen = vec![false; sats * times];
    for record in reader.records() {
        let record = record.unwrap();
        let t: f64 = record[ct].parse().unwrap();
        let k = times_s.iter().position(|&x| x == t).unwrap();
        let id: usize = record[ci].parse().unwrap();
        assert_eq!(trajectory["times_utc"][k], record[cu]);
        let sample = k * sats + id;
        for axis in 0..3 {
            let v: f64 = record[cx + axis].parse().unwrap();
            assert_eq!(positions[3 * sample + axis], v as f32);
        }
        seen[sample] = true;
    }
    // The removed satellite has no position from its removal (t = 100 s) on; every other sample has one.
    for (sample, seen) in seen.iter().enumerate() {
        let (k, id) = (sample / sats, sample % sats);
        let removed = id == 2 && times_s[k] >= 100.0;
        assert_eq!(*seen, !removed, "t = {} s, satellite {id}", times_s[k]);
        assert_eq!(positions[3 * sample].is_nan(), removed);
    }

    // The same run directory gives the same bytes.
    let again = report(&out);
    assert!(again.status.success());
    assert_eq!(std::fs::read(out.join("report.html")).unwrap(), page);

    // A rerun into the directory (report.html is one of a run's files) is allowed.
    run(&dir, SCENARIO, &[]);
    assert!(!out.join("report.html").exists());
}

#[test]
fn val_report_embeds_plots_sorted_and_says_when_there_is_no_trajectory() {
    let dir = scratch_dir("plots");
    let out = run(
        &dir,
        &SCENARIO.replace("trajectory = true", "trajectory = false"),
        &["--no-plots"],
    );
    let plots = out.join("plots");
    std::fs::create_dir(&plots).unwrap();
    let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="10" height="10"><rect width="5" height="5"/></svg>"#;
    std::fs::write(plots.join("b-separation.svg"), svg).unwrap();
    std::fs::write(plots.join("a-elements.svg"), svg).unwrap();
    std::fs::write(plots.join("notes.txt"), "not a plot").unwrap();
    // A figure written as SVG and PNG (as `satflock plot` does) appears once, as its SVG; a PNG alone
    // appears as itself.
    let png = [0x89u8, b'P', b'N', b'G', b'\r', b'\n', 0x1a, b'\n'];
    std::fs::write(plots.join("a-elements.png"), png).unwrap();
    std::fs::write(plots.join("c-only.png"), png).unwrap();
    assert!(report(&out).status.success());
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.contains("id=\"viewer-none\""));
    assert!(html.contains("no trajectory.csv"));
    assert!(page_data(&html)["trajectory"].is_null());
    assert!(!html.contains("id=\"plots-none\""));
    let encoded = base64::engine::general_purpose::STANDARD.encode(svg);
    let figures: Vec<usize> = ["a-elements.svg", "b-separation.svg"]
        .iter()
        .map(|name| html.find(&format!("alt=\"{name}\"")).unwrap())
        .collect();
    assert!(figures[0] < figures[1], "plots sorted by name");
    assert_eq!(
        html.matches(&format!("src=\"data:image/svg+xml;base64,{encoded}\""))
            .count(),
        2
    );
    assert!(!html.contains("notes.txt"));
    assert!(!html.contains("alt=\"a-elements.png\""));
    assert!(html.contains("alt=\"c-only.png\""));
    assert!(
        !html.contains("http://"),
        "the SVG's namespace is inside the data URL"
    );

    // Without plots the page says how to make them.
    std::fs::remove_dir_all(&plots).unwrap();
    assert!(report(&out).status.success());
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.contains("id=\"plots-none\""));
    assert!(html.contains("satflock plot DIR"));
}

#[test]
fn regress_report_of_a_directory_that_is_not_a_run_exits_2_naming_the_file() {
    let dir = scratch_dir("not-a-run");
    let done = report(&dir);
    assert_eq!(done.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&done.stderr);
    assert!(stderr.contains("summary.json"), "{stderr}");
    assert!(!dir.join("report.html").exists());
}
