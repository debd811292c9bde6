//! Local-vertical local-horizontal (LVLH) frames of a reference orbit ([`LvlhFrame`]), relative states
//! in the two conventions the project uses ([`RelativeStateHill`], [`RelativeStateGao`]) and the
//! constant rotation between them ([`hill_to_gao`], [`gao_to_hill`]).
//!
//! The internal convention is Hill/RSW: `x` radially outward (`r/|r|`), `z` along the orbit normal
//! (`h/|h|`, `h = r x v`), `y = z x x` (along-track, the direction of flight on a circular orbit).
//! Gao's `o-xyz` frame (x along-track, y = minus orbit normal, z toward the Earth's centre) is the same
//! frame with its axes relabelled: `q_gao = C q_hill` with `C = [[0,1,0],[0,0,-1],[-1,0,0]]`, a proper
//! rotation. Both frames rotate together, so `C` maps positions, velocities seen in the rotating frame
//! and accelerations alike.

use nalgebra::{Matrix3, Vector3, Vector6};

use super::state::CartesianState;

/// The LVLH (Hill/RSW) frame of a reference orbit at one instant: its origin (the reference state in
/// ECI), the rotation from ECI to Hill axes, and the frame's angular velocity in ECI.
///
/// The reference must have non-zero position and non-zero angular momentum `r x v` (any bound or
/// unbound orbit qualifies); otherwise the axes are undefined and the frame holds NaN.
#[derive(Clone, Copy, Debug)]
pub struct LvlhFrame {
    origin: CartesianState,
    rotation_eci_to_hill: Matrix3<f64>,
    angular_velocity_eci_rad_s: Vector3<f64>,
}

impl LvlhFrame {
    /// Frame of `reference` (ECI state) with the Keplerian frame rate `omega = h / r^2`, i.e. the
    /// rate of the radial direction about the orbit normal. Exact when the reference feels only a
    /// central (e.g. point-mass) force; with J2 or thrust acting on the reference use
    /// [`LvlhFrame::from_reference_with_acceleration`].
    pub fn from_reference(reference: &CartesianState) -> LvlhFrame {
        Self::build(reference, None)
    }

    /// Frame of `reference` (ECI state) whose angular velocity is exact for a reference that feels the
    /// total ECI acceleration `reference_accel_eci_m_s2` \[m/s^2\] (gravity including J2, plus thrust):
    /// `omega = (r/h) (a . h_hat) x_hat + (h/r^2) z_hat`. The radial component is the rotation of the
    /// orbit plane about the radius vector caused by the acceleration normal to the plane; the
    /// in-plane acceleration leaves the frame rate unchanged (it changes `h`, which is already in the
    /// `h/r^2` term at this instant).
    pub fn from_reference_with_acceleration(
        reference: &CartesianState,
        reference_accel_eci_m_s2: &Vector3<f64>,
    ) -> LvlhFrame {
        Self::build(reference, Some(reference_accel_eci_m_s2))
    }

    fn build(reference: &CartesianState, accel: Option<&Vector3<f64>>) -> LvlhFrame {
        let r_vec = reference.position_m;
        let h_vec = reference.specific_angular_momentum_m2_s();
        let r = r_vec.norm();
        let h = h_vec.norm();
        let x_hat = r_vec / r;
        let z_hat = h_vec / h;
        let y_hat = z_hat.cross(&x_hat);
        // Rows are the Hill axes in ECI components, so R v_eci gives Hill components.
        let rotation_eci_to_hill =
            Matrix3::from_rows(&[x_hat.transpose(), y_hat.transpose(), z_hat.transpose()]);
        let mut angular_velocity_eci_rad_s = (h / (r * r)) * z_hat;
        if let Some(a) = accel {
            angular_velocity_eci_rad_s += (r / h) * a.dot(&z_hat) * x_hat;
        }
        LvlhFrame {
            origin: *reference,
            rotation_eci_to_hill,
            angular_velocity_eci_rad_s,
        }
    }

    /// Rotation matrix taking ECI vector components to Hill components (its rows are the Hill axes
    /// expressed in ECI).
    pub fn rotation_eci_to_hill(&self) -> Matrix3<f64> {
        self.rotation_eci_to_hill
    }

    /// Angular velocity of the Hill frame relative to ECI, in ECI components \[rad/s\].
    pub fn angular_velocity_eci_rad_s(&self) -> Vector3<f64> {
        self.angular_velocity_eci_rad_s
    }

    /// The reference (origin) state, ECI.
    pub fn origin(&self) -> &CartesianState {
        &self.origin
    }

    /// Relative state of `satellite` (ECI) in this frame: position `rho = R (r_s - r_o)` \[m\] and the
    /// velocity seen in the rotating frame `rho_dot = R ((v_s - v_o) - omega x (r_s - r_o))` \[m/s\].
    #[inline]
    pub fn to_hill(&self, satellite: &CartesianState) -> RelativeStateHill {
        let dr = satellite.position_m - self.origin.position_m;
        let dv = satellite.velocity_mps - self.origin.velocity_mps;
        let transport = self.angular_velocity_eci_rad_s.cross(&dr);
        RelativeStateHill {
            position_m: self.rotation_eci_to_hill * dr,
            velocity_mps: self.rotation_eci_to_hill * (dv - transport),
        }
    }

    /// ECI state of a satellite at the relative state `relative` in this frame; the inverse of
    /// [`LvlhFrame::to_hill`].
    pub fn from_hill(&self, relative: &RelativeStateHill) -> CartesianState {
        let dr = self.rotation_eci_to_hill.transpose() * relative.position_m;
        let dv = self.rotation_eci_to_hill.transpose() * relative.velocity_mps
            + self.angular_velocity_eci_rad_s.cross(&dr);
        CartesianState::new(self.origin.position_m + dr, self.origin.velocity_mps + dv)
    }

    /// Components in Hill axes of the ECI vector `v_eci` (pure rotation, no transport term: for
    /// accelerations, directions, forces). Units are those of the input.
    pub fn vector_eci_to_hill(&self, v_eci: &Vector3<f64>) -> Vector3<f64> {
        self.rotation_eci_to_hill * v_eci
    }

    /// ECI components of the Hill-axes vector `v_hill` (pure rotation). Units are those of the input.
    pub fn vector_hill_to_eci(&self, v_hill: &Vector3<f64>) -> Vector3<f64> {
        self.rotation_eci_to_hill.transpose() * v_hill
    }
}

/// Relative state in the Hill/RSW frame (x radial out, y along-track, z orbit normal).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct RelativeStateHill {
    /// Relative position, Hill axes \[m\].
    pub position_m: Vector3<f64>,
    /// Relative velocity as seen in the rotating Hill frame, Hill axes \[m/s\].
    pub velocity_mps: Vector3<f64>,
}

impl RelativeStateHill {
    /// The state as the 6-vector `[x, y, z, vx, vy, vz]` \[m, m/s\], Hill axes: the layout of the
    /// `relative` models.
    pub fn to_vector6(&self) -> Vector6<f64> {
        let (p, v) = (&self.position_m, &self.velocity_mps);
        Vector6::new(p.x, p.y, p.z, v.x, v.y, v.z)
    }

    /// The state from the 6-vector `[x, y, z, vx, vy, vz]` \[m, m/s\], Hill axes.
    pub fn from_vector6(state_hill: &Vector6<f64>) -> Self {
        Self {
            position_m: state_hill.fixed_rows::<3>(0).into_owned(),
            velocity_mps: state_hill.fixed_rows::<3>(3).into_owned(),
        }
    }
}

/// Relative state in Gao's `o-xyz` frame (x along-track, y minus orbit normal, z toward the Earth's
/// centre).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct RelativeStateGao {
    /// Relative position, Gao axes \[m\].
    pub position_m: Vector3<f64>,
    /// Relative velocity as seen in the rotating frame, Gao axes \[m/s\].
    pub velocity_mps: Vector3<f64>,
}

/// Gao `o-xyz` components of a vector given in Hill components: `q_gao = C q_hill` with
/// `C = [[0,1,0],[0,0,-1],[-1,0,0]]` (x_gao = y_hill, y_gao = -z_hill, z_gao = -x_hill). Units are those
/// of the input.
pub fn hill_to_gao(v_hill: &Vector3<f64>) -> Vector3<f64> {
    Vector3::new(v_hill.y, -v_hill.z, -v_hill.x)
}

/// Hill components of a vector given in Gao `o-xyz` components: `q_hill = C^T q_gao`
/// (x_hill = -z_gao, y_hill = x_gao, z_hill = -y_gao). Units are those of the input.
pub fn gao_to_hill(v_gao: &Vector3<f64>) -> Vector3<f64> {
    Vector3::new(-v_gao.z, v_gao.x, -v_gao.y)
}

impl From<RelativeStateHill> for RelativeStateGao {
    fn from(hill: RelativeStateHill) -> Self {
        RelativeStateGao {
            position_m: hill_to_gao(&hill.position_m),
            velocity_mps: hill_to_gao(&hill.velocity_mps),
        }
    }
}

impl From<RelativeStateGao> for RelativeStateHill {
    fn from(gao: RelativeStateGao) -> Self {
        RelativeStateHill {
            position_m: gao_to_hill(&gao.position_m),
            velocity_mps: gao_to_hill(&gao.velocity_mps),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regress_vector6_layout_and_round_trip() {
        let s = RelativeStateHill {
            position_m: Vector3::new(1.0, 2.0, 3.0),
            velocity_mps: Vector3::new(4.0, 5.0, 6.0),
        };
        let v = s.to_vector6();
        assert_eq!(v, Vector6::new(1.0, 2.0, 3.0, 4.0, 5.0, 6.0));
        assert_eq!(RelativeStateHill::from_vector6(&v), s);
    }

    fn inclined_reference() -> CartesianState {
        CartesianState::new(
            Vector3::new(5.0e6, 4.0e6, 2.0e6),
            Vector3::new(-3.5e3, 3.0e3, 5.0e3),
        )
    }

    #[test]
    fn zero_normal_acceleration_gives_the_keplerian_frame() {
        let reference = inclined_reference();
        let plain = LvlhFrame::from_reference(&reference);
        let zero = LvlhFrame::from_reference_with_acceleration(&reference, &Vector3::zeros());
        assert_eq!(zero.rotation_eci_to_hill(), plain.rotation_eci_to_hill());
        assert_eq!(
            zero.angular_velocity_eci_rad_s(),
            plain.angular_velocity_eci_rad_s()
        );
        assert_eq!(zero.origin(), plain.origin());

        // Any acceleration in the orbit plane (radial + along-track) leaves the frame rate unchanged.
        let h_hat = reference.specific_angular_momentum_m2_s().normalize();
        let in_plane = Vector3::new(-7.0, 3.0, 1.0);
        let in_plane = in_plane - in_plane.dot(&h_hat) * h_hat;
        let with = LvlhFrame::from_reference_with_acceleration(&reference, &in_plane);
        assert_eq!(with.rotation_eci_to_hill(), plain.rotation_eci_to_hill());
        // The projection of in_plane on h_hat is zero only to rounding, a few ulp of |a| = 7.7 m/s^2
        // (~7e-15 m/s^2), which the factor r/h = 1.3e-4 s/m turns into ~1e-18 rad/s.
        let difference =
            (with.angular_velocity_eci_rad_s() - plain.angular_velocity_eci_rad_s()).norm();
        assert!(difference < 1e-18, "{difference}");
    }

    #[test]
    fn normal_acceleration_adds_a_radial_rate() {
        let reference = inclined_reference();
        let r = reference.position_m.norm();
        let h_vec = reference.specific_angular_momentum_m2_s();
        let h_hat = h_vec.normalize();
        let accel = 1e-2 * h_hat;
        let frame = LvlhFrame::from_reference_with_acceleration(&reference, &accel);
        let omega_hill = frame.vector_eci_to_hill(&frame.angular_velocity_eci_rad_s());
        let expected = Vector3::new(r / h_vec.norm() * 1e-2, 0.0, h_vec.norm() / (r * r));
        // Components are ~1e-3 rad/s; rounding of one rotation is a few ulp of that (~1e-18).
        assert!(
            (omega_hill - expected).norm() < 1e-18,
            "{omega_hill} vs {expected}"
        );
    }
}
