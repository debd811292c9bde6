//! The truth monitors, run after every segment on truth states whatever the law does: divergence (a
//! non-finite state, or a satellite beyond the allowed distance), the minimum separation and collision
//! count, and the continuous closest approach to every threat and clearance of every obstacle (from each
//! satellite's cubic Hermite path over the segment, so a minimum between two steps is not missed); and
//! the applied commands, which must be finite ([`check_commands`]).

use nalgebra::Vector3;

use crate::environment::{closest_approach_to_threat, HermiteSegment};
use crate::metrics::{FiveElementsWorkspace, MetricsError, SeparationTracker};
use crate::orbit::RelativeStateHill;
use rayon::prelude::*;

use crate::swarm::simulation::satellites::Fleet;
use crate::swarm::simulation::sensing::CHUNK;
use crate::swarm::simulation::{Divergence, SimError, Simulation};
use crate::swarm::state::satellite_of;
use crate::swarm::storage_order::permute;
use crate::swarm::Law;

/// The truth monitors' own state: the live metrics' buffers, the continuous threat and obstacle
/// monitor, and the truth at the start of the segment their Hermite paths start from.
pub(super) struct Monitors {
    pub live: LiveMetrics,
    pub approach: crate::environment::ApproachMonitor,
    /// Truth relative states at the start of the last segment (empty in a scenario without threats
    /// or obstacles).
    pub truth_previous: Vec<RelativeStateHill>,
    /// Whether a condition event tests the closest approach to a threat (`threat_within_m`): then
    /// every segment's continuous closest approach of the swarm goes into `threat_window_m`.
    pub tracks_threats: bool,
    /// The closest approach between a live satellite and a threat over the segments since the
    /// conditions were last evaluated \[m\] (`None`: none observed).
    pub threat_window_m: Option<f64>,
}

/// Buffers of the separation and five-element metrics over the live satellites. Allocated once.
pub(super) struct LiveMetrics {
    /// Storage indices of the live satellites, ascending (the separation tracker's ids).
    indices: Vec<usize>,
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    radii_m: Vec<f64>,
    tracker: SeparationTracker,
    pub workspace: FiveElementsWorkspace,
}

impl LiveMetrics {
    /// Moves the separation tracker's anchors (by storage index) to the storage order in which new
    /// index `k` holds old index `moves[k]`.
    pub fn move_anchors(&mut self, moves: &[u32], visited: &mut Vec<bool>) {
        self.tracker.renumber(
            moves.len(),
            |anchors| permute(anchors, moves, visited),
            |old| moves.iter().position(|&m| m as usize == old).unwrap_or(old),
        );
    }

    pub fn new(n: usize) -> Self {
        Self {
            indices: Vec::with_capacity(n),
            x: Vec::with_capacity(n),
            y: Vec::with_capacity(n),
            z: Vec::with_capacity(n),
            radii_m: Vec::with_capacity(n),
            tracker: SeparationTracker::new(),
            workspace: FiveElementsWorkspace::new(),
        }
    }
}

impl Simulation {
    /// Runs every truth monitor on the segment that ended now and started at `t0_s`.
    pub(super) fn monitor(&mut self, t0_s: f64) -> Result<(), SimError> {
        self.check_divergence()?;
        let (separation, collisions) = live_separation(
            &self.satellites.truth,
            &self.satellites.fleet.active,
            &self.satellites.fleet.radii_m,
            &mut self.monitors.live,
        );
        self.totals.min_separation_m = self.totals.min_separation_m.min(separation);
        self.totals.max_collisions = self.totals.max_collisions.max(collisions);
        self.totals.collision_pair_samples += collisions;
        if self.clock.time_s > t0_s
            && !(self.config.threats.is_empty() && self.config.obstacles.is_empty())
        {
            for (i, (start, end)) in self
                .monitors
                .truth_previous
                .iter()
                .zip(&self.satellites.truth)
                .enumerate()
            {
                if !self.satellites.fleet.active[i] {
                    continue;
                }
                // Finite states (checked above) and t1 > t0 make the segment valid.
                if let Ok(segment) = HermiteSegment::new(
                    t0_s,
                    self.clock.time_s,
                    start.position_m,
                    start.velocity_mps,
                    end.position_m,
                    end.velocity_mps,
                ) {
                    let _ = self.monitors.approach.observe_segment(
                        self.satellites.fleet.order.id_at(i),
                        &segment,
                        &self.config.threats,
                        &self.config.obstacles,
                    );
                    if self.monitors.tracks_threats {
                        for threat in &self.config.threats {
                            let d = closest_approach_to_threat(&segment, threat).distance_m;
                            let window = &mut self.monitors.threat_window_m;
                            *window = Some(window.map_or(d, |w| w.min(d)));
                        }
                    }
                }
            }
        }
        Ok(())
    }

    fn check_divergence(&self) -> Result<(), SimError> {
        let bound = self.config.max_distance_m;
        let diverged = |i: usize| -> Option<Divergence> {
            if !self.satellites.fleet.active[i] {
                return None;
            }
            let rel = &self.satellites.truth[i];
            let finite = rel.position_m.iter().all(|v| v.is_finite())
                && rel.velocity_mps.iter().all(|v| v.is_finite());
            if !finite {
                return Some(Divergence::NotFinite);
            }
            let distance_m = rel.position_m.norm();
            if distance_m > bound {
                return Some(Divergence::TooFar {
                    distance_m,
                    limit_m: bound,
                });
            }
            let forces = self.config.dynamics.forces()?;
            let (position_m, _) = satellite_of(self.state.as_slice(), self.state.n(), i);
            forces
                .below_floor(&position_m)
                .map(|(altitude_m, floor_m)| Divergence::BelowAtmosphere {
                    altitude_m,
                    floor_m,
                })
        };
        // Scanned in storage order; the diverged satellite with the smallest id is named, whatever the
        // storage order.
        let order = &self.satellites.fleet.order;
        let first = (0..self.satellites.truth.len())
            .filter_map(|i| diverged(i).map(|reason| (order.id_at(i), reason)))
            .min_by_key(|(id, _)| *id);
        match first {
            Some((satellite, reason)) => Err(SimError::Diverged {
                satellite,
                time_s: self.clock.time_s,
                reason,
            }),
            None => Ok(()),
        }
    }
}

/// Minimum separation between live satellites \[m\] and the count of pairs closer than the sum of their
/// radii, from relative positions (infinite and 0 with fewer than two live satellites; NaN and 0 for a
/// non-finite position, which the divergence check reports). Exact at any distance at every call: the
/// tracker searches fully only when the motion since its last full search could have made a new pair
/// closest or colliding ([`SeparationTracker`]).
pub(super) fn live_separation(
    relative: &[RelativeStateHill],
    active: &[bool],
    radii_m: &[f64],
    live: &mut LiveMetrics,
) -> (f64, usize) {
    live.indices.clear();
    live.indices
        .extend((0..relative.len()).filter(|&i| active[i]));
    let m = live.indices.len();
    for buffer in [&mut live.x, &mut live.y, &mut live.z, &mut live.radii_m] {
        buffer.resize(m, 0.0);
    }
    // The live satellites' positions and radii, gathered in parallel (each slot on its own).
    let indices = &live.indices;
    live.x
        .par_iter_mut()
        .zip(live.y.par_iter_mut())
        .zip(live.z.par_iter_mut())
        .zip(live.radii_m.par_iter_mut())
        .zip(indices.par_iter())
        .with_min_len(CHUNK)
        .for_each(|((((x, y), z), radius), &i)| {
            let p = relative[i].position_m;
            (*x, *y, *z, *radius) = (p.x, p.y, p.z, radii_m[i]);
        });
    match live
        .tracker
        .update(&live.indices, &live.x, &live.y, &live.z, &live.radii_m)
    {
        Ok(sep) => (sep.min_distance_m, sep.collisions),
        Err(MetricsError::TooFewSatellites { .. }) => (f64::INFINITY, 0),
        Err(_) => (f64::NAN, 0),
    }
}

/// Refuses a non-finite applied command (`applied_hill`, by storage index) of a live satellite of
/// `fleet`: [`SimError::BadCommand`] naming the smallest such id, the law, the tick and the segment's
/// start `time_s` \[s\].
pub(super) fn check_commands(
    applied_hill: &[Vector3<f64>],
    fleet: &Fleet,
    law: &Law,
    tick: u64,
    time_s: f64,
) -> Result<(), SimError> {
    let bad = applied_hill
        .iter()
        .enumerate()
        .filter(|&(i, u)| fleet.active[i] && !u.norm().is_finite())
        .map(|(i, u)| (fleet.order.id_at(i), u))
        .min_by_key(|(id, _)| *id);
    match bad {
        None => Ok(()),
        Some((satellite, u)) => Err(SimError::BadCommand {
            satellite,
            tick,
            time_s,
            law: law.name().to_string(),
            command: [u.x, u.y, u.z],
        }),
    }
}
