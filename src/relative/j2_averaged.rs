//! Averaged-J2 relative orbital parameters C₁…C₆ of Takahashi & Sakai, built on the
//! Schweighart–Sedwick (SS) model, with the connectable time and the user-defined swarm plane.
//!
//! Source: `docs/methods/j2-distance.md` (the "method page"), which restates and corrects
//! Y. Takahashi, S. Sakai, "Distance-based Relative Orbital Transition for Satellite Swarm Array
//! Deployment Under J2 Perturbation". Sections implemented here:
//!
//! * §2.4 (Eq. 5): free motion in closed form, [`AveragedJ2::free_motion`];
//! * §3.1–3.2 (Eq. 6): state ↔ parameters, [`AveragedJ2::parameters`] and [`AveragedJ2::state`];
//! * §3.4 (Eq. 13): parameter rates under input, [`AveragedJ2::parameter_rates`];
//! * §3.5: pair parameters in a truth simulation are the parameters of the difference of two relative
//!   states given in a common LVLH frame with rotating-frame velocities (the engine's
//!   [`crate::orbit::LvlhFrame::to_hill`] with the J2 frame rate), [`AveragedJ2::pair_parameters`];
//! * §4.1 (Eq. 7): relaxed connectable time, [`connectable_time_s`]; §4.2 strict initial escape time
//!   (diagnostic, sampled and bisected), [`AveragedJ2::initial_escape_time_s`];
//! * §5.2–5.7 (Eqs. 8–12): the swarm plane [`SwarmPlane`]: z targets, z-frequency feed-forward
//!   (corrected sign), r_avg → r_xyd, normalised frame {Ŝ}, de-rotated frame {S̄}, measured angles.
//!
//! # Frame and units
//!
//! Every relative state is `[x, y, z, vx, vy, vz]` in the Hill/RSW LVLH frame (the method page's {O}: x radial
//! out, y along-track, z orbit normal), m and m/s, velocities seen in the rotating frame. Every
//! parameter C₁…C₆ is a length \[m\]. The SS constants (method page §1.3) come from
//! [`SchweighartSedwick`].

use nalgebra::{Matrix3, Vector3, Vector6};

use super::SchweighartSedwick;

/// The six averaged-J2 relative orbital parameters of a relative state (method page §3.1, Eq. 6), all in
/// metres. `c1_m`: drift parameter (along-track drift rate −ε₂C₁); `c4_m`: along-track offset of the
/// ellipse centre; `(c2_m, c3_m)`: in-plane amplitude vector rotating at ω_xy; `(c5_m, c6_m)`:
/// cross-track amplitude vector rotating at ω_z.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct OrbitParameters {
    /// C₁, drift parameter \[m\].
    pub c1_m: f64,
    /// C₂, in-plane amplitude vector, first component (ẋ̄/ω_xy) \[m\].
    pub c2_m: f64,
    /// C₃, in-plane amplitude vector, second component (x̄ − 2c₊C₁) \[m\].
    pub c3_m: f64,
    /// C₄, along-track offset of the ellipse centre \[m\].
    pub c4_m: f64,
    /// C₅, cross-track amplitude vector, first component (ż/ω_z) \[m\].
    pub c5_m: f64,
    /// C₆, cross-track amplitude vector, second component (z) \[m\].
    pub c6_m: f64,
}

impl OrbitParameters {
    /// The parameters as an array `[C₁, …, C₆]` \[m\].
    pub fn to_array(&self) -> [f64; 6] {
        [
            self.c1_m, self.c2_m, self.c3_m, self.c4_m, self.c5_m, self.c6_m,
        ]
    }

    /// Parameters from an array `[C₁, …, C₆]` \[m\].
    pub fn from_array(c: [f64; 6]) -> Self {
        Self {
            c1_m: c[0],
            c2_m: c[1],
            c3_m: c[2],
            c4_m: c[3],
            c5_m: c[4],
            c6_m: c[5],
        }
    }

    /// In-plane amplitude r_xy = √(C₂² + C₃²) \[m\].
    pub fn r_xy_m(&self) -> f64 {
        self.c2_m.hypot(self.c3_m)
    }

    /// In-plane phase θ_xy = atan2(C₃, C₂) \[rad\].
    pub fn theta_xy_rad(&self) -> f64 {
        self.c3_m.atan2(self.c2_m)
    }

    /// Cross-track amplitude r_z = √(C₅² + C₆²) \[m\].
    pub fn r_z_m(&self) -> f64 {
        self.c5_m.hypot(self.c6_m)
    }

    /// Cross-track phase θ_z = atan2(C₆, C₅) \[rad\].
    pub fn theta_z_rad(&self) -> f64 {
        self.c6_m.atan2(self.c5_m)
    }
}

/// The averaged-J2 parameter toolkit for one reference orbit: the SS model with the constants the
/// parameter maps use (method page §1.3), cached.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AveragedJ2 {
    model: SchweighartSedwick,
    c_plus: f64,
    c_minus: f64,
    omega_xy_rad_s: f64,
    omega_z_rad_s: f64,
    epsilon_2_rad_s: f64,
    k0_s: f64,
    k1: f64,
}

impl AveragedJ2 {
    /// The toolkit for the SS model `model`.
    pub fn new(model: SchweighartSedwick) -> Self {
        Self {
            c_plus: model.c_plus(),
            c_minus: model.c_minus(),
            omega_xy_rad_s: model.omega_xy_rad_s(),
            omega_z_rad_s: model.omega_z_rad_s(),
            epsilon_2_rad_s: model.epsilon_2_rad_s(),
            k0_s: model.k0_s(),
            k1: model.k1(),
            model,
        }
    }

    /// The underlying SS model.
    pub fn model(&self) -> &SchweighartSedwick {
        &self.model
    }

    /// c₊ = √(1 + s_J2) \[-\].
    pub fn c_plus(&self) -> f64 {
        self.c_plus
    }

    /// c₋ = √(1 − s_J2) \[-\].
    pub fn c_minus(&self) -> f64 {
        self.c_minus
    }

    /// In-plane relative frequency ω_xy \[rad/s\].
    pub fn omega_xy_rad_s(&self) -> f64 {
        self.omega_xy_rad_s
    }

    /// Cross-track relative frequency ω_z \[rad/s\].
    pub fn omega_z_rad_s(&self) -> f64 {
        self.omega_z_rad_s
    }

    /// Drift gain ε₂ \[rad/s\]: the ellipse centre moves along-track at −ε₂ C₁.
    pub fn epsilon_2_rad_s(&self) -> f64 {
        self.epsilon_2_rad_s
    }

    /// Input gain k₀ \[s\].
    pub fn k0_s(&self) -> f64 {
        self.k0_s
    }

    /// Ratio k₁ \[-\].
    pub fn k1(&self) -> f64 {
        self.k1
    }

    /// Parameters of a relative state (Hill, m and m/s; method page §3.1, Eq. 6).
    pub fn parameters(&self, state_hill: &Vector6<f64>) -> OrbitParameters {
        let (cp, cm, w) = (self.c_plus, self.c_minus, self.omega_xy_rad_s);
        // Scaled coordinates of {O_J2}: x̄ = c₊x, ȳ = c₋y.
        let xb = cp * state_hill[0];
        let yb = cm * state_hill[1];
        let xbd = cp * state_hill[3];
        let ybd = cm * state_hill[4];
        let c1 = cp / (cm * cm) * (2.0 * xb + ybd / w);
        let c4 = (yb - 2.0 * xbd / w) / cm;
        OrbitParameters {
            c1_m: c1,
            c2_m: 0.5 * (yb - cm * c4),
            c3_m: xb - 2.0 * cp * c1,
            c4_m: c4,
            c5_m: state_hill[5] / self.omega_z_rad_s,
            c6_m: state_hill[2],
        }
    }

    /// Parameters of the pair (j, k): those of `state_j − state_k`, both relative to a common LVLH origin
    /// with rotating-frame velocities (method page §3.4–3.5: the maps are linear, so C_jk = C_j − C_k).
    pub fn pair_parameters(
        &self,
        state_j_hill: &Vector6<f64>,
        state_k_hill: &Vector6<f64>,
    ) -> OrbitParameters {
        self.parameters(&(state_j_hill - state_k_hill))
    }

    /// Relative state (Hill, m and m/s) of the parameters (method page §3.2, the inverse of Eq. 6).
    pub fn state(&self, p: &OrbitParameters) -> Vector6<f64> {
        let (cp, cm, w) = (self.c_plus, self.c_minus, self.omega_xy_rad_s);
        let xb = p.c3_m + 2.0 * cp * p.c1_m;
        let yb = cm * p.c4_m + 2.0 * p.c2_m;
        let xbd = w * p.c2_m;
        let ybd = -cm * self.epsilon_2_rad_s * p.c1_m - 2.0 * w * p.c3_m;
        Vector6::new(
            xb / cp,
            yb / cm,
            p.c6_m,
            xbd / cp,
            ybd / cm,
            self.omega_z_rad_s * p.c5_m,
        )
    }

    /// Free relative state (Hill, m and m/s) `t_s` seconds after a state of parameters `p`, from the
    /// closed form of method page §2.4 (Eq. 5, l_z = 0):
    /// x = 2C₁ + r_xy sin(ω_xy t + θ_xy)/c₊, y = C₄ − ε₂C₁t + 2 r_xy cos(ω_xy t + θ_xy)/c₋,
    /// z = r_z sin(ω_z t + θ_z).
    pub fn free_motion(&self, p: &OrbitParameters, t_s: f64) -> Vector6<f64> {
        let (cp, cm, w, wz) = (
            self.c_plus,
            self.c_minus,
            self.omega_xy_rad_s,
            self.omega_z_rad_s,
        );
        let (s, c) = (w * t_s).sin_cos();
        let (sz, cz) = (wz * t_s).sin_cos();
        // r sin(φ+θ) = C₂ sin φ + C₃ cos φ and r cos(φ+θ) = C₂ cos φ − C₃ sin φ.
        let sin_part = p.c2_m * s + p.c3_m * c;
        let cos_part = p.c2_m * c - p.c3_m * s;
        Vector6::new(
            2.0 * p.c1_m + sin_part / cp,
            p.c4_m - self.epsilon_2_rad_s * p.c1_m * t_s + 2.0 * cos_part / cm,
            p.c5_m * sz + p.c6_m * cz,
            w * cos_part / cp,
            -self.epsilon_2_rad_s * p.c1_m - 2.0 * w * sin_part / cm,
            wz * (p.c5_m * cz - p.c6_m * sz),
        )
    }

    /// Time derivatives of the parameters \[m/s\] under the control acceleration `u_hill_m_s2`
    /// (Hill, m/s²), method page §3.4 (Eq. 13), in the order C₁…C₆.
    pub fn parameter_rates(&self, p: &OrbitParameters, u_hill_m_s2: &Vector3<f64>) -> [f64; 6] {
        let (k0, w, wz) = (self.k0_s, self.omega_xy_rad_s, self.omega_z_rad_s);
        [
            0.5 * k0 * u_hill_m_s2.y,
            -w * p.c3_m + 0.5 * self.c_minus * k0 * u_hill_m_s2.x,
            w * p.c2_m - self.c_plus * k0 * u_hill_m_s2.y,
            -self.epsilon_2_rad_s * p.c1_m - k0 * u_hill_m_s2.x,
            -wz * p.c6_m + u_hill_m_s2.z / wz,
            wz * p.c5_m,
        ]
    }

    /// Relaxed connectable time T̂_conn \[s\] of a pair (method page §4.1): see [`connectable_time_s`].
    pub fn connectable_time_s(&self, p: &OrbitParameters, range_m: f64) -> f64 {
        connectable_time_s(p.c1_m, p.c4_m, self.epsilon_2_rad_s, range_m)
    }

    /// Strict initial escape time T̲_out \[s\] (method page §4.2, a diagnostic): the first time `t ≥ 0` at which
    /// the free relative position (Eq. 5) reaches `‖r‖ = range_m`, found by sampling every `sample_s`
    /// seconds and bisecting the first bracket to 1 ms. 0 if the pair starts outside; `None` if it
    /// stays inside up to `horizon_s`.
    pub fn initial_escape_time_s(
        &self,
        p: &OrbitParameters,
        range_m: f64,
        horizon_s: f64,
        sample_s: f64,
    ) -> Option<f64> {
        let outside = |t: f64| self.free_motion(p, t).fixed_rows::<3>(0).norm() - range_m;
        if outside(0.0) >= 0.0 {
            return Some(0.0);
        }
        let mut t0 = 0.0;
        while t0 < horizon_s {
            let t1 = (t0 + sample_s).min(horizon_s);
            if outside(t1) >= 0.0 {
                let (mut lo, mut hi) = (t0, t1);
                while hi - lo > 1e-3 {
                    let mid = 0.5 * (lo + hi);
                    if outside(mid) >= 0.0 {
                        hi = mid;
                    } else {
                        lo = mid;
                    }
                }
                return Some(hi);
            }
            t0 = t1;
        }
        None
    }
}

/// Relaxed connectable time T̂_conn \[s\] (method page §4.1, Definition 1, Eq. 7): the exit time of the free
/// ellipse centre `[2C₁, C₄ − ε₂C₁t]` from the disc of radius `range_m` (r_s):
/// t± = (C₄ ± √(r_s² − 4C₁²)) / (ε₂C₁), T̂ = max(t₊, t₋, 0). Edge cases (our reconstruction): C₁ = 0
/// gives +∞ if |C₄| ≤ r_s, else 0; 4C₁² > r_s² gives 0. Symmetric under (C₁, C₄) → (−C₁, −C₄).
pub fn connectable_time_s(c1_m: f64, c4_m: f64, epsilon_2_rad_s: f64, range_m: f64) -> f64 {
    if c1_m == 0.0 {
        return if c4_m.abs() <= range_m {
            f64::INFINITY
        } else {
            0.0
        };
    }
    let d = range_m * range_m - 4.0 * c1_m * c1_m;
    if d < 0.0 {
        return 0.0;
    }
    let rate = epsilon_2_rad_s * c1_m;
    let tp = (c4_m + d.sqrt()) / rate;
    let tm = (c4_m - d.sqrt()) / rate;
    tp.max(tm).max(0.0)
}

/// A user-defined swarm plane (method page §5.2–5.7): the plane angles Θ_P and Θ_z-xy \[rad\].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SwarmPlane {
    /// Θ_P \[rad\], in (0, π/2] (the normal's tilt from the radial axis towards −z).
    pub theta_p_rad: f64,
    /// Θ_z-xy \[rad\], in (−π/2, π/2).
    pub theta_zxy_rad: f64,
}

impl SwarmPlane {
    /// Target phase offset δθ_d = atan(2 tan Θ_z-xy) \[rad\] (Eq. 8, principal branch).
    pub fn delta_theta_d_rad(&self) -> f64 {
        (2.0 * self.theta_zxy_rad.tan()).atan()
    }

    /// Target amplitude ratio r_zd / r_xy = cos Θ_z-xy / (tan Θ_P cos δθ_d) \[-\] (Eq. 8).
    pub fn amplitude_ratio(&self) -> f64 {
        self.theta_zxy_rad.cos() / (self.theta_p_rad.tan() * self.delta_theta_d_rad().cos())
    }

    /// The z targets (C₅d, C₆d) \[m\] of a pair from its current in-plane vector (C₂, C₃) \[m\]: the linear
    /// form of Eq. 9 (method page §5.2), C₅d = (C₂ cos Θz − 2C₃ sin Θz)/tan Θ_P,
    /// C₆d = (C₃ cos Θz + 2C₂ sin Θz)/tan Θ_P.
    pub fn z_targets_m(&self, c2_m: f64, c3_m: f64) -> (f64, f64) {
        let (sz, cz) = self.theta_zxy_rad.sin_cos();
        let tp = self.theta_p_rad.tan();
        (
            (c2_m * cz - 2.0 * c3_m * sz) / tp,
            (c3_m * cz + 2.0 * c2_m * sz) / tp,
        )
    }

    /// Ratio S = r_avg / r_xyd of the RMS neighbour distance over one period to the target amplitude
    /// \[-\] (method page §5.5, Eq. 12 with the corrected time-mean normalisation):
    /// S² = ½ ((1 + 3 sin²Θz)/tan²Θ_P + (3s + 5)/(1 − s²)), s = s_J2.
    pub fn distance_ratio(&self, s_j2: f64) -> f64 {
        let sz = self.theta_zxy_rad.sin();
        let tp = self.theta_p_rad.tan();
        (0.5 * ((1.0 + 3.0 * sz * sz) / (tp * tp) + (3.0 * s_j2 + 5.0) / (1.0 - s_j2 * s_j2)))
            .sqrt()
    }

    /// Target in-plane amplitude r_xyd = r_avg / S \[m\] for an average (RMS) neighbour distance
    /// `average_distance_m` \[m\] (method page §5.5).
    pub fn target_amplitude_m(&self, average_distance_m: f64, s_j2: f64) -> f64 {
        average_distance_m / self.distance_ratio(s_j2)
    }

    /// C^{Ŝ/O} \[-\]: the linear map from a Hill relative position \[m\] to the normalised swarm frame
    /// {Ŝ} \[m\] (method page §5.6), C^{Ŝ/S} C^{S/O_J2} diag(c₊, c₋, 1). On a target orbit (Eq. 11) it gives
    /// 2 r_xyd [0, cos φ, sin φ]: x is the out-of-plane residual, (y, z) a layout rotating at ω_xy.
    pub fn normalised_frame(&self, c_plus: f64, c_minus: f64) -> Matrix3<f64> {
        let (sp, cp) = self.theta_p_rad.sin_cos();
        let (sz, cz) = self.theta_zxy_rad.sin_cos();
        #[rustfmt::skip]
        let s_from_oj2 = Matrix3::new(
            cp, 0.0, -sp,
            0.0, 1.0, 0.0,
            sp, 0.0, cp,
        ) * Matrix3::new(
            cz, sz, 0.0,
            -sz, cz, 0.0,
            0.0, 0.0, 1.0,
        );
        #[rustfmt::skip]
        let shat_from_s = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 2.0))
            * Matrix3::new(
                1.0, 0.0, 0.0,
                0.0, cz, sz,
                0.0, -sz, cz,
            )
            * Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, sp));
        shat_from_s * s_from_oj2 * Matrix3::from_diagonal(&Vector3::new(c_plus, c_minus, 1.0))
    }

    /// Measured plane angles (Θ̂_P, Θ̂_z-xy) \[rad\] of a pair's parameters (method page §5.7):
    /// δθ = wrap(θ_z − θ_xy), Θ̂z = atan(tan δθ / 2), Θ̂_P = atan2(r_xy cos Θ̂z, r_z cos δθ).
    /// `None` when r_xy ≤ `min_amplitude_m` (the angles are then undefined or noisy).
    pub fn measured_angles_rad(p: &OrbitParameters, min_amplitude_m: f64) -> Option<(f64, f64)> {
        let r_xy = p.r_xy_m();
        if r_xy <= min_amplitude_m {
            return None;
        }
        let mut dtheta = p.theta_z_rad() - p.theta_xy_rad();
        while dtheta > std::f64::consts::PI {
            dtheta -= 2.0 * std::f64::consts::PI;
        }
        while dtheta <= -std::f64::consts::PI {
            dtheta += 2.0 * std::f64::consts::PI;
        }
        let theta_z = (0.5 * dtheta.tan()).atan();
        let theta_p = (r_xy * theta_z.cos()).atan2(p.r_z_m() * dtheta.cos());
        Some((theta_p, theta_z))
    }
}

/// The de-rotation C^{S̄/Ŝ}(t) \[-\] (method page §5.6): turns the {Ŝ} layout, which rotates rigidly at ω_xy on
/// target, into time-invariant positions of the de-rotated frame {S̄}.
pub fn derotation(omega_xy_rad_s: f64, t_s: f64) -> Matrix3<f64> {
    let (s, c) = (omega_xy_rad_s * t_s).sin_cos();
    #[rustfmt::skip]
    let m = Matrix3::new(
        1.0, 0.0, 0.0,
        0.0, c, s,
        0.0, -s, c,
    );
    m
}

/// The z-frequency feed-forward (method page §5.3, Eq. 10 with the corrected sign) \[m/s²\]:
/// u_dz = (ω_z² − ω_xy²) z, which turns z̈ = −ω_z² z into z̈ = −ω_xy² z. `z_m`: cross-track offset
/// from any common origin \[m\].
pub fn z_frequency_feedforward_m_s2(omega_z_rad_s: f64, omega_xy_rad_s: f64, z_m: f64) -> f64 {
    (omega_z_rad_s * omega_z_rad_s - omega_xy_rad_s * omega_xy_rad_s) * z_m
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec_model() -> AveragedJ2 {
        // The constants of our reconstruction (method page §1.3): μ = 3.986e14, k_J2 = 2.633e25 = 1.5 J2 μ R².
        let mu = 3.986e14;
        let r_e = 6378.137e3;
        let j2 = 2.633e25 / (1.5 * mu * r_e * r_e);
        AveragedJ2::new(SchweighartSedwick::new(
            6871e3,
            51.7f64.to_radians(),
            mu,
            r_e,
            j2,
        ))
    }

    #[test]
    fn val_inverse_map_matches_spec_test_vector() {
        let k = spec_model();
        let p = OrbitParameters::from_array([0.01, 0.2, -0.1, 0.3, 0.05, -0.15]);
        let s = k.state(&p);
        // our independently computed reference vector (method page §11.3), printed to 7 significant digits: tolerance is half a unit of the
        // last printed digit, relative
        let expected = [
            -0.07999467,
            0.70002132,
            -0.15,
            2.216779e-4,
            1.884422e-4,
            5.545813e-5,
        ];
        for (a, b) in s.iter().zip(expected) {
            assert!(((a - b) / b).abs() < 5e-7, "{a} vs {b}");
        }
        let back = k.parameters(&s).to_array();
        for (a, b) in back.iter().zip(p.to_array()) {
            // round trip: a few roundings of O(1) terms
            assert!((a - b).abs() < 1e-15, "{a} vs {b}");
        }
    }

    #[test]
    fn val_connectable_time_golden_values() {
        let k = spec_model();
        let e2 = k.epsilon_2_rad_s();
        let h = |c1: f64, c4: f64| connectable_time_s(c1, c4, e2, 1.0) / 3600.0;
        // our independently computed values for method page §4.1, printed to 6 digits: 1e-5 relative
        for (c1, c4, expect) in [
            (0.01, 0.3, 10.8558),
            (0.1, -0.5, 0.40072),
            (-0.01, 0.3, 5.84464),
        ] {
            assert!(((h(c1, c4) - expect) / expect).abs() < 1e-5, "{c1} {c4}");
        }
        assert_eq!(h(0.0, 0.5), f64::INFINITY);
        assert_eq!(h(0.6, 0.0), 0.0);
    }

    #[test]
    fn val_plane_golden_values() {
        let k = spec_model();
        let s = k.model().s_j2();
        let deg = f64::to_radians;
        let p1 = SwarmPlane {
            theta_p_rad: deg(30.0),
            theta_zxy_rad: 0.0,
        };
        let p2 = SwarmPlane {
            theta_p_rad: deg(40.0),
            theta_zxy_rad: deg(50.0),
        };
        // method page §5.5: S(Θ1) = 2 + 3.998e-5 (4 digits), S(Θ2) = 2.111984 (7 digits)
        assert!((p1.distance_ratio(s) - 2.0 - 3.998e-5).abs() < 5e-9);
        assert!((p2.distance_ratio(s) - 2.111984).abs() < 5e-7);
        // our independently computed value for method page §5.2 (7 digits)
        let (c5d, c6d) = p2.z_targets_m(0.2, -0.1);
        assert!((c5d - 0.3357961).abs() < 5e-8 && (c6d - 0.2885700).abs() < 5e-8);
        // our independently computed §5.6 matrix of Θ2, printed to 9 digits
        let m = p2.normalised_frame(k.c_plus(), k.c_minus());
        #[rustfmt::skip]
        let expected = Matrix3::new(
            0.492430121, 0.58679281, -0.64278761,
            -0.288969857, 0.655602542, 0.377203253,
            1.515157598, -0.577878108, 0.633022222,
        );
        assert!((m - expected).abs().max() < 5e-9);
    }

    #[test]
    fn val_closed_form_matches_ss_state_transition() {
        let k = spec_model();
        let p = OrbitParameters::from_array([0.01, 0.2, -0.1, 0.3, 0.05, -0.15]);
        let x0 = k.state(&p);
        for t in [0.0, 100.0, 1234.5, 5000.0] {
            let a = k.free_motion(&p, t);
            let b = k.model().propagate(&x0, t);
            // two closed forms of the same linear model, O(1) m states: rounding only
            assert!(
                (a - b).abs().max() < 1e-13,
                "t = {t}: {}",
                (a - b).abs().max()
            );
        }
    }

    #[test]
    fn val_parameter_rates_match_differentiated_map() {
        // Eq. 13 against d/dt of Eq. 6 along the SS dynamics (Eq. 4): C is linear, so
        // dC/dt = C(ẋ) exactly, with ẋ from the SS right-hand side.
        let k = spec_model();
        let p = OrbitParameters::from_array([0.01, 0.2, -0.1, 0.3, 0.05, -0.15]);
        let u = Vector3::new(3e-7, -2e-7, 5e-7);
        let x = k.state(&p);
        let xdot = k.model().derivative(&x, &u);
        let numeric = k.parameters(&xdot).to_array();
        let analytic = k.parameter_rates(&p, &u);
        for (a, b) in numeric.iter().zip(analytic) {
            // rates are O(1e-4) m/s: rounding of products of O(1e3) levers and O(1e-7) inputs
            assert!((a - b).abs() < 1e-16, "{a} vs {b}");
        }
    }

    #[test]
    fn val_normalised_frame_maps_targets_to_circles() {
        let k = spec_model();
        let plane = SwarmPlane {
            theta_p_rad: 40f64.to_radians(),
            theta_zxy_rad: 50f64.to_radians(),
        };
        let m = plane.normalised_frame(k.c_plus(), k.c_minus());
        let r = 0.237;
        let dd = plane.delta_theta_d_rad();
        let ratio = plane.amplitude_ratio();
        for phi in [0.0, 0.7, 2.0, 4.5] {
            // Eq. 11, the desired relative trajectory
            let pd = Vector3::new(
                r * f64::sin(phi) / k.c_plus(),
                2.0 * r * f64::cos(phi) / k.c_minus(),
                r * ratio * (phi + dd).sin(),
            );
            let q = m * pd;
            let expected = Vector3::new(0.0, 2.0 * r * phi.cos(), 2.0 * r * phi.sin());
            // O(0.5 m) quantities: rounding only
            assert!((q - expected).norm() < 1e-14, "{q:?}");
        }
    }
}
