//! The event timeline: commands (new law parameters, a law switch, ground messages such as threat
//! warnings, link outages, satellite losses, thruster failures, stopping the run, an extra recording)
//! that take effect at a given simulation time or when a condition on the swarm's truth state holds
//! ([`Trigger`], [`Condition`]), and the record of each firing ([`Firing`]).

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
    /// End the run now: the recorder gets a last snapshot at this time and the run returns as
    /// stopped ([`crate::swarm::Simulation::stopped_by`]).
    StopRun,
    /// Hand the recorder a snapshot at this time (besides the recording cadence).
    RecordSnapshot,
}

impl EventAction {
    /// The action's name in scenario files and outputs (`set-law-parameters`, `stop-run`, …).
    pub fn name(&self) -> &'static str {
        match self {
            Self::SetLawParameters(_) => "set-law-parameters",
            Self::SwitchLaw(_) => "switch-law",
            Self::ThreatWarning { .. } => "threat-warning",
            Self::CutLinks(_) => "cut-links",
            Self::RestoreLinks(_) => "restore-links",
            Self::RemoveSatellite(_) => "remove-satellite",
            Self::FailThruster { .. } => "fail-thruster",
            Self::StopRun => "stop-run",
            Self::RecordSnapshot => "record-snapshot",
        }
    }

    /// A copy of the action for an event that may fire again (`None` for the law actions, whose
    /// built law or parameter set is handed over when they fire: such events fire once).
    pub fn repeatable_copy(&self) -> Option<Self> {
        Some(match self {
            Self::SetLawParameters(_) | Self::SwitchLaw(_) => return None,
            Self::ThreatWarning { threat, active } => Self::ThreatWarning {
                threat: *threat,
                active: *active,
            },
            Self::CutLinks(s) => Self::CutLinks(s.clone()),
            Self::RestoreLinks(s) => Self::RestoreLinks(s.clone()),
            Self::RemoveSatellite(i) => Self::RemoveSatellite(*i),
            Self::FailThruster { satellite, axis } => Self::FailThruster {
                satellite: *satellite,
                axis: *axis,
            },
            Self::StopRun => Self::StopRun,
            Self::RecordSnapshot => Self::RecordSnapshot,
        })
    }
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
            Self::StopRun => write!(f, "StopRun"),
            Self::RecordSnapshot => write!(f, "RecordSnapshot"),
        }
    }
}

/// One entry of the timeline.
#[derive(Debug)]
pub struct Event {
    /// Its index in the scenario's `[[events]]` (outputs name it `events[index]`).
    pub index: usize,
    /// When it fires.
    pub trigger: Trigger,
    /// What it does.
    pub action: EventAction,
}

impl Event {
    /// The event `index` that fires at `time_s` \[s\].
    pub fn at(index: usize, time_s: f64, action: EventAction) -> Self {
        Self {
            index,
            trigger: Trigger::Time(time_s),
            action,
        }
    }

    /// Its time \[s\], for an event that fires at a time.
    pub fn time_s(&self) -> Option<f64> {
        match self.trigger {
            Trigger::Time(t) => Some(t),
            Trigger::Condition(_) => None,
        }
    }
}

/// When an event fires.
#[derive(Clone, Debug, PartialEq)]
pub enum Trigger {
    /// At this time, seconds since the scenario start \[s\].
    Time(f64),
    /// At the first control tick (integration step in continuous control) at which the condition
    /// holds on the swarm's truth; with [`Condition::repeat`], again at each later tick at which it
    /// holds after it has re-armed.
    Condition(Condition),
}

/// A condition on the swarm's truth state, evaluated at every control tick from t = 0 (see
/// `docs/scenarios.md`, "Condition events").
///
/// Semantics: the condition starts armed; it fires at the first tick at which it holds (t = 0
/// included) and is then disarmed. With [`Condition::repeat`] it re-arms at a later tick at which
/// its value is back past the threshold by at least [`Condition::hysteresis`] (in the test's unit),
/// and fires again at the next tick at which it holds: once per crossing.
#[derive(Clone, Debug, PartialEq)]
pub struct Condition {
    /// What is tested.
    pub test: ConditionTest,
    /// How far back past the threshold the value must come before the condition re-arms, in the
    /// test's unit (m for the distances, the outcome's unit, dimensionless for L); 0: as soon as it
    /// no longer holds.
    pub hysteresis: f64,
    /// Fire at every crossing (after re-arming); `false`: once.
    pub repeat: bool,
}

/// The key a law reports whether its formation is reached under, in its results (`true`/`false`)
/// and among its metric names: what `formation_reached = true` tests when no uniformity target is
/// given.
pub const SHAPE_REACHED: &str = "shape_reached";

/// What a [`Condition`] tests, and its value.
#[derive(Clone, Debug, PartialEq)]
pub enum ConditionTest {
    /// The minimum separation between two live satellites now (exact, truth) is below the
    /// threshold \[m\]. Value: the separation \[m\].
    MinSeparationBelow {
        /// The threshold \[m\].
        threshold_m: f64,
    },
    /// A live satellite came within this distance of a threat during the segments since the last
    /// tick (continuous closest approach along each satellite's cubic Hermite path, so a pass
    /// between ticks is not missed) \[m\]. Value: that smallest distance \[m\].
    ThreatWithin {
        /// The distance \[m\].
        distance_m: f64,
    },
    /// The running law reports its formation reached: its result [`SHAPE_REACHED`] is `true`.
    /// Value: 1 or 0.
    ShapeReached,
    /// The uniformity L of the live satellites' five elements (truth positions) is within
    /// `tolerance` of `target`. Value: L.
    UniformityWithin {
        /// The target L (dimensionless).
        target: f64,
        /// The largest |L − target| that counts as reached.
        tolerance: f64,
    },
    /// At least this many satellites have been removed. Value: the count removed.
    SatellitesLostAtLeast(usize),
    /// The conjunction monitor found an encounter (a pair's closest approach below its threshold,
    /// refined continuously between steps) over the segments since the last tick. Value: the smallest
    /// miss distance among those encounters \[m\] (absent when there was none; a simulation
    /// without a monitor, [`crate::swarm::Simulation::set_conjunction_threshold_m`], never fires it:
    /// a scenario refuses that).
    Conjunction,
    /// A declared outcome of the running law ([`crate::swarm::Headline`], a key of its results)
    /// crosses a bound. Value: the outcome (absent while the law gives no number for it).
    LawOutcome {
        /// The outcome's key in the law's results.
        name: String,
        /// The bound it crosses.
        bound: Bound,
    },
}

impl ConditionTest {
    /// The condition's key in scenario files (`min_separation_below_m`, …).
    pub fn key(&self) -> &'static str {
        match self {
            Self::MinSeparationBelow { .. } => "min_separation_below_m",
            Self::ThreatWithin { .. } => "threat_within_m",
            Self::ShapeReached | Self::UniformityWithin { .. } => "formation_reached",
            Self::SatellitesLostAtLeast(_) => "satellites_lost_at_least",
            Self::Conjunction => "conjunction",
            Self::LawOutcome { .. } => "law_outcome",
        }
    }

    /// Whether the condition holds for `value` (a value that does not exist never holds).
    pub fn holds(&self, value: Option<f64>) -> bool {
        let Some(v) = value else {
            return false;
        };
        match self {
            Self::MinSeparationBelow { threshold_m } => v < *threshold_m,
            Self::ThreatWithin { distance_m } => v <= *distance_m,
            Self::ShapeReached => v >= 0.5,
            Self::UniformityWithin { target, tolerance } => (v - target).abs() <= *tolerance,
            Self::SatellitesLostAtLeast(k) => v >= *k as f64,
            Self::Conjunction => true,
            Self::LawOutcome { bound, .. } => match bound {
                Bound::Above(x) => v > *x,
                Bound::Below(x) => v < *x,
            },
        }
    }

    /// Whether `value` is back past the threshold by at least `hysteresis`, so that a repeating
    /// condition re-arms (a value that does not exist re-arms; satellites never come back).
    pub fn rearms(&self, value: Option<f64>, hysteresis: f64) -> bool {
        let Some(v) = value else {
            return true;
        };
        match self {
            Self::MinSeparationBelow { threshold_m } => v >= threshold_m + hysteresis,
            Self::ThreatWithin { distance_m } => v > distance_m + hysteresis,
            Self::ShapeReached => v < 0.5,
            Self::UniformityWithin { target, tolerance } => {
                (v - target).abs() > tolerance + hysteresis
            }
            Self::SatellitesLostAtLeast(_) | Self::Conjunction => false,
            Self::LawOutcome { bound, .. } => match bound {
                Bound::Above(x) => v <= x - hysteresis,
                Bound::Below(x) => v >= x + hysteresis,
            },
        }
    }
}

/// The bound a law outcome crosses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bound {
    /// Holds when the outcome is greater than this.
    Above(f64),
    /// Holds when the outcome is less than this.
    Below(f64),
}

/// One firing of an event, as logged (`events.jsonl`, `summary.json` `events`).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Firing {
    /// The event's index in the scenario's `[[events]]`.
    pub event: usize,
    /// When it fired, seconds since the scenario start \[s\].
    pub time_s: f64,
    /// The tick it fired at: base steps (control periods, or integration steps in continuous
    /// control) completed by then.
    pub tick: u64,
    /// What triggered it: `time_s`, or the condition's key.
    pub trigger: &'static str,
    /// The condition's value when it fired, in its unit (absent for a timed event).
    pub value: Option<f64>,
    /// The action's name.
    pub action: &'static str,
}
