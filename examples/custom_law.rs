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
//! The law's code is in `examples/custom_law/centring.rs`; this example drives it by hand on a
//! prepared scenario. `examples/custom_law_cli.rs` registers the same law in a `satflock` binary of its
//! own, so scenario and controller files (`examples/custom_law.toml`) can name it.
//!
//! Run it with `cargo run --release --example custom_law`.

use nalgebra::Vector3;
use satflock::scenario::Scenario;
use satflock::swarm::{Law, Recorder, Simulation, Snapshot};

// The law itself, shared with `examples/custom_law_cli.rs` (which registers it in a `satflock` binary).
#[path = "custom_law/centring.rs"]
mod centring;
use centring::{Centring, CentringParameters};

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
    let law = Law::new(Centring::new(CentringParameters {
        stiffness_per_s2: 1e-4,
        damping_per_s: 2e-2,
        dither_m: 0.01,
    })?);
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
