//! The periodic re-sort of the satellites' storage order (`crate::swarm::storage_order`): in sampled
//! control, every [`RESORT_PERIOD_TICKS`] ticks, by sensing-grid cell (a stable key: cell, then id), so
//! satellites near in space are near in memory and the per-tick passes (grid build, each satellite's
//! own data, its neighbours' states and broadcasts, its command) read memory nearly in sequence instead
//! of at random on a large swarm. Every per-satellite array moves with it, the law's states included.
//! Not while the running law senses no neighbours (`GuidanceLaw::senses_neighbours`): its passes are
//! per satellite, in any order, and nothing is gained for the cost of the re-sort.
//!
//! Nothing a run computes depends on the storage order: each satellite's computations read the same
//! inputs wherever it is stored, neighbours are visited in (cell, id) order whatever the storage order
//! ([`crate::grid::NeighbourGrid::build_ranked`]), and what is summed over satellites is summed by id.
//! So a run gives the same bits re-sorted at every tick or never (tested below, on every law).

use crate::swarm::simulation::{ControlTiming, Simulation};
use crate::swarm::storage_order::Moves;

/// Control ticks between two re-sorts of the storage order (sampled control only). Satellites drift
/// across cells slowly compared with a tick, and a re-sort costs a few passes over the swarm.
pub(super) const RESORT_PERIOD_TICKS: u64 = 32;

impl Simulation {
    /// Re-sorts the storage order by sensing-grid cell of the truth positions now (cell, then id) if
    /// this tick is due (sampled control only; continuous control keeps the id order), moving every
    /// per-satellite array with it. A running law that senses no neighbours reads nothing by cell, so
    /// the order is left as it is.
    pub(super) fn resort_if_due(&mut self, tick: u64) {
        if !matches!(self.config.control, ControlTiming::Sampled { .. })
            || !self.sensed.grids.neighbours
            || self.resort_period_ticks == 0
            || !tick.is_multiple_of(self.resort_period_ticks)
        {
            return;
        }
        let ranks = self.satellites.fleet.order.ranks();
        let range_m = self.config.sensing.range_m;
        let Some(cells) = self
            .sensed
            .grids
            .grid_over(&self.satellites.truth, range_m, ranks)
        else {
            return; // a non-finite position: the divergence check stops the run
        };
        let moves = Moves::new(cells.to_vec());
        if moves.is_identity() {
            return;
        }
        // Every array moves on its own, in parallel.
        let (state, satellites, integration, law) = (
            &mut self.state,
            &mut self.satellites,
            &mut self.integration,
            &mut self.law,
        );
        rayon::join(
            || {
                moves.apply_all(state.satellite_components_mut().collect());
                if let Some(guesses) = integration.step_guesses_s() {
                    moves.apply(guesses);
                }
            },
            || rayon::join(|| satellites.permute(&moves), || law.permute_states(&moves)),
        );
        // The sensing grid's neighbour list is by storage index: renumbered, it lasts.
        self.sensed
            .grids
            .grid
            .renumber_neighbour_list(moves.as_slice());
        // The separation tracker's anchors are by storage index: they move too.
        self.monitors.live.move_anchors(&moves);
        // The conjunction screen's candidate pairs are by storage index: it builds them again.
        if let Some(conjunctions) = &mut self.monitors.conjunctions {
            conjunctions.storage_order_changed();
        }
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use crate::run::build_simulation;
    use crate::scenario::Scenario;
    use crate::swarm::recorder::{Recorder, Snapshot};

    /// Every number a recorder receives, as bits, snapshot after snapshot.
    #[derive(Default, PartialEq, Debug)]
    struct Capture(Vec<u64>);

    impl Recorder for Capture {
        fn record(&mut self, s: &Snapshot<'_>) -> std::io::Result<()> {
            let mut put = |v: f64| self.0.push(v.to_bits());
            put(s.time_s);
            for (r, e) in s.relative_states.iter().zip(s.inertial_states) {
                r.position_m
                    .iter()
                    .chain(&r.velocity_mps)
                    .for_each(|v| put(*v));
                e.position_m
                    .iter()
                    .chain(&e.velocity_mps)
                    .for_each(|v| put(*v));
            }
            s.delta_v_axes_mps.iter().flatten().for_each(|v| put(*v));
            s.delta_v_mps.iter().for_each(|v| put(*v));
            s.law_metrics.iter().for_each(|v| put(*v));
            s.law_outputs.iter().for_each(|v| put(*v));
            put(s.min_separation_m);
            if let Some(f) = s.five_elements {
                f.r_o_m.iter().chain(&f.v_o_mps).for_each(|v| put(*v));
                [f.d_max_m, f.diameter_m, f.d_min_m, f.uniformity_l]
                    .into_iter()
                    .for_each(&mut put);
            }
            let env = s.environment;
            put(env.min_threat_distance_m.unwrap_or(-1.0));
            put(env.min_obstacle_clearance_m.unwrap_or(-1.0));
            self.0.extend(s.active.iter().map(|a| u64::from(*a)));
            self.0.extend([
                s.collisions as u64,
                env.threat_incursions,
                env.obstacle_incursions,
            ]);
            Ok(())
        }
    }

    /// Runs `text` to `until_s` re-sorting every `period` ticks (0: never): what the recorder got, the
    /// final state, law outputs, results, totals and what the public accessors give by id (Hill and ECI
    /// states, flags, the law's states when it is the pigeon law), and whether the storage order ended
    /// up shuffled.
    fn run(text: &str, until_s: f64, period: u64) -> (Capture, String, bool) {
        let (capture, summary, shuffled, _) = run_listed(text, until_s, period, true);
        (capture, summary, shuffled)
    }

    /// [`run`], with the sensing grid's neighbour list kept or not (`list`), and how many times the
    /// list was made.
    fn run_listed(
        text: &str,
        until_s: f64,
        period: u64,
        list: bool,
    ) -> (Capture, String, bool, u64) {
        let scenario = Scenario::from_toml(text, "t", Path::new(".")).unwrap();
        let mut sim = build_simulation(&scenario).unwrap();
        sim.resort_period_ticks = period;
        sim.sensed.grids.grid.keep_neighbour_list(list);
        let mut capture = Capture::default();
        sim.advance_to(until_s, &mut capture).unwrap();
        let shuffled = sim.satellites.fleet.order.ranks().is_some();
        let state: Vec<u64> = sim.state().as_slice().iter().map(|v| v.to_bits()).collect();
        let outputs: Vec<u64> = sim.law_outputs().iter().map(|v| v.to_bits()).collect();
        let results = sim.law_results();
        let summary = format!(
            "{state:?} {outputs:?} {results:?} {:?} {:?} {:?} {:?} {:?} {:?}",
            sim.totals(),
            (0..sim.satellite_count())
                .map(|i| sim.approach_monitor().satellite_threat_minimum(i))
                .collect::<Vec<_>>(),
            sim.states_hill(),
            sim.states_eci(),
            sim.active(),
            sim.law_states::<crate::guidance::pigeon::Pigeon>(),
        );
        let made = sim.stage_timings().neighbour_lists_made;
        (capture, summary, shuffled, made)
    }

    /// A law that senses no neighbours is never re-sorted, even when due at every tick (free drift in
    /// sampled control).
    #[test]
    fn a_law_without_neighbours_keeps_the_storage_order() {
        let text = include_str!("../../../scenarios/free-drift.toml").to_string()
            + "[control]\nmode = \"sampled\"\nperiod_s = 1.0\n";
        let (_, _, shuffled) = run(&text, 20.0, 1);
        assert!(!shuffled);
    }

    /// The storage order changes no bit of a run: re-sorted at every tick or never, every law gives the
    /// same records, final states, law outputs and results, totals and per-satellite threat minima, with
    /// navigation and process noise, events naming satellites (removal, link cuts and restores, a
    /// thruster failure), threats and obstacles, a member origin, an adaptive integrator, a
    /// centralised step and a law switch; and the re-sorted runs really are stored out of id order.
    #[test]
    fn runs_are_bitwise_the_same_whatever_the_storage_order() {
        let sphere = |law: &str, extra: &str, integrator: &str, dynamics: &str| {
            format!(
                "name = \"t\"\nseed = 5\nduration_s = 6.0\nrecord_interval_s = 0.5\n\
                 [dynamics]\nmodel = \"{dynamics}\"\nintegrator = \"{integrator}\"\nstep_s = 0.05\n\
                 process_noise_mps2 = 1e-5\n\
                 [reference]\naltitude_m = 600e3\ninclination_deg = 98.0\n{extra}\n\
                 [control]\nmode = \"sampled\"\nperiod_s = 0.05\n\
                 [satellites]\ncount = 400\nmass_kg = 100.0\nradius_m = 0.5\n\
                 allow_start_in_obstacle = true\n\
                 max_accel_mps2 = 0.05\n\
                 initial = {{ distribution = \"sphere\", radius_m = 300.0 }}\n\
                 [sensing]\nrange_m = 60.0\nposition_noise_m = 0.01\nvelocity_noise_mps = 1e-4\n\
                 [law]\n{law}\n\
                 [[obstacles]]\nname = \"o\"\ncenter_hill_m = [0.0, 0.0, 0.0]\nradius_m = 20.0\n\
                 [[threats]]\nname = \"k\"\ndanger_radius_m = 5.0\n\
                 aim_point_hill_m = [0.0, 100.0, 0.0]\ndirection_hill = [0.0, 0.0, -1.0]\n\
                 speed_mps = 200.0\narrival_time_s = 2.0\n\
                 [[events]]\ntime_s = 0.5\naction = \"remove-satellite\"\nsatellite = 17\n\
                 [[events]]\ntime_s = 0.6\naction = \"cut-links\"\nsatellites = [3, 250, 399]\n\
                 [[events]]\ntime_s = 0.9\naction = \"fail-thruster\"\nsatellite = 123\naxis = \"y\"\n\
                 [[events]]\ntime_s = 1.2\naction = \"restore-links\"\nsatellites = [250]\n\
                 [[events]]\ntime_s = 1.0\naction = \"threat-warning\"\nthreat = 0\nactive = true\n\
                 [output]\ntrajectory = false\n"
            )
        };
        let pigeon = "name = \"pigeon\"\nswitching = true\negalitarian_range_m = 50.0\n\
                      hierarchical_range_m = 60.0";
        let bifurcating = "name = \"bifurcating\"\nk_f_kg_per_m_s2 = 0.003\nk_c_kg_per_s2 = 0.25\n\
                           k_v_kg_per_s = 2000.0\navoidance_radius_m = 60.0\na = 1.0\nb = 1.0\n\
                           radius_m = 300.0\nmu_m = -5000.0";
        let cases = [
            sphere(pigeon, "", "rk4", "j2"),
            sphere(pigeon, "", "rk4", "j2")
                + &format!("[[events]]\ntime_s = 3.0\naction = \"switch-law\"\n[events.law]\n{bifurcating}\n"),
            sphere(
                bifurcating,
                "origin = \"member\"\norigin_member = 7",
                "rk4",
                "j2",
            ),
            sphere(bifurcating, "", "dop853", "hcw"),
            // (Sensing ranges below the swarms' sizes, so that they span several cells.)
            include_str!("../../../scenarios/hold.toml").to_string()
                + "[sensing]\nrange_m = 30.0\n",
            include_str!("../../../scenarios/ts-outage.toml")
                .replace("range_m = 20.0", "range_m = 1.0"),
            include_str!("../../../scenarios/es-e1.toml")
                .replace(
                    "mode = \"continuous\"",
                    "mode = \"sampled\"\nperiod_s = 0.02",
                )
                .replace("range_m = 1000.0", "range_m = 10.5"),
        ];
        for (k, text) in cases.iter().enumerate() {
            let until_s = [6.0, 6.0, 6.0, 6.0, 3700.0, 3700.0, 1600.0][k];
            let (never, never_summary, never_shuffled) = run(text, until_s, 0);
            let (every, every_summary, every_shuffled) = run(text, until_s, 1);
            assert!(!never_shuffled);
            assert!(
                every_shuffled,
                "case {k}: the re-sorted run stayed in id order"
            );
            assert!(never.0.len() > 100, "case {k}: too little recorded");
            assert!(never == every, "case {k}: records differ");
            assert_eq!(never_summary, every_summary, "case {k}");
        }
    }

    /// The sensing grid's neighbour list changes no bit of a run: a bifurcating swarm whose avoidance
    /// reach (12 m) is a fifth of its sensing range (60 m) (500 satellites in a 100 m ball: about one
    /// neighbour within the reach each), with navigation noise, a removal and
    /// link cuts hiding satellites, and a re-sort at every tick renumbering the list, gives the same
    /// records, states and totals with the list (made again as satellites move) as without it.
    #[test]
    fn runs_are_bitwise_the_same_with_or_without_the_neighbour_list() {
        let text = "name = \"t\"\nseed = 3\nduration_s = 40.0\nrecord_interval_s = 0.5\n\
                    [dynamics]\nmodel = \"j2\"\nintegrator = \"rk4\"\nstep_s = 0.1\n\
                    [reference]\naltitude_m = 600e3\ninclination_deg = 98.0\n\
                    [control]\nmode = \"sampled\"\nperiod_s = 0.1\n\
                    [satellites]\ncount = 500\nmass_kg = 100.0\nradius_m = 0.5\n\
                    max_accel_mps2 = 0.05\n\
                    initial = { distribution = \"sphere\", radius_m = 100.0 }\n\
                    [sensing]\nrange_m = 60.0\nposition_noise_m = 0.01\nvelocity_noise_mps = 1e-4\n\
                    [law]\nname = \"bifurcating\"\nk_f_kg_per_m_s2 = 0.003\nk_c_kg_per_s2 = 0.25\n\
                    k_v_kg_per_s = 20.0\navoidance_radius_m = 12.0\na = 1.0\nb = 1.0\n\
                    radius_m = 100.0\nmu_m = -100.0\n\
                    [[events]]\ntime_s = 0.5\naction = \"remove-satellite\"\nsatellite = 17\n\
                    [[events]]\ntime_s = 0.6\naction = \"cut-links\"\nsatellites = [3, 250, 399]\n\
                    [[events]]\ntime_s = 1.2\naction = \"restore-links\"\nsatellites = [250]\n\
                    [output]\ntrajectory = false\n";
        let (walked, walked_summary, _, none) = run_listed(text, 40.0, 1, false);
        let (listed, listed_summary, shuffled, made) = run_listed(text, 40.0, 1, true);
        assert!(shuffled);
        assert_eq!(none, 0);
        assert!(
            made >= 2,
            "the list was made {made} times: never made again"
        );
        assert!(walked.0.len() > 1000, "too little recorded");
        assert!(walked == listed, "records differ");
        assert_eq!(walked_summary, listed_summary);
    }
}
