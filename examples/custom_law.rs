//! A guidance law of your own, written against satflock's public API only.
//!
//! The law, "centring": move the whole swarm so that its centroid sits on the LVLH origin, leaving every
//! satellite's motion about the centroid alone, although no satellite knows where the others are beyond
//! its sensing range.
//!
//! * **Memory** (the law's per-satellite `State`): each satellite keeps an estimate of the swarm
//!   centroid's state (position and velocity), its own state at the previous tick and how many
//!   neighbours it had.
//! * **Update** (once per control tick, double-buffered by the engine): a dynamic average consensus. The
//!   estimate moves toward the neighbours' broadcast estimates with Metropolis weights
//!   w = 1 / (1 + max(own degree, neighbour degree)) (symmetric, so the swarm-wide mean of the estimates
//!   is conserved), then follows the change of the satellite's own state since the last tick (so that
//!   mean tracks the true centroid as the swarm moves), plus a small random dither drawn from the
//!   satellite's own random stream (`LawContext::random`, reproducible on any thread count).
//! * **Command**: the same push for every satellite, a PD on the estimated centroid state with the HCW
//!   natural acceleration of the centroid cancelled, u = −k_p ĉ − k_d ċ − a_HCW(ĉ, ċ). HCW being linear,
//!   the centroid then obeys c̈ = −k_p c − k_d ċ and each satellite's offset from it moves freely.
//!
//! Run it with `cargo run --release --example custom_law`.

use nalgebra::{Vector3, Vector6};
use satflock::relative::Hcw;
use satflock::scenario::Scenario;
use satflock::swarm::{
    Broadcast, GuidanceLaw, Law, LawContext, LawError, Recorder, SatelliteView, Simulation,
    Snapshot, SwarmView,
};

/// The law's parameters (what a `set-law-parameters` event would replace).
#[derive(Clone, Debug)]
struct CentringParameters {
    stiffness_per_s2: f64,
    damping_per_s: f64,
    /// Standard deviation of the random dither added to each estimate per tick [m].
    dither_m: f64,
}

/// What each satellite remembers between ticks (and broadcasts to its neighbours).
#[derive(Clone, Default)]
struct Memory {
    /// Estimated centroid state [m, m/s], Hill frame.
    centroid: Vector6<f64>,
    /// Own (sensed) state at the previous tick [m, m/s].
    last_own: Vector6<f64>,
    neighbours: usize,
}

struct Centring(CentringParameters);

impl GuidanceLaw for Centring {
    type State = Memory;
    type Parameters = CentringParameters;

    fn name(&self) -> &'static str {
        "centring"
    }

    /// Start: every satellite's first guess of the centroid is its own state.
    fn initialise(&mut self, swarm: &SwarmView<'_>, states: &mut [Memory]) -> Result<(), LawError> {
        for (i, memory) in states.iter_mut().enumerate() {
            let mut neighbours = 0;
            swarm.satellite(i).for_each_neighbour(|_| neighbours += 1);
            let own = swarm.relative_states[i].to_vector6();
            *memory = Memory {
                centroid: own,
                last_own: own,
                neighbours,
            };
        }
        Ok(())
    }

    /// One consensus step from the previous tick's states (own and neighbours').
    fn update_state(
        &self,
        satellite: &SatelliteView<'_>,
        broadcast: &Broadcast<'_, Memory>,
        context: &LawContext,
    ) -> Memory {
        let me = broadcast.own();
        let own = satellite.own_state().to_vector6();
        let mut centroid = me.centroid;
        let mut neighbours = 0;
        satellite.for_each_neighbour(|nb| {
            let other = broadcast.of(nb);
            let weight = 1.0 / (1.0 + me.neighbours.max(other.neighbours) as f64);
            centroid += weight * (other.centroid - me.centroid);
            neighbours += 1;
        });
        centroid += own - me.last_own;
        let mut random = context.random();
        for k in 0..3 {
            centroid[k] += self.0.dither_m * random.standard_normal();
        }
        Memory {
            centroid,
            last_own: own,
            neighbours,
        }
    }

    /// PD on the estimated centroid state, with the centroid's HCW natural acceleration cancelled.
    fn command(
        &self,
        satellite: &SatelliteView<'_>,
        state: &Memory,
        _c: &LawContext,
    ) -> Vector3<f64> {
        let c = state.centroid.fixed_rows::<3>(0).into_owned();
        let c_dot = state.centroid.fixed_rows::<3>(3).into_owned();
        let hcw = Hcw::new(satellite.shared().mean_motion_rad_s);
        -self.0.stiffness_per_s2 * c
            - self.0.damping_per_s * c_dot
            - hcw.natural_acceleration_m_s2(&c, &c_dot)
    }

    fn set_parameters(&mut self, parameters: &CentringParameters) -> Result<(), LawError> {
        self.0 = parameters.clone();
        Ok(())
    }

    /// Lets the engine refuse a control period too long for the gains (roots of s² + k_d s + k_p).
    fn fastest_rate_per_s(&self, _mass_kg: f64) -> Option<f64> {
        let (kp, kd) = (self.0.stiffness_per_s2, self.0.damping_per_s);
        let disc = kd * kd - 4.0 * kp;
        Some(if disc > 0.0 {
            0.5 * (kd + disc.sqrt())
        } else {
            kp.sqrt()
        })
    }

    /// Per-satellite outputs: written as trajectory columns by the CLI, read below by our recorder.
    fn output_names(&self) -> &'static [&'static str] {
        &["centroid_x_m", "centroid_y_m", "centroid_z_m", "neighbours"]
    }

    fn write_outputs(&self, state: &Memory, values: &mut [f64]) {
        values[..3].copy_from_slice(&state.centroid.as_slice()[..3]);
        values[3] = state.neighbours as f64;
    }
}

/// A small in-memory recorder: one table row per recording time.
#[derive(Default)]
struct Table(Vec<[f64; 5]>);

impl Recorder for Table {
    fn record(&mut self, s: &Snapshot<'_>) -> std::io::Result<()> {
        let n = s.relative_states.len() as f64;
        let truth = s
            .relative_states
            .iter()
            .map(|r| r.position_m)
            .sum::<Vector3<f64>>()
            / n;
        let k = s.law_output_names.len();
        let estimates: Vec<Vector3<f64>> = s
            .law_outputs
            .chunks(k)
            .map(|o| Vector3::new(o[0], o[1], o[2]))
            .collect();
        let worst = estimates
            .iter()
            .map(|e| (e - truth).norm())
            .fold(0.0, f64::max);
        let degree = s.law_outputs.chunks(k).map(|o| o[3]).sum::<f64>() / n;
        let dv = s.delta_v_mps.iter().sum::<f64>() / n;
        self.0
            .push([s.time_s, truth.norm(), worst, degree, dv * 1e3]);
        Ok(())
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // Start from the built-in `hold` scenario (20 satellites in a 200 m ball, J2 truth, sampled 1 s,
    // 2 mm/s² thrusters) and change what we need: a shorter run, a sensing range that makes the
    // neighbour graph multi-hop, no events (they were written for the `hold` law), and a swarm whose
    // centroid starts 15 m off the origin.
    let mut prepared = Scenario::load("hold")?.prepare()?;
    prepared.config.duration_s = 600.0;
    prepared.config.record_interval_s = 60.0;
    prepared.config.sensing.range_m = 250.0;
    let offset = Vector3::new(10.0, -10.0, 5.0);
    for satellite in &mut prepared.satellites {
        satellite.relative_state.position_m += offset;
    }
    let law = Law::new(Centring(CentringParameters {
        stiffness_per_s2: 1e-4,
        damping_per_s: 2e-2,
        dither_m: 0.01,
    }));
    let mut sim = Simulation::new(prepared.config, &prepared.satellites, law, Vec::new())?;
    let mut table = Table::default();
    sim.run(&mut table, &mut |_| {})?;

    // Worst estimate error: the largest distance from a satellite's estimate to the true centroid (the
    // consensus lags the satellites' own motion about the centroid, and the dither keeps it from zero).
    println!("   t [s]  |centroid| [m]  worst estimate error [m]  neighbours  mean dv [mm/s]");
    for [t, centroid, error, degree, dv] in &table.0 {
        println!("{t:8.0}  {centroid:14.3}  {error:24.3}  {degree:10.1}  {dv:14.3}");
    }
    Ok(())
}
