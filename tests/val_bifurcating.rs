//! Validation of the `bifurcating` law (method page `docs/methods/bifurcating.md` §3) against independent
//! references: the analytic formation force against central finite differences of the potential for
//! every shape family, the equilibria of Tables 1–2 (method page §3.4), the spring repulsion of §3.2 and its
//! Newton's-third-law symmetry, the frame mapping at the law's boundary, the parameter checks and the
//! engine's refusal of a step too long for k_v/m.

use nalgebra::Vector3;
use satflock::dynamics::PhysicalProperties;
use satflock::guidance::bifurcating::{
    Bifurcating, BifurcatingParameters, Dimension, TargetSet, REGULARISATION_M,
};
use satflock::guidance::LawConfig;
use satflock::integrate::{IntegratorMethod, Tolerances};
use satflock::orbit::{gao_to_hill, EarthModel, KeplerianElements, RelativeStateHill};
use satflock::swarm::{
    Actuator, ControlTiming, DynamicsModel, GuidanceLaw, LimitKind, NullRecorder, Origin,
    SatelliteInit, Sensing, SimError, Simulation, SimulationConfig,
};

/// Method page §4.2 defaults in SI: k_f = 3 kg/(km s²), k_c = 0.25, k_v = 2000, s = 0.2 km, σ = 10 km.
fn params(
    dimension: Dimension,
    a: f64,
    b: f64,
    c: f64,
    r_m: f64,
    mu_m: f64,
) -> BifurcatingParameters {
    BifurcatingParameters {
        k_f_kg_per_m_s2: 3e-3,
        k_c_kg_per_s2: 0.25,
        k_v_kg_per_s: 2000.0,
        avoidance_radius_m: 200.0,
        dimension,
        a,
        b,
        c,
        radius_m: r_m,
        mu_m,
        sigma_m: 10_000.0,
        cw_feedforward: false,
    }
}

/// Every shape family of method page §3.4 (Tables 1–2, Figs. 7–10 and 19).
fn families() -> Vec<(&'static str, BifurcatingParameters)> {
    use Dimension::{Planar, Spatial};
    vec![
        ("circle", params(Planar, 1.0, 1.0, 1.0, 500.0, -5000.0)),
        (
            "double circle",
            params(Planar, 1.0, 1.0, 1.0, 1000.0, 500.0),
        ),
        ("disk", params(Planar, 1.0, 1.0, 1.0, 0.0, -1000.0)),
        ("ellipse", params(Planar, 1.0, 0.6, 1.0, 1000.0, -5000.0)),
        (
            "double ellipse",
            params(Planar, 1.5, 1.0, 1.0, 1000.0, 500.0),
        ),
        ("ellipse disk", params(Planar, 1.0, 0.6, 1.0, 0.0, -1000.0)),
        ("line", params(Planar, 1.0, 0.0, 1.0, 1000.0, -1000.0)),
        ("double line", params(Planar, 1.0, 0.0, 1.0, 1000.0, 500.0)),
        ("fig 8 ring", params(Planar, 1.0, 1.0, 1.0, 600.0, 400.0)),
        ("sphere", params(Spatial, 1.0, 1.0, 1.0, 1000.0, -5000.0)),
        (
            "double sphere",
            params(Spatial, 1.0, 1.0, 1.0, 1000.0, 500.0),
        ),
        ("ball", params(Spatial, 1.0, 1.0, 1.0, 0.0, -1000.0)),
        ("ellipsoid", params(Spatial, 1.0, 0.8, 0.6, 1000.0, -5000.0)),
        (
            "double ellipsoid",
            params(Spatial, 1.0, 0.8, 0.6, 1000.0, 200.0),
        ),
        (
            "solid ellipsoid",
            params(Spatial, 1.0, 0.8, 0.6, 0.0, -1000.0),
        ),
    ]
}

/// F_f = −∇U_f against a central difference of U_f on a 7×5×7 grid over ±2.1 km for every family.
/// Step h = 1e-3 m: the truncation error of the central difference is h²/6·U''' ~ 1e-10 relative for
/// U''' ~ k_f, and rounding is ε·|U|/h ~ 1e-16·1e4 J / 1e-3 m ~ 1e-9 N against forces of 1 to 1e4 N;
/// the tolerance 1e-7 relative (floor 1e-9 N for tiny forces) is what the method page asks. Points with ρ < 1 m
/// are skipped: inside the ε ball the force is the regularised one, not a gradient (method page §3.4).
#[test]
fn val_formation_force_is_minus_gradient_for_every_family() {
    let h = 1e-3;
    for (label, p) in families() {
        for i in -3..=3 {
            for j in -2..=2 {
                for k in -3..=3 {
                    let q = Vector3::new(
                        700.0 * i as f64 + 13.0,
                        310.0 * j as f64 + 7.0,
                        700.0 * k as f64 - 11.0,
                    );
                    let force = p.formation_force_gao_n(&q);
                    let mut fd = Vector3::zeros();
                    for axis in 0..3 {
                        let mut qp = q;
                        let mut qm = q;
                        qp[axis] += h;
                        qm[axis] -= h;
                        fd[axis] = -(p.formation_potential_j(&qp) - p.formation_potential_j(&qm))
                            / (2.0 * h);
                    }
                    let err = (force - fd).norm();
                    assert!(
                        err <= 1e-7 * force.norm() + 1e-9,
                        "{label} at {q:?}: analytic {force:?} vs finite difference {fd:?}"
                    );
                }
            }
        }
    }
}

/// Method page §3.4 equilibria: the force vanishes (to rounding, 1e-9 N against forces of ~1e3 N one metre
/// away) on the exact level sets of Tables 1–2 as corrected, and points back toward them from ±1 m.
#[test]
fn val_equilibria_are_the_corrected_level_sets() {
    use Dimension::{Planar, Spatial};
    let cases: Vec<(BifurcatingParameters, Vec<Vector3<f64>>)> = vec![
        // Circle radius r (x–z plane).
        (
            params(Planar, 1.0, 1.0, 1.0, 500.0, -5000.0),
            vec![
                Vector3::new(500.0, 0.0, 0.0),
                Vector3::new(0.0, 0.0, -500.0),
            ],
        ),
        // Double circle radii r ± μ.
        (
            params(Planar, 1.0, 1.0, 1.0, 1000.0, 500.0),
            vec![
                Vector3::new(500.0, 0.0, 0.0),
                Vector3::new(0.0, 0.0, 1500.0),
            ],
        ),
        // Double ellipse a=1.5, b=1, r=1 km, μ=0.5 km: semi-axes a r ± μ/b (x) and b r ± μ/a (z).
        (
            params(Planar, 1.5, 1.0, 1.0, 1000.0, 500.0),
            vec![
                Vector3::new(1500.0 + 500.0, 0.0, 0.0),
                Vector3::new(1500.0 - 500.0, 0.0, 0.0),
                Vector3::new(0.0, 0.0, 1000.0 + 500.0 / 1.5),
                Vector3::new(0.0, 0.0, 1000.0 - 500.0 / 1.5),
            ],
        ),
        // Double line z = ±μ/a.
        (
            params(Planar, 2.0, 0.0, 1.0, 1000.0, 500.0),
            vec![
                Vector3::new(123.0, 0.0, 250.0),
                Vector3::new(-77.0, 0.0, -250.0),
            ],
        ),
        // Ellipsoid semi-axes a r, b r, c r.
        (
            params(Spatial, 1.0, 0.8, 0.6, 1000.0, -5000.0),
            vec![
                Vector3::new(1000.0, 0.0, 0.0),
                Vector3::new(0.0, 800.0, 0.0),
                Vector3::new(0.0, 0.0, 600.0),
            ],
        ),
        // Double ellipsoid semi-axes a r ± μ/(b c) etc.
        (
            params(Spatial, 1.0, 0.8, 0.6, 1000.0, 200.0),
            vec![
                Vector3::new(1000.0 + 200.0 / 0.48, 0.0, 0.0),
                Vector3::new(0.0, 800.0 - 200.0 / 0.6, 0.0),
                Vector3::new(0.0, 0.0, 600.0 + 200.0 / 0.8),
            ],
        ),
    ];
    for (p, points) in cases {
        for q in points {
            assert!(p.formation_force_gao_n(&q).norm() <= 1e-9, "{p:?} at {q:?}");
            let dir = q.normalize();
            let out = p.formation_force_gao_n(&(q + dir));
            let inn = p.formation_force_gao_n(&(q - dir));
            assert!(
                out.dot(&dir) < 0.0 && inn.dot(&dir) > 0.0,
                "{p:?} not stable at {q:?}"
            );
        }
    }
}

/// Method page §3.4 singular point: with a·b·r > 0 and μ < a·b·r the centre is a repelling cone point;
/// the regularised force is continuous, linear inside ε and exactly zero at the origin.
#[test]
fn val_regularised_cone_point() {
    let p = params(Dimension::Planar, 1.0, 1.0, 1.0, 500.0, -5000.0);
    assert_eq!(p.formation_force_gao_n(&Vector3::zeros()), Vector3::zeros());
    let inside = p.formation_force_gao_n(&Vector3::new(0.5 * REGULARISATION_M, 0.0, 0.0));
    let edge = p.formation_force_gao_n(&Vector3::new(REGULARISATION_M, 0.0, 0.0));
    // Linear inside ε: half the distance, half the force, up to the change of φ'(e) across the ε ball,
    // ε·φ''/|φ'| = 1e-3·6000/(500·5500) ≈ 2.2e-6 relative (tolerance 5e-6).
    assert!((inside.x - 0.5 * edge.x).abs() <= 5e-6 * edge.x.abs());
    // Outward (repelling), magnitude k_f·|φ'(−abr)| = k_f·abr·(abr − μ) at the edge (1e-9 relative:
    // e differs from −abr by ε = 1e-3 m, i.e. 2e-6 relative).
    let expected = 3e-3 * 500.0 * (500.0 + 5000.0);
    assert!(edge.x > 0.0 && (edge.x - expected).abs() <= 3e-6 * expected);
    // The method page §1.2 check: k_f = 3 kg/(km s²), e = −0.45 km, μ = −5 km → |F| = 7360 N (exact in SI).
    let f = p
        .formation_force_gao_n(&Vector3::new(50.0, 0.0, 0.0))
        .norm();
    assert!((f - 3e-3 * 450.0 * 5450.0).abs() <= 1e-9 * f && (f - 7357.5).abs() < 1e-6);
}

/// Parameter sets that make no formation are refused with the key and the allowed range (method page §3.4).
#[test]
fn val_parameter_checks_name_the_key() {
    let ok = params(Dimension::Planar, 1.0, 1.0, 1.0, 1000.0, 500.0);
    assert!(Bifurcating::new(ok.clone()).is_ok());
    let cases: Vec<(BifurcatingParameters, &str)> = vec![
        (
            BifurcatingParameters {
                mu_m: 1000.0,
                ..ok.clone()
            },
            "mu_m",
        ),
        (
            BifurcatingParameters {
                mu_m: 0.0,
                ..ok.clone()
            },
            "mu_m",
        ),
        (
            BifurcatingParameters {
                a: 0.0,
                b: 0.0,
                ..ok.clone()
            },
            "shape factors",
        ),
        (
            BifurcatingParameters {
                k_f_kg_per_m_s2: 0.0,
                ..ok.clone()
            },
            "k_f_kg_per_m_s2",
        ),
        (
            BifurcatingParameters {
                sigma_m: -1.0,
                ..ok.clone()
            },
            "sigma_m",
        ),
        (
            BifurcatingParameters {
                radius_m: f64::NAN,
                ..ok.clone()
            },
            "radius_m",
        ),
        (
            BifurcatingParameters {
                dimension: Dimension::Spatial,
                b: 0.0,
                c: 0.0,
                ..ok.clone()
            },
            "shape factors",
        ),
    ];
    for (p, key) in cases {
        let err = Bifurcating::new(p).unwrap_err().to_string();
        assert!(err.contains(key) && err.contains("allowed"), "{err}");
    }
    // Unknown keys of a scenario's [law] table are refused by the registry.
    let table: toml::Table = toml::from_str(
        "name = 'bifurcating'\nk_f_kg_per_m_s2 = 3e-3\nk_c_kg_per_s2 = 0.25\nk_v_kg_per_s = 2000.0\n\
         avoidance_radius_m = 200.0\na = 1.0\nb = 1.0\nradius_m = 500.0\nmu_m = -5000.0\nk_f = 3.0",
    )
    .unwrap();
    assert!(table.try_into::<LawConfig>().is_err());
    // Filled shapes are recognised as such.
    assert_eq!(
        params(Dimension::Planar, 1.0, 1.0, 1.0, 0.0, -1000.0).target_set(),
        TargetSet::Filled
    );
    assert_eq!(
        params(Dimension::Planar, 1.0, 0.0, 1.0, 0.0, -1000.0).target_set(),
        TargetSet::LevelSets
    );
}

fn config(step_s: f64, control: ControlTiming, range_m: f64) -> SimulationConfig {
    let earth = EarthModel::WGS84_EGM96;
    let a = 6_978_137.0;
    SimulationConfig {
        earth,
        dynamics: DynamicsModel::Hcw(satflock::relative::Hcw::new(earth.mean_motion_rad_s(a))),
        integrator: IntegratorMethod::Rk4,
        step_s,
        tolerances: Tolerances {
            relative: 1e-10,
            absolute: 1e-6,
        },
        control,
        origin: Origin::VirtualReference,
        reference: KeplerianElements {
            semi_major_axis_m: a,
            eccentricity: 0.0,
            inclination_rad: 98f64.to_radians(),
            raan_rad: 0.0,
            arg_perigee_rad: 0.0,
            true_anomaly_rad: 0.0,
        }
        .to_cartesian(earth.mu_m3_s2)
        .unwrap(),
        reference_properties: PhysicalProperties::point_mass(100.0),
        mean_motion_rad_s: earth.mean_motion_rad_s(a),
        duration_s: 1.0,
        record_interval_s: 1.0,
        sensing: Sensing {
            range_m,
            position_noise_m: 0.0,
            velocity_noise_mps: 0.0,
            ring_neighbours: None,
        },
        process_noise_m_s2: 0.0,
        threats: vec![],
        obstacles: vec![],
        tracked_objects: Vec::new(),
        max_distance_m: 1e6,
        seed: 1,
    }
}

fn sats(positions_hill_m: &[[f64; 3]], velocity: [f64; 3]) -> Vec<SatelliteInit> {
    positions_hill_m
        .iter()
        .map(|p| SatelliteInit {
            relative_state: RelativeStateHill {
                position_m: Vector3::from(*p),
                velocity_mps: Vector3::from(velocity),
            },
            properties: PhysicalProperties::point_mass(100.0),
            radius_m: 0.0,
            actuator: Actuator::new(f64::INFINITY, LimitKind::Norm),
            drag_attitudes: None,
        })
        .collect()
}

/// The engine refuses an RK4 step or a control period too long for k_v/m = 20 1/s (method page §3.7: the
/// damping alone needs h < 0.07 s for RK4 and a hold period below 0.05 s), and accepts 0.05 s.
#[test]
fn val_stiff_damping_refuses_long_steps() {
    let law = || {
        satflock::swarm::Law::new(
            Bifurcating::new(params(Dimension::Planar, 1.0, 1.0, 1.0, 500.0, -5000.0)).unwrap(),
        )
    };
    let s = sats(&[[0.0, 10.0, 0.0], [0.0, -10.0, 0.0]], [0.0; 3]);
    for (step, control) in [
        (0.1, ControlTiming::Continuous),
        (0.01, ControlTiming::Sampled { period_s: 0.06 }),
    ] {
        match Simulation::new(config(step, control, 500.0), &s, law(), vec![]) {
            Err(e @ (SimError::StepTooLong { .. } | SimError::ControlPeriodTooLong { .. })) => {
                assert!(e.to_string().contains("bifurcating"), "{e}")
            }
            other => panic!("accepted step {step} s: {:?}", other.err()),
        }
    }
    let mut sim = Simulation::new(
        config(0.05, ControlTiming::Continuous, 500.0),
        &s,
        law(),
        vec![],
    )
    .unwrap();
    sim.run(&mut NullRecorder, &mut |_| {}).unwrap();
    // An avoidance radius beyond the sensing range is refused when the law starts.
    match Simulation::new(
        config(0.05, ControlTiming::Continuous, 100.0),
        &s,
        law(),
        vec![],
    ) {
        Err(SimError::Law(e)) => assert!(e.to_string().contains("sensing range")),
        other => panic!("accepted s > range: {:?}", other.err()),
    }
}

/// Method page §3.1–3.2 at the law's boundary, on HCW dynamics (ω = n): the command equals
/// (C^T F_f(C q) + F_c − k_v v)/m computed by hand, the pair forces are opposite (Newton's third law),
/// coincident satellites are split deterministically along ±x_Gao, and F_c has the spring magnitude
/// k_c (s − d). Tolerance 1e-12 relative: same formulas, different evaluation order.
#[test]
fn val_command_matches_hand_computation() {
    let p = params(Dimension::Planar, 1.0, 1.0, 1.0, 500.0, -5000.0);
    let law = Bifurcating::new(p.clone()).unwrap();
    // Two satellites 150 m apart along Hill z (s = 200 m), one moving.
    let positions = [
        [100.0, 40.0, 20.0],
        [100.0, 40.0, 170.0],
        [900.0, 0.0, 0.0],
        [900.0, 0.0, 0.0],
    ];
    let states: Vec<RelativeStateHill> = positions
        .iter()
        .enumerate()
        .map(|(i, q)| RelativeStateHill {
            position_m: Vector3::from(*q),
            velocity_mps: Vector3::new(0.1 * i as f64, -0.2, 0.05),
        })
        .collect();
    let (x, y, z): (Vec<f64>, Vec<f64>, Vec<f64>) = (
        states.iter().map(|s| s.position_m.x).collect(),
        states.iter().map(|s| s.position_m.y).collect(),
        states.iter().map(|s| s.position_m.z).collect(),
    );
    let mut grid = satflock::grid::NeighbourGrid::new();
    grid.build(&x, &y, &z, 200.0).unwrap();
    let masses = [100.0; 4];
    let flags = [true; 4];
    let view = satflock::swarm::SwarmView::new(
        &states,
        &masses,
        &flags,
        &flags,
        &grid,
        satflock::swarm::SharedInfo {
            time_s: 0.0,
            mean_motion_rad_s: 1.08e-3,
            sensing_range_m: 200.0,
            reference_model: satflock::relative::SchweighartSedwick::new(
                6_978_137.0,
                1.7,
                3.986004418e14,
                6_378_137.0,
                1.08262668e-3,
            ),
        },
        satflock::swarm::EnvironmentView::default(),
    );
    let context = satflock::swarm::LawContext::new(
        0.0,
        0,
        0.1,
        satflock::swarm::Actuator::new(f64::INFINITY, satflock::swarm::LimitKind::Norm),
        0,
        1,
    );
    let u: Vec<Vector3<f64>> = (0..4)
        .map(|i| law.command(&view.satellite(i), &(), &context))
        .collect();
    let own = |i: usize| {
        let q = satflock::orbit::hill_to_gao(&states[i].position_m);
        gao_to_hill(&p.formation_force_gao_n(&q)) - 2000.0 * states[i].velocity_mps
    };
    let spring = Vector3::new(0.0, 0.0, -0.25 * (200.0 - 150.0)); // on satellite 0, pushed to −z
    let close = |a: Vector3<f64>, b: Vector3<f64>| (a - b).norm() <= 1e-12 * a.norm().max(b.norm());
    assert!(close(u[0], (own(0) + spring) / 100.0));
    assert!(close(u[1], (own(1) - spring) / 100.0));
    // Coincident pair: ±k_c s along x_Gao = Hill +y, lower index pushed to +x_Gao.
    let split = gao_to_hill(&Vector3::new(0.25 * 200.0, 0.0, 0.0));
    assert!(close(u[2], (own(2) + split) / 100.0));
    assert!(close(u[3], (own(3) - split) / 100.0));
}
