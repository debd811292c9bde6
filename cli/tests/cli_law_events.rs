//! A `set-law-parameters` event whose gains the timing cannot resolve is refused when the scenario is
//! loaded, not when the event fires: exit code 2, a message naming the file, the event's key, the control
//! period and its limit, and nothing written.

mod common;
use common::scratch_dir;

#[test]
fn val_stiff_gain_set_by_an_event_is_refused_at_load_time() {
    // `hold` with k_d = 0.02 1/s: raising k_p to 4 1/s² at t = 1000 s makes the closed loop
    // s² + 0.02 s + 4 = 0 underdamped with |s| = √k_p = 2 1/s, so a zero-order hold needs a period
    // below 1/2 = 0.5 s; the scenario's control period is 1 s. The event is inserted first in the file
    // (`events[0]`), before the existing slot-offset event at the same time.
    let hold = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenarios/hold.toml"),
    )
    .unwrap();
    let first_event = hold.find("[[events]]").expect("hold.toml has events");
    let stiff = "[[events]]\n\
                 time_s = 1000.0\n\
                 action = \"set-law-parameters\"\n\
                 parameters = { stiffness_per_s2 = 4.0 }\n\n";
    let text = format!("{}{stiff}{}", &hold[..first_event], &hold[first_event..]);
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
