//! The values the condition events test at a tick, from the truth: the minimum separation now, the
//! closest approach to a threat over the segments since the last tick, the law's reported formation
//! and declared outcomes (its results, read without changing the run), the uniformity L of the live
//! satellites, the count of satellites removed and the closest encounter the conjunction monitor found
//! since the last tick. Each is computed only when a pending condition
//! needs it, serially or by the exact reductions of the metrics: the same bits on any thread count.

use nalgebra::Vector3;

use crate::swarm::events::{ConditionTest, SHAPE_REACHED};
use crate::swarm::simulation::monitors::live_separation;
use crate::swarm::simulation::snapshots::five_elements_of;
use crate::swarm::simulation::Simulation;

impl Simulation {
    /// The value of every condition event now, in the timeline's order (`None` for an event that
    /// has fired for good, or whose value does not exist now). Takes the threat window (the closest
    /// approach over the segments since the last call), which starts again.
    pub(super) fn condition_values(&mut self) -> Vec<Option<f64>> {
        let window_m = self.monitors.threat_window_m.take();
        let tests: Vec<Option<ConditionTest>> = self
            .timeline
            .conditions
            .iter()
            .map(|c| c.action.as_ref().map(|_| c.condition.test.clone()))
            .collect();
        let needs = |f: fn(&ConditionTest) -> bool| tests.iter().flatten().any(f);
        let results = needs(|t| {
            matches!(
                t,
                ConditionTest::ShapeReached | ConditionTest::LawOutcome { .. }
            )
        })
        .then(|| self.with_truth_view(|law, view, placement| law.results(view, placement)));
        let separation_m =
            needs(|t| matches!(t, ConditionTest::MinSeparationBelow { .. })).then(|| {
                live_separation(
                    &self.satellites.truth,
                    &self.satellites.fleet.active,
                    &self.satellites.fleet.radii_m,
                    &mut self.monitors.live,
                )
                .0
            });
        let threat_m = needs(|t| matches!(t, ConditionTest::ThreatWithin { .. }))
            .then(|| self.threat_distance_now_m())
            .flatten()
            .map(|now| window_m.map_or(now, |w| w.min(now)));
        let uniformity = needs(|t| matches!(t, ConditionTest::UniformityWithin { .. }))
            .then(|| self.uniformity_l())
            .flatten();
        let conjunction_m = needs(|t| matches!(t, ConditionTest::Conjunction))
            .then(|| self.conjunction_window_m())
            .flatten();
        let lost = self.satellites.fleet.active.iter().filter(|a| !**a).count() as f64;
        let outcome = |name: &str| {
            let value = results.as_ref()?.get(name)?;
            value
                .as_f64()
                .or_else(|| value.as_bool().map(|b| if b { 1.0 } else { 0.0 }))
        };
        tests
            .iter()
            .map(|test| match test.as_ref()? {
                ConditionTest::MinSeparationBelow { .. } => separation_m,
                ConditionTest::ThreatWithin { .. } => threat_m,
                ConditionTest::ShapeReached => outcome(SHAPE_REACHED),
                ConditionTest::UniformityWithin { .. } => uniformity,
                ConditionTest::SatellitesLostAtLeast(_) => Some(lost),
                ConditionTest::Conjunction => conjunction_m,
                ConditionTest::LawOutcome { name, .. } => outcome(name),
            })
            .collect()
    }

    /// The smallest miss distance of the conjunction monitor's encounters found since the last call
    /// \[m\] (`None`: none, or no monitor); those are seen from then on.
    fn conjunction_window_m(&mut self) -> Option<f64> {
        let encounters = self.monitors.conjunctions.as_ref()?.encounters();
        let new = &encounters[self.monitors.conjunctions_seen.min(encounters.len())..];
        self.monitors.conjunctions_seen = encounters.len();
        new.iter().map(|e| e.miss_distance_m).reduce(f64::min)
    }

    /// The smallest distance between a live satellite and a threat now \[m\] (`None` without either).
    fn threat_distance_now_m(&self) -> Option<f64> {
        let t = self.clock.time_s;
        let threats: Vec<Vector3<f64>> = self
            .config
            .threats
            .iter()
            .map(|threat| threat.position_hill_m(t))
            .collect();
        self.satellites
            .truth
            .iter()
            .zip(&self.satellites.fleet.active)
            .filter(|(_, active)| **active)
            .flat_map(|(s, _)| threats.iter().map(move |p| (s.position_m - p).norm()))
            .reduce(f64::min)
    }

    /// The uniformity L of the live satellites' truth states now, by id (`None` with fewer than
    /// two).
    fn uniformity_l(&mut self) -> Option<f64> {
        let fleet = &self.satellites.fleet;
        let truth = &self.satellites.truth;
        let live: Vec<usize> = (0..fleet.active.len())
            .map(|id| fleet.order.index_of(id))
            .filter(|&i| fleet.active[i])
            .collect();
        five_elements_of(
            &live,
            |i| (truth[i].position_m, truth[i].velocity_mps),
            |i| fleet.radii_m[i],
            &mut self.monitors.live.workspace,
        )
        .map(|e| e.uniformity_l)
    }
}
