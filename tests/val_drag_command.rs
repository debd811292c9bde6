//! Drag as an actuator (`[satellites] drag_modes_m2`, `CommandsDrag::drag_command`): the engine applies
//! a law's drag commands to the force set, keeps the minimum dwell, counts the changes and records the
//! area, and a drag-only law spends no propellant.
//!
//! Open loop through the command path: two satellites released from the same state, one commanded to
//! its high-drag mode and one to its low-drag mode, separate along-track as the Hill–Clohessy–Wiltshire
//! secular term of a constant differential along-track acceleration predicts (Leonard, Hollister &
//! Bergmann, "Orbital formationkeeping with differential drag", J. Guidance 12(1), 1989):
//! `Δs(t) = (3/4) ρ ΔB n² a² F t²`, ΔB the difference of `C_d A / m`, F the co-rotation factor
//! `(1 − (ω_E/n) cos i)²`. The linear theory's second-order excess is bounded as in
//! `tests/dynamics_drag.rs` (the density change over the decay, `2 t (f₁ + f₂) / (3 n H)`, plus the
//! cross-track wind's share, here the same F), and its sign is known (the measured separation exceeds
//! the linear theory); the test asks for `0 < error < 2 ε(t)`, as that test does.

use std::f64::consts::PI;

use nalgebra::Vector3;
use satflock::orbit::{CartesianState, KeplerianElements};
use satflock::scenario::Scenario;
use satflock::swarm::{
    Broadcast, CommandsDrag, DragCommand, GuidanceLaw, Law, LawContext, LawError, NullRecorder,
    SatelliteView, SimError, Simulation, SwarmView,
};

/// Density at the reference altitude \[kg/m^3\], the layer's reference altitude \[m\] and scale height
/// \[m\] (a one-layer exponential atmosphere around 400 km).
const RHO_0: f64 = 3.725e-12;
const H_0: f64 = 400_000.0;
const SCALE_HEIGHT: f64 = 58_515.0;
const INCLINATION_DEG: f64 = 51.6;
const MASS_KG: f64 = 4.0;
const LOW_M2: f64 = 0.01;
const HIGH_M2: f64 = 0.035;

/// A scenario of two satellites at the reference orbit (circular, 400 km, i = 51.6°), point-mass
/// gravity and exponential drag, each with the modes low and high, sampled control every `period_s`.
fn scenario(period_s: f64, dwell: &str, extra: &str) -> String {
    format!(
        r#"
name = "drag-command"
duration_s = 600.0
record_interval_s = 600.0
seed = 1
[reference]
altitude_m = {H_0:.1}
inclination_deg = {INCLINATION_DEG}
[dynamics]
model = "two-body"
integrator = "rk4"
step_s = {period_s}
[dynamics.forces.gravity]
model = "point-mass"
[dynamics.forces.drag]
atmosphere = "exponential"
reference_density_kg_per_m3 = {RHO_0:e}
reference_altitude_m = {H_0:.1}
scale_height_m = {SCALE_HEIGHT:.1}
corotation = true
[control]
mode = "sampled"
period_s = {period_s}
[satellites]
count = 2
mass_kg = {MASS_KG}
drag_coefficient = 2.2
drag_modes_m2 = {{ low = {LOW_M2}, high = {HIGH_M2} }}
{dwell}
allow_initial_overlap = true
initial = {{ distribution = "list", frame = "hill", states = [[0, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0, 0]] }}
{extra}
[law]
name = "none"
[sensing]
range_m = 1000.0
"#
    )
}

/// Commands satellite 1 to the mode of largest area and satellite 0 to the smallest, from t = 0; or,
/// with `flip_every_ticks`, every satellite alternates between the two every that many ticks.
struct Split {
    flip_every_ticks: Option<u64>,
}

impl GuidanceLaw for Split {
    /// (id, ticks seen).
    type State = (usize, u64);
    type Parameters = ();
    satflock::capabilities!(CommandsDrag);

    fn name(&self) -> &'static str {
        "split"
    }

    fn initialise(
        &mut self,
        _: &SwarmView<'_>,
        states: &mut [(usize, u64)],
    ) -> Result<(), LawError> {
        for (id, s) in states.iter_mut().enumerate() {
            *s = (id, 0);
        }
        Ok(())
    }

    fn update_state(
        &self,
        _: &SatelliteView<'_>,
        broadcast: &Broadcast<'_, (usize, u64)>,
        _: &LawContext,
    ) -> (usize, u64) {
        let (id, ticks) = *broadcast.own();
        (id, ticks + 1)
    }

    fn command(&self, _: &SatelliteView<'_>, _: &(usize, u64), _: &LawContext) -> Vector3<f64> {
        Vector3::zeros()
    }

    fn set_parameters(&mut self, _: &()) -> Result<(), LawError> {
        Ok(())
    }
}

impl CommandsDrag<(usize, u64)> for Split {
    fn drag_command(&self, &(id, ticks): &(usize, u64)) -> Option<DragCommand> {
        let high = match self.flip_every_ticks {
            None => id == 1,
            Some(k) => ((ticks - 1) / k) % 2 == 1,
        };
        Some(if high {
            DragCommand::Maximum
        } else {
            DragCommand::Minimum
        })
    }
}

fn simulation(text: &str, duration_s: f64, law: Split) -> Result<Simulation, SimError> {
    let scenario = Scenario::from_toml(text, "drag-command.toml", std::path::Path::new("."))
        .expect("scenario");
    let mut prepared = scenario.prepare().expect("prepare");
    prepared.config.duration_s = duration_s;
    prepared.config.record_interval_s = duration_s;
    Simulation::new(
        prepared.config,
        &prepared.satellites,
        Law::new(law),
        prepared.events,
    )
}

#[test]
fn val_commanded_differential_drag_matches_the_hcw_secular_term() {
    let mu = 3.986004418e14;
    let a0 = 6_378_136.3 + H_0;
    let n = (mu / (a0 * a0 * a0)).sqrt();
    let period = 2.0 * PI / n;
    let step = period / 600.0;
    let orbits = 6.0;
    let mut sim = simulation(
        &scenario(step, "", ""),
        orbits * period,
        Split {
            flip_every_ticks: None,
        },
    )
    .expect("simulation");
    sim.run(&mut NullRecorder, &mut |_| {}).expect("run");
    let beta = |area: f64| 2.2 * area / MASS_KG;
    let delta_b = beta(HIGH_M2) - beta(LOW_M2);
    let earth_rotation = 7.292115e-5;
    let f = {
        let g = 1.0 - earth_rotation / n * INCLINATION_DEG.to_radians().cos();
        g * g
    };
    let t = sim.time_s();
    let states = sim.states_eci();
    let u: Vec<f64> = states
        .iter()
        .map(|s| {
            KeplerianElements::from_cartesian(
                &CartesianState::new(s.position_m, s.velocity_mps),
                mu,
            )
            .unwrap()
            .argument_of_latitude_rad()
        })
        .collect();
    // The draggier satellite sinks, speeds up and leads.
    let du = (u[1] - u[0] + PI).rem_euclid(2.0 * PI) - PI;
    let measured = a0 * du;
    let rho = RHO_0;
    let theory = 0.75 * rho * delta_b * n * n * a0 * a0 * f * t * t;
    let drag_along = |b: f64| 0.5 * rho * b * (n * a0) * (n * a0) * f;
    let predicted =
        2.0 * t * (drag_along(beta(LOW_M2)) + drag_along(beta(HIGH_M2))) / (3.0 * n * SCALE_HEIGHT);
    let error = measured / theory - 1.0;
    println!(
        "after {orbits} orbits: the high-drag satellite leads by {measured:.4} m, theory {theory:.4} m, \
         relative error {error:.3e} (second-order excess bound {predicted:.3e})"
    );
    assert!(
        error > 0.0 && error < 2.0 * predicted,
        "{error:e} vs {:e}",
        2.0 * predicted
    );
    // The commanded areas are what the engine used and recorded, one change each (satellite 0 started
    // in its low mode and stayed there).
    assert_eq!(sim.drag_areas_m2().unwrap(), vec![LOW_M2, HIGH_M2]);
    assert_eq!(sim.drag_switches(), vec![0, 1]);
    // A drag-only law spends no propellant.
    assert!(sim.state().ledger(0).1 == 0.0 && sim.state().ledger(1).1 == 0.0);
}

#[test]
fn val_commanded_areas_equal_fixed_areas_bit_for_bit() {
    // The high-drag satellite commanded from t = 0 flies exactly as one given that area from the start.
    let step = 10.0;
    let duration = 3000.0;
    let mut commanded = simulation(
        &scenario(step, "", ""),
        duration,
        Split {
            flip_every_ticks: None,
        },
    )
    .unwrap();
    commanded.run(&mut NullRecorder, &mut |_| {}).unwrap();
    let fixed_text = scenario(step, "", "").replace(
        "allow_initial_overlap = true",
        &format!("allow_initial_overlap = true\ndrag_area_m2 = [{LOW_M2}, {HIGH_M2}]"),
    );
    let fixed_scenario = Scenario::from_toml(&fixed_text, "fixed.toml", std::path::Path::new("."))
        .unwrap()
        .prepare()
        .unwrap();
    let mut config = fixed_scenario.config;
    config.duration_s = duration;
    config.record_interval_s = duration;
    let mut plain = Simulation::new(
        config,
        &fixed_scenario.satellites,
        fixed_scenario.law,
        fixed_scenario.events,
    )
    .unwrap();
    plain.run(&mut NullRecorder, &mut |_| {}).unwrap();
    for (a, b) in commanded.states_eci().iter().zip(plain.states_eci()) {
        assert_eq!(a.position_m, b.position_m);
        assert_eq!(a.velocity_mps, b.velocity_mps);
    }
}

#[test]
fn val_minimum_dwell_holds_a_mode_and_switches_are_counted() {
    // Commands flip every tick (10 s); with a 60 s dwell the area changes at most every 60 s.
    let step = 10.0;
    let mut sim = simulation(
        &scenario(step, "drag_min_dwell_s = 60.0", ""),
        600.0,
        Split {
            flip_every_ticks: Some(1),
        },
    )
    .unwrap();
    sim.run(&mut NullRecorder, &mut |_| {}).unwrap();
    // Ticks at 0, 10, …, 590 s; the command at tick k (t = 10 k s) is low for even k, high for odd k.
    // The satellites start low: the first change is to high at 10 s. After a change at t the next is
    // allowed from t + 60 s, when the command equals the current mode (the parity is the same), so it
    // comes one tick later, at t + 70 s: changes at 10, 80, 150, …, 570 s, nine in all.
    let switches = sim.drag_switches();
    assert_eq!(switches, vec![9, 9], "changes at 10, 80, …, 570 s");
    let mut free = simulation(
        &scenario(step, "", ""),
        600.0,
        Split {
            flip_every_ticks: Some(1),
        },
    )
    .unwrap();
    free.run(&mut NullRecorder, &mut |_| {}).unwrap();
    assert_eq!(
        free.drag_switches(),
        vec![59, 59],
        "a change at every tick but the first"
    );
}

#[test]
fn val_bad_drag_attitudes_are_refused_at_load_naming_the_key() {
    let refused = |text: String, key: &str| {
        let e = Scenario::from_toml(&text, "bad.toml", std::path::Path::new("."))
            .and_then(|s| s.prepare())
            .err()
            .unwrap_or_else(|| panic!("accepted: {key}"))
            .to_string();
        assert!(e.contains(key) && e.contains("bad.toml"), "{e}");
        e
    };
    let e = refused(
        scenario(10.0, "", "").replace(
            &format!("drag_modes_m2 = {{ low = {LOW_M2}, high = {HIGH_M2} }}"),
            "drag_modes_m2 = { low = -0.01, high = 0.035 }",
        ),
        "satellites.drag_modes_m2",
    );
    assert!(e.contains("-0.01"), "{e}");
    let e = refused(
        scenario(10.0, "drag_min_dwell_s = 5.0", ""),
        "satellites.drag_min_dwell_s",
    );
    assert!(e.contains(">= 10 s"), "{e}");
    refused(
        scenario(10.0, "", "drag_area_m2 = 0.02"),
        "satellites.drag_area_m2",
    );
    refused(
        scenario(10.0, "drag_area_range_m2 = [0.01, 0.02]", ""),
        "satellites.drag_area_range_m2",
    );
}
