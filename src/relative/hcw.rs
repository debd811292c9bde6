//! Hill–Clohessy–Wiltshire (HCW) relative motion about a circular Keplerian reference orbit.
//!
//! Equations of motion in the Hill/RSW frame (see the module docs of [`crate::relative`]), with mean
//! motion `n` \[rad/s\] and control acceleration `u` \[m/s²\]:
//!
//! ```text
//! x'' = 3 n² x + 2 n y' + ux
//! y'' =        − 2 n x' + uy
//! z'' =   − n² z        + uz
//! ```
//!
//! Closed-form solution (e.g. Vallado, *Fundamentals of Astrodynamics and Applications*, 4th ed.,
//! §6.8; Curtis, *Orbital Mechanics for Engineering Students*, §7.5), with `θ = n t`,
//! `S = sin θ`, `C = cos θ`:
//!
//! ```text
//! x(t)  = (4 − 3C) x0 + (S/n) vx0 + (2/n)(1 − C) vy0
//! y(t)  = 6(S − θ) x0 + y0 − (2/n)(1 − C) vx0 + (1/n)(4S − 3θ) vy0
//! z(t)  = C z0 + (S/n) vz0
//! vx(t) = 3 n S x0 + C vx0 + 2 S vy0
//! vy(t) = −6 n (1 − C) x0 − 2 S vx0 + (4C − 3) vy0
//! vz(t) = −n S z0 + C vz0
//! ```
//!
//! The mean along-track velocity of a free orbit is `−3 (vy0 + 2 n x0)`; it vanishes (bounded
//! "2:1" ellipse) when `vy0 = −2 n x0`. Two textbook special cases: zero initial relative velocity at
//! radial offset `x0` drifts at `−6 n x0` (ellipse centred at `4 x0`, `y` loses `12 π x0` per orbit);
//! a co-circular orbit at offset `x0` (`vy0 = −(3/2) n x0`) stays at `x0` and drifts at
//! `−(3/2) n x0`, the familiar `−(3/2) n Δa` from Kepler's third law.

use nalgebra::{Matrix6, SMatrix, Vector3, Vector6};

use super::series::{cosc, sinc, sinc3};

/// Hill–Clohessy–Wiltshire model of relative motion about a circular reference orbit.
///
/// States are Hill/RSW `[x, y, z, vx, vy, vz]` in m and m/s; accelerations in m/s².
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hcw {
    /// Mean motion `n` of the circular reference orbit \[rad/s\]; must be finite and `≥ 0`
    /// (`n = 0` gives the double integrator).
    pub mean_motion_rad_s: f64,
}

impl Hcw {
    /// HCW model for a circular reference orbit of mean motion `mean_motion_rad_s` \[rad/s\].
    ///
    /// # Panics
    ///
    /// If the mean motion is negative or not finite.
    pub fn new(mean_motion_rad_s: f64) -> Self {
        assert!(
            mean_motion_rad_s.is_finite() && mean_motion_rad_s >= 0.0,
            "HCW mean motion must be finite and non-negative, got {mean_motion_rad_s} rad/s"
        );
        Self { mean_motion_rad_s }
    }

    /// Time derivative of the Hill state \[m/s, m/s²\] under the control acceleration
    /// `control_accel_hill_m_s2` \[m/s², Hill frame\].
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
    /// and rotating-frame velocity `velocity_hill_mps` \[m/s\]: `[3n²x + 2n vy, −2n vx, −n²z]`.
    pub fn natural_acceleration_m_s2(
        &self,
        position_hill_m: &Vector3<f64>,
        velocity_hill_mps: &Vector3<f64>,
    ) -> Vector3<f64> {
        let n = self.mean_motion_rad_s;
        Vector3::new(
            3.0 * n * n * position_hill_m.x + 2.0 * n * velocity_hill_mps.y,
            -2.0 * n * velocity_hill_mps.x,
            -n * n * position_hill_m.z,
        )
    }

    /// Closed-form state transition matrix `Φ(dt)` (module docs), mapping a Hill state at `t` to the
    /// free-motion Hill state at `t + dt` \[s\]. Any sign of `dt` is allowed.
    pub fn state_transition_matrix(&self, dt_s: f64) -> Matrix6<f64> {
        let n = self.mean_motion_rad_s;
        let t = dt_s;
        let theta = n * t;
        let (s, c) = theta.sin_cos();
        // s1 = S/n, c2 = (1 − C)/n², s3 = (θ − S)/n³, all well conditioned as n → 0.
        let s1 = t * sinc(theta);
        let c2 = t * t * cosc(theta);
        let s3 = t * t * t * sinc3(theta);
        #[rustfmt::skip]
        let phi = Matrix6::from_row_slice(&[
            4.0 - 3.0 * c,      0.0, 0.0,    s1,               2.0 * n * c2,      0.0,
            -6.0 * n * n * n * s3, 1.0, 0.0, -2.0 * n * c2,     4.0 * s1 - 3.0 * t, 0.0,
            0.0,                0.0, c,      0.0,              0.0,               s1,
            3.0 * n * s,        0.0, 0.0,    c,                2.0 * s,           0.0,
            -6.0 * n * n * n * c2, 0.0, 0.0, -2.0 * s,         4.0 * c - 3.0,     0.0,
            0.0,                0.0, -n * s, 0.0,              0.0,               c,
        ]);
        phi
    }

    /// Free-motion Hill state \[m, m/s\] after `dt_s` \[s\]: `Φ(dt) · state_hill`.
    pub fn propagate(&self, state_hill: &Vector6<f64>, dt_s: f64) -> Vector6<f64> {
        self.state_transition_matrix(dt_s) * state_hill
    }

    /// Exact zero-order-hold input matrix `Γ(dt) = ∫₀^dt Φ(τ) B dτ` with `B = [0; I₃]` \[m·s², s\].
    ///
    /// A control acceleration `u` \[m/s², Hill\] held constant over `dt` gives the Hill state
    /// `Φ(dt) x + Γ(dt) u`. With `θ = n dt`, `S = sin θ`, `C = cos θ`:
    ///
    /// ```text
    ///        ux                    uy                         uz
    /// x   [ (1−C)/n²           2(θ−S)/n²                  0        ]
    /// y   [ −2(θ−S)/n²         4(1−C)/n² − (3/2) dt²      0        ]
    /// z   [ 0                  0                          (1−C)/n² ]
    /// vx  [ S/n                2(1−C)/n                   0        ]
    /// vy  [ −2(1−C)/n          4S/n − 3 dt                0        ]
    /// vz  [ 0                  0                          S/n      ]
    /// ```
    ///
    /// As `n → 0` it tends to the double integrator (`dt²/2` on position, `dt` on velocity).
    pub fn control_input_matrix(&self, dt_s: f64) -> SMatrix<f64, 6, 3> {
        let n = self.mean_motion_rad_s;
        let t = dt_s;
        let theta = n * t;
        let s1 = t * sinc(theta);
        let c2 = t * t * cosc(theta);
        let s3 = t * t * t * sinc3(theta);
        #[rustfmt::skip]
        let gamma = SMatrix::<f64, 6, 3>::from_row_slice(&[
            c2,                2.0 * n * s3,             0.0,
            -2.0 * n * s3,     4.0 * c2 - 1.5 * t * t,   0.0,
            0.0,               0.0,                      c2,
            s1,                2.0 * n * c2,             0.0,
            -2.0 * n * c2,     4.0 * s1 - 3.0 * t,       0.0,
            0.0,               0.0,                      s1,
        ]);
        gamma
    }

    /// Initial along-track velocity `vy` \[m/s\] that makes the free relative orbit starting at radial
    /// offset `x_m` \[m\] bounded (no along-track drift): `vy = −2 n x`.
    pub fn no_drift_velocity_y_mps(&self, x_m: f64) -> f64 {
        -2.0 * self.mean_motion_rad_s * x_m
    }

    /// Mean along-track velocity \[m/s\] of the free relative orbit through `state_hill`:
    /// `−3 (vy + 2 n x)`. Over any whole number of orbits, `y` changes by exactly this times the
    /// elapsed time.
    pub fn along_track_drift_mps(&self, state_hill: &Vector6<f64>) -> f64 {
        -3.0 * (state_hill[4] + 2.0 * self.mean_motion_rad_s * state_hill[0])
    }
}
