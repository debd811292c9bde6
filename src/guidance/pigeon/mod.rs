//! The `pigeon` law: distributed formation flight with pigeon-flock interaction-pattern switching, after
//! H. Qiu, Q. Zhou, C. Sun, X. Wang, Y. Feng, "Distributed Satellite Formation Based on Swarm Intelligence
//! of Pigeon Flocks" (IEEE conference paper). Method page: `docs/methods/pigeon.md`.
//!
//! The satellite's motion is split (the paper's Algorithm 1):
//!
//! * **Pigeon plane** y–z: the "pigeon position" is x_i = (z_i, y_i) — **z first** — with velocity
//!   v_i = (ż_i, ẏ_i), and every distance of the law is a 2-D distance in this plane. The desired
//!   acceleration u_i \[m/s²\] is the flock law (Eq. 14): formation term −K^F Σ_{N_i^1} ∇V^F over the
//!   hysteretic egalitarian set (whatever the pattern), obstacle term −K^O Σ ∇V^O over the obstacles the
//!   view reports, and for dominant satellites (S_d) the target term −K^T ∇V^T; velocity alignment
//!   −K^V Σ_{N_i} w_ij v_ij over the pattern's set with the pattern's weights ([`potentials`]).
//! * **Radial axis** x: held at zero by the PD ẍ_des = −K^P x − K^D ẋ.
//!
//! The CW inverse turns (ẍ_des, ÿ = u_i², z̈ = u_i¹) into thrust, which is clipped per axis at the
//! satellite's own actuator limit; the saturated thrust f̄ (Hill, m/s²) is the command ([`thrust`]).
//!
//! **Pattern switching** ([`switching`]), once per tick in `update_state`: the egalitarian set N_i^1 with
//! hysteresis (kept in the per-satellite [`PigeonState`]), the hierarchical set N_i^2, the local order
//! parameter V_a,i over the previous tick's N_i (N_i^1 at the first tick), p_h = 1/(1 + α e^(−β(1 − V_a,i)))
//! and one uniform draw from the satellite's own stream for the tick ([`LawContext::random`]), so runs
//! are bitwise identical on any thread count.
//!
//! **Assumptions**: the scenario's sensing range must reach R_c^2 (refused otherwise when the law
//! starts); the engine's neighbour query is 3-D, so a pair counts as sensed only within the sensing
//! range in 3-D (identical to the 2-D rule once the radial PD has brought x to zero). Engine obstacles
//! are spheres; the law uses the 2-D distance to the centre and the sphere's radius as r^O.

pub(crate) mod connectivity;
mod links;
pub mod parameters;
pub mod potentials;
pub mod switching;
pub mod thrust;

use crate::invalid::Invalid;
use nalgebra::{Vector2, Vector3};
use serde::Serialize;

use crate::swarm::{
    Better, Broadcast, Diagnostics, GuidanceLaw, Headline, LawContext, LawError, Reports,
    SatelliteView, SwarmFacts, SwarmView,
};

pub use parameters::PigeonParameters;
pub use potentials::{FormationPotential, ObstaclePotential};
pub use thrust::{cw_thrust, CwThrust};

use links::{contains, LinkIds};
use parameters::invalid;

/// Per-satellite output columns.
const OUTPUT_NAMES: &[&str] = &["pigeon_pattern"];

/// Metric columns.
const METRIC_NAMES: &[&str] = &[
    "pigeon_order_parameter",
    "pigeon_mean_distance_m",
    "pigeon_mean_target_distance_m",
    "pigeon_hierarchical",
    "pigeon_switches",
    "pigeon_barrier_violations",
];

/// The pigeon-plane vector (z, y) of a Hill vector (x, y, z).
pub fn pigeon_plane(hill: &Vector3<f64>) -> Vector2<f64> {
    Vector2::new(hill.z, hill.y)
}

/// One satellite's law state, updated once per tick.
///
/// The two neighbour sets are kept in one list of 32-bit ids (satellite ids, which the sensing grid
/// keeps below 2³²): N_i^1 sorted, then — in the hierarchical pattern only — the rest of N_i^2
/// sorted. N_i^1 ⊆ N_i^2 always (a link needs the distance ≤ R_c^1 ≤ R_c^2), so N_i is the whole list
/// in the hierarchical pattern and N_i^1 in the egalitarian one. Up to 13 ids are held in the state
/// itself (128 bytes in all), a longer list on the heap.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PigeonState {
    /// Number of updates so far (0 before the first tick).
    pub updates: u64,
    /// N_i^1 (sorted), then N_i^2 \ N_i^1 (sorted) when `hierarchical`.
    links: LinkIds,
    /// Length of N_i^1 at the front of `links`.
    egalitarian_len: u32,
    /// This tick's pattern: hierarchical (`true`) or egalitarian.
    pub hierarchical: bool,
    /// V_a,i used for this tick's draw (dimensionless, in \[0, 1\]).
    pub local_order_parameter: f64,
    /// p_h of this tick's draw.
    pub hierarchical_probability: f64,
    /// Pattern switches of this satellite so far (a change of pattern from one tick to the next).
    pub switches: u64,
    /// Samples with a sensed neighbour of higher id at 2-D distance ≤ R_L^3 (each pair counted once per
    /// tick, by its lower-id satellite).
    pub separation_violations: u64,
    /// Samples with an obstacle at 2-D centre distance ≤ r^O + R_L^4.
    pub clearance_violations: u64,
}

impl PigeonState {
    /// A state in the given pattern with the egalitarian set N_i^1 `egalitarian` and, in the
    /// hierarchical pattern, the hierarchical set N_i^2 `hierarchical_set` (ignored otherwise; its
    /// members in N_i^1 are not repeated); every other field as before the first tick. Ids need not be
    /// sorted; an id of 2³² or more (never a satellite the grid reports) is dropped.
    pub fn with_links(egalitarian: &[usize], hierarchical_set: Option<&[usize]>) -> Self {
        let to_ids = |ids: &[usize]| -> Vec<u32> {
            let mut ids: Vec<u32> = ids.iter().filter_map(|&j| u32::try_from(j).ok()).collect();
            ids.sort_unstable();
            ids.dedup();
            ids
        };
        let mut ids = to_ids(egalitarian);
        let egalitarian_len = ids.len() as u32;
        if let Some(set) = hierarchical_set {
            let rest: Vec<u32> = to_ids(set)
                .into_iter()
                .filter(|j| ids[..egalitarian_len as usize].binary_search(j).is_err())
                .collect();
            ids.extend(rest);
        }
        let mut links = LinkIds::default();
        links.assign(&ids);
        Self {
            links,
            egalitarian_len,
            hierarchical: hierarchical_set.is_some(),
            ..Self::default()
        }
    }

    /// N_i^1: the egalitarian neighbours (hysteretic), sorted ids.
    pub fn egalitarian(&self) -> &[u32] {
        &self.links.as_slice()[..self.egalitarian_len as usize]
    }

    /// N_i^2 \ N_i^1, sorted ids: the rest of this tick's hierarchical set (empty in the egalitarian
    /// pattern).
    fn hierarchical_rest(&self) -> &[u32] {
        if self.hierarchical {
            &self.links.as_slice()[self.egalitarian_len as usize..]
        } else {
            &[]
        }
    }

    /// Whether satellite `id` is in N_i^1.
    pub fn is_egalitarian(&self, id: usize) -> bool {
        contains(self.egalitarian(), id)
    }

    /// Whether satellite `id` is in N_i, the neighbours of this tick's pattern (the next tick's V_a,i
    /// is taken over them).
    pub fn is_neighbour(&self, id: usize) -> bool {
        self.is_egalitarian(id) || contains(self.hierarchical_rest(), id)
    }

    /// N_i: the neighbours of this tick's pattern (N_i^1 or N_i^2), sorted ids.
    pub fn neighbours(&self) -> Vec<u32> {
        let mut all = [self.egalitarian(), self.hierarchical_rest()].concat();
        all.sort_unstable();
        all
    }
}

thread_local! {
    /// Per-thread buffers of the update: N_i^1 and N_i^2 \ N_i^1 as the walk finds them, until the
    /// pattern is drawn (so the update never allocates once the buffers have grown).
    static UPDATE_LINKS: std::cell::RefCell<(Vec<u32>, Vec<u32>)> =
        const { std::cell::RefCell::new((Vec::new(), Vec::new())) };
}

/// The `pigeon` law.
#[derive(Clone, Debug)]
pub struct Pigeon {
    parameters: PigeonParameters,
    /// S_d, sorted.
    dominant: Vec<usize>,
    started: Option<SwarmFacts>,
    /// (time \[s\], mean inter-satellite distance \[m\]) at every recording since the law started, for
    /// the stabilisation time of the summary.
    mean_distance_history: Vec<(f64, f64)>,
    /// First recording time at which the mean target distance was inside the target zone \[s\].
    target_zone_reached_s: Option<f64>,
}

impl Pigeon {
    /// Builds the law, checking its parameters.
    pub fn new(parameters: PigeonParameters) -> Result<Self, LawError> {
        parameters.check()?;
        let mut dominant = parameters.dominant.clone();
        dominant.sort_unstable();
        Ok(Self {
            parameters,
            dominant,
            started: None,
            mean_distance_history: Vec::new(),
            target_zone_reached_s: None,
        })
    }

    /// The stabilisation time of the mean inter-satellite distance \[s\]: the first recording after which
    /// it stays within ±2 % of its last recorded value (the paper's "tends to be stable"; resolution: the
    /// recording interval). `None` before two recordings.
    pub fn stabilisation_time_s(&self) -> Option<f64> {
        let (_, last) = *self.mean_distance_history.last()?;
        if self.mean_distance_history.len() < 2 || !last.is_finite() {
            return None;
        }
        let band = 0.02 * last.abs();
        let first_inside_for_good = self
            .mean_distance_history
            .iter()
            .rposition(|(_, d)| (d - last).abs() > band || d.is_nan())
            .map_or(0, |k| k + 1);
        Some(self.mean_distance_history[first_inside_for_good].0)
    }

    /// The current parameters.
    pub fn parameters(&self) -> &PigeonParameters {
        &self.parameters
    }

    /// Whether satellite `id` is dominant (knows the target).
    pub fn is_dominant(&self, id: usize) -> bool {
        self.dominant.binary_search(&id).is_ok()
    }

    /// The formation potential of the parameters.
    pub fn formation_potential(&self) -> FormationPotential {
        let p = &self.parameters;
        FormationPotential {
            min_separation_m: p.min_separation_m,
            desired_separation_m: p.desired_separation_m,
            link_range_m: p.egalitarian_range_m,
        }
    }

    /// The obstacle potential of a circle of radius `radius_m` \[m\].
    pub fn obstacle_potential(&self, radius_m: f64) -> ObstaclePotential {
        ObstaclePotential {
            radius_m,
            min_clearance_m: self.parameters.min_clearance_m,
            detection_m: self.parameters.obstacle_detection_m,
        }
    }

    fn check_against(p: &PigeonParameters, started: &SwarmFacts) -> Result<(), LawError> {
        if p.hierarchical_range_m > started.sensing_range_m {
            return Err(invalid(Invalid::keys(
                "hierarchical_range_m",
                format!(
                    "hierarchical_range_m = {} m exceeds the sensing range {} m: the hierarchical \
                 pattern links every satellite within R_c^2 (allowed: hierarchical_range_m <= \
                 sensing.range_m)",
                    p.hierarchical_range_m, started.sensing_range_m
                ),
                "",
            )));
        }
        if let Some(&bad) = p.dominant.iter().find(|&&d| d >= started.count) {
            return Err(invalid(Invalid::keys("dominant", format!(
                "dominant lists satellite {bad} but the swarm has {} satellites (allowed: 0 ..= {})",
                started.count,
                started.count.saturating_sub(1)
            ), "")));
        }
        Ok(())
    }

    /// The desired pigeon-plane acceleration u_i = (z̈, ÿ) of Eq. 14 \[m/s²\] for satellite `satellite`
    /// in state `state` (before the CW inverse and saturation).
    pub fn flock_acceleration(
        &self,
        satellite: &SatelliteView<'_>,
        state: &PigeonState,
    ) -> Vector2<f64> {
        let p = &self.parameters;
        let own = satellite.own_state();
        let x_i = pigeon_plane(&own.position_m);
        let v_i = pigeon_plane(&own.velocity_mps);
        let dominant = self.is_dominant(satellite.id());
        let formation = self.formation_potential();
        let (egalitarian_set, rest) = (state.egalitarian(), state.hierarchical_rest());
        let mut u = Vector2::zeros();
        satellite.for_each_neighbour(|nb| {
            let x_ij = -pigeon_plane(&nb.offset_m);
            let v_ij = v_i - pigeon_plane(&nb.state.velocity_mps);
            let egalitarian = contains(egalitarian_set, nb.id);
            if egalitarian {
                let r = x_ij.norm();
                if r > 0.0 {
                    u -= p.k_formation_per_s2 * formation.slope_m(r) * x_ij / r;
                }
            }
            if egalitarian || contains(rest, nb.id) {
                let leader = dominant || self.is_dominant(nb.id);
                let w = if state.hierarchical && leader {
                    p.leader_weight
                } else {
                    1.0
                };
                u -= p.k_alignment_per_s * w * v_ij;
            }
        });
        satellite.for_each_obstacle(|o| {
            let d = x_i - pigeon_plane(&o.center_hill_m);
            let r = d.norm();
            if r > 0.0 {
                u -= p.k_obstacle_per_s2 * self.obstacle_potential(o.radius_m).slope_m(r) * d / r;
            }
        });
        if dominant {
            let d = x_i - pigeon_plane(&Vector3::from(p.target_hill_m));
            let r = d.norm();
            if r > 0.0 {
                u -= p.k_target_per_m_s2 * potentials::target_slope_m2(r, p.target_zone_m) * d / r;
            }
            u -= p.target_velocity_damping_per_s * v_i;
        }
        u
    }

    /// The whole Step 3–5 of one satellite: flock acceleration, radial PD, CW inverse, saturation at
    /// the actuator limit of `context` and back-substitution.
    pub fn thrust(
        &self,
        satellite: &SatelliteView<'_>,
        state: &PigeonState,
        context: &LawContext,
    ) -> CwThrust {
        let p = &self.parameters;
        let own = satellite.own_state();
        let u = self.flock_acceleration(satellite, state);
        let radial =
            -p.k_radial_p_per_s2 * own.position_m.x - p.k_radial_d_per_s * own.velocity_mps.x;
        cw_thrust(
            &own.position_m,
            &own.velocity_mps,
            &u,
            radial,
            satellite.shared().mean_motion_rad_s,
            context.max_accel_m_s2(),
        )
    }

    /// Global order parameter V_a (over live satellites), mean pair distance and mean target distance in
    /// the pigeon plane \[m\] of a swarm. O(N²) in the pair distance.
    pub fn swarm_measures(&self, swarm: &SwarmView<'_>) -> (f64, f64, f64) {
        let live: Vec<usize> = (0..swarm.len()).filter(|i| swarm.active[*i]).collect();
        let positions: Vec<Vector2<f64>> = live
            .iter()
            .map(|i| pigeon_plane(&swarm.relative_states[*i].position_m))
            .collect();
        let velocities: Vec<Vector2<f64>> = live
            .iter()
            .map(|i| pigeon_plane(&swarm.relative_states[*i].velocity_mps))
            .collect();
        let order = switching::order_parameter(&velocities);
        let (mut sum, mut pairs) = (0.0, 0usize);
        for (a, pa) in positions.iter().enumerate() {
            for pb in &positions[a + 1..] {
                sum += (pa - pb).norm();
                pairs += 1;
            }
        }
        let mean_distance = if pairs > 0 {
            sum / pairs as f64
        } else {
            f64::NAN
        };
        let target = pigeon_plane(&Vector3::from(self.parameters.target_hill_m));
        let mean_target = if positions.is_empty() {
            f64::NAN
        } else {
            positions.iter().map(|x| (x - target).norm()).sum::<f64>() / positions.len() as f64
        };
        (order, mean_distance, mean_target)
    }
}

impl GuidanceLaw for Pigeon {
    type State = PigeonState;
    type Parameters = PigeonParameters;
    crate::capabilities!(Reports, Diagnostics);

    fn name(&self) -> &'static str {
        "pigeon"
    }

    fn initialise(
        &mut self,
        swarm: &SwarmView<'_>,
        _states: &mut [PigeonState],
    ) -> Result<(), LawError> {
        self.mean_distance_history.clear();
        self.target_zone_reached_s = None;
        let started = SwarmFacts::of(swarm);
        self.check_swarm(&started)?;
        self.started = Some(started);
        Ok(())
    }

    /// The update reads only the satellite's own previous state: updated in place.
    fn reads_neighbour_broadcasts(&self) -> bool {
        false
    }

    fn check_swarm(&self, swarm: &SwarmFacts) -> Result<(), LawError> {
        Self::check_against(&self.parameters, swarm)
    }

    /// Step 2 of Algorithm 1 (see [`Pigeon::update_state_into`]).
    fn update_state(
        &self,
        satellite: &SatelliteView<'_>,
        broadcast: &Broadcast<'_, PigeonState>,
        context: &LawContext,
    ) -> PigeonState {
        let mut state = PigeonState::default();
        self.update_state_into(satellite, broadcast, context, &mut state);
        state
    }

    /// Step 2 of Algorithm 1: N_i^1 (hysteresis), N_i^2, V_a,i over the previous N_i, p_h, the pattern
    /// draw, and the barrier-violation counts, in one walk over the neighbours (V_a,i sums the headings
    /// in the walk's order), into `state` (reusing its heap list, if it has one).
    fn update_state_into(
        &self,
        satellite: &SatelliteView<'_>,
        broadcast: &Broadcast<'_, PigeonState>,
        context: &LawContext,
        state: &mut PigeonState,
    ) {
        let p = &self.parameters;
        let previous = broadcast.own();
        let first = previous.updates == 0;
        let id = satellite.id();
        let own = satellite.own_state();
        let mut separation_violations = 0u64;
        // V_a,i over the previous tick's N_i (N_i^1 at the first tick), with the velocities sensed now.
        let mut headings = switching::unit_heading(&pigeon_plane(&own.velocity_mps));
        let mut members = 1usize;
        let (previous_egalitarian, previous_rest) =
            (previous.egalitarian(), previous.hierarchical_rest());
        UPDATE_LINKS.with_borrow_mut(|(links, rest)| {
            links.clear();
            rest.clear();
            satellite.for_each_neighbour(|nb| {
                let r = pigeon_plane(&nb.offset_m).norm();
                let linked = contains(previous_egalitarian, nb.id);
                let egalitarian =
                    switching::egalitarian_link(linked, r, p.egalitarian_range_m, p.link_delay_m);
                // Grid ids are 32-bit (see `PigeonState`).
                let j = nb.id as u32;
                if egalitarian {
                    links.push(j);
                } else if switching::hierarchical_link(r, p.hierarchical_range_m) {
                    rest.push(j);
                }
                if r <= p.min_separation_m && nb.id > id {
                    separation_violations += 1;
                }
                let member = if first {
                    egalitarian
                } else {
                    linked || contains(previous_rest, nb.id)
                };
                if member {
                    headings += switching::unit_heading(&pigeon_plane(&nb.state.velocity_mps));
                    members += 1;
                }
            });
            links.sort_unstable();
            let egalitarian_len = links.len();
            let local_order = headings.norm() / members as f64;
            let (probability, hierarchical) = if p.switching {
                let ph = switching::hierarchical_probability(local_order, p.alpha, p.beta);
                (ph, context.random().uniform() < ph)
            } else {
                (0.0, false)
            };
            if hierarchical {
                rest.sort_unstable();
                links.extend_from_slice(rest);
            }
            let x_i = pigeon_plane(&own.position_m);
            let mut clearance_violations = 0u64;
            satellite.for_each_obstacle(|o| {
                let r = (x_i - pigeon_plane(&o.center_hill_m)).norm();
                if r <= o.radius_m + p.min_clearance_m {
                    clearance_violations += 1;
                }
            });
            let switched = !first && hierarchical != previous.hierarchical;
            state.links.assign(links);
            *state = PigeonState {
                updates: previous.updates + 1,
                links: std::mem::take(&mut state.links),
                egalitarian_len: egalitarian_len as u32,
                hierarchical,
                local_order_parameter: local_order,
                hierarchical_probability: probability,
                switches: previous.switches + u64::from(switched),
                separation_violations: previous.separation_violations + separation_violations,
                clearance_violations: previous.clearance_violations + clearance_violations,
            };
        });
    }

    /// The saturated thrust f̄, Hill frame \[m/s²\] (`docs/methods/pigeon.md`).
    fn command(
        &self,
        satellite: &SatelliteView<'_>,
        state: &PigeonState,
        context: &LawContext,
    ) -> Vector3<f64> {
        self.thrust(satellite, state, context).saturated_m_s2
    }

    fn set_parameters(&mut self, parameters: &PigeonParameters) -> Result<(), LawError> {
        let law = Self::new(parameters.clone())?;
        if let Some(started) = &self.started {
            Self::check_against(parameters, started)?;
        }
        self.parameters = law.parameters;
        self.dominant = law.dominant;
        Ok(())
    }

    /// The largest per-link closed-loop rate of the law's linear parts \[1/s\] (mass-independent):
    ///
    /// * the radial PD s² + K^D s + K^P: its largest root modulus;
    /// * one alignment link: v_ij decays at K^V (w_ij + w_ji) ≤ 2 K^V w';
    /// * one formation link at the desired distance: ω = √(2 K^F V^F''(R_d)), V^F''(R_d) = 2 c²,
    ///   c = max(R_d/(R_d − R_L^3), R_d/(R_c^1 − R_d)) (the stiffer branch);
    /// * the optional damping K^{T,v}.
    ///
    /// Not included, because the engine cannot know them before the run or they are not resolvable by
    /// design: the neighbour count (a satellite with m links damps at up to K^V w' m; 8.1/s for 9
    /// hierarchical links at the defaults, still inside explicit-Euler stability 2/t_s at 0.1 s), the
    /// obstacle stiffness (depends on each obstacle's radius), and the barrier stiffness near the
    /// clamp (K^F c² (1 + 10⁶), hundreds per second: the barriers are soft in discrete time, and the law
    /// counts the samples that cross them). Defaults: max(0.2, 1.8, 0.57, 0) = 1.8/s, so periods up to
    /// 0.55 s are accepted.
    fn fastest_rate_per_s(&self, _mass_kg: f64) -> Option<f64> {
        let p = &self.parameters;
        let (kp, kd) = (p.k_radial_p_per_s2, p.k_radial_d_per_s);
        let discriminant = kd * kd - 4.0 * kp;
        let pd = if discriminant >= 0.0 {
            0.5 * (kd + discriminant.sqrt())
        } else {
            kp.sqrt()
        };
        let alignment = 2.0 * p.k_alignment_per_s * p.leader_weight;
        let d = p.desired_separation_m;
        let c = (d / (d - p.min_separation_m)).max(d / (p.egalitarian_range_m - d));
        let formation = (2.0 * p.k_formation_per_s2 * 2.0 * c * c).sqrt();
        Some(
            pd.max(alignment)
                .max(formation)
                .max(p.target_velocity_damping_per_s),
        )
    }
}

/// The `pigeon` law's results (`summary.json` `law`), over the live satellites in the pigeon plane.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PigeonResults {
    /// Final global order parameter V_a.
    pub pigeon_order_parameter: f64,
    /// Final mean pair distance \[m\] (null without a pair).
    pub pigeon_mean_distance_m: Option<f64>,
    /// Final mean distance to the target \[m\] (null without a live satellite).
    pub pigeon_mean_target_distance_m: Option<f64>,
    /// Pattern switches, in total.
    pub pigeon_switches: u64,
    /// Pattern switches of each satellite, by id.
    pub pigeon_switches_per_satellite: Vec<u64>,
    /// Barrier violations in total (separation pairs + obstacle clearances, counted per tick).
    pub pigeon_barrier_violations: u64,
    /// Separation-barrier violations (pairs, counted per tick).
    pub pigeon_separation_violations: u64,
    /// Obstacle-clearance violations (counted per tick).
    pub pigeon_clearance_violations: u64,
    /// The dominant satellites S_d (ids, sorted).
    pub pigeon_dominant: Vec<usize>,
    /// See [`Pigeon::stabilisation_time_s`] \[s\] (resolution: the recording interval).
    pub pigeon_stabilisation_time_s: Option<f64>,
    /// The first recording with the mean target distance below R_L^2 \[s\] (null if never;
    /// resolution: the recording interval).
    pub pigeon_time_to_target_zone_s: Option<f64>,
}

impl Reports<PigeonState> for Pigeon {
    type Results = PigeonResults;

    fn headlines(&self) -> &'static [Headline] {
        const HEADLINES: &[Headline] = &[
            Headline::new(
                "pigeon_order_parameter",
                "order parameter",
                "-",
                Better::Higher,
            ),
            Headline::new(
                "pigeon_stabilisation_time_s",
                "stabilisation time",
                "s",
                Better::Lower,
            ),
        ];
        HEADLINES
    }

    /// `pigeon_order_parameter`, `pigeon_mean_distance_m`, `pigeon_mean_target_distance_m` (final),
    /// `pigeon_switches` (total) and `pigeon_switches_per_satellite`, `pigeon_barrier_violations` (total)
    /// with `pigeon_separation_violations` and `pigeon_clearance_violations`, `pigeon_dominant`,
    /// `pigeon_stabilisation_time_s` (see [`Pigeon::stabilisation_time_s`]) and
    /// `pigeon_time_to_target_zone_s` (first recording with the mean target distance below R_L^2; null if
    /// never). Both have the recording interval as their resolution.
    fn results(&self, swarm: &SwarmView<'_>, states: &[PigeonState]) -> PigeonResults {
        let (order, mean_distance, mean_target) = self.swarm_measures(swarm);
        let finite = |v: f64| v.is_finite().then_some(v);
        let separation: u64 = states.iter().map(|s| s.separation_violations).sum();
        let clearance: u64 = states.iter().map(|s| s.clearance_violations).sum();
        PigeonResults {
            pigeon_order_parameter: order,
            pigeon_mean_distance_m: finite(mean_distance),
            pigeon_mean_target_distance_m: finite(mean_target),
            pigeon_switches: states.iter().map(|s| s.switches).sum(),
            pigeon_switches_per_satellite: states.iter().map(|s| s.switches).collect(),
            pigeon_barrier_violations: separation + clearance,
            pigeon_separation_violations: separation,
            pigeon_clearance_violations: clearance,
            pigeon_dominant: self.dominant.clone(),
            pigeon_stabilisation_time_s: self.stabilisation_time_s(),
            pigeon_time_to_target_zone_s: self.target_zone_reached_s,
        }
    }
}

impl Diagnostics<PigeonState> for Pigeon {
    fn output_names(&self) -> &'static [&'static str] {
        OUTPUT_NAMES
    }

    /// `pigeon_pattern`: 0 egalitarian, 1 hierarchical.
    fn write_outputs(&self, state: &PigeonState, values: &mut [f64]) {
        values[0] = if state.hierarchical { 1.0 } else { 0.0 };
    }

    fn metric_names(&self) -> &'static [&'static str] {
        METRIC_NAMES
    }

    /// Global order parameter V_a, mean pair distance \[m\] and mean target distance \[m\] (pigeon
    /// plane, live satellites), the number of live hierarchical satellites, the pattern switches so far
    /// and the barrier violations so far (separation pairs + obstacle clearances, counted per tick).
    fn record_metrics(
        &mut self,
        swarm: &SwarmView<'_>,
        states: &[PigeonState],
        values: &mut [f64],
    ) {
        let (order, mean_distance, mean_target) = self.swarm_measures(swarm);
        let now = swarm.shared.time_s;
        self.mean_distance_history.push((now, mean_distance));
        if self.target_zone_reached_s.is_none() && mean_target < self.parameters.target_zone_m {
            self.target_zone_reached_s = Some(now);
        }
        let hierarchical = states
            .iter()
            .zip(swarm.active)
            .filter(|(s, a)| **a && s.hierarchical)
            .count();
        values[0] = order;
        values[1] = mean_distance;
        values[2] = mean_target;
        values[3] = hierarchical as f64;
        values[4] = states.iter().map(|s| s.switches).sum::<u64>() as f64;
        values[5] = states
            .iter()
            .map(|s| s.separation_violations + s.clearance_violations)
            .sum::<u64>() as f64;
    }
}

#[cfg(test)]
mod tests;
