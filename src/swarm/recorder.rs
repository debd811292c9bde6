//! What the engine hands to its outputs at every recording time: a [`Snapshot`] of the swarm, consumed by
//! a [`Recorder`]. Recording streams: the engine never keeps the trajectory in memory.

use nalgebra::Vector3;

use crate::metrics::FiveElements;
use crate::orbit::{CartesianState, RelativeStateHill};
use crate::swarm::events::Firing;

/// The swarm at one recording time.
#[derive(Debug)]
pub struct Snapshot<'a> {
    /// Time since the scenario start \[s\].
    pub time_s: f64,
    /// States relative to the LVLH origin, Hill frame \[m, m/s\] (truth, without navigation noise).
    pub relative_states: &'a [RelativeStateHill],
    /// Inertial states, ECI \[m, m/s\].
    pub inertial_states: &'a [CartesianState],
    /// `false` for removed satellites (they are not written).
    pub active: &'a [bool],
    /// Delta-v ledger per satellite: ∫|a| dt per Hill axis \[m/s\].
    pub delta_v_axes_mps: &'a [[f64; 3]],
    /// Delta-v ledger per satellite: ∫‖a‖ dt \[m/s\].
    pub delta_v_mps: &'a [f64],
    /// Five-element characterisation of the live satellites (None when fewer than two are left).
    pub five_elements: Option<FiveElements>,
    /// Smallest distance between two live satellites at this time \[m\] (infinite with fewer than two).
    pub min_separation_m: f64,
    /// Pairs of live satellites closer than the sum of their radii at this time.
    pub collisions: usize,
    /// The running law's metric names (see [`crate::swarm::Diagnostics::metric_names`]).
    pub law_metric_names: &'static [&'static str],
    /// Their values now, in the same order.
    pub law_metrics: &'a [f64],
    /// The running law's per-satellite output names (see [`crate::swarm::Diagnostics::output_names`]).
    pub law_output_names: &'static [&'static str],
    /// Their values now, satellite-major: satellite i's at `i * k .. (i + 1) * k`.
    pub law_outputs: &'a [f64],
    /// The threat and obstacle monitors so far.
    pub environment: EnvironmentSnapshot,
    /// Drag area of every satellite \[m^2\], by id (empty when no satellite has drag attitudes).
    pub drag_areas_m2: &'a [f64],
    /// Drag-area changes of every satellite so far, summed.
    pub drag_switches: u64,
    /// The control history ([`crate::swarm::Simulation::set_control_history`]; both empty when it is
    /// off): every satellite's commanded acceleration, the law's command before the actuator, Hill
    /// frame \[m/s^2\], by id. Sampled control: the command of the last tick at or before this time,
    /// held since (zero before the first tick); continuous control: the command evaluated at this
    /// time's state. Zero for a removed satellite.
    pub commanded_hill_mps2: &'a [Vector3<f64>],
    /// The applied acceleration of the same command, after the actuator (saturation and failed axes;
    /// process noise, a disturbance, not included), Hill frame \[m/s^2\], by id. A satellite's command
    /// was limited by its actuator exactly where it differs from [`Self::commanded_hill_mps2`].
    pub applied_hill_mps2: &'a [Vector3<f64>],
}

/// The continuous threat and obstacle monitors from the start of the run to a recording time.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EnvironmentSnapshot {
    /// Number of threats in the scenario.
    pub threats: usize,
    /// Number of obstacles in the scenario.
    pub obstacles: usize,
    /// Smallest distance between a live satellite and a threat so far \[m\] (None: no threat, or none
    /// observed yet).
    pub min_threat_distance_m: Option<f64>,
    /// Smallest clearance between a live satellite and an obstacle's surface so far \[m\] (negative:
    /// inside; None: no obstacle, or none observed yet).
    pub min_obstacle_clearance_m: Option<f64>,
    /// Entries of satellites into threat danger spheres so far.
    pub threat_incursions: u64,
    /// Entries of satellites into obstacles so far.
    pub obstacle_incursions: u64,
}

/// A consumer of snapshots (CSV writers, in-memory collectors for tests, Python callbacks).
pub trait Recorder {
    /// Records one snapshot. An error stops the run.
    fn record(&mut self, snapshot: &Snapshot<'_>) -> std::io::Result<()>;

    /// Takes in one firing of an event, in firing order (default: ignored). An error stops the run.
    fn event_fired(&mut self, _firing: &Firing) -> std::io::Result<()> {
        Ok(())
    }
}

/// A recorder that discards everything (benchmarks, runs that only want the summary).
#[derive(Debug, Default, Clone, Copy)]
pub struct NullRecorder;

impl Recorder for NullRecorder {
    fn record(&mut self, _snapshot: &Snapshot<'_>) -> std::io::Result<()> {
        Ok(())
    }
}
