//! The simulations measured by `satflock bench` and by the criterion benchmark `cli/benches/engine_step.rs`
//! (one definition for both): scenario text scaled to N satellites, built through the library's run
//! path, and the `hold`-plus-repulsion law that only benchmarks use.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::{bail, Result};
use nalgebra::Vector3;
use satflock::guidance::hold::{Feedforward, Hold, HoldParameters};
use satflock::run::build_prepared;
use satflock::scenario::Scenario;
use satflock::swarm::{
    GuidanceLaw, Law, LawContext, LawError, SatelliteView, Simulation, SwarmView,
};

/// `hold` plus a linear spring repulsion from every neighbour within the sensing range (the engine
/// benchmark's law).
pub struct HoldAndRepel {
    /// The `hold` law whose command the repulsion adds to.
    pub hold: Hold,
    /// Sensing range, beyond which the spring is slack \[m\].
    pub range_m: f64,
    /// Spring gain per metre of compression \[1/s²\].
    pub gain_per_s2: f64,
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
    fn prefetch(&self, id: usize) {
        self.hold.prefetch(id);
    }
    fn set_parameters(&mut self, p: &HoldParameters) -> Result<(), LawError> {
        self.hold.set_parameters(p)
    }
}

/// Radius of a ball of `n` satellites with about 10 others within `range_m` \[m\].
fn ball_radius_m(n: usize, range_m: f64) -> f64 {
    range_m * (n as f64 / 10.0).cbrt()
}

/// The scenario text shared by the sphere cases: J2 truth, RK4 and sampled control at `step_s`, a ball of
/// `n` satellites sized for ~10 neighbours in `range_m` (random, so two satellites may start touching: at
/// 10^7 about 0.4 pairs of the bifurcating case are expected within 1 m, and the run goes on), and the
/// law table `law`.
fn sphere_case(n: usize, step_s: f64, range_m: f64, satellites: &str, law: &str) -> String {
    format!(
        "name = \"bench\"\nseed = 1\nduration_s = 1e6\nrecord_interval_s = 1e6\n\
         [dynamics]\nmodel = \"j2\"\nintegrator = \"rk4\"\nstep_s = {step_s}\n\
         [reference]\naltitude_m = 600e3\ninclination_deg = 98.0\n\
         [control]\nmode = \"sampled\"\nperiod_s = {step_s}\n\
         [satellites]\ncount = {n}\n{satellites}\nallow_initial_overlap = true\n\
         initial = {{ distribution = \"sphere\", radius_m = {radius} }}\n\
         [sensing]\nrange_m = {range_m}\n[law]\n{law}\n[output]\ntrajectory = false\nallow_large = true\n",
        radius = ball_radius_m(n, range_m),
    )
}

/// The equilibrium-shaping case: a triangular lattice of `n` nodes 6 m apart, each satellite on its node,
/// a threat far away (the engine benchmark's case).
fn equilibrium_shaping_case(n: usize) -> String {
    let side = (n as f64).sqrt().ceil() as usize;
    let mut nodes = String::new();
    let mut states = String::new();
    for k in 0..n {
        let (row, col) = ((k / side) as f64, (k % side) as f64);
        let (x, y) = (
            6.0 * (col + 0.5 * (row % 2.0)),
            6.0 * 3f64.sqrt() / 2.0 * row,
        );
        let _ = write!(nodes, "[{x:?}, {y:?}, 0.0],");
        let _ = write!(states, "[{x:?}, {y:?}, 0.0, 0.0, 0.0, 0.0],");
    }
    format!(
        "name = \"bench\"\nseed = 1\nduration_s = 1e5\nrecord_interval_s = 1e5\n\
         [dynamics]\nmodel = \"j2\"\nintegrator = \"rk4\"\nstep_s = 0.025\n\
         [reference]\nsemi_major_axis_m = 7.0e6\ninclination_deg = 45.0\n\
         [control]\nmode = \"sampled\"\nperiod_s = 0.025\n\
         [satellites]\ncount = {n}\nmass_kg = 7.0\nradius_m = 0.15\nmax_accel_mps2 = 1.4e-3\n\
         accel_limit = \"per-axis\"\ninitial = {{ distribution = \"list\", frame = \"hill\", states = [{states}] }}\n\
         [law]\nname = \"equilibrium-shaping\"\nstrategy = \"moving-centroid\"\nformation = \"custom\"\n\
         nodes_hill_m = [{nodes}]\nthreat = 0\nescape = \"parallel\"\n\
         [sensing]\nrange_m = 13.0\n\
         [[threats]]\nname = \"far\"\ndanger_radius_m = 1.0\naim_point_hill_m = [0.0, 0.0, 0.0]\n\
         direction_hill = [0.0, 0.0, -1.0]\nspeed_mps = 1.0\narrival_time_s = 1e6\n\
         [output]\ntrajectory = false\nallow_large = true\n"
    )
}

/// The simulation of the guided case `name` (`propagation`, `hold-repel`, `bifurcating`, `pigeon`,
/// `equilibrium-shaping`) at `n` satellites; an error for any other name.
pub fn simulation(name: &str, n: usize) -> Result<Simulation> {
    let text = match name {
        "propagation" => sphere_case(
            n,
            1.0,
            50.0,
            "mass_kg = 5.0\nradius_m = 0.1",
            "name = \"none\"",
        ),
        "hold-repel" => sphere_case(
            n,
            1.0,
            50.0,
            "mass_kg = 5.0\nradius_m = 0.1\nmax_accel_mps2 = 1e-2",
            "name = \"hold\"\nstiffness_per_s2 = 1e-5\ndamping_per_s = 6e-3\nfeedforward = \"hcw\"",
        ),
        "bifurcating" => {
            // The formation shell is the ball itself (radius R, μ = −R), and k_f makes the formation
            // force 1e-3 m/s² at the centre (k_f · R · 2R / m): the swarm settles slowly, as a guided
            // swarm near its formation does. (A fixed 500 m shell pulls the satellites of a 10⁵ ball
            // 10 km out at ~1e4 m/s², flinging them at km/s: no guidance scenario looks like that.)
            let ball_m = ball_radius_m(n, 500.0);
            let mass_kg = 100.0;
            let k_f = 1e-3 * mass_kg / (2.0 * ball_m * ball_m);
            sphere_case(
                n,
                0.05,
                500.0,
                &format!("mass_kg = {mass_kg:?}\nradius_m = 0.5"),
                &format!(
                    "name = \"bifurcating\"\nk_f_kg_per_m_s2 = {k_f:e}\nk_c_kg_per_s2 = 0.25\n\
                     k_v_kg_per_s = 2000.0\navoidance_radius_m = 500.0\na = 1.0\nb = 1.0\n\
                     radius_m = {ball_m:?}\nmu_m = {mu:?}",
                    mu = -ball_m
                ),
            )
        }
        "pigeon" => sphere_case(
            n,
            0.1,
            150.0,
            "mass_kg = 10.0\nradius_m = 0.05\nmax_accel_mps2 = 5.0\naccel_limit = \"per-axis\"",
            "name = \"pigeon\"\nswitching = true\negalitarian_range_m = 120.0\n\
             hierarchical_range_m = 150.0",
        ),
        "equilibrium-shaping" => equilibrium_shaping_case(n),
        other => bail!("the case {other} runs no simulation"),
    };
    let scenario = Scenario::from_toml(&text, &format!("bench:{name}"), Path::new("."))
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    let mut prepared = scenario.prepare().map_err(|e| anyhow::anyhow!("{e}"))?;
    if name == "hold-repel" {
        let law = HoldAndRepel {
            hold: Hold::new(HoldParameters {
                stiffness_per_s2: 1e-5,
                damping_per_s: 6e-3,
                feedforward: Feedforward::Hcw,
                slot_offset_hill_m: [0.0; 3],
            })?,
            range_m: 50.0,
            gain_per_s2: 1e-7,
        };
        prepared
            .replace_law(&scenario, Law::new(law), "bench:hold-repel")
            .map_err(|e| anyhow::anyhow!("{e}"))?;
    }
    build_prepared(&scenario, prepared).map_err(|e| anyhow::anyhow!("{e}"))
}
