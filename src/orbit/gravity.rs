//! Gravitational acceleration models of the Earth in the inertial frame ([`GravityModel`]): point
//! mass and point mass plus the J2 zonal term.

use std::fmt;
use std::str::FromStr;

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use super::constants::EarthModel;
use super::elements::OrbitError;

/// Which terms of the Earth's gravity field act on a satellite.
///
/// Parsed from and serialised as kebab-case names (`"two-body"`, `"j2"`). Further zonal terms
/// (J3, J4, ...) and atmospheric drag are meant to be added as new variants; code matching on this
/// enum should expect that.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum GravityModel {
    /// Point mass (Keplerian): `a = -mu r / |r|^3`.
    TwoBody,
    /// Point mass plus the J2 zonal harmonic (Earth oblateness), the gradient of
    /// `U = (mu/r) (1 - J2 (R/r)^2 P2(z/r))`, `P2(s) = (3 s^2 - 1)/2`.
    J2,
}

/// Accepted names, in the order of [`GravityModel`]'s variants, for error messages.
const VALID_NAMES: &str = "two-body, j2";

impl GravityModel {
    /// Gravitational acceleration \[m/s^2\] in ECI at the ECI position `position_eci_m` \[m\], for the
    /// constants `earth`. The ECI z axis must be the Earth's polar (figure) axis.
    ///
    /// The J2 model is the gradient of the potential above written out, with `k = 3/2 J2 (R/r)^2`:
    /// `a_x = -mu x / r^3 (1 + k (1 - 5 z^2/r^2))`, `a_y` likewise,
    /// `a_z = -mu z / r^3 (1 + k (3 - 5 z^2/r^2))`.
    ///
    /// Does not allocate. The position must be non-zero (the result is not finite at the origin);
    /// this is not checked, as the function sits in the innermost loop.
    #[inline]
    pub fn acceleration_m_s2(
        &self,
        earth: &EarthModel,
        position_eci_m: &Vector3<f64>,
    ) -> Vector3<f64> {
        let r2 = position_eci_m.norm_squared();
        let r = r2.sqrt();
        let mu_over_r3 = earth.mu_m3_s2 / (r2 * r);
        match self {
            GravityModel::TwoBody => -mu_over_r3 * position_eci_m,
            GravityModel::J2 => {
                let k = 1.5 * earth.j2 * earth.equatorial_radius_m * earth.equatorial_radius_m / r2;
                let five_z2_over_r2 = 5.0 * position_eci_m.z * position_eci_m.z / r2;
                let horizontal = -mu_over_r3 * (1.0 + k * (1.0 - five_z2_over_r2));
                let vertical = -mu_over_r3 * (1.0 + k * (3.0 - five_z2_over_r2));
                Vector3::new(
                    horizontal * position_eci_m.x,
                    horizontal * position_eci_m.y,
                    vertical * position_eci_m.z,
                )
            }
        }
    }

    /// The kebab-case name of the model, as accepted by [`FromStr`] and written by serde.
    pub fn name(&self) -> &'static str {
        match self {
            GravityModel::TwoBody => "two-body",
            GravityModel::J2 => "j2",
        }
    }
}

impl fmt::Display for GravityModel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for GravityModel {
    type Err = OrbitError;

    /// Parses `"two-body"` or `"j2"` (exact, lower case).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "two-body" => Ok(GravityModel::TwoBody),
            "j2" => Ok(GravityModel::J2),
            _ => Err(OrbitError::UnknownGravityModel {
                name: s.to_owned(),
                valid: VALID_NAMES,
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_errors_list_valid_names() {
        for model in [GravityModel::TwoBody, GravityModel::J2] {
            assert_eq!(model.to_string().parse::<GravityModel>(), Ok(model));
        }
        assert_eq!(
            serde_json::to_string(&GravityModel::TwoBody).unwrap(),
            "\"two-body\""
        );
        let err = "J2".parse::<GravityModel>().unwrap_err().to_string();
        assert!(
            err.contains("\"J2\"") && err.contains("two-body, j2"),
            "{err}"
        );
    }
}
