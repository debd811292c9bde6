//! Conjunctions: every close approach of two satellites, or of a satellite and a threat or obstacle,
//! whose miss distance falls below a threshold (`[conjunctions] threshold_m`), located in time between
//! the integration steps and described as a conjunction data message needs it.
//!
//! | module | holds |
//! | --- | --- |
//! | `encounter` | what an encounter is (a local minimum of the pair's distance below the threshold, carried across segment boundaries) and the walk that finds them on one segment |
//! | `screen` | the Verlet list of candidate satellite pairs, built through the neighbour grid |
//!
//! [`ConjunctionMonitor::observe_segment`] takes each integration segment of the swarm (the truth at
//! both ends, Hill frame): the satellites' paths are the cubic Hermite interpolants of their end states
//! ([`HermiteSegment`]), so a pair's relative path is a cubic too, and its distance's local minima are
//! found exactly on it by the root isolation of [`crate::environment::closest_approach`]. Satellite
//! pairs are screened by the neighbour grid's candidates (`screen.rs`, never all pairs); satellite–threat and satellite–obstacle
//! pairs by a bound on each satellite's sweep (threats move on straight lines, obstacles are fixed, both
//! in the Hill frame). Threats and obstacles are points here (their centres): the miss distance is
//! centre to centre, as in a conjunction data message.
//!
//! Each encounter is stated at its time of closest approach (TCA) with both objects' inertial states
//! then (EME2000, through the caller's map from the Hill frame at that time), and the secondary's position
//! and velocity relative to the primary in the primary's RTN frame (R radial out, T along-track, N along
//! the orbit normal r × v): position `R (r₂ − r₁)`, velocity `R (v₂ − v₁)` with the inertial velocities
//! (the CCSDS CDM's `RELATIVE_POSITION_*` / `RELATIVE_VELOCITY_*`). The primary is the satellite with the
//! smaller id (or the satellite of a satellite–object pair).
//!
//! Determinism: pairs are visited in an order that depends only on the positions, each pair's numbers
//! are computed from its two satellites in id order, and a segment's encounters are sorted by (TCA,
//! primary, secondary): the same bytes on any thread count and any storage order.

mod encounter;
mod screen;

use std::collections::BTreeMap;

use nalgebra::Vector3;
use rayon::prelude::*;
use thiserror::Error;

use crate::environment::closest_approach::lower_bound_m;
use crate::environment::{HermiteSegment, Motion, Obstacle, Threat};
use crate::grid::NeighbourError;
use crate::orbit::{CartesianState, LvlhFrame, RelativeStateHill};
use encounter::{walk, Candidate};
pub(crate) use screen::Ends;
use screen::PairScreen;

/// The other object of an encounter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize)]
#[serde(tag = "kind", content = "index", rename_all = "kebab-case")]
pub enum Secondary {
    /// A satellite, by id.
    Satellite(usize),
    /// A threat, by its index in the scenario's `[[threats]]`.
    Threat(usize),
    /// An obstacle, by its index in the scenario's `[[obstacles]]`.
    Obstacle(usize),
}

impl Secondary {
    /// `satellite`, `threat` or `obstacle`.
    pub fn kind(&self) -> &'static str {
        match self {
            Secondary::Satellite(_) => "satellite",
            Secondary::Threat(_) => "threat",
            Secondary::Obstacle(_) => "obstacle",
        }
    }

    /// The satellite id, or the threat's or obstacle's index.
    pub fn index(&self) -> usize {
        match *self {
            Secondary::Satellite(k) | Secondary::Threat(k) | Secondary::Obstacle(k) => k,
        }
    }
}

/// One encounter: a local minimum of a pair's distance below the threshold (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Encounter {
    /// Time of closest approach, seconds since the scenario start \[s\].
    pub tca_s: f64,
    /// The primary satellite's id.
    pub primary: usize,
    /// The other object.
    pub secondary: Secondary,
    /// Distance between the two centres at TCA \[m\].
    pub miss_distance_m: f64,
    /// Norm of the inertial relative velocity at TCA, `|v₂ − v₁|` \[m/s\].
    pub relative_speed_mps: f64,
    /// Secondary's position relative to the primary at TCA, the primary's RTN axes \[m\].
    pub relative_position_rtn_m: [f64; 3],
    /// Secondary's inertial velocity relative to the primary at TCA, the primary's RTN axes \[m/s\].
    pub relative_velocity_rtn_mps: [f64; 3],
    /// The primary's state at TCA, EME2000 (`[x, y, z, vx, vy, vz]`, m and m/s).
    pub primary_eme2000: [f64; 6],
    /// The secondary's state at TCA, EME2000 (`[x, y, z, vx, vy, vz]`, m and m/s).
    pub secondary_eme2000: [f64; 6],
}

impl Encounter {
    /// The encounter of a located minimum, with both states mapped to EME2000 by `to_eme2000` (the
    /// Hill state at a time to the inertial state).
    fn new(
        primary: usize,
        secondary: Secondary,
        found: &Candidate,
        to_eme2000: &dyn Fn(f64, &RelativeStateHill) -> CartesianState,
    ) -> Self {
        let p = to_eme2000(found.tca_s, &found.primary_hill);
        let s = to_eme2000(found.tca_s, &found.secondary_hill);
        let rtn = LvlhFrame::from_reference(&p);
        let dr = rtn.vector_eci_to_hill(&(s.position_m - p.position_m));
        let dv_eci = s.velocity_mps - p.velocity_mps;
        let dv = rtn.vector_eci_to_hill(&dv_eci);
        Encounter {
            tca_s: found.tca_s,
            primary,
            secondary,
            miss_distance_m: found.distance_m,
            relative_speed_mps: dv_eci.norm(),
            relative_position_rtn_m: dr.into(),
            relative_velocity_rtn_mps: dv.into(),
            primary_eme2000: p.to_array(),
            secondary_eme2000: s.to_array(),
        }
    }
}

/// Why a conjunction monitor could not be built or a segment could not be screened.
#[derive(Clone, Debug, PartialEq, Error)]
#[non_exhaustive]
pub enum ConjunctionError {
    /// The threshold is negative or not finite.
    #[error("conjunction threshold {threshold_m} m is out of range (allowed: finite, >= 0 m)")]
    Threshold {
        /// The rejected threshold \[m\].
        threshold_m: f64,
    },
    /// The neighbour grid refused the positions (a non-finite position).
    #[error(transparent)]
    Grid(#[from] NeighbourError),
}

/// One segment of the swarm as the monitor takes it.
pub struct SwarmSegment<'a> {
    /// Start of the segment \[s\].
    pub t0_s: f64,
    /// End of the segment \[s\], later than `t0_s`.
    pub t1_s: f64,
    /// Every satellite's truth at `t0_s`, Hill frame of the LVLH origin, by storage index.
    pub start: &'a [RelativeStateHill],
    /// Every satellite's truth at `t1_s`, Hill frame, by storage index.
    pub end: &'a [RelativeStateHill],
    /// Storage indices of the live satellites, ascending.
    pub live: &'a [usize],
    /// Each storage index's satellite id.
    pub id_of: &'a (dyn Fn(usize) -> usize + Sync),
    /// The threats (Hill frame), in scenario order.
    pub threats: &'a [Threat],
    /// The obstacles (Hill frame), in scenario order.
    pub obstacles: &'a [Obstacle],
}

/// The run's conjunction monitor: the encounters found so far and those of the last segment.
#[derive(Clone, Debug)]
pub struct ConjunctionMonitor {
    threshold_m: f64,
    screen: PairScreen,
    /// Minima below the threshold open at the end of the last segment, by (primary id, secondary).
    open: BTreeMap<(usize, Secondary), Candidate>,
    encounters: Vec<Encounter>,
    /// Index in `encounters` of the first one found on the last segment.
    last_segment_from: usize,
}

impl ConjunctionMonitor {
    /// A monitor of the encounters closer than `threshold_m` \[m\] (finite, ≥ 0; 0 finds none).
    ///
    /// # Errors
    /// [`ConjunctionError::Threshold`] for a negative or non-finite threshold.
    pub fn new(threshold_m: f64) -> Result<Self, ConjunctionError> {
        if !(threshold_m.is_finite() && threshold_m >= 0.0) {
            return Err(ConjunctionError::Threshold { threshold_m });
        }
        Ok(Self {
            threshold_m,
            screen: PairScreen::default(),
            open: BTreeMap::new(),
            encounters: Vec::new(),
            last_segment_from: 0,
        })
    }

    /// The threshold \[m\].
    pub fn threshold_m(&self) -> f64 {
        self.threshold_m
    }

    /// Every encounter found so far, segment by segment, each segment's sorted by (TCA, primary,
    /// secondary).
    pub fn encounters(&self) -> &[Encounter] {
        &self.encounters
    }

    /// The encounters found on the last segment observed (a minimum at a segment boundary is found on
    /// the segment after it, when the distance has risen): what a condition "any encounter below the
    /// threshold" tests after each segment.
    pub fn last_segment(&self) -> &[Encounter] {
        &self.encounters[self.last_segment_from..]
    }

    /// Builds of the candidate-pair list so far (a measure of the screening's cost).
    pub fn screen_builds(&self) -> u64 {
        self.screen.builds()
    }

    /// The storage order of the satellites changed: the candidate list is built again on the next
    /// segment (its storage indices no longer hold).
    pub fn storage_order_changed(&mut self) {
        self.screen.invalidate();
    }

    /// Takes in one segment of the swarm; `to_eme2000` maps a Hill state at a time within it to the
    /// inertial state (called only for the encounters found).
    ///
    /// # Errors
    /// [`ConjunctionError::Grid`] for a non-finite position; nothing is recorded then.
    pub fn observe_segment(
        &mut self,
        segment: &SwarmSegment<'_>,
        to_eme2000: &dyn Fn(f64, &RelativeStateHill) -> CartesianState,
    ) -> Result<(), ConjunctionError> {
        self.last_segment_from = self.encounters.len();
        if self.threshold_m == 0.0 || segment.t1_s <= segment.t0_s {
            return Ok(());
        }
        let ends = Ends {
            t0_s: segment.t0_s,
            t1_s: segment.t1_s,
            start: segment.start,
            end: segment.end,
            live: segment.live,
        };
        let threshold_m = self.threshold_m;
        let previous = std::mem::take(&mut self.open);
        let mut found: Vec<Encounter> = Vec::new();
        let mut note = |key: (usize, Secondary),
                        primary: &HermiteSegment,
                        c: &[Vector3<f64>; 4],
                        open: &mut BTreeMap<(usize, Secondary), Candidate>| {
            let carried = previous.get(&key).copied();
            if carried.is_none() && lower_bound_m(c) >= threshold_m {
                return;
            }
            let w = walk(primary, c, carried, threshold_m);
            for minimum in &w.found {
                found.push(Encounter::new(key.0, key.1, minimum, to_eme2000));
            }
            if let Some(candidate) = w.open {
                open.insert(key, candidate);
            }
        };
        let mut open = BTreeMap::new();
        let active = |i: usize| segment.live.binary_search(&i).is_ok();
        for &(a, b) in self.screen.pairs(&ends, threshold_m)? {
            let (a, b) = (a as usize, b as usize);
            if !(active(a) && active(b)) {
                continue;
            }
            let (ia, ib) = ((segment.id_of)(a), (segment.id_of)(b));
            let ((p, pid), (s, sid)) = if ia < ib {
                ((a, ia), (b, ib))
            } else {
                ((b, ib), (a, ia))
            };
            let primary = ends.segment(p);
            let c = primary.cubic_to(&ends.segment(s));
            note((pid, Secondary::Satellite(sid)), &primary, &c, &mut open);
        }
        let objects: Vec<(Secondary, Motion)> = segment
            .threats
            .iter()
            .enumerate()
            .map(|(k, t)| (Secondary::Threat(k), *t.motion()))
            .chain(
                segment
                    .obstacles
                    .iter()
                    .enumerate()
                    .map(|(k, o)| (Secondary::Obstacle(k), *o.motion())),
            )
            .collect();
        if !objects.is_empty() {
            for (i, k) in near_objects(&ends, &objects, threshold_m) {
                let primary = ends.segment(i);
                let c = objects[k].1.relative_cubic(&primary).map(|v| -v);
                note(((segment.id_of)(i), objects[k].0), &primary, &c, &mut open);
            }
        }
        found.sort_by(|x, y| {
            x.tca_s
                .total_cmp(&y.tca_s)
                .then(x.primary.cmp(&y.primary))
                .then(x.secondary.cmp(&y.secondary))
        });
        self.encounters.extend(found);
        self.open = open;
        Ok(())
    }
}

/// The (storage index, object index) pairs whose distance may come below `threshold_m` on the segment:
/// the distance at the end minus the satellite's sweep and the object's travel over the segment.
fn near_objects(
    ends: &Ends<'_>,
    objects: &[(Secondary, Motion)],
    threshold_m: f64,
) -> Vec<(usize, usize)> {
    let (t0_s, t1_s) = (ends.t0_s, ends.t1_s);
    let objects: Vec<(Vector3<f64>, f64)> = objects
        .iter()
        .map(|(_, motion)| {
            (
                motion.position_hill_m(t1_s),
                motion.travel_bound_m(t0_s, t1_s),
            )
        })
        .collect();
    ends.live
        .par_iter()
        .with_min_len(4096)
        .fold(Vec::new, |mut near, &i| {
            let segment = ends.segment(i);
            let sweep_m = segment.sweep_bound_m();
            for (k, &(end_m, travel_m)) in objects.iter().enumerate() {
                let gap = segment.p1_hill_m - end_m;
                // A relative margin covers the rounding of the bound itself.
                let margin_m = 1e-9 * (gap.norm() + sweep_m + travel_m);
                if gap.norm() - sweep_m - travel_m - margin_m < threshold_m {
                    near.push((i, k));
                }
            }
            near
        })
        .collect::<Vec<Vec<_>>>()
        .concat()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_negative_or_non_finite_threshold_is_refused() {
        for bad in [-1.0, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                ConjunctionMonitor::new(bad),
                Err(ConjunctionError::Threshold { .. })
            ));
        }
        assert!(ConjunctionMonitor::new(0.0).is_ok());
    }
}
