//! `differential-drag`: propellant-free along-track phasing of a flock in one orbital plane, each
//! satellite switching between its low- and high-drag attitude (ours, beyond the seed papers; the design
//! follows Leonard, Hollister & Bergmann, "Orbital formationkeeping with differential drag", J. Guidance
//! 12(1), 1989, and Planet's Flock phasing, Foster et al., J. Spacecraft and Rockets 55(2), 2018; method
//! page `docs/methods/differential-drag.md`).
//!
//! A satellite's **phase** is its angle along the orbit ahead of the LVLH origin, in the Hill frame
//! `φ = atan2(y, R + x)` (R the reference orbit's radius at t = 0, x radial, y along-track). When the law
//! starts, the satellites are ranked (ties by id): rank k's **slot** is `(k − k̄) s` ahead of the
//! flock's phase centroid (s = `spacing_deg`, k̄ the mean rank), so the flock spreads to equal gaps s (12
//! satellites at 30° then also close the orbit with a 30° gap). The ranking is by the phase each
//! satellite would reach after one update period of free drift (its phase plus the HCW secular drift
//! `−(6 n x + 3 ẏ)/R` times `update_period_s`), so a flock released from one dispenser is ranked in the
//! order its release velocities spread it, not against it. It is the one step that sees the whole
//! flock at once, as a ground segment assigning the slots would. With `slots = "reference"` the slots
//! sit about the reference orbit's origin instead, and a satellite needs nobody else's phase. At each evaluation a satellite unwraps the phases of the satellites it senses
//! along the rank order (each step between consecutive ranks wrapped to (−180°, 180°]), takes their
//! centroid and mean rank, and its phase error is `e = φ − (φ̄ + (k − k̄) s)`: e > 0 means it is ahead
//! of its slot. Every satellite regulating to the common centroid, not to its neighbours, avoids the
//! string instability of a chain of bang-bang double integrators.
//!
//! High drag lowers the orbit faster, which raises the mean motion: the satellite gains phase. So once
//! per `update_period_s` (one orbital period averages out the short-periodic J2 terms of the phases),
//! from its error and the error's rate since the last update, it evaluates Leonard's switching function
//! `σ = e + ė|ė| / (2 α)` on the phase plane, α = `authority_deg_per_day2`/2 (half the differential phase
//! acceleration of the two modes: a margin, since the neighbours switch too), and chooses the low-drag
//! mode when `σ > δ` (ahead: fall back), the high-drag mode when `σ < −δ` (behind: catch up), and the
//! low-drag mode (which saves altitude) inside the dead band `|σ| ≤ δ` (δ = `deadband_deg`).
//!
//! With `slots = "flock"` it needs to sense the flock: a sensing range covering the flock's arc (for 12
//! satellites over a whole orbit, the orbit's diameter), or a ring neighbourhood covering it
//! (`[sensing] ring_neighbours`); sensing only part of the flock, it uses the run of consecutive ranks
//! around its own. It cannot change the plane, and its time to phase grows as 1/ΔB (method page).

use crate::invalid::Invalid;
use std::f64::consts::{PI, TAU};
use std::sync::Arc;

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::swarm::{
    Broadcast, CommandsDrag, Diagnostics, DragCommand, GuidanceLaw, LawContext, LawError, Reports,
    SatelliteView, SwarmView,
};

/// Seconds per day.
const DAY_S: f64 = 86_400.0;

/// Parameters of the `differential-drag` law.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DifferentialDragParameters {
    /// Target phase spacing between consecutive satellites along the orbit \[deg\]; in (0, 180].
    pub spacing_deg: f64,
    /// Half-width of the dead band on the switching function \[deg\]; >= 0.
    #[serde(default)]
    pub deadband_deg: f64,
    /// Differential phase acceleration between a satellite in its high-drag and one in its low-drag
    /// mode \[deg/day^2\]; > 0: `(3/2) ρ n² a ΔB` converted (the method page derives it).
    pub authority_deg_per_day2: f64,
    /// How often a satellite re-evaluates its error and may switch \[s\]; > 0 (one orbital period).
    pub update_period_s: f64,
    /// Tolerance of "phased" for the law's results: every spacing within this fraction of
    /// `spacing_deg` (default 0.05).
    #[serde(default = "default_phased_tolerance")]
    pub phased_tolerance: f64,
    /// What the slots are placed about (default `flock`).
    #[serde(default)]
    pub slots: SlotAnchor,
}

/// What the `differential-drag` slots are placed about.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SlotAnchor {
    /// The phase centroid of the satellites a satellite senses, itself included (the whole flock when
    /// the sensing range covers it): needs no common reference, but every satellite must sense the
    /// flock's whole arc, O(N²) per evaluation.
    #[default]
    Flock,
    /// The reference orbit's origin (a virtual chief each satellite propagates on board): slot k at
    /// `(k − (N − 1)/2) s` ahead of it. A satellite needs only its own navigation state and rank, O(1)
    /// per evaluation; the reference's ballistic coefficient must lie between the satellites' low- and
    /// high-drag ones (`[reference] drag_area_m2`), or the slots drift away faster than a satellite can
    /// follow.
    Reference,
}

fn default_phased_tolerance() -> f64 {
    0.05
}

impl DifferentialDragParameters {
    fn check(&self) -> Result<(), LawError> {
        let bad = |invalid: Invalid| LawError::invalid("differential-drag", invalid);
        if !(self.spacing_deg > 0.0 && self.spacing_deg <= 180.0) {
            return Err(bad(Invalid::range(
                "spacing_deg",
                self.spacing_deg,
                "(0, 180]",
            )));
        }
        if !(self.deadband_deg >= 0.0 && self.deadband_deg.is_finite()) {
            return Err(bad(Invalid::range(
                "deadband_deg",
                self.deadband_deg,
                "finite, >= 0",
            )));
        }
        if !(self.authority_deg_per_day2 > 0.0 && self.authority_deg_per_day2.is_finite()) {
            return Err(bad(Invalid::range(
                "authority_deg_per_day2",
                self.authority_deg_per_day2,
                "finite, > 0",
            )));
        }
        if !(self.update_period_s > 0.0 && self.update_period_s.is_finite()) {
            return Err(bad(Invalid::range(
                "update_period_s",
                self.update_period_s,
                "finite, > 0",
            )));
        }
        if !(self.phased_tolerance > 0.0 && self.phased_tolerance < 1.0) {
            return Err(bad(Invalid::range(
                "phased_tolerance",
                self.phased_tolerance,
                "(0, 1)",
            )));
        }
        Ok(())
    }
}

/// One satellite's memory.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DragPhasing {
    /// In the high-drag mode.
    pub high: bool,
    /// Phase error at the last evaluation \[rad\].
    pub error_rad: f64,
    /// Its rate between the last two evaluations \[rad/s\].
    pub rate_rad_s: f64,
    /// Time of the last evaluation \[s\] (`None` before the first).
    pub evaluated_s: Option<f64>,
    /// Mode changes the law asked for.
    pub switches: u64,
}

/// Keeps, of `(rank, phase)` pairs sorted by rank and holding `own_rank`, only the run of consecutive
/// ranks that holds it: a satellite seen across the flock's open end (the last rank behind the first,
/// in a ring neighbourhood) is not taken for a near one.
fn keep_consecutive_ranks(sensed: &mut Vec<(usize, f64)>, own_rank: usize) {
    let own = sensed.partition_point(|e| e.0 < own_rank);
    let first = (0..own)
        .rev()
        .find(|&k| sensed[k].0 + 1 != sensed[k + 1].0)
        .map_or(0, |k| k + 1);
    let last = (own..sensed.len() - 1)
        .find(|&k| sensed[k].0 + 1 != sensed[k + 1].0)
        .unwrap_or(sensed.len() - 1);
    sensed.truncate(last + 1);
    sensed.drain(..first);
}

/// `d` wrapped to (−π, π] \[rad\].
fn wrap_rad(d: f64) -> f64 {
    PI - (PI - d).rem_euclid(TAU)
}

/// The `differential-drag` law.
#[derive(Clone, Debug)]
pub struct DifferentialDrag {
    parameters: DifferentialDragParameters,
    /// First time every spacing was within tolerance and stayed so, as seen at the recordings \[s\].
    phased_since_s: Option<f64>,
    /// The largest spacing error at the last recording \[deg\].
    last_max_error_deg: f64,
    /// Each satellite's rank by id (`usize::MAX`: not ranked, e.g. removed before the start).
    ranks: Arc<Vec<usize>>,
    /// How many satellites were ranked.
    ranked: usize,
}

impl DifferentialDrag {
    /// The law, its parameters checked.
    pub fn new(parameters: DifferentialDragParameters) -> Result<Self, LawError> {
        parameters.check()?;
        Ok(Self {
            parameters,
            phased_since_s: None,
            last_max_error_deg: f64::NAN,
            ranks: Arc::new(Vec::new()),
            ranked: 0,
        })
    }

    /// Phase of a Hill position ahead of the LVLH origin \[rad\].
    fn phase_rad(position_m: &Vector3<f64>, reference_radius_m: f64) -> f64 {
        position_m.y.atan2(reference_radius_m + position_m.x)
    }

    /// The phase error of the satellite of rank `own_rank` \[rad\], from the phases of the ranked
    /// satellites it senses, itself included: `(rank, phase)` pairs sorted by rank.
    fn error_rad(&self, own_rank: usize, sensed: &[(usize, f64)]) -> f64 {
        let spacing = self.parameters.spacing_deg.to_radians();
        let mut unwrapped = Vec::with_capacity(sensed.len());
        for (k, &(_, phase)) in sensed.iter().enumerate() {
            let value = match k {
                0 => phase,
                _ => {
                    let previous: f64 = unwrapped[k - 1];
                    previous + wrap_rad(phase - previous)
                }
            };
            unwrapped.push(value);
        }
        let count = sensed.len() as f64;
        let centroid = unwrapped.iter().sum::<f64>() / count;
        let mean_rank = sensed.iter().map(|(r, _)| *r as f64).sum::<f64>() / count;
        let own = sensed
            .iter()
            .position(|(r, _)| *r == own_rank)
            .map_or(centroid, |k| unwrapped[k]);
        own - (centroid + (own_rank as f64 - mean_rank) * spacing)
    }

    /// The largest spacing error over the swarm's live satellites \[deg\]: the gaps between consecutive
    /// phases, all of them when the satellites close the orbit (count × spacing ≥ 360° − spacing/2),
    /// else all but the widest.
    pub fn max_spacing_error_deg(&self, phases_rad: &mut [f64]) -> f64 {
        let n = phases_rad.len();
        if n < 2 {
            return 0.0;
        }
        phases_rad.sort_by(f64::total_cmp);
        let mut gaps: Vec<f64> = phases_rad.windows(2).map(|w| w[1] - w[0]).collect();
        gaps.push(TAU - (phases_rad[n - 1] - phases_rad[0]));
        let spacing = self.parameters.spacing_deg;
        let ring = n as f64 * spacing >= 360.0 - 0.5 * spacing;
        if !ring {
            let widest = gaps
                .iter()
                .enumerate()
                .max_by(|a, b| a.1.total_cmp(b.1))
                .map_or(0, |(k, _)| k);
            gaps.remove(widest);
        }
        gaps.iter()
            .map(|g| (g.to_degrees() - spacing).abs())
            .fold(0.0, f64::max)
    }
}

impl GuidanceLaw for DifferentialDrag {
    type State = DragPhasing;
    type Parameters = DifferentialDragParameters;
    crate::capabilities!(CommandsDrag, Diagnostics, Reports);

    fn name(&self) -> &'static str {
        "differential-drag"
    }

    fn initialise(&mut self, swarm: &SwarmView<'_>, _: &mut [DragPhasing]) -> Result<(), LawError> {
        let radius = swarm.shared.reference_model.reference_radius_m();
        let n = swarm.shared.mean_motion_rad_s;
        let horizon_s = self.parameters.update_period_s;
        let mut live: Vec<(f64, usize)> = (0..swarm.len())
            .filter(|&i| swarm.active[i])
            .map(|i| {
                let state = &swarm.relative_states[i];
                // The HCW secular along-track drift −(6 n x + 3 ẏ) [m/s] over one update period.
                let drift_rad_s =
                    -(6.0 * n * state.position_m.x + 3.0 * state.velocity_mps.y) / radius;
                (
                    Self::phase_rad(&state.position_m, radius) + drift_rad_s * horizon_s,
                    i,
                )
            })
            .collect();
        live.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut ranks = vec![usize::MAX; swarm.len()];
        for (k, &(_, id)) in live.iter().enumerate() {
            ranks[id] = k;
        }
        self.ranks = Arc::new(ranks);
        self.ranked = live.len();
        Ok(())
    }

    /// The update reads only the satellite's own previous state: updated in place.
    fn reads_neighbour_broadcasts(&self) -> bool {
        false
    }

    fn update_state(
        &self,
        satellite: &SatelliteView<'_>,
        broadcast: &Broadcast<'_, DragPhasing>,
        _context: &LawContext,
    ) -> DragPhasing {
        let mut state = broadcast.own().clone();
        let shared = satellite.shared();
        let t = shared.time_s;
        let due = state
            .evaluated_s
            .is_none_or(|last| t - last >= self.parameters.update_period_s * (1.0 - 1e-9));
        if !due {
            return state;
        }
        let radius = shared.reference_model.reference_radius_m();
        let rank_of = |id: usize| self.ranks.get(id).copied().filter(|r| *r != usize::MAX);
        let Some(own_rank) = rank_of(satellite.id()) else {
            return state;
        };
        let own_phase = Self::phase_rad(&satellite.own_state().position_m, radius);
        let error = match self.parameters.slots {
            SlotAnchor::Reference => {
                let middle = (self.ranked as f64 - 1.0) / 2.0;
                let slot = (own_rank as f64 - middle) * self.parameters.spacing_deg.to_radians();
                wrap_rad(own_phase - slot)
            }
            SlotAnchor::Flock => {
                let mut sensed = vec![(own_rank, own_phase)];
                satellite.for_each_neighbour(|nb| {
                    if let Some(rank) = rank_of(nb.id) {
                        sensed.push((rank, Self::phase_rad(&nb.state.position_m, radius)));
                    }
                });
                sensed.sort_by_key(|e| e.0);
                // Sensing part of the flock (a ring neighbourhood, or a range shorter than the
                // flock): only the run of consecutive ranks around its own.
                if sensed.len() < self.ranked {
                    keep_consecutive_ranks(&mut sensed, own_rank);
                }
                self.error_rad(own_rank, &sensed)
            }
        };
        let rate = match state.evaluated_s {
            Some(last) if t > last => wrap_rad(error - state.error_rad) / (t - last),
            _ => 0.0,
        };
        let alpha = 0.5 * self.parameters.authority_deg_per_day2.to_radians() / (DAY_S * DAY_S);
        let sigma = error + rate * rate.abs() / (2.0 * alpha);
        let deadband = self.parameters.deadband_deg.to_radians();
        let high = sigma < -deadband;
        if high != state.high {
            state.switches += 1;
        }
        state.high = high;
        state.error_rad = error;
        state.rate_rad_s = rate;
        state.evaluated_s = Some(t);
        state
    }

    fn command(&self, _: &SatelliteView<'_>, _: &DragPhasing, _: &LawContext) -> Vector3<f64> {
        Vector3::zeros()
    }

    fn set_parameters(&mut self, parameters: &DifferentialDragParameters) -> Result<(), LawError> {
        parameters.check()?;
        self.parameters = parameters.clone();
        Ok(())
    }
}

impl CommandsDrag<DragPhasing> for DifferentialDrag {
    fn drag_command(&self, state: &DragPhasing) -> Option<DragCommand> {
        Some(if state.high {
            DragCommand::Maximum
        } else {
            DragCommand::Minimum
        })
    }
}

impl Diagnostics<DragPhasing> for DifferentialDrag {
    fn output_names(&self) -> &'static [&'static str] {
        &["dd_phase_error_deg", "dd_high_drag"]
    }

    fn write_outputs(&self, state: &DragPhasing, values: &mut [f64]) {
        values[0] = state.error_rad.to_degrees();
        values[1] = f64::from(u8::from(state.high));
    }

    fn metric_names(&self) -> &'static [&'static str] {
        &["dd_max_spacing_error_deg", "dd_high_drag_count"]
    }

    fn record_metrics(
        &mut self,
        swarm: &SwarmView<'_>,
        states: &[DragPhasing],
        values: &mut [f64],
    ) {
        let radius = swarm.shared.reference_model.reference_radius_m();
        let mut phases: Vec<f64> = swarm
            .relative_states
            .iter()
            .zip(swarm.active)
            .filter(|(_, a)| **a)
            .map(|(s, _)| Self::phase_rad(&s.position_m, radius))
            .collect();
        let error = self.max_spacing_error_deg(&mut phases);
        let tolerance = self.parameters.phased_tolerance * self.parameters.spacing_deg;
        if error <= tolerance {
            self.phased_since_s.get_or_insert(swarm.shared.time_s);
        } else {
            self.phased_since_s = None;
        }
        self.last_max_error_deg = error;
        values[0] = error;
        values[1] = states
            .iter()
            .zip(swarm.active)
            .filter(|(s, a)| **a && s.high)
            .count() as f64;
    }
}

/// The `differential-drag` law's results (`summary.json` `law`; the engine adds
/// `mean_altitude_decay_m`, as for every law that commands drag).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DifferentialDragResults {
    /// Since when the largest spacing error has stayed within the phased tolerance \[s\] (null if it
    /// is not within it at the last recording).
    pub time_to_phase_s: Option<f64>,
    /// The largest spacing error at the last recording \[deg\] (null before one).
    pub max_phase_error_deg: Option<f64>,
    /// Drag-mode changes, summed over the satellites.
    pub mode_switches: u64,
    /// The thrust Δv the law uses: none \[m/s\].
    pub thrust_delta_v_mps: f64,
}

impl Reports<DragPhasing> for DifferentialDrag {
    type Results = DifferentialDragResults;

    fn results(&self, _swarm: &SwarmView<'_>, states: &[DragPhasing]) -> DifferentialDragResults {
        DifferentialDragResults {
            time_to_phase_s: self.phased_since_s,
            max_phase_error_deg: self
                .last_max_error_deg
                .is_finite()
                .then_some(self.last_max_error_deg),
            mode_switches: states.iter().map(|s| s.switches).sum(),
            thrust_delta_v_mps: 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn law(spacing_deg: f64) -> DifferentialDrag {
        DifferentialDrag::new(DifferentialDragParameters {
            spacing_deg,
            deadband_deg: 0.1,
            authority_deg_per_day2: 0.01,
            update_period_s: 5400.0,
            phased_tolerance: 0.05,
            slots: SlotAnchor::Flock,
        })
        .unwrap()
    }

    #[test]
    fn only_the_run_of_consecutive_ranks_around_its_own_is_kept() {
        let ranks = |sensed: &[(usize, f64)]| sensed.iter().map(|e| e.0).collect::<Vec<_>>();
        // Rank 0 with one ring neighbour each side in a flock of 12: 11 is seen behind it across the
        // open end.
        let mut across = vec![(0, 0.0), (1, 0.5), (11, -0.5)];
        across.sort_by_key(|e| e.0);
        keep_consecutive_ranks(&mut across, 0);
        assert_eq!(ranks(&across), [0, 1]);
        // Gaps on both sides of rank 5: 2 and 9 are cut off, 4 … 7 kept.
        let mut gaps: Vec<(usize, f64)> = [2, 4, 5, 6, 7, 9].iter().map(|&r| (r, 0.0)).collect();
        keep_consecutive_ranks(&mut gaps, 5);
        assert_eq!(ranks(&gaps), [4, 5, 6, 7]);
        // The last rank alone with its lower neighbours; a whole run is kept whole.
        let mut end: Vec<(usize, f64)> = [0, 9, 10, 11].iter().map(|&r| (r, 0.0)).collect();
        keep_consecutive_ranks(&mut end, 11);
        assert_eq!(ranks(&end), [9, 10, 11]);
        let mut whole: Vec<(usize, f64)> = (3..8).map(|r| (r, 0.0)).collect();
        keep_consecutive_ranks(&mut whole, 3);
        assert_eq!(ranks(&whole), [3, 4, 5, 6, 7]);
    }

    #[test]
    fn phase_errors_against_the_slots_about_the_centroid() {
        let l = law(30.0);
        let d = |deg: f64| deg.to_radians();
        // Ranks 0, 1, 2 at 0°, 20°, 50°: centroid 23.33°, mean rank 1, slots −6.67°, 23.33°, 53.33°:
        // errors +6.67°, −3.33°, −3.33°.
        let sensed = [(0, d(0.0)), (1, d(20.0)), (2, d(50.0))];
        let e = |rank: usize| l.error_rad(rank, &sensed).to_degrees();
        assert!((e(0) - 20.0 / 3.0).abs() < 1e-9, "{}", e(0));
        assert!((e(1) + 10.0 / 3.0).abs() < 1e-9, "{}", e(1));
        assert!((e(2) + 10.0 / 3.0).abs() < 1e-9, "{}", e(2));
        // Twelve at 30° around the whole orbit, across the ±180° cut: no error anywhere.
        let ring: Vec<(usize, f64)> = (0..12)
            .map(|k| (k, d(-165.0 + 30.0 * k as f64 + 100.0)))
            .map(|(k, p)| (k, PI - (PI - p).rem_euclid(TAU)))
            .collect();
        for k in 0..12 {
            assert!(l.error_rad(k, &ring).abs() < 1e-12, "rank {k}");
        }
        let mut phases = vec![d(0.0), d(20.0), d(50.0)];
        assert!((l.max_spacing_error_deg(&mut phases) - 10.0).abs() < 1e-9);
        let mut all: Vec<f64> = ring.iter().map(|r| r.1).collect();
        assert!(l.max_spacing_error_deg(&mut all) < 1e-9);
    }

    #[test]
    fn parameters_out_of_range_are_refused_naming_the_key() {
        let mut p = law(30.0).parameters;
        p.authority_deg_per_day2 = 0.0;
        let e = DifferentialDrag::new(p).unwrap_err().to_string();
        assert!(e.contains("authority_deg_per_day2"), "{e}");
    }
}
