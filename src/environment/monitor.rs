//! The per-run approach monitor: for every satellite and every threat the minimum centre distance and its
//! time, for every satellite and every obstacle the minimum surface clearance and its time, and the
//! number of incursions into threat danger spheres and obstacles, from the satellites' integration
//! segments (see [`crate::environment::closest_approach`]).
//!
//! Satellites are points here (their centres); a caller that wants hard-body contact can inflate the
//! obstacle radii and danger radii by the satellite's radius.

use super::closest_approach::{lower_bound_m, scan, Approach, Clearance, HermiteSegment};
use super::motion::Motion;
use super::obstacle::Obstacle;
use super::threat::Threat;
use super::EnvironmentError;
use rayon::prelude::*;

/// Smallest number of satellites per parallel work item of [`ApproachMonitor::observe_segments`].
const PARALLEL_MIN_SATELLITES: usize = 256;

/// A per-pair minimum located in the swarm: which satellite, which object (threat or obstacle index, in
/// the order of the slices given to [`ApproachMonitor::observe_segment`]) and the minimum itself.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct PairMinimum<T> {
    /// Satellite index.
    pub satellite: usize,
    /// Threat or obstacle index.
    pub object: usize,
    /// The minimum ([`Approach`] for threats, [`Clearance`] for obstacles).
    pub minimum: T,
}

/// Running state of one satellite–object pair.
#[derive(Clone, Copy, Debug)]
struct PairState {
    /// Smallest distance (threats: centre distance; obstacles: surface clearance) so far (m); +∞ before
    /// the first observation.
    min_m: f64,
    /// Time of `min_m` (s).
    time_s: f64,
    /// Whether the satellite was inside the danger sphere / obstacle at the end of its last segment.
    inside: bool,
    /// Number of entries so far.
    incursions: u64,
}

impl PairState {
    const NEW: PairState = PairState {
        min_m: f64::INFINITY,
        time_s: f64::NAN,
        inside: false,
        incursions: 0,
    };
}

/// Accumulates, over a run, the closest approaches of `N` satellites to `T` threats and `O` obstacles and
/// the incursions into them.
///
/// Storage (`N × (T + O)` pair states) is allocated by [`ApproachMonitor::new`];
/// [`ApproachMonitor::observe_segment`] does not allocate.
///
/// **Incursions.** A satellite is inside a threat's danger sphere when its centre distance is
/// `< danger_radius_m`, inside an obstacle when its surface clearance is `< 0` (touching does not count,
/// as for collisions). Each passage from outside to inside counts once, including entries and exits
/// within one segment (found exactly from the monotone pieces of the segment's squared distance). The
/// inside/outside state is carried from the end of a satellite's previous segment to the start of its
/// next, so a satellite that stays inside across segments counts once; a satellite already inside at the
/// start of its first observed segment counts one incursion.
///
/// The same objects must be passed, in the same order, to every call. A non-finite segment (a diverged
/// run) compares false everywhere and updates nothing.
#[derive(Clone, Debug)]
pub struct ApproachMonitor {
    satellites: usize,
    threats: usize,
    obstacles: usize,
    threat_pairs: Vec<PairState>,
    obstacle_pairs: Vec<PairState>,
}

impl ApproachMonitor {
    /// A monitor for `satellites` satellites, `threats` threats and `obstacles` obstacles, with no
    /// observation yet.
    pub fn new(satellites: usize, threats: usize, obstacles: usize) -> Self {
        Self {
            satellites,
            threats,
            obstacles,
            threat_pairs: vec![PairState::NEW; satellites * threats],
            obstacle_pairs: vec![PairState::NEW; satellites * obstacles],
        }
    }

    /// Number of satellites the monitor was built for.
    pub fn satellite_count(&self) -> usize {
        self.satellites
    }

    /// Number of threats the monitor was built for.
    pub fn threat_count(&self) -> usize {
        self.threats
    }

    /// Number of obstacles the monitor was built for.
    pub fn obstacle_count(&self) -> usize {
        self.obstacles
    }

    /// Takes in one integration segment of satellite `satellite` (Hill frame): updates its minimum
    /// distance to each threat and clearance to each obstacle, and counts its incursions.
    ///
    /// Segments of one satellite should be observed in time order (the incursion state is carried from
    /// one to the next); satellites are independent. A segment that provably cannot lower a pair's
    /// minimum nor reach its sphere is dismissed by a cheap lower bound (chord distance minus a bound on
    /// the cubic's deviation from its chord) without changing any result.
    ///
    /// # Errors
    /// [`EnvironmentError::SatelliteIndex`] for an index out of range, [`EnvironmentError::ObjectCount`]
    /// when `threats` or `obstacles` is not as long as the monitor was built for; nothing is updated then.
    pub fn observe_segment(
        &mut self,
        satellite: usize,
        segment: &HermiteSegment,
        threats: &[Threat],
        obstacles: &[Obstacle],
    ) -> Result<(), EnvironmentError> {
        if satellite >= self.satellites {
            return Err(EnvironmentError::SatelliteIndex {
                index: satellite,
                count: self.satellites,
            });
        }
        self.check_objects(threats, obstacles)?;
        let threat_states =
            &mut self.threat_pairs[satellite * self.threats..(satellite + 1) * self.threats];
        let obstacle_states =
            &mut self.obstacle_pairs[satellite * self.obstacles..(satellite + 1) * self.obstacles];
        observe_satellite(threat_states, obstacle_states, segment, threats, obstacles);
        Ok(())
    }

    /// [`Self::observe_segment`] for every satellite at once, in parallel: `segment_of(satellite)` is
    /// the satellite's segment (`None`: nothing observed for it this time). Satellites are independent,
    /// so the results are those of observing each one in turn, on any thread count.
    ///
    /// # Errors
    /// [`EnvironmentError::ObjectCount`] when `threats` or `obstacles` is not as long as the monitor
    /// was built for; nothing is updated then.
    pub fn observe_segments(
        &mut self,
        segment_of: impl Fn(usize) -> Option<HermiteSegment> + Sync,
        threats: &[Threat],
        obstacles: &[Obstacle],
    ) -> Result<(), EnvironmentError> {
        self.check_objects(threats, obstacles)?;
        let observe = |satellite: usize,
                       threat_states: &mut [PairState],
                       obstacle_states: &mut [PairState]| {
            if let Some(segment) = segment_of(satellite) {
                observe_satellite(threat_states, obstacle_states, &segment, threats, obstacles);
            }
        };
        let (t, o) = (self.threats, self.obstacles);
        let (threat_pairs, obstacle_pairs) = (&mut self.threat_pairs, &mut self.obstacle_pairs);
        match (t > 0, o > 0) {
            (true, true) => threat_pairs
                .par_chunks_mut(t)
                .zip(obstacle_pairs.par_chunks_mut(o))
                .enumerate()
                .with_min_len(PARALLEL_MIN_SATELLITES)
                .for_each(|(s, (a, b))| observe(s, a, b)),
            (true, false) => threat_pairs
                .par_chunks_mut(t)
                .enumerate()
                .with_min_len(PARALLEL_MIN_SATELLITES)
                .for_each(|(s, a)| observe(s, a, &mut [])),
            (false, true) => obstacle_pairs
                .par_chunks_mut(o)
                .enumerate()
                .with_min_len(PARALLEL_MIN_SATELLITES)
                .for_each(|(s, b)| observe(s, &mut [], b)),
            (false, false) => {}
        }
        Ok(())
    }

    /// [`EnvironmentError::ObjectCount`] unless `threats` and `obstacles` are as many as the monitor
    /// was built for.
    fn check_objects(
        &self,
        threats: &[Threat],
        obstacles: &[Obstacle],
    ) -> Result<(), EnvironmentError> {
        for (what, expected, got) in [
            ("threats", self.threats, threats.len()),
            ("obstacles", self.obstacles, obstacles.len()),
        ] {
            if got != expected {
                return Err(EnvironmentError::ObjectCount {
                    what,
                    expected,
                    got,
                });
            }
        }
        Ok(())
    }

    /// Closest approach of satellite `satellite` to threat `threat` so far; `None` before the pair's
    /// first observation.
    ///
    /// # Panics
    /// If an index is out of range.
    pub fn threat_approach(&self, satellite: usize, threat: usize) -> Option<Approach> {
        assert!(satellite < self.satellites && threat < self.threats);
        let st = &self.threat_pairs[satellite * self.threats + threat];
        st.min_m.is_finite().then_some(Approach {
            time_s: st.time_s,
            distance_m: st.min_m,
        })
    }

    /// Smallest clearance of satellite `satellite` to obstacle `obstacle` so far (negative: it has been
    /// inside); `None` before the pair's first observation.
    ///
    /// # Panics
    /// If an index is out of range.
    pub fn obstacle_clearance(&self, satellite: usize, obstacle: usize) -> Option<Clearance> {
        assert!(satellite < self.satellites && obstacle < self.obstacles);
        let st = &self.obstacle_pairs[satellite * self.obstacles + obstacle];
        st.min_m.is_finite().then_some(Clearance {
            time_s: st.time_s,
            clearance_m: st.min_m,
        })
    }

    /// Number of entries of satellite `satellite` into the danger sphere of threat `threat`.
    ///
    /// # Panics
    /// If an index is out of range.
    pub fn threat_incursions(&self, satellite: usize, threat: usize) -> u64 {
        assert!(satellite < self.satellites && threat < self.threats);
        self.threat_pairs[satellite * self.threats + threat].incursions
    }

    /// Number of entries of satellite `satellite` into obstacle `obstacle`.
    ///
    /// # Panics
    /// If an index is out of range.
    pub fn obstacle_incursions(&self, satellite: usize, obstacle: usize) -> u64 {
        assert!(satellite < self.satellites && obstacle < self.obstacles);
        self.obstacle_pairs[satellite * self.obstacles + obstacle].incursions
    }

    /// Closest approach of satellite `satellite` to any threat so far (the lowest threat index among
    /// ties); `None` without threats or observations.
    ///
    /// # Panics
    /// If `satellite` is out of range.
    pub fn satellite_threat_minimum(&self, satellite: usize) -> Option<PairMinimum<Approach>> {
        assert!(satellite < self.satellites);
        (0..self.threats)
            .filter_map(|k| {
                self.threat_approach(satellite, k).map(|a| PairMinimum {
                    satellite,
                    object: k,
                    minimum: a,
                })
            })
            .reduce(|best, x| {
                if x.minimum.distance_m < best.minimum.distance_m {
                    x
                } else {
                    best
                }
            })
    }

    /// Smallest clearance of satellite `satellite` to any obstacle so far (the lowest obstacle index
    /// among ties); `None` without obstacles or observations.
    ///
    /// # Panics
    /// If `satellite` is out of range.
    pub fn satellite_obstacle_minimum(&self, satellite: usize) -> Option<PairMinimum<Clearance>> {
        assert!(satellite < self.satellites);
        (0..self.obstacles)
            .filter_map(|k| {
                self.obstacle_clearance(satellite, k).map(|c| PairMinimum {
                    satellite,
                    object: k,
                    minimum: c,
                })
            })
            .reduce(|best, x| {
                if x.minimum.clearance_m < best.minimum.clearance_m {
                    x
                } else {
                    best
                }
            })
    }

    /// Closest approach of any satellite to any threat so far (lowest satellite, then threat index among
    /// ties); `None` without threats or observations.
    pub fn swarm_threat_minimum(&self) -> Option<PairMinimum<Approach>> {
        (0..self.satellites)
            .filter_map(|i| self.satellite_threat_minimum(i))
            .reduce(|best, x| {
                if x.minimum.distance_m < best.minimum.distance_m {
                    x
                } else {
                    best
                }
            })
    }

    /// Smallest clearance of any satellite to any obstacle so far (lowest satellite, then obstacle index
    /// among ties); `None` without obstacles or observations.
    pub fn swarm_obstacle_minimum(&self) -> Option<PairMinimum<Clearance>> {
        (0..self.satellites)
            .filter_map(|i| self.satellite_obstacle_minimum(i))
            .reduce(|best, x| {
                if x.minimum.clearance_m < best.minimum.clearance_m {
                    x
                } else {
                    best
                }
            })
    }

    /// Entries of satellite `satellite` into all threat danger spheres.
    ///
    /// # Panics
    /// If `satellite` is out of range.
    pub fn satellite_threat_incursions(&self, satellite: usize) -> u64 {
        assert!(satellite < self.satellites);
        self.threat_pairs[satellite * self.threats..(satellite + 1) * self.threats]
            .iter()
            .map(|st| st.incursions)
            .sum()
    }

    /// Entries of satellite `satellite` into all obstacles.
    ///
    /// # Panics
    /// If `satellite` is out of range.
    pub fn satellite_obstacle_incursions(&self, satellite: usize) -> u64 {
        assert!(satellite < self.satellites);
        self.obstacle_pairs[satellite * self.obstacles..(satellite + 1) * self.obstacles]
            .iter()
            .map(|st| st.incursions)
            .sum()
    }

    /// Entries of all satellites into all threat danger spheres.
    pub fn total_threat_incursions(&self) -> u64 {
        self.threat_pairs.iter().map(|st| st.incursions).sum()
    }

    /// Entries of all satellites into all obstacles.
    pub fn total_obstacle_incursions(&self) -> u64 {
        self.obstacle_pairs.iter().map(|st| st.incursions).sum()
    }
}

/// Updates one satellite's pairs with its segment: `threat_states` and `obstacle_states` in the order of
/// `threats` and `obstacles`.
fn observe_satellite(
    threat_states: &mut [PairState],
    obstacle_states: &mut [PairState],
    segment: &HermiteSegment,
    threats: &[Threat],
    obstacles: &[Obstacle],
) {
    for (state, threat) in threat_states.iter_mut().zip(threats) {
        observe_pair(
            state,
            segment,
            threat.motion(),
            threat.danger_radius_m(),
            0.0,
        );
    }
    for (state, obstacle) in obstacle_states.iter_mut().zip(obstacles) {
        let radius_m = obstacle.radius_m();
        observe_pair(state, segment, obstacle.motion(), radius_m, radius_m);
    }
}

/// Updates one pair with one segment. The pair's quantity is `distance − offset_m` (threats: offset 0,
/// the centre distance; obstacles: offset = radius, the surface clearance); inside means
/// `distance < radius_m`.
fn observe_pair(
    state: &mut PairState,
    segment: &HermiteSegment,
    motion: &Motion,
    radius_m: f64,
    offset_m: f64,
) {
    let c = motion.relative_cubic(segment);
    let bound_m = lower_bound_m(&c);
    // Every distance on the segment is ≥ bound_m: the minimum cannot drop strictly below the current
    // one, and the satellite stays outside (inside is a strict `<`).
    if bound_m - offset_m >= state.min_m && bound_m >= radius_m {
        state.inside = false;
        return;
    }
    let sc = scan(&c);
    let (s, distance_m) = sc.minimum(&c);
    let value_m = distance_m - offset_m;
    if value_m < state.min_m {
        state.min_m = value_m;
        state.time_s = segment.time_at(s);
    }
    // |d|² is monotone between break points: one entry per outside → inside step.
    let mut inside = state.inside;
    for &d in sc.distances_m() {
        let now_inside = d < radius_m;
        if now_inside && !inside {
            state.incursions += 1;
        }
        inside = now_inside;
    }
    state.inside = inside;
}
