//! Low-precision analytic positions of the Sun and the Moon ([`sun_position_eci_m`],
//! [`moon_position_eci_m`]) and the constants of the Sun and the Moon the force models use
//! ([`ASTRONOMICAL_UNIT_M`], [`GM_SUN_M3_S2`], [`GM_MOON_M3_S2`]).
//!
//! # The model
//!
//! Both positions are the closed-form series of Montenbruck & Gill, *Satellite Orbits* (Springer,
//! 2000), §3.3.2, eqs. (3.38)–(3.49), also in their companion code (`SunPos`, `MoonPos`) and in
//! Montenbruck & Pfleger, *Astronomy on the Personal Computer* (`MINI_SUN`, `MINI_MOON`):
//!
//! * **Sun**: an unperturbed Kepler orbit of the Earth, written as the Sun's geocentric ecliptic
//!   longitude `λ = Ω + ω + M + 6892″ sin M + 72″ sin 2M` with `Ω + ω = 282.9400°` and the mean
//!   anomaly `M = 357.5256° + 35999.049° T`, the distance
//!   `r = (149.619 − 2.499 cos M − 0.021 cos 2M) · 10⁶ km` and a zero ecliptic latitude.
//! * **Moon**: the mean longitude `L0` and the four Delaunay arguments `l` (the Moon's mean
//!   anomaly), `l′` (the Sun's), `F` (the Moon's mean argument of latitude) and `D` (the mean
//!   elongation of the Moon from the Sun), and the main periodic terms of the longitude (14
//!   terms), the latitude (8) and the distance (9).
//!
//! `T` is the time in Julian centuries of TT past J2000 (`T = t_TT / (36525 · 86400 s)`).
//!
//! # Frame
//!
//! The ecliptic coordinates are referred to the mean ecliptic and equinox of J2000 and rotated to
//! the equator by the J2000 obliquity `ε = 23.43929111°`, which gives EME2000 (the engine's ECI):
//!
//! * the Sun's longitude is taken **without** the precession term `+1.3972° T` that Montenbruck &
//!   Gill add to refer it to the mean equinox of date;
//! * the Moon's mean longitude keeps their term `−1.3972° T`, which converts the mean longitude of
//!   date, `218.31617° + 481267.88088° T`, to the J2000 equinox.
//!
//! The motion of the ecliptic since J2000 (below 1″ per decade in latitude) and the frame bias
//! between EME2000 and the ICRF (0.02″) are far below the model's own error and are neglected.
//!
//! # Accuracy
//!
//! * **Sun.** The series holds the longitude of perigee `Ω + ω` fixed, so its mean longitude
//!   `280.4656° + 35999.049° T` drifts from the true J2000-referred one, `280.46646° +
//!   35999.37294° T` (Meeus, *Astronomical Algorithms*, 2nd ed., eq. 25.2 less the general
//!   precession), by `0.00086° + 0.32394° |T|`: 1.2′ in 2006, 5.1′ in 2026. On top of that come the
//!   perturbations of the Earth's orbit by the Moon (the Earth's monthly wobble about the Earth–Moon
//!   barycentre, 6.5″) and the planets, which the VSOP87 series list as terms of 7″ and smaller
//!   (about 10″ rms, 60″ at worst). The distance is good to 3 · 10⁻⁵ typically and 1.2 · 10⁻⁴ at
//!   worst (the same perturbations in the radius vector, the largest 3.1 · 10⁻⁵ AU from the Moon).
//!   Measured: 70″ against the Astronomical Almanac for 2006 April 2, 91″ against Meeus's
//!   Example 26.a (1992 October 13).
//! * **Moon.** Montenbruck & Pfleger give the same lunar series (`MINI_MOON`) as "approx. 5′/1′" in
//!   right ascension and declination: the longitude terms it leaves out are 45″, 40″, 38″, 36″,
//!   31″ and smaller (Meeus, Table 47.A; ~1′ rms). The distance terms it leaves out are 130, 109,
//!   105, 80, 49 km and smaller: a few hundred km, about 0.1 % (0.2 % at worst). Measured against
//!   Meeus's Example 47.a (1992 April 12): 0.31′ in longitude, 0.09′ in latitude, 51 km.
//!
//! The measurements are `tests/dynamics_sun_moon.rs`.
//!
//! That is ample for the third-body and radiation-pressure forces on a near-Earth satellite, where a
//! direction error δ changes a lunisolar acceleration of ~10⁻⁶ m/s² by ~δ · 10⁻⁶ m/s² (3 · 10⁻¹⁰
//! m/s² for 1′), and shifts the time of a shadow boundary by δ / n (at 400 km, 1′ ≈ 0.26 s).

use nalgebra::Vector3;

/// The astronomical unit \[m\]: exactly 149 597 870 700 m by IAU 2012 Resolution B2.
pub const ASTRONOMICAL_UNIT_M: f64 = 149_597_870_700.0;

/// The Sun's gravitational parameter `GM` \[m^3/s^2\]: 1.327 124 400 18 · 10²⁰ m³/s², JPL DE405
/// (Standish 1998, JPL IOM 312.F-98-048; the TDB-compatible value Montenbruck & Gill and most
/// astrodynamics codes use). The IERS Conventions (2010), Table 1.1, give the TCB-compatible
/// 1.327 124 420 99 · 10²⁰ m³/s² (from DE421): 1.6 · 10⁻⁸ relative, far below the ephemeris error.
pub const GM_SUN_M3_S2: f64 = 1.327_124_400_18e20;

/// The Moon's gravitational parameter `GM` \[m^3/s^2\]: 4902.800066 km³/s², JPL DE430 (Folkner et
/// al. 2014, IPN Progress Report 42-196, Table 4; the value JPL Horizons quotes, 4902.80007). DE405
/// has 4902.801 km³/s² (2 · 10⁻⁷ relative): the digits past 4.9028 · 10¹² do not matter here.
pub const GM_MOON_M3_S2: f64 = 4.902_800_066e12;

/// Seconds per Julian century (36525 days of 86400 s).
const SECONDS_PER_JULIAN_CENTURY: f64 = 36_525.0 * 86_400.0;

/// The mean obliquity of the ecliptic at J2000, 23.43929111° = 84381.448″ (IAU 1976), in radians.
const OBLIQUITY_J2000_RAD: f64 = 23.439_291_11 * DEG;

/// One degree in radians.
const DEG: f64 = std::f64::consts::PI / 180.0;

/// One arcsecond in radians.
const ARCSEC: f64 = DEG / 3600.0;

/// `degrees` reduced to `[0°, 360°)` and converted to radians (keeps the arguments small so their
/// sines keep full precision decades from J2000).
#[inline]
fn angle_rad(degrees: f64) -> f64 {
    degrees.rem_euclid(360.0) * DEG
}

/// Ecliptic (mean ecliptic and equinox of J2000) spherical coordinates `longitude_rad`,
/// `latitude_rad` and `radius_m` to EME2000 Cartesian coordinates \[m\]: a rotation about x by
/// `−ε` (Montenbruck & Gill eq. 3.46, `r = R_x(−ε) (r cos β cos λ, r cos β sin λ, r sin β)`).
#[inline]
fn ecliptic_to_eme2000_m(longitude_rad: f64, latitude_rad: f64, radius_m: f64) -> Vector3<f64> {
    let (sin_l, cos_l) = longitude_rad.sin_cos();
    let (sin_b, cos_b) = latitude_rad.sin_cos();
    let (sin_e, cos_e) = OBLIQUITY_J2000_RAD.sin_cos();
    let x = radius_m * cos_b * cos_l;
    let y = radius_m * cos_b * sin_l;
    let z = radius_m * sin_b;
    Vector3::new(x, cos_e * y - sin_e * z, sin_e * y + cos_e * z)
}

/// The Sun's geocentric position \[m\], ECI (EME2000), at `tt_s_past_j2000` TT seconds past J2000
/// (2000-01-01T12:00:00 TT): Montenbruck & Gill, *Satellite Orbits*, eqs. (3.43)–(3.46), referred
/// to the mean equinox of J2000 (no `+1.3972° T` precession term). Geometric (no light time, no
/// aberration). Accuracy: `0.32° |T|` (the fixed perigee) plus ~10″ (60″ at worst) in direction,
/// 1.2′ in 2006 and 5′ in 2026, and ~3 · 10⁻⁵ (1.2 · 10⁻⁴ at worst) in distance; see the module
/// documentation.
pub fn sun_position_eci_m(tt_s_past_j2000: f64) -> Vector3<f64> {
    let t = tt_s_past_j2000 / SECONDS_PER_JULIAN_CENTURY;
    // Mean anomaly of the Sun (of the Earth's orbit), eq. (3.43).
    let m = angle_rad(357.5256 + 35_999.049 * t);
    let (sin_m, cos_m) = m.sin_cos();
    let (sin_2m, cos_2m) = (2.0 * m).sin_cos();
    // Ecliptic longitude: Ω + ω = 282.9400°, the mean anomaly and the equation of centre, eq. (3.44).
    let longitude = angle_rad(282.9400) + m + (6892.0 * sin_m + 72.0 * sin_2m) * ARCSEC;
    // Distance, eq. (3.45): (149.619 − 2.499 cos M − 0.021 cos 2M) · 10⁶ km.
    let radius_m = (149.619 - 2.499 * cos_m - 0.021 * cos_2m) * 1.0e9;
    ecliptic_to_eme2000_m(longitude, 0.0, radius_m)
}

/// The Moon's geocentric position \[m\], ECI (EME2000), at `tt_s_past_j2000` TT seconds past J2000:
/// Montenbruck & Gill, *Satellite Orbits*, eqs. (3.47)–(3.49), the mean longitude referred to the
/// J2000 equinox by its `−1.3972° T` term. Geometric. Accuracy: a few arcminutes in direction
/// (Montenbruck & Pfleger: approx. 5′ in right ascension, 1′ in declination) and about 0.1 % in
/// distance; see the module documentation.
pub fn moon_position_eci_m(tt_s_past_j2000: f64) -> Vector3<f64> {
    let t = tt_s_past_j2000 / SECONDS_PER_JULIAN_CENTURY;
    // Fundamental arguments, eq. (3.47) [deg, T in Julian centuries].
    // L0: the Moon's mean longitude (of date, then referred to the J2000 equinox by −1.3972° T).
    let l0 = angle_rad(218.316_17 + 481_267.880_88 * t - 1.3972 * t);
    // l: the Moon's mean anomaly.
    let l = angle_rad(134.962_92 + 477_198.867_53 * t);
    // l′: the Sun's mean anomaly.
    let lp = angle_rad(357.525_43 + 35_999.049_44 * t);
    // F: the Moon's mean argument of latitude (mean distance from the ascending node).
    let f = angle_rad(93.272_83 + 483_202.018_73 * t);
    // D: the mean elongation of the Moon from the Sun.
    let d = angle_rad(297.850_27 + 445_267.111_35 * t);

    // Longitude, eq. (3.48): L0 plus the main periodic terms [arcsec].
    let dlambda = 22_640.0 * l.sin() + 769.0 * (2.0 * l).sin() - 4_586.0 * (l - 2.0 * d).sin()
        + 2_370.0 * (2.0 * d).sin()
        - 668.0 * lp.sin()
        - 412.0 * (2.0 * f).sin()
        - 212.0 * (2.0 * l - 2.0 * d).sin()
        - 206.0 * (l + lp - 2.0 * d).sin()
        + 192.0 * (l + 2.0 * d).sin()
        - 165.0 * (lp - 2.0 * d).sin()
        + 148.0 * (l - lp).sin()
        - 125.0 * d.sin()
        - 110.0 * (l + lp).sin()
        - 55.0 * (2.0 * f - 2.0 * d).sin();
    let longitude = l0 + dlambda * ARCSEC;

    // Latitude, eq. (3.48): 18520″ sin(F + λ − L0 + 412″ sin 2F + 541″ sin l′) and seven smaller
    // terms [arcsec].
    let h = f - 2.0 * d;
    let s = f + (dlambda + 412.0 * (2.0 * f).sin() + 541.0 * lp.sin()) * ARCSEC;
    let beta = 18_520.0 * s.sin() - 526.0 * h.sin() + 44.0 * (l + h).sin()
        - 31.0 * (-l + h).sin()
        - 25.0 * (-2.0 * l + f).sin()
        - 23.0 * (lp + h).sin()
        + 21.0 * (-l + f).sin()
        + 11.0 * (-lp + h).sin();
    let latitude = beta * ARCSEC;

    // Distance, eq. (3.49) [km].
    let radius_km = 385_000.0
        - 20_905.0 * l.cos()
        - 3_699.0 * (2.0 * d - l).cos()
        - 2_956.0 * (2.0 * d).cos()
        - 570.0 * (2.0 * l).cos()
        + 246.0 * (2.0 * l - 2.0 * d).cos()
        - 205.0 * (lp - 2.0 * d).cos()
        - 171.0 * (l + 2.0 * d).cos()
        - 152.0 * (l + lp - 2.0 * d).cos();

    ecliptic_to_eme2000_m(longitude, latitude, radius_km * 1.0e3)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two vectors' angle \[rad\].
    fn angle(a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
        a.cross(b).norm().atan2(a.dot(b))
    }

    #[test]
    fn sun_lies_in_the_j2000_ecliptic_at_about_one_au() {
        // Over ±50 years: the ecliptic latitude is zero by construction (the position is normal
        // to the ecliptic pole R_x(−ε) ẑ = (0, −sin ε, cos ε)) and the distance stays within the
        // Earth's perihelion and aphelion (0.98329 and 1.01671 AU for e = 0.01671).
        let pole = Vector3::new(0.0, -OBLIQUITY_J2000_RAD.sin(), OBLIQUITY_J2000_RAD.cos());
        for k in -50..=50 {
            let t_s = f64::from(k) * 365.25 * 86_400.0 + f64::from(k) * 1234.5;
            let sun = sun_position_eci_m(t_s);
            assert!(sun.normalize().dot(&pole).abs() < 1e-15, "latitude at {k}");
            let au = sun.norm() / ASTRONOMICAL_UNIT_M;
            assert!((0.9832..=1.0168).contains(&au), "{au} AU at year {k}");
        }
    }

    #[test]
    fn sun_moves_about_one_degree_a_day_eastward() {
        // The mean motion in the J2000 frame is 360°/365.25636 d (sidereal year) = 0.98561°/day;
        // the true motion varies by ±2e (±3.3 %) over the orbit.
        let mut previous = sun_position_eci_m(0.0);
        for day in 1..=366 {
            let now = sun_position_eci_m(f64::from(day) * 86_400.0);
            let step_deg = angle(&previous, &now).to_degrees();
            assert!(
                (0.95..=1.02).contains(&step_deg),
                "{step_deg}° on day {day}"
            );
            // Eastward: the motion is along the ecliptic pole (prograde).
            let pole = Vector3::new(0.0, -OBLIQUITY_J2000_RAD.sin(), OBLIQUITY_J2000_RAD.cos());
            assert!(previous.cross(&now).dot(&pole) > 0.0);
            previous = now;
        }
    }

    #[test]
    fn moon_stays_within_its_distance_and_latitude_envelope() {
        // Perigee and apogee range 356 400 to 406 700 km; the ecliptic latitude stays below the
        // orbit's inclination 5.145° plus its ±0.15° oscillation (Meeus, ch. 47 and 50). Sampled
        // every 0.37 day over 20 years.
        let pole = Vector3::new(0.0, -OBLIQUITY_J2000_RAD.sin(), OBLIQUITY_J2000_RAD.cos());
        let mut min_km = f64::INFINITY;
        let mut max_km = 0.0_f64;
        let mut max_lat_deg = 0.0_f64;
        for k in 0..(20 * 1000) {
            let t_s = (f64::from(k) * 0.37 - 3650.0) * 86_400.0;
            let moon = moon_position_eci_m(t_s);
            let km = moon.norm() / 1e3;
            min_km = min_km.min(km);
            max_km = max_km.max(km);
            max_lat_deg = max_lat_deg.max(moon.normalize().dot(&pole).asin().to_degrees().abs());
        }
        assert!(
            (355_500.0..357_500.0).contains(&min_km),
            "perigee {min_km} km"
        );
        assert!(
            (405_500.0..407_500.0).contains(&max_km),
            "apogee {max_km} km"
        );
        assert!(
            (5.0..5.35).contains(&max_lat_deg),
            "latitude {max_lat_deg}°"
        );
    }

    #[test]
    fn moon_period_is_the_sidereal_month() {
        // Successive passes through the same J2000 longitude (x–z plane crossing with y rising)
        // are a sidereal month apart, 27.32166 d on average (±~0.3 d from the anomaly).
        let crossing_after = |start_s: f64| {
            let step = 600.0;
            let mut t = start_s;
            let mut previous = moon_position_eci_m(t).y;
            loop {
                t += step;
                let y = moon_position_eci_m(t).y;
                if previous < 0.0 && y >= 0.0 && moon_position_eci_m(t).x > 0.0 {
                    return t;
                }
                previous = y;
            }
        };
        let mut t = crossing_after(0.0);
        let first = t;
        for _ in 0..13 {
            t = crossing_after(t + 86_400.0);
        }
        let mean_days = (t - first) / 13.0 / 86_400.0;
        assert!((mean_days - 27.321_66).abs() < 0.05, "{mean_days} d");
    }
}
