//! `satflock bench --quick`: one JSON line per case with the documented keys, then a Markdown table;
//! a bad `--max-n` or case name exits 2. Timings are never asserted.

mod common;

use common::{satflock, stderr};

#[test]
fn quick_suite_prints_parseable_lines_with_the_keys() {
    let out = satflock().args(["bench", "--quick"]).output().unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<serde_json::Value> = text
        .lines()
        .take_while(|l| !l.is_empty())
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let cases: Vec<&str> = lines.iter().map(|l| l["case"].as_str().unwrap()).collect();
    assert_eq!(
        cases,
        [
            "propagation",
            "hold-repel",
            "bifurcating",
            "equilibrium-shaping",
            "pigeon",
            "five-elements"
        ]
    );
    for line in &lines {
        for key in [
            "case",
            "law",
            "n",
            "steps",
            "sat_steps_per_s",
            "wall_s",
            "setup_s",
            "peak_rss_bytes",
        ] {
            assert!(line.get(key).is_some(), "{line} lacks {key}");
        }
        assert!(line["sat_steps_per_s"].as_f64().unwrap() > 0.0);
        if line["case"] != "five-elements" {
            let split = &line["split"];
            for stage in ["sensing", "law", "propagation", "monitors", "recording"] {
                let f = split[stage].as_f64().unwrap();
                assert!((0.0..=1.0).contains(&f), "{stage}: {f}");
            }
        }
    }
    assert!(text.contains("| case | law | N |"));
}

#[test]
fn bad_options_exit_2_naming_them() {
    let out = satflock().args(["bench", "--max-n", "5"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("--max-n"));
    let out = satflock()
        .args(["bench", "--case", "warp"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("hold-repel"));
}
