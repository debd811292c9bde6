//! The `differential-drag` law closed loop on the built-in `dd-flock-phasing` (12 cubesats from one
//! dispenser at 510 km, low/high drag 0.01/0.035 m² at 4 kg, C_d 2.2): the flock reaches equal 30°
//! spacing by drag alone and holds it, against the first-principles time to phase of
//! `docs/methods/differential-drag.md`; no propellant; the same bits on 1 and 2 threads.
//!
//! First-principles estimate (independent of the engine): a satellite in its high-drag mode gains phase
//! on one in its low-drag mode at `α = (3/2) ρ n² a ΔB` \[rad/s²\] (the HCW secular term of a constant
//! differential along-track drag, validated in `tests/dynamics_drag.rs` and `tests/val_drag_command.rs`).
//! The chain's ends must separate by (N − 1) s = 330° relative to each other, accelerating half the way
//! and braking the other half: `t ≈ 2 √(330° / α)`. The run must phase (every spacing within 5 % of
//! 30°, and staying so to the end: the law's `time_to_phase_s`) within the 300 days simulated; the
//! ratio to the estimate is printed (measured: 166 days against 173, the release velocities spreading
//! the flock in its rank order from the start; `campaigns/dd-flock-phasing-seeds.toml` gives the spread
//! over 20 seeds of release dispersion and navigation noise).

use std::f64::consts::PI;

use satflock::run::build_simulation;
use satflock::scenario::Scenario;
use satflock::swarm::{NullRecorder, Simulation};

#[path = "common/builtin.rs"]
mod builtin_variant;
use builtin_variant::builtin_with;

/// The built-in `name`, ready to run.
fn simulation(name: &str) -> Simulation {
    build_simulation(&Scenario::load(name).unwrap()).unwrap()
}

fn run(threads: usize) -> Simulation {
    let mut sim = simulation("dd-flock-phasing");
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| sim.run(&mut NullRecorder, &mut |_| {}))
        .unwrap();
    sim
}

#[test]
fn val_flock_phases_by_drag_alone_and_deterministically() {
    let mut one = run(1);
    let results = one.law_results();
    // The estimate from the scenario's own numbers.
    let mu: f64 = 3.986004418e14;
    let a: f64 = 6_378_136.3 + 510e3;
    let n = (mu / (a * a * a)).sqrt();
    let rho = 6.967e-13 * (-(510e3 - 500e3) / 63_822.0f64).exp();
    let delta_b = 2.2 * (0.035 - 0.01) / 4.0;
    let alpha = 1.5 * rho * n * n * a * delta_b;
    let estimate_s = 2.0 * (330.0 * PI / 180.0 / alpha).sqrt();
    let phased_s = results["time_to_phase_s"]
        .as_f64()
        .unwrap_or_else(|| panic!("the flock did not phase in 300 days: {results:?}"));
    let final_error = results["max_phase_error_deg"].as_f64().unwrap();
    println!(
        "phased at {:.1} days (first-principles estimate {:.1} days, ratio {:.2}); final largest \
         spacing error {final_error:.3} deg; {} mode switches",
        phased_s / 86_400.0,
        estimate_s / 86_400.0,
        phased_s / estimate_s,
        results["mode_switches"]
    );
    assert!(final_error <= 0.05 * 30.0, "{final_error}");
    assert!(
        phased_s > 0.5 * estimate_s,
        "faster than the physics allows"
    );
    // Drag only: no thrust.
    for id in 0..12 {
        assert_eq!(one.state().ledger(id).1, 0.0);
    }
    assert_eq!(results["thrust_delta_v_mps"].as_f64(), Some(0.0));
    // Bitwise the same on two threads.
    let two = run(2);
    for (a, b) in one.states_eci().iter().zip(two.states_eci()) {
        assert_eq!(a.position_m, b.position_m);
        assert_eq!(a.velocity_mps, b.velocity_mps);
    }
    assert_eq!(one.drag_switches(), two.drag_switches());
    check_decay_against_drag_delta_v(&mut one);
}

/// The same flock with `slots = "reference"`: each satellite regulates to its slot about the reference
/// orbit (flying at the mid drag area 0.0225 m², inside the satellites' authority) and senses nobody
/// (a sensing range of 20 m). Criterion, fixed before the run: it phases within the 300 days and ends
/// within 5 % of 30°. The outermost slots are 165° from the reference, as they are from the flock's
/// centroid, so the same first-principles estimate (173 days) applies.
#[test]
fn val_flock_phases_about_the_reference_orbit_without_sensing() {
    let scenario = builtin_with(
        "dd-flock-phasing",
        &[
            (
                "spacing_deg = 30.0",
                "spacing_deg = 30.0\nslots = \"reference\"",
            ),
            (
                "inclination_deg = 97.4",
                "inclination_deg = 97.4\ndrag_area_m2 = 0.0225",
            ),
            ("range_m = 1.4e7 ", "range_m = 20.0 "),
        ],
    );
    let mut sim = build_simulation(&scenario).unwrap();
    sim.run(&mut NullRecorder, &mut |_| {}).unwrap();
    let results = sim.law_results();
    let phased_s = results["time_to_phase_s"]
        .as_f64()
        .unwrap_or_else(|| panic!("the flock did not phase about the reference: {results:?}"));
    let final_error = results["max_phase_error_deg"].as_f64().unwrap();
    println!(
        "reference slots: phased at {:.1} days; final largest spacing error {final_error:.3} deg; {} \
         mode switches; mean altitude decay {:.0} m",
        phased_s / 86_400.0,
        results["mode_switches"],
        results["mean_altitude_decay_m"]
    );
    assert!(final_error <= 0.05 * 30.0, "{final_error}");
}

/// `dd-flock-phasing` with its sensing replaced: `range_m = 20 m` and `ring_neighbours = k`.
fn ring_sensing(k: usize) -> Simulation {
    let ring = format!("ring_neighbours = {k}\nrange_m = 20.0 ");
    build_simulation(&builtin_with(
        "dd-flock-phasing",
        &[("range_m = 1.4e7 ", &ring)],
    ))
    .unwrap()
}

/// The ring neighbourhood with 6 satellites on each side covers the 12-satellite flock: every satellite
/// senses the same set as with a range of the orbit's diameter, whatever the distances, so the run has
/// the same bits (30 days).
#[test]
fn val_ring_neighbourhood_covering_the_flock_gives_the_same_bits() {
    let mut by_range = simulation("dd-flock-phasing");
    let mut by_ring = ring_sensing(6);
    let days = 30.0 * 86_400.0;
    by_range.advance_to(days, &mut NullRecorder).unwrap();
    by_ring.advance_to(days, &mut NullRecorder).unwrap();
    for (a, b) in by_range.states_eci().iter().zip(by_ring.states_eci()) {
        assert_eq!(a.position_m, b.position_m);
        assert_eq!(a.velocity_mps, b.velocity_mps);
    }
    assert_eq!(by_range.drag_switches(), by_ring.drag_switches());
}

/// The method page's argument against window laws, measured: with one ring neighbour on each side
/// (slots about the centroid of the three satellites sensed) only the chain's two ends see that the
/// flock is too short, so the spread creeps inward from the ends. Criterion, fixed before the run from
/// that argument: the flock does not phase within the 300 days (its largest spacing error at the end
/// stays above the 5 % tolerance).
#[test]
fn val_a_window_of_ring_neighbours_does_not_spread_the_flock() {
    let mut sim = ring_sensing(1);
    sim.run(&mut NullRecorder, &mut |_| {}).unwrap();
    let results = sim.law_results();
    let final_error = results["max_phase_error_deg"].as_f64().unwrap();
    println!(
        "ring of 1 neighbour each side: largest spacing error {final_error:.2} deg at 300 days, time \
         to phase {}",
        results["time_to_phase_s"]
    );
    assert!(results["time_to_phase_s"].is_null(), "{results:?}");
    assert!(final_error > 0.05 * 30.0, "{final_error}");
}

/// `dd-pair-keeping`: two satellites released together drift apart and are then held inside the
/// 10–150 km along-track band (the band, as APL's CAT mission held its pair) for 30 days, by
/// drag alone. The separation is measured here from the truth Hill states at every recording (hourly),
/// independently of the law's own metric.
#[test]
fn val_pair_is_held_inside_its_band_by_drag_alone() {
    struct Separations(Vec<(f64, f64)>);
    impl satflock::swarm::Recorder for Separations {
        fn record(&mut self, s: &satflock::swarm::Snapshot<'_>) -> std::io::Result<()> {
            let radius = 6_378_136.3 + 510e3;
            let phase = |k: usize| {
                let p = s.relative_states[k].position_m;
                p.y.atan2(radius + p.x)
            };
            self.0.push((s.time_s, (phase(1) - phase(0)) * radius));
            Ok(())
        }
    }
    let mut sim = simulation("dd-pair-keeping");
    let mut separations = Separations(Vec::new());
    sim.run(&mut separations, &mut |_| {}).unwrap();
    let entered = separations
        .0
        .iter()
        .position(|(_, d)| *d >= 10e3)
        .expect("the pair never reached 10 km");
    let (lowest, highest) = separations.0[entered..]
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), (_, d)| {
            (lo.min(*d), hi.max(*d))
        });
    println!(
        "inside 10-150 km from {:.2} days: separation {:.1}-{:.1} km to 30 days",
        separations.0[entered].0 / 86_400.0,
        lowest / 1e3,
        highest / 1e3
    );
    assert!(lowest >= 10e3 && highest <= 150e3, "{lowest} {highest}");
    assert!(separations.0.last().unwrap().0 >= 30.0 * 86_400.0 - 1.0);
    for id in 0..2 {
        assert_eq!(sim.state().ledger(id).1, 0.0);
    }
    check_decay_against_drag_delta_v(&mut sim);
}

/// The drag Δv and the mean-altitude decay the engine reports, against each other: on a near-circular
/// orbit drag takes energy at the rate v·a_drag, so `da = (2 a / v) dv_drag` (vis-viva). The swarm's
/// mean altitude over the last orbit lies below that over the first by (2 a / v) times the mean drag Δv,
/// within 10 % (the osculating eccentricity, J2, the orbit-averaging windows and the left-point sum of
/// the Δv are each of order a per cent). The law's results carry the same decay.
fn check_decay_against_drag_delta_v(sim: &mut Simulation) {
    let mu: f64 = 3.986004418e14;
    let (first, last) = sim
        .mean_altitude_first_and_last_orbit_m()
        .expect("an orbit-averaged altitude");
    let a = 6_378_136.3 + 0.5 * (first + last);
    let v = (mu / a).sqrt();
    let delta_v = sim.drag_delta_v_mps().expect("drag attitudes");
    let mean_dv = delta_v.iter().sum::<f64>() / delta_v.len() as f64;
    let predicted = 2.0 * a / v * mean_dv;
    let decay = first - last;
    println!(
        "mean altitude {:.1} km -> {:.1} km: decay {decay:.1} m; drag dv {mean_dv:.4} m/s gives {predicted:.1} m",
        first / 1e3,
        last / 1e3
    );
    assert!(
        (decay / predicted - 1.0).abs() < 0.1,
        "{decay} m vs {predicted} m"
    );
    assert_eq!(
        sim.law_results()["mean_altitude_decay_m"].as_f64(),
        Some(decay)
    );
}
