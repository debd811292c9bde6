//! The per-satellite warning state machine of the `equilibrium-shaping` law (the ground station's
//! warning and 'safe' flag of the paper's §3.1, made explicit): NOMINAL → WARNED on a ground warning
//! about the law's threat, WARNED → RETURNING when the warning is lifted,
//! RETURNING → NOMINAL once the formation has settled (or → WARNED on a new warning). In NOMINAL and
//! RETURNING the satellite also reacts to the threat its own sensors see within the physical sensing
//! radius. Every switch (mode or physical sensing) suppresses the feed-forward for the tick and is
//! appended to the satellite's timeline.
//!
//! [`next_state`] is a pure function of the previous state and an [`Observation`], so a scripted
//! warning timeline can drive it without a simulation. Positions and velocities are Hill-frame vectors
//! relative to the LVLH origin \[m, m/s\]; times are seconds since the scenario start.

use std::sync::Arc;

use nalgebra::Vector3;

use super::field::DIRECTION_EPSILON_M;
use super::parameters::{gaussian_width_m2, Escape};
use crate::random::{Purpose, RandomStream};

/// A satellite's mode.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Mode {
    /// The strategy's nominal field (keeps the formation), plus the physically sensed threat term.
    #[default]
    Nominal,
    /// A ground warning is in force: the strategy's scatter field.
    Warned,
    /// The warning was lifted: the strategy's return field until the formation settles.
    Returning,
}

impl Mode {
    /// The value of the `es_mode` output: 0 nominal, 1 warned, 2 returning.
    pub fn code(self) -> f64 {
        match self {
            Mode::Nominal => 0.0,
            Mode::Warned => 1.0,
            Mode::Returning => 2.0,
        }
    }

    /// Name used in `summary.json`.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Nominal => "nominal",
            Mode::Warned => "warned",
            Mode::Returning => "returning",
        }
    }
}

/// What a satellite stored when it was warned.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Warning {
    /// t_w: when the satellite received the warning \[s\].
    pub warned_at_s: f64,
    /// p_T(t_w): the threat's position in the warning message, Hill \[m\].
    pub threat_position_hill_m: Vector3<f64>,
    /// v_T: the threat's velocity in the message, Hill \[m/s\] (the on-board track is
    /// p_T(t) = p_T(t_w) + v_T (t − t_w)).
    pub threat_velocity_hill_mps: Vector3<f64>,
    /// Virtual sensing radius R_s,i = ‖x_i(t_w) − p_T(t_w)‖ \[m\].
    pub virtual_sensing_radius_m: f64,
    /// K_i = 2 (R_s,i / 3)² \[m²\].
    pub width_m2: f64,
    /// The escape direction chosen at the warning, Hill unit vector: v̂_T (`parallel`), the common
    /// perpendicular (`perp-common`), or the fallback of `perp-radial` and `away` (the common
    /// perpendicular).
    pub escape_direction_hill: Vector3<f64>,
}

impl Warning {
    /// The on-board track of the threat at `time_s` \[s\], Hill \[m\].
    pub fn threat_position_at_hill_m(&self, time_s: f64) -> Vector3<f64> {
        self.threat_position_hill_m + self.threat_velocity_hill_mps * (time_s - self.warned_at_s)
    }
}

/// One entry of a satellite's timeline.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModeEvent {
    /// A mode change.
    Mode {
        /// Mode before.
        from: Mode,
        /// Mode after.
        to: Mode,
    },
    /// The threat came within the physical sensing radius (NOMINAL or RETURNING).
    ThreatSensed,
    /// The threat left the physical sensing radius, or the satellite was warned while sensing it.
    ThreatLost,
}

/// A timeline entry with its time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModeChange {
    /// When \[s\] (the tick at which the satellite saw the change).
    pub time_s: f64,
    /// What changed.
    pub event: ModeEvent,
}

/// The law's per-satellite state.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EsState {
    /// Current mode.
    pub mode: Mode,
    /// When the current mode began \[s\].
    pub mode_since_s: f64,
    /// What was stored at the warning (in WARNED only).
    pub warning: Option<Warning>,
    /// Whether the physically sensed threat term is on (NOMINAL and RETURNING only).
    pub threat_sensed: bool,
    /// Whether a switch happened at this tick: the feed-forward is zero until the next tick.
    pub feedforward_suppressed: bool,
    /// In RETURNING: since when the settling conditions have held \[s\].
    pub settled_since_s: Option<f64>,
    /// Every switch so far, in time order (shared between ticks: cloning the state does not copy it).
    pub timeline: ModeTimeline,
}

/// A satellite's switches in time order, read as a slice of [`ModeChange`]. Cloning shares the entries
/// (a satellite's state is cloned at every tick). An empty timeline holds no allocation, so cloning it
/// touches no reference count: the states of a swarm that has not switched yet, all clones of one
/// default, would otherwise share one count, updated by every thread at every satellite and tick.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ModeTimeline(Option<Arc<[ModeChange]>>);

impl ModeTimeline {
    /// Appends `change` (a new shared copy of the entries with it at the end).
    fn push(&mut self, change: ModeChange) {
        let mut entries = Vec::with_capacity(self.len() + 1);
        entries.extend_from_slice(self);
        entries.push(change);
        self.0 = Some(entries.into());
    }
}

impl std::ops::Deref for ModeTimeline {
    type Target = [ModeChange];

    fn deref(&self) -> &[ModeChange] {
        self.0.as_deref().unwrap_or_default()
    }
}

/// What a satellite knows at a tick, for its state machine.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Observation {
    /// Time of the tick \[s\].
    pub time_s: f64,
    /// Own position, Hill \[m\].
    pub own_position_hill_m: Vector3<f64>,
    /// The ground's track of the law's threat while a warning about it is in force: position and
    /// velocity now, Hill \[m, m/s\]; `None` without a warning.
    pub warned_threat_hill: Option<(Vector3<f64>, Vector3<f64>)>,
    /// Distance to the law's threat as the satellite's own sensors see it \[m\]; `None` when not sensed.
    pub sensed_threat_distance_m: Option<f64>,
    /// RMS over the sensed neighbours of (‖x_i − x_j‖ − δ_ij) \[m\] (0 with no neighbour in range).
    pub pair_rms_error_m: f64,
    /// Largest speed of the satellite and its sensed neighbours \[m/s\].
    pub max_speed_mps: f64,
}

/// The settings of the state machine (from the law's parameters).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MachineSettings {
    /// Physical sensing radius R_s \[m\].
    pub physical_sensing_radius_m: f64,
    /// Escape rule.
    pub escape: Escape,
    /// Given common direction (`perp-common`), Hill, any length.
    pub escape_direction_hill: Option<Vector3<f64>>,
    /// Seed of the common direction when none is given.
    pub escape_seed: u64,
    /// Settling: RMS pair error below this \[m\].
    pub settle_error_m: f64,
    /// Settling: speeds below this \[m/s\].
    pub settle_speed_mps: f64,
    /// Settling: held this long \[s\].
    pub settle_hold_s: f64,
}

/// A unit vector along `v`, or +x (radial) for a zero vector.
fn unit_or_x(v: &Vector3<f64>) -> Vector3<f64> {
    let n = v.norm();
    if n > 0.0 {
        v / n
    } else {
        Vector3::x()
    }
}

/// An orthonormal pair (e₁, e₂) perpendicular to the unit vector `v_hat`, fixed by a rule: e₁ = unit(v̂ ×
/// the Hill axis of smallest |v̂_k| (first on ties)), e₂ = v̂ × e₁.
pub fn perpendicular_basis(v_hat: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let mut axis = 0;
    for k in 1..3 {
        if v_hat[k].abs() < v_hat[axis].abs() {
            axis = k;
        }
    }
    let e1 = v_hat.cross(&Vector3::ith(axis, 1.0)).normalize();
    (e1, v_hat.cross(&e1))
}

/// The `perp-common` escape direction for a threat moving with `threat_velocity_mps` (Hill, m/s): the
/// given direction projected perpendicular to v_T and normalised, or (none given, or a given direction
/// along v_T) cos θ e₁ + sin θ e₂ of [`perpendicular_basis`] with θ = 2π u, u the first uniform draw of
/// `RandomStream::new(seed, LawUpdate, 0, 0)`. A pure function of (v̂_T, given, seed): every satellite
/// makes the same choice.
pub fn common_escape_direction(
    threat_velocity_mps: &Vector3<f64>,
    given_hill: Option<&Vector3<f64>>,
    seed: u64,
) -> Vector3<f64> {
    let v_hat = unit_or_x(threat_velocity_mps);
    if let Some(d) = given_hill {
        let projected = d - d.dot(&v_hat) * v_hat;
        if projected.norm() > DIRECTION_EPSILON_M * d.norm() {
            return projected.normalize();
        }
    }
    let (e1, e2) = perpendicular_basis(&v_hat);
    let theta = std::f64::consts::TAU * RandomStream::new(seed, Purpose::LawUpdate, 0, 0).uniform();
    theta.cos() * e1 + theta.sin() * e2
}

/// Whether a given `perp-common` direction is usable for a threat moving with `threat_velocity_mps`:
/// not along v_T (within [`DIRECTION_EPSILON_M`] relative).
pub fn direction_is_perpendicular_enough(
    direction_hill: &Vector3<f64>,
    threat_velocity_mps: &Vector3<f64>,
) -> bool {
    let v_hat = unit_or_x(threat_velocity_mps);
    let projected = direction_hill - direction_hill.dot(&v_hat) * v_hat;
    projected.norm() > DIRECTION_EPSILON_M * direction_hill.norm()
}

impl MachineSettings {
    /// The escape direction stored at a warning about a threat moving with `threat_velocity_mps`.
    pub fn escape_direction_hill(&self, threat_velocity_mps: &Vector3<f64>) -> Vector3<f64> {
        match self.escape {
            Escape::Parallel => unit_or_x(threat_velocity_mps),
            Escape::PerpCommon | Escape::PerpRadial | Escape::Away => common_escape_direction(
                threat_velocity_mps,
                self.escape_direction_hill.as_ref(),
                self.escape_seed,
            ),
        }
    }
}

/// The state after one tick, from the previous state and what the satellite observes now.
///
/// * NOMINAL or RETURNING, warning in force → WARNED: store t_w, p_T(t_w), v_T, R_s,i = ‖x_i − p_T‖,
///   K_i = 2 (R_s,i/3)² and the escape direction.
/// * WARNED, no warning → RETURNING (the stored warning is dropped: K returns to the physical width).
/// * RETURNING, no warning: once the RMS pair error is below `settle_error_m` and every speed below
///   `settle_speed_mps` for `settle_hold_s` → NOMINAL.
/// * NOMINAL and RETURNING: the physically sensed threat term is on while the sensed distance is within
///   the physical sensing radius; always off in WARNED.
pub fn next_state(
    previous: &EsState,
    observation: &Observation,
    settings: &MachineSettings,
) -> EsState {
    let t = observation.time_s;
    let mut s = previous.clone();
    s.feedforward_suppressed = false;
    let switch = |s: &mut EsState, to: Mode| {
        s.timeline.push(ModeChange {
            time_s: t,
            event: ModeEvent::Mode { from: s.mode, to },
        });
        s.mode = to;
        s.mode_since_s = t;
        s.settled_since_s = None;
        s.feedforward_suppressed = true;
    };
    match (previous.mode, observation.warned_threat_hill) {
        (Mode::Nominal | Mode::Returning, Some((position, velocity))) => {
            let radius = (observation.own_position_hill_m - position).norm();
            s.warning = Some(Warning {
                warned_at_s: t,
                threat_position_hill_m: position,
                threat_velocity_hill_mps: velocity,
                virtual_sensing_radius_m: radius,
                width_m2: gaussian_width_m2(radius),
                escape_direction_hill: settings.escape_direction_hill(&velocity),
            });
            switch(&mut s, Mode::Warned);
        }
        (Mode::Warned, None) => {
            s.warning = None;
            switch(&mut s, Mode::Returning);
        }
        (Mode::Returning, None) => {
            let settled = observation.pair_rms_error_m < settings.settle_error_m
                && observation.max_speed_mps < settings.settle_speed_mps;
            if settled {
                let since = *s.settled_since_s.get_or_insert(t);
                if t - since >= settings.settle_hold_s {
                    switch(&mut s, Mode::Nominal);
                }
            } else {
                s.settled_since_s = None;
            }
        }
        (Mode::Nominal, None) | (Mode::Warned, Some(_)) => {}
    }
    let sensed = s.mode != Mode::Warned
        && observation
            .sensed_threat_distance_m
            .is_some_and(|d| d <= settings.physical_sensing_radius_m);
    if sensed != s.threat_sensed {
        s.timeline.push(ModeChange {
            time_s: t,
            event: if sensed {
                ModeEvent::ThreatSensed
            } else {
                ModeEvent::ThreatLost
            },
        });
        s.threat_sensed = sensed;
        s.feedforward_suppressed = true;
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn change(time_s: f64, to: Mode) -> ModeChange {
        ModeChange {
            time_s,
            event: ModeEvent::Mode {
                from: Mode::Nominal,
                to,
            },
        }
    }

    /// An empty timeline holds no allocation (so a swarm's default states share no reference count);
    /// pushes append in order, and a clone reads the same entries and is not changed by a later push
    /// to the original.
    #[test]
    fn the_timeline_appends_shares_on_clone_and_starts_without_an_allocation() {
        let mut timeline = ModeTimeline::default();
        assert!(timeline.0.is_none());
        assert!(timeline.is_empty());
        timeline.push(change(1.0, Mode::Warned));
        let before = timeline.clone();
        timeline.push(change(2.5, Mode::Returning));
        assert_eq!(&*before, &[change(1.0, Mode::Warned)]);
        assert_eq!(
            &*timeline,
            &[change(1.0, Mode::Warned), change(2.5, Mode::Returning)]
        );
        let shared = timeline.clone();
        assert!(matches!(
            (&shared.0, &timeline.0),
            (Some(a), Some(b)) if Arc::ptr_eq(a, b)
        ));
    }
}
