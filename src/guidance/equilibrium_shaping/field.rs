//! The kinematic building blocks of the `equilibrium-shaping` law: desired-velocity terms [m/s] of one
//! satellite, each a pure function returning the velocity **and** its Jacobians with respect to the
//! satellite's own position, a neighbour's position and time, from which the law builds the analytic
//! material derivative of its field (the feed-forward of the velocity-tracking controller).
//!
//! Every vector is in the Hill frame (x radial out, y along-track, z orbit normal) relative to the LVLH
//! origin \[m, m/s\]. Pair terms take the offset y = x_i − x_j of satellite i from neighbour j \[m\]; their
//! Jacobian with respect to the neighbour's position is minus the one with respect to the own position.
//!
//! Terms (S. Nag and L. Summerer, "Behaviour based, autonomous and distributed scatter manoeuvres for
//! satellite swarms", Acta Astronautica 82 (2013) 95–109; equation numbers are the paper's, the forms the
//! paper's garbled equations were reconstructed to are documented on each function):
//!
//! | function | term | paper |
//! | --- | --- | --- |
//! | [`pair_attraction_repulsion`] | −y (a − b e^(−‖y‖²/c)) | Eq. 1 |
//! | [`linear_source`], [`quadratic_source`], [`gaussian_source`] | −∇ of a source potential | Eq. 2 |
//! | [`threat`] | A â e^(−d²/K) | Eq. 3 |
//! | [`lennard_jones`] | −∇ ε((σ/r)¹² − 2(σ/r)⁶) | Eqs. 8–9 |
//! | [`scatter`] | κ (R² − ρ²) ê_ρ | Eq. 10 |
//! | [`viscosity`] | −ν(x) v | Eqs. 11–12 |
//! | [`gather`], [`avoid`], [`dock`] | −c (x − ξ), b y e^(−‖y‖²/k₂), −d (x − ξ) e^(−‖x − ξ‖²/k₃) | 13–15 |

use nalgebra::{Matrix3, Vector3};

/// Below this distance \[m\] a direction is taken as undefined (coincident points).
pub const DIRECTION_EPSILON_M: f64 = 1e-9;

/// Length scale of the viscosity coefficient's decay, e^(−|ζ|/2 m) \[m\] (the paper's constant 2).
pub const VISCOSITY_LENGTH_M: f64 = 2.0;

/// Fraction of σ below which the Lennard-Jones term is evaluated at r = 0.5 σ (its singularity guard).
pub const LENNARD_JONES_GUARD: f64 = 0.5;

/// One desired-velocity term of satellite i and its derivatives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FieldTerm {
    /// Desired velocity, Hill frame \[m/s\].
    pub velocity_mps: Vector3<f64>,
    /// Jacobian with respect to the satellite's own position, ∂v/∂x_i \[1/s\].
    pub d_own_per_s: Matrix3<f64>,
    /// Jacobian with respect to the neighbour's position, ∂v/∂x_j \[1/s\] (zero for terms without a
    /// neighbour).
    pub d_neighbour_per_s: Matrix3<f64>,
    /// Partial derivative with respect to time at fixed positions, ∂v/∂t \[m/s²\] (moving sources).
    pub d_time_m_s2: Vector3<f64>,
}

impl FieldTerm {
    /// The zero term.
    pub fn zero() -> Self {
        Self {
            velocity_mps: Vector3::zeros(),
            d_own_per_s: Matrix3::zeros(),
            d_neighbour_per_s: Matrix3::zeros(),
            d_time_m_s2: Vector3::zeros(),
        }
    }

    /// A term of the satellite's own position only (static source).
    fn own(velocity_mps: Vector3<f64>, d_own_per_s: Matrix3<f64>) -> Self {
        Self {
            velocity_mps,
            d_own_per_s,
            ..Self::zero()
        }
    }

    /// A pair term g(y), y = x_i − x_j, with Jacobian ∂g/∂y.
    fn pair(velocity_mps: Vector3<f64>, d_offset_per_s: Matrix3<f64>) -> Self {
        Self {
            velocity_mps,
            d_own_per_s: d_offset_per_s,
            d_neighbour_per_s: -d_offset_per_s,
            d_time_m_s2: Vector3::zeros(),
        }
    }

    /// Rate of change of the term along a motion \[m/s²\]: ∂v/∂x_i · v_i + ∂v/∂x_j · v_j + ∂v/∂t, with
    /// `own_velocity_mps` = v_i and `neighbour_velocity_mps` = v_j (Hill frame, m/s).
    pub fn material_derivative_m_s2(
        &self,
        own_velocity_mps: &Vector3<f64>,
        neighbour_velocity_mps: &Vector3<f64>,
    ) -> Vector3<f64> {
        self.d_own_per_s * own_velocity_mps
            + self.d_neighbour_per_s * neighbour_velocity_mps
            + self.d_time_m_s2
    }
}

/// Unit vector of `v` and its norm, `None` below [`DIRECTION_EPSILON_M`].
fn unit(v: &Vector3<f64>) -> Option<(Vector3<f64>, f64)> {
    let n = v.norm();
    (n >= DIRECTION_EPSILON_M).then(|| (v / n, n))
}

/// Eq. 1, the pairwise attraction–repulsion of the moving-centroid field: g(y) = −y (a − b e^(−‖y‖²/c)),
/// with y = x_i − x_j \[m\], linear attraction `a_per_s` \[1/s\], repulsion strength `b_per_s` \[1/s\] and
/// repulsion range `c_m2` \[m²\]. It is −∇J of J = a‖y‖²/2 + b c e^(−‖y‖²/c)/2 and vanishes at
/// ‖y‖ = δ when a = b e^(−δ²/c) (Eq. 4, [`super::shaping::pair_attraction_per_s`]).
pub fn pair_attraction_repulsion(
    offset_m: &Vector3<f64>,
    a_per_s: f64,
    b_per_s: f64,
    c_m2: f64,
) -> FieldTerm {
    let e = (-offset_m.norm_squared() / c_m2).exp();
    let h = a_per_s - b_per_s * e;
    // ∂g/∂y = −h I − y ∇hᵀ, ∇h = (2 b e / c) y.
    let jac =
        -h * Matrix3::identity() - (2.0 * b_per_s * e / c_m2) * offset_m * offset_m.transpose();
    FieldTerm::pair(-h * offset_m, jac)
}

/// Eq. 2's linear source s(y) = a_sᵀ y + b_s: velocity −∇s = −a_s (`gradient_m_per_s` = a_s \[m/s\]),
/// uniform, no derivatives.
pub fn linear_source(gradient_m_per_s: &Vector3<f64>) -> FieldTerm {
    FieldTerm::own(-gradient_m_per_s, Matrix3::zeros())
}

/// Eq. 2's quadratic source s(y) = A_s ‖y − c_s‖²/2 + b_s at `position_m` = y, centre `center_m` \[m\],
/// strength `strength_per_s` = A_s \[1/s\]: velocity −A_s (y − c_s) (an attractor for A_s > 0).
pub fn quadratic_source(
    position_m: &Vector3<f64>,
    center_m: &Vector3<f64>,
    strength_per_s: f64,
) -> FieldTerm {
    FieldTerm::own(
        -strength_per_s * (position_m - center_m),
        -strength_per_s * Matrix3::identity(),
    )
}

/// Eq. 2's Gaussian source s(y) = −(A_s/2) e^(−‖y − c_s‖²/l_s) + b_s at `position_m` = y, centre
/// `center_m` \[m\], strength `strength_m2_per_s` = A_s \[m²/s\], width `width_m2` = l_s \[m²\]: velocity
/// −∇s = −(A_s/l_s) e (y − c_s), an attractor for A_s > 0 and a repeller for A_s < 0. Several sources
/// add (Eq. 2).
pub fn gaussian_source(
    position_m: &Vector3<f64>,
    center_m: &Vector3<f64>,
    strength_m2_per_s: f64,
    width_m2: f64,
) -> FieldTerm {
    let s = position_m - center_m;
    let e = (-s.norm_squared() / width_m2).exp();
    let k = strength_m2_per_s / width_m2 * e;
    let jac = -k * (Matrix3::identity() - (2.0 / width_m2) * s * s.transpose());
    FieldTerm::own(-k * s, jac)
}

/// How the threat term's unit escape direction â is chosen (the `escape` key).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EscapeRule {
    /// A fixed unit vector (Hill frame): the threat's own direction of motion (`parallel`) or one common
    /// direction perpendicular to it (`perp-common`).
    Fixed(Vector3<f64>),
    /// `perp-radial`: away from the threat's line, â = unit((x − p_T) − ((x − p_T)·v̂_T) v̂_T); the
    /// `fallback` unit vector (Hill frame) when the satellite is within [`DIRECTION_EPSILON_M`] of the line.
    Radial {
        /// Used on the threat's line.
        fallback: Vector3<f64>,
    },
    /// `away`: directly away from the threat's current position, â = unit(x − p_T); the `fallback`
    /// unit vector (Hill frame) when the satellite is within [`DIRECTION_EPSILON_M`] of the threat.
    Away {
        /// Used at the threat's position.
        fallback: Vector3<f64>,
    },
}

/// Eq. 3, the threat term A â e^(−d²/K) at own position `position_m` \[m\], with threat position
/// `threat_position_m` \[m\] and velocity `threat_velocity_mps` \[m/s\] now (Hill frame), scale
/// `scale_mps` = A \[m/s\], Gaussian width `width_m2` = K = 2 (R_s/3)² \[m²\] and escape rule `escape`.
///
/// The term is a function of y = x − p_T(t) only (for `perp-radial` the projection removes the part along
/// v_T, which is the only part that changes with time; for `away` â = unit(y) itself), so
/// ∂v/∂t = −(∂v/∂x) v_T, with ∂â/∂y = (I − â âᵀ)/‖y‖ for `away`. A zero threat velocity with
/// `perp-radial` makes the projection the identity (flee straight away from the threat, as `away`).
pub fn threat(
    position_m: &Vector3<f64>,
    threat_position_m: &Vector3<f64>,
    threat_velocity_mps: &Vector3<f64>,
    scale_mps: f64,
    width_m2: f64,
    escape: &EscapeRule,
) -> FieldTerm {
    let y = position_m - threat_position_m;
    let e = (-y.norm_squared() / width_m2).exp();
    let grad_e = (-2.0 * e / width_m2) * y; // ∇e
    let (a_hat, d_a_hat) = match escape {
        EscapeRule::Fixed(a) => (*a, Matrix3::zeros()),
        EscapeRule::Radial { fallback } => {
            let projector = match unit(threat_velocity_mps) {
                Some((v_hat, _)) => Matrix3::identity() - v_hat * v_hat.transpose(),
                None => Matrix3::identity(),
            };
            match unit(&(projector * y)) {
                // ∂â/∂y = (I − â âᵀ) P / ‖P y‖.
                Some((a, q)) => (a, (Matrix3::identity() - a * a.transpose()) * projector / q),
                None => (*fallback, Matrix3::zeros()),
            }
        }
        EscapeRule::Away { fallback } => match unit(&y) {
            // ∂â/∂y = (I − â âᵀ) / ‖y‖.
            Some((a, r)) => (a, (Matrix3::identity() - a * a.transpose()) / r),
            None => (*fallback, Matrix3::zeros()),
        },
    };
    let d_own = scale_mps * (e * d_a_hat + a_hat * grad_e.transpose());
    FieldTerm {
        velocity_mps: scale_mps * e * a_hat,
        d_own_per_s: d_own,
        d_neighbour_per_s: Matrix3::zeros(),
        d_time_m_s2: -d_own * threat_velocity_mps,
    }
}

/// Largest ‖∂v/∂x‖ of the threat term over all positions for a fixed escape direction \[1/s\]:
/// A · max_d (2d/K) e^(−d²/K) = A √(2/K) e^(−1/2), at d = √(K/2).
pub fn threat_rate_bound_per_s(scale_mps: f64, width_m2: f64) -> f64 {
    scale_mps * (2.0 / width_m2).sqrt() * (-0.5f64).exp()
}

/// Eqs. 8–9 (reconstructed), the Lennard-Jones spacing term of the pair with desired distance
/// `sigma_m` = σ_ij \[m\] and depth `epsilon_m2_per_s` = ε \[m²/s\]: the velocity −∇_{x_i} V of
/// V(r) = ε((σ/r)¹² − 2(σ/r)⁶) (minimum −ε exactly at r = σ):
/// (12ε/σ) ((σ/r)¹³ − (σ/r)⁷) y/r, repulsive below σ, weakly attractive beyond (as r⁻⁷).
///
/// Singularity guard: the magnitude is evaluated at r_eff = max(r, 0.5σ) (at 0.5σ it is already
/// 96 768 ε/σ); below 0.5σ only the direction changes. Coincident satellites (r below
/// [`DIRECTION_EPSILON_M`]) get no term: the direction is undefined.
pub fn lennard_jones(offset_m: &Vector3<f64>, epsilon_m2_per_s: f64, sigma_m: f64) -> FieldTerm {
    let Some((y_hat, r)) = unit(offset_m) else {
        return FieldTerm::zero();
    };
    let guard = LENNARD_JONES_GUARD * sigma_m;
    let r_eff = r.max(guard);
    let q = sigma_m / r_eff;
    let q6 = q.powi(6);
    let q7 = q6 * q;
    let q13 = q7 * q6;
    let f = 12.0 * epsilon_m2_per_s / sigma_m * (q13 - q7);
    // f'(r) = (12ε/σ²)(−13 (σ/r)¹⁴ + 7 (σ/r)⁸) where r_eff = r, 0 where the guard holds r_eff fixed.
    let df = if r >= guard {
        12.0 * epsilon_m2_per_s / (sigma_m * sigma_m) * (-13.0 * q13 * q + 7.0 * q7 * q)
    } else {
        0.0
    };
    let radial = y_hat * y_hat.transpose();
    let jac = df * radial + (f / r) * (Matrix3::identity() - radial);
    FieldTerm::pair(f * y_hat, jac)
}

/// Eq. 10 (reconstructed), the scatter term κ (R² − ρ²) ê_ρ about the danger sphere of centre
/// `center_m` \[m\] and radius `radius_m` = R \[m\], gain `gain_per_m_s` = κ \[1/(m·s)\], at own position
/// `position_m` \[m\]: outward inside the sphere, inward outside, zero on it, no tangential part.
///
/// At the centre (ρ below [`DIRECTION_EPSILON_M`]) the direction is `fallback` (a unit vector, e.g. the
/// satellite's own node direction) and the Jacobian, singular there, is returned as zero.
pub fn scatter(
    position_m: &Vector3<f64>,
    center_m: &Vector3<f64>,
    radius_m: f64,
    gain_per_m_s: f64,
    fallback: &Vector3<f64>,
) -> FieldTerm {
    let s = position_m - center_m;
    let Some((e_rho, rho)) = unit(&s) else {
        return FieldTerm::own(
            gain_per_m_s * radius_m * radius_m * fallback,
            Matrix3::zeros(),
        );
    };
    let h = gain_per_m_s * (radius_m * radius_m - rho * rho);
    let dh = -2.0 * gain_per_m_s * rho;
    let radial = e_rho * e_rho.transpose();
    let jac = dh * radial + (h / rho) * (Matrix3::identity() - radial);
    FieldTerm::own(h * e_rho, jac)
}

/// The viscosity coefficient of Eqs. 11–12 (reconstructed) at one position: the term is −ν v, with v
/// the satellite's actual velocity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Viscosity {
    /// ν, dimensionless.
    pub coefficient: f64,
    /// ∇ν with respect to the own position \[1/m\] (zero outside the band; the jumps at the band edges,
    /// where ν steps from K_ν e^(−D/2 m) to 0, and the kink on the surface are not differentiated).
    pub gradient_per_m: Vector3<f64>,
}

impl Viscosity {
    /// The term −ν v for the actual velocity `velocity_mps` \[m/s\].
    pub fn velocity_mps(&self, velocity_mps: &Vector3<f64>) -> Vector3<f64> {
        -self.coefficient * velocity_mps
    }

    /// Its rate of change at a fixed velocity `velocity_mps` along that same velocity \[m/s²\]:
    /// −(∇ν · v) v. The part −ν v̇ is left to the caller, which knows v̇.
    pub fn material_derivative_fixed_velocity_m_s2(
        &self,
        velocity_mps: &Vector3<f64>,
    ) -> Vector3<f64> {
        -self.gradient_per_m.dot(velocity_mps) * velocity_mps
    }
}

/// Eqs. 11–12 (reconstructed): ν = K_ν e^(−|ζ|/2 m) when |ζ| < D, 0 otherwise, with ζ = R − ρ the
/// required minus the actual distance from the danger sphere's centre `center_m` \[m\] (radius `radius_m`
/// \[m\]), gain `gain` = K_ν (dimensionless) and band `band_m` = D \[m\], at own position `position_m`.
pub fn viscosity(
    position_m: &Vector3<f64>,
    center_m: &Vector3<f64>,
    radius_m: f64,
    gain: f64,
    band_m: f64,
) -> Viscosity {
    let s = position_m - center_m;
    let rho = s.norm();
    let zeta = radius_m - rho;
    if zeta.abs() >= band_m || gain == 0.0 {
        return Viscosity {
            coefficient: 0.0,
            gradient_per_m: Vector3::zeros(),
        };
    }
    let nu = gain * (-zeta.abs() / VISCOSITY_LENGTH_M).exp();
    // ∂ν/∂x = −(ν/2 m) sign(ζ) ∂ζ/∂x, ∂ζ/∂x = −ê_ρ.
    let gradient = match unit(&s) {
        Some((e_rho, _)) if zeta != 0.0 => e_rho * (nu / VISCOSITY_LENGTH_M) * zeta.signum(),
        _ => Vector3::zeros(),
    };
    Viscosity {
        coefficient: nu,
        gradient_per_m: gradient,
    }
}

/// Eq. 13, gather towards sink `sink_m` = ξ \[m\]: −c (x − ξ), `gain_per_s` = c \[1/s\]. With a uniform c
/// the sum over all N sinks equals one sink at their centroid with gain N c.
pub fn gather(position_m: &Vector3<f64>, sink_m: &Vector3<f64>, gain_per_s: f64) -> FieldTerm {
    FieldTerm::own(
        -gain_per_s * (position_m - sink_m),
        -gain_per_s * Matrix3::identity(),
    )
}

/// Eq. 14 (sign reconstructed: repulsive), avoid neighbour j: b y e^(−‖y‖²/k₂), y = x_i − x_j \[m\],
/// `gain_per_s` = b_ij \[1/s\], `range_m2` = k₂ \[m²\].
pub fn avoid(offset_m: &Vector3<f64>, gain_per_s: f64, range_m2: f64) -> FieldTerm {
    let e = (-offset_m.norm_squared() / range_m2).exp();
    let k = gain_per_s * e;
    let jac = k * (Matrix3::identity() - (2.0 / range_m2) * offset_m * offset_m.transpose());
    FieldTerm::pair(k * offset_m, jac)
}

/// Eq. 15, dock at sink `sink_m` = ξ \[m\]: −d (x − ξ) e^(−‖x − ξ‖²/k₃), `gain_per_s` = d \[1/s\],
/// `range_m2` = k₃ \[m²\].
pub fn dock(
    position_m: &Vector3<f64>,
    sink_m: &Vector3<f64>,
    gain_per_s: f64,
    range_m2: f64,
) -> FieldTerm {
    let s = position_m - sink_m;
    let k = gain_per_s * (-s.norm_squared() / range_m2).exp();
    let jac = -k * (Matrix3::identity() - (2.0 / range_m2) * s * s.transpose());
    FieldTerm::own(-k * s, jac)
}

#[cfg(test)]
mod tests {
    //! Every term's Jacobians against central finite differences of its own velocity. Step h = 1e-5 m
    //! (or s): the truncation error is O(h²·|v'''|) ≈ 1e-10 of the scale and the rounding error
    //! O(ε|v|/h) ≈ 1e-11, so 1e-7 relative to the Jacobian's largest entry (plus 1e-9 absolute) separates
    //! a correct Jacobian from a wrong term by many orders.

    use super::*;

    const H: f64 = 1e-5;

    fn assert_close(analytic: &Matrix3<f64>, numeric: &Matrix3<f64>, what: &str) {
        let scale = analytic.amax().max(numeric.amax());
        let err = (analytic - numeric).amax();
        assert!(
            err <= 1e-7 * scale + 1e-9,
            "{what}: analytic {analytic} vs finite difference {numeric} (error {err:e}, scale {scale:e})"
        );
    }

    /// ∂v/∂p by central differences of `f` at `p`.
    fn jacobian(f: &dyn Fn(&Vector3<f64>) -> Vector3<f64>, p: &Vector3<f64>) -> Matrix3<f64> {
        let mut j = Matrix3::zeros();
        for k in 0..3 {
            let mut plus = *p;
            let mut minus = *p;
            plus[k] += H;
            minus[k] -= H;
            j.set_column(k, &((f(&plus) - f(&minus)) / (2.0 * H)));
        }
        j
    }

    fn points() -> Vec<Vector3<f64>> {
        vec![
            Vector3::new(1.3, -2.1, 0.7),
            Vector3::new(-4.0, 3.5, -1.2),
            Vector3::new(0.4, 0.3, 2.9),
            Vector3::new(6.5, 1.0, -0.5),
        ]
    }

    fn check_pair(term: &dyn Fn(&Vector3<f64>) -> FieldTerm, what: &str) {
        for y in points() {
            let t = term(&y);
            let numeric = jacobian(&|p| term(p).velocity_mps, &y);
            assert_close(&t.d_own_per_s, &numeric, what);
            assert_close(&t.d_neighbour_per_s, &(-numeric), what);
        }
    }

    fn check_own(term: &dyn Fn(&Vector3<f64>) -> FieldTerm, what: &str) {
        for x in points() {
            let t = term(&x);
            let numeric = jacobian(&|p| term(p).velocity_mps, &x);
            assert_close(&t.d_own_per_s, &numeric, what);
            assert_eq!(t.d_neighbour_per_s, Matrix3::zeros(), "{what}");
        }
    }

    #[test]
    fn val_pair_terms_jacobians_match_finite_differences() {
        check_pair(
            &|y| pair_attraction_repulsion(y, 0.546474, 20.0, 10.0),
            "Eq. 1",
        );
        check_pair(&|y| avoid(y, 42.5935, 6.0), "avoid");
        // Lennard-Jones on both sides of σ and inside the guard (r < 0.5 σ = 3 m for σ = 6 m).
        check_pair(&|y| lennard_jones(y, 0.1, 6.0), "Lennard-Jones σ = 6 m");
        check_pair(
            &|y| lennard_jones(y, 0.1, 10.392),
            "Lennard-Jones σ = 10.392 m",
        );
    }

    #[test]
    fn val_own_terms_jacobians_match_finite_differences() {
        let c = Vector3::new(0.5, -0.2, 0.1);
        check_own(&|x| quadratic_source(x, &c, 0.3), "quadratic source");
        check_own(&|x| gaussian_source(x, &c, -4.0, 9.0), "Gaussian source");
        check_own(&|x| gather(x, &c, 3.214e-3), "gather");
        check_own(&|x| dock(x, &c, 40.0, 6.0), "dock");
        let fallback = Vector3::x();
        check_own(&|x| scatter(x, &c, 20.0, 5e-4, &fallback), "scatter");
        assert_eq!(linear_source(&c).velocity_mps, -c);
    }

    #[test]
    fn val_threat_jacobians_match_finite_differences() {
        let p0 = Vector3::new(1.0, -0.5, 4.0);
        let v_t = Vector3::new(0.3, 0.2, -1.0);
        let diagonal = Vector3::new(1.0, 1.0, 0.0).normalize();
        let rules = [
            (EscapeRule::Fixed(v_t.normalize()), "parallel"),
            (EscapeRule::Fixed(diagonal), "fixed diagonal"),
            (EscapeRule::Radial { fallback: diagonal }, "perp-radial"),
            (EscapeRule::Away { fallback: diagonal }, "away"),
        ];
        for (rule, what) in rules {
            for (k_m2, t_s) in [(22.22, 0.0), (88.9, 1.7)] {
                let at =
                    |x: &Vector3<f64>, t: f64| threat(x, &(p0 + v_t * t), &v_t, 40.0, k_m2, &rule);
                for x in points() {
                    let term = at(&x, t_s);
                    let numeric = jacobian(&|p| at(p, t_s).velocity_mps, &x);
                    assert_close(&term.d_own_per_s, &numeric, what);
                    let dt =
                        (at(&x, t_s + H).velocity_mps - at(&x, t_s - H).velocity_mps) / (2.0 * H);
                    let scale = term.d_time_m_s2.amax().max(dt.amax());
                    assert!(
                        (term.d_time_m_s2 - dt).amax() <= 1e-7 * scale + 1e-9,
                        "{what}: ∂v/∂t {} vs {}",
                        term.d_time_m_s2,
                        dt
                    );
                }
            }
        }
    }

    #[test]
    fn val_threat_rate_bound_is_the_largest_gradient() {
        // Along the escape direction the rank-one Jacobian's eigenvalue is −(2A e/K)(â·y); its largest
        // magnitude over y = s â is the closed-form bound, reached at s = √(K/2).
        let (a, k) = (40.0, 22.22);
        let a_hat = Vector3::z();
        let bound = threat_rate_bound_per_s(a, k);
        let mut largest: f64 = 0.0;
        for i in 0..20_001 {
            let s = i as f64 * 1e-3;
            let t = threat(
                &(a_hat * s),
                &Vector3::zeros(),
                &a_hat,
                a,
                k,
                &EscapeRule::Fixed(a_hat),
            );
            largest = largest.max(t.d_own_per_s.norm());
        }
        assert!(
            (largest - bound).abs() <= 1e-6 * bound,
            "{largest} vs {bound}"
        );
    }

    #[test]
    fn val_viscosity_gradient_matches_finite_differences() {
        let c = Vector3::zeros();
        // Inside and outside the surface, within the 0.5 m band of a 20 m sphere.
        for x in [
            Vector3::new(19.8, 0.1, -0.2),
            Vector3::new(12.0, 16.2, 0.3),
            Vector3::new(-0.1, 0.2, 19.7),
        ] {
            let nu = viscosity(&x, &c, 20.0, 1.0, 0.5);
            assert!(nu.coefficient > 0.0);
            let mut numeric = Vector3::zeros();
            for k in 0..3 {
                let mut plus = x;
                let mut minus = x;
                plus[k] += H;
                minus[k] -= H;
                numeric[k] = (viscosity(&plus, &c, 20.0, 1.0, 0.5).coefficient
                    - viscosity(&minus, &c, 20.0, 1.0, 0.5).coefficient)
                    / (2.0 * H);
            }
            assert!(
                (nu.gradient_per_m - numeric).amax() <= 1e-8,
                "{} vs {}",
                nu.gradient_per_m,
                numeric
            );
        }
        assert_eq!(
            viscosity(&Vector3::new(10.0, 0.0, 0.0), &c, 20.0, 1.0, 0.5).coefficient,
            0.0
        );
    }

    #[test]
    fn val_pair_term_vanishes_at_the_eq4_distance_and_lennard_jones_at_sigma() {
        // Eq. 1 with a = b e^(−δ²/c) is at rest at ‖y‖ = δ; Lennard-Jones at r = σ.
        for delta in [6.0, 6.0 * 3f64.sqrt(), 12.0] {
            let a = 20.0 * (-delta * delta / 10.0f64).exp();
            let y = Vector3::new(0.6, -0.8, 0.0) * delta;
            let g = pair_attraction_repulsion(&y, a, 20.0, 10.0).velocity_mps;
            assert!(
                g.norm() <= 1e-15 * delta * 20.0,
                "Eq. 1 at δ = {delta}: {g}"
            );
            let lj = lennard_jones(&y, 0.1, delta).velocity_mps;
            assert!(lj.norm() <= 1e-16, "LJ at σ = {delta}: {lj}");
        }
        // Repulsive inside σ, attractive outside.
        let y = Vector3::new(1.0, 0.0, 0.0);
        assert!(lennard_jones(&(y * 5.0), 0.1, 6.0).velocity_mps.x > 0.0);
        assert!(lennard_jones(&(y * 7.0), 0.1, 6.0).velocity_mps.x < 0.0);
        // The guard: at r = 0.5σ the speed is 96 768 ε/σ.
        let v = lennard_jones(&(y * 3.0), 0.1, 6.0).velocity_mps.norm();
        assert!((v - 96_768.0 * 0.1 / 6.0).abs() <= 1e-9 * v, "{v}");
    }
}
