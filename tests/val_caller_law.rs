//! A caller's law in place of the scenario's ([`Prepared::replace_law`], [`run_prepared`]): the way
//! an embedding (the Python package) runs a law the scenario file cannot name.
//!
//! * The built-in `hold` law handed in by the caller, with the scenario's own parameters, gives the
//!   files of the scenario's own run byte for byte (the same law through two paths).
//! * The scenario's law events, and a law the dynamics cannot follow, are refused naming the key.
//! * A law that fails while running ([`LawError::Failed`]) stops the run with that error; the summary
//!   says `failed` with its message.

use std::path::{Path, PathBuf};

use nalgebra::Vector3;

use satflock::guidance::hold::{Feedforward, Hold, HoldParameters};
use satflock::run::{run_prepared, run_scenario, RunError};
use satflock::scenario::{Scenario, ScenarioError};
use satflock::swarm::{
    Centralised, GuidanceLaw, Law, LawContext, LawError, SatelliteView, SimError, SwarmView,
};

fn scratch(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("satflock-caller-law-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// `hold` cut to 300 s, its law event removed (its thruster failure kept, at 150 s).
fn short_hold() -> Scenario {
    let mut scenario = Scenario::load("hold").unwrap();
    scenario.file.duration_s = 300.0;
    scenario.file.events.retain(|e| e.time_s == Some(2000.0));
    scenario.file.events[0].time_s = Some(150.0);
    scenario
}

fn read(dir: &Path, file: &str) -> String {
    std::fs::read_to_string(dir.join(file)).unwrap()
}

#[test]
fn the_callers_hold_law_gives_the_scenarios_run_byte_for_byte() {
    let scenario = short_hold();
    let own = scratch("own");
    run_scenario(&scenario, &own, &mut |_| {}).unwrap();
    let mut prepared = scenario.prepare().unwrap();
    let law = Hold::new(HoldParameters {
        stiffness_per_s2: 1e-4,
        damping_per_s: 2e-2,
        feedforward: Feedforward::Hcw,
        slot_offset_hill_m: [0.0; 3],
    })
    .unwrap();
    prepared
        .replace_law(&scenario, Law::new(law), "test:hold")
        .unwrap();
    let caller = scratch("caller");
    let summary = run_prepared(
        &scenario,
        prepared,
        &caller,
        &Default::default(),
        &mut |_| {},
    )
    .unwrap();
    assert_eq!(summary.controller.as_deref(), Some("test:hold"));
    for file in ["trajectory.csv", "metrics.csv"] {
        assert_eq!(read(&own, file), read(&caller, file), "{file}");
    }
    assert!(read(&caller, "scenario.toml").starts_with(
        "# As run: the scenario builtin:hold with the caller's law test:hold instead of its [law]."
    ));
    for dir in [own, caller] {
        std::fs::remove_dir_all(dir).unwrap();
    }
}

#[test]
fn law_events_and_a_law_the_dynamics_cannot_follow_are_refused() {
    let free = || {
        Law::new(
            Hold::new(HoldParameters {
                stiffness_per_s2: 1e-4,
                damping_per_s: 0.0,
                feedforward: Feedforward::None,
                slot_offset_hill_m: [0.0; 3],
            })
            .unwrap(),
        )
    };
    let hold = Scenario::load("hold").unwrap();
    let e = hold
        .prepare()
        .unwrap()
        .replace_law(&hold, free(), "test")
        .unwrap_err();
    assert!(
        matches!(&e, ScenarioError::Invalid { key, .. } if key == "events[0]"),
        "{e}"
    );
    assert!(e.to_string().contains("set-law-parameters"), "{e}");
    // es-e0 flies the kinematic model, which takes velocity commands only.
    let kinematic = Scenario::load("es-e0").unwrap();
    let e = kinematic
        .prepare()
        .unwrap()
        .replace_law(&kinematic, free(), "test")
        .unwrap_err();
    assert!(
        matches!(&e, ScenarioError::Invalid { key, .. } if key == "dynamics.model"),
        "{e}"
    );
}

/// A law that fails at its first tick at or after `at_s`.
struct FailsAt {
    at_s: f64,
}

impl GuidanceLaw for FailsAt {
    type State = ();
    type Parameters = ();
    satflock::capabilities!(Centralised);

    fn name(&self) -> &'static str {
        "fails-at"
    }

    fn command(&self, _: &SatelliteView<'_>, _: &(), _: &LawContext) -> Vector3<f64> {
        Vector3::zeros()
    }

    fn set_parameters(&mut self, _: &()) -> Result<(), LawError> {
        Ok(())
    }
}

impl Centralised for FailsAt {
    fn centralised_due(&self, time_s: f64) -> bool {
        time_s >= self.at_s
    }

    fn centralised_update(&mut self, swarm: &SwarmView<'_>) -> Result<(), LawError> {
        Err(LawError::Failed {
            law: "fails-at".into(),
            time_s: swarm.shared.time_s,
            message: "out of ideas".into(),
        })
    }
}

#[test]
fn a_law_that_fails_while_running_stops_the_run() {
    let scenario = short_hold();
    let mut prepared = scenario.prepare().unwrap();
    prepared
        .replace_law(&scenario, Law::new(FailsAt { at_s: 42.0 }), "test:fails-at")
        .unwrap();
    let out = scratch("fails");
    let e = run_prepared(&scenario, prepared, &out, &Default::default(), &mut |_| {}).unwrap_err();
    let message = "law `fails-at` failed at t = 42 s: out of ideas";
    assert!(
        matches!(&e, RunError::Simulation(SimError::Law(LawError::Failed { time_s, .. })) if *time_s == 42.0),
        "{e}"
    );
    assert_eq!(e.to_string(), message);
    let summary: serde_json::Value = serde_json::from_str(&read(&out, "summary.json")).unwrap();
    assert_eq!(summary["status"], "failed");
    assert_eq!(summary["error"], message);
    assert_eq!(summary["simulated_s"], 42.0);
    std::fs::remove_dir_all(out).unwrap();
}
