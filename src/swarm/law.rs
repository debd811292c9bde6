//! The interface between the engine and a guidance law: the [`GuidanceLaw`] trait and the read-only
//! sensing views the engine builds for it.
//!
//! Decentralisation is enforced by the types: a law computes one satellite's command from a
//! [`SatelliteView`], which gives that satellite its own relative state, the neighbours its sensors and
//! links reach (from the neighbour grid, honouring link outages and satellite losses), and the swarm-level
//! information the scenario grants ([`SharedInfo`]). Only [`GuidanceLaw::initialise`] (once, before the run
//! or after a law switch, e.g. to capture slots) and [`GuidanceLaw::centralised_update`] (a periodic
//! **centralised** step the law schedules itself, e.g. a ground-computed grouping) see the whole swarm.
//!
//! Every vector here is in the engine's internal LVLH convention, Hill/RSW (x radial out, y along-track,
//! z orbit normal), relative to the LVLH origin (the virtual reference orbit or a member satellite). Laws
//! written in another convention (Gao's o-xyz) convert at their boundary with
//! [`crate::orbit::hill_to_gao`] / [`crate::orbit::gao_to_hill`].

use std::collections::BTreeMap;

use nalgebra::Vector3;
use thiserror::Error;

use crate::grid::NeighbourGrid;
use crate::orbit::RelativeStateHill;
use crate::relative::SchweighartSedwick;

/// Swarm-level information granted to every satellite (ground warnings, broadcast quantities).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SharedInfo {
    /// Simulation time since the scenario start \[s\].
    pub time_s: f64,
    /// Mean motion of the reference orbit \[rad/s\] (for CW/HCW feed-forward terms).
    pub mean_motion_rad_s: f64,
    /// Whether a ground threat warning is active (set and cleared by the event timeline).
    pub threat_warning_active: bool,
    /// Range of every satellite's sensors and links \[m\]: neighbours farther away are never visited.
    pub sensing_range_m: f64,
    /// Schweighart–Sedwick J2-linearised model of the reference orbit at t = 0 (radius and osculating
    /// inclination of the LVLH origin's initial state; the model itself for `J2Linear` dynamics, J2 = 0
    /// for the J2-free models), for laws built on averaged J2 constants.
    pub reference_model: SchweighartSedwick,
}

/// What satellite `i` knows of a neighbour `j` within sensing range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Neighbour {
    /// The neighbour's index.
    pub id: usize,
    /// The neighbour's state relative to the LVLH origin, Hill frame \[m, m/s\].
    pub state: RelativeStateHill,
    /// Neighbour position minus own position, Hill frame \[m\].
    pub offset_m: Vector3<f64>,
    /// Distance between the two satellites \[m\].
    pub distance_m: f64,
}

/// The whole swarm as the engine sees it at one right-hand-side evaluation: navigation states relative to
/// the LVLH origin (Hill frame), who is alive and linked, and the neighbour grid over those positions.
/// Laws get a [`SatelliteView`] of it, never the whole view, except in [`GuidanceLaw::initialise`].
#[derive(Clone, Copy)]
pub struct SwarmView<'a> {
    /// Relative states, Hill frame, one per satellite (navigation solution: truth plus any noise).
    pub relative_states: &'a [RelativeStateHill],
    /// Masses \[kg\].
    pub masses_kg: &'a [f64],
    /// `false` for satellites removed from the swarm.
    pub active: &'a [bool],
    /// `false` for satellites whose links are cut: they neither see nor are seen.
    pub links_up: &'a [bool],
    /// Grid over the navigation positions, built with the sensing range as its radius (empty if a
    /// position was not finite; the divergence check then stops the run after the step).
    pub grid: &'a NeighbourGrid,
    /// Swarm-level information.
    pub shared: SharedInfo,
}

impl<'a> SwarmView<'a> {
    /// Number of satellites (including removed ones, whose `active` flag is false).
    pub fn len(&self) -> usize {
        self.relative_states.len()
    }

    /// Whether the swarm has no satellites.
    pub fn is_empty(&self) -> bool {
        self.relative_states.is_empty()
    }

    /// The view satellite `id` is allowed to have.
    pub fn satellite(&self, id: usize) -> SatelliteView<'a> {
        SatelliteView { id, swarm: *self }
    }
}

/// What one satellite senses: its own state, its reachable neighbours and the shared information.
#[derive(Clone, Copy)]
pub struct SatelliteView<'a> {
    id: usize,
    swarm: SwarmView<'a>,
}

impl SatelliteView<'_> {
    /// This satellite's index.
    pub fn id(&self) -> usize {
        self.id
    }

    /// Own state relative to the LVLH origin, Hill frame \[m, m/s\].
    pub fn own_state(&self) -> RelativeStateHill {
        self.swarm.relative_states[self.id]
    }

    /// Own mass \[kg\].
    pub fn mass_kg(&self) -> f64 {
        self.swarm.masses_kg[self.id]
    }

    /// Swarm-level information.
    pub fn shared(&self) -> &SharedInfo {
        &self.swarm.shared
    }

    /// Visits every live, linked neighbour within sensing range, in a deterministic order.
    /// A satellite whose own links are cut sees nobody.
    pub fn for_each_neighbour(&self, mut visit: impl FnMut(&Neighbour)) {
        let s = &self.swarm;
        if !s.links_up[self.id] {
            return;
        }
        s.grid.for_each_neighbour(self.id, |nb| {
            let j = nb.index;
            if s.active[j] && s.links_up[j] {
                visit(&Neighbour {
                    id: j,
                    state: s.relative_states[j],
                    offset_m: Vector3::new(nb.dx_m, nb.dy_m, nb.dz_m),
                    distance_m: nb.distance_m,
                });
            }
        });
    }
}

/// A law's failure to accept its parameters or to start.
#[derive(Debug, Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum LawError {
    /// A parameter is missing, unknown, of the wrong type or out of range.
    #[error("law `{law}`: {message}")]
    InvalidParameters {
        /// The law's registry name.
        law: String,
        /// What is wrong and what is allowed.
        message: String,
    },
}

/// A guidance law: maps what one satellite senses to its commanded acceleration.
///
/// Implementations must be deterministic functions of the view (no hidden random state), so that runs
/// are reproducible on any thread count. A law never touches the integrator or the truth state.
pub trait GuidanceLaw: Send + Sync {
    /// Registry name of the law (as written in scenario files).
    fn name(&self) -> &'static str;

    /// Called once before the run starts, and again when the law is switched in by an event, with the
    /// whole swarm. Default: nothing to do.
    fn initialise(&mut self, _swarm: &SwarmView<'_>) -> Result<(), LawError> {
        Ok(())
    }

    /// Commanded acceleration of one satellite, Hill frame \[m/s^2\], before actuator limits.
    fn command_m_s2(&self, satellite: &SatelliteView<'_>) -> Vector3<f64>;

    /// Replaces some parameters (an event of the timeline). Keys not given keep their value; unknown keys
    /// and out-of-range values are errors.
    fn set_parameters(&mut self, parameters: &toml::Table) -> Result<(), LawError>;

    /// The fastest closed-loop rate \[1/s\] the law can impose on a satellite of the given mass, if it has
    /// one: the engine refuses a control period or a fixed integration step too long to resolve it.
    fn fastest_rate_per_s(&self, _mass_kg: f64) -> Option<f64> {
        None
    }

    /// Names of the scalar metrics the law reports at every recording time (extra columns of
    /// `metrics.csv`, each name with its unit). Default: none.
    fn metric_names(&self) -> &'static [&'static str] {
        &[]
    }

    /// Called at every recording time (outside the integrator, in time order) with the truth swarm:
    /// writes the values of [`GuidanceLaw::metric_names`] into `values` (same order and length). The
    /// law may keep what it needs across calls (e.g. when a shape was first reached). Default: nothing.
    fn record_metrics(&mut self, _swarm: &SwarmView<'_>, _values: &mut [f64]) {}

    /// Whether the law's centralised step is due at the control tick `time_s` \[s\]. The engine asks at
    /// every control tick (sampled mode) or integration step (continuous mode), outside the integrator's
    /// right-hand side, and calls [`GuidanceLaw::centralised_update`] when this returns `true`. The law
    /// owns its schedule (e.g. a period that grows during the run). Default: never.
    fn centralised_due(&self, _time_s: f64) -> bool {
        false
    }

    /// A **centralised** step with the whole swarm (navigation states, who is alive and linked), run
    /// before the commands of a tick at which [`GuidanceLaw::centralised_due`] is `true`. It models a
    /// computation that needs every satellite at once (a ground segment or an elected leader), not
    /// something a satellite can do from its own view; laws that use it are not fully decentralised and
    /// must say so. Its results (e.g. neighbour sets) are read by [`GuidanceLaw::command_m_s2`].
    /// Default: nothing to do.
    fn centralised_update(&mut self, _swarm: &SwarmView<'_>) -> Result<(), LawError> {
        Ok(())
    }

    /// Law-specific results for `summary.json`, computed from the final swarm. Default: none.
    fn results(&self, _swarm: &SwarmView<'_>) -> BTreeMap<String, serde_json::Value> {
        BTreeMap::new()
    }
}
