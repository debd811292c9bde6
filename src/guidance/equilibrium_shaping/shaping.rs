//! Equilibrium shaping (ES): the coefficients that make a desired node geometry an equilibrium of the
//! desired-velocity field, from a linear solve (S. Nag and L. Summerer, Acta Astronautica 82 (2013)
//! 95–109, §3 and Eq. 4).
//!
//! * Eq. 1's pair field: every pair term vanishes at ‖y‖ = δ_ij when a_ij = b e^(−δ_ij²/c)
//!   ([`pair_attraction_per_s`]), for any geometry.
//! * Gather/avoid/dock (Eqs. 13–15) with uniform gather c and dock d: the avoid coefficients b_ij = b_ji
//!   (one per pair) are the unknowns p of A p = r, 3N equations (x, y, z of every node):
//!   0 = Σ_t (−c − d e^(−δ_it²/k₃)) (ξ_i − ξ_t) + Σ_{j≠i} b_ij e^(−δ_ij²/k₂) (ξ_i − ξ_j). Column (i, j) of A
//!   holds e^(−δ_ij²/k₂)(ξ_i − ξ_j) in the rows of i and its negative in the rows of j; r is minus the
//!   gather and dock terms. The system is under-determined (rank 5 of 6 for the rhombus, 9 of 15 for the
//!   hexagon); [`solve_min_norm`] returns the minimum-norm solution p = A⁺ r from a singular value
//!   decomposition, which is exact and well scaled, and refuses a node set it cannot shape
//!   (‖A p − r‖ > 1e-9 ‖r‖). [`closed_form_avoid_per_s`] is the pairwise-cancelling alternative (exact,
//!   badly scaled), kept as a reference.
//!
//! Nodes are positions in the Hill frame relative to the LVLH origin \[m\]; node i is satellite i's.

use nalgebra::{DMatrix, DVector, Vector3};
use thiserror::Error;

use super::neighbourhood;

/// Relative residual above which a node set is refused: ‖A p − r‖ > `RESIDUAL_TOLERANCE` · ‖r‖.
pub const RESIDUAL_TOLERANCE: f64 = 1e-9;

/// Nodes closer than this fraction of the formation's extent (the diagonal of its bounding box, 1 to √3
/// times the largest node distance, [`neighbourhood::extent_m`]) are taken as coincident.
pub const COINCIDENT_FRACTION: f64 = 1e-9;

/// Condition number (largest over smallest retained singular value) above which a solution is flagged.
pub const CONDITION_WARNING: f64 = 1e12;

/// Why a node set cannot be shaped.
#[derive(Debug, Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum ShapingError {
    /// Fewer than two nodes: no pair to shape.
    #[error("a formation needs at least 2 nodes, got {count}")]
    TooFewNodes {
        /// Nodes given.
        count: usize,
    },
    /// A node coordinate is NaN or infinite.
    #[error("node {node} is not finite")]
    NonFinite {
        /// Index of the node.
        node: usize,
    },
    /// Two nodes coincide: the pair has no desired distance and its satellites would collide.
    #[error(
        "nodes {first} and {second} coincide ({distance_m:e} m apart): a pair needs a non-zero desired \
         distance"
    )]
    CoincidentNodes {
        /// First node.
        first: usize,
        /// Second node.
        second: usize,
        /// Their distance \[m\].
        distance_m: f64,
    },
    /// The linear system has no exact solution: the behaviours cannot make this geometry an equilibrium.
    #[error(
        "the node set cannot be shaped with these behaviours: residual {residual:e} > {RESIDUAL_TOLERANCE:e} \
         × |r| = {rhs_norm:e} (the field cannot vanish at every node)"
    )]
    Unreachable {
        /// ‖A p − r‖ of the least-squares solution \[m/s\].
        residual: f64,
        /// ‖r‖ \[m/s\].
        rhs_norm: f64,
    },
}

/// Fixed coefficients of the gather/avoid/dock field (Eqs. 13–15).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GatherAvoidDock {
    /// Gather coefficient c_it = c towards every sink \[1/s\].
    pub gather_per_s: f64,
    /// Dock coefficient d_it = d at every sink \[1/s\].
    pub dock_per_s: f64,
    /// Avoid range k₂ \[m²\].
    pub avoid_range_m2: f64,
    /// Dock range k₃ \[m²\].
    pub dock_range_m2: f64,
}

/// Eq. 4: the attraction a_ij = b e^(−δ²/c) \[1/s\] that puts Eq. 1's pair at rest at distance `delta_m`
/// \[m\], for repulsion strength `b_per_s` \[1/s\] and range `c_m2` \[m²\].
pub fn pair_attraction_per_s(delta_m: f64, b_per_s: f64, c_m2: f64) -> f64 {
    b_per_s * (-delta_m * delta_m / c_m2).exp()
}

/// The pairwise-cancelling avoid coefficient b_ij = (c + d e^(−δ²/k₃)) e^(δ²/k₂) \[1/s\] for a pair at
/// desired distance `delta_m` \[m\]: with it every pair's gather, dock and avoid terms cancel, for any
/// geometry (exact but badly scaled: 2.1e5 1/s for the rhombus' long diagonal).
pub fn closed_form_avoid_per_s(delta_m: f64, gains: &GatherAvoidDock) -> f64 {
    let d2 = delta_m * delta_m;
    (gains.gather_per_s + gains.dock_per_s * (-d2 / gains.dock_range_m2).exp())
        * (d2 / gains.avoid_range_m2).exp()
}

/// Refuses node sets with fewer than two nodes, non-finite coordinates or coincident nodes (closer than
/// [`COINCIDENT_FRACTION`] of the formation's extent; the closest such pair is named, ties to the first
/// in lexicographic order). O(N log N) through a neighbour grid (plus the coincident pairs found).
pub fn check_nodes(nodes_m: &[Vector3<f64>]) -> Result<(), ShapingError> {
    if nodes_m.len() < 2 {
        return Err(ShapingError::TooFewNodes {
            count: nodes_m.len(),
        });
    }
    if let Some(node) = nodes_m
        .iter()
        .position(|n| !n.iter().all(|v| v.is_finite()))
    {
        return Err(ShapingError::NonFinite { node });
    }
    let threshold_m = COINCIDENT_FRACTION * neighbourhood::extent_m(nodes_m);
    match neighbourhood::closest_pair_within(nodes_m, threshold_m) {
        Some((first, second, distance_m)) => Err(ShapingError::CoincidentNodes {
            first,
            second,
            distance_m,
        }),
        None => Ok(()),
    }
}

/// The linear system A p = r of the avoid coefficients.
#[derive(Clone, Debug, PartialEq)]
pub struct EsSystem {
    /// A, 3N × P: row 3i + k is axis k of node i; column m is pair `pairs[m]` \[m\].
    pub matrix: DMatrix<f64>,
    /// r, 3N: minus the gather and dock terms at the nodes \[m/s\].
    pub rhs: DVector<f64>,
    /// The unknown pairs (i < j), in column order.
    pub pairs: Vec<(usize, usize)>,
}

/// Every pair (i, j), i < j, of `count` nodes, in row-major order.
pub fn all_pairs(count: usize) -> Vec<(usize, usize)> {
    (0..count)
        .flat_map(|i| (i + 1..count).map(move |j| (i, j)))
        .collect()
}

/// Assembles A p = r for the nodes `nodes_m` (Hill, m), the fixed gains and the pairs whose avoid
/// coefficient is free (`pairs`, i < j; the other pairs' coefficients are zero).
pub fn assemble(
    nodes_m: &[Vector3<f64>],
    gains: &GatherAvoidDock,
    pairs: &[(usize, usize)],
) -> EsSystem {
    let n = nodes_m.len();
    let mut matrix = DMatrix::zeros(3 * n, pairs.len());
    for (m, &(i, j)) in pairs.iter().enumerate() {
        let y = nodes_m[i] - nodes_m[j];
        let col = y * (-y.norm_squared() / gains.avoid_range_m2).exp();
        for k in 0..3 {
            matrix[(3 * i + k, m)] = col[k];
            matrix[(3 * j + k, m)] = -col[k];
        }
    }
    let mut rhs = DVector::zeros(3 * n);
    for i in 0..n {
        let mut r = Vector3::zeros();
        for t in 0..n {
            let s = nodes_m[i] - nodes_m[t];
            r += (gains.gather_per_s
                + gains.dock_per_s * (-s.norm_squared() / gains.dock_range_m2).exp())
                * s;
        }
        rhs.fixed_rows_mut::<3>(3 * i).copy_from(&r);
    }
    EsSystem {
        matrix,
        rhs,
        pairs: pairs.to_vec(),
    }
}

/// The minimum-norm solution of an [`EsSystem`].
#[derive(Clone, Debug, PartialEq)]
pub struct EsSolution {
    /// The pairs (i < j), in the order of `coefficients_per_s`.
    pub pairs: Vec<(usize, usize)>,
    /// Avoid coefficients b_ij \[1/s\].
    pub coefficients_per_s: Vec<f64>,
    /// ‖A p − r‖ \[m/s\].
    pub residual: f64,
    /// ‖r‖ \[m/s\].
    pub rhs_norm: f64,
    /// Numerical rank of A (singular values above max(3N, P) · ε · σ_max).
    pub rank: usize,
    /// σ_max / σ_min over the retained singular values (1 for a zero matrix).
    pub condition_number: f64,
}

impl EsSolution {
    /// Whether any coefficient is negative (that avoid term would attract).
    pub fn has_negative_coefficients(&self) -> bool {
        self.coefficients_per_s.iter().any(|b| *b < 0.0)
    }

    /// Whether the retained part of A is worse conditioned than [`CONDITION_WARNING`].
    pub fn is_ill_conditioned(&self) -> bool {
        self.condition_number > CONDITION_WARNING
    }

    /// The coefficient of pair (i, j) in either order, 0 for a pair that is not free.
    pub fn coefficient_per_s(&self, i: usize, j: usize) -> f64 {
        let key = (i.min(j), i.max(j));
        self.pairs
            .iter()
            .position(|p| *p == key)
            .map_or(0.0, |m| self.coefficients_per_s[m])
    }
}

/// p = A⁺ r by singular value decomposition (singular values at or below max(3N, P) · ε · σ_max treated
/// as zero, NumPy's default), with its residual. Refuses the system when ‖A p − r‖ > 1e-9 ‖r‖.
///
/// The decomposition is of Aᵀ = U Σ Vᵀ (one row per pair), and p = U Σ⁺ Vᵀ r: it keeps the relative
/// accuracy of the tiny coefficients of distant pairs, whose columns are e^(−δ²/k₂) smaller (hexagon,
/// opposite pairs: 9e-9 relative to the symmetry-reduced solution, against 1.4e-6 when A itself is
/// decomposed).
pub fn solve_min_norm(system: &EsSystem) -> Result<EsSolution, ShapingError> {
    let a = &system.matrix;
    let r = &system.rhs;
    let rhs_norm = r.norm();
    let (coefficients, rank, condition_number) = if a.ncols() == 0 {
        (DVector::zeros(0), 0, 1.0)
    } else {
        let svd = a.transpose().svd(true, true);
        let sigma_max = svd.singular_values.max();
        let tolerance = a.nrows().max(a.ncols()) as f64 * f64::EPSILON * sigma_max;
        let (u, v_t) = (
            svd.u.as_ref().expect("U was computed"),
            svd.v_t.as_ref().expect("Vᵀ was computed"),
        );
        let mut y = v_t * r;
        let mut rank = 0;
        let mut sigma_min = f64::INFINITY;
        for (k, s) in svd.singular_values.iter().enumerate() {
            if *s > tolerance {
                y[k] /= *s;
                rank += 1;
                sigma_min = sigma_min.min(*s);
            } else {
                y[k] = 0.0;
            }
        }
        let condition = if rank == 0 {
            1.0
        } else {
            sigma_max / sigma_min
        };
        (u * y, rank, condition)
    };
    let residual = (a * &coefficients - r).norm();
    if residual > RESIDUAL_TOLERANCE * rhs_norm {
        return Err(ShapingError::Unreachable { residual, rhs_norm });
    }
    Ok(EsSolution {
        pairs: system.pairs.clone(),
        coefficients_per_s: coefficients.iter().copied().collect(),
        residual,
        rhs_norm,
        rank,
        condition_number,
    })
}

/// The minimum-norm avoid coefficients of every pair of `nodes_m` (Hill, m) for the gains: checks the
/// nodes ([`check_nodes`]), assembles ([`assemble`]) and solves ([`solve_min_norm`]).
pub fn solve_avoid_coefficients(
    nodes_m: &[Vector3<f64>],
    gains: &GatherAvoidDock,
) -> Result<EsSolution, ShapingError> {
    check_nodes(nodes_m)?;
    solve_min_norm(&assemble(nodes_m, gains, &all_pairs(nodes_m.len())))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn val_empty_and_zero_systems() {
        // No free pair and a zero right-hand side (c = d = 0): exact with p empty.
        let nodes = [Vector3::zeros(), Vector3::x()];
        let gains = GatherAvoidDock {
            gather_per_s: 0.0,
            dock_per_s: 0.0,
            avoid_range_m2: 6.0,
            dock_range_m2: 6.0,
        };
        let s = solve_min_norm(&assemble(&nodes, &gains, &[])).unwrap();
        assert_eq!((s.rank, s.residual), (0, 0.0));
        // With gains but no free pair: refused.
        let gains = GatherAvoidDock {
            gather_per_s: 1.0,
            ..gains
        };
        assert!(matches!(
            solve_min_norm(&assemble(&nodes, &gains, &[])),
            Err(ShapingError::Unreachable { .. })
        ));
    }
}
