//! The point-mass attraction of a third body, the Sun or the Moon ([`ThirdBody`]), on a satellite
//! in the geocentric frame: the direct attraction minus the attraction on the Earth (the indirect
//! term), computed without the cancellation of the direct difference (Battin's `f(q)`).

use nalgebra::Vector3;

use super::config::BodyName;
use super::ephemeris::{GM_MOON_M3_S2, GM_SUN_M3_S2};
use super::{Bodies, ForceModel, Instant, PhysicalProperties};

/// The perturbing acceleration of one third body's point mass on a satellite, in the geocentric
/// (ECI) frame, indirect term included (Montenbruck & Gill, *Satellite Orbits*, eq. 3.37):
///
/// `a = GM_b ( (r_b − r)/|r_b − r|³ − r_b/|r_b|³ )`,
///
/// `r` the satellite's and `r_b` the body's geocentric position ([`Instant::sun_eci_m`],
/// [`Instant::moon_eci_m`]), `GM_b` [`super::GM_SUN_M3_S2`] or [`super::GM_MOON_M3_S2`].
///
/// The two terms nearly cancel (for the Sun at low Earth orbit they are 5.9 · 10⁻³ m/s² each and
/// differ by 5 · 10⁻⁷ m/s²: four digits lost), so the difference is evaluated in Battin's form
/// (*An Introduction to the Mathematics and Methods of Astrodynamics*, rev. ed., AIAA 1999,
/// eqs. 8.60–8.62, p. 389): with `d = r_b − r` and `q = r · (r − 2 r_b) / |r_b|²` (so that
/// `|d|² = |r_b|² (1 + q)`),
///
/// `a = −GM_b / |d|³ ( r + f(q) r_b )`,  `f(q) = q (3 + 3q + q²) / (1 + (1 + q)^{3/2})`
/// `= (1 + q)^{3/2} − 1`,
///
/// which has no subtraction of nearly equal numbers; it is exactly zero at `r = 0`.
#[derive(Clone, Debug, PartialEq)]
pub struct ThirdBody {
    body: BodyName,
}

impl ThirdBody {
    /// The point mass of `body`.
    pub fn new(body: BodyName) -> Self {
        Self { body }
    }

    /// The body.
    pub fn body(&self) -> BodyName {
        self.body
    }

    /// The body's gravitational parameter \[m^3/s^2\].
    pub fn gm_m3_s2(&self) -> f64 {
        match self.body {
            BodyName::Sun => GM_SUN_M3_S2,
            BodyName::Moon => GM_MOON_M3_S2,
        }
    }

    /// The perturbing acceleration \[m/s^2\] of a point mass `gm_m3_s2` \[m^3/s^2\] at geocentric
    /// `body_m` \[m\] on a satellite at geocentric `position_m` \[m\] (any one inertial frame), in
    /// Battin's form (see the type's documentation).
    #[inline]
    pub fn point_mass_perturbation_m_s2(
        gm_m3_s2: f64,
        body_m: &Vector3<f64>,
        position_m: &Vector3<f64>,
    ) -> Vector3<f64> {
        let body2 = body_m.norm_squared();
        let q = position_m.dot(&(position_m - 2.0 * body_m)) / body2;
        let one_plus_q = 1.0 + q;
        let f = q * (3.0 + 3.0 * q + q * q) / (1.0 + one_plus_q * one_plus_q.sqrt());
        // |d|³ = (|r_b|² (1 + q))^{3/2}.
        let d2 = body2 * one_plus_q;
        let d3 = d2 * d2.sqrt();
        (position_m + f * body_m) * (-gm_m3_s2 / d3)
    }
}

impl ForceModel for ThirdBody {
    fn name(&self) -> String {
        match self.body {
            BodyName::Sun => "third body (sun)".to_owned(),
            BodyName::Moon => "third body (moon)".to_owned(),
        }
    }

    fn acceleration_eci_m_s2(
        &self,
        at: &Instant,
        position_eci_m: &Vector3<f64>,
        _velocity_eci_mps: &Vector3<f64>,
        _properties: &PhysicalProperties,
    ) -> Vector3<f64> {
        let body_m = match self.body {
            BodyName::Sun => at.sun_eci_m(),
            BodyName::Moon => at.moon_eci_m(),
        };
        Self::point_mass_perturbation_m_s2(self.gm_m3_s2(), &body_m, position_eci_m)
    }

    fn bodies(&self) -> Bodies {
        Bodies {
            sun: self.body == BodyName::Sun,
            moon: self.body == BodyName::Moon,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The direct difference, for comparison.
    fn naive(gm: f64, s: &Vector3<f64>, r: &Vector3<f64>) -> Vector3<f64> {
        let d = s - r;
        gm * (d / d.norm().powi(3) - s / s.norm().powi(3))
    }

    #[test]
    fn battin_form_equals_the_direct_difference() {
        // At the Moon's distance the direct difference loses under two digits, so the two forms
        // agree to ~1e-14 relative; for the Sun four digits are lost (agreement ~1e-12). A
        // difference formula error (a sign, a factor) would show at O(1).
        let moon = Vector3::new(3.0e8, -2.0e8, 1.1e8);
        let sun = Vector3::new(-1.2e11, 8.0e10, 3.5e10);
        for r in [
            Vector3::new(7.0e6, 0.0, 0.0),
            Vector3::new(-3.0e6, 5.0e6, 2.0e6),
            Vector3::new(0.0, 0.0, 4.2e7),
        ] {
            for (gm, s, tol) in [(GM_MOON_M3_S2, moon, 1e-12), (GM_SUN_M3_S2, sun, 1e-10)] {
                let battin = ThirdBody::point_mass_perturbation_m_s2(gm, &s, &r);
                let direct = naive(gm, &s, &r);
                assert!(
                    (battin - direct).norm() <= tol * battin.norm(),
                    "{battin} vs {direct}"
                );
            }
        }
    }

    #[test]
    fn bodies_and_names() {
        let sun = ThirdBody::new(BodyName::Sun);
        let moon = ThirdBody::new(BodyName::Moon);
        assert_eq!(
            sun.bodies(),
            Bodies {
                sun: true,
                moon: false
            }
        );
        assert_eq!(
            moon.bodies(),
            Bodies {
                sun: false,
                moon: true
            }
        );
        assert_eq!(sun.name(), "third body (sun)");
        assert_eq!(moon.name(), "third body (moon)");
        assert_eq!(sun.gm_m3_s2(), GM_SUN_M3_S2);
        assert_eq!(moon.body(), BodyName::Moon);
    }
}
