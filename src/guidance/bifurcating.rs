//! The `bifurcating` law: cluster formation and reconfiguration by a bifurcating potential field
//! (W. Gao, K. Li, C. Wei, *Aerospace* 9(3):137, 2022), as restated in
//! `docs/methods/bifurcating.md` (cited below as the "method page").
//!
//! Each satellite i computes, from its own state relative to the formation centre (the LVLH origin: the
//! virtual reference orbit, or a member used as "target spacecraft", method page §3.5) and from the neighbours
//! it senses within the avoidance radius s:
//!
//! u_i = (F_f(q_i) + F_c,i − k_v v_i) / m_i   (method page §3.1, paper Eq. 10 read in the rotating frame)
//!
//! * F_f = −∇U_f, the formation term of the scalar bifurcating potential φ(e) = |e|³/3 − μe²/2
//!   (method page §3.3, Eqs. 15–21) applied to a shape coordinate e (method page §3.4):
//!   - 2-D (Eq. 22): ρ = √(b²x² + a²z²), e = ρ − a·b·r, U_f = k_f (φ(e) + σ y²);
//!   - 3-D (Eqs. 24–25): d = √(b²c²x² + a²c²y² + a²b²z²), e = d − a·b·c·r, U_f = k_f φ(e);
//!
//!   with (x, y, z) Gao `o-xyz` coordinates (x along-track, y minus orbit normal, z nadir);
//! * F_c = Σ_j k_c (s − d_ij) (q_i − q_j)/d_ij over neighbours with d_ij ≤ s: the bounded spring
//!   repulsion of method page §3.2 (the paper's Eqs. 12–14 read consistently);
//! * v_i is the rotating-frame relative velocity (method page §3.1), the one the engine's view carries;
//! * optional feed-forward cancelling the CW natural acceleration (`cw_feedforward`, default off).
//!
//! Singular points (method page §3.4): when a·b·r = 0 (resp. a·b·c·r = 0) the smooth form
//! ∇U_f = k_f (ρ − μ)(b²x, 0, a²z) (+ the σ term) is evaluated, with no division; otherwise ∇ρ is
//! regularised as (b²x, 0, a²z)/max(ρ, ε), ε = 1 mm. Coincident satellites (d_ij = 0) are pushed apart
//! along ±x (along-track) by index order, so that runs stay reproducible.
//!
//! The law keeps no slot assignment: a reconfiguration is an event of the timeline that replaces the
//! shape parameters; every satellite then slides down the new potential from wherever it is.
//!
//! Units: SI inside (m, kg, s). The paper's km-based gains convert as k_f \[kg/(m·s²)\] = 10⁻³ ×
//! k_f \[kg/(km·s²)\]; k_c \[kg/s²\] and k_v \[kg/s\] keep their numbers; lengths ×1000 (method page §1.2).

use crate::invalid::Invalid;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::orbit::{gao_to_hill, hill_to_gao};
use crate::relative::Hcw;
use crate::swarm::{
    Better, Diagnostics, GuidanceLaw, Headline, LawContext, LawError, Reports, SatelliteView,
    SwarmFacts, SwarmView, TargetFormation,
};

/// Regularisation radius ε of the shape coordinate at the cone point ρ = 0 (resp. d = 0) \[m\]
/// (method page §3.4: 10⁻⁶ km).
pub const REGULARISATION_M: f64 = 1e-3;

/// Fraction of the shape's size within which every satellite must sit for the shape to count as reached
/// (method page §6, O6: "max radial error and |y| below 5 % of r").
pub const SHAPE_REACHED_FRACTION: f64 = 0.05;

/// Points per target ring of a 2-D shape in [`BifurcatingParameters::target_points_hill_m`] (one every 5°).
pub const TARGET_RING_POINTS: usize = 72;

/// Points per target surface of a 3-D shape in [`BifurcatingParameters::target_points_hill_m`].
pub const TARGET_SURFACE_POINTS: usize = 400;

/// Which potential: the in-plane one with an out-of-plane well, or the stereo one.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Dimension {
    /// 2-D potential (paper Eq. 22): shapes in the orbital plane (Gao x–z), out-of-plane well σ y².
    #[default]
    #[serde(rename = "2d")]
    Planar,
    /// 3-D potential (paper Eqs. 24–25): surfaces and volumes, shape factor c used.
    #[serde(rename = "3d")]
    Spatial,
}

/// Parameters of the `bifurcating` law (SI; the paper's km-based values convert as method page §1.2 says).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BifurcatingParameters {
    /// Formation gain k_f \[kg/(m·s²)\] (paper: kg/(km·s²), ×10⁻³); finite, > 0.
    pub k_f_kg_per_m_s2: f64,
    /// Collision-avoidance gain k_c \[kg/s² = N/m\]; finite, >= 0.
    pub k_c_kg_per_s2: f64,
    /// Velocity damping k_v \[kg/s = N·s/m\] on the rotating-frame relative velocity; finite, >= 0.
    pub k_v_kg_per_s: f64,
    /// Avoidance radius s \[m\]: neighbours closer than this repel; finite, >= 0 and not above the
    /// sensing range.
    pub avoidance_radius_m: f64,
    /// `"2d"` (default) or `"3d"`.
    #[serde(default)]
    pub dimension: Dimension,
    /// Shape factor a (dimensionless, weights z in ρ and d); finite, >= 0.
    pub a: f64,
    /// Shape factor b (dimensionless, weights x); finite, >= 0.
    pub b: f64,
    /// Shape factor c (dimensionless, 3-D only, weights y; default 1); finite, >= 0.
    #[serde(default = "default_c")]
    pub c: f64,
    /// Radius parameter r \[m\] (0: filled shapes); finite, >= 0.
    pub radius_m: f64,
    /// Bifurcation parameter μ \[m\]: < 0 one shell, > 0 two shells e = ±μ; finite, ≠ 0.
    pub mu_m: f64,
    /// Out-of-plane stiffness σ \[m\] of the 2-D potential's well σ y² (never given by the paper; default
    /// 10 km, method page §4.1); finite, > 0.
    #[serde(default = "default_sigma")]
    pub sigma_m: f64,
    /// Cancel the CW natural acceleration (default false: the paper does not, method page §3.1).
    #[serde(default)]
    pub cw_feedforward: bool,
}

fn default_c() -> f64 {
    1.0
}

fn default_sigma() -> f64 {
    10_000.0
}

/// The set the formation term drives satellites to (method page §3.4, Tables 1–2 corrected).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TargetSet {
    /// One or two level sets of the shape coordinate: e = 0 (μ < 0) or e = ±μ (μ > 0): rings, ellipses,
    /// lines, surfaces.
    LevelSets,
    /// μ < 0 with r = 0 and every shape factor non-zero: the potential's minimum is the centre point and
    /// the filled shape (disk, ellipse disk, ball, solid ellipsoid) is made by the repulsion; no level
    /// set to measure against.
    Filled,
}

/// How far a swarm is from the law's target shape (method page §6, O6/O9–O12).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeError {
    /// Largest distance of a satellite from the nearest stable level set, to first order |Δe|/‖∇e‖ \[m\]
    /// (`None` for filled shapes).
    pub max_residual_m: Option<f64>,
    /// Largest |y| (Gao, out of the orbital plane) \[m\] (2-D potential; 0 in 3-D).
    pub max_out_of_plane_m: f64,
    /// Size the 5 % criterion is relative to: smallest semi-axis of the inner (or only) target level set
    /// \[m\] (`None` for filled shapes and for the single line/plane, which have no size).
    pub size_m: Option<f64>,
    /// Largest shape coordinate ρ (2-D) or d (3-D) over the satellites \[m\]: the level set enclosing all.
    pub max_shape_coordinate_m: f64,
}

impl ShapeError {
    /// Whether both the residual and the out-of-plane error are within [`SHAPE_REACHED_FRACTION`] of the
    /// size (`None` when the shape has no size).
    pub fn reached(&self) -> Option<bool> {
        let size = self.size_m?;
        let residual = self.max_residual_m?;
        let limit = SHAPE_REACHED_FRACTION * size;
        Some(residual <= limit && self.max_out_of_plane_m <= limit)
    }
}

impl BifurcatingParameters {
    /// Checks every range and refuses parameter sets that make no formation (method page §3.4).
    pub fn check(&self) -> Result<(), LawError> {
        let invalid = |invalid: Invalid| LawError::invalid("bifurcating", invalid);
        let finite_at_least = |key: &str, v: f64, min: f64, strict: bool| {
            let ok = v.is_finite() && if strict { v > min } else { v >= min };
            if ok {
                Ok(())
            } else {
                Err(invalid(Invalid::range(
                    key,
                    v,
                    format!("finite, {} {min}", if strict { ">" } else { ">=" }),
                )))
            }
        };
        finite_at_least("k_f_kg_per_m_s2", self.k_f_kg_per_m_s2, 0.0, true)?;
        finite_at_least("k_c_kg_per_s2", self.k_c_kg_per_s2, 0.0, false)?;
        finite_at_least("k_v_kg_per_s", self.k_v_kg_per_s, 0.0, false)?;
        finite_at_least("avoidance_radius_m", self.avoidance_radius_m, 0.0, false)?;
        finite_at_least("a", self.a, 0.0, false)?;
        finite_at_least("b", self.b, 0.0, false)?;
        finite_at_least("c", self.c, 0.0, false)?;
        finite_at_least("radius_m", self.radius_m, 0.0, false)?;
        finite_at_least("sigma_m", self.sigma_m, 0.0, true)?;
        if !(self.mu_m.is_finite() && self.mu_m != 0.0) {
            return Err(invalid(Invalid::range(
                "mu_m",
                self.mu_m,
                "finite, != 0; mu = 0 leaves no stiffness at the \
                 target set, phi''(0) = 0",
            )));
        }
        let zeros = self.factors().iter().filter(|f| **f == 0.0).count();
        if zeros > 1 {
            return Err(invalid(Invalid::keys("shape factors", format!(
                "shape factors (a, b{}) = ({}, {}{}) have {zeros} zeros: the shape coordinate is then \
                 zero everywhere in the formation plane and makes no formation (allowed: at most one \
                 zero)",
                if self.dimension == Dimension::Spatial { ", c" } else { "" },
                self.a,
                self.b,
                if self.dimension == Dimension::Spatial {
                    format!(", {}", self.c)
                } else {
                    String::new()
                }
            ), "")));
        }
        let offset = self.shape_offset_m();
        if offset > 0.0 && self.mu_m >= offset {
            return Err(invalid(Invalid::keys(
                "mu_m",
                format!(
                "mu_m = {} m >= the shape offset {} m (a·b·r, or a·b·c·r in 3-D): the inner shell \
                 e = -mu would have a negative radius and the centre becomes a potential minimum \
                 (allowed: mu_m < {offset} m, or radius_m = 0)",
                self.mu_m, offset
            ),
                "",
            )));
        }
        Ok(())
    }

    /// The shape factors that enter the shape coordinate: (a, b) in 2-D, (a, b, c) in 3-D.
    fn factors(&self) -> Vec<f64> {
        match self.dimension {
            Dimension::Planar => vec![self.a, self.b],
            Dimension::Spatial => vec![self.a, self.b, self.c],
        }
    }

    /// Offset of the shape coordinate, a·b·r (2-D) or a·b·c·r (3-D) \[m\]: e = ρ − offset.
    pub fn shape_offset_m(&self) -> f64 {
        match self.dimension {
            Dimension::Planar => self.a * self.b * self.radius_m,
            Dimension::Spatial => self.a * self.b * self.c * self.radius_m,
        }
    }

    /// Per-axis weights w of the shape coordinate ρ² = Σ w_k q_k² (Gao axes x, y, z): (b², 0, a²) in 2-D,
    /// (b²c², a²c², a²b²) in 3-D.
    fn weights(&self) -> Vector3<f64> {
        let (a2, b2, c2) = (self.a * self.a, self.b * self.b, self.c * self.c);
        match self.dimension {
            Dimension::Planar => Vector3::new(b2, 0.0, a2),
            Dimension::Spatial => Vector3::new(b2 * c2, a2 * c2, a2 * b2),
        }
    }

    /// What the potential drives satellites to.
    pub fn target_set(&self) -> TargetSet {
        let all_nonzero = self.factors().iter().all(|f| *f > 0.0);
        if self.mu_m < 0.0 && self.radius_m == 0.0 && all_nonzero {
            TargetSet::Filled
        } else {
            TargetSet::LevelSets
        }
    }

    /// Points on the stable level sets the formation term drives satellites to, Hill frame relative to the
    /// formation centre \[m\]: [`TARGET_RING_POINTS`] evenly spaced in angle on each ring or ellipse of
    /// the 2-D potential (ρ = a·b·r for μ < 0; ρ = a·b·r ± μ, or ρ = μ when r = 0, for μ > 0), or
    /// [`TARGET_SURFACE_POINTS`] on each ellipsoid of the 3-D potential (a Fibonacci lattice mapped to
    /// d = the same values). `None` for the filled shapes (no level set) and for shapes with a zero shape
    /// factor (lines, planes: unbounded sets).
    pub fn target_points_hill_m(&self) -> Option<Vec<Vector3<f64>>> {
        if self.target_set() == TargetSet::Filled || self.factors().contains(&0.0) {
            return None;
        }
        let offset = self.shape_offset_m();
        let levels: Vec<f64> = match (self.mu_m > 0.0, offset > 0.0) {
            (false, _) => vec![offset],
            (true, true) => vec![offset - self.mu_m, offset + self.mu_m],
            (true, false) => vec![self.mu_m],
        };
        let (a, b, c) = (self.a, self.b, self.c);
        let mut points = Vec::new();
        for rho in levels {
            match self.dimension {
                Dimension::Planar => {
                    for k in 0..TARGET_RING_POINTS {
                        let theta = std::f64::consts::TAU * k as f64 / TARGET_RING_POINTS as f64;
                        let q = Vector3::new(rho / b * theta.cos(), 0.0, rho / a * theta.sin());
                        points.push(gao_to_hill(&q));
                    }
                }
                Dimension::Spatial => {
                    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
                    let n = TARGET_SURFACE_POINTS as f64;
                    for k in 0..TARGET_SURFACE_POINTS {
                        let uz = 1.0 - (2.0 * k as f64 + 1.0) / n;
                        let r = (1.0 - uz * uz).sqrt();
                        let phi = golden * k as f64;
                        let q = Vector3::new(
                            rho * r * phi.cos() / (b * c),
                            rho * r * phi.sin() / (a * c),
                            rho * uz / (a * b),
                        );
                        points.push(gao_to_hill(&q));
                    }
                }
            }
        }
        Some(points)
    }

    /// Formation potential U_f at Gao position `q_gao_m` \[m\], in joules (method page §3.4).
    pub fn formation_potential_j(&self, q_gao_m: &Vector3<f64>) -> f64 {
        let rho = self.weights().dot(&q_gao_m.component_mul(q_gao_m)).sqrt();
        let e = rho - self.shape_offset_m();
        let phi = e.abs().powi(3) / 3.0 - self.mu_m * e * e / 2.0; // φ(e), method page §3.3
        let well = match self.dimension {
            Dimension::Planar => self.sigma_m * q_gao_m.y * q_gao_m.y, // σ y², Eq. 22
            Dimension::Spatial => 0.0,
        };
        self.k_f_kg_per_m_s2 * (phi + well)
    }

    /// Formation force F_f = −∇U_f at Gao position `q_gao_m` \[m\], Gao frame \[N\], with the singular
    /// point handled as method page §3.4 says.
    pub fn formation_force_gao_n(&self, q_gao_m: &Vector3<f64>) -> Vector3<f64> {
        let w = self.weights();
        let g = w.component_mul(q_gao_m); // ρ ∇ρ = (w_x x, w_y y, w_z z)
        let rho = w.dot(&q_gao_m.component_mul(q_gao_m)).sqrt();
        let offset = self.shape_offset_m();
        // φ'(e) ∇ρ, with φ'(e) = e(|e| − μ).
        let shape_gradient = if offset == 0.0 {
            // e = ρ, so φ'(e)/ρ = ρ − μ: smooth, no division.
            g * (rho - self.mu_m)
        } else {
            let e = rho - offset;
            g * (e * (e.abs() - self.mu_m) / rho.max(REGULARISATION_M))
        };
        let well_gradient = match self.dimension {
            Dimension::Planar => Vector3::new(0.0, 2.0 * self.sigma_m * q_gao_m.y, 0.0), // ∇(σ y²)
            Dimension::Spatial => Vector3::zeros(),
        };
        -self.k_f_kg_per_m_s2 * (shape_gradient + well_gradient)
    }

    /// Largest curvature of U_f over the region the formation occupies, |e| ≤ |μ| + offset: the stiffness
    /// k_f (φ''(e)·max w + 2σ) with φ''(e) = 2|e| − μ \[N/m\]. The inward cone at the regularised centre
    /// (an unstable, repelling point) is excluded: it is not a closed-loop rate to resolve.
    fn formation_stiffness_n_per_m(&self) -> f64 {
        let e_max = self.mu_m.abs() + self.shape_offset_m();
        let phi2 = 2.0 * e_max - self.mu_m;
        let w = self.weights();
        let w_max = w.x.max(w.y).max(w.z);
        let well = match self.dimension {
            Dimension::Planar => 2.0 * self.sigma_m,
            Dimension::Spatial => 0.0,
        };
        self.k_f_kg_per_m_s2 * (phi2 * w_max + well)
    }

    /// Shape error of satellites at Gao positions `positions_gao_m` \[m\] relative to the formation centre
    /// (method page §6: residual to the nearest stable level set, out-of-plane error, size for the 5 % test).
    pub fn shape_error(&self, positions_gao_m: &[Vector3<f64>]) -> ShapeError {
        let w = self.weights();
        let offset = self.shape_offset_m();
        let mu = self.mu_m;
        let target = self.target_set();
        let w_nonzero_min = [w.x, w.y, w.z]
            .into_iter()
            .filter(|v| *v > 0.0)
            .fold(f64::INFINITY, f64::min);
        let mut max_residual: f64 = 0.0;
        let mut max_y: f64 = 0.0;
        let mut max_rho: f64 = 0.0;
        for q in positions_gao_m {
            let rho = w.dot(&q.component_mul(q)).sqrt();
            max_rho = max_rho.max(rho);
            if self.dimension == Dimension::Planar {
                max_y = max_y.max(q.y.abs());
            }
            let e = rho - offset;
            // Distance in e to the nearest stable level set: e = 0 (μ < 0) or e = ±μ (μ > 0).
            let de = if mu < 0.0 {
                e.abs()
            } else {
                (e - mu).abs().min((e + mu).abs())
            };
            // First-order distance |Δe| / ‖∇ρ‖, ‖∇ρ‖ = ‖w∘q‖/ρ; at the centre use the smallest slope.
            let slope = if rho > REGULARISATION_M {
                w.component_mul(q).norm() / rho
            } else {
                w_nonzero_min.sqrt()
            };
            max_residual = max_residual.max(de / slope);
        }
        // Inner (or only) shell: ρ_in = offset − μ (two shells about a ring), μ (two shells about the
        // centre, offset = 0), or offset (one shell); its smallest semi-axis is ρ_in / max √w_k.
        let rho_inner = if mu > 0.0 {
            if offset > 0.0 {
                offset - mu
            } else {
                mu
            }
        } else {
            offset
        };
        let w_max = w.x.max(w.y).max(w.z);
        let size =
            (target == TargetSet::LevelSets && rho_inner > 0.0).then(|| rho_inner / w_max.sqrt());
        ShapeError {
            max_residual_m: (target == TargetSet::LevelSets).then_some(max_residual),
            max_out_of_plane_m: max_y,
            size_m: size,
            max_shape_coordinate_m: max_rho,
        }
    }
}

/// The `bifurcating` law.
#[derive(Clone, Debug)]
pub struct Bifurcating {
    parameters: BifurcatingParameters,
    /// Sensing range of the swarm \[m\], known once the law has started (the avoidance radius must not
    /// exceed it: farther neighbours are never sensed).
    sensing_range_m: Option<f64>,
    /// Time-to-shape bookkeeping across recordings: when the current shape was commanded \[s\] (`None`
    /// until the first recording after a start or a reconfiguration) and when it was first reached \[s\].
    shape_commanded_at_s: Option<f64>,
    shape_reached_at_s: Option<f64>,
}

/// Metric columns of the law in `metrics.csv`.
const METRIC_NAMES: &[&str] = &[
    "shape_max_residual_m",
    "shape_max_out_of_plane_m",
    "shape_reached",
];

impl Bifurcating {
    /// Builds the law, checking the parameters.
    pub fn new(parameters: BifurcatingParameters) -> Result<Self, LawError> {
        parameters.check()?;
        Ok(Self {
            parameters,
            sensing_range_m: None,
            shape_commanded_at_s: None,
            shape_reached_at_s: None,
        })
    }

    /// Shape error of the live satellites of a swarm (positions converted to Gao's o-xyz).
    fn swarm_shape_error(&self, swarm: &SwarmView<'_>) -> ShapeError {
        let positions: Vec<Vector3<f64>> = swarm
            .relative_states
            .iter()
            .zip(swarm.active)
            .filter(|(_, a)| **a)
            .map(|(s, _)| hill_to_gao(&s.position_m))
            .collect();
        self.parameters.shape_error(&positions)
    }

    /// Time from the last shape command (start or reconfiguration) to the first recording at which the
    /// 5 % criterion held \[s\], if it has been reached.
    pub fn time_to_shape_s(&self) -> Option<f64> {
        Some(self.shape_reached_at_s? - self.shape_commanded_at_s?)
    }

    /// The current parameters.
    pub fn parameters(&self) -> &BifurcatingParameters {
        &self.parameters
    }

    fn check_range(parameters: &BifurcatingParameters, range: f64) -> Result<(), LawError> {
        match range {
            range if parameters.avoidance_radius_m > range => Err(LawError::invalid(
                "bifurcating",
                Invalid::new(
                    "avoidance_radius_m",
                    format!("{} m", parameters.avoidance_radius_m),
                    format!(
                        "exceeds the sensing range {range} m: neighbours between the two would be \
                         missed"
                    ),
                    "<= sensing.range_m",
                ),
            )),
            _ => Ok(()),
        }
    }

    /// Collision-avoidance force F_c on satellite `satellite`, Hill frame \[N\] (method page §3.2).
    fn avoidance_force_hill_n(&self, satellite: &SatelliteView<'_>) -> Vector3<f64> {
        let p = &self.parameters;
        let s = p.avoidance_radius_m;
        let mut force = Vector3::zeros();
        if s == 0.0 || p.k_c_kg_per_s2 == 0.0 {
            return force;
        }
        let id = satellite.id();
        // Only the neighbours within s (<= the sensing range, checked when the law starts) push.
        satellite.for_each_neighbour_within(s, |nb| {
            let d = nb.distance_m;
            if d > 0.0 {
                // k_c (s − d) (q_i − q_j)/d, with q_i − q_j = −offset.
                force -= nb.offset_m * (p.k_c_kg_per_s2 * (s - d) / d);
            } else {
                // Coincident: push along ±x_Gao (Hill +y, along-track) by index order, magnitude k_c s;
                // opposite for the pair, so Newton's third law still holds.
                let sign = if id < nb.id { 1.0 } else { -1.0 };
                force += gao_to_hill(&Vector3::new(sign * p.k_c_kg_per_s2 * s, 0.0, 0.0));
            }
        });
        force
    }
}

impl GuidanceLaw for Bifurcating {
    type State = ();
    type Parameters = BifurcatingParameters;
    crate::capabilities!(Reports, Diagnostics, TargetFormation);

    fn name(&self) -> &'static str {
        "bifurcating"
    }

    fn initialise(&mut self, swarm: &SwarmView<'_>, _states: &mut [()]) -> Result<(), LawError> {
        self.sensing_range_m = Some(swarm.shared.sensing_range_m);
        self.check_swarm(&SwarmFacts::of(swarm))
    }

    fn check_swarm(&self, swarm: &SwarmFacts) -> Result<(), LawError> {
        Self::check_range(&self.parameters, swarm.sensing_range_m)
    }

    fn command(
        &self,
        satellite: &SatelliteView<'_>,
        _state: &(),
        _context: &LawContext,
    ) -> Vector3<f64> {
        let p = &self.parameters;
        let own = satellite.own_state();
        let formation = gao_to_hill(&p.formation_force_gao_n(&hill_to_gao(&own.position_m)));
        let damping = -p.k_v_kg_per_s * own.velocity_mps;
        let mut u =
            (formation + self.avoidance_force_hill_n(satellite) + damping) / satellite.mass_kg();
        if p.cw_feedforward {
            let hcw = Hcw::new(satellite.shared().mean_motion_rad_s);
            u -= hcw.natural_acceleration_m_s2(&own.position_m, &own.velocity_mps);
        }
        u
    }

    fn set_parameters(&mut self, parameters: &BifurcatingParameters) -> Result<(), LawError> {
        parameters.check()?;
        if let Some(range) = self.sensing_range_m {
            Self::check_range(parameters, range)?;
        }
        self.parameters = parameters.clone();
        // A new shape: time-to-shape restarts at the next recording.
        self.shape_commanded_at_s = None;
        self.shape_reached_at_s = None;
        Ok(())
    }

    /// Largest |root| of m s² + k_v s + K = 0, K = the formation stiffness over the occupied region plus
    /// 12 k_c (the repulsion's curvature k_c per neighbour, for a satellite's close neighbours in 3-D).
    fn fastest_rate_per_s(&self, mass_kg: f64) -> Option<f64> {
        let p = &self.parameters;
        let c = p.k_v_kg_per_s / mass_kg;
        let k = (p.formation_stiffness_n_per_m() + 12.0 * p.k_c_kg_per_s2) / mass_kg;
        let disc = c * c - 4.0 * k;
        Some(if disc > 0.0 {
            0.5 * (c + disc.sqrt())
        } else {
            k.sqrt()
        })
    }
}

/// The `bifurcating` law's results (`summary.json` `law`; method page §6), over live satellites.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BifurcatingResults {
    /// From the last shape command to the first recording meeting the 5 % criterion \[s\] (null if
    /// not reached; resolution = the recording interval).
    pub time_to_shape_s: Option<f64>,
    /// Final largest distance from the nearest stable level set \[m\] ([`ShapeError::max_residual_m`]).
    pub shape_max_residual_m: Option<f64>,
    /// Final largest out-of-plane distance \[m\] ([`ShapeError::max_out_of_plane_m`]).
    pub shape_max_out_of_plane_m: f64,
    /// The size the 5 % criterion is relative to \[m\] ([`ShapeError::size_m`]).
    pub shape_size_m: Option<f64>,
    /// Whether the final shape meets the 5 % criterion (null where the shape has no size).
    pub shape_reached: Option<bool>,
    /// Final largest shape coordinate \[m\] ([`ShapeError::max_shape_coordinate_m`]).
    pub shape_max_coordinate_m: f64,
}

impl Reports<()> for Bifurcating {
    type Results = BifurcatingResults;

    fn headlines(&self) -> &'static [Headline] {
        const HEADLINES: &[Headline] = &[
            Headline::new("time_to_shape_s", "time to shape", "s", Better::Lower),
            Headline::new(
                "shape_max_residual_m",
                "final shape residual",
                "m",
                Better::Lower,
            ),
        ];
        HEADLINES
    }

    /// Final shape error (method page §6): `shape_max_residual_m`, `shape_max_out_of_plane_m`, `shape_size_m`,
    /// `shape_reached` (5 % criterion) and `shape_max_coordinate_m`, over live satellites, and
    /// `time_to_shape_s` (from the last shape command to the first recording meeting the 5 % criterion;
    /// null if not reached; resolution = the recording interval).
    fn results(&self, swarm: &SwarmView<'_>, _states: &[()]) -> BifurcatingResults {
        let error = self.swarm_shape_error(swarm);
        BifurcatingResults {
            time_to_shape_s: self.time_to_shape_s(),
            shape_max_residual_m: error.max_residual_m,
            shape_max_out_of_plane_m: error.max_out_of_plane_m,
            shape_size_m: error.size_m,
            shape_reached: error.reached(),
            shape_max_coordinate_m: error.max_shape_coordinate_m,
        }
    }
}

impl Diagnostics<()> for Bifurcating {
    fn metric_names(&self) -> &'static [&'static str] {
        METRIC_NAMES
    }

    /// Shape residual, out-of-plane error and whether the 5 % criterion holds (1 or 0; NaN where the
    /// shape has no size), and the time-to-shape bookkeeping.
    fn record_metrics(&mut self, swarm: &SwarmView<'_>, _states: &[()], values: &mut [f64]) {
        let error = self.swarm_shape_error(swarm);
        let now = swarm.shared.time_s;
        let commanded = *self.shape_commanded_at_s.get_or_insert(now);
        let reached = error.reached();
        if reached == Some(true) && self.shape_reached_at_s.is_none() && now >= commanded {
            self.shape_reached_at_s = Some(now);
        }
        values[0] = error.max_residual_m.unwrap_or(f64::NAN);
        values[1] = error.max_out_of_plane_m;
        values[2] = reached.map_or(f64::NAN, |r| if r { 1.0 } else { 0.0 });
    }
}

impl TargetFormation for Bifurcating {
    /// The stable level sets of the current shape ([`BifurcatingParameters::target_points_hill_m`]).
    fn target_formation_hill_m(&self) -> Option<Vec<Vector3<f64>>> {
        self.parameters.target_points_hill_m()
    }
}
