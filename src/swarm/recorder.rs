//! What the engine hands to its outputs at every recording time: a [`Snapshot`] of the swarm, consumed by
//! a [`Recorder`]. Recording streams: the engine never keeps the trajectory in memory.

use crate::metrics::FiveElements;
use crate::orbit::{CartesianState, RelativeStateHill};

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
    /// The running law's metric names (see [`crate::swarm::GuidanceLaw::metric_names`]).
    pub law_metric_names: &'static [&'static str],
    /// Their values now, in the same order.
    pub law_metrics: &'a [f64],
}

/// A consumer of snapshots (CSV writers, in-memory collectors for tests, Python callbacks).
pub trait Recorder {
    /// Records one snapshot. An error stops the run.
    fn record(&mut self, snapshot: &Snapshot<'_>) -> std::io::Result<()>;
}

/// A recorder that discards everything (benchmarks, runs that only want the summary).
#[derive(Debug, Default, Clone, Copy)]
pub struct NullRecorder;

impl Recorder for NullRecorder {
    fn record(&mut self, _snapshot: &Snapshot<'_>) -> std::io::Result<()> {
        Ok(())
    }
}
