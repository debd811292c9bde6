//! The `equilibrium-shaping` law: behaviour-based, distributed scatter manoeuvres of a small satellite
//! cluster under a threat warning, after S. Nag and L. Summerer, "Behaviour based, autonomous and
//! distributed scatter manoeuvres for satellite swarms", Acta Astronautica 82 (2013) 95–109. Method
//! page: `docs/methods/equilibrium-shaping.md`.
//!
//! Two layers run on every satellite, in the Hill frame (x radial out, y along-track, z orbit normal)
//! relative to the LVLH origin (the formation centre):
//!
//! 1. **Kinematic layer**: a desired-velocity field v_des \[m/s\] summed from behaviour terms
//!    ([`field`]), whose free coefficients are set once by **equilibrium shaping** ([`shaping`]) so that
//!    the field vanishes with every satellite on its node (satellite i ↔ node i). Which terms are active
//!    depends on the strategy and the satellite's mode ([`desired::field_of`], [`state_machine`]).
//! 2. **Dynamic layer** (paper Eq. 7): u = k (v_des − v) + a_ff − a_in(x, v) \[m/s²\], with a_in the HCW
//!    natural acceleration (3n²x + 2n ẏ, −2n ẋ, −n²z) of the reference's mean motion n and a_ff the
//!    analytic material derivative of v_des along the motion: J_i v_i + Σ_j ∂v_des/∂x_j v_j + ∂v_des/∂t
//!    (the Jacobians come with every term; the threat's motion enters through ∂/∂t). The actuator cap
//!    and process noise are the engine's.
//!
//! **The viscosity term's own-velocity dependence** (S1 WARNED only): v_des = v_f − ν(x) v depends on the
//! satellite's actual velocity v. Its material derivative contains −ν v̇, and v̇ = a_in + u is what the
//! command itself produces. The law resolves this algebraically: with a_f the material derivative of
//! v_f − ν v at fixed v (−(∇ν·v) v included), a_ff = a_f − ν v̇ and v̇ = k (v_des − v) + a_ff give
//! u = (k (v_des − v) + a_f) / (1 + ν) − a_in, so that the tracking error e = v_des − v obeys ė = −k e
//! exactly (before saturation and noise). With `feedforward = "none"` the command is
//! u = k (v_des − v) − a_in, whose velocity loop then has the rate k (1 + ν). On the kinematic model the
//! commanded velocity is the fixed point v = v_f − ν v, i.e. v_f / (1 + ν).
//!
//! **Feed-forward reset**: on every switch of a satellite's state machine (mode change, or the threat
//! entering or leaving the physical sensing radius) a_ff is zero for that tick, as the method
//! prescribes (against an impulse from a differentiated jump). The analytic feed-forward has no memory,
//! so the reset only drops one tick of it.
//!
//! **Costs** (N nodes, k the nodes within a radius): pair terms run over the neighbours the engine's grid
//! returns (O(N k) per step), the Eq. 1 attractions a_ij of the node pairs within the sensing range
//! tabulated when the law starts (O(N k) memory, looked up per neighbour; [`PairValues`]); the dock term sums over every node (O(N) per satellite), and the
//! equilibrium-shaping solve is a dense SVD of the N(N−1)/2 × 3N matrix Aᵀ, done once, which limits the
//! strategies that use them (S1, S3, S4) to [`MAX_SHAPED_NODES`] nodes; those strategies need a sensing
//! range covering the whole formation (the ES coefficients balance every pair at the nodes). S2's pair
//! terms vanish one by one at the nodes and need neither. Nothing else is quadratic in N, so S2 runs at
//! 10⁶ satellites: the set-up's node check finds coincident nodes through a neighbour grid and the
//! field's rate bound sums the Eq. 1 Jacobian over the pairs within a cutoff radius with the rest
//! bounded analytically ([`desired::pair_gershgorin_rate_per_s`], [`neighbourhood`]), O(N k) once; the
//! record-time formation error runs over the node pairs within the sensing range (O(N k log k) per
//! recording); the gather over every sink is one term at the node centroid.

pub mod desired;
pub mod field;
pub mod neighbourhood;
pub mod parameters;
mod results;
pub mod shaping;
pub mod state_machine;

use crate::invalid::Invalid;
use neighbourhood::{NodePairs, PairValues};
use std::sync::Arc;

use nalgebra::Vector3;

use crate::relative::Hcw;
use crate::swarm::{
    Broadcast, CommandKind, Diagnostics, GuidanceLaw, LawContext, LawError, SatelliteView,
    SwarmFacts, SwarmView, TargetFormation,
};

pub use desired::{DesiredVelocity, FieldSet, Tables, ThreatUse};
pub use parameters::{EquilibriumShapingParameters, Escape, Feedforward, Formation, Strategy};
pub use results::{
    EquilibriumShapingResults, EsAvoidResults, EsCoefficient, EsPairAttraction, EsSatelliteResults,
    EsTimelineEntry, EsWarningResults,
};
pub use shaping::{EsSolution, GatherAvoidDock, ShapingError};
pub use state_machine::{
    EsState, MachineSettings, Mode, ModeChange, ModeEvent, ModeTimeline, Observation,
};

/// Largest node count of the strategies that solve for avoid coefficients (S1, S3, S4): the dense SVD of
/// the N(N−1)/2 × 3N matrix Aᵀ grows as ~N⁴·⁵ (measured 0.06 s at 64 nodes, 0.4 s at 100, 1.3 s at 128).
pub const MAX_SHAPED_NODES: usize = 128;

/// Largest node count for which `summary.json` lists the Eq. 4 attraction of every pair.
pub const MAX_LISTED_NODES: usize = 128;

/// Per-satellite output columns.
const OUTPUT_NAMES: &[&str] = &["es_mode"];

/// Metric columns.
const METRIC_NAMES: &[&str] = &[
    "es_formation_error_m",
    "es_centroid_displacement_m",
    "es_min_threat_distance_m",
    "es_nominal",
    "es_warned",
    "es_returning",
];

fn invalid(invalid: Invalid) -> LawError {
    LawError::invalid("equilibrium-shaping", invalid)
}

/// The `equilibrium-shaping` law.
#[derive(Clone, Debug)]
pub struct EquilibriumShaping {
    parameters: EquilibriumShapingParameters,
    tables: Arc<Tables>,
    /// The avoid-coefficient solution (strategies with a gather/avoid/dock field).
    avoid: Option<EsSolution>,
    /// Largest |λ| of the stacked Jacobian at the nodes over the strategy's fields \[1/s\].
    field_rate_per_s: f64,
    /// What the law learnt from the swarm when it started.
    started: Option<SwarmFacts>,
    /// The node pairs of the formation error: those within the sensing range once started (every pair
    /// before).
    error_pairs: Arc<NodePairs>,
    /// Smallest satellite–threat distance over the recordings so far \[m\].
    min_threat_distance_m: f64,
}

impl EquilibriumShaping {
    /// Builds the law: checks the parameters, solves the equilibrium shaping if the strategy needs it and
    /// computes the field's rate at the nodes.
    pub fn new(parameters: EquilibriumShapingParameters) -> Result<Self, LawError> {
        let (tables, avoid, field_rate_per_s) = Self::prepare(&parameters)?;
        let error_pairs = Arc::new(NodePairs::every(tables.nodes_m.len()));
        Ok(Self {
            parameters,
            tables: Arc::new(tables),
            avoid,
            field_rate_per_s,
            started: None,
            error_pairs,
            min_threat_distance_m: f64::INFINITY,
        })
    }

    /// Node tables (without the common escape direction, known once the law starts), avoid solution and
    /// field rate of a parameter set.
    fn prepare(
        p: &EquilibriumShapingParameters,
    ) -> Result<(Tables, Option<EsSolution>, f64), LawError> {
        p.check()?;
        let nodes = p.nodes_hill_m();
        let n = nodes.len();
        let fields = desired::fields_of(p.strategy);
        let shaped = fields
            .iter()
            .any(|(set, _)| *set == FieldSet::GatherAvoidDock);
        let avoid = if shaped {
            if n > MAX_SHAPED_NODES {
                return Err(invalid(Invalid::keys(
                    "strategy",
                    format!(
                    "strategy = \"{}\" solves for the avoid coefficients of every pair (a dense \
                     3N × N(N-1)/2 system): {n} nodes exceed the {MAX_SHAPED_NODES} allowed (use \
                     strategy = \"moving-centroid\" for larger formations)",
                    p.strategy.name()
                ),
                    "",
                )));
            }
            Some(
                shaping::solve_avoid_coefficients(&nodes, &p.gather_avoid_dock()).map_err(|e| {
                    invalid(Invalid::keys(
                        "strategy",
                        format!("equilibrium shaping: {e}"),
                        "",
                    ))
                })?,
            )
        } else {
            None
        };
        let mut avoid_table = Vec::new();
        if let Some(solution) = &avoid {
            avoid_table = vec![0.0; n * n];
            for (&(i, j), b) in solution.pairs.iter().zip(&solution.coefficients_per_s) {
                avoid_table[i * n + j] = *b;
                avoid_table[j * n + i] = *b;
            }
        }
        let centroid = nodes.iter().sum::<Vector3<f64>>() / n as f64;
        let tables = Tables {
            nodes_m: nodes,
            node_centroid_m: centroid,
            avoid_per_s: avoid_table,
            common_escape_hill: None,
            pair_attractions: PairValues::default(),
        };
        let rate = fields
            .iter()
            .map(|(set, _)| desired::field_rate_at_nodes_per_s(p, &tables, *set))
            .fold(0.0, f64::max);
        Ok((tables, avoid, rate))
    }

    /// The current parameters.
    pub fn parameters(&self) -> &EquilibriumShapingParameters {
        &self.parameters
    }

    /// The node tables.
    pub fn tables(&self) -> &Tables {
        &self.tables
    }

    /// The equilibrium-shaping solution of the avoid coefficients (strategies S1, S3, S4).
    pub fn avoid_solution(&self) -> Option<&EsSolution> {
        self.avoid.as_ref()
    }

    /// Largest eigenvalue modulus of the stacked field Jacobian at the nodes over the strategy's fields
    /// \[1/s\] (threat and viscosity terms excluded; see [`GuidanceLaw::fastest_rate_per_s`]).
    pub fn field_rate_at_nodes_per_s(&self) -> f64 {
        self.field_rate_per_s
    }

    /// The state machine's settings.
    pub fn machine_settings(&self) -> MachineSettings {
        let p = &self.parameters;
        MachineSettings {
            physical_sensing_radius_m: p.physical_sensing_radius_m,
            escape: p.escape,
            escape_direction_hill: p.escape_direction_hill.map(Vector3::from),
            escape_seed: p.escape_seed,
            settle_error_m: p.settle_error_m,
            settle_speed_mps: p.settle_speed_mps,
            settle_hold_s: p.settle_hold_s,
        }
    }

    /// The active field of satellite `satellite` in state `state`: velocity and material derivative.
    pub fn desired_velocity(
        &self,
        satellite: &SatelliteView<'_>,
        state: &EsState,
    ) -> DesiredVelocity {
        desired::desired_velocity(&self.parameters, &self.tables, satellite, state)
    }

    /// What satellite `satellite` observes for its state machine (settling quantities only in
    /// RETURNING, where they are used).
    pub fn observe(&self, satellite: &SatelliteView<'_>, mode: Mode) -> Observation {
        let p = &self.parameters;
        let own = satellite.own_state();
        let mut sensed = None;
        satellite.for_each_threat(|t| {
            if t.id == p.threat {
                sensed = Some(t.distance_m);
            }
        });
        let (mut sum, mut count, mut speed) = (0.0, 0usize, own.velocity_mps.norm());
        if mode == Mode::Returning {
            let i = satellite.id();
            satellite.for_each_neighbour(|nb| {
                let e = nb.distance_m - self.tables.distance_m(i, nb.id);
                sum += e * e;
                count += 1;
                speed = speed.max(nb.state.velocity_mps.norm());
            });
        }
        Observation {
            time_s: satellite.shared().time_s,
            own_position_hill_m: own.position_m,
            warned_threat_hill: satellite
                .warned_threat(p.threat)
                .map(|t| (t.position_hill_m, t.velocity_hill_mps)),
            sensed_threat_distance_m: sensed,
            pair_rms_error_m: if count > 0 {
                (sum / count as f64).sqrt()
            } else {
                0.0
            },
            max_speed_mps: speed,
        }
    }

    /// Checks a parameter set against the swarm: one satellite per node, every node pair within sensing
    /// range (strategies with equilibrium-shaped avoid coefficients), the threat index, a usable
    /// `perp-common` direction. Returns the common escape direction
    /// for the law's threat (`None` when the scenario has no threat).
    fn check_against(
        p: &EquilibriumShapingParameters,
        tables: &Tables,
        started: &SwarmFacts,
    ) -> Result<Option<Vector3<f64>>, LawError> {
        let nodes = tables.nodes_m.len();
        if started.count != nodes {
            return Err(invalid(Invalid::keys("formation", format!(
                "the formation has {nodes} nodes but the swarm {} satellites (satellite i takes node \
                 i: give as many satellites as nodes)",
                started.count
            ), "")));
        }
        // The ES avoid coefficients balance every pair at the nodes: each pair must be sensed there.
        // (Eq. 1 and Lennard-Jones pair terms vanish one by one at the nodes, so S2 needs no such range.)
        let shaped = desired::fields_of(p.strategy)
            .iter()
            .any(|(set, _)| *set == FieldSet::GatherAvoidDock);
        let range = started.sensing_range_m;
        if shaped {
            let largest = Self::largest_node_distance_m(tables);
            if largest > range {
                return Err(invalid(Invalid::keys(
                    "formation",
                    format!(
                    "the largest node distance {largest} m exceeds the sensing range {range} m: the \
                     equilibrium-shaped avoid coefficients balance every pair at the nodes, so every \
                     satellite must sense every other there (allowed: sensing.range_m >= {largest})"
                ),
                    "",
                )));
            }
        }
        let threats = &started.threat_velocities_hill_mps;
        if threats.is_empty() {
            // Without threats the law only shapes; a threat named beyond the default is a mistake
            // (e.g. this law's controller put on a case without the threat it was written for).
            return match p.threat {
                0 => Ok(None),
                k => Err(invalid(Invalid::keys(
                    "threat",
                    format!(
                    "threat = {k} but the scenario has no threats (allowed: 0, the default, which \
                     has no effect without threats)"
                ),
                    "",
                ))),
            };
        }
        let Some(v_t) = threats.get(p.threat) else {
            return Err(invalid(Invalid::keys(
                "threat",
                format!(
                    "threat = {} but the scenario has {} threats (allowed: 0 ..= {})",
                    p.threat,
                    threats.len(),
                    threats.len() - 1
                ),
                "",
            )));
        };
        if let (Escape::PerpCommon, Some(d)) = (p.escape, p.escape_direction_hill) {
            if !state_machine::direction_is_perpendicular_enough(&Vector3::from(d), v_t) {
                return Err(invalid(Invalid::keys("escape_direction_hill", format!(
                    "escape_direction_hill = {d:?} is along the velocity of threat {} ({:?} m/s): \
                     nothing is left perpendicular to it (allowed: any direction not parallel to the \
                     threat's velocity)",
                    p.threat,
                    [v_t.x, v_t.y, v_t.z]
                ), "")));
            }
        }
        Ok(Some(state_machine::common_escape_direction(
            v_t,
            p.escape_direction_hill.map(Vector3::from).as_ref(),
            p.escape_seed,
        )))
    }

    /// The Eq. 4 attractions a_ij of the node pairs within `range_m` \[m\] (the sensing range) for
    /// strategies with the Eq. 1 field, computed as [`Tables::pair_attraction_per_s`] computes them
    /// (empty for the other strategies). O(N k) with k the nodes within the range.
    fn pair_attractions(
        p: &EquilibriumShapingParameters,
        tables: &Tables,
        range_m: f64,
    ) -> PairValues {
        let paired = desired::fields_of(p.strategy)
            .iter()
            .any(|(set, _)| *set == FieldSet::Pair);
        if !paired {
            return PairValues::default();
        }
        PairValues::within(&tables.nodes_m, range_m, |i, j| {
            shaping::pair_attraction_per_s(tables.distance_m(i, j), p.pair_b_per_s, p.pair_c_m2)
        })
    }

    fn largest_node_distance_m(tables: &Tables) -> f64 {
        let n = tables.nodes_m.len();
        let mut largest: f64 = 0.0;
        for i in 0..n {
            for j in i + 1..n {
                largest = largest.max(tables.distance_m(i, j));
            }
        }
        largest
    }

    /// Formation error (RMS of ‖x_i − x_j‖ − δ_ij over the live pairs whose nodes are within the sensing
    /// range, δ_ij ≤ R: every pair for S1, S3 and S4, whose checks ask for it, and for any formation the
    /// range covers) \[m\] and centroid displacement (centroid of the live satellites minus the centroid of
    /// their nodes) \[m\] of a swarm. Pairs are summed in lexicographic order. O(N k log k) with k the
    /// nodes within the range (before the law starts: every pair).
    pub fn formation_error(&self, swarm: &SwarmView<'_>) -> (f64, f64) {
        let n = swarm.len().min(self.tables.nodes_m.len());
        let live = |i: usize| i < n && swarm.active[i];
        let (mut sum, mut pairs) = (0.0, 0usize);
        let mut partners = Vec::new();
        for i in (0..n).filter(|i| live(*i)) {
            self.error_pairs
                .for_each_later_partner(i, &mut partners, |j| {
                    if live(j) {
                        let d = (swarm.relative_states[i].position_m
                            - swarm.relative_states[j].position_m)
                            .norm();
                        let e = d - self.tables.distance_m(i, j);
                        sum += e * e;
                        pairs += 1;
                    }
                });
        }
        let error = if pairs > 0 {
            (sum / pairs as f64).sqrt()
        } else {
            0.0
        };
        let (mut shift, mut count) = (Vector3::zeros(), 0usize);
        for i in (0..n).filter(|i| live(*i)) {
            shift += swarm.relative_states[i].position_m - self.tables.nodes_m[i];
            count += 1;
        }
        let displacement = if count == 0 {
            0.0
        } else {
            (shift / count as f64).norm()
        };
        (error, displacement)
    }

    /// Smallest distance of a live satellite from the law's threat now \[m\] (`None` without it).
    fn threat_distance_m(&self, swarm: &SwarmView<'_>) -> Option<f64> {
        let threat = swarm.environment.threats.get(self.parameters.threat)?;
        let p = threat.position_hill_m(swarm.shared.time_s);
        (0..swarm.len())
            .filter(|i| swarm.active[*i])
            .map(|i| (swarm.relative_states[i].position_m - p).norm())
            .reduce(f64::min)
    }
}

impl GuidanceLaw for EquilibriumShaping {
    type State = EsState;
    type Parameters = EquilibriumShapingParameters;
    crate::capabilities!(Reports, Diagnostics, TargetFormation);

    fn name(&self) -> &'static str {
        "equilibrium-shaping"
    }

    fn command_kind(&self) -> CommandKind {
        if self.parameters.kinematic {
            CommandKind::Velocity
        } else {
            CommandKind::Acceleration
        }
    }

    fn initialise(
        &mut self,
        swarm: &SwarmView<'_>,
        states: &mut [EsState],
    ) -> Result<(), LawError> {
        let started = SwarmFacts::of(swarm);
        let common = Self::check_against(&self.parameters, &self.tables, &started)?;
        let mut tables = (*self.tables).clone();
        tables.common_escape_hill = common;
        tables.pair_attractions =
            Self::pair_attractions(&self.parameters, &tables, started.sensing_range_m);
        self.error_pairs = Arc::new(NodePairs::within(&tables.nodes_m, started.sensing_range_m));
        self.tables = Arc::new(tables);
        self.started = Some(started);
        self.min_threat_distance_m = f64::INFINITY;
        for s in states.iter_mut() {
            s.mode_since_s = swarm.shared.time_s;
        }
        Ok(())
    }

    /// The update reads only the satellite's own previous state: updated in place.
    fn reads_neighbour_broadcasts(&self) -> bool {
        false
    }

    fn check_swarm(&self, swarm: &SwarmFacts) -> Result<(), LawError> {
        Self::check_against(&self.parameters, &self.tables, swarm).map(|_| ())
    }

    fn update_state(
        &self,
        satellite: &SatelliteView<'_>,
        broadcast: &Broadcast<'_, EsState>,
        _context: &LawContext,
    ) -> EsState {
        let previous = broadcast.own();
        let observation = self.observe(satellite, previous.mode);
        state_machine::next_state(previous, &observation, &self.machine_settings())
    }

    fn command(
        &self,
        satellite: &SatelliteView<'_>,
        state: &EsState,
        _context: &LawContext,
    ) -> Vector3<f64> {
        let p = &self.parameters;
        let desired = self.desired_velocity(satellite, state);
        if p.kinematic {
            return desired.kinematic_velocity_mps();
        }
        let own = satellite.own_state();
        let v = own.velocity_mps;
        let k = p.tracking_gain_per_s;
        let error = desired.velocity_mps(&v) - v;
        let tracking = if p.feedforward == Feedforward::Analytic && !state.feedforward_suppressed {
            (k * error + desired.material_derivative_m_s2) / (1.0 + desired.viscosity.coefficient)
        } else {
            k * error
        };
        let natural = Hcw::new(satellite.shared().mean_motion_rad_s)
            .natural_acceleration_m_s2(&own.position_m, &v);
        tracking - natural
    }

    fn set_parameters(
        &mut self,
        parameters: &EquilibriumShapingParameters,
    ) -> Result<(), LawError> {
        let (mut tables, avoid, rate) = Self::prepare(parameters)?;
        let mut error_pairs = NodePairs::every(tables.nodes_m.len());
        if let Some(started) = &self.started {
            tables.common_escape_hill = Self::check_against(parameters, &tables, started)?;
            tables.pair_attractions =
                Self::pair_attractions(parameters, &tables, started.sensing_range_m);
            error_pairs = NodePairs::within(&tables.nodes_m, started.sensing_range_m);
        }
        self.error_pairs = Arc::new(error_pairs);
        self.parameters = parameters.clone();
        self.tables = Arc::new(tables);
        self.avoid = avoid;
        self.field_rate_per_s = rate;
        Ok(())
    }

    /// max(k, |λ_max| of the stacked field Jacobian at the nodes over the strategy's fields, the threat
    /// term's largest gradient A √(2/K) e^(−1/2) at the physical width when a threat term is used, and
    /// k (1 + K_ν) for the viscosity without feed-forward) \[1/s\]. Warned threat terms use a virtual
    /// width K_i ≥ the physical one whenever the warning comes before the threat is within R_s, so their
    /// gradient is smaller. The mass does not enter (the law commands accelerations per unit mass).
    fn fastest_rate_per_s(&self, _mass_kg: f64) -> Option<f64> {
        let p = &self.parameters;
        let fields = desired::fields_of(p.strategy);
        let mut rate = p.tracking_gain_per_s.max(self.field_rate_per_s);
        if fields.iter().any(|(_, t)| *t != ThreatUse::Off) {
            rate = rate.max(field::threat_rate_bound_per_s(
                p.threat_scale_mps,
                p.physical_width_m2(),
            ));
        }
        if p.feedforward == Feedforward::None
            && fields.iter().any(|(set, _)| *set == FieldSet::Scatter)
        {
            rate = rate.max(p.tracking_gain_per_s * (1.0 + p.viscosity_gain));
        }
        Some(rate)
    }
}

impl Diagnostics<EsState> for EquilibriumShaping {
    fn output_names(&self) -> &'static [&'static str] {
        OUTPUT_NAMES
    }

    /// `es_mode`: 0 nominal, 1 warned, 2 returning.
    fn write_outputs(&self, state: &EsState, values: &mut [f64]) {
        values[0] = state.mode.code();
    }

    fn metric_names(&self) -> &'static [&'static str] {
        METRIC_NAMES
    }

    /// Formation error, centroid displacement, smallest satellite–threat distance over the recordings so
    /// far (NaN without the law's threat; the engine's continuous monitor is the authoritative miss
    /// distance), and the number of live satellites in each mode.
    fn record_metrics(&mut self, swarm: &SwarmView<'_>, states: &[EsState], values: &mut [f64]) {
        let (error, displacement) = self.formation_error(swarm);
        if let Some(d) = self.threat_distance_m(swarm) {
            self.min_threat_distance_m = self.min_threat_distance_m.min(d);
        }
        let mut counts = [0.0; 3];
        for (s, _) in states.iter().zip(swarm.active).filter(|(_, a)| **a) {
            counts[s.mode.code() as usize] += 1.0;
        }
        values[0] = error;
        values[1] = displacement;
        values[2] = if self.min_threat_distance_m.is_finite() {
            self.min_threat_distance_m
        } else {
            f64::NAN
        };
        values[3..6].copy_from_slice(&counts);
    }
}

impl TargetFormation for EquilibriumShaping {
    /// The nodes ξ_i (satellite i ↔ node i).
    fn target_formation_hill_m(&self) -> Option<Vec<Vector3<f64>>> {
        Some(self.tables.nodes_m.clone())
    }
}
