//! The active desired-velocity field of one satellite: which building blocks a strategy uses in each
//! mode (paper §4; the strategy table of `docs/methods/equilibrium-shaping.md`), their sum at the
//! satellite's sensed state, and the analytic material derivative of that sum along the satellite's and
//! its neighbours' motion; also the stacked field Jacobian at the nodes that bounds the closed-loop rate:
//! its exact largest |λ| up to [`EXACT_RATE_NODES`] nodes (dense, once), above it for the Eq. 1 field a
//! Gershgorin bound over the node pairs within a cutoff plus an analytic bound of the pairs beyond
//! ([`pair_gershgorin_rate_per_s`], O(N k) once).
//!
//! Hill frame (x radial out, y along-track, z orbit normal), relative to the LVLH origin \[m, m/s\].

use nalgebra::{DMatrix, Matrix3, Vector3};
use rayon::prelude::*;

use super::field::{self, EscapeRule, FieldTerm, Viscosity};
use super::neighbourhood::{self, PairValues};
use super::parameters::{EquilibriumShapingParameters, Escape, Strategy};
use super::shaping::pair_attraction_per_s;
use super::state_machine::{EsState, Mode};
use crate::swarm::SatelliteView;

/// The position-dependent building blocks of a field.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FieldSet {
    /// Eq. 1 pair attraction–repulsion with a_ij from Eq. 4 (keeps relative geometry).
    Pair,
    /// Gather (Eq. 13) + avoid (Eq. 14, ES coefficients) + dock (Eq. 15) (returns to the nodes).
    GatherAvoidDock,
    /// Lennard-Jones (σ_ij = node distances) + scatter + viscosity (Eqs. 8–12).
    Scatter,
}

/// Which threat term is added.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ThreatUse {
    /// None.
    Off,
    /// The threat the satellite's own sensors see within the physical sensing radius, K = 2 (R_s/3)².
    Physical,
    /// The warned threat on its on-board track, K_i from the virtual sensing radius.
    Warned,
}

/// The field of `strategy` in `mode` (paper §4; the method page's strategy table). NOMINAL and
/// RETURNING add the physically sensed threat term; WARNED adds the warned one, except in S1, whose
/// satellites are not told the threat's state.
pub fn field_of(strategy: Strategy, mode: Mode) -> (FieldSet, ThreatUse) {
    use FieldSet::*;
    match (strategy, mode) {
        (Strategy::ScatterGather, Mode::Warned) => (Scatter, ThreatUse::Off),
        (Strategy::ScatterGather | Strategy::FixedCentroid, Mode::Nominal | Mode::Returning) => {
            (GatherAvoidDock, ThreatUse::Physical)
        }
        (Strategy::FixedCentroid, Mode::Warned) => (GatherAvoidDock, ThreatUse::Warned),
        (Strategy::MovingCentroid | Strategy::Mix, Mode::Nominal) => (Pair, ThreatUse::Physical),
        (Strategy::MovingCentroid, Mode::Returning) => (Pair, ThreatUse::Physical),
        (Strategy::MovingCentroid | Strategy::Mix, Mode::Warned) => (Pair, ThreatUse::Warned),
        (Strategy::Mix, Mode::Returning) => (GatherAvoidDock, ThreatUse::Physical),
    }
}

/// Every field a strategy uses, over its three modes.
pub fn fields_of(strategy: Strategy) -> Vec<(FieldSet, ThreatUse)> {
    let mut out: Vec<(FieldSet, ThreatUse)> = Vec::new();
    for mode in [Mode::Nominal, Mode::Warned, Mode::Returning] {
        let f = field_of(strategy, mode);
        if !out.contains(&f) {
            out.push(f);
        }
    }
    out
}

/// What the law precomputes once from its parameters: the nodes and the pair coefficient tables.
#[derive(Clone, Debug)]
pub struct Tables {
    /// ξ_i, Hill \[m\].
    pub nodes_m: Vec<Vector3<f64>>,
    /// Centroid of the nodes, Hill \[m\].
    pub node_centroid_m: Vector3<f64>,
    /// Avoid coefficients b_ij \[1/s\], row-major N × N, symmetric (empty when the strategy has no
    /// gather/avoid/dock field, such as S2: only the strategies capped at [`super::MAX_SHAPED_NODES`]
    /// nodes hold this O(N²) table).
    pub avoid_per_s: Vec<f64>,
    /// The `perp-common` direction (also the `perp-radial` and `away` fallback) for the law's threat as
    /// the scenario defines it, Hill unit vector (`None` until the law has started, or without such a
    /// threat).
    pub common_escape_hill: Option<Vector3<f64>>,
    /// The Eq. 4 attractions a_ij \[1/s\] of the node pairs within the sensing range (empty until the
    /// law has started, and for strategies without the Eq. 1 field): [`Self::pair_attraction_per_s`]
    /// looks them up instead of computing a square root and an exponential per neighbour and step.
    pub pair_attractions: PairValues,
}

impl Tables {
    /// Desired distance δ_ij = ‖ξ_i − ξ_j‖ \[m\].
    pub fn distance_m(&self, i: usize, j: usize) -> f64 {
        (self.nodes_m[i] - self.nodes_m[j]).norm()
    }

    /// Eq. 4 attraction a_ij \[1/s\] of nodes i and j for repulsion strength `b_per_s` \[1/s\] and range
    /// `c_m2` \[m²\] (those the table was made with): tabulated, or computed as the table computes it.
    #[inline]
    pub fn pair_attraction_per_s(&self, i: usize, j: usize, b_per_s: f64, c_m2: f64) -> f64 {
        self.pair_attractions
            .get(i, j)
            .unwrap_or_else(|| pair_attraction_per_s(self.distance_m(i, j), b_per_s, c_m2))
    }

    /// Avoid coefficient b_ij \[1/s\].
    pub fn avoid_per_s(&self, i: usize, j: usize) -> f64 {
        self.avoid_per_s[i * self.nodes_m.len() + j]
    }

    /// Unit direction from the danger centre to node i (the scatter term's direction at the centre), +x
    /// when the node is the centre.
    fn node_direction(&self, i: usize, center_m: &Vector3<f64>) -> Vector3<f64> {
        let d = self.nodes_m[i] - center_m;
        let n = d.norm();
        if n > field::DIRECTION_EPSILON_M {
            d / n
        } else {
            Vector3::x()
        }
    }
}

/// The active field at one satellite.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DesiredVelocity {
    /// The sum of every term except the viscosity, Hill \[m/s\].
    pub field_velocity_mps: Vector3<f64>,
    /// The viscosity coefficient and its gradient (zero outside S1's scatter field).
    pub viscosity: Viscosity,
    /// Material derivative of `field_velocity_mps` along the motion (own and neighbours' velocities,
    /// the threat's motion) plus the viscosity term's −(∇ν·v) v, Hill \[m/s²\]; the viscosity's −ν v̇ is
    /// resolved by the controller.
    pub material_derivative_m_s2: Vector3<f64>,
}

impl DesiredVelocity {
    /// The desired velocity v_des = v_field − ν v for the satellite's actual velocity `velocity_mps`.
    pub fn velocity_mps(&self, velocity_mps: &Vector3<f64>) -> Vector3<f64> {
        self.field_velocity_mps + self.viscosity.velocity_mps(velocity_mps)
    }

    /// The kinematic model's velocity: the fixed point v = v_field − ν v, i.e. v_field / (1 + ν).
    pub fn kinematic_velocity_mps(&self) -> Vector3<f64> {
        self.field_velocity_mps / (1.0 + self.viscosity.coefficient)
    }
}

/// Adds a term and its material derivative.
fn add(
    sum: &mut (Vector3<f64>, Vector3<f64>),
    term: &FieldTerm,
    own_v: &Vector3<f64>,
    nb_v: &Vector3<f64>,
) {
    sum.0 += term.velocity_mps;
    sum.1 += term.material_derivative_m_s2(own_v, nb_v);
}

/// The escape rule for a threat moving with `velocity_mps`, given the stored or precomputed common
/// direction `common` (a unit vector).
fn escape_rule(escape: Escape, velocity_mps: &Vector3<f64>, common: &Vector3<f64>) -> EscapeRule {
    match escape {
        Escape::Parallel => {
            let n = velocity_mps.norm();
            EscapeRule::Fixed(if n > 0.0 {
                velocity_mps / n
            } else {
                Vector3::x()
            })
        }
        Escape::PerpCommon => EscapeRule::Fixed(*common),
        Escape::PerpRadial => EscapeRule::Radial { fallback: *common },
        Escape::Away => EscapeRule::Away { fallback: *common },
    }
}

/// The active field of satellite `satellite` in state `state`.
pub fn desired_velocity(
    p: &EquilibriumShapingParameters,
    tables: &Tables,
    satellite: &SatelliteView<'_>,
    state: &EsState,
) -> DesiredVelocity {
    let (set, threat_use) = field_of(p.strategy, state.mode);
    let own = satellite.own_state();
    let (x, v) = (own.position_m, own.velocity_mps);
    let i = satellite.id();
    let zero = Vector3::zeros();
    let mut sum = (Vector3::zeros(), Vector3::zeros());
    let mut viscosity = Viscosity {
        coefficient: 0.0,
        gradient_per_m: Vector3::zeros(),
    };
    match set {
        FieldSet::Pair => satellite.for_each_neighbour(|nb| {
            let a = tables.pair_attraction_per_s(i, nb.id, p.pair_b_per_s, p.pair_c_m2);
            let term =
                field::pair_attraction_repulsion(&-nb.offset_m, a, p.pair_b_per_s, p.pair_c_m2);
            add(&mut sum, &term, &v, &nb.state.velocity_mps);
        }),
        FieldSet::GatherAvoidDock => {
            let n = tables.nodes_m.len() as f64;
            // Σ_t −c (x − ξ_t) = −N c (x − ξ̄): one sink at the centroid with gain N c.
            let gather = field::gather(&x, &tables.node_centroid_m, n * p.gather_per_s);
            add(&mut sum, &gather, &v, &zero);
            for sink in &tables.nodes_m {
                let dock = field::dock(&x, sink, p.dock_per_s, p.dock_range_m2);
                add(&mut sum, &dock, &v, &zero);
            }
            satellite.for_each_neighbour(|nb| {
                let b = tables.avoid_per_s(i, nb.id);
                let term = field::avoid(&-nb.offset_m, b, p.avoid_range_m2);
                add(&mut sum, &term, &v, &nb.state.velocity_mps);
            });
        }
        FieldSet::Scatter => {
            satellite.for_each_neighbour(|nb| {
                let sigma = tables.distance_m(i, nb.id);
                let term = field::lennard_jones(&-nb.offset_m, p.lj_epsilon_m2_per_s, sigma);
                add(&mut sum, &term, &v, &nb.state.velocity_mps);
            });
            let center = Vector3::from(p.danger_center_hill_m);
            let scatter = field::scatter(
                &x,
                &center,
                p.danger_radius_m,
                p.scatter_gain_per_m_s,
                &tables.node_direction(i, &center),
            );
            add(&mut sum, &scatter, &v, &zero);
            viscosity = field::viscosity(
                &x,
                &center,
                p.danger_radius_m,
                p.viscosity_gain,
                p.viscosity_band_m,
            );
            sum.1 += viscosity.material_derivative_fixed_velocity_m_s2(&v);
        }
    }
    match threat_use {
        ThreatUse::Off => {}
        ThreatUse::Physical => {
            if state.threat_sensed {
                let common = tables.common_escape_hill.unwrap_or_else(Vector3::x);
                satellite.for_each_threat(|threat| {
                    if threat.id == p.threat {
                        let rule = escape_rule(p.escape, &threat.velocity_hill_mps, &common);
                        let term = field::threat(
                            &x,
                            &threat.position_hill_m,
                            &threat.velocity_hill_mps,
                            p.threat_scale_mps,
                            p.physical_width_m2(),
                            &rule,
                        );
                        add(&mut sum, &term, &v, &zero);
                    }
                });
            }
        }
        ThreatUse::Warned => {
            if let Some(w) = &state.warning {
                let rule = escape_rule(
                    p.escape,
                    &w.threat_velocity_hill_mps,
                    &w.escape_direction_hill,
                );
                let term = field::threat(
                    &x,
                    &w.threat_position_at_hill_m(satellite.shared().time_s),
                    &w.threat_velocity_hill_mps,
                    p.threat_scale_mps,
                    w.width_m2,
                    &rule,
                );
                add(&mut sum, &term, &v, &zero);
            }
        }
    }
    DesiredVelocity {
        field_velocity_mps: sum.0,
        viscosity,
        material_derivative_m_s2: sum.1,
    }
}

/// The Jacobian of the stacked field (every satellite on its node) of one field set with respect to
/// every position, 3N × 3N \[1/s\]: block (i, i) the own-position derivatives, block (i, j) the
/// neighbour's. The threat term and the viscosity are not included (they have no fixed point to
/// linearise about; the law bounds them separately). O(N²) time and memory: for at most
/// [`EXACT_RATE_NODES`] nodes.
pub fn stacked_jacobian_at_nodes(
    p: &EquilibriumShapingParameters,
    tables: &Tables,
    set: FieldSet,
) -> DMatrix<f64> {
    let nodes = &tables.nodes_m;
    let n = nodes.len();
    let mut jac = DMatrix::zeros(3 * n, 3 * n);
    let center = Vector3::from(p.danger_center_hill_m);
    for i in 0..n {
        let x = nodes[i];
        let mut own_terms: Vec<FieldTerm> = Vec::new();
        match set {
            FieldSet::Pair => {}
            FieldSet::GatherAvoidDock => {
                own_terms.push(field::gather(
                    &x,
                    &tables.node_centroid_m,
                    n as f64 * p.gather_per_s,
                ));
                for sink in nodes {
                    own_terms.push(field::dock(&x, sink, p.dock_per_s, p.dock_range_m2));
                }
            }
            FieldSet::Scatter => own_terms.push(field::scatter(
                &x,
                &center,
                p.danger_radius_m,
                p.scatter_gain_per_m_s,
                &tables.node_direction(i, &center),
            )),
        }
        for t in &own_terms {
            let mut block = jac.fixed_view_mut::<3, 3>(3 * i, 3 * i);
            block += t.d_own_per_s;
        }
        for j in (0..n).filter(|j| *j != i) {
            let t = pair_term(p, tables, set, i, j, &(x - nodes[j]));
            let mut own_block = jac.fixed_view_mut::<3, 3>(3 * i, 3 * i);
            own_block += t.d_own_per_s;
            let mut nb_block = jac.fixed_view_mut::<3, 3>(3 * i, 3 * j);
            nb_block += t.d_neighbour_per_s;
        }
    }
    jac
}

/// Node counts up to which [`field_rate_at_nodes_per_s`] solves the 3N × 3N eigenproblem; above it a
/// Node counts up to which [`field_rate_at_nodes_per_s`] solves the 3N × 3N eigenproblem of the Eq. 1
/// field; above it a Gershgorin bound is used ([`pair_gershgorin_rate_per_s`]: O(N) memory, O(N k)
/// time with k the nodes within the cutoff). Equal to [`super::MAX_SHAPED_NODES`], the cap of the
/// strategies with gather/avoid/dock (and scatter) fields, which are therefore always solved exactly.
pub const EXACT_RATE_NODES: usize = super::MAX_SHAPED_NODES;

/// Largest eigenvalue modulus of [`stacked_jacobian_at_nodes`] \[1/s\]. Every field set is a gradient
/// field (Eq. 1, gather, avoid, dock, Lennard-Jones and scatter are each −∇ of a potential, the pair
/// potentials symmetric in i and j), so the stacked Jacobian is symmetric up to rounding; the symmetric
/// eigensolver is used on its symmetric part. For the Eq. 1 field above [`EXACT_RATE_NODES`] nodes an
/// upper bound of every |λ| is returned instead, [`pair_gershgorin_rate_per_s`]. The other field sets
/// are always solved exactly (dense, O(N³)): the law uses them only up to [`super::MAX_SHAPED_NODES`]
/// nodes.
pub fn field_rate_at_nodes_per_s(
    p: &EquilibriumShapingParameters,
    tables: &Tables,
    set: FieldSet,
) -> f64 {
    if set == FieldSet::Pair && tables.nodes_m.len() > EXACT_RATE_NODES {
        return pair_gershgorin_rate_per_s(p, tables);
    }
    let jac = stacked_jacobian_at_nodes(p, tables, set);
    ((&jac + jac.transpose()) * 0.5)
        .symmetric_eigenvalues()
        .iter()
        .map(|l| l.abs())
        .fold(0.0, f64::max)
}

/// Gershgorin's bound (largest absolute row sum) of the Eq. 1 field's stacked Jacobian at the nodes
/// \[1/s\], without forming it, over the node pairs within the cutoff
/// [`neighbourhood::pair_cutoff_m`] (found through the neighbour grid), plus the analytic bound
/// [`neighbourhood::pair_tail_per_s`] of every pair left out: an upper bound of the exact row sums'
/// maximum, by at most [`neighbourhood::NEGLECTED_RELATIVE`] · b (2·10⁻¹⁵ 1/s for b = 20 1/s) beyond
/// the rounding of the sums. O(N) memory, O(N k) time (k: nodes within the cutoff, ~57 on the 6 m
/// triangular lattice with c = 10 m²), rows in parallel.
pub fn pair_gershgorin_rate_per_s(p: &EquilibriumShapingParameters, tables: &Tables) -> f64 {
    let nodes = &tables.nodes_m;
    let n = nodes.len();
    let cutoff_m = neighbourhood::pair_cutoff_m(p.pair_c_m2, n);
    let grid = neighbourhood::node_grid(nodes, cutoff_m);
    let row = |i: usize| {
        let mut own = Matrix3::zeros();
        let mut off_diagonal = Vector3::zeros();
        grid.for_each_neighbour(i, |nb| {
            let t = pair_term(
                p,
                tables,
                FieldSet::Pair,
                i,
                nb.index,
                &(nodes[i] - nodes[nb.index]),
            );
            own += t.d_own_per_s;
            off_diagonal += t.d_neighbour_per_s.abs().column_sum();
        });
        (own.abs().column_sum() + off_diagonal).max()
    };
    let largest = (0..n).into_par_iter().map(row).reduce(|| 0.0, f64::max);
    largest + neighbourhood::pair_tail_per_s(p.pair_b_per_s, p.pair_c_m2, cutoff_m, n)
}

/// The pair term of `set` between nodes i and j at offset `offset_m` = x_i − x_j \[m\].
fn pair_term(
    p: &EquilibriumShapingParameters,
    tables: &Tables,
    set: FieldSet,
    i: usize,
    j: usize,
    offset_m: &Vector3<f64>,
) -> FieldTerm {
    let delta = tables.distance_m(i, j);
    match set {
        FieldSet::Pair => field::pair_attraction_repulsion(
            offset_m,
            pair_attraction_per_s(delta, p.pair_b_per_s, p.pair_c_m2),
            p.pair_b_per_s,
            p.pair_c_m2,
        ),
        FieldSet::GatherAvoidDock => {
            field::avoid(offset_m, tables.avoid_per_s(i, j), p.avoid_range_m2)
        }
        FieldSet::Scatter => field::lennard_jones(offset_m, p.lj_epsilon_m2_per_s, delta),
    }
}
