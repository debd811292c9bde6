//! Benchmark: one engine step (point-mass + J2 truth, RK4 at 1 s, sampled control at 1 s) with the `hold`
//! law plus a short-range pairwise repulsion through the neighbour grid (about 10 neighbours each), for
//! N = 1 000, 10 000 and 100 000. Throughput is reported in satellite-steps per second.
//!
//! The actuator limit (1e-2 m/s²) exceeds the 3 n² x needed to hold the outermost radial offsets (1.1 km
//! at N = 10^5: 3.8e-3 m/s²), so the swarm stays put however many steps criterion runs; with a limit
//! below that, outer satellites saturate, drift away and every grid query slows down as the box grows.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use nalgebra::Vector3;
use satflock::guidance::hold::{Feedforward, Hold, HoldParameters};
use satflock::integrate::{IntegratorMethod, Tolerances};
use satflock::orbit::{EarthModel, GravityModel, KeplerianElements};
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
    let config = SimulationConfig {
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
    };
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
    group.finish();
}

criterion_group!(benches, engine_step);
criterion_main!(benches);
