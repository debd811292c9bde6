//! Schweighart–Sedwick (SS) J2-linearised relative motion, in the form Takahashi & Sakai use.
//!
//! Source: S. A. Schweighart, R. J. Sedwick, "High-Fidelity Linearized J2 Model for Satellite
//! Formation Flight", *J. Guidance, Control, and Dynamics* 25(6), 2002, as restated in
//! `docs/methods/j2-distance.md` (cited below as the "method page").
//!
//! # Frame
//!
//! The method page's frame {O} (§1.1) is the Hill/RSW frame: `x` radial out, `y` along-track, `z` orbit
//! normal. This module uses it unchanged; states are `[x, y, z, vx, vy, vz]` in m and m/s.
//!
//! # Constants (method page §1.3)
//!
//! From the reference radius `r` \[m\], inclination `i` \[rad\], Earth's `μ` \[m³/s²\], `R` \[m\]
//! and `J2`:
//!
//! ```text
//! k_J2 = (3/2) J2 μ R²                                   [m⁵/s²]
//! s    = k_J2 (1 + 3 cos 2i) / (4 μ r²) = 3 J2 R² (1 + 3 cos 2i) / (8 r²)      [-]
//! c±   = √(1 ± s)                                         [-]
//! ω_o  = √(μ / r³)            Keplerian mean motion       [rad/s]
//! ω_ref = c₊ ω_o              SS frame rotation rate      [rad/s]
//! ω_xy = c₋ ω_o               in-plane relative frequency [rad/s]
//! ω_z  = ω_o (c₊ + k_J2 cos² i / (μ r²))   cross-track frequency (Eq. 3)  [rad/s]
//! ε₂   = (3 + 5s) ω_xy / (c₊ c₋)           drift gain     [rad/s]
//! k₀   = 2 c₊ / (ω_xy c₋)                  input gain     [s]
//! k₁   = (3 + 5s) / (4 (1 + s))            ratio          [-]
//! ```
//!
//! # Dynamics (method page §2.3, Eq. 4, physical coordinates)
//!
//! ```text
//! x'' − 2 ω_o c₊ y' − (3 + 5s) ω_o² x = ux
//! y'' + 2 ω_o c₊ x'                   = uy
//! z'' + ω_z² z                        = uz
//! ```
//!
//! This is Eq. 4 after substituting the scaled coordinates `x̄ = c₊ x`, `ȳ = c₋ y` (method page §2.3,
//! \[verified\] there and re-checked in `tests/val_relative.rs`). The cross-track equation is the
//! identical-inclination case of the method page (`ω_z = ω_z,ref`, `l_z = 0`): the differential-nodal terms
//! of SS are not modelled.
//!
//! # Free motion (method page §2.4, Eq. 5)
//!
//! With `a = 2 ω_o c₊`, `b = (3 + 5s) ω_o²` and `a² − b = ω_xy²`, the in-plane motion is an
//! oscillation at `ω_xy` about a centre drifting along-track at `−(b/ω_xy²)(vy0 + a x0)`, which is
//! the method page's `−ε₂ C₁` with `C₁ = c₊ (vy0 + a x0) / (c₋² ω_o)` (§3.1).
//! [`SchweighartSedwick::state_transition_matrix`] is that solution written as a matrix.
//!
//! # Limits of validity
//!
//! SS is a mean (J2-averaged) model about an artificial circular reference orbit. Against a truth
//! propagation with J2, relative orbits set up with zero SS drift can still drift slowly (method page §3.5);
//! that is model mismatch, not a bug.

use nalgebra::{Matrix6, SMatrix, Vector3, Vector6};

use super::series::{cosc, sinc, sinc3};

/// Schweighart–Sedwick J2-linearised relative motion model (method page §2.3), Hill/RSW frame, SI units.
///
/// Built once from the reference orbit's radius and inclination (method page §2.2); all constants of method page
/// §1.3 are available through accessors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SchweighartSedwick {
    reference_radius_m: f64,
    inclination_rad: f64,
    mean_motion_rad_s: f64,
    k_j2_m5_s2: f64,
    s_j2: f64,
    c_plus: f64,
    c_minus: f64,
    omega_z_rad_s: f64,
}

impl SchweighartSedwick {
    /// SS model for a reference orbit of radius `reference_radius_m` \[m\] and inclination
    /// `inclination_rad` \[rad\], with Earth's gravitational parameter `mu_m3_s2` \[m³/s²\], equatorial
    /// radius `earth_radius_m` \[m\] and second zonal harmonic `j2` \[-\]. Constants per method page §1.3 (see
    /// the module docs). `j2 = 0` gives exactly the HCW model with `n = √(μ/r³)`.
    ///
    /// # Panics
    ///
    /// If the radius or `μ` is not finite and positive, the Earth radius is negative or not finite,
    /// the inclination or `J2` is not finite, or `|s_J2| ≥ 1` (no physical orbit comes close).
    pub fn new(
        reference_radius_m: f64,
        inclination_rad: f64,
        mu_m3_s2: f64,
        earth_radius_m: f64,
        j2: f64,
    ) -> Self {
        assert!(
            reference_radius_m.is_finite() && reference_radius_m > 0.0,
            "reference radius must be finite and positive, got {reference_radius_m} m"
        );
        assert!(
            mu_m3_s2.is_finite() && mu_m3_s2 > 0.0,
            "mu must be finite and positive, got {mu_m3_s2} m^3/s^2"
        );
        assert!(
            earth_radius_m.is_finite() && earth_radius_m >= 0.0,
            "Earth radius must be finite and non-negative, got {earth_radius_m} m"
        );
        assert!(
            inclination_rad.is_finite(),
            "inclination must be finite, got {inclination_rad} rad"
        );
        assert!(j2.is_finite(), "J2 must be finite, got {j2}");
        let r = reference_radius_m;
        let k_j2_m5_s2 = 1.5 * j2 * mu_m3_s2 * earth_radius_m * earth_radius_m;
        let s_j2 =
            k_j2_m5_s2 * (1.0 + 3.0 * (2.0 * inclination_rad).cos()) / (4.0 * mu_m3_s2 * r * r);
        assert!(
            s_j2.abs() < 1.0,
            "|s_J2| = {} must be < 1 for the SS model",
            s_j2.abs()
        );
        let c_plus = (1.0 + s_j2).sqrt();
        let c_minus = (1.0 - s_j2).sqrt();
        let mean_motion_rad_s = (mu_m3_s2 / (r * r * r)).sqrt();
        let cos_i = inclination_rad.cos();
        let omega_z_rad_s =
            mean_motion_rad_s * (c_plus + k_j2_m5_s2 * cos_i * cos_i / (mu_m3_s2 * r * r));
        Self {
            reference_radius_m,
            inclination_rad,
            mean_motion_rad_s,
            k_j2_m5_s2,
            s_j2,
            c_plus,
            c_minus,
            omega_z_rad_s,
        }
    }

    /// Reference orbit radius `r_ref` \[m\].
    pub fn reference_radius_m(&self) -> f64 {
        self.reference_radius_m
    }

    /// Reference orbit inclination `i_ref` \[rad\].
    pub fn inclination_rad(&self) -> f64 {
        self.inclination_rad
    }

    /// Keplerian mean motion `ω_o = √(μ/r³)` of the reference radius \[rad/s\] (method page §1.3).
    pub fn mean_motion_rad_s(&self) -> f64 {
        self.mean_motion_rad_s
    }

    /// `k_J2 = (3/2) J2 μ R²` \[m⁵/s²\] (method page §1.3).
    pub fn k_j2_m5_s2(&self) -> f64 {
        self.k_j2_m5_s2
    }

    /// SS J2 parameter `s_J2 = k_J2 (1 + 3 cos 2i) / (4 μ r²)` \[-\] (method page §1.3).
    pub fn s_j2(&self) -> f64 {
        self.s_j2
    }

    /// `c₊ = √(1 + s_J2)` \[-\] (method page §1.3; the `c` of Schweighart & Sedwick).
    pub fn c_plus(&self) -> f64 {
        self.c_plus
    }

    /// `c₋ = √(1 − s_J2)` \[-\] (method page §1.3).
    pub fn c_minus(&self) -> f64 {
        self.c_minus
    }

    /// Rotation rate of the SS reference frame about `z`, `ω_ref = c₊ ω_o` \[rad/s\] (method page §1.3).
    pub fn omega_ref_rad_s(&self) -> f64 {
        self.c_plus * self.mean_motion_rad_s
    }

    /// In-plane relative frequency `ω_xy = c₋ ω_o` \[rad/s\] (method page §1.3).
    pub fn omega_xy_rad_s(&self) -> f64 {
        self.c_minus * self.mean_motion_rad_s
    }

    /// Cross-track relative frequency `ω_z,ref = ω_o (c₊ + k_J2 cos² i / (μ r²))` \[rad/s\]
    /// (method page §1.3, Eq. 3).
    pub fn omega_z_rad_s(&self) -> f64 {
        self.omega_z_rad_s
    }

    /// Drift gain `ε₂ = (3 + 5 s_J2) ω_xy / (c₊ c₋)` \[rad/s\] (method page §1.3): the along-track drift rate
    /// is `−ε₂ C₁` (method page §2.4).
    pub fn epsilon_2_rad_s(&self) -> f64 {
        (3.0 + 5.0 * self.s_j2) * self.omega_xy_rad_s() / (self.c_plus * self.c_minus)
    }

    /// Input gain `k₀ = 2 c₊ / (ω_xy c₋)` \[s\] (method page §1.3, used by the C-parameter dynamics §3.4).
    pub fn k0_s(&self) -> f64 {
        2.0 * self.c_plus / (self.omega_xy_rad_s() * self.c_minus)
    }

    /// Ratio `k₁ = (3 + 5 s_J2) / (4 (1 + s_J2))` \[-\] (method page §1.3).
    pub fn k1(&self) -> f64 {
        (3.0 + 5.0 * self.s_j2) / (4.0 * (1.0 + self.s_j2))
    }

    /// Coriolis coefficient `a = 2 ω_o c₊` \[rad/s\] of the in-plane equations.
    fn coupling_rad_s(&self) -> f64 {
        2.0 * self.mean_motion_rad_s * self.c_plus
    }

    /// Radial stiffness `b = (3 + 5 s) ω_o²` \[1/s²\] of the in-plane equations.
    fn radial_stiffness_s2(&self) -> f64 {
        (3.0 + 5.0 * self.s_j2) * self.mean_motion_rad_s * self.mean_motion_rad_s
    }

    /// Time derivative of the Hill state \[m/s, m/s²\] under the control acceleration
    /// `control_accel_hill_m_s2` \[m/s², Hill frame\] (method page §2.3, physical form).
    pub fn derivative(
        &self,
        state_hill: &Vector6<f64>,
        control_accel_hill_m_s2: &Vector3<f64>,
    ) -> Vector6<f64> {
        let position = state_hill.fixed_rows::<3>(0).into_owned();
        let velocity = state_hill.fixed_rows::<3>(3).into_owned();
        let a = self.natural_acceleration_m_s2(&position, &velocity) + control_accel_hill_m_s2;
        Vector6::new(velocity.x, velocity.y, velocity.z, a.x, a.y, a.z)
    }

    /// Uncontrolled relative acceleration \[m/s², Hill frame\] at Hill position `position_hill_m` \[m\]
    /// and rotating-frame velocity `velocity_hill_mps` \[m/s\]:
    /// `[2 ω_o c₊ vy + (3 + 5s) ω_o² x, −2 ω_o c₊ vx, −ω_z² z]`.
    pub fn natural_acceleration_m_s2(
        &self,
        position_hill_m: &Vector3<f64>,
        velocity_hill_mps: &Vector3<f64>,
    ) -> Vector3<f64> {
        let a = self.coupling_rad_s();
        let b = self.radial_stiffness_s2();
        let wz = self.omega_z_rad_s;
        Vector3::new(
            a * velocity_hill_mps.y + b * position_hill_m.x,
            -a * velocity_hill_mps.x,
            -wz * wz * position_hill_m.z,
        )
    }

    /// Closed-form state transition matrix `Φ(dt)` of the free SS motion (method page §2.4 as a matrix),
    /// mapping a Hill state at `t` to the Hill state at `t + dt` \[s\]. Any sign of `dt` is allowed.
    ///
    /// With `a = 2 ω_o c₊`, `b = (3 + 5s) ω_o²`, `ω = ω_xy`, `θ = ω dt`, `S, C = sin θ, cos θ`:
    ///
    /// ```text
    /// x  = [C + a²(1−C)/ω²] x0 + (S/ω) vx0 + a(1−C)/ω² vy0
    /// y  = −a b (θ−S)/ω³ x0 + y0 − a(1−C)/ω² vx0 + [dt − a²(θ−S)/ω³] vy0
    /// vx = (b S/ω) x0 + C vx0 + (a S/ω) vy0
    /// vy = −a b (1−C)/ω² x0 − (a S/ω) vx0 + [1 − a²(1−C)/ω²] vy0
    /// z  = cos(ω_z dt) z0 + sin(ω_z dt)/ω_z vz0,   vz = −ω_z sin(ω_z dt) z0 + cos(ω_z dt) vz0
    /// ```
    pub fn state_transition_matrix(&self, dt_s: f64) -> Matrix6<f64> {
        let a = self.coupling_rad_s();
        let b = self.radial_stiffness_s2();
        let t = dt_s;
        let theta = self.omega_xy_rad_s() * t;
        let c = theta.cos();
        // s1 = S/ω, c2 = (1 − C)/ω², s3 = (θ − S)/ω³, well conditioned for short steps.
        let s1 = t * sinc(theta);
        let c2 = t * t * cosc(theta);
        let s3 = t * t * t * sinc3(theta);
        let theta_z = self.omega_z_rad_s * t;
        let (sz, cz) = theta_z.sin_cos();
        let s1z = t * sinc(theta_z);
        let wz = self.omega_z_rad_s;
        #[rustfmt::skip]
        let phi = Matrix6::from_row_slice(&[
            c + a * a * c2,  0.0, 0.0,      s1,        a * c2,            0.0,
            -a * b * s3,     1.0, 0.0,      -a * c2,   t - a * a * s3,    0.0,
            0.0,             0.0, cz,       0.0,       0.0,               s1z,
            b * s1,          0.0, 0.0,      c,         a * s1,            0.0,
            -a * b * c2,     0.0, 0.0,      -a * s1,   1.0 - a * a * c2,  0.0,
            0.0,             0.0, -wz * sz, 0.0,       0.0,               cz,
        ]);
        phi
    }

    /// Free-motion Hill state \[m, m/s\] after `dt_s` \[s\]: `Φ(dt) · state_hill`.
    pub fn propagate(&self, state_hill: &Vector6<f64>, dt_s: f64) -> Vector6<f64> {
        self.state_transition_matrix(dt_s) * state_hill
    }

    /// Exact zero-order-hold input matrix `Γ(dt) = ∫₀^dt Φ(τ) B dτ`, `B = [0; I₃]` \[m·s², s\]: a
    /// control acceleration `u` \[m/s², Hill\] held over `dt` \[s\] gives `Φ(dt) x + Γ(dt) u`.
    ///
    /// With the notation of [`Self::state_transition_matrix`]:
    ///
    /// ```text
    ///        ux               uy                                   uz
    /// x   [ (1−C)/ω²          a(θ−S)/ω³                            0              ]
    /// y   [ −a(θ−S)/ω³        [a²(1−C)/ω² − b dt²/2] / ω²          0              ]
    /// z   [ 0                 0                                    (1−C_z)/ω_z²   ]
    /// vx  [ S/ω               a(1−C)/ω²                            0              ]
    /// vy  [ −a(1−C)/ω²        dt − a²(θ−S)/ω³                      0              ]
    /// vz  [ 0                 0                                    S_z/ω_z        ]
    /// ```
    pub fn control_input_matrix(&self, dt_s: f64) -> SMatrix<f64, 6, 3> {
        let a = self.coupling_rad_s();
        let b = self.radial_stiffness_s2();
        let w = self.omega_xy_rad_s();
        let t = dt_s;
        let theta = w * t;
        let s1 = t * sinc(theta);
        let c2 = t * t * cosc(theta);
        let s3 = t * t * t * sinc3(theta);
        let theta_z = self.omega_z_rad_s * t;
        let s1z = t * sinc(theta_z);
        let c2z = t * t * cosc(theta_z);
        let yy = (a * a * c2 - 0.5 * b * t * t) / (w * w);
        #[rustfmt::skip]
        let gamma = SMatrix::<f64, 6, 3>::from_row_slice(&[
            c2,          a * s3,           0.0,
            -a * s3,     yy,               0.0,
            0.0,         0.0,              c2z,
            s1,          a * c2,           0.0,
            -a * c2,     t - a * a * s3,   0.0,
            0.0,         0.0,              s1z,
        ]);
        gamma
    }

    /// Initial along-track velocity `vy` \[m/s\] that makes the free SS relative orbit starting at
    /// radial offset `x_m` \[m\] drift-free: `vy = −2 ω_o c₊ x`, i.e. `C₁ = 0` (method page §3.1, §3.3). The
    /// condition does not involve `vx`, `y` or the cross-track state.
    pub fn no_drift_velocity_y_mps(&self, x_m: f64) -> f64 {
        -self.coupling_rad_s() * x_m
    }

    /// Mean along-track velocity \[m/s\] of the free SS relative orbit through `state_hill`:
    /// `−(3 + 5s)/(1 − s) · (vy + 2 ω_o c₊ x)`, equal to the method page's `−ε₂ C₁` (§2.4). Over any whole
    /// number of in-plane periods `2π/ω_xy`, `y` changes by exactly this times the elapsed time.
    pub fn along_track_drift_mps(&self, state_hill: &Vector6<f64>) -> f64 {
        let w = self.omega_xy_rad_s();
        -self.radial_stiffness_s2() / (w * w)
            * (state_hill[4] + self.coupling_rad_s() * state_hill[0])
    }
}
