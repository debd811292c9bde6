//! The Earth's shadow: the fraction of the solar disc a satellite sees ([`lit_fraction`]), 1 in full
//! sunlight and 0 in the umbra, for the three models of [`ShadowName`] (none, cylindrical, conical),
//! and the Sun's radius the conical model uses ([`SUN_RADIUS_M`]).
//!
//! The Earth is a sphere of the caller's radius (the equatorial radius in a force set). The oblate
//! Earth's shadow is up to 21 km narrower over the poles, which at 400 km (where the distance from
//! the shadow axis changes by ~2.6 km/s at the boundary) moves a boundary that crosses near a pole
//! by up to ~8 s. Atmospheric refraction and absorption are neglected.

use nalgebra::Vector3;

use super::config::ShadowName;

/// The Sun's radius \[m\]: 696 000 km, the value of Montenbruck & Gill, *Satellite Orbits* (their
/// constant `R_Sun`; Allen's *Astrophysical Quantities*). The IAU 2015 Resolution B3 nominal solar
/// radius is 695 700 km: 0.04 % smaller, which moves a penumbra boundary by 0.0001° (2 ms of shadow
/// time at 400 km).
pub const SUN_RADIUS_M: f64 = 696_000.0e3;

/// The fraction \[0, 1\] of the solar disc visible from a satellite at `position_eci_m` \[m\] (ECI),
/// the Sun at `sun_eci_m` \[m\] (ECI, geocentric), the Earth a sphere of `earth_radius_m` \[m\]:
///
/// * [`ShadowName::None`]: always 1;
/// * [`ShadowName::Cylindrical`]: 0 behind the Earth (`r · ŝ < 0`) inside the cylinder of radius
///   `earth_radius_m` about the anti-Sun axis (`|r − (r · ŝ) ŝ| < R`), else 1;
/// * [`ShadowName::Conical`]: from the apparent radii of the Sun `a = asin(R_☉ / |s − r|)` and of
///   the Earth `b = asin(R / |r|)` and their apparent separation `c = ∠(−r, s − r)`, as seen from
///   the satellite (Montenbruck & Gill, *Satellite Orbits*, §3.4.2, eqs. 3.85–3.87): 1 when
///   `c ≥ a + b` (lit), 0 when `c ≤ b − a` (umbra), `1 − b²/a²` when `c ≤ a − b` (annular: only
///   beyond the umbra's tip, ~1.4 · 10⁶ km), else one minus the area of overlap of the two discs
///   `A = a² acos(x/a) + b² acos((c − x)/b) − c y` with `x = (c² + a² − b²)/(2c)`,
///   `y = √(a² − x²)`, over the Sun's `π a²` (penumbra). The discs are taken as plane circles of
///   those angular radii, as in Montenbruck & Gill.
///
/// Inside the Earth's sphere (not a physical case) the conical model takes `b` as 90°: dark when
/// the Sun's centre is more than `a` below the local horizon.
pub fn lit_fraction(
    shadow: ShadowName,
    position_eci_m: &Vector3<f64>,
    sun_eci_m: &Vector3<f64>,
    earth_radius_m: f64,
) -> f64 {
    match shadow {
        ShadowName::None => 1.0,
        ShadowName::Cylindrical => cylindrical(position_eci_m, sun_eci_m, earth_radius_m),
        ShadowName::Conical => conical(position_eci_m, sun_eci_m, earth_radius_m),
    }
}

/// The cylindrical model: 0 or 1.
fn cylindrical(
    position_eci_m: &Vector3<f64>,
    sun_eci_m: &Vector3<f64>,
    earth_radius_m: f64,
) -> f64 {
    let sun_hat = sun_eci_m.normalize();
    let along = position_eci_m.dot(&sun_hat);
    if along >= 0.0 {
        return 1.0;
    }
    let across = (position_eci_m - along * sun_hat).norm();
    if across < earth_radius_m {
        0.0
    } else {
        1.0
    }
}

/// The conical model: the visible fraction of the solar disc, Montenbruck & Gill eqs. 3.85–3.87.
fn conical(position_eci_m: &Vector3<f64>, sun_eci_m: &Vector3<f64>, earth_radius_m: f64) -> f64 {
    let to_sun = sun_eci_m - position_eci_m;
    let to_sun_m = to_sun.norm();
    let radius_m = position_eci_m.norm();
    // Apparent radii of the Sun (a) and the Earth (b) [rad].
    let a = (SUN_RADIUS_M / to_sun_m).min(1.0).asin();
    let b = (earth_radius_m / radius_m).min(1.0).asin();
    // Apparent separation of their centres [rad]: the angle at the satellite between the directions
    // to the Earth's centre (−r) and to the Sun (s − r), from atan2 (accurate at small angles too).
    let earth_dir = -position_eci_m;
    let c = earth_dir
        .cross(&to_sun)
        .norm()
        .atan2(earth_dir.dot(&to_sun));
    if c >= a + b {
        return 1.0;
    }
    if c <= b - a {
        return 0.0;
    }
    if c <= a - b {
        // The Earth's disc inside the Sun's (annular eclipse).
        return 1.0 - (b * b) / (a * a);
    }
    // Partial overlap (penumbra): the lens area of two circles of radii a and b at distance c.
    let x = (c * c + a * a - b * b) / (2.0 * c);
    let y = (a * a - x * x).max(0.0).sqrt();
    let area = a * a * (x / a).clamp(-1.0, 1.0).acos()
        + b * b * ((c - x) / b).clamp(-1.0, 1.0).acos()
        - c * y;
    (1.0 - area / (std::f64::consts::PI * a * a)).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    const R_EARTH_M: f64 = 6_378_137.0;
    const AU_M: f64 = 149_597_870_700.0;

    fn sun() -> Vector3<f64> {
        Vector3::new(AU_M, 0.0, 0.0)
    }

    #[test]
    fn none_is_always_lit() {
        let behind = Vector3::new(-7.0e6, 0.0, 0.0);
        assert_eq!(
            lit_fraction(ShadowName::None, &behind, &sun(), R_EARTH_M),
            1.0
        );
    }

    #[test]
    fn sunward_side_is_lit_and_anti_sun_axis_is_dark() {
        let sunward = Vector3::new(7.0e6, 0.0, 0.0);
        let behind = Vector3::new(-7.0e6, 1.0e6, -2.0e6);
        for shadow in [ShadowName::Cylindrical, ShadowName::Conical] {
            assert_eq!(lit_fraction(shadow, &sunward, &sun(), R_EARTH_M), 1.0);
            assert_eq!(lit_fraction(shadow, &behind, &sun(), R_EARTH_M), 0.0);
        }
        // Beside the Earth, off the cylinder: lit in both models.
        let beside = Vector3::new(-1.0e6, 0.0, 7.0e6);
        assert_eq!(
            lit_fraction(ShadowName::Cylindrical, &beside, &sun(), R_EARTH_M),
            1.0
        );
        assert_eq!(
            lit_fraction(ShadowName::Conical, &beside, &sun(), R_EARTH_M),
            1.0
        );
    }

    #[test]
    fn lens_area_is_exact_for_a_half_covered_equal_disc() {
        // Unit check of the overlap formula: two discs of equal radius a whose centres are a apart
        // overlap by a² (2π/3 − √3/2) (the classical lens; Weisstein, "Circle-Circle Intersection").
        // Reproduce equal apparent radii: Earth seen from 1.5e9 m has b = asin(R/r); put the Sun
        // where a = b and the separation c = a.
        let r = 1.5e9;
        let b = (R_EARTH_M / r).asin();
        let sun_distance = SUN_RADIUS_M / b.sin();
        // Satellite on the x axis at -r; the Sun seen at angle c = b from the Earth's centre.
        let position = Vector3::new(-r, 0.0, 0.0);
        let direction = Vector3::new(b.cos(), b.sin(), 0.0);
        let sun = position + sun_distance * direction;
        let lit = lit_fraction(ShadowName::Conical, &position, &sun, R_EARTH_M);
        let expected =
            1.0 - (2.0 * std::f64::consts::PI / 3.0 - 3.0_f64.sqrt() / 2.0) / std::f64::consts::PI;
        assert!((lit - expected).abs() < 1e-9, "{lit} vs {expected}");
    }
}
