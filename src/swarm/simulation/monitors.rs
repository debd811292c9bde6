//! The truth monitors, run after every segment on truth states whatever the law does: divergence (a
//! non-finite state, or a satellite beyond the allowed distance), the minimum separation and collision
//! count, and the continuous closest approach to every threat and clearance of every obstacle (from each
//! satellite's cubic Hermite path over the segment, so a minimum between two steps is not missed); and
//! the applied commands, which must be finite ([`check_commands`]).

use nalgebra::Vector3;

use crate::conjunction::{ConjunctionMonitor, SwarmSegment};
use crate::dynamics::ForceSet;
use crate::environment::{closest_approach_to_threat, HermiteSegment};
use crate::metrics::{FiveElementsWorkspace, MetricsError, SeparationTracker, TrackedPositions};
use crate::orbit::{CartesianState, LvlhFrame, RelativeStateHill};

use crate::swarm::simulation::satellites::Fleet;
use crate::swarm::simulation::sensing::CHUNK;
use crate::swarm::simulation::Origin;
use crate::swarm::simulation::{Divergence, SimError, Simulation, SimulationConfig};
use crate::swarm::state::{reference_of, satellite_of};
use crate::swarm::storage_order::Moves;
use crate::swarm::Law;
use rayon::prelude::*;

/// The truth monitors' own state: the live metrics' buffers, the continuous threat and obstacle
/// monitor, and the truth at the start of the segment their Hermite paths start from.
pub(super) struct Monitors {
    pub live: LiveMetrics,
    pub approach: crate::environment::ApproachMonitor,
    /// Truth relative states at the start of the last segment (empty in a scenario without threats,
    /// obstacles or conjunction monitor).
    pub truth_previous: Vec<RelativeStateHill>,
    /// The conjunction monitor, when the run has one.
    pub conjunctions: Option<ConjunctionMonitor>,
    /// The LVLH origin's states at the start of the last segment (conjunction monitor only).
    pub origin_previous: OriginStates,
    /// The live satellite with the smallest id whose truth state diverged, and why, as the last
    /// truth pass found it ([`divergence_check`]).
    pub diverged: Option<(usize, Divergence)>,
    /// Whether a condition event tests the closest approach to a threat (`threat_within_m`): then
    /// every segment's continuous closest approach of the swarm goes into `threat_window_m`.
    pub tracks_threats: bool,
    /// The closest approach between a live satellite and a threat over the segments since the
    /// conditions were last evaluated \[m\] (`None`: none observed).
    pub threat_window_m: Option<f64>,
    /// How many of the conjunction monitor's encounters the conditions have seen: those after it were
    /// found since the conditions were last evaluated.
    pub conjunctions_seen: usize,
}

/// What places the Hill frame at an instant: the state of the frame's origin (EME2000 for the inertial
/// models: the virtual reference or the member origin; the virtual reference for the linear and
/// kinematic models, whose states are Hill states relative to it) and, for the linear and kinematic
/// models with a member origin, that member's state relative to the virtual reference (Hill; zero
/// otherwise), which the truth relative states are taken from.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct OriginStates {
    /// The frame's origin, EME2000 \[m, m/s\].
    pub origin_eme2000: CartesianState,
    /// The member origin relative to the virtual reference, Hill frame \[m, m/s\] (linear and
    /// kinematic models; zero otherwise).
    pub member_offset_hill: RelativeStateHill,
}

/// Buffers of the separation and five-element metrics over the live satellites, allocated at their first
/// use (not at the set-up's peak), then kept. The separation tracker reads the positions straight from
/// the truth states: with every satellite live it needs no buffer of its own.
pub(super) struct LiveMetrics {
    /// Storage indices of the live satellites, ascending (the separation tracker's ids), when some
    /// satellite is not live (empty otherwise: every storage index).
    indices: Vec<usize>,
    /// The live satellites' radii \[m\] when some satellite is not live (empty otherwise: the fleet's
    /// own column is read).
    radii_m: Vec<f64>,
    tracker: SeparationTracker,
    pub workspace: FiveElementsWorkspace,
}

/// The live satellites' positions as the separation tracker reads them: truth relative positions
/// (Hill frame, m) by storage index, every satellite or only those `listed`.
struct LivePositions<'a> {
    relative: &'a [RelativeStateHill],
    listed: Option<&'a [usize]>,
}

impl TrackedPositions for LivePositions<'_> {
    fn len(&self) -> usize {
        self.listed.map_or(self.relative.len(), <[usize]>::len)
    }

    fn id(&self, k: usize) -> usize {
        self.listed.map_or(k, |listed| listed[k])
    }

    fn position_m(&self, k: usize) -> [f64; 3] {
        let p = &self.relative[self.id(k)].position_m;
        [p.x, p.y, p.z]
    }

    /// Every storage index, or the live ones listed in ascending order.
    fn ids_known_ascending(&self) -> bool {
        true
    }

    fn index_of_id(&self, id: usize) -> Option<usize> {
        match self.listed {
            None => (id < self.relative.len()).then_some(id),
            Some(listed) => listed.binary_search(&id).ok(),
        }
    }

    /// Every storage index: the id is the index (with some satellites not live, a bisection would
    /// cost more than the miss it saves).
    fn prefetch_id(&self, id: usize) {
        if let (None, Some(state)) = (self.listed, self.relative.get(id)) {
            crate::prefetch::read(&state.position_m);
        }
    }
}

impl LiveMetrics {
    /// Moves the separation tracker's anchors (by storage index) to the storage order in which new
    /// index `k` holds old index `moves[k]`.
    pub fn move_anchors(&mut self, moves: &Moves) {
        self.tracker
            .renumber(moves.as_slice(), |anchors| moves.apply(anchors));
    }

    /// The separation tracker's full searches so far.
    pub fn full_searches(&self) -> u64 {
        self.tracker.full_searches()
    }

    /// The separation tracker's narrow searches so far.
    pub fn narrow_searches(&self) -> u64 {
        self.tracker.narrow_searches()
    }

    pub fn new() -> Self {
        Self {
            indices: Vec::new(),
            radii_m: Vec::new(),
            tracker: SeparationTracker::new(),
            workspace: FiveElementsWorkspace::new(),
        }
    }
}

impl Simulation {
    /// Runs every truth monitor on the segment that ended now and started at `t0_s`.
    pub(super) fn monitor(&mut self, t0_s: f64) -> Result<(), SimError> {
        if let Some((satellite, reason)) = self.monitors.diverged {
            return Err(SimError::Diverged {
                satellite,
                time_s: self.clock.time_s,
                reason,
            });
        }
        let (separation, collisions) = live_separation(
            &self.satellites.truth,
            &self.satellites.fleet.active,
            &self.satellites.fleet.radii_m,
            &mut self.monitors.live,
        );
        self.totals.min_separation_m = self.totals.min_separation_m.min(separation);
        self.totals.max_collisions = self.totals.max_collisions.max(collisions);
        self.totals.collision_pair_samples += collisions;
        if self.clock.time_s > t0_s && self.monitors.conjunctions.is_some() {
            let clock = std::time::Instant::now();
            self.monitor_conjunctions(t0_s)?;
            self.timings.conjunctions_s += clock.elapsed().as_secs_f64();
        }
        if self.clock.time_s > t0_s
            && !(self.config.threats.is_empty() && self.config.obstacles.is_empty())
        {
            let (t1_s, order) = (self.clock.time_s, &self.satellites.fleet.order);
            let (start, end) = (&self.monitors.truth_previous, &self.satellites.truth);
            let active = &self.satellites.fleet.active;
            // Each live satellite's path over the segment, by id (finite states, checked above, and
            // t1 > t0 make it valid).
            let segment_of = |id: usize| {
                let i = order.index_of(id);
                active[i].then(|| {
                    HermiteSegment::new(
                        t0_s,
                        t1_s,
                        start[i].position_m,
                        start[i].velocity_mps,
                        end[i].position_m,
                        end[i].velocity_mps,
                    )
                    .ok()
                })?
            };
            let (threats, obstacles) = (&self.config.threats, &self.config.obstacles);
            // The monitor was built for these threats and obstacles.
            let _ = self
                .monitors
                .approach
                .observe_segments(segment_of, threats, obstacles);
            if self.monitors.tracks_threats {
                let closest_m = (0..end.len())
                    .into_par_iter()
                    .with_min_len(CHUNK)
                    .filter_map(|id| {
                        let segment = segment_of(id)?;
                        threats
                            .iter()
                            .map(|threat| closest_approach_to_threat(&segment, threat).distance_m)
                            .reduce(f64::min)
                    })
                    .reduce_with(f64::min);
                if let Some(d) = closest_m {
                    let window = &mut self.monitors.threat_window_m;
                    *window = Some(window.map_or(d, |w| w.min(d)));
                }
            }
        }
        Ok(())
    }

    /// The origin's states now ([`OriginStates`]).
    pub(super) fn origin_states(&self) -> OriginStates {
        let data = self.state.as_slice();
        let n = self.state.n();
        let member = |k: usize| satellite_of(data, n, self.satellites.fleet.order.index_of(k));
        let reference = reference_of(data);
        let (origin, offset) = match (self.config.dynamics.is_inertial(), self.config.origin) {
            (true, Origin::Member(k)) => (member(k), None),
            (false, Origin::Member(k)) => (reference, Some(member(k))),
            (_, Origin::VirtualReference) => (reference, None),
        };
        OriginStates {
            origin_eme2000: CartesianState::new(origin.0, origin.1),
            member_offset_hill: offset.map_or_else(RelativeStateHill::default, |(p, v)| {
                RelativeStateHill {
                    position_m: p,
                    velocity_mps: v,
                }
            }),
        }
    }

    /// The conjunction monitor on the segment that ended now and started at `t0_s`; the Hill frame at
    /// an instant of the segment is placed by the origin's states interpolated between its ends (cubic
    /// Hermite), as the truth relative states were taken ([`super::sensing`]).
    fn monitor_conjunctions(&mut self, t0_s: f64) -> Result<(), SimError> {
        let t1_s = self.clock.time_s;
        let (start, end) = (self.monitors.origin_previous, self.origin_states());
        let inertial = self.config.dynamics.is_inertial();
        let properties = match self.config.origin {
            Origin::VirtualReference => self.config.reference_properties,
            Origin::Member(k) => self
                .satellites
                .fleet
                .properties(self.satellites.fleet.order.index_of(k)),
        };
        let config = &self.config;
        let to_eme2000 = |t_s: f64, hill: &RelativeStateHill| -> CartesianState {
            let origin = interpolate(t0_s, t1_s, &start.origin_eme2000, &end.origin_eme2000, t_s);
            let offset = interpolate(
                t0_s,
                t1_s,
                &CartesianState::new(
                    start.member_offset_hill.position_m,
                    start.member_offset_hill.velocity_mps,
                ),
                &CartesianState::new(
                    end.member_offset_hill.position_m,
                    end.member_offset_hill.velocity_mps,
                ),
                t_s,
            );
            let frame = if inertial {
                let accel = config.dynamics.reference_acceleration_m_s2(
                    &config.earth,
                    t_s,
                    &origin.position_m,
                    &origin.velocity_mps,
                    &properties,
                );
                LvlhFrame::from_reference_with_acceleration(&origin, &accel)
            } else {
                LvlhFrame::from_reference(&origin)
            };
            frame.from_hill(&RelativeStateHill {
                position_m: hill.position_m + offset.position_m,
                velocity_mps: hill.velocity_mps + offset.velocity_mps,
            })
        };
        let order = &self.satellites.fleet.order;
        let id_of = |i: usize| order.id_at(i);
        let live: Vec<usize> = (0..self.satellites.truth.len())
            .filter(|&i| self.satellites.fleet.active[i])
            .collect();
        let segment = SwarmSegment {
            t0_s,
            t1_s,
            start: &self.monitors.truth_previous,
            end: &self.satellites.truth,
            live: &live,
            id_of: &id_of,
            threats: &self.config.threats,
            obstacles: &self.config.obstacles,
        };
        if let Some(monitor) = self.monitors.conjunctions.as_mut() {
            monitor.observe_segment(&segment, &to_eme2000)?;
        }
        Ok(())
    }
}

/// Why the live satellite at storage index `i` of `fleet` (its position in the state `position_m`,
/// its truth relative state `rel`) stops the run, with its id: a non-finite state, a distance from the
/// origin beyond `config.max_distance_m`, or a position below the atmosphere's floor (inertial models
/// with drag, whose state positions are EME2000). Satellites that are not live are not checked.
pub(super) fn divergence_check<'a>(
    config: &'a SimulationConfig,
    fleet: &'a Fleet,
) -> impl Fn(usize, &Vector3<f64>, &RelativeStateHill) -> Option<(usize, Divergence)> + Sync + 'a {
    let bound = config.max_distance_m;
    // A squared distance up to this is within the bound with room for the square root's rounding.
    let surely_within_m2 = (bound * (1.0 - 1e-9)).powi(2);
    // Only an atmosphere has a floor: without one, the position in the state is not read.
    let forces = config.dynamics.forces().filter(|f| f.drag().is_some());
    // A squared distance from the Earth's centre beyond which a position is clear of the floor
    // (`None`: no floor).
    let clear_of_floor_m2 = forces.and_then(ForceSet::clear_of_floor_m2);
    move |i, position_m, rel| {
        if !fleet.active[i] {
            return None;
        }
        // The common case without a square root or a branch per component: six finite components
        // have a finite sum, and any NaN or infinite one makes the sum NaN or infinite.
        let (p, v) = (&rel.position_m, &rel.velocity_mps);
        let sum = p.x + p.y + p.z + v.x + v.y + v.z;
        if sum.is_finite()
            && p.norm_squared() <= surely_within_m2
            && clear_of_floor_m2.is_none_or(|clear_m2| position_m.norm_squared() > clear_m2)
        {
            return None;
        }
        let reason = {
            let finite = rel.position_m.iter().all(|v| v.is_finite())
                && rel.velocity_mps.iter().all(|v| v.is_finite());
            let distance_m = rel.position_m.norm();
            if !finite {
                Some(Divergence::NotFinite)
            } else if distance_m > bound {
                Some(Divergence::TooFar {
                    distance_m,
                    limit_m: bound,
                })
            } else {
                forces.and_then(|forces| {
                    forces.below_floor(position_m).map(|(altitude_m, floor_m)| {
                        Divergence::BelowAtmosphere {
                            altitude_m,
                            floor_m,
                        }
                    })
                })
            }
        };
        reason.map(|reason| (fleet.order.id_at(i), reason))
    }
}

/// The cubic Hermite interpolant at `t_s` of the states `a` at `t0_s` and `b` at `t1_s` (one frame, any:
/// positions and velocities of the same frame, m and m/s).
fn interpolate(
    t0_s: f64,
    t1_s: f64,
    a: &CartesianState,
    b: &CartesianState,
    t_s: f64,
) -> CartesianState {
    let segment = HermiteSegment {
        t0_s,
        t1_s,
        p0_hill_m: a.position_m,
        v0_hill_mps: a.velocity_mps,
        p1_hill_m: b.position_m,
        v1_hill_mps: b.velocity_mps,
    };
    CartesianState::new(segment.position_hill_m(t_s), segment.velocity_hill_mps(t_s))
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
    live.radii_m.clear();
    let every_one_live = active.iter().all(|&a| a);
    if !every_one_live {
        live.indices
            .extend((0..relative.len()).filter(|&i| active[i]));
        live.radii_m
            .extend(live.indices.iter().map(|&i| radii_m[i]));
    }
    let positions = LivePositions {
        relative,
        listed: (!every_one_live).then_some(live.indices.as_slice()),
    };
    let radii_m = if every_one_live {
        radii_m
    } else {
        &live.radii_m
    };
    match live.tracker.update_from(&positions, radii_m) {
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
    // In parallel: a root per satellite is a serial millisecond or more on a large swarm. (The
    // smallest id is unique, so the answer does not depend on the split.)
    let bad = applied_hill
        .par_iter()
        .enumerate()
        .with_min_len(CHUNK)
        .filter_map(|(i, u)| bad_command(fleet, i, u))
        .min_by_key(|(id, _)| *id);
    bad_command_error(bad, law, tick, time_s)
}

/// The id of the satellite at storage index `i` and its applied command `u` (Hill frame \[m/s^2\] or
/// \[m/s\]) if it is live and the command's norm is not finite.
#[inline]
pub(super) fn bad_command(
    fleet: &Fleet,
    i: usize,
    u: &Vector3<f64>,
) -> Option<(usize, Vector3<f64>)> {
    // The norm is the root of the squared norm, so one is finite exactly when the other is.
    (fleet.active[i] && !u.norm_squared().is_finite()).then(|| (fleet.order.id_at(i), *u))
}

/// The error stopping the run at tick `tick` (time `time_s` \[s\]) for the bad command of the smallest
/// id, `bad` ([`bad_command`]); `Ok` when there is none.
pub(super) fn bad_command_error(
    bad: Option<(usize, Vector3<f64>)>,
    law: &Law,
    tick: u64,
    time_s: f64,
) -> Result<(), SimError> {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The separation updates are counted as full or narrow searches (at least one per tick), and
    /// the first is a full one (no anchors yet): what `summary.json`'s `timing` reports.
    #[test]
    fn stage_timings_count_every_separation_search() {
        let text = "name = \"t\"\nseed = 1\nduration_s = 20.0\nrecord_interval_s = 20.0\n\
             [reference]\naltitude_m = 600e3\ninclination_deg = 97.8\n\
             [satellites]\ncount = 300\nmass_kg = 5.0\nradius_m = 0.1\n\
             initial = { distribution = \"sphere\", radius_m = 500.0 }\n\
             [law]\nname = \"none\"\n[control]\nmode = \"sampled\"\nperiod_s = 1.0\n";
        let scenario =
            crate::scenario::Scenario::from_toml(text, "t", std::path::Path::new(".")).unwrap();
        let mut sim = crate::run::build_simulation(&scenario).unwrap();
        sim.run(&mut crate::swarm::NullRecorder, &mut |_| {})
            .unwrap();
        let timings = sim.stage_timings();
        assert!(timings.separation_full_searches >= 1);
        assert!(timings.separation_full_searches + timings.separation_narrow_searches >= 20);
    }

    /// A non-finite applied command is reported for the smallest live id, whatever the chunks the
    /// parallel check splits the swarm into: bad commands in several chunks (one of them a removed
    /// satellite's, with a smaller id, which is skipped), on 1 and 4 threads.
    #[test]
    fn check_commands_names_the_smallest_live_bad_id() {
        let n = 5 * CHUNK + 7;
        let text = format!(
            "name = \"t\"\nseed = 1\nduration_s = 10.0\nrecord_interval_s = 10.0\n\
             [reference]\naltitude_m = 600e3\ninclination_deg = 97.8\n\
             [satellites]\ncount = {n}\nmass_kg = 5.0\nradius_m = 0.1\n\
             initial = {{ distribution = \"sphere\", radius_m = 5000.0 }}\n\
             [law]\nname = \"none\"\n"
        );
        let scenario =
            crate::scenario::Scenario::from_toml(&text, "t", std::path::Path::new(".")).unwrap();
        let mut sim = crate::run::build_simulation(&scenario).unwrap();
        let mut applied = vec![Vector3::zeros(); n];
        for (i, bad) in [
            (4 * CHUNK + 3, f64::NAN),
            (2 * CHUNK + 1, f64::INFINITY),
            (CHUNK - 2, f64::NAN),
        ] {
            applied[i] = Vector3::new(0.0, bad, 0.0);
        }
        sim.satellites.fleet.active[CHUNK - 2] = false;
        for threads in [1, 4] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let e =
                pool.install(|| check_commands(&applied, &sim.satellites.fleet, &sim.law, 3, 1.5));
            match e {
                Err(SimError::BadCommand {
                    satellite, tick: 3, ..
                }) => {
                    assert_eq!(satellite, 2 * CHUNK + 1, "{threads} threads")
                }
                other => panic!("{threads} threads: {other:?}"),
            }
            // The sampled tick checks in the pass that holds the commands: the same answer.
            sim.satellites.applied_hill.clone_from(&applied);
            let held = pool.install(|| sim.hold_commands(None));
            assert_eq!(held.map(|(id, _)| id), Some(2 * CHUNK + 1), "{threads}");
            assert_eq!(
                sim.satellites.held_control[4 * CHUNK + 3].y.to_bits(),
                f64::NAN.to_bits()
            );
        }
    }

    fn at_x(x: f64) -> RelativeStateHill {
        RelativeStateHill {
            position_m: Vector3::new(x, 0.0, 0.0),
            velocity_mps: Vector3::zeros(),
        }
    }

    /// The divergence check against its definition, on both sides of its quick test: a distance at
    /// the bound (1 km) or just inside passes, one ulp beyond is too far, any non-finite component
    /// (in the velocity too, and an infinite position whose squared norm is not a number to compare)
    /// is not finite, and a satellite that is not live is never reported.
    #[test]
    fn divergence_check_follows_its_definition() {
        let text = "name = \"t\"\nseed = 1\nduration_s = 10.0\nrecord_interval_s = 10.0\n\
                    [dynamics]\nmodel = \"hcw\"\nintegrator = \"rk4\"\nstep_s = 1.0\n\
                    max_distance_m = 1000.0\n\
                    [reference]\naltitude_m = 600e3\ninclination_deg = 97.8\n\
                    [satellites]\ncount = 3\nmass_kg = 5.0\nradius_m = 0.1\n\
                    initial = { distribution = \"sphere\", radius_m = 50.0 }\n\
                    [law]\nname = \"none\"\n";
        let scenario =
            crate::scenario::Scenario::from_toml(text, "t", std::path::Path::new(".")).unwrap();
        let mut sim = crate::run::build_simulation(&scenario).unwrap();
        let at = |p: [f64; 3], v: [f64; 3]| RelativeStateHill {
            position_m: Vector3::from(p),
            velocity_mps: Vector3::from(v),
        };
        let outcome = |sim: &Simulation, i: usize, rel: RelativeStateHill| {
            let check = divergence_check(&sim.config, &sim.satellites.fleet);
            check(i, &rel.position_m, &rel).map(|(_, why)| why)
        };
        let just_beyond = 1000.0_f64.next_up();
        for (rel, expected) in [
            (at([1000.0, 0.0, 0.0], [0.0; 3]), None),
            (at([0.0, 999.999_999_9, 0.0], [1.0; 3]), None),
            (at([600.0, 0.0, 800.0], [0.0; 3]), None),
            (
                at([0.0, 0.0, just_beyond], [0.0; 3]),
                Some(Divergence::TooFar {
                    distance_m: just_beyond,
                    limit_m: 1000.0,
                }),
            ),
            (
                at([1.0, 2.0, 3.0], [0.0, f64::NAN, 0.0]),
                Some(Divergence::NotFinite),
            ),
            (
                at([1.0, 2.0, 3.0], [0.0, 0.0, f64::NEG_INFINITY]),
                Some(Divergence::NotFinite),
            ),
            (
                at([f64::INFINITY, 0.0, 0.0], [0.0; 3]),
                Some(Divergence::NotFinite),
            ),
        ] {
            assert_eq!(outcome(&sim, 1, rel), expected, "{rel:?}");
        }
        let index = sim.satellites.fleet.order.index_of(2);
        sim.satellites.fleet.active[index] = false;
        assert_eq!(
            outcome(&sim, index, at([f64::NAN, 0.0, 0.0], [0.0; 3])),
            None
        );
    }

    /// With drag, the divergence check's quick test lets through only positions clear of the
    /// atmosphere's floor (100 km for the exponential layer): at 550 km nothing is reported, nor
    /// 50 m above the floor (inside the quick test's margin, decided by the exact height); 1 m below
    /// the floor is, with its spherical height; and on a geodetic height a position on the pole
    /// 1 m below the floor too (its spherical height, from WGS-84's equatorial radius, would be far
    /// below).
    #[test]
    fn divergence_check_with_drag_reports_the_floor() {
        for (altitude, radius_m) in [("spherical", 6_378_137.0), ("geodetic", 6_356_752.314_245)] {
            let text = format!(
                "name = \"t\"\nseed = 1\nduration_s = 10.0\nrecord_interval_s = 10.0\n\
                 [dynamics]\nmodel = \"j2\"\nintegrator = \"rk4\"\nstep_s = 1.0\n\
                 [dynamics.forces.drag]\natmosphere = \"exponential\"\n\
                 reference_density_kg_per_m3 = 6.967e-13\nreference_altitude_m = 500e3\n\
                 scale_height_m = 63822.0\naltitude = \"{altitude}\"\n\
                 [reference]\naltitude_m = 550e3\ninclination_deg = 53.0\n\
                 [satellites]\ncount = 2\nmass_kg = 100.0\nradius_m = 0.5\ndrag_area_m2 = 0.5\n\
                 drag_coefficient = 2.2\n\
                 initial = {{ distribution = \"sphere\", radius_m = 50.0 }}\n\
                 [law]\nname = \"none\"\n"
            );
            let scenario =
                crate::scenario::Scenario::from_toml(&text, "t", std::path::Path::new("."))
                    .unwrap();
            let sim = crate::run::build_simulation(&scenario).unwrap();
            let check = divergence_check(&sim.config, &sim.satellites.fleet);
            let near = at_x(10.0);
            let on_pole = |height_m: f64| Vector3::new(0.0, 0.0, radius_m + height_m);
            assert_eq!(check(0, &on_pole(550e3), &near), None, "{altitude}");
            assert_eq!(check(0, &on_pole(100e3 + 50.0), &near), None, "{altitude}");
            match check(0, &on_pole(100e3 - 1.0), &near) {
                Some((
                    _,
                    Divergence::BelowAtmosphere {
                        altitude_m,
                        floor_m,
                    },
                )) => {
                    assert_eq!(floor_m, 100e3);
                    assert!(
                        (altitude_m - (100e3 - 1.0)).abs() < 1e-3,
                        "{altitude}: {altitude_m}"
                    );
                }
                other => panic!("{altitude}: {other:?}"),
            }
        }
    }

    /// Four satellites on a line with radii of their own: the pairs (0, 1) and (1, 2) touch. With
    /// satellite 1 removed nothing touches; reading satellite 1's radius for satellite 2 (a radius taken
    /// by live rank instead of storage index) would make (0, 2) touch.
    #[test]
    fn live_separation_reads_each_live_satellites_own_radius() {
        let relative: Vec<_> = [0.0, 1.0, 1.5, 4.0].map(at_x).to_vec();
        let radii_m = [0.1, 2.0, 0.8, 1.0];
        let mut live = LiveMetrics::new();
        let all = live_separation(&relative, &[true; 4], &radii_m, &mut live);
        assert_eq!(all, (0.5, 2));
        let without_1 = [true, false, true, true];
        for metrics in [&mut live, &mut LiveMetrics::new()] {
            assert_eq!(
                live_separation(&relative, &without_1, &radii_m, metrics),
                (1.5, 0)
            );
        }
        // And back to every satellite live: the fleet's own radii again.
        assert_eq!(
            live_separation(&relative, &[true; 4], &radii_m, &mut live),
            (0.5, 2)
        );
    }
}
