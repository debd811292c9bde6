//! Validation of the `pigeon` law (H. Qiu, Q. Zhou, C. Sun, X. Wang, Y. Feng, "Distributed Satellite
//! Formation Based on Swarm Intelligence of Pigeon Flocks", IEEE conference paper), each check against a
//! reference independent of the code under test:
//!
//! * P5: with the default radial PD on HCW truth, the ten satellites of the paper's Table I are within
//!   0.5 m of the y–z plane after 60 s, and each x(t) follows the critically damped closed form;
//! * P8: the saturated thrust is within the per-axis limit and the back-substituted accelerations satisfy
//!   the CW equations written out here (1e-12); in a run, the per-axis delta-v ledger never grows faster
//!   than the limit;
//! * P10: p_h at V_a = 1 and 0 against the closed forms;
//! * the formation and obstacle forces against central finite differences of the potentials, through
//!   the law's own flock acceleration (this also checks the z-first pigeon coordinates);
//! * continuity and C¹ of V^F at R_d and of V^O at ρ;
//! * a whole switching run bitwise identical on 1 and 2 threads;
//! * the `[law]` keys, the refusal of a too-long control period and of a sensing range below R_c^2;
//! * the load-time warning of an initial egalitarian link graph that is not connected: at
//!   R_c^1 = 120 m it names satellite 0 and its nearest distance 115.3 m computed by hand from Table I;
//!   none at the default 130 m.
//!
//! P9 (hysteresis) and the P10 draw frequency are unit tests in `src/guidance/pigeon/tests.rs`.
//! Hill frame (x radial out, y along-track, z orbit normal), SI units.

use nalgebra::{Vector2, Vector3};
use satflock::dynamics::PhysicalProperties;
use satflock::environment::Obstacle;
use satflock::grid::NeighbourGrid;
use satflock::guidance::pigeon::potentials::{target_potential_m3, target_slope_m2};
use satflock::guidance::pigeon::switching::hierarchical_probability;
use satflock::guidance::pigeon::{
    cw_thrust, FormationPotential, ObstaclePotential, Pigeon, PigeonParameters, PigeonState,
};
use satflock::guidance::LawConfig;
use satflock::integrate::{IntegratorMethod, Tolerances};
use satflock::orbit::{EarthModel, KeplerianElements, RelativeStateHill};
use satflock::random::{Purpose, RandomStream};
use satflock::relative::{Hcw, SchweighartSedwick};
use satflock::swarm::{
    Actuator, ControlTiming, DynamicsModel, EnvironmentView, GuidanceLaw, Law, LimitKind, Origin,
    Recorder, SatelliteInit, Sensing, SharedInfo, SimError, Simulation, SimulationConfig, Snapshot,
    SwarmView,
};

/// Target orbit radius r_T \[m\] (our reconstruction, `docs/methods/pigeon.md`).
const R_T_M: f64 = 7_400_000.0;
/// Per-axis thrust limit \[m/s²\] (our reconstruction, `docs/methods/pigeon.md`).
const LIMIT_M_S2: f64 = 5.0;

fn n() -> f64 {
    EarthModel::WGS84_EGM96.mean_motion_rad_s(R_T_M)
}

/// Table I: (x, y, z) \[m\], (ẋ, ẏ, ż) \[m/s\].
const TABLE_I: [[f64; 6]; 10] = [
    [0.6, -163.0, -694.4, -2.3, 1.0, -3.0],
    [-1.6, -45.1, -783.6, 0.2, 3.5, 1.5],
    [-4.5, -139.7, -807.3, 4.6, 0.5, 4.3],
    [1.0, -242.8, -806.0, -1.4, 2.2, 0.2],
    [0.7, -64.8, -918.5, -4.8, 4.2, -4.9],
    [-0.5, -145.6, -894.9, 3.2, 4.2, -1.7],
    [3.0, -244.7, -926.7, -1.3, -1.1, -3.5],
    [4.2, -49.0, -1007.1, -2.6, -4.5, -4.6],
    [3.8, -139.7, -990.3, 3.3, -4.6, -2.5],
    [-4.9, -250.7, -1011.5, -1.5, 2.0, -4.0],
];

fn table_i() -> Vec<RelativeStateHill> {
    TABLE_I
        .iter()
        .map(|r| RelativeStateHill {
            position_m: Vector3::new(r[0], r[1], r[2]),
            velocity_mps: Vector3::new(r[3], r[4], r[5]),
        })
        .collect()
}

/// The two obstacles of our reconstruction, spheres centred in the y–z plane: (z, y) = (−400, −80) m, r = 100 m and
/// (−800, 130) m, r = 80 m, detected from R_c^3 = 100 m off the surface.
fn obstacles() -> Vec<Obstacle> {
    [((-400.0, -80.0), 100.0), ((-800.0, 130.0), 80.0)]
        .iter()
        .enumerate()
        .map(|(k, ((z, y), r))| {
            Obstacle::new(format!("obstacle {k}"), Vector3::new(0.0, *y, *z), *r)
                .unwrap()
                .with_detection_range_m(100.0)
                .unwrap()
        })
        .collect()
}

fn config(
    period_s: f64,
    duration_s: f64,
    record_interval_s: f64,
    range_m: f64,
) -> SimulationConfig {
    let earth = EarthModel::WGS84_EGM96;
    let elements = KeplerianElements {
        semi_major_axis_m: R_T_M,
        eccentricity: 0.0,
        inclination_rad: std::f64::consts::FRAC_PI_4,
        raan_rad: std::f64::consts::FRAC_PI_6,
        arg_perigee_rad: 0.0,
        true_anomaly_rad: 0.0,
    };
    SimulationConfig {
        earth,
        dynamics: DynamicsModel::Hcw(Hcw::new(n())),
        integrator: IntegratorMethod::Rk4,
        step_s: period_s,
        tolerances: Tolerances {
            relative: 1e-10,
            absolute: 1e-9,
        },
        control: ControlTiming::Sampled { period_s },
        origin: Origin::VirtualReference,
        reference: elements.to_cartesian(earth.mu_m3_s2).unwrap(),
        reference_properties: PhysicalProperties::point_mass(10.0),
        mean_motion_rad_s: n(),
        duration_s,
        record_interval_s,
        sensing: Sensing {
            range_m,
            position_noise_m: 0.0,
            velocity_noise_mps: 0.0,
            ring_neighbours: None,
        },
        process_noise_m_s2: 0.0,
        threats: vec![],
        obstacles: obstacles(),
        tracked_objects: Vec::new(),
        max_distance_m: 1e6,
        seed: 2024,
    }
}

fn satellites() -> Vec<SatelliteInit> {
    table_i()
        .into_iter()
        .map(|s| SatelliteInit {
            relative_state: s,
            properties: PhysicalProperties::point_mass(10.0),
            radius_m: 0.5,
            actuator: Actuator::new(LIMIT_M_S2, LimitKind::PerAxis),
            drag_attitudes: None,
        })
        .collect()
}

#[derive(Default)]
struct Collect {
    times: Vec<f64>,
    states: Vec<Vec<RelativeStateHill>>,
    delta_v_axes: Vec<Vec<[f64; 3]>>,
    outputs: Vec<Vec<f64>>,
    metrics: Vec<Vec<f64>>,
    metric_names: Vec<&'static str>,
}

impl Recorder for Collect {
    fn record(&mut self, s: &Snapshot<'_>) -> std::io::Result<()> {
        self.times.push(s.time_s);
        self.states.push(s.relative_states.to_vec());
        self.delta_v_axes.push(s.delta_v_axes_mps.to_vec());
        self.outputs.push(s.law_outputs.to_vec());
        self.metrics.push(s.law_metrics.to_vec());
        self.metric_names = s.law_metric_names.to_vec();
        Ok(())
    }
}

fn run(parameters: PigeonParameters, duration_s: f64, record_s: f64) -> (Collect, Simulation) {
    let law = Pigeon::new(parameters).unwrap();
    let mut sim = Simulation::new(
        config(0.1, duration_s, record_s, 150.0),
        &satellites(),
        Law::new(law),
        vec![],
    )
    .unwrap();
    let mut rec = Collect::default();
    sim.run(&mut rec, &mut |_| {}).unwrap();
    (rec, sim)
}

#[test]
fn val_p5_radial_pd_brings_table_i_into_the_yz_plane_and_p8_ledger_respects_the_limit() {
    let (rec, _) = run(PigeonParameters::default(), 80.0, 0.5);
    // P5: max |x| < 0.5 m at every recording from 60 s on.
    let mut worst: f64 = 0.0;
    for (t, states) in rec.times.iter().zip(&rec.states) {
        if *t >= 60.0 {
            worst = states
                .iter()
                .map(|s| s.position_m.x.abs())
                .fold(worst, f64::max);
        }
    }
    assert!(worst < 0.5, "max |x| after 60 s = {worst} m");
    // Independent reference: the radial channel is never saturated here (|f^x| ≤ K^P|x| + K^D|ẋ| + 2n|ẏ|
    // + 3n²|x| < 2 m/s² for Table I), so x obeys ẍ = −K^P x − K^D ẋ with the command held over
    // t_s = 0.1 s: the critically damped closed form x(t) = (x₀ + (ẋ₀ + ω x₀) t) e^(−ωt), ω = 0.2 rad/s.
    // The sampled loop is the continuous one with the feedback held for up to t_s: the acceleration
    // difference is ≤ (K^P |ẋ| + K^D |ẍ|) t_s, which decays with the transient (∝ t e^(−ωt)). At 10 s
    // |ẋ| ≲ 0.6 m/s and |ẍ| ≲ 0.2 m/s² for Table I, a difference ≲ 0.02 m/s² whose response through the
    // loop (impulse response t e^(−ωt), integral 1/ω² = 25 s²) is ≲ 0.5 m: we gate at that derived bound
    // after 10 s (the largest deviation observed, 0.15 m, is printed).
    let omega = 0.2;
    let mut largest: f64 = 0.0;
    for (t, states) in rec.times.iter().zip(&rec.states) {
        if *t < 10.0 {
            continue;
        }
        for (s, r) in states.iter().zip(TABLE_I) {
            let reference = (r[0] + (r[3] + omega * r[0]) * t) * (-omega * t).exp();
            largest = largest.max((s.position_m.x - reference).abs());
            assert!(
                (s.position_m.x - reference).abs() <= 0.5,
                "t = {t}: x {} vs closed form {reference}",
                s.position_m.x
            );
        }
    }
    eprintln!("P5: max |x| after 60 s = {worst:e} m; largest deviation from the closed form after 10 s = {largest:e} m");
    // P8 in a run: the per-axis delta-v ledger (∫|f̄_k| dt) never grows faster than the limit; 1e-9
    // relative for the ledger's RK4 rounding.
    for w in rec.delta_v_axes.windows(2).zip(rec.times.windows(2)) {
        let ((a, b), dt) = ((&w.0[0], &w.0[1]), w.1[1] - w.1[0]);
        for (da, db) in a.iter().zip(b) {
            for k in 0..3 {
                assert!(db[k] - da[k] <= LIMIT_M_S2 * dt * (1.0 + 1e-9), "axis {k}");
            }
        }
    }
    // The metrics are written and finite; the switch counter never decreases.
    let k = rec
        .metric_names
        .iter()
        .position(|m| *m == "pigeon_switches")
        .unwrap();
    assert!(rec.metrics.windows(2).all(|m| m[1][k] >= m[0][k]));
    assert!(rec.metrics.iter().flatten().all(|v| v.is_finite()));
}

#[test]
fn val_p8_saturated_thrust_is_within_the_limit_and_back_substitution_satisfies_cw() {
    // Random states and desired accelerations (up to 4× the limit, so every axis is saturated in part of
    // the draws). CW written out here: ẍ − 2nẏ − 3n²x = f̄^x, ÿ + 2nẋ = f̄^y, z̈ + n²z = f̄^z, with
    // (z̈, ÿ) = the back-substituted pigeon acceleration and ẍ the back-substituted radial one. 1e-12
    // absolute on accelerations of ≤ 20 m/s² is ~20 ulps: rounding of the three-term sums only.
    let n = n();
    let mut rng = RandomStream::new(1, Purpose::InitialStates, 0, 0);
    let mut saturated = [0usize; 3];
    for _ in 0..10_000 {
        let mut draw = |scale: f64| rng.uniform_range(-scale, scale);
        let p = Vector3::new(draw(1e3), draw(1e3), draw(1e3));
        let v = Vector3::new(draw(10.0), draw(10.0), draw(10.0));
        let u = Vector2::new(draw(20.0), draw(20.0));
        let radial = draw(20.0);
        let t = cw_thrust(&p, &v, &u, radial, n, LIMIT_M_S2);
        let f = t.saturated_m_s2;
        for k in 0..3 {
            assert!(f[k].abs() <= LIMIT_M_S2);
            saturated[k] += usize::from(f[k] != t.required_m_s2[k]);
        }
        let (xdd, ydd, zdd) = (
            t.radial_accel_m_s2,
            t.pigeon_accel_m_s2[1],
            t.pigeon_accel_m_s2[0],
        );
        assert!((xdd - 2.0 * n * v.y - 3.0 * n * n * p.x - f.x).abs() <= 1e-12);
        assert!((ydd + 2.0 * n * v.x - f.y).abs() <= 1e-12);
        assert!((zdd + n * n * p.z - f.z).abs() <= 1e-12);
        // Unsaturated axes reproduce the desired accelerations.
        if f.x == t.required_m_s2.x {
            assert!((xdd - radial).abs() <= 1e-12);
        }
        if f.y == t.required_m_s2.y {
            assert!((ydd - u[1]).abs() <= 1e-12);
        }
        if f.z == t.required_m_s2.z {
            assert!((zdd - u[0]).abs() <= 1e-12);
        }
    }
    assert!(
        saturated.iter().all(|c| *c > 1000),
        "saturation exercised: {saturated:?}"
    );
}

#[test]
fn val_p10_switching_probability_limits() {
    // p_h(1) = 1/(1 + α), p_h(0) = 1/(1 + α e^(−β)) (paper §2.6); evaluated to the last few ulps.
    for (alpha, beta) in [(9.0_f64, 10.0_f64), (2.0, 0.5), (100.0, 3.0)] {
        let one = hierarchical_probability(1.0, alpha, beta);
        let zero = hierarchical_probability(0.0, alpha, beta);
        assert!((one - 1.0 / (1.0 + alpha)).abs() <= 1e-15);
        assert!((zero - 1.0 / (1.0 + alpha * (-beta).exp())).abs() <= 1e-15);
        assert!(one < 0.5 && zero > one);
    }
    assert!((hierarchical_probability(1.0, 9.0, 10.0) - 0.1).abs() <= 1e-16);
}

// ------------------------------------------------------------------------------------------------------
// Potentials: forces against finite differences, continuity and C¹
// ------------------------------------------------------------------------------------------------------

/// Central difference of `f` at `r` with step `h`.
fn central(f: impl Fn(f64) -> f64, r: f64, h: f64) -> f64 {
    (f(r + h) - f(r - h)) / (2.0 * h)
}

#[test]
fn val_potential_slopes_match_finite_differences_and_are_c1_at_the_joins() {
    // Central differences with h = 1e-4 m: truncation h²|V'''|/6 ≲ 1e-8 · |V'''| and rounding
    // ε|V|/h ≲ 2e-16 · 1e4 / 1e-4 = 2e-8 m; we allow 1e-6 m + 1e-6 relative.
    let formation = FormationPotential {
        min_separation_m: 20.0,
        desired_separation_m: 40.0,
        link_range_m: 120.0,
    };
    let h = 1e-4;
    let mut r = 20.5;
    while r < 119.5 {
        if (r - 40.0_f64).abs() > 2.0 * h {
            let fd = central(|q| formation.potential_m2(q), r, h);
            let slope = formation.slope_m(r);
            assert!(
                (fd - slope).abs() <= 1e-6 + 1e-6 * slope.abs(),
                "V^F at {r}: {fd} vs {slope}"
            );
        }
        r += 0.37;
    }
    for radius in [100.0, 80.0, 5.0] {
        let obstacle = ObstaclePotential {
            radius_m: radius,
            min_clearance_m: 10.0,
            detection_m: 100.0,
        };
        let mut r = radius + 10.5;
        while r < radius + 130.0 {
            if (r - obstacle.outer_m()).abs() > 2.0 * h {
                let fd = central(|q| obstacle.potential_m2(q), r, h);
                let slope = obstacle.slope_m(r);
                assert!(
                    (fd - slope).abs() <= 1e-6 + 1e-6 * slope.abs(),
                    "V^O at {r}: {fd} vs {slope}"
                );
            }
            r += 0.53;
        }
        // C¹ at ρ: slope zero at ρ and beyond, |slope| ≤ V''(ρ⁻) ε + O(ε²) just inside, with
        // V''(ρ⁻) = 2 c², c = ρ/(R_c^3 − R_L^4); potential continuous (difference O(ε²)).
        let rho = obstacle.outer_m();
        let c = rho / 90.0;
        assert!(obstacle.slope_m(rho).abs() <= 1e-12 * rho && obstacle.slope_m(rho + 1e-9) == 0.0);
        for eps in [1e-3, 1e-4] {
            assert!(obstacle.slope_m(rho - eps).abs() <= 2.0 * c * c * eps * 1.01);
            let jump = obstacle.potential_m2(rho - eps) - obstacle.potential_m2(rho + eps);
            assert!(
                jump.abs() <= c * c * eps * eps * 1.01 + 1e-9 * rho * rho,
                "V^O jump {jump}"
            );
        }
        // Barrier: +∞ at the clearance limit, finite clamped force just outside it.
        assert!(obstacle.potential_m2(obstacle.inner_m()).is_infinite());
        assert!(
            obstacle.slope_m(obstacle.inner_m()).is_finite()
                && obstacle.slope_m(obstacle.inner_m()) < 0.0
        );
    }
    // C¹ at R_d: zero slope from both sides; V'' = 2c² on each side, c_A = 2, c_B = 0.5.
    assert!(formation.slope_m(40.0).abs() <= 1e-12);
    for eps in [1e-3, 1e-4] {
        assert!(
            formation.slope_m(40.0 - eps) < 0.0
                && formation.slope_m(40.0 - eps) >= -8.0 * eps * 1.01
        );
        assert!(
            formation.slope_m(40.0 + eps) > 0.0
                && formation.slope_m(40.0 + eps) <= 0.5 * eps * 1.01
        );
        let jump = formation.potential_m2(40.0 - eps) - formation.potential_m2(40.0 + eps);
        assert!(
            jump.abs() <= 4.0 * eps * eps * 1.01 + 1e-12,
            "V^F jump {jump}"
        );
    }
    // Guards: the clamped slope at and past both barriers is finite, repulsive below R_L^3 and
    // attractive beyond R_c^1, and equals the slope at s = 1e-3 R_d.
    let at_clamp_a = formation.slope_m(20.0 + 1e-3 * 40.0 / 2.0);
    assert_eq!(formation.slope_m(20.0), at_clamp_a);
    assert_eq!(formation.slope_m(15.0), at_clamp_a);
    assert!(
        at_clamp_a < 0.0 && formation.slope_m(130.0) > 0.0 && formation.slope_m(130.0).is_finite()
    );
    // V^T: slope against finite differences, zero inside the zone, C¹ at it.
    for r in [50.5, 80.0, 300.0, 800.0] {
        let fd = central(|q| target_potential_m3(q, 50.0), r, h);
        assert!((fd - target_slope_m2(r, 50.0)).abs() <= 1e-6 * fd.abs().max(1.0));
    }
    assert_eq!(target_slope_m2(49.0, 50.0), 0.0);
}

/// A scene of satellites (and obstacles) as a law sees it: sensing range 200 m.
struct Scene {
    states: Vec<RelativeStateHill>,
    masses_kg: Vec<f64>,
    flags: Vec<bool>,
    grid: NeighbourGrid,
    obstacles: Vec<Obstacle>,
}

impl Scene {
    fn new(positions: &[Vector3<f64>], obstacles: Vec<Obstacle>) -> Self {
        let states: Vec<RelativeStateHill> = positions
            .iter()
            .map(|p| RelativeStateHill {
                position_m: *p,
                velocity_mps: Vector3::zeros(),
            })
            .collect();
        let mut grid = NeighbourGrid::new();
        let (x, y, z): (Vec<f64>, Vec<f64>, Vec<f64>) = (
            positions.iter().map(|p| p.x).collect(),
            positions.iter().map(|p| p.y).collect(),
            positions.iter().map(|p| p.z).collect(),
        );
        grid.build(&x, &y, &z, 200.0).unwrap();
        let count = positions.len();
        Self {
            states,
            masses_kg: vec![10.0; count],
            flags: vec![true; count],
            grid,
            obstacles,
        }
    }

    fn view(&self) -> SwarmView<'_> {
        let earth = EarthModel::WGS84_EGM96;
        SwarmView::new(
            &self.states,
            &self.masses_kg,
            &self.flags,
            &self.flags,
            &self.grid,
            SharedInfo {
                time_s: 0.0,
                mean_motion_rad_s: n(),
                sensing_range_m: 200.0,
                reference_model: SchweighartSedwick::new(
                    R_T_M,
                    0.0,
                    earth.mu_m3_s2,
                    earth.equatorial_radius_m,
                    0.0,
                ),
            },
            EnvironmentView {
                threats: &[],
                obstacles: &self.obstacles,
                threat_warnings: &[],
            },
        )
    }
}

#[test]
fn val_flock_forces_are_minus_the_gradient_of_the_summed_potentials_in_z_y_order() {
    // Satellite 0 with three egalitarian neighbours (both branches of V^F) and one obstacle within
    // detection: its flock acceleration (no alignment: every velocity zero; not dominant) must equal
    // −K^F ∇Σ V^F − K^O ∇V^O, the gradient taken by central differences of the potentials with respect
    // to satellite 0's z (first component) and y (second) — the independent reference for both the
    // slopes' directions and the pigeon coordinate order. Tolerance as in the slope test.
    let p = PigeonParameters {
        dominant: vec![],
        ..PigeonParameters::default()
    };
    let law = Pigeon::new(p.clone()).unwrap();
    let own = Vector3::new(0.3, 10.0, -20.0);
    let others = [
        Vector3::new(0.0, 40.0, -5.0),   // 33.5 m: repulsive branch
        Vector3::new(-0.2, -50.0, 10.0), // 67 m: attractive branch
        Vector3::new(0.1, 90.0, -70.0),  // 94 m: attractive, near the connectivity barrier
    ];
    let obstacle = Obstacle::new("o", Vector3::new(0.0, -40.0, -100.0), 30.0).unwrap();
    let mut positions = vec![own];
    positions.extend_from_slice(&others);
    let scene = Scene::new(&positions, vec![obstacle]);
    let state = PigeonState::with_links(&[1, 2, 3], None);
    let u = law.flock_acceleration(&scene.view().satellite(0), &state);
    let formation = law.formation_potential();
    let obstacle = law.obstacle_potential(30.0);
    let energy = |z: f64, y: f64| {
        let mut e = 0.0;
        for o in &others {
            e += p.k_formation_per_s2 * formation.potential_m2((z - o.z).hypot(y - o.y));
        }
        e + p.k_obstacle_per_s2 * obstacle.potential_m2((z + 100.0).hypot(y + 40.0))
    };
    let h = 1e-4;
    let dz = (energy(own.z + h, own.y) - energy(own.z - h, own.y)) / (2.0 * h);
    let dy = (energy(own.z, own.y + h) - energy(own.z, own.y - h)) / (2.0 * h);
    assert!(
        (u[0] + dz).abs() <= 1e-7 + 1e-6 * dz.abs(),
        "z: {} vs {}",
        u[0],
        -dz
    );
    assert!(
        (u[1] + dy).abs() <= 1e-7 + 1e-6 * dy.abs(),
        "y: {} vs {}",
        u[1],
        -dy
    );
    assert!(
        u.norm() > 1e-2,
        "the check is not vacuous: |u| = {}",
        u.norm()
    );
}

// ------------------------------------------------------------------------------------------------------
// Determinism, keys, refusals
// ------------------------------------------------------------------------------------------------------

#[test]
fn val_switching_run_is_bitwise_identical_on_one_and_two_threads() {
    let once = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let (rec, sim) = run(PigeonParameters::default(), 20.0, 1.0);
            let bits: Vec<u64> = rec
                .states
                .iter()
                .flatten()
                .flat_map(|s| [s.position_m, s.velocity_mps])
                .flat_map(|v| [v.x, v.y, v.z])
                .chain(rec.outputs.iter().flatten().copied())
                .chain(rec.metrics.iter().flatten().copied())
                .map(f64::to_bits)
                .collect();
            (bits, sim.law_outputs())
        })
    };
    let (one, out_one) = once(1);
    let (two, out_two) = once(2);
    assert_eq!(one, two);
    assert_eq!(out_one, out_two);
    // The run did switch patterns (the check is not vacuous).
    let (rec, _) = run(PigeonParameters::default(), 20.0, 1.0);
    let k = rec
        .metric_names
        .iter()
        .position(|m| *m == "pigeon_switches")
        .unwrap();
    assert!(rec.metrics.last().unwrap()[k] > 0.0);
}

#[test]
fn val_law_keys_parse_and_bad_values_and_setups_are_refused() {
    let text = r#"
        name = "pigeon"
        switching = true
        dominant = [0, 1, 2]
        target_hill_m = [0.0, 0.0, 0.0]
        egalitarian_range_m = 130.0
        hierarchical_range_m = 150.0
        link_delay_m = 10.0
        min_separation_m = 20.0
        desired_separation_m = 40.0
        target_zone_m = 50.0
        min_clearance_m = 10.0
        obstacle_detection_m = 100.0
        k_formation_per_s2 = 0.02
        k_target_per_m_s2 = 1e-5
        k_alignment_per_s = 0.3
        k_obstacle_per_s2 = 0.05
        k_radial_p_per_s2 = 0.04
        k_radial_d_per_s = 0.4
        alpha = 9.0
        beta = 10.0
        leader_weight = 3.0
        target_velocity_damping_per_s = 0.0
    "#;
    let config: LawConfig = toml::from_str(text).unwrap();
    assert_eq!(config.name(), "pigeon");
    let LawConfig::Pigeon(p) = &config else {
        panic!("wrong variant")
    };
    assert_eq!(**p, PigeonParameters::default());
    let minimal: LawConfig = toml::from_str("name = \"pigeon\"").unwrap();
    assert_eq!(minimal, config);
    assert!(LawConfig::NAMES.contains(&"pigeon"));
    assert!(config.build().is_ok());
    assert!(toml::from_str::<LawConfig>(&format!("{text}\nspeed_mps = 1.0")).is_err());
    let bad = |edit: &dyn Fn(&mut PigeonParameters), key: &str| {
        let mut p = PigeonParameters::default();
        edit(&mut p);
        let e = Pigeon::new(p).unwrap_err().to_string();
        assert!(e.contains(key), "{e} should name {key}");
    };
    bad(&|p| p.hierarchical_range_m = 100.0, "hierarchical_range_m");
    bad(&|p| p.link_delay_m = 130.0, "link_delay_m");
    bad(&|p| p.desired_separation_m = 20.0, "desired_separation_m");
    bad(&|p| p.desired_separation_m = 130.0, "desired_separation_m");
    bad(&|p| p.obstacle_detection_m = 10.0, "obstacle_detection_m");
    bad(&|p| p.alpha = 1.0, "alpha");
    bad(&|p| p.beta = 0.0, "beta");
    bad(&|p| p.leader_weight = 0.5, "leader_weight");
    bad(&|p| p.dominant = vec![1, 1], "dominant");
    // The rate bound: 1.8/s at the defaults (2 K^V w'); 0.1 s accepted (above), 1 s refused.
    let law = Pigeon::new(PigeonParameters::default()).unwrap();
    assert!((law.fastest_rate_per_s(10.0).unwrap() - 1.8).abs() <= 1e-12);
    let refused = Simulation::new(
        config_for(1.0, 150.0),
        &satellites(),
        Law::new(law.clone()),
        vec![],
    );
    assert!(
        matches!(refused, Err(SimError::ControlPeriodTooLong { .. })),
        "1 s period accepted"
    );
    // A sensing range below R_c^2 is refused when the law starts, naming the key.
    let refused = Simulation::new(
        config_for(0.1, 140.0),
        &satellites(),
        Law::new(law.clone()),
        vec![],
    );
    let e = refused
        .err()
        .expect("sensing range below R_c^2 accepted")
        .to_string();
    assert!(e.contains("hierarchical_range_m"), "{e}");
    // A dominant index beyond the swarm is refused when the law starts.
    let beyond = Pigeon::new(PigeonParameters {
        dominant: vec![0, 10],
        ..PigeonParameters::default()
    })
    .unwrap();
    assert!(Simulation::new(
        config_for(0.1, 150.0),
        &satellites(),
        Law::new(beyond),
        vec![]
    )
    .is_err());
}

fn config_for(period_s: f64, range_m: f64) -> SimulationConfig {
    config(period_s, 10.0, 1.0, range_m)
}

/// The built-in `pigeon-switching` with its `[law]` edited by `edit`, prepared (validated).
fn switching_builtin(edit: impl FnOnce(&mut PigeonParameters)) -> satflock::scenario::Prepared {
    let mut scenario = satflock::scenario::Scenario::load("pigeon-switching").unwrap();
    let LawConfig::Pigeon(p) = &mut scenario.file.law else {
        panic!("pigeon-switching does not run the pigeon law")
    };
    edit(p);
    scenario.prepare().unwrap()
}

#[test]
fn val_initial_link_graph_warning_names_satellite_0_at_120_m_and_is_silent_at_130_m() {
    // Reference by hand from Table I's (y, z) columns: satellite 0 is at (y, z) = (−163.0, −694.4) m,
    // satellite 2 at (−139.7, −807.3) m: Δy = −23.3 m, Δz = 112.9 m, √(23.3² + 112.9²) = √13289.30
    // = 115.279 m; satellite 1 is √(117.9² + 89.2²) = 147.8 m away and satellites 3–9 are more than
    // 111 m away in z alone. So at R_c^1 − R_L^1 = 120 − 10 = 110 m satellite 0 has no link.
    let by_hand = (23.3f64.powi(2) + 112.9f64.powi(2)).sqrt();
    assert!((by_hand - 115.279).abs() < 1e-3);
    let plane = |r: &[f64; 6]| Vector2::new(r[2], r[1]);
    let nearest = TABLE_I[1..]
        .iter()
        .map(|r| (plane(r) - plane(&TABLE_I[0])).norm())
        .fold(f64::INFINITY, f64::min);
    assert_eq!(nearest, (plane(&TABLE_I[2]) - plane(&TABLE_I[0])).norm());
    assert!((nearest - by_hand).abs() < 1e-9);

    let at_120 = switching_builtin(|p| p.egalitarian_range_m = 120.0);
    // The built-in's initial states are Table I.
    for (s, r) in at_120.satellites.iter().zip(TABLE_I.iter()) {
        assert_eq!(s.relative_state.position_m, Vector3::new(r[0], r[1], r[2]));
    }
    let [warning] = at_120.warnings.as_slice() else {
        panic!("expected one warning, got {:?}", at_120.warnings)
    };
    assert!(
        warning.starts_with("law.egalitarian_range_m − law.link_delay_m = 110 m:"),
        "{warning}"
    );
    assert!(
        warning.contains("2 components of 9 and 1 satellites"),
        "{warning}"
    );
    let expected = format!("satellite 0 has no neighbour within 110 m, nearest {by_hand:.1} m");
    assert_eq!(
        expected,
        "satellite 0 has no neighbour within 110 m, nearest 115.3 m"
    );
    assert!(warning.contains(&expected), "{warning}");

    // The default (130 m: link radius 120 m > 115.3 m) and the non-switching baseline: no warning.
    let default = switching_builtin(|_| {});
    assert!(default.warnings.is_empty(), "{:?}", default.warnings);
    let baseline = satflock::scenario::Scenario::load("pigeon-baseline")
        .unwrap()
        .prepare()
        .unwrap();
    assert!(baseline.warnings.is_empty(), "{:?}", baseline.warnings);
    // Just above the nearest distance the graph connects; just below it does not.
    let above = switching_builtin(|p| p.egalitarian_range_m = 10.0 + by_hand + 0.01);
    assert!(above.warnings.is_empty(), "{:?}", above.warnings);
    let below = switching_builtin(|p| p.egalitarian_range_m = 10.0 + by_hand - 0.01);
    assert_eq!(below.warnings.len(), 1);
    // Switching off: checked too (without switching every satellite uses the egalitarian links all
    // the time).
    let off = switching_builtin(|p| {
        p.egalitarian_range_m = 120.0;
        p.switching = false;
    });
    assert_eq!(off.warnings.len(), 1, "{:?}", off.warnings);
}
