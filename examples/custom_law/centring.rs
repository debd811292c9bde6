//! The "centring" law of `examples/custom_law.rs` (driven by hand there) and
//! `examples/custom_law_cli.rs` (registered in a `satflock` binary of its own), shared by both (and by
//! the CLI test `cli/tests/custom_law.rs`) through `#[path]`.
//!
//! Move the whole swarm so that its centroid sits on the LVLH origin, leaving every satellite's motion
//! about the centroid alone, although no satellite knows where the others are beyond its sensing range:
//! a dynamic average consensus on the centroid's state (the per-satellite `State`), then the same PD
//! push for every satellite on its estimate, with the centroid's HCW natural acceleration cancelled. See
//! `examples/custom_law.rs` for the details.

use nalgebra::{Vector3, Vector6};
use satflock::invalid::Invalid;
use satflock::relative::Hcw;
use satflock::swarm::{
    Better, Broadcast, Diagnostics, GuidanceLaw, Headline, LawContext, LawError, Reports,
    SatelliteView, SwarmView,
};
use serde::{Deserialize, Serialize};

/// The law's name in scenario files (`[law] name = "centring"`).
pub const NAME: &str = "centring";

/// The law's parameters: the `[law]` table of a scenario or controller file (besides `name`), and what
/// a `set-law-parameters` event replaces.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CentringParameters {
    /// Proportional gain on the estimated centroid position \[1/s²\]; finite, > 0.
    pub stiffness_per_s2: f64,
    /// Derivative gain on the estimated centroid velocity \[1/s\]; finite, >= 0.
    pub damping_per_s: f64,
    /// Standard deviation of the random dither added to each estimate per tick \[m\]; finite, >= 0
    /// (default 0).
    #[serde(default)]
    pub dither_m: f64,
}

impl CentringParameters {
    /// Checks every value's range; the error names the key and the allowed range.
    pub fn check(&self) -> Result<(), LawError> {
        let invalid = |key: &str, value: f64, allowed: &str| {
            Err(LawError::invalid(NAME, Invalid::range(key, value, allowed)))
        };
        if !(self.stiffness_per_s2.is_finite() && self.stiffness_per_s2 > 0.0) {
            return invalid("stiffness_per_s2", self.stiffness_per_s2, "finite, > 0");
        }
        if !(self.damping_per_s.is_finite() && self.damping_per_s >= 0.0) {
            return invalid("damping_per_s", self.damping_per_s, "finite, >= 0");
        }
        if !(self.dither_m.is_finite() && self.dither_m >= 0.0) {
            return invalid("dither_m", self.dither_m, "finite, >= 0");
        }
        Ok(())
    }
}

/// What each satellite remembers between ticks (and broadcasts to its neighbours).
#[derive(Clone, Default)]
pub struct Memory {
    /// Estimated centroid state [m, m/s], Hill frame.
    pub centroid: Vector6<f64>,
    /// Own (sensed) state at the previous tick [m, m/s].
    pub last_own: Vector6<f64>,
    /// Neighbours sensed at the last update.
    pub neighbours: usize,
}

/// The centring law.
pub struct Centring(CentringParameters);

impl Centring {
    /// The law, its parameters checked.
    pub fn new(parameters: CentringParameters) -> Result<Self, LawError> {
        parameters.check()?;
        Ok(Self(parameters))
    }
}

/// The true centroid's position of the active satellites, Hill frame \[m\].
fn true_centroid(swarm: &SwarmView<'_>) -> Option<Vector3<f64>> {
    let positions: Vec<Vector3<f64>> = swarm
        .relative_states
        .iter()
        .zip(swarm.active)
        .filter(|(_, &active)| active)
        .map(|(r, _)| r.position_m)
        .collect();
    (!positions.is_empty()).then(|| positions.iter().sum::<Vector3<f64>>() / positions.len() as f64)
}

impl GuidanceLaw for Centring {
    type State = Memory;
    type Parameters = CentringParameters;
    satflock::capabilities!(Reports, Diagnostics);

    fn name(&self) -> &'static str {
        NAME
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
        parameters.check()?;
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
}

/// The law's results (`summary.json` `law`), when a satellite is alive at the end.
#[derive(Serialize)]
pub struct CentringResults {
    /// The true centroid's final distance from the origin \[m\].
    pub centroid_offset_m: f64,
    /// The largest distance from an active satellite's estimate to the true centroid \[m\].
    pub worst_estimate_error_m: f64,
}

/// What the law reports: typed results and the headlines among them.
impl Reports<Memory> for Centring {
    type Results = Option<CentringResults>;

    /// The rows `satflock compare` shows for this law.
    fn headlines(&self) -> &'static [Headline] {
        const HEADLINES: &[Headline] = &[
            Headline::new(
                "centroid_offset_m",
                "final centroid offset",
                "m",
                Better::Lower,
            ),
            Headline::new(
                "worst_estimate_error_m",
                "final worst centroid estimate error",
                "m",
                Better::Lower,
            ),
        ];
        HEADLINES
    }

    /// `centroid_offset_m`: the true centroid's final distance from the origin; `worst_estimate_error_m`:
    /// the largest distance from an active satellite's estimate to the true centroid.
    fn results(&self, swarm: &SwarmView<'_>, states: &[Memory]) -> Option<CentringResults> {
        let centroid = true_centroid(swarm)?;
        let worst_estimate_error_m = states
            .iter()
            .zip(swarm.active)
            .filter(|(_, &active)| active)
            .map(|(m, _)| (m.centroid.fixed_rows::<3>(0) - centroid).norm())
            .fold(0.0, f64::max);
        Some(CentringResults {
            centroid_offset_m: centroid.norm(),
            worst_estimate_error_m,
        })
    }
}

/// Extra trajectory columns.
impl Diagnostics<Memory> for Centring {
    /// Per-satellite outputs: written as trajectory columns by the CLI, read below by our recorder.
    fn output_names(&self) -> &'static [&'static str] {
        &["centroid_x_m", "centroid_y_m", "centroid_z_m", "neighbours"]
    }

    fn write_outputs(&self, state: &Memory, values: &mut [f64]) {
        values[..3].copy_from_slice(&state.centroid.as_slice()[..3]);
        values[3] = state.neighbours as f64;
    }
}
