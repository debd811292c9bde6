//! Regression tests for engine bugs found in review (fixed in a310185), each checked against an
//! independent reference and each failing on the old behaviour:
//!
//! 1. `Simulation::step()` mixed with `run()` sent time backwards (step bypassed the scheduler): the
//!    recorder must see increasing times, the clock must match the HCW closed form of the state, and
//!    `step()` ×15 then `run()` must end bit for bit where one `run()` ends.
//! 2. Kinematic model, sampled mode: the continuous obstacle monitor interpolated each segment with the
//!    previous tick's velocity; the clearance of a polyline path must be the analytic one.
//! 3. A law's `update_state` and `command` drew the same numbers from `LawContext::random()`: their first
//!    draws must differ and be uncorrelated.
//!
//! (The fourth, a law forging a `Neighbour`, is a `compile_fail` doc test on `Neighbour`.)

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};

use nalgebra::Vector3;
use satflock::dynamics::PhysicalProperties;
use satflock::environment::Obstacle;
use satflock::guidance::free_drift::FreeDrift;
use satflock::integrate::{IntegratorMethod, Tolerances};
use satflock::orbit::{EarthModel, KeplerianElements, RelativeStateHill};
use satflock::random::{Purpose, RandomStream};
use satflock::relative::Hcw;
use satflock::swarm::{
    Actuator, Broadcast, CommandKind, ControlTiming, DynamicsModel, EnvironmentSnapshot,
    GuidanceLaw, Law, LawContext, LawError, LimitKind, NullRecorder, Origin, Recorder,
    SatelliteInit, SatelliteView, Sensing, Simulation, SimulationConfig, Snapshot,
};

// ------------------------------------------------------------------------------------------------------
// Helpers (copied from tests/val_law_state.rs)
// ------------------------------------------------------------------------------------------------------

const A_M: f64 = 6_978_137.0;

fn n() -> f64 {
    EarthModel::WGS84_EGM96.mean_motion_rad_s(A_M)
}

fn config(dynamics: DynamicsModel, control: ControlTiming, duration_s: f64) -> SimulationConfig {
    let earth = EarthModel::WGS84_EGM96;
    let elements = KeplerianElements {
        semi_major_axis_m: A_M,
        eccentricity: 0.0,
        inclination_rad: 97.8f64.to_radians(),
        raan_rad: 0.0,
        arg_perigee_rad: 0.0,
        true_anomaly_rad: 0.0,
    };
    SimulationConfig {
        earth,
        dynamics,
        integrator: IntegratorMethod::Rk4,
        step_s: 1.0,
        tolerances: Tolerances {
            relative: 1e-10,
            absolute: 1e-6,
        },
        control,
        origin: Origin::VirtualReference,
        reference: elements.to_cartesian(earth.mu_m3_s2).unwrap(),
        reference_properties: PhysicalProperties::point_mass(10.0),
        mean_motion_rad_s: n(),
        duration_s,
        record_interval_s: duration_s,
        sensing: Sensing {
            range_m: 100.0,
            position_noise_m: 0.0,
            velocity_noise_mps: 0.0,
            ring_neighbours: None,
        },
        process_noise_m_s2: 0.0,
        threats: vec![],
        obstacles: vec![],
        tracked_objects: Vec::new(),
        max_distance_m: 1e6,
        seed: 5,
    }
}

fn state(p: [f64; 3], v: [f64; 3]) -> RelativeStateHill {
    RelativeStateHill {
        position_m: Vector3::from(p),
        velocity_mps: Vector3::from(v),
    }
}

fn satellites(states: &[RelativeStateHill]) -> Vec<SatelliteInit> {
    states
        .iter()
        .map(|s| SatelliteInit {
            relative_state: *s,
            properties: PhysicalProperties::point_mass(10.0),
            radius_m: 0.1,
            actuator: Actuator::new(f64::INFINITY, LimitKind::Norm),
            drag_attitudes: None,
        })
        .collect()
}

/// `count` satellites at rest, uniform in the box `[-half, half]` per axis (drawn from the library's own
/// counter-based streams, so the layout is fixed by `seed`).
fn scattered(count: usize, half_m: [f64; 3], seed: u64) -> Vec<RelativeStateHill> {
    (0..count)
        .map(|i| {
            let mut s = RandomStream::new(seed, Purpose::InitialStates, i as u64, 0);
            let p = Vector3::from_fn(|k, _| s.uniform_range(-half_m[k], half_m[k]));
            RelativeStateHill {
                position_m: p,
                velocity_mps: Vector3::zeros(),
            }
        })
        .collect()
}

fn bits(values: impl IntoIterator<Item = f64>) -> Vec<u64> {
    values.into_iter().map(f64::to_bits).collect()
}

fn correlation(a: &[f64], b: &[f64]) -> f64 {
    let m = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / m, b.iter().sum::<f64>() / m);
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        sab += (x - ma) * (y - mb);
        saa += (x - ma) * (x - ma);
        sbb += (y - mb) * (y - mb);
    }
    sab / (saa * sbb).sqrt()
}

/// Keeps everything a snapshot carries that the tests compare, bit for bit.
#[derive(Default, Debug, PartialEq)]
struct Collect {
    times: Vec<f64>,
    states: Vec<Vec<RelativeStateHill>>,
    delta_v: Vec<Vec<u64>>,
    outputs: Vec<Vec<u64>>,
    environment: Vec<EnvironmentSnapshot>,
    min_separation_bits: Vec<u64>,
}

impl Recorder for Collect {
    fn record(&mut self, s: &Snapshot<'_>) -> std::io::Result<()> {
        self.times.push(s.time_s);
        self.states.push(s.relative_states.to_vec());
        self.delta_v.push(bits(s.delta_v_mps.iter().copied()));
        self.outputs.push(bits(s.law_outputs.iter().copied()));
        self.environment.push(s.environment);
        self.min_separation_bits.push(s.min_separation_m.to_bits());
        Ok(())
    }
}

// ------------------------------------------------------------------------------------------------------
// (1) step() mixed with run()
// ------------------------------------------------------------------------------------------------------

/// HCW free motion from rest at (x0, 0, z0), written out by hand (not the library's Φ):
/// x = x0 (4 − 3 cos nt), y = 6 x0 (sin nt − nt), z = z0 cos nt and their derivatives.
fn hcw_from_rest(x0: f64, z0: f64, t: f64) -> RelativeStateHill {
    let n = n();
    let (s, c) = (n * t).sin_cos();
    state(
        [x0 * (4.0 - 3.0 * c), 6.0 * x0 * (s - n * t), z0 * c],
        [3.0 * x0 * n * s, 6.0 * x0 * n * (c - 1.0), -z0 * n * s],
    )
}

/// Asserts a state equals the hand-written HCW closed form at `t`. RK4 with h = 1 s on HCW: per step
/// the truncation is ~(n h)⁵/120 ≈ 1e-17 of the state, so rounding dominates (~1e-14 m over 30 steps).
/// One integration step of 1 s in the wrong place moves x by 1.5·x0·n²·t·h ≈ 5e-4 m here.
fn assert_hcw(got: &RelativeStateHill, x0: f64, z0: f64, t: f64, what: &str) -> f64 {
    let exact = hcw_from_rest(x0, z0, t);
    let dp = (got.position_m - exact.position_m).norm();
    let dv = (got.velocity_mps - exact.velocity_mps).norm();
    assert!(
        dp <= 1e-9 && dv <= 1e-12,
        "{what}: state differs from HCW at t = {t} s by {dp:.3e} m, {dv:.3e} m/s"
    );
    dp
}

#[test]
fn regress_step_then_run_keeps_time_increasing_and_equals_one_run() {
    // HCW, sampled 1 s, 30 s, recordings every 10 s; one satellite at rest at (10, 0, 20) m, free drift.
    // 15 × step() then run(). Old behaviour: step() kept its own clock, run() started over from the
    // recording count (a snapshot at 15 s, then 10 s: time went backwards) and ended 5 s late (35 s
    // of motion labelled 30 s).
    let (x0, z0) = (10.0, 20.0);
    let initial = [state([x0, 0.0, z0], [0.0; 3])];
    let make = || {
        let mut cfg = config(
            DynamicsModel::Hcw(Hcw::new(n())),
            ControlTiming::Sampled { period_s: 1.0 },
            30.0,
        );
        cfg.record_interval_s = 10.0;
        Simulation::new(cfg, &satellites(&initial), Law::new(FreeDrift), vec![]).unwrap()
    };

    let mut stepped = make();
    for k in 1..=15 {
        stepped.step().unwrap();
        assert_eq!(stepped.time_s(), k as f64, "clock after step {k}");
    }
    assert_hcw(&stepped.states_hill()[0], x0, z0, 15.0, "after 15 steps");
    let mut b = Collect::default();
    let mut progress = Vec::new();
    stepped.run(&mut b, &mut |t| progress.push(t)).unwrap();

    // Strictly increasing times, seen by the recorder and by the progress callback, past 15 s.
    assert!(
        b.times.windows(2).all(|w| w[0] < w[1]),
        "recorded times not increasing: {:?}",
        b.times
    );
    assert!(
        progress.windows(2).all(|w| w[0] < w[1]) && progress.first() > Some(&15.0),
        "progress times: {progress:?}"
    );
    // step() passes the recording times it crosses (no recorder): run() records the remaining ones.
    assert_eq!(b.times, vec![20.0, 30.0]);
    assert_eq!(progress.last(), Some(&30.0));

    // The clock matches the state: every snapshot, and the end, against the HCW closed form.
    assert_eq!(stepped.time_s(), 30.0);
    for (t, states) in b.times.iter().zip(&b.states) {
        assert_hcw(&states[0], x0, z0, *t, "snapshot");
    }
    let end_error = assert_hcw(&stepped.states_hill()[0], x0, z0, 30.0, "end of run");
    eprintln!(
        "step x15 + run: recorded at {:?} s, clock {} s, position error vs HCW {end_error:.2e} m",
        b.times,
        stepped.time_s()
    );

    // The same scheduling as one uninterrupted run: final state bit for bit, same snapshots at the
    // recording times both saw.
    let mut whole = make();
    let mut a = Collect::default();
    whole.run(&mut a, &mut |_| {}).unwrap();
    assert_eq!(a.times, vec![0.0, 10.0, 20.0, 30.0]);
    assert_eq!(
        bits(whole.state().as_slice().iter().copied()),
        bits(stepped.state().as_slice().iter().copied()),
        "final state"
    );
    assert_eq!(whole.time_s(), stepped.time_s());
    assert_eq!(whole.totals(), stepped.totals());
    let tail = Collect {
        times: a.times[2..].to_vec(),
        states: a.states[2..].to_vec(),
        delta_v: a.delta_v[2..].to_vec(),
        outputs: a.outputs[2..].to_vec(),
        environment: a.environment[2..].to_vec(),
        min_separation_bits: a.min_separation_bits[2..].to_vec(),
    };
    assert_eq!(tail, b, "snapshots at 20 s and 30 s");
}

// ------------------------------------------------------------------------------------------------------
// (2) Kinematic model, sampled: the monitor's start velocity
// ------------------------------------------------------------------------------------------------------

/// Velocity command +y before 5 s, +x from 5 s on (1 m/s).
struct Turn;

impl GuidanceLaw for Turn {
    type State = ();
    type Parameters = ();
    fn name(&self) -> &'static str {
        "turn"
    }
    fn command_kind(&self) -> CommandKind {
        CommandKind::Velocity
    }
    fn command(&self, s: &SatelliteView<'_>, _state: &(), _c: &LawContext) -> Vector3<f64> {
        if s.shared().time_s < 5.0 - 1e-9 {
            Vector3::new(0.0, 1.0, 0.0)
        } else {
            Vector3::new(1.0, 0.0, 0.0)
        }
    }
    fn set_parameters(&mut self, _p: &()) -> Result<(), LawError> {
        Ok(())
    }
}

#[test]
fn regress_kinematic_sampled_monitor_uses_the_followed_velocity() {
    // Kinematic model, sampled 1 s, 10 s, from the origin: the held velocity commands make the path
    // the polyline (0,0,0) → (0,5,0) → (5,5,0), exactly. Obstacle: centre (0.5, 7, 0), radius 1.5 m.
    // First leg: nearest point (0,5,0), distance √(0.5² + 2²) = 2.0616 m. Second leg (x, 5, 0): nearest
    // at x = 0.5, i.e. t = 5.5 s, distance 2 m. Analytic clearance: 2 − 1.5 = 0.5 m at t = 5.5 s.
    // Every segment is straight, so the monitor's closed form is exact up to rounding: 1e-9 m, 1e-9 s.
    // Old behaviour: the segment [5, 6] was interpolated with the start velocity (0, 1, 0) of the
    // previous tick, a bent cubic passing closer to the obstacle.
    let centre = Vector3::new(0.5, 7.0, 0.0);
    let radius = 1.5;
    let mut cfg = config(
        DynamicsModel::Kinematic,
        ControlTiming::Sampled { period_s: 1.0 },
        10.0,
    );
    cfg.obstacles = vec![Obstacle::new("o", centre, radius).unwrap()];
    let initial = [state([0.0; 3], [0.0; 3])];
    let mut sim = Simulation::new(cfg, &satellites(&initial), Law::new(Turn), vec![]).unwrap();
    sim.run(&mut NullRecorder, &mut |_| {}).unwrap();

    let end = sim.states_hill()[0];
    assert!(
        (end.position_m - Vector3::new(5.0, 5.0, 0.0)).norm() <= 1e-12,
        "end of the polyline: {:?}",
        end.position_m
    );
    let expected_clearance = (centre - Vector3::new(0.5, 5.0, 0.0)).norm() - radius;
    assert_eq!(expected_clearance, 0.5);
    let got = sim.approach_monitor().obstacle_clearance(0, 0).unwrap();
    eprintln!(
        "kinematic sampled: monitor clearance {:.15} m at {:.12} s (analytic 0.5 m at 5.5 s)",
        got.clearance_m, got.time_s
    );
    assert!(
        (got.clearance_m - expected_clearance).abs() <= 1e-9,
        "clearance {} m, analytic 0.5 m",
        got.clearance_m
    );
    assert!(
        (got.time_s - 5.5).abs() <= 1e-9,
        "time of the minimum {} s, analytic 5.5 s",
        got.time_s
    );
    assert_eq!(sim.approach_monitor().obstacle_incursions(0, 0), 0);
}

// ------------------------------------------------------------------------------------------------------
// (3) Independent random streams for a law's update and command
// ------------------------------------------------------------------------------------------------------

/// (satellite, tick) → first uniform draw.
type Draws = Arc<Mutex<BTreeMap<(usize, u64), f64>>>;

/// Takes the first uniform of its context's stream in the update and in the command and writes each
/// down, keyed by satellite and tick. Commands nothing.
struct DrawRecorder {
    update: Draws,
    command: Draws,
}

impl GuidanceLaw for DrawRecorder {
    type State = f64;
    type Parameters = ();
    fn name(&self) -> &'static str {
        "draw-recorder"
    }
    fn update_state(&self, s: &SatelliteView<'_>, _b: &Broadcast<'_, f64>, c: &LawContext) -> f64 {
        let u = c.random().uniform();
        let old = self.update.lock().unwrap().insert((s.id(), c.tick), u);
        assert!(
            old.is_none(),
            "two updates of {} at tick {}",
            s.id(),
            c.tick
        );
        u
    }
    fn command(&self, s: &SatelliteView<'_>, _state: &f64, c: &LawContext) -> Vector3<f64> {
        let u = c.random().uniform();
        let old = self.command.lock().unwrap().insert((s.id(), c.tick), u);
        assert!(
            old.is_none(),
            "two commands of {} at tick {}",
            s.id(),
            c.tick
        );
        Vector3::zeros()
    }
    fn set_parameters(&mut self, _p: &()) -> Result<(), LawError> {
        Ok(())
    }
}

#[test]
fn regress_law_update_and_command_draw_from_independent_streams() {
    // 64 satellites, sampled 1 s, 100 ticks: N ≈ 6400 (satellite, tick) pairs of first draws. Under
    // independence the sample correlation of the pairs has standard deviation 1/√N, so |r| < 4.5/√N
    // fails by chance with probability ~7e-6; the draws, 53-bit uniforms, coincide with probability
    // ~N·2⁻⁵³. Old behaviour: one stream for both, the same number every time (r = 1).
    let (count, ticks) = (64, 100);
    let update: Draws = Arc::default();
    let command: Draws = Arc::default();
    let law = DrawRecorder {
        update: update.clone(),
        command: command.clone(),
    };
    let cfg = config(
        DynamicsModel::Hcw(Hcw::new(n())),
        ControlTiming::Sampled { period_s: 1.0 },
        ticks as f64,
    );
    let initial = scattered(count, [50.0; 3], 3);
    let mut sim = Simulation::new(cfg, &satellites(&initial), Law::new(law), vec![]).unwrap();
    sim.run(&mut NullRecorder, &mut |_| {}).unwrap();

    let update = update.lock().unwrap();
    let command = command.lock().unwrap();
    let (mut a, mut b) = (Vec::new(), Vec::new());
    for (key, u) in update.iter() {
        if let Some(c) = command.get(key) {
            assert_ne!(u, c, "satellite {} tick {}: same draw", key.0, key.1);
            a.push(*u);
            b.push(*c);
        }
    }
    let pairs = a.len();
    assert!(
        pairs >= count * (ticks - 1),
        "only {pairs} (satellite, tick) pairs with both an update and a command"
    );
    let r = correlation(&a, &b);
    let limit = 4.5 / (pairs as f64).sqrt();
    eprintln!("update vs command first draws: N = {pairs}, r = {r:.4} (limit {limit:.4})");
    assert!(r.abs() < limit, "correlation {r} over {pairs} pairs");
}
