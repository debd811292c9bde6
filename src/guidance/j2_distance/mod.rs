//! The `j2-distance` law: the distance-based relative orbital stabiliser of Takahashi & Sakai under J2
//! (main, Eq. 15) and the opposing baseline (Eq. 16), with the barrier s(r), the practical gain design,
//! actuation bound and DT grouping.
//!
//! Source: `docs/methods/j2-distance.md` (the "method page"): §3 (parameters C₁…C₆, via
//! [`crate::relative::j2_averaged`]), §5 (plane targets), §6.3 (antisymmetric pair terms), §7.1 (barrier,
//! clamped), §7.2 (distance function with (ϱ, ς, τ) = (2c₊, 0, 1)), §7.3 (Eq. 15), §7.4 (Eq. 16), §7.6
//! (gain design from the Laplacian eigenvalues, γ_B cap; or the §4.1 preset), §7.7 (norm saturation
//! ‖f‖ ≤ f̄), §9 (grouping, [`grouping`]), and §9.6, an opt-in extension beyond the paper
//! (`preserve_connectivity`: the grouping never splits the communication graph).
//!
//! Per satellite j, with C_jk the parameters of x_j − x_k (both relative to the LVLH origin, rotating-frame
//! velocities, Hill frame) and k over j's neighbours in the current edge set that j can sense:
//! u_j = Σ_k u_{j←k}(C_jk), then u_j ← u_j min(1, f̄/(m_j‖u_j‖)).
//!
//! **Centralised part.** The neighbour sets come from Algorithm 1, which needs the whole swarm: it runs as
//! the engine's periodic centralised step on the schedule of method page §9.5 (5, 10, 20, 40 min per quarter of
//! the schedule's end time), or once at the start. The gains of §7.6 are recomputed at each grouping from
//! the Laplacian's eigenvalues, also centrally. The control itself is decentralised: each satellite uses
//! only its neighbours' relative states and these broadcast quantities.

pub mod grouping;

use crate::invalid::Invalid;
use std::sync::Arc;

use nalgebra::{DMatrix, Matrix3, Vector3, Vector6};
use serde::{Deserialize, Serialize};

use crate::orbit::RelativeStateHill;
use crate::relative::j2_averaged::{
    connectable_time_s, z_frequency_feedforward_m_s2, AveragedJ2, OrbitParameters, SwarmPlane,
};
use crate::swarm::{
    Better, Centralised, Diagnostics, GuidanceLaw, Headline, LawContext, LawError, Reports,
    SatelliteView, SwarmView,
};

use grouping::{group, Components, GroupingSettings, Node};

/// Which stabiliser.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Variant {
    /// Main stabiliser u^main (Eq. 15): drift C₁ removed by along-track thrust, offset C₄ by radial thrust.
    #[default]
    Main,
    /// Opposing stabiliser u^opp (Eq. 16): C₄ errors also fed into along-track thrust (uses drift).
    Opp,
}

/// How the gains γ_B, ψ, f₀, g₀ are set.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum GainDesign {
    /// Method page §7.6: from λ₂ and λ_max of the current Laplacian at every grouping, with the γ_B cap.
    #[default]
    Theorem,
    /// The paper's §4.1 preset (for k_B = 0): γ_B = 1, ψ = 0, g₀ = 0, f₀ = −ε₂/(2k_A).
    Preset,
}

/// When the (centralised) grouping runs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum GroupingSchedule {
    /// At the start, then every `grouping_first_period_s`, doubled at each quarter of
    /// `grouping_schedule_end_s` (method page §9.5).
    #[default]
    Growing,
    /// Once, at the start (fixed grouping of the §4.1 comparison).
    Once,
}

/// Parameters of the `j2-distance` law (defaults: method page §10.1).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct J2DistanceParameters {
    /// Stabiliser: `main` (Eq. 15, default) or `opp` (Eq. 16).
    #[serde(default)]
    pub variant: Variant,
    /// k_A \[1/s\] (default 1.5e-2, paper).
    #[serde(default = "default_k_a")]
    pub gain_a_per_s: f64,
    /// k_B \[1/s\], distance-loop gain (default 1.5e-2; 0 disables distance control).
    #[serde(default = "default_k_a")]
    pub gain_b_per_s: f64,
    /// k_z \[1/s\], cross-track gain (default 5e-3).
    #[serde(default = "default_k_z")]
    pub gain_z_per_s: f64,
    /// γ_A \[-\], C₄ stiffness (default 10).
    #[serde(default = "default_gamma_a")]
    pub gamma_a: f64,
    /// Gain design: `theorem` (default) or `preset`.
    #[serde(default)]
    pub gain_design: GainDesign,
    /// α_a \[-\] of the theorem design (default 0.5).
    #[serde(default = "default_alpha_a")]
    pub gain_alpha_a: f64,
    /// α_b \[-\] of the theorem design (default 1).
    #[serde(default = "default_one")]
    pub gain_alpha_b: f64,
    /// Cap γ_B,max \[-\] (default 1).
    #[serde(default = "default_one")]
    pub gamma_b_max: f64,
    /// Plane angle Θ_P \[deg\], in (0, 90] (default 30).
    #[serde(default = "default_theta_p")]
    pub plane_theta_p_deg: f64,
    /// Plane angle Θ_z-xy \[deg\], in (−90, 90) (default 0).
    #[serde(default)]
    pub plane_theta_zxy_deg: f64,
    /// Average (RMS over one period) neighbour distance r_avg \[m\] (default 0.5).
    #[serde(default = "default_r_avg")]
    pub average_distance_m: f64,
    /// Barrier lower bound r̲_xy \[m\] (default 0.1, the satellite size).
    #[serde(default = "default_r_low")]
    pub min_amplitude_m: f64,
    /// Barrier clamp margin η as a fraction of r_xyd − r̲_xy \[-\] (default 0.05).
    #[serde(default = "default_clamp")]
    pub barrier_clamp_fraction: f64,
    /// Controllable range r_s \[m\] (default 1): grouping and T̂_conn.
    #[serde(default = "default_one")]
    pub controllable_range_m: f64,
    /// Maximum force f̄ \[N\] (default 5e-7), norm saturation.
    #[serde(default = "default_max_force")]
    pub max_force_n: f64,
    /// Followers per leader n̄_f (default 5).
    #[serde(default = "default_followers")]
    pub followers_max: usize,
    /// Outer-edge pruning factor κ \[-\] (default 1.5; 0 disables pruning).
    #[serde(default = "default_prune")]
    pub prune_factor: f64,
    /// Grouping schedule: `growing` (default) or `once`.
    #[serde(default)]
    pub grouping: GroupingSchedule,
    /// First grouping period \[s\] (default 300).
    #[serde(default = "default_first_period")]
    pub grouping_first_period_s: f64,
    /// End time of the growing schedule \[s\] (usually the run's duration; default 432000 = 120 h).
    #[serde(default = "default_schedule_end")]
    pub grouping_schedule_end_s: f64,
    /// Add the z-frequency feed-forward (ω_z² − ω_xy²) z_j (method page §5.3; default false).
    #[serde(default)]
    pub z_frequency_feedforward: bool,
    /// Connectivity-preserving grouping, an extension beyond the paper (method page §9.6; default
    /// false, the paper's Algorithm 1): after each grouping, add back the shortest links (Ŝ-plane
    /// distance, satellites within sensing range) that rejoin what the grouping split, so that it has no
    /// more connected components than the graph of all links in range.
    #[serde(default)]
    pub preserve_connectivity: bool,
}

fn default_k_a() -> f64 {
    1.5e-2
}
fn default_k_z() -> f64 {
    5e-3
}
fn default_gamma_a() -> f64 {
    10.0
}
fn default_alpha_a() -> f64 {
    0.5
}
fn default_one() -> f64 {
    1.0
}
fn default_theta_p() -> f64 {
    30.0
}
fn default_r_avg() -> f64 {
    0.5
}
fn default_r_low() -> f64 {
    0.1
}
fn default_clamp() -> f64 {
    0.05
}
fn default_max_force() -> f64 {
    5e-7
}
fn default_followers() -> usize {
    5
}
fn default_prune() -> f64 {
    1.5
}
fn default_first_period() -> f64 {
    300.0
}
fn default_schedule_end() -> f64 {
    432_000.0
}

impl Default for J2DistanceParameters {
    fn default() -> Self {
        toml::from_str("").expect("every key has a default")
    }
}

fn check(p: &J2DistanceParameters) -> Result<(), LawError> {
    let invalid = |invalid: Invalid| LawError::invalid("j2-distance", invalid);
    let positive = [
        ("gain_a_per_s", p.gain_a_per_s),
        ("gamma_a", p.gamma_a),
        ("average_distance_m", p.average_distance_m),
        ("controllable_range_m", p.controllable_range_m),
        ("max_force_n", p.max_force_n),
        ("grouping_first_period_s", p.grouping_first_period_s),
        ("grouping_schedule_end_s", p.grouping_schedule_end_s),
        ("gain_alpha_b", p.gain_alpha_b),
    ];
    for (key, v) in positive {
        if !(v.is_finite() && v > 0.0) {
            return Err(invalid(Invalid::range(key, v, "finite, > 0")));
        }
    }
    let non_negative = [
        ("gain_b_per_s", p.gain_b_per_s),
        ("gain_z_per_s", p.gain_z_per_s),
        ("gamma_b_max", p.gamma_b_max),
        ("min_amplitude_m", p.min_amplitude_m),
        ("prune_factor", p.prune_factor),
    ];
    for (key, v) in non_negative {
        if !(v.is_finite() && v >= 0.0) {
            return Err(invalid(Invalid::range(key, v, "finite, >= 0")));
        }
    }
    if !(p.gain_alpha_a > 0.0 && p.gain_alpha_a <= 1.0) {
        return Err(invalid(Invalid::range(
            "gain_alpha_a",
            p.gain_alpha_a,
            "(0, 1]",
        )));
    }
    if !(p.barrier_clamp_fraction > 0.0 && p.barrier_clamp_fraction < 0.5) {
        return Err(invalid(Invalid::range(
            "barrier_clamp_fraction",
            p.barrier_clamp_fraction,
            "(0, 0.5)",
        )));
    }
    if !(p.plane_theta_p_deg > 0.0 && p.plane_theta_p_deg <= 90.0) {
        return Err(invalid(Invalid::range(
            "plane_theta_p_deg",
            p.plane_theta_p_deg,
            "(0, 90]",
        )));
    }
    if !(p.plane_theta_zxy_deg > -90.0 && p.plane_theta_zxy_deg < 90.0) {
        return Err(invalid(Invalid::range(
            "plane_theta_zxy_deg",
            p.plane_theta_zxy_deg,
            "(-90, 90)",
        )));
    }
    if p.followers_max < 1 {
        return Err(invalid(Invalid::keys(
            "followers_max",
            "followers_max = 0 is out of range (allowed: >= 1)",
            "",
        )));
    }
    Ok(())
}

/// The gains of Eq. 15 besides k_A, k_B, k_z, γ_A (method page §7.6), and the eigenvalues they came from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Gains {
    /// γ_B \[-\].
    pub gamma_b: f64,
    /// ψ \[-\].
    pub psi: f64,
    /// f₀ \[-\].
    pub f0: f64,
    /// g₀ \[-\].
    pub g0: f64,
    /// λ₀ \[-\] (theorem design; 0 for the preset).
    pub lambda_0: f64,
    /// Smallest non-zero Laplacian eigenvalue over components with edges \[-\].
    pub lambda_2: f64,
    /// Largest Laplacian eigenvalue \[-\].
    pub lambda_max: f64,
}

/// The theorem gains of method page §7.6 from ρ = ε₂/k_A and the Laplacian's λ₂, λ_max:
/// a = α_a ρ/λ_max, b = min(α_b ρ/λ₂, a + 4γ_B,max), λ₀ = (a+b)/2, γ_B = (b−a)/4,
/// ψ = (1−k₁)/k₁ (−λ₀ + √(λ₀² − 4γ_B²)), f₀ = ψ/2 − λ₀, g₀ = −k₁f₀ − λ₀.
pub fn theorem_gains(
    rho: f64,
    k1: f64,
    lambda_2: f64,
    lambda_max: f64,
    alpha_a: f64,
    alpha_b: f64,
    gamma_b_max: f64,
) -> Gains {
    let a = alpha_a * rho / lambda_max;
    let b = (alpha_b * rho / lambda_2).min(a + 4.0 * gamma_b_max);
    let lambda_0 = 0.5 * (a + b);
    let gamma_b = 0.25 * (b - a);
    let psi = (1.0 - k1) / k1
        * (-lambda_0
            + (lambda_0 * lambda_0 - 4.0 * gamma_b * gamma_b)
                .max(0.0)
                .sqrt());
    let f0 = 0.5 * psi - lambda_0;
    Gains {
        gamma_b,
        psi,
        f0,
        g0: -k1 * f0 - lambda_0,
        lambda_0,
        lambda_2,
        lambda_max,
    }
}

/// The barrier needs its target above its lower bound: r_d > r̲ (otherwise the clamp interval is empty).
fn check_target_amplitude(d: &Derived, p: &J2DistanceParameters) -> Result<(), LawError> {
    let target = d.target_amplitude_m;
    if target.is_finite() && target > p.min_amplitude_m {
        Ok(())
    } else {
        Err(LawError::invalid(
            "j2-distance",
            Invalid::new(
                "min_amplitude_m",
                format!("{} m", p.min_amplitude_m),
                format!(
                    "is not below the target amplitude {target} m that plane_theta_p_deg, \
                     plane_theta_zxy_deg and average_distance_m give"
                ),
                "a target amplitude > min_amplitude_m",
            ),
        ))
    }
}

/// Clamped barrier s(r) \[-\] (method page §7.1): (r − r_d)/(r − r̲) + (r − r_d)/((2r_d − r̲) − r), evaluated at
/// r clamped to [r̲ + η, 2r_d − r̲ − η], η = `clamp_fraction`·(r_d − r̲). Lengths in m.
pub fn barrier(r_m: f64, target_m: f64, lower_m: f64, clamp_fraction: f64) -> f64 {
    let eta = clamp_fraction * (target_m - lower_m);
    let upper = 2.0 * target_m - lower_m;
    let r = r_m.clamp(lower_m + eta, upper - eta);
    (r - target_m) / (r - lower_m) + (r - target_m) / (upper - r)
}

/// The law's constants derived from its parameters and the reference orbit.
#[derive(Clone, Copy, Debug)]
struct Derived {
    model: AveragedJ2,
    plane: SwarmPlane,
    /// Target amplitude r_xyd \[m\].
    target_amplitude_m: f64,
    /// C^{Ŝ/O} \[-\].
    normalised: Matrix3<f64>,
}

/// The centralised state: neighbour lists (CSR) and gains, shared read-only with the command.
#[derive(Clone, Debug, Default)]
struct Network {
    /// Neighbours of satellite j: `neighbours[offsets[j]..offsets[j + 1]]`, sorted.
    offsets: Vec<usize>,
    neighbours: Vec<usize>,
    edges: Vec<(usize, usize)>,
    gains: Gains,
}

/// Running statistics of the groupings, for the results (`grouping` of [`J2DistanceResults`]).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct GroupingStats {
    /// Groupings run so far.
    pub updates: usize,
    /// Edges added plus edges removed, summed over the updates after the first.
    pub edge_changes: usize,
    /// Time of the last update that changed the edge set \[s\].
    pub last_change_s: f64,
    /// Whether the graph over the live satellites was connected at every update.
    pub always_connected: bool,
    /// Largest number of connected components seen.
    pub max_components: usize,
    /// Connected components of the current graph over the live satellites.
    pub components: usize,
    /// Time of the first update whose graph was not connected \[s\] (`None` while always connected).
    pub first_disconnected_s: Option<f64>,
    /// Updates at which the connectivity-preserving grouping added edges (0 when it is off).
    pub connectivity_repairs: usize,
    /// Edges it added, summed over the updates.
    pub connectivity_repair_edges: usize,
}

/// Swarm-level metrics of one instant (see [`J2Distance::instant_metrics`]).
#[derive(Clone, Copy, Debug)]
struct InstantMetrics {
    /// max |C₁| over live satellites relative to the origin \[m\].
    max_c1: f64,
    /// max |C₄| \[m\].
    max_c4: f64,
    /// min T̂_conn \[s\].
    min_t: f64,
    /// (min, max) measured Θ̂_P over satellites with r_xy > 0.05 m \[deg\] (±∞ if none).
    theta_p: (f64, f64),
    /// (min, max) measured Θ̂_z-xy \[deg\].
    theta_zxy: (f64, f64),
    /// p5, p50, p95 of the edge ratio r_xy,jk / r_xyd \[-\] (NaN without edges).
    ratio_percentiles: [f64; 3],
    /// Fraction of live satellites whose unsaturated command exceeds the limit \[-\].
    saturated_fraction: f64,
}

/// Columns of `metrics.csv` the law adds (method page §13 "Recorder and metrics"), in this order.
const METRIC_NAMES: &[&str] = &[
    "ts_max_abs_c1_m",
    "ts_max_abs_c4_m",
    "ts_theta_p_min_deg",
    "ts_theta_p_max_deg",
    "ts_theta_zxy_min_deg",
    "ts_theta_zxy_max_deg",
    "ts_edge_ratio_p5",
    "ts_edge_ratio_p50",
    "ts_edge_ratio_p95",
    "ts_min_connectable_time_h",
    "ts_saturation_fraction",
    "ts_edges",
    "ts_components",
    "ts_edge_changes_total",
];

/// The `j2-distance` law.
#[derive(Clone, Debug)]
pub struct J2Distance {
    parameters: J2DistanceParameters,
    derived: Option<Derived>,
    network: Arc<Network>,
    next_grouping_s: f64,
    stats: GroupingStats,
}

impl J2Distance {
    /// Builds the law, checking its parameters.
    pub fn new(parameters: J2DistanceParameters) -> Result<Self, LawError> {
        check(&parameters)?;
        Ok(Self {
            parameters,
            derived: None,
            network: Arc::new(Network::default()),
            next_grouping_s: 0.0,
            stats: GroupingStats {
                always_connected: true,
                ..GroupingStats::default()
            },
        })
    }

    /// The current gains (after the last grouping).
    pub fn gains(&self) -> Gains {
        self.network.gains
    }

    /// The current edge set (j < k, sorted).
    pub fn edges(&self) -> &[(usize, usize)] {
        &self.network.edges
    }

    /// Target in-plane amplitude r_xyd \[m\] (after the law has started).
    pub fn target_amplitude_m(&self) -> Option<f64> {
        self.derived.map(|d| d.target_amplitude_m)
    }

    /// Derives the constants; refuses a target amplitude (from the plane angles and the average distance)
    /// that is not above the barrier's lower bound, where the barrier has no admissible interval.
    fn derive(&mut self, swarm: &SwarmView<'_>) -> Result<(), LawError> {
        let p = &self.parameters;
        let model = AveragedJ2::new(swarm.shared.reference_model);
        let plane = SwarmPlane {
            theta_p_rad: p.plane_theta_p_deg.to_radians(),
            theta_zxy_rad: p.plane_theta_zxy_deg.to_radians(),
        };
        self.derived = Some(Derived {
            model,
            plane,
            target_amplitude_m: plane
                .target_amplitude_m(p.average_distance_m, model.model().s_j2()),
            normalised: plane.normalised_frame(model.c_plus(), model.c_minus()),
        });
        check_target_amplitude(self.derived.as_ref().expect("set above"), p)
    }

    /// The pair term u_{j←k} \[m/s²\] (Hill) of Eq. 15 or 16 for the pair parameters C_jk.
    fn pair_term(&self, d: &Derived, gains: &Gains, c: &OrbitParameters) -> Vector3<f64> {
        let p = &self.parameters;
        let m = &d.model;
        let (k0, k1, cm, eps2) = (m.k0_s(), m.k1(), m.c_minus(), m.epsilon_2_rad_s());
        let (ka, ga) = (p.gain_a_per_s, p.gamma_a);
        // Distance function (ϱ, ς, τ) = (2c₊, 0, 1): r̄ = √((2c₊C₁ + C₃)² + C₂²) (§7.2).
        let rbar = (2.0 * m.c_plus() * c.c1_m + c.c3_m).hypot(c.c2_m);
        let sk = p.gain_b_per_s
            * barrier(
                rbar,
                d.target_amplitude_m,
                p.min_amplitude_m,
                p.barrier_clamp_fraction,
            );
        let (c5d, _) = d.plane.z_targets_m(c.c2_m, c.c3_m);
        let uz = -p.gain_z_per_s * m.omega_z_rad_s() * (c.c5_m - c5d);
        match p.variant {
            Variant::Main => {
                let gb2 = gains.gamma_b * gains.gamma_b;
                let ux = ka / (2.0 * k0)
                    * (ga * gb2 * c.c4_m - (ga * gb2 * gains.psi - 2.0 * gains.f0) * c.c1_m)
                    - cm / (2.0 * k0 * k1 * k1) * sk * gb2 * c.c2_m;
                let uy = -ka / k0 * c.c1_m + cm / (2.0 * k0 * k1) * sk * gains.g0 * c.c2_m;
                Vector3::new(ux, uy, uz)
            }
            Variant::Opp => {
                let ux = ka / (2.0 * k0) * ga * c.c4_m - cm / (2.0 * k0) * sk * c.c2_m;
                let uy = -ka / k0 * c.c1_m + ga * eps2 / (2.0 * k0) * c.c4_m
                    - cm * eps2 / (2.0 * k0 * k1 * ka) * sk * c.c2_m;
                Vector3::new(ux, uy, uz)
            }
        }
    }

    /// Unsaturated command of one satellite \[m/s²\] (Hill).
    fn raw_command(&self, satellite: &SatelliteView<'_>) -> Vector3<f64> {
        let Some(d) = &self.derived else {
            return Vector3::zeros();
        };
        let net = &*self.network;
        let j = satellite.id();
        if j + 1 >= net.offsets.len() {
            return Vector3::zeros();
        }
        let mine = &net.neighbours[net.offsets[j]..net.offsets[j + 1]];
        let own = satellite.own_state().to_vector6();
        let mut u = Vector3::zeros();
        satellite.for_each_neighbour(|nb| {
            if mine.binary_search(&nb.id).is_ok() {
                let c = d.model.parameters(&(own - nb.state.to_vector6()));
                u += self.pair_term(d, &net.gains, &c);
            }
        });
        if self.parameters.z_frequency_feedforward {
            u.z += z_frequency_feedforward_m_s2(
                d.model.omega_z_rad_s(),
                d.model.omega_xy_rad_s(),
                own[2],
            );
        }
        u
    }

    /// The swarm-level metrics of one instant, relative to the LVLH origin (the reference satellite):
    /// shared by [`Reports::results`] and [`Diagnostics::record_metrics`]. `None` before the law
    /// has started.
    fn instant_metrics(&self, swarm: &SwarmView<'_>) -> Option<InstantMetrics> {
        let d = self.derived.as_ref()?;
        let p = &self.parameters;
        let mut m = InstantMetrics {
            max_c1: 0.0,
            max_c4: 0.0,
            min_t: f64::INFINITY,
            theta_p: (f64::INFINITY, f64::NEG_INFINITY),
            theta_zxy: (f64::INFINITY, f64::NEG_INFINITY),
            ratio_percentiles: [f64::NAN; 3],
            saturated_fraction: 0.0,
        };
        let mut live = 0usize;
        let mut saturated = 0usize;
        for i in (0..swarm.len()).filter(|&i| swarm.active[i]) {
            live += 1;
            let c = d.model.parameters(&swarm.relative_states[i].to_vector6());
            m.max_c1 = m.max_c1.max(c.c1_m.abs());
            m.max_c4 = m.max_c4.max(c.c4_m.abs());
            m.min_t = m
                .min_t
                .min(d.model.connectable_time_s(&c, p.controllable_range_m));
            if let Some((tp, tz)) = SwarmPlane::measured_angles_rad(&c, 0.05) {
                let (tp, tz) = (tp.to_degrees(), tz.to_degrees());
                m.theta_p = (m.theta_p.0.min(tp), m.theta_p.1.max(tp));
                m.theta_zxy = (m.theta_zxy.0.min(tz), m.theta_zxy.1.max(tz));
            }
            let sat = swarm.satellite(i);
            if self.raw_command(&sat).norm() > p.max_force_n / sat.mass_kg() {
                saturated += 1;
            }
        }
        let mut ratios: Vec<f64> = self
            .network
            .edges
            .iter()
            .filter(|(a, b)| swarm.active[*a] && swarm.active[*b])
            .map(|&(a, b)| {
                let c = d.model.pair_parameters(
                    &swarm.relative_states[a].to_vector6(),
                    &swarm.relative_states[b].to_vector6(),
                );
                c.r_xy_m() / d.target_amplitude_m
            })
            .collect();
        ratios.sort_by(f64::total_cmp);
        m.ratio_percentiles = [0.05, 0.5, 0.95].map(|q| percentile(&ratios, q));
        m.saturated_fraction = saturated as f64 / live.max(1) as f64;
        Some(m)
    }

    /// Grouping period in effect at `time_s` (method page §9.5) \[s\]; infinite for the `once` schedule.
    fn grouping_period_s(&self, time_s: f64) -> f64 {
        let p = &self.parameters;
        match p.grouping {
            GroupingSchedule::Once => f64::INFINITY,
            GroupingSchedule::Growing => {
                let quarter = (4.0 * time_s / p.grouping_schedule_end_s)
                    .floor()
                    .clamp(0.0, 3.0);
                p.grouping_first_period_s * 2f64.powf(quarter)
            }
        }
    }
}

/// λ₂ (smallest non-zero over components with edges) and λ_max of the Laplacian of `edges` over the
/// live satellites (`live[i]` is the local index of satellite i), and the number of components.
fn laplacian_eigenvalues(
    n_live: usize,
    edges: &[(usize, usize)],
    local: &[usize],
) -> (f64, f64, usize) {
    let mut l = DMatrix::<f64>::zeros(n_live, n_live);
    let mut components = Components::new(n_live);
    for &(a, b) in edges {
        let (i, j) = (local[a], local[b]);
        l[(i, j)] -= 1.0;
        l[(j, i)] -= 1.0;
        l[(i, i)] += 1.0;
        l[(j, j)] += 1.0;
        components.union(i, j);
    }
    let count = (0..n_live)
        .map(|i| components.find(i))
        .collect::<std::collections::BTreeSet<_>>()
        .len();
    let mut eig: Vec<f64> = l.symmetric_eigenvalues().iter().copied().collect();
    eig.sort_by(f64::total_cmp);
    // One zero eigenvalue per component (isolated satellites included).
    let lambda_2 = eig.get(count).copied().unwrap_or(0.0);
    let lambda_max = eig.last().copied().unwrap_or(0.0);
    (lambda_2, lambda_max, count)
}

/// Percentile (nearest rank) of sorted values.
fn percentile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let rank = ((q * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len());
    sorted[rank - 1]
}

impl GuidanceLaw for J2Distance {
    type State = ();
    type Parameters = J2DistanceParameters;
    crate::capabilities!(Centralised, Reports, Diagnostics);

    fn name(&self) -> &'static str {
        "j2-distance"
    }

    fn initialise(&mut self, swarm: &SwarmView<'_>, _states: &mut [()]) -> Result<(), LawError> {
        self.derive(swarm)?;
        self.next_grouping_s = swarm.shared.time_s;
        Ok(())
    }

    fn command(
        &self,
        satellite: &SatelliteView<'_>,
        _state: &(),
        _context: &LawContext,
    ) -> Vector3<f64> {
        let u = self.raw_command(satellite);
        // Norm saturation ‖f‖ ≤ f̄ (method page §7.7): u ← u min(1, f̄/(m‖u‖)).
        let limit = self.parameters.max_force_n / satellite.mass_kg();
        let norm = u.norm();
        if norm > limit {
            u * (limit / norm)
        } else {
            u
        }
    }

    /// The fastest linear closed-loop rate of Eq. 15/16 \[1/s\] (independent of mass: the law commands
    /// accelerations). Per Laplacian eigenvalue λ (method page §3.4, §7.3): the C₁ loop decays at k_A λ/2, the
    /// C₄ loop at k_A γ_A γ_B² λ/2 (main; k_A γ_A λ/2 for opp) and the C₅ loop at k_z λ. The distance
    /// loop near r_xyd is slower (about k_B γ_B² λ · 2r_xyd/(r_xyd − r̲) · c₋²/(4k₁²) ≈ 0.023 γ_B² λ with the
    /// defaults). γ_B is taken at its cap γ_B,max (1 for the §4.1 preset; the theorem design sits there while λ₂ is small, the
    /// first 1–2 h of the §4.2 runs). λ_max is known only after a grouping, which comes after this
    /// check, so it is **estimated**, not bounded: λ_max ≤ 2Δ with Δ = 6, the mean degree of a planar
    /// triangulation (an irregular DT can exceed it; our 100-satellite runs saw λ_max 9.2–13.3, i.e.
    /// up to 11 % above the estimate). With the defaults this is 0.9 1/s: the 1 s zero-order hold of the
    /// `ts-*` scenarios runs at T·k ≈ 0.9–1.0 during the capped transient, at the edge of the engine's
    /// accuracy margin and well inside stability (T·k < 2).
    fn fastest_rate_per_s(&self, _mass_kg: f64) -> Option<f64> {
        let p = &self.parameters;
        let lambda_max = 12.0;
        let gamma_b = match p.gain_design {
            GainDesign::Theorem => p.gamma_b_max,
            GainDesign::Preset => 1.0,
        };
        let c4_stiffness = match p.variant {
            Variant::Main => p.gamma_a * gamma_b * gamma_b,
            Variant::Opp => p.gamma_a,
        };
        let in_plane = 0.5 * p.gain_a_per_s * c4_stiffness.max(1.0);
        Some(in_plane.max(p.gain_z_per_s) * lambda_max)
    }

    fn set_parameters(&mut self, parameters: &J2DistanceParameters) -> Result<(), LawError> {
        check(parameters)?;
        self.parameters = parameters.clone();
        if let Some(d) = &mut self.derived {
            let model = d.model;
            let plane = SwarmPlane {
                theta_p_rad: self.parameters.plane_theta_p_deg.to_radians(),
                theta_zxy_rad: self.parameters.plane_theta_zxy_deg.to_radians(),
            };
            *d = Derived {
                model,
                plane,
                target_amplitude_m: plane
                    .target_amplitude_m(self.parameters.average_distance_m, model.model().s_j2()),
                normalised: plane.normalised_frame(model.c_plus(), model.c_minus()),
            };
            check_target_amplitude(d, &self.parameters)?;
        }
        Ok(())
    }
}

impl Centralised for J2Distance {
    fn centralised_due(&self, time_s: f64) -> bool {
        time_s >= self.next_grouping_s - 1e-9
    }

    /// Algorithm 1 and the gain design (centralised; see the module docs).
    fn centralised_update(&mut self, swarm: &SwarmView<'_>) -> Result<(), LawError> {
        if self.derived.is_none() {
            self.derive(swarm)?;
        }
        let d = self.derived.expect("derived above");
        let p = &self.parameters;
        let live: Vec<usize> = (0..swarm.len()).filter(|&i| swarm.active[i]).collect();
        let mut local = vec![usize::MAX; swarm.len()];
        for (k, &i) in live.iter().enumerate() {
            local[i] = k;
        }
        let states: Vec<Vector6<f64>> = swarm
            .relative_states
            .iter()
            .map(RelativeStateHill::to_vector6)
            .collect();
        let nodes: Vec<Node> = live
            .iter()
            .map(|&i| {
                let q = d.normalised * swarm.relative_states[i].position_m;
                Node {
                    id: i,
                    plane_m: [q.y, q.z],
                }
            })
            .collect();
        let settings = GroupingSettings {
            followers_max: p.followers_max,
            range_m: p.controllable_range_m,
            prune_length_m: (p.prune_factor > 0.0)
                .then_some(p.prune_factor * 2.0 * d.target_amplitude_m),
        };
        let eps2 = d.model.epsilon_2_rad_s();
        let mut result = group(&nodes, &settings, |a, b| {
            let c = d
                .model
                .pair_parameters(&states[nodes[a].id], &states[nodes[b].id]);
            connectable_time_s(c.c1_m, c.c4_m, eps2, p.controllable_range_m)
        });
        if p.preserve_connectivity {
            // The communication graph: every pair of live satellites that sense each other (links
            // up, within sensing range), as local indices.
            let mut links = Vec::new();
            for (k, &i) in live.iter().enumerate() {
                swarm.satellite(i).for_each_neighbour(|nb| {
                    if nb.id > i {
                        links.push((k, local[nb.id]));
                    }
                });
            }
            let added = grouping::preserve_connectivity(&nodes, &links, &mut result);
            if !added.is_empty() {
                self.stats.connectivity_repairs += 1;
                self.stats.connectivity_repair_edges += added.len();
            }
        }
        let (lambda_2, lambda_max, components) =
            laplacian_eigenvalues(live.len(), &result.edges, &local);
        let m = &d.model;
        let gains = match p.gain_design {
            GainDesign::Preset => Gains {
                gamma_b: 1.0,
                psi: 0.0,
                f0: -m.epsilon_2_rad_s() / (2.0 * p.gain_a_per_s),
                g0: 0.0,
                lambda_0: 0.0,
                lambda_2,
                lambda_max,
            },
            GainDesign::Theorem if lambda_2 > 0.0 && lambda_max > 0.0 => theorem_gains(
                m.epsilon_2_rad_s() / p.gain_a_per_s,
                m.k1(),
                lambda_2,
                lambda_max,
                p.gain_alpha_a,
                p.gain_alpha_b,
                p.gamma_b_max,
            ),
            // No edge at all: nothing to control; keep the previous gains.
            GainDesign::Theorem => self.network.gains,
        };
        // Edge-set changes (symmetric difference) after the first grouping.
        let old = &self.network.edges;
        let time_s = swarm.shared.time_s;
        if self.stats.updates > 0 {
            let common = result
                .edges
                .iter()
                .filter(|e| old.binary_search(e).is_ok())
                .count();
            let changes = (old.len() - common) + (result.edges.len() - common);
            if changes > 0 {
                self.stats.edge_changes += changes;
                self.stats.last_change_s = time_s;
            }
        }
        self.stats.updates += 1;
        self.stats.max_components = self.stats.max_components.max(components);
        self.stats.components = components;
        if components > 1 {
            self.stats.always_connected = false;
            self.stats.first_disconnected_s.get_or_insert(time_s);
        }
        // CSR neighbour lists.
        let n = swarm.len();
        let mut degree = vec![0usize; n];
        for &(a, b) in &result.edges {
            degree[a] += 1;
            degree[b] += 1;
        }
        let mut offsets = vec![0usize; n + 1];
        for i in 0..n {
            offsets[i + 1] = offsets[i] + degree[i];
        }
        let mut fill = offsets.clone();
        let mut neighbours = vec![0usize; offsets[n]];
        for &(a, b) in &result.edges {
            neighbours[fill[a]] = b;
            fill[a] += 1;
            neighbours[fill[b]] = a;
            fill[b] += 1;
        }
        for i in 0..n {
            neighbours[offsets[i]..offsets[i + 1]].sort_unstable();
        }
        self.network = Arc::new(Network {
            offsets,
            neighbours,
            edges: result.edges,
            gains,
        });
        self.next_grouping_s = time_s + self.grouping_period_s(time_s);
        Ok(())
    }
}

/// The `j2-distance` law's results (`summary.json` `law`), relative to the LVLH origin (the reference
/// satellite S/C_ref); non-finite values are null.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct J2DistanceResults {
    /// max |C₁| over live satellites \[m\].
    pub max_abs_c1_m: Option<f64>,
    /// max |C₄| over live satellites \[m\].
    pub max_abs_c4_m: Option<f64>,
    /// min T̂_conn over live satellites \[h\].
    pub min_connectable_time_h: Option<f64>,
    /// Range of the measured plane angle θ_p over satellites with r_xy > 0.05 m \[deg\].
    pub plane_theta_p_deg_range: [Option<f64>; 2],
    /// Range of the measured plane angle θ_zxy over satellites with r_xy > 0.05 m \[deg\].
    pub plane_theta_zxy_deg_range: [Option<f64>; 2],
    /// Percentiles 5, 50 and 95 of r_xy/r_xyd over the edges.
    pub edge_ratio_p5_p50_p95: [Option<f64>; 3],
    /// Fraction of the live satellites saturated now.
    pub saturation_fraction: Option<f64>,
    /// Number of edges of the current grouping.
    pub edges: usize,
    /// The edges of the current grouping (pairs of ids).
    pub edge_list: Vec<(usize, usize)>,
    /// The target amplitude of the plane \[m\].
    pub target_amplitude_m: Option<f64>,
    /// Grouping statistics.
    pub grouping: GroupingStats,
    /// The current gains.
    pub gains: Gains,
}

impl Reports<()> for J2Distance {
    /// `None` before the law has derived its constants (no results are written).
    type Results = Option<J2DistanceResults>;

    fn headlines(&self) -> &'static [Headline] {
        const HEADLINES: &[Headline] = &[
            Headline::new("max_abs_c1_m", "max abs C1", "m", Better::Lower),
            Headline::new("max_abs_c4_m", "max abs C4", "m", Better::Lower),
            Headline::new(
                "min_connectable_time_h",
                "min connectable time",
                "h",
                Better::Higher,
            ),
        ];
        HEADLINES
    }

    /// Relative to the LVLH origin (the reference satellite S/C_ref): max |C₁|, max |C₄| \[m\], measured
    /// plane angles over satellites with r_xy > 0.05 m \[deg\], min T̂_conn \[h\]; per edge r_xy/r_xyd
    /// percentiles; the fraction of live satellites saturated now; the edge list; grouping statistics
    /// and gains.
    fn results(&self, swarm: &SwarmView<'_>, _states: &[()]) -> Option<J2DistanceResults> {
        let (Some(d), Some(m)) = (&self.derived, self.instant_metrics(swarm)) else {
            return None;
        };
        let InstantMetrics {
            max_c1,
            max_c4,
            min_t,
            theta_p: (tp_lo, tp_hi),
            theta_zxy: (tz_lo, tz_hi),
            ratio_percentiles: [r5, r50, r95],
            saturated_fraction,
        } = m;
        let finite = |v: f64| v.is_finite().then_some(v);
        Some(J2DistanceResults {
            max_abs_c1_m: finite(max_c1),
            max_abs_c4_m: finite(max_c4),
            min_connectable_time_h: finite(min_t / 3600.0),
            plane_theta_p_deg_range: [finite(tp_lo), finite(tp_hi)],
            plane_theta_zxy_deg_range: [finite(tz_lo), finite(tz_hi)],
            edge_ratio_p5_p50_p95: [finite(r5), finite(r50), finite(r95)],
            saturation_fraction: finite(saturated_fraction),
            edges: self.network.edges.len(),
            edge_list: self.network.edges.clone(),
            target_amplitude_m: finite(d.target_amplitude_m),
            grouping: self.stats.clone(),
            gains: self.network.gains,
        })
    }
}

impl Diagnostics<()> for J2Distance {
    fn metric_names(&self) -> &'static [&'static str] {
        METRIC_NAMES
    }

    /// The time series of the quantities `summary.json` reports at the end (same definitions, see
    /// [`Reports::results`]), plus the current edge count, component count and the cumulative
    /// edge-set changes. Angles are NaN while no satellite has r_xy > 0.05 m; T̂_conn is in hours
    /// (`inf` when no satellite drifts).
    fn record_metrics(&mut self, swarm: &SwarmView<'_>, _states: &[()], values: &mut [f64]) {
        let Some(m) = self.instant_metrics(swarm) else {
            values.fill(f64::NAN);
            return;
        };
        let finite = |v: f64| if v.is_finite() { v } else { f64::NAN };
        values[0] = m.max_c1;
        values[1] = m.max_c4;
        values[2] = finite(m.theta_p.0);
        values[3] = finite(m.theta_p.1);
        values[4] = finite(m.theta_zxy.0);
        values[5] = finite(m.theta_zxy.1);
        values[6..9].copy_from_slice(&m.ratio_percentiles);
        values[9] = m.min_t / 3600.0;
        values[10] = m.saturated_fraction;
        values[11] = self.network.edges.len() as f64;
        values[12] = self.stats.components as f64;
        values[13] = self.stats.edge_changes as f64;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn val_barrier_golden_values() {
        // our independently computed values for method page §7.1 (r_xyd = 0.25, r̲ = 0.1, η = 0.0075), printed to 7 digits
        let expected = [-6.964286, -0.75, 0.0, 0.75, 6.964286, 19.487179];
        for (r, e) in [0.12, 0.2, 0.25, 0.3, 0.38, 1.0].into_iter().zip(expected) {
            assert!((barrier(r, 0.25, 0.1, 0.05) - e).abs() < 5e-7, "s({r})");
        }
    }

    #[test]
    fn val_theorem_gains_satisfy_eq_17_18() {
        // λ values typical of method page §7.6; ρ = ε₂/k_A with the constants of method page §1.3.
        let (rho, k1) = (3.3259368e-3 / 1.5e-2, 0.7500533);
        let g = theorem_gains(rho, k1, 0.15, 9.25, 0.5, 1.0, 1.0);
        // Eq. 17: ψ solves (k₁/(1−k₁))ψ = −λ₀ + √(λ₀² − 4γ_B²); f₀, g₀ as defined
        let lhs = k1 / (1.0 - k1) * g.psi;
        let rhs = -g.lambda_0 + (g.lambda_0 * g.lambda_0 - 4.0 * g.gamma_b * g.gamma_b).sqrt();
        assert!((lhs - rhs).abs() < 1e-12);
        // Eq. 18 for λ₂ and λ_max (the cap is inactive here): equalities of the design, to rounding
        assert!(rho / (g.lambda_0 + 2.0 * g.gamma_b) <= 0.15 * (1.0 + 1e-12));
        assert!(9.25 <= rho / (g.lambda_0 - 2.0 * g.gamma_b) * (1.0 + 1e-12));
        // method page §7.6 typical settled values: γ_B 0.33–0.40, ψ −0.18 to −0.23, f₀ −0.76 to −0.93,
        // g₀ −0.10 to −0.12
        assert!((0.33..=0.40).contains(&g.gamma_b), "{g:?}");
        assert!((-0.23..=-0.18).contains(&g.psi), "{g:?}");
        assert!((-0.93..=-0.76).contains(&g.f0), "{g:?}");
        assert!((-0.12..=-0.10).contains(&g.g0), "{g:?}");
    }

    #[test]
    fn val_fastest_rate_is_the_capped_c4_loop() {
        // Defaults: k_A γ_A γ_B,max² λ̂/2 = 1.5e-2 · 10 · 1 · 12 / 2 = 0.9 1/s (C₁ loop 0.09, z loop 0.06).
        let law = J2Distance::new(J2DistanceParameters::default()).unwrap();
        assert!((law.fastest_rate_per_s(0.5).unwrap() - 0.9).abs() < 1e-12);
        // A stiff z loop dominates when k_z > k_A γ_A γ_B,max² / 2.
        let law = J2Distance::new(J2DistanceParameters {
            gain_z_per_s: 0.1,
            ..J2DistanceParameters::default()
        })
        .unwrap();
        assert!((law.fastest_rate_per_s(0.5).unwrap() - 1.2).abs() < 1e-12);
        // With γ_A γ_B,max² < 1 the C₁ loop (k_A λ/2) is the fastest in-plane one.
        let law = J2Distance::new(J2DistanceParameters {
            gamma_a: 0.5,
            ..J2DistanceParameters::default()
        })
        .unwrap();
        assert!((law.fastest_rate_per_s(0.5).unwrap() - 0.09).abs() < 1e-12);
    }

    /// Groups, once, a swarm laid out by hand in the Ŝ plane (positions r = (C^{Ŝ/O})⁻¹ (0, y, z), at
    /// rest, 20 m sensing range): two 2×3 lattices of spacing 0.5 m, 3 m apart. Returns the edges and
    /// the grouping results.
    fn group_two_clusters(preserve_connectivity: bool) -> (Vec<(usize, usize)>, GroupingStats) {
        use crate::grid::NeighbourGrid;
        use crate::swarm::{EnvironmentView, SharedInfo};
        let earth = crate::orbit::EarthModel::WGS84_EGM96;
        let shared = SharedInfo {
            time_s: 0.0,
            mean_motion_rad_s: earth.mean_motion_rad_s(6871e3),
            sensing_range_m: 20.0,
            reference_model: crate::relative::SchweighartSedwick::new(
                6871e3,
                51.7f64.to_radians(),
                earth.mu_m3_s2,
                earth.equatorial_radius_m,
                earth.j2,
            ),
        };
        let mut law = J2Distance::new(J2DistanceParameters {
            preserve_connectivity,
            ..J2DistanceParameters::default()
        })
        .unwrap();
        let normalised = {
            let model = AveragedJ2::new(shared.reference_model);
            let p = &law.parameters;
            SwarmPlane {
                theta_p_rad: p.plane_theta_p_deg.to_radians(),
                theta_zxy_rad: p.plane_theta_zxy_deg.to_radians(),
            }
            .normalised_frame(model.c_plus(), model.c_minus())
        };
        let to_hill = normalised.try_inverse().unwrap();
        let mut states = Vec::new();
        for shift in [0.0, 3.0] {
            for (row, col) in (0..2).flat_map(|r| (0..3).map(move |c| (r, c))) {
                let y = shift + 0.5 * (col as f64 + 0.5 * row as f64);
                let z = 0.5 * row as f64 * 3f64.sqrt() / 2.0;
                states.push(RelativeStateHill {
                    position_m: to_hill * Vector3::new(0.0, y, z),
                    velocity_mps: Vector3::zeros(),
                });
            }
        }
        let coordinate =
            |k: usize| -> Vec<f64> { states.iter().map(|s| s.position_m[k]).collect() };
        let mut grid = NeighbourGrid::new();
        grid.build(&coordinate(0), &coordinate(1), &coordinate(2), 20.0)
            .unwrap();
        let flags = vec![true; states.len()];
        let masses = vec![0.5; states.len()];
        let view = SwarmView::new(
            &states,
            &masses,
            &flags,
            &flags,
            &grid,
            shared,
            EnvironmentView::default(),
        );
        law.initialise(&view, &mut []).unwrap();
        law.centralised_update(&view).unwrap();
        let results = law.results(&view, &[]).expect("derived at initialise");
        (law.edges().to_vec(), results.grouping)
    }

    #[test]
    fn val_preserving_grouping_keeps_the_bridge_of_a_hand_built_swarm() {
        // By hand (Ŝ plane): the nearest pair between the clusters is 5 (1.25, 0.433) – 6 (3, 0), at
        // 1.803 m, longer than r_s = 1 m, so Algorithm 1 drops it; every other pair within a cluster is
        // 0.5 m (lattice edges) or more.
        let (paper, stats) = group_two_clusters(false);
        assert!(!paper.contains(&(5, 6)));
        assert!(paper.iter().all(|&(a, b)| (a < 6) == (b < 6)), "{paper:?}");
        assert_eq!(stats.components, 2);
        assert_eq!(stats.connectivity_repairs, 0);
        let (kept, stats) = group_two_clusters(true);
        let mut expected = paper.clone();
        expected.push((5, 6));
        expected.sort_unstable();
        assert_eq!(kept, expected);
        assert_eq!(stats.components, 1);
        assert!(stats.always_connected);
        assert_eq!(stats.connectivity_repairs, 1);
        assert_eq!(stats.connectivity_repair_edges, 1);
    }

    #[test]
    fn val_pair_terms_are_odd() {
        // method page §6.3: u_{k←j} = −u_{j←k}, so the swarm's total force is zero before saturation.
        let mut law = J2Distance::new(J2DistanceParameters {
            plane_theta_p_deg: 40.0,
            plane_theta_zxy_deg: 50.0,
            ..J2DistanceParameters::default()
        })
        .unwrap();
        let model = AveragedJ2::new(crate::relative::SchweighartSedwick::new(
            6871e3,
            51.7f64.to_radians(),
            3.986e14,
            6378.137e3,
            1.08263e-3,
        ));
        let plane = SwarmPlane {
            theta_p_rad: 40f64.to_radians(),
            theta_zxy_rad: 50f64.to_radians(),
        };
        law.derived = Some(Derived {
            model,
            plane,
            target_amplitude_m: 0.2367,
            normalised: plane.normalised_frame(model.c_plus(), model.c_minus()),
        });
        let gains = theorem_gains(0.2217, model.k1(), 0.15, 9.25, 0.5, 1.0, 1.0);
        let d = law.derived.unwrap();
        for variant in [Variant::Main, Variant::Opp] {
            law.parameters.variant = variant;
            for c in [
                [0.01, 0.2, -0.1, 0.3, 0.05, -0.15],
                [-0.3, 0.02, 0.4, -1.0, 0.1, 0.2],
            ] {
                let a = OrbitParameters::from_array(c);
                let b = OrbitParameters::from_array(c.map(|v| -v));
                let s = law.pair_term(&d, &gains, &a) + law.pair_term(&d, &gains, &b);
                // the terms are ~1e-6 m/s²: exact cancellation up to rounding
                assert!(s.norm() < 1e-20, "{variant:?}: {s:?}");
            }
        }
    }
}
