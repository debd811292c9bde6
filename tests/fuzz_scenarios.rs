//! Fuzzing the scenario front door: mutants of every built-in scenario (a value replaced by an extreme
//! or wrong-typed one, a key deleted, an unknown key added, random bytes flipped) are loaded, validated
//! and, when that succeeds, built and stepped a few times. Nothing may panic, and every error of the
//! load, the validation or the build names the file.
//!
//! Bounded for CI: 4096 mutants from a fixed seed (about 1.5 s in release mode; 60 000 mutants from
//! seeds 1–3 passed when this was written); set `SATFLOCK_FUZZ_CASES=N` and `SATFLOCK_FUZZ_SEED=S` for a
//! longer or different search. Every crash found becomes a named `regress_fuzz_*` case below.

mod common;

use std::path::Path;

use proptest::prelude::*;
use proptest::sample::Index;
use satflock::run::build_simulation;
use satflock::scenario::{builtin::BUILTINS, Scenario};

use common::toml_fuzz::{check, flip, mutate, mutation, quietly, runner};

const SOURCE: &str = "fuzz.toml";
const DEFAULT_CASES: u32 = 4096;
/// Satellites × integration steps of the whole run above which a mutant is only built, not stepped.
const MAX_RUN_WORK: f64 = 2e7;
/// Steps taken when the run is small enough.
const STEPS: usize = 3;

/// Loads, validates, builds and (when small) steps one mutant. `Err` describes a broken promise.
fn exercise(text: &str) -> Result<(), String> {
    let names_file = |stage: &str, msg: String| -> Result<(), String> {
        if msg.contains(SOURCE) {
            Ok(())
        } else {
            Err(format!("{stage} error does not name the file: {msg}"))
        }
    };
    let scenario = match Scenario::from_toml(text, SOURCE, Path::new(".")) {
        Ok(s) => s,
        Err(e) => return names_file("load", e.to_string()),
    };
    let prepared = match scenario.prepare() {
        Ok(p) => p,
        Err(e) => return names_file("prepare", e.to_string()),
    };
    let work = prepared.satellites.len() as f64 * prepared.config.duration_s
        / prepared.config.step_s.min(prepared.config.base_step_s());
    let mut sim = match build_simulation(&scenario) {
        Ok(s) => s,
        Err(e) => return names_file("build", e.to_string()),
    };
    if work.is_finite() && work <= MAX_RUN_WORK {
        for _ in 0..STEPS {
            // A run may stop early (divergence, a collision rule): an error, not a panic.
            if sim.step().is_err() {
                break;
            }
        }
    }
    Ok(())
}

#[test]
fn fuzz_mutated_builtin_scenarios_never_panic() {
    let mut runner = runner(DEFAULT_CASES);
    let strategy = (
        0..BUILTINS.len(),
        prop::collection::vec(mutation(), 0..3),
        prop::collection::vec((any::<Index>(), any::<u8>()), 0..4),
    );
    let result = quietly(|| {
        runner.run(&strategy, |(b, mutations, flips)| {
            let builtin = &BUILTINS[b];
            let text = flip(&mutate(builtin.toml, &mutations), &flips);
            let label = format!("{} {mutations:?} flips {flips:?}", builtin.name);
            check(&label, &text, exercise).map_err(TestCaseError::fail)
        })
    });
    if let Err(e) = result {
        panic!("{e}");
    }
}

#[test]
fn fuzz_unmutated_builtins_pass_the_harness() {
    // The harness itself: every built-in loads, builds and steps (or is only built) without a problem.
    for b in BUILTINS {
        check(b.name, b.toml, exercise).unwrap();
        let round_trip = mutate(b.toml, &[]);
        check(b.name, &round_trip, exercise).unwrap();
    }
}

/// Found by the fuzzer: `avoidance_radius_m` beyond the sensing range passed validation and the law's
/// refusal at build time came back without the file or the key (exit 1 in the CLI).
#[test]
fn regress_fuzz_law_refusal_at_build_names_file_and_key() {
    let b = BUILTINS
        .iter()
        .find(|b| b.name == "gao-double-circle")
        .unwrap();
    let text = b.toml.replace(
        "avoidance_radius_m = 200.0",
        "avoidance_radius_m = 1000000000",
    );
    assert_ne!(text, b.toml);
    let scenario = Scenario::from_toml(&text, SOURCE, Path::new(".")).unwrap();
    let err = build_simulation(&scenario)
        .err()
        .expect("refused")
        .to_string();
    assert!(err.contains(SOURCE), "{err}");
    assert!(err.contains("key `law`"), "{err}");
    assert!(err.contains("avoidance_radius_m"), "{err}");
    check("regression", &text, exercise).unwrap();
}

/// Found by the fuzzer: a plane angle that makes the j2-distance target amplitude fall to (or below) the
/// barrier's lower bound made `f64::clamp` panic on an empty interval in the first command; the law now
/// refuses it when it starts, naming the keys.
#[test]
fn regress_fuzz_j2_distance_target_below_the_barrier_is_refused() {
    let b = BUILTINS
        .iter()
        .find(|b| b.name == "ts-connectable-large")
        .unwrap();
    let mut table: toml::Table = b.toml.parse().unwrap();
    table["law"]
        .as_table_mut()
        .unwrap()
        .insert("plane_theta_p_deg".into(), toml::Value::Float(1e-300));
    let text = toml::to_string(&table).unwrap();
    let scenario = Scenario::from_toml(&text, SOURCE, Path::new(".")).unwrap();
    let err = build_simulation(&scenario)
        .err()
        .expect("refused")
        .to_string();
    assert!(err.contains(SOURCE), "{err}");
    assert!(err.contains("min_amplitude_m"), "{err}");
    check("regression", &text, exercise).unwrap();
}

/// Found by the fuzzer: with a non-finite navigation position the sensing grid is left empty for that
/// evaluation, and a law visiting its neighbours indexed the empty grid (index out of bounds). A
/// satellite now sees no neighbour then (the divergence check stops the run after the step).
#[test]
fn regress_fuzz_neighbours_of_an_empty_grid_are_none() {
    use nalgebra::Vector3;
    use satflock::grid::NeighbourGrid;
    use satflock::orbit::RelativeStateHill;
    use satflock::swarm::{EnvironmentView, SharedInfo, SwarmView};
    let states = [RelativeStateHill {
        position_m: Vector3::new(f64::NAN, 0.0, 0.0),
        velocity_mps: Vector3::zeros(),
    }; 2];
    let grid = NeighbourGrid::new(); // never built: empty
    let flags = [true; 2];
    let view = SwarmView::new(
        &states,
        &[1.0, 1.0],
        &flags,
        &flags,
        &grid,
        SharedInfo {
            time_s: 0.0,
            mean_motion_rad_s: 1e-3,
            sensing_range_m: 10.0,
            reference_model: satflock::relative::SchweighartSedwick::new(
                7.0e6,
                1.0,
                3.986004418e14,
                6_378_137.0,
                1.08262668e-3,
            ),
        },
        EnvironmentView::default(),
    );
    let mut visited = 0;
    view.satellite(1).for_each_neighbour(|_| visited += 1);
    assert_eq!(visited, 0);
}
