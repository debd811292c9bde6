//! Truth dynamics of the swarm: which equations propagate every satellite, and in which frame the
//! satellites' states are kept.
//!
//! * [`DynamicsModel::Inertial`]: each satellite in ECI under point-mass (+ J2) gravity plus its control
//!   acceleration rotated from LVLH (the default truth);
//! * [`DynamicsModel::Hcw`] and [`DynamicsModel::J2Linear`]: each satellite's Hill LVLH state relative to
//!   the virtual reference orbit, under the Hill–Clohessy–Wiltshire or the Schweighart–Sedwick
//!   J2-linearised equations (some papers simulate on these);
//! * [`DynamicsModel::Kinematic`]: each satellite's Hill position follows the law's commanded velocity
//!   exactly (a velocity-field law's kinematic layer, as in the threat paper's §3 building blocks); the
//!   actuator model does not apply and the delta-v ledger stays zero.
//!
//! The reference orbit is always propagated in ECI, with the same gravity as the satellites for the
//! inertial model, two-body for HCW (its circular-orbit assumption) and point mass + J2 for the
//! J2-linearised and kinematic models, and no control.

use nalgebra::Vector3;

use crate::orbit::{EarthModel, GravityModel};
use crate::relative::{Hcw, SchweighartSedwick};

/// The equations that propagate each satellite.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DynamicsModel {
    /// ECI states under the given gravity plus control.
    Inertial(GravityModel),
    /// Hill states relative to the reference, Hill–Clohessy–Wiltshire equations.
    Hcw(Hcw),
    /// Hill states relative to the reference, Schweighart–Sedwick J2-linearised equations.
    J2Linear(SchweighartSedwick),
    /// Hill positions relative to the reference moved by the commanded velocity (no forces).
    Kinematic,
}

impl DynamicsModel {
    /// Whether satellite states are kept in ECI (else in the Hill frame of the reference orbit).
    pub fn is_inertial(&self) -> bool {
        matches!(self, DynamicsModel::Inertial(_))
    }

    /// The model's name in scenario files.
    pub fn name(&self) -> &'static str {
        match self {
            DynamicsModel::Inertial(GravityModel::J2) => "j2",
            DynamicsModel::Inertial(GravityModel::TwoBody) => "two-body",
            DynamicsModel::Hcw(_) => "hcw",
            DynamicsModel::J2Linear(_) => "j2-linear",
            DynamicsModel::Kinematic => "kinematic",
        }
    }

    /// Gravity used to propagate the reference orbit.
    pub fn reference_gravity(&self) -> GravityModel {
        match self {
            DynamicsModel::Inertial(g) => *g,
            DynamicsModel::Hcw(_) => GravityModel::TwoBody,
            DynamicsModel::J2Linear(_) | DynamicsModel::Kinematic => GravityModel::J2,
        }
    }

    /// Time derivative of one satellite's state (position \[m\], velocity \[m/s\]) in the model's frame, under
    /// an applied control acceleration expressed in that same frame (ECI for the inertial model, Hill for
    /// the linear ones) \[m/s^2\]. Returns (velocity \[m/s\], acceleration \[m/s^2\]). For the kinematic
    /// model `control` is the commanded Hill velocity \[m/s\]: the position moves with it and the
    /// velocity state does not change (the engine sets it to the command).
    #[inline]
    pub fn satellite_derivative(
        &self,
        earth: &EarthModel,
        position_m: &Vector3<f64>,
        velocity_mps: &Vector3<f64>,
        control_m_s2: &Vector3<f64>,
    ) -> (Vector3<f64>, Vector3<f64>) {
        match self {
            DynamicsModel::Inertial(g) => (
                *velocity_mps,
                g.acceleration_m_s2(earth, position_m) + control_m_s2,
            ),
            DynamicsModel::Hcw(m) => (
                *velocity_mps,
                m.natural_acceleration_m_s2(position_m, velocity_mps) + control_m_s2,
            ),
            DynamicsModel::J2Linear(m) => (
                *velocity_mps,
                m.natural_acceleration_m_s2(position_m, velocity_mps) + control_m_s2,
            ),
            DynamicsModel::Kinematic => (*control_m_s2, Vector3::zeros()),
        }
    }
}
