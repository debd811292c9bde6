//! The event timeline: commands that take effect at a given simulation time (new law parameters, a law
//! switch, ground messages such as threat warnings, link outages, satellite losses, thruster failures).

use crate::swarm::law::{Law, LawParameters};

/// Which satellites an event concerns.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Selection {
    /// Every satellite.
    All,
    /// The listed satellite indices.
    Satellites(Vec<usize>),
}

impl Selection {
    /// Whether satellite `i` is selected.
    pub fn contains(&self, i: usize) -> bool {
        match self {
            Selection::All => true,
            Selection::Satellites(ids) => ids.contains(&i),
        }
    }
}

/// A thrust axis of the Hill frame, or all of them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ThrustAxis {
    /// Hill x (radial).
    X,
    /// Hill y (along-track).
    Y,
    /// Hill z (orbit normal).
    Z,
    /// Every axis: the satellite can no longer thrust.
    All,
}

/// What an event does.
pub enum EventAction {
    /// Replace the running law's parameters (a typed set, merged and validated by the scenario layer).
    SetLawParameters(LawParameters),
    /// Switch to another law (already built and validated by the scenario layer).
    SwitchLaw(Law),
    /// A ground message: raise or clear the warning about one threat.
    ThreatWarning {
        /// The threat's index in the scenario.
        threat: usize,
        /// Whether the warning is in force from now on.
        active: bool,
    },
    /// Cut the links of the selected satellites.
    CutLinks(Selection),
    /// Restore the links of the selected satellites.
    RestoreLinks(Selection),
    /// Remove a satellite from the swarm (lost): it is no longer propagated, sensed or counted.
    RemoveSatellite(usize),
    /// A thruster failure: the axis delivers no more thrust.
    FailThruster {
        /// The satellite.
        satellite: usize,
        /// The failed axis.
        axis: ThrustAxis,
    },
}

impl std::fmt::Debug for EventAction {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::SetLawParameters(_) => write!(f, "SetLawParameters"),
            Self::SwitchLaw(law) => write!(f, "SwitchLaw({})", law.name()),
            Self::ThreatWarning { threat, active } => {
                write!(f, "ThreatWarning {{ threat: {threat}, active: {active} }}")
            }
            Self::CutLinks(s) => write!(f, "CutLinks({s:?})"),
            Self::RestoreLinks(s) => write!(f, "RestoreLinks({s:?})"),
            Self::RemoveSatellite(i) => write!(f, "RemoveSatellite({i})"),
            Self::FailThruster { satellite, axis } => {
                write!(
                    f,
                    "FailThruster {{ satellite: {satellite}, axis: {axis:?} }}"
                )
            }
        }
    }
}

/// One entry of the timeline.
#[derive(Debug)]
pub struct Event {
    /// When it takes effect, seconds since the scenario start \[s\].
    pub time_s: f64,
    /// What it does.
    pub action: EventAction,
}
