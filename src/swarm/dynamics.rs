//! Truth dynamics of the swarm: which equations propagate every satellite, and in which frame the
//! satellites' states are kept.
//!
//! * [`DynamicsModel::Inertial`]: each satellite in ECI under a [`ForceSet`] (by default point-mass + J2
//!   gravity; zonal harmonics, drag, SRP and third bodies when the scenario asks) plus its control
//!   acceleration rotated from LVLH (the default truth);
//! * [`DynamicsModel::Hcw`] and [`DynamicsModel::J2Linear`]: each satellite's Hill LVLH state relative to
//!   the virtual reference orbit, under the Hill–Clohessy–Wiltshire or the Schweighart–Sedwick
//!   J2-linearised equations (some papers simulate on these);
//! * [`DynamicsModel::Kinematic`]: each satellite's Hill position follows the law's commanded velocity
//!   exactly (a velocity-field law's kinematic layer, as in the threat paper's §3 building blocks); the
//!   actuator model does not apply and the delta-v ledger stays zero.
//!
//! The reference orbit is always propagated in ECI, with the same force set as the satellites for the
//! inertial model (a virtual reference with its own physical properties), two-body for HCW (its
//! circular-orbit assumption) and point mass + J2 for the J2-linearised and kinematic models, and no
//! control.

use std::sync::Arc;

use nalgebra::Vector3;

use crate::dynamics::{ForceSet, PhysicalProperties};
use crate::orbit::{EarthModel, GravityModel};
use crate::relative::{Hcw, SchweighartSedwick};

/// The equations that propagate each satellite.
#[derive(Clone, Debug)]
pub enum DynamicsModel {
    /// ECI states under the force set plus control.
    Inertial(Arc<ForceSet>),
    /// Hill states relative to the reference, Hill–Clohessy–Wiltshire equations.
    Hcw(Hcw),
    /// Hill states relative to the reference, Schweighart–Sedwick J2-linearised equations.
    J2Linear(SchweighartSedwick),
    /// Hill positions relative to the reference moved by the commanded velocity (no forces).
    Kinematic,
}

impl PartialEq for DynamicsModel {
    /// Inertial models are equal when their force sets name the same models with the same gravity
    /// field and epoch (force sets hold trait objects, so this compares what they say of themselves).
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            (DynamicsModel::Inertial(a), DynamicsModel::Inertial(b)) => {
                Arc::ptr_eq(a, b)
                    || (a.summary() == b.summary()
                        && a.gravity_field() == b.gravity_field()
                        && a.instant(0.0) == b.instant(0.0))
            }
            (DynamicsModel::Hcw(a), DynamicsModel::Hcw(b)) => a == b,
            (DynamicsModel::J2Linear(a), DynamicsModel::J2Linear(b)) => a == b,
            (DynamicsModel::Kinematic, DynamicsModel::Kinematic) => true,
            _ => false,
        }
    }
}

impl DynamicsModel {
    /// Inertial truth under `gravity` alone with the constants `earth` (`[dynamics] model = "j2"` or
    /// `"two-body"`): the force set no epoch or satellite property enters.
    pub fn inertial(gravity: GravityModel, earth: EarthModel) -> Self {
        DynamicsModel::Inertial(Arc::new(ForceSet::gravity(gravity, earth)))
    }

    /// Whether satellite states are kept in ECI (else in the Hill frame of the reference orbit).
    pub fn is_inertial(&self) -> bool {
        matches!(self, DynamicsModel::Inertial(_))
    }

    /// The model's name in scenario files.
    pub fn name(&self) -> &'static str {
        match self {
            DynamicsModel::Inertial(forces) => match forces.gravity_field() {
                crate::dynamics::Gravity::Field(GravityModel::TwoBody, _)
                    if forces.is_gravity_only() =>
                {
                    "two-body"
                }
                crate::dynamics::Gravity::Field(GravityModel::J2, _)
                    if forces.is_gravity_only() =>
                {
                    "j2"
                }
                _ => "forces",
            },
            DynamicsModel::Hcw(_) => "hcw",
            DynamicsModel::J2Linear(_) => "j2-linear",
            DynamicsModel::Kinematic => "kinematic",
        }
    }

    /// The force set of inertial truth (`None` for the relative models).
    pub fn forces(&self) -> Option<&ForceSet> {
        match self {
            DynamicsModel::Inertial(forces) => Some(forces),
            _ => None,
        }
    }

    /// The ECI acceleration \[m/s^2\] of the reference orbit (or a member origin) at `position_m`
    /// \[m\] with `velocity_mps` \[m/s\] (ECI), `t_s` after the epoch, with `properties`: the force
    /// set for inertial truth, two-body for HCW, point mass + J2 (constants `earth`) otherwise.
    #[inline]
    pub fn reference_acceleration_m_s2(
        &self,
        earth: &EarthModel,
        t_s: f64,
        position_m: &Vector3<f64>,
        velocity_mps: &Vector3<f64>,
        properties: &PhysicalProperties,
    ) -> Vector3<f64> {
        match self {
            DynamicsModel::Inertial(forces) => forces.acceleration_eci_m_s2(
                &forces.instant(t_s),
                position_m,
                velocity_mps,
                properties,
            ),
            DynamicsModel::Hcw(_) => GravityModel::TwoBody.acceleration_m_s2(earth, position_m),
            DynamicsModel::J2Linear(_) | DynamicsModel::Kinematic => {
                GravityModel::J2.acceleration_m_s2(earth, position_m)
            }
        }
    }

    /// Whether the reference orbit feels J2 (for the J2-linearised model given to laws).
    pub fn reference_has_j2(&self) -> bool {
        match self {
            DynamicsModel::Inertial(forces) => !matches!(
                forces.gravity_field(),
                crate::dynamics::Gravity::Field(GravityModel::TwoBody, _)
            ),
            DynamicsModel::Hcw(_) => false,
            DynamicsModel::J2Linear(_) | DynamicsModel::Kinematic => true,
        }
    }

    /// Time derivative of one satellite's state (position \[m\], velocity \[m/s\]) in the model's frame, under
    /// an applied control acceleration expressed in that same frame (ECI for the inertial model, Hill for
    /// the linear ones) \[m/s^2\]. Returns (velocity \[m/s\], acceleration \[m/s^2\]). For the kinematic
    /// model `control` is the commanded Hill velocity \[m/s\]: the position moves with it and the
    /// velocity state does not change (the engine sets it to the command). `t_s` (seconds after the
    /// epoch) and `properties` reach the inertial force set only.
    #[inline]
    pub fn satellite_derivative(
        &self,
        t_s: f64,
        position_m: &Vector3<f64>,
        velocity_mps: &Vector3<f64>,
        properties: &PhysicalProperties,
        control_m_s2: &Vector3<f64>,
    ) -> (Vector3<f64>, Vector3<f64>) {
        match self {
            DynamicsModel::Inertial(forces) => (
                *velocity_mps,
                forces.acceleration_eci_m_s2(
                    &forces.instant(t_s),
                    position_m,
                    velocity_mps,
                    properties,
                ) + control_m_s2,
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
