//! Benchmark: one engine step (point-mass + J2 truth, RK4 at 1 s, sampled control at 1 s) with the `hold`
//! law plus a short-range pairwise repulsion through the neighbour grid (about 10 neighbours each), for
//! N = 1 000, 10 000 and 100 000. Throughput is reported in satellite-steps per second.
//!
//! The actuator limit (1e-2 m/s²) exceeds the 3 n² x needed to hold the outermost radial offsets (1.1 km
//! at N = 10^5: 3.8e-3 m/s²), so the swarm stays put however many steps criterion runs; with a limit
//! below that, outer satellites saturate, drift away and every grid query slows down as the box grows.
//!
//! A fourth case, `equilibrium-shaping-hexagonal/10000`, runs the `equilibrium-shaping` law (Eq. 1 pair
//! field through the grid, 18 neighbours each) on a 10 000-satellite triangular lattice, sampled at 0.025 s.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use nalgebra::Vector3;
use satflock::environment::Threat;
use satflock::guidance::hold::{Feedforward, Hold, HoldParameters};
use satflock::guidance::LawConfig;
use satflock::integrate::{IntegratorMethod, Tolerances};
use satflock::orbit::{EarthModel, GravityModel, KeplerianElements, RelativeStateHill};
use satflock::scenario::initial;
use satflock::swarm::{
    Actuator, ControlTiming, DynamicsModel, GuidanceLaw, Law, LawContext, LawError, LimitKind,
    Origin, SatelliteInit, SatelliteView, Sensing, Simulation, SimulationConfig, SwarmView,
};

/// `hold` plus a linear spring repulsion from every neighbour within the sensing range.
struct HoldAndRepel {
    hold: Hold,
    range_m: f64,
    gain_per_s2: f64,
}

impl GuidanceLaw for HoldAndRepel {
    type State = ();
    type Parameters = HoldParameters;

    fn name(&self) -> &'static str {
        "hold-and-repel"
    }
    fn initialise(&mut self, swarm: &SwarmView<'_>, states: &mut [()]) -> Result<(), LawError> {
        self.hold.initialise(swarm, states)
    }
    fn command(&self, s: &SatelliteView<'_>, state: &(), context: &LawContext) -> Vector3<f64> {
        let mut u = self.hold.command(s, state, context);
        s.for_each_neighbour(|nb| {
            u -= self.gain_per_s2 * (self.range_m - nb.distance_m) * nb.offset_m
                / nb.distance_m.max(1e-9);
        });
        u
    }
    fn set_parameters(&mut self, p: &HoldParameters) -> Result<(), LawError> {
        self.hold.set_parameters(p)
    }
}

fn simulation(n: usize) -> Simulation {
    let earth = EarthModel::WGS84_EGM96;
    let a = 6_978_137.0;
    // Density chosen so that a ball of the sensing range holds ~10 others: N (r/R)^3 = 10.
    let range_m = 50.0;
    let radius_m = range_m * (n as f64 / 10.0).cbrt();
    let positions = initial::sphere(1, n, radius_m, Vector3::zeros());
    let satellites: Vec<SatelliteInit> = initial::with_velocity(
        positions,
        satflock::scenario::schema::InitialVelocity::Zero,
        earth.mean_motion_rad_s(a),
    )
    .into_iter()
    .map(|relative_state| SatelliteInit {
        relative_state,
        mass_kg: 5.0,
        radius_m: 0.1,
        actuator: Actuator::new(1e-2, LimitKind::Norm),
    })
    .collect();
    let config = base_config(earth, a, range_m);
    let law = HoldAndRepel {
        hold: Hold::new(HoldParameters {
            stiffness_per_s2: 1e-5,
            damping_per_s: 6e-3,
            feedforward: Feedforward::Hcw,
            slot_offset_hill_m: [0.0; 3],
        })
        .unwrap(),
        range_m,
        gain_per_s2: 1e-7,
    };
    Simulation::new(config, &satellites, Law::new(law), vec![]).unwrap()
}

/// The engine configuration shared by the cases: point mass + J2 truth, RK4 at 1 s, sampled control at
/// 1 s, a near-polar circular reference of semi-major axis `a` \[m\], sensing range `range_m` \[m\].
fn base_config(earth: EarthModel, a: f64, range_m: f64) -> SimulationConfig {
    SimulationConfig {
        earth,
        dynamics: DynamicsModel::Inertial(GravityModel::J2),
        integrator: IntegratorMethod::Rk4,
        step_s: 1.0,
        tolerances: Tolerances {
            relative: 1e-10,
            absolute: 1e-6,
        },
        control: ControlTiming::Sampled { period_s: 1.0 },
        origin: Origin::VirtualReference,
        reference: KeplerianElements {
            semi_major_axis_m: a,
            eccentricity: 0.0,
            inclination_rad: 1.7,
            raan_rad: 0.0,
            arg_perigee_rad: 0.0,
            true_anomaly_rad: 0.0,
        }
        .to_cartesian(earth.mu_m3_s2)
        .unwrap(),
        mean_motion_rad_s: earth.mean_motion_rad_s(a),
        duration_s: 1e9,
        record_interval_s: 1e9,
        sensing: Sensing {
            range_m,
            position_noise_m: 0.0,
            velocity_noise_mps: 0.0,
        },
        process_noise_m_s2: 0.0,
        threats: vec![],
        obstacles: vec![],
        max_distance_m: 1e7,
        seed: 1,
    }
}

/// The `equilibrium-shaping` law (moving-centroid strategy: the Eq. 1 pair field through the neighbour
/// grid, plus the threat term) on a flat triangular ("hexagonal") lattice of `n` satellites 6 m apart,
/// every satellite on its node, a threat far away; sampled at 0.025 s (above 128 nodes the law bounds
/// its fastest rate by Gershgorin's theorem, 30.5 1/s here, so the engine refuses a hold longer than
/// 0.033 s). Sensing range 13 m: each satellite sees its 18 lattice neighbours at 6, 10.4 and 12 m.
fn equilibrium_shaping(n: usize) -> Simulation {
    let earth = EarthModel::WGS84_EGM96;
    let a = 7_000_000.0;
    let side = (n as f64).sqrt().ceil() as usize;
    let nodes: Vec<[f64; 3]> = (0..n)
        .map(|k| {
            let (row, col) = ((k / side) as f64, (k % side) as f64);
            [
                6.0 * (col + 0.5 * (row % 2.0)),
                6.0 * 3f64.sqrt() / 2.0 * row,
                0.0,
            ]
        })
        .collect();
    let nodes_toml: Vec<String> = nodes
        .iter()
        .map(|p| format!("[{:?}, {:?}, {:?}]", p[0], p[1], p[2]))
        .collect();
    let law: LawConfig = toml::from_str(&format!(
        "name = \"equilibrium-shaping\"\nstrategy = \"moving-centroid\"\nformation = \"custom\"\n\
         nodes_hill_m = [{}]\nthreat = 0\nescape = \"parallel\"\n",
        nodes_toml.join(", ")
    ))
    .unwrap();
    let satellites: Vec<SatelliteInit> = nodes
        .iter()
        .map(|p| SatelliteInit {
            relative_state: RelativeStateHill {
                position_m: Vector3::from(*p),
                velocity_mps: Vector3::zeros(),
            },
            mass_kg: 7.0,
            radius_m: 0.15,
            actuator: Actuator::new(1.4e-3, LimitKind::PerAxis),
        })
        .collect();
    let threat = Threat::from_state(
        "far",
        0.0,
        Vector3::new(0.0, 0.0, 1e6),
        Vector3::new(0.0, 0.0, 1.0),
        1.0,
    )
    .unwrap();
    let mut config = base_config(earth, a, 13.0);
    config.step_s = 0.025;
    config.control = ControlTiming::Sampled { period_s: 0.025 };
    config.threats = vec![threat];
    Simulation::new(config, &satellites, law.build().unwrap(), vec![]).unwrap()
}

fn engine_step(c: &mut Criterion) {
    let mut group = c.benchmark_group("engine_step");
    for n in [1_000usize, 10_000, 100_000] {
        let mut sim = simulation(n);
        group.throughput(Throughput::Elements(n as u64));
        group.sample_size(if n >= 100_000 { 10 } else { 20 });
        group.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, _| {
            b.iter(|| sim.step().unwrap())
        });
    }
    let n = 10_000;
    let mut sim = equilibrium_shaping(n);
    group.throughput(Throughput::Elements(n as u64));
    group.sample_size(10);
    group.bench_with_input(
        BenchmarkId::new("equilibrium-shaping-hexagonal", n),
        &n,
        |b, _| b.iter(|| sim.step().unwrap()),
    );
    group.finish();
}

criterion_group!(benches, engine_step);
criterion_main!(benches);
