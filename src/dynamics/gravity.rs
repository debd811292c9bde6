//! The Earth's gravity in a force set ([`Gravity`]): point mass or point mass + J2 exactly as
//! [`crate::orbit::GravityModel`] computes them (the engine's bits since its first release), or the zonal
//! harmonics J2..Jn ([`super::ZonalGravity`]).

use nalgebra::Vector3;

use super::zonal::ZonalGravity;
use super::{ForceModel, Instant, PhysicalProperties};
use crate::orbit::{EarthModel, GravityModel};

/// The gravity field of a force set.
#[derive(Clone, Debug, PartialEq)]
pub enum Gravity {
    /// Point mass or point mass + J2, with the Earth constants they use.
    Field(GravityModel, EarthModel),
    /// Point mass + zonal harmonics J2..Jn.
    Zonal(ZonalGravity),
}

impl Gravity {
    /// The acceleration \[m/s^2\], ECI, at `position_eci_m` \[m\] (ECI, z on the Earth's polar axis).
    #[inline]
    pub fn acceleration_m_s2(&self, position_eci_m: &Vector3<f64>) -> Vector3<f64> {
        match self {
            Gravity::Field(model, earth) => model.acceleration_m_s2(earth, position_eci_m),
            Gravity::Zonal(zonal) => zonal.acceleration_m_s2(position_eci_m),
        }
    }
}

impl ForceModel for Gravity {
    fn name(&self) -> String {
        match self {
            Gravity::Field(GravityModel::TwoBody, _) => "gravity (point mass)".to_owned(),
            Gravity::Field(GravityModel::J2, _) => "gravity (point mass + J2)".to_owned(),
            Gravity::Zonal(z) => format!("gravity (zonal J2..J{})", z.degree()),
        }
    }

    fn acceleration_eci_m_s2(
        &self,
        _at: &Instant,
        position_eci_m: &Vector3<f64>,
        _velocity_eci_mps: &Vector3<f64>,
        _properties: &PhysicalProperties,
    ) -> Vector3<f64> {
        self.acceleration_m_s2(position_eci_m)
    }
}
