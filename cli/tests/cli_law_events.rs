//! A `set-law-parameters` event whose gains the timing cannot resolve is refused when the scenario is
//! loaded, not when the event fires: exit code 2, a message naming the file, the event's key, the control
//! period and its limit, and nothing written.

mod common;
use common::scratch_dir;

/// The built-in `hold.toml` with an event (its keys, `KEY = VALUE` lines) inserted before its own, so
/// that it is `events[0]`.
fn hold_with_first_event(keys: &str) -> String {
    let hold = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenarios/hold.toml"),
    )
    .unwrap();
    let first_event = hold.find("[[events]]").expect("hold.toml has events");
    format!(
        "{}[[events]]\n{keys}\n\n{}",
        &hold[..first_event],
        &hold[first_event..]
    )
}

#[test]
fn val_stiff_gain_set_by_an_event_is_refused_at_load_time() {
    // `hold` with k_d = 0.02 1/s: raising k_p to 4 1/s² at t = 1000 s makes the closed loop
    // s² + 0.02 s + 4 = 0 underdamped with |s| = √k_p = 2 1/s, so a zero-order hold needs a period
    // below 1/2 = 0.5 s; the scenario's control period is 1 s. The event is inserted first in the file
    // (`events[0]`), before the existing slot-offset event at the same time.
    let text = hold_with_first_event(
        "time_s = 1000.0\n\
         action = \"set-law-parameters\"\n\
         parameters = { stiffness_per_s2 = 4.0 }",
    );
    assert!(
        text.contains("period_s = 1.0"),
        "hold.toml changed its control period"
    );

    let dir = scratch_dir("stiff");
    let file = dir.join("stiff-hold.toml");
    std::fs::write(&file, text).unwrap();
    let out = dir.join("out");
    let output = common::satflock()
        .arg("run")
        .arg(&file)
        .arg("--out")
        .arg(&out)
        .arg("--quiet")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "stderr: {stderr}");
    for needle in [
        file.to_str().unwrap(),
        "events[0].parameters",
        "control period 1 s",
        "period < 0.5000 s",
        "control.period_s",
    ] {
        assert!(stderr.contains(needle), "`{needle}` missing from: {stderr}");
    }
    // Refused before anything is created: no output directory at all.
    assert!(
        !out.exists(),
        "output directory was created: {:?}",
        std::fs::read_dir(&out).map(|d| d.count())
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 30: a condition event with a negative threshold, naming an outcome no law of the run
/// declares, or testing conjunctions without a monitor, and a negative `[conjunctions] threshold_m`,
/// are refused at load time with exit code 2 and the key.
#[test]
fn regress_bad_condition_event_exits_2_naming_the_key() {
    let dir = scratch_dir("bad-condition");
    for (event, key) in [
        (
            "condition = { min_separation_below_m = -5.0 }",
            "events[0].condition.min_separation_below_m",
        ),
        (
            "condition = { law_outcome = \"no_such_outcome\", below = 1.0 }",
            "events[0].condition.law_outcome",
        ),
        (
            "condition = { conjunction = true }",
            "events[0].condition.conjunction",
        ),
        // A table after the event's keys: the scenario's `[conjunctions]`.
        (
            "condition = { conjunction = true }\n[conjunctions]\nthreshold_m = -1.0",
            "conjunctions.threshold_m",
        ),
    ] {
        let (keys, tables) = event
            .split_once("\n[")
            .map_or((event, String::new()), |(k, t)| (k, format!("\n[{t}")));
        let text = hold_with_first_event(&format!("{keys}\naction = \"stop-run\"{tables}"));
        let file = dir.join("bad-condition.toml");
        std::fs::write(&file, text).unwrap();
        let out = dir.join("out");
        let output = common::satflock()
            .arg("run")
            .arg(&file)
            .arg("--out")
            .arg(&out)
            .arg("--quiet")
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "stderr: {stderr}");
        assert!(stderr.contains(key), "`{key}` missing from: {stderr}");
        assert!(!out.exists());
    }
    let _ = std::fs::remove_dir_all(&dir);
}
