//! Solar radiation pressure on a cannonball satellite ([`SolarRadiationPressure`]): the pressure of
//! sunlight at 1 AU ([`SOLAR_PRESSURE_N_PER_M2`]) scaled by the inverse square of the distance to
//! the Sun, the satellite's `C_r A / m` and the lit fraction of the Earth's shadow model
//! ([`super::lit_fraction`]).

use nalgebra::Vector3;

use super::config::ShadowName;
use super::ephemeris::ASTRONOMICAL_UNIT_M;
use super::shadow::lit_fraction;
use super::{Bodies, ForceModel, Instant, PhysicalProperties};

/// The solar radiation pressure at 1 AU \[N/m^2\]: `P_☉ = Φ / c = 4.56 · 10⁻⁶ N/m²`, for the solar
/// flux `Φ ≈ 1367 W/m²` and the speed of light (Montenbruck & Gill, *Satellite Orbits*, eq. 3.72).
pub const SOLAR_PRESSURE_N_PER_M2: f64 = 4.56e-6;

/// The cannonball model of solar radiation pressure (Montenbruck & Gill, *Satellite Orbits*,
/// eq. 3.75 with the surface normal along the Sun line):
/// `a = −ν P_☉ C_r (A/m) (AU/d)² û`, where `û` is the unit vector from the satellite to the Sun, `d`
/// their distance, `C_r A / m` the satellite's [`PhysicalProperties::srp_area_per_mass_m2_per_kg`]
/// and `ν` the lit fraction of the shadow model ([`super::lit_fraction`]) for an Earth sphere of
/// the radius given at construction. The Sun is the geocentric analytic Sun of the instant
/// ([`Instant::sun_eci_m`]); the radiation pressure of the Earth (albedo, infrared) is not modelled.
#[derive(Clone, Debug, PartialEq)]
pub struct SolarRadiationPressure {
    shadow: ShadowName,
    earth_radius_m: f64,
}

impl SolarRadiationPressure {
    /// SRP with the shadow model `shadow` and an Earth sphere of `earth_radius_m` \[m\] casting it.
    pub fn new(shadow: ShadowName, earth_radius_m: f64) -> Self {
        Self {
            shadow,
            earth_radius_m,
        }
    }

    /// The shadow model.
    pub fn shadow(&self) -> ShadowName {
        self.shadow
    }

    /// The radius \[m\] of the Earth sphere that casts the shadow.
    pub fn earth_radius_m(&self) -> f64 {
        self.earth_radius_m
    }
}

impl ForceModel for SolarRadiationPressure {
    fn name(&self) -> String {
        let shadow = match self.shadow {
            ShadowName::None => "no shadow",
            ShadowName::Cylindrical => "cylindrical shadow",
            ShadowName::Conical => "conical shadow",
        };
        format!("solar radiation pressure ({shadow})")
    }

    fn acceleration_eci_m_s2(
        &self,
        at: &Instant,
        position_eci_m: &Vector3<f64>,
        _velocity_eci_mps: &Vector3<f64>,
        properties: &PhysicalProperties,
    ) -> Vector3<f64> {
        let area_per_mass = properties.srp_area_per_mass_m2_per_kg();
        if area_per_mass == 0.0 {
            return Vector3::zeros();
        }
        let sun_eci_m = at.sun_eci_m();
        let lit = lit_fraction(self.shadow, position_eci_m, &sun_eci_m, self.earth_radius_m);
        if lit == 0.0 {
            return Vector3::zeros();
        }
        // From the satellite to the Sun: u = (s − r) / d; a = −ν P C_r (A/m) (AU/d)² u, computed as
        // −ν P C_r (A/m) AU² (s − r) / d³.
        let to_sun = sun_eci_m - position_eci_m;
        let d2 = to_sun.norm_squared();
        let d = d2.sqrt();
        let scale = -lit
            * SOLAR_PRESSURE_N_PER_M2
            * area_per_mass
            * ASTRONOMICAL_UNIT_M
            * ASTRONOMICAL_UNIT_M
            / (d2 * d);
        to_sun * scale
    }

    fn bodies(&self) -> Bodies {
        Bodies {
            sun: true,
            moon: false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn properties(mass_kg: f64, area_m2: f64, c_r: f64) -> PhysicalProperties {
        PhysicalProperties {
            srp_area_m2: area_m2,
            reflectivity_coefficient: c_r,
            ..PhysicalProperties::point_mass(mass_kg)
        }
    }

    #[test]
    fn names_say_the_shadow() {
        let srp = SolarRadiationPressure::new(ShadowName::Conical, 6_378_137.0);
        assert_eq!(srp.name(), "solar radiation pressure (conical shadow)");
        assert_eq!(
            SolarRadiationPressure::new(ShadowName::None, 1.0).name(),
            "solar radiation pressure (no shadow)"
        );
        assert_eq!(
            srp.bodies(),
            Bodies {
                sun: true,
                moon: false
            }
        );
    }

    #[test]
    fn points_away_from_the_sun_with_the_cannonball_magnitude() {
        let srp = SolarRadiationPressure::new(ShadowName::Conical, 6_378_137.0);
        let at = Instant::new(
            1.0e8,
            Bodies {
                sun: true,
                moon: false,
            },
        );
        let sun = at.sun_eci_m();
        // On the sunward side at GEO distance.
        let r = sun.normalize() * 42_164.0e3;
        let p = properties(100.0, 2.0, 1.5);
        let a = srp.acceleration_eci_m_s2(&at, &r, &Vector3::zeros(), &p);
        let d = (sun - r).norm();
        let expected = 4.56e-6 * 1.5 * 2.0 / 100.0 * (ASTRONOMICAL_UNIT_M / d).powi(2);
        assert!((a.norm() / expected - 1.0).abs() < 1e-14);
        assert!(a.normalize().dot(&(sun - r).normalize()) < -1.0 + 1e-15);
        // No area: no force.
        let none =
            srp.acceleration_eci_m_s2(&at, &r, &Vector3::zeros(), &properties(100.0, 0.0, 1.5));
        assert_eq!(none, Vector3::zeros());
    }
}
