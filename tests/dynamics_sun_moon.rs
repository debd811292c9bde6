//! The Sun and the Moon of the force models against independent references: the analytic
//! ephemerides against published positions (the Astronomical Almanac, Meeus, Vallado), the
//! third-body acceleration against its tidal expansion, solar radiation pressure against the
//! cannonball formula and a propagation, and the shadow boundaries against the geometry of a
//! circular orbit. Public API only. Every tolerance is the stated accuracy of the model and of the
//! reference (see each comment), never a fit to the code's output.

use nalgebra::{Matrix3, Vector3};
use satflock::dynamics::{
    lit_fraction, moon_position_eci_m, sun_position_eci_m, Bodies, BodyName, ForceModel, ForceSet,
    ForcesConfig, Instant, PhysicalProperties, ShadowName, SolarRadiationPressure, SrpConfig,
    ThirdBody, ThirdBodyConfig, ASTRONOMICAL_UNIT_M, GM_MOON_M3_S2, GM_SUN_M3_S2,
    SOLAR_PRESSURE_N_PER_M2, SUN_RADIUS_M,
};
use satflock::integrate::Rk4;
use satflock::orbit::EarthModel;
use satflock::time::parse_epoch_utc;

const ARCSEC: f64 = std::f64::consts::PI / (180.0 * 3600.0);
const ARCMIN: f64 = 60.0 * ARCSEC;
const DEG: f64 = std::f64::consts::PI / 180.0;
const JD_J2000: f64 = 2_451_545.0;
const SECONDS_PER_CENTURY: f64 = 36_525.0 * 86_400.0;

/// TT seconds past J2000 of a TT Julian date.
fn tt_s_of_jd_tt(jd_tt: f64) -> f64 {
    (jd_tt - JD_J2000) * 86_400.0
}

/// TT seconds past J2000 of a UTC date-time, through the crate's parser and hifitime.
fn tt_s_of_utc(utc: &str) -> f64 {
    parse_epoch_utc(utc).unwrap().to_tt_since_j2k().to_seconds()
}

/// The angle between two vectors \[rad\].
fn angle(a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    a.cross(b).norm().atan2(a.dot(b))
}

/// The IAU 1976 precession matrix from the mean equator and equinox of J2000 to those of date,
/// `T` TT Julian centuries past J2000: `P = R3(−z_A) R2(θ_A) R3(−ζ_A)` with Lieske's (1977)
/// angles (Vallado, *Fundamentals*, 4th ed., eq. 3-88; Meeus, *Astronomical Algorithms*, eq. 21.3).
/// Written here, independently of the crate (which works in EME2000 only).
fn precession_j2000_to_mean_of_date(t: f64) -> Matrix3<f64> {
    let zeta = (2306.2181 * t + 0.30188 * t * t + 0.017998 * t * t * t) * ARCSEC;
    let z = (2306.2181 * t + 1.09468 * t * t + 0.018203 * t * t * t) * ARCSEC;
    let theta = (2004.3109 * t - 0.42665 * t * t - 0.041833 * t * t * t) * ARCSEC;
    // Frame rotations (the passive matrices of Vallado's ROT2/ROT3).
    let rot3 = |phi: f64| {
        let (s, c) = phi.sin_cos();
        Matrix3::new(c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0)
    };
    let rot2 = |phi: f64| {
        let (s, c) = phi.sin_cos();
        Matrix3::new(c, 0.0, -s, 0.0, 1.0, 0.0, s, 0.0, c)
    };
    rot3(-z) * rot2(theta) * rot3(-zeta)
}

/// Equatorial (mean of date) to ecliptic longitude, latitude \[rad\] and distance, with the IAU 1980
/// mean obliquity of date `ε_A = 84381.448″ − 46.8150″ T − 0.00059″ T² + 0.001813″ T³`.
fn ecliptic_of_date(r: &Vector3<f64>, t: f64) -> (f64, f64, f64) {
    let eps = (84_381.448 - 46.8150 * t - 0.00059 * t * t + 0.001813 * t * t * t) * ARCSEC;
    let (s, c) = eps.sin_cos();
    let x = r.x;
    let y = c * r.y + s * r.z;
    let z = -s * r.y + c * r.z;
    let rho = r.norm();
    (
        y.atan2(x).rem_euclid(std::f64::consts::TAU),
        (z / rho).asin(),
        rho,
    )
}

/// The angle between the longitudes `a` and `b` \[rad\], in (−π, π].
fn longitude_difference(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(std::f64::consts::TAU);
    if d > std::f64::consts::PI {
        d - std::f64::consts::TAU
    } else {
        d
    }
}

/// The analytic Sun's direction error budget at `t` centuries \[rad\]. Montenbruck & Gill's mean
/// longitude is `Ω + ω + M = 280.4656° + 35999.049° T` (the mean anomaly's rate: the longitude of
/// perigee is held fixed), the true one referred to the J2000 equinox `280.46646° + 35999.37294° T`
/// (Meeus eq. 25.2, `280.46646° + 36000.76983° T` of date, less the general precession
/// `5028.796″ T`): they part by `0.00086° + 0.32394° |T|`. The Kepler series also leaves out the
/// perturbations of the Earth's longitude, whose terms in VSOP87 (Meeus, Appendix III, Earth L0:
/// 7.2″, 7.1″, 6.5″ (the Moon), 5.5″, 4.8″, 2.7″ ...) add up to about 60″ at worst (10″ rms), the
/// third-order term of the equation of the centre (1.0″) and a mean-anomaly offset (0.4″).
/// Bound: `0.00086° + 0.32394° |T| + 62″`.
fn sun_model_direction_budget(t: f64) -> f64 {
    (0.000_86 + 0.323_94 * t.abs()) * DEG + 62.0 * ARCSEC
}

/// The analytic Sun's distance error budget (relative) at `t` centuries: the periodic terms of the
/// radius vector the Kepler series leaves out (VSOP87 Earth R0, Meeus Appendix III: 3.1e-5 AU, the
/// Earth's monthly wobble about the Earth–Moon barycentre, then 1.6e-5, 1.6e-5, 0.9e-5 AU and
/// smaller from Venus and Jupiter) add up to ~1.1e-4 at worst, and the fixed eccentricity
/// (the R1 term 1.03e-3 τ, τ = T/10) adds 1.03e-4 |T|: 1.2e-4 + 1.03e-4 |T|.
fn sun_model_distance_budget(t: f64) -> f64 {
    1.2e-4 + 1.03e-4 * t.abs()
}

// ----------------------------------------------------------------------------------------------
// Ephemerides
// ----------------------------------------------------------------------------------------------

#[test]
fn tt_of_utc_matches_julian_dates() {
    // Vallado's companion code for Example 5-1 (ex5_1.m) takes 2006-04-01 23:58:54.816 UTC so
    // that TT = 2006-04-02 0h (TT − UTC = 33 + 32.184 s); JD_TT = 2453827.5. The crate's epoch
    // parser and hifitime's TT past J2000 must give that instant to the microsecond.
    let tt = tt_s_of_utc("2006-04-01T23:58:54.816Z");
    assert!((tt - tt_s_of_jd_tt(2_453_827.5)).abs() < 1e-6, "{tt}");
    // 1994: TAI − UTC = 28 s.
    let tt = tt_s_of_utc("1994-04-27T23:58:59.816Z");
    assert!((tt - tt_s_of_jd_tt(2_449_470.5)).abs() < 1e-6, "{tt}");
}

#[test]
fn sun_matches_the_astronomical_almanac_2006_april_2() {
    // The Astronomical Almanac for 2006, geocentric rectangular coordinates of the Sun referred to
    // the ICRS (J2000 mean equator and equinox), 2006 April 2, 0h TT: (0.9775113, 0.1911521,
    // 0.0828717) AU, as quoted in Vallado's companion code for Example 5-1 (ex5_1.m, `rsunaa`).
    let t_s = tt_s_of_jd_tt(2_453_827.5);
    let t = t_s / SECONDS_PER_CENTURY;
    let reference = Vector3::new(0.977_511_3, 0.191_152_1, 0.082_871_7) * ASTRONOMICAL_UNIT_M;
    let sun = sun_position_eci_m(t_s);
    let angle_err = angle(&sun, &reference);
    let distance_err = sun.norm() / reference.norm() - 1.0;
    println!(
        "Sun vs AA 2006-04-02: {:.1}″ in direction, {:.2e} in distance (budget {:.1}″)",
        angle_err / ARCSEC,
        distance_err,
        sun_model_direction_budget(t) / ARCSEC
    );
    // Budget: the model's (76″ + 62″ = 138″ here) plus 21″ for the reference, in case the tabulated
    // coordinates carry the annual aberration (20.5″), plus its 7-digit rounding (0.1″).
    assert!(angle_err <= sun_model_direction_budget(t) + 21.0 * ARCSEC);
    // Distance: the model's budget plus the reference's rounding (5e-8 AU).
    assert!(distance_err.abs() <= sun_model_distance_budget(t) + 1e-7);
}

#[test]
fn sun_matches_meeus_example_26a() {
    // Meeus, *Astronomical Algorithms*, 2nd ed., Example 26.a: 1992 October 13.0 TD (JDE 2448908.5),
    // the Sun's geometric rectangular coordinates referred to the mean equator and equinox of date
    // from VSOP87 (accurate to ~1″): X = −0.9379952, Y = −0.3116544, Z = −0.1351215 AU. The
    // crate's EME2000 Sun is precessed to the date (IAU 1976) for the comparison.
    let t_s = tt_s_of_jd_tt(2_448_908.5);
    let t = t_s / SECONDS_PER_CENTURY;
    let reference = Vector3::new(-0.937_995_2, -0.311_654_4, -0.135_121_5) * ASTRONOMICAL_UNIT_M;
    let sun = precession_j2000_to_mean_of_date(t) * sun_position_eci_m(t_s);
    let angle_err = angle(&sun, &reference);
    let distance_err = sun.norm() / reference.norm() - 1.0;
    println!(
        "Sun vs Meeus 26.a 1992-10-13: {:.1}″ in direction, {:.2e} in distance (budget {:.1}″)",
        angle_err / ARCSEC,
        distance_err,
        sun_model_direction_budget(t) / ARCSEC
    );
    // Budget: the model's (87″ + 62″ = 149″ at T = −0.072) plus the reference's ~1″ and rounding.
    assert!(angle_err <= sun_model_direction_budget(t) + 2.0 * ARCSEC);
    assert!(distance_err.abs() <= sun_model_distance_budget(t) + 1e-7);
}

#[test]
fn sun_matches_vallado_example_5_1() {
    // Vallado, *Fundamentals of Astrodynamics and Applications*, 4th ed., Example 5-1, 2006 April 2
    // (TT 0h, as in his companion code): r_☉ = 146 186 235 I + 28 789 144 J + 12 481 136 K km in
    // the mean-of-date frame (MOD), from his Algorithm 29, the Astronomical Almanac's low-precision
    // formula, whose stated accuracy is 0.01° (36″) for the apparent (aberrated) direction. The
    // crate's EME2000 Sun is precessed to the date (IAU 1976: 6.25 years ≈ 314″ in longitude).
    let t_s = tt_s_of_utc("2006-04-01T23:58:54.816Z");
    let t = t_s / SECONDS_PER_CENTURY;
    let reference = Vector3::new(146_186_235.0, 28_789_144.0, 12_481_136.0) * 1e3;
    let sun = precession_j2000_to_mean_of_date(t) * sun_position_eci_m(t_s);
    let angle_err = angle(&sun, &reference);
    let distance_err = sun.norm() / reference.norm() - 1.0;
    // Without precession the frames would differ by ~314″: show that the comparison sees it.
    let unprecessed = angle(&sun_position_eci_m(t_s), &reference);
    println!(
        "Sun vs Vallado 5-1 (MOD): {:.1}″ in direction ({:.1}″ without precession), {:.2e} in \
         distance",
        angle_err / ARCSEC,
        unprecessed / ARCSEC,
        distance_err
    );
    // Budget: the model's (138″) plus Vallado's 36″ and the aberration his longitude includes
    // (20.5″).
    assert!(angle_err <= sun_model_direction_budget(t) + 36.0 * ARCSEC + 21.0 * ARCSEC);
    // His distance is the same two-term Kepler expansion (1.000140612 − 0.016708617 cos M −
    // 0.000139589 cos 2M AU) with the same neglected terms: the model's budget covers both.
    assert!(distance_err.abs() <= sun_model_distance_budget(t));
}

#[test]
fn moon_matches_meeus_example_47a() {
    // Meeus, *Astronomical Algorithms*, 2nd ed., Example 47.a: 1992 April 12, 0h TD (JDE 2448724.5),
    // the Moon's geocentric ecliptic coordinates referred to the mean ecliptic and equinox of date
    // (no nutation) from the truncated ELP-2000/82 of his chapter 47 (accurate to ~10″ in
    // longitude, 4″ in latitude): λ = 133.162655°, β = −3.229126°, Δ = 368 409.7 km.
    let t_s = tt_s_of_jd_tt(2_448_724.5);
    let t = t_s / SECONDS_PER_CENTURY;
    let moon = precession_j2000_to_mean_of_date(t) * moon_position_eci_m(t_s);
    let (lambda, beta, distance_m) = ecliptic_of_date(&moon, t);
    let d_lambda = longitude_difference(lambda, 133.162_655 * DEG);
    let d_beta = beta - (-3.229_126 * DEG);
    let d_distance_km = distance_m / 1e3 - 368_409.7;
    println!(
        "Moon vs Meeus 47.a 1992-04-12: Δλ = {:.2}′, Δβ = {:.2}′, Δr = {:.0} km ({:.3} %)",
        d_lambda / ARCMIN,
        d_beta / ARCMIN,
        d_distance_km,
        100.0 * d_distance_km / 368_409.7
    );
    // Montenbruck & Pfleger give the same lunar series (MINI_MOON, *Astronomy on the Personal
    // Computer*) as "approx. 5′/1′" in right ascension and declination; the ecliptic longitude
    // and latitude errors are of the same size (the terms left out are in λ up to 45″, 40″, 38″,
    // 36″, 31″ ... and sum to ~7′ at worst, Meeus Table 47.A). Plus Meeus's own 10″ and 4″.
    assert!(d_lambda.abs() * beta.cos() <= 5.0 * ARCMIN + 10.0 * ARCSEC);
    assert!(d_beta.abs() <= 1.0 * ARCMIN + 4.0 * ARCSEC);
    // Distance: the largest terms the series leaves out are 130, 109, 105, 80 and 49 km (Meeus
    // Table 47.A) and the rest add a few hundred km more: ~0.2 % (770 km) at worst.
    assert!(d_distance_km.abs() <= 770.0);
}

#[test]
fn series_match_an_independent_implementation_of_the_same_model() {
    // A transcription check, tighter than the accuracy tests (a wrong sign on a 55″ term would hide
    // inside 5′). The Rust crate brahe (duncaneddy/brahe, src/orbit_dynamics/ephemerides.rs, its
    // tests `test_sun_position` and `test_moon_position`) implements the same Montenbruck & Gill
    // series, in the revolution form of their companion code, and tabulates EME2000 positions [m]
    // at MJD_TT 60310.0 and 60311.0 (2024 January 1 and 2, 0h TT). Its constants differ from the
    // book's degrees used here by 1.6e-5° (Sun: Ω + ω = 0.7859444 rev) and 1.2e-5° (M), so the
    // Suns agree to 0.2″ and 1 km; for the Moon by 0.00029° in L0 (0.606433 rev vs 218.31617°),
    // −0.00187° in F, 0.00245° in l′ and −0.00031° in D, which move the longitude by ~1.0″, the
    // latitude by ≤ 18520″ · 3.3e-5 = 0.6″ and the distance by < 1 km: 3″ and 1 km.
    let sun_rows = [
        (
            60_310.0,
            [24622331959.5803, -133060326832.922, -57688711921.8327],
        ),
        (
            60_311.0,
            [27197674033.8982, -132635566579.098, -57504555813.8335],
        ),
    ];
    let moon_rows = [
        (
            60_310.0,
            [-367995522.308997, 142596488.428594, 89284714.7899626],
        ),
        (
            60_311.0,
            [-394746662.3846, 72542978.2908859, 52734738.1846248],
        ),
    ];
    for (mjd_tt, reference) in sun_rows {
        let reference = Vector3::from(reference);
        let sun = sun_position_eci_m(tt_s_of_jd_tt(mjd_tt + 2_400_000.5));
        let angle_err = angle(&sun, &reference);
        let distance_err = sun.norm() - reference.norm();
        println!(
            "Sun vs brahe at MJD_TT {mjd_tt}: {:.3}″, {:.1} m",
            angle_err / ARCSEC,
            distance_err
        );
        assert!(angle_err <= 0.2 * ARCSEC);
        assert!(distance_err.abs() <= 1.0e3);
    }
    for (mjd_tt, reference) in moon_rows {
        let reference = Vector3::from(reference);
        let moon = moon_position_eci_m(tt_s_of_jd_tt(mjd_tt + 2_400_000.5));
        let angle_err = angle(&moon, &reference);
        let distance_err = moon.norm() - reference.norm();
        println!(
            "Moon vs brahe at MJD_TT {mjd_tt}: {:.3}″, {:.1} m",
            angle_err / ARCSEC,
            distance_err
        );
        assert!(angle_err <= 3.0 * ARCSEC);
        assert!(distance_err.abs() <= 1.0e3);
    }
}

#[test]
fn moon_matches_vallado_example_5_3() {
    // Vallado, *Fundamentals*, 4th ed., Example 5-3: 1994 April 28, 0h (his JD 2449470.5, taken as
    // TT here), r_☾ = −134 240.626 I − 311 571.590 J − 126 693.785 K km in the mean-of-date frame,
    // from his Algorithm 31, the Astronomical Almanac's low-precision lunar formula. That formula is
    // stated to 0.3° in longitude, 0.2° in latitude and 0.003° in horizontal parallax (0.3 % of
    // the distance), so this is a coarse check: the tight one is Meeus 47.a above.
    let t_s = tt_s_of_utc("1994-04-27T23:58:59.816Z");
    let t = t_s / SECONDS_PER_CENTURY;
    let reference = Vector3::new(-134_240.626, -311_571.590, -126_693.785) * 1e3;
    let moon = precession_j2000_to_mean_of_date(t) * moon_position_eci_m(t_s);
    let angle_err = angle(&moon, &reference);
    let distance_err = moon.norm() / reference.norm() - 1.0;
    println!(
        "Moon vs Vallado 5-3 (MOD): {:.2}′ in direction, {:.3} % in distance",
        angle_err / ARCMIN,
        100.0 * distance_err
    );
    // Budget: Vallado's √(0.3² + 0.2²)° = 0.36° plus this model's ~5′ (0.085°).
    assert!(angle_err <= (0.36 + 0.085) * DEG);
    // Distance: his 0.003° of parallax at 0.95° is 0.32 %; this model's 0.2 %.
    assert!(distance_err.abs() <= 0.0032 + 0.002);
}

// ----------------------------------------------------------------------------------------------
// Third body
// ----------------------------------------------------------------------------------------------

fn instant(t_s: f64) -> Instant {
    Instant::new(
        t_s,
        Bodies {
            sun: true,
            moon: true,
        },
    )
}

const NO_VELOCITY: Vector3<f64> = Vector3::new(0.0, 0.0, 0.0);

#[test]
fn third_body_on_the_earth_body_line_is_the_tidal_term() {
    // On the line to the body, at r from the Earth's centre toward it, the exact perturbation is
    // GM/d² ((1 − x)⁻² − 1) = (2 GM r / d³) (1 + 3x/2 + 2x² + ...), x = r/d, and on the far side
    // (2 GM r / d³) (1 − 3x/2 + 2x² − ...) away from the body (Vallado, *Fundamentals*, §8.6.3;
    // Montenbruck & Gill §3.2.2). So the closed form 2 GM r/d³ holds to the order of the first
    // neglected term 3x/2, and with that term to 3x².
    let earth = EarthModel::WGS84_EGM96;
    let r = earth.equatorial_radius_m + 400.0e3;
    for (k, t_s) in [-2.5e8, 1.9e8, 7.7e8].into_iter().enumerate() {
        let at = instant(t_s);
        for (body, gm, position) in [
            (BodyName::Moon, GM_MOON_M3_S2, at.moon_eci_m()),
            (BodyName::Sun, GM_SUN_M3_S2, at.sun_eci_m()),
        ] {
            let model = ThirdBody::new(body);
            let d = position.norm();
            let u = position / d;
            let x = r / d;
            let tidal = 2.0 * gm * r / d.powi(3);
            for side in [1.0, -1.0] {
                let satellite = side * r * u;
                let a = model.acceleration_eci_m_s2(
                    &at,
                    &satellite,
                    &NO_VELOCITY,
                    &PhysicalProperties::point_mass(1.0),
                );
                // Along the line, pointing away from the Earth on both sides (stretching).
                let along = a.dot(&(side * u));
                let across = (a - a.dot(&u) * u).norm();
                let ratio = along / tidal;
                if k == 0 {
                    println!(
                        "{body:?}, side {side:+}: |a| = {:.4e} m/s², a / (2GMr/d³) − 1 = {:.4e} \
                         (3x/2 = {:.4e})",
                        a.norm(),
                        ratio - 1.0,
                        1.5 * x
                    );
                }
                assert!((ratio - 1.0).abs() <= 2.0 * x, "{body:?} {ratio}");
                assert!(
                    (ratio - 1.0 - side * 1.5 * x).abs() <= 3.0 * x * x,
                    "{body:?} {ratio}"
                );
                assert!(across <= 1e-12 * a.norm());
            }
        }
    }
}

#[test]
fn third_body_magnitudes_at_low_earth_orbit() {
    // On the body line at r = 6778 km the perturbation is 2 GM r / d³ (1 ± 3x/2 ...), x = r/d
    // (see above). The Moon's distance spans perigee to apogee, 356 400 to 406 700 km (Meeus
    // ch. 50; this truncated series reaches 355 500 to 407 500 km), so the Moon's perturbation must
    // lie between 2 GM r / d³ at 407 500 km times (1 − 2x) and at 355 500 km times (1 + 2x):
    // ~1e-6 m/s². The Sun's spans perihelion to aphelion, 0.9832 to 1.0168 AU: ~5.5e-7 m/s².
    let r = EarthModel::WGS84_EGM96.equatorial_radius_m + 400.0e3;
    let tidal = |gm: f64, d: f64, factor: f64| 2.0 * gm * r / d.powi(3) * factor;
    let moon_range = tidal(GM_MOON_M3_S2, 407.5e6, 1.0 - 2.0 * r / 407.5e6)
        ..=tidal(GM_MOON_M3_S2, 355.5e6, 1.0 + 2.0 * r / 355.5e6);
    let au = ASTRONOMICAL_UNIT_M;
    let sun_range = tidal(GM_SUN_M3_S2, 1.0168 * au, 1.0 - 2.0 * r / au)
        ..=tidal(GM_SUN_M3_S2, 0.9832 * au, 1.0 + 2.0 * r / au);
    println!(
        "Moon range {:.3e} to {:.3e}, Sun range {:.3e} to {:.3e} m/s²",
        moon_range.start(),
        moon_range.end(),
        sun_range.start(),
        sun_range.end()
    );
    assert!(*moon_range.start() > 0.9e-6 && *moon_range.end() < 1.6e-6);
    assert!(*sun_range.start() > 5.0e-7 && *sun_range.end() < 5.7e-7);
    let moon = ThirdBody::new(BodyName::Moon);
    let sun = ThirdBody::new(BodyName::Sun);
    for day in 0..60 {
        let at = instant(f64::from(day) * 86_400.0 * 6.1);
        let p = PhysicalProperties::point_mass(1.0);
        let a_moon = moon
            .acceleration_eci_m_s2(&at, &(r * at.moon_eci_m().normalize()), &NO_VELOCITY, &p)
            .norm();
        let a_sun = sun
            .acceleration_eci_m_s2(&at, &(r * at.sun_eci_m().normalize()), &NO_VELOCITY, &p)
            .norm();
        assert!(moon_range.contains(&a_moon), "{a_moon}");
        assert!(sun_range.contains(&a_sun), "{a_sun}");
    }
}

#[test]
fn third_body_indirect_term_is_present() {
    // At the Earth's centre the perturbation is zero: the direct attraction GM/d² (3.3e-5 m/s² for
    // the Moon, 5.9e-3 m/s² for the Sun) is cancelled exactly by the indirect term.
    let at = instant(3.3e8);
    let p = PhysicalProperties::point_mass(1.0);
    for body in [BodyName::Moon, BodyName::Sun] {
        let a =
            ThirdBody::new(body).acceleration_eci_m_s2(&at, &Vector3::zeros(), &NO_VELOCITY, &p);
        assert_eq!(a, Vector3::zeros(), "{body:?}");
    }
    // Perpendicular to the line the tide compresses: a ≈ −GM r/d³ (1 + O(x)).
    let r = 7.0e6;
    for (body, gm, position) in [
        (BodyName::Moon, GM_MOON_M3_S2, at.moon_eci_m()),
        (BodyName::Sun, GM_SUN_M3_S2, at.sun_eci_m()),
    ] {
        let d = position.norm();
        let perpendicular = position.cross(&Vector3::z()).normalize() * r;
        let a = ThirdBody::new(body).acceleration_eci_m_s2(&at, &perpendicular, &NO_VELOCITY, &p);
        let expected = -gm * perpendicular / d.powi(3);
        assert!(
            (a - expected).norm() <= 2.0 * (r / d) * expected.norm(),
            "{body:?}"
        );
    }
}

#[test]
fn third_body_reads_its_own_ephemeris() {
    assert_eq!(
        ThirdBody::new(BodyName::Sun).bodies(),
        Bodies {
            sun: true,
            moon: false
        }
    );
    assert_eq!(
        ThirdBody::new(BodyName::Moon).bodies(),
        Bodies {
            sun: false,
            moon: true
        }
    );
    // An instant computed without the ephemerides computes them on request, to the same bits.
    let t_s = 4.4e8;
    let lazy = Instant::new(t_s, Bodies::default());
    assert_eq!(lazy.sun_eci_m(), instant(t_s).sun_eci_m());
    assert_eq!(lazy.moon_eci_m(), instant(t_s).moon_eci_m());
}

// ----------------------------------------------------------------------------------------------
// Solar radiation pressure
// ----------------------------------------------------------------------------------------------

fn srp_properties() -> PhysicalProperties {
    // A 100 kg satellite with 1.2 m² facing the Sun and C_r = 1.3.
    PhysicalProperties {
        srp_area_m2: 1.2,
        reflectivity_coefficient: 1.3,
        ..PhysicalProperties::point_mass(100.0)
    }
}

#[test]
fn srp_is_the_cannonball_pressure_outside_the_shadow() {
    let earth = EarthModel::WGS84_EGM96;
    let at = instant(2.2e8);
    let sun = at.sun_eci_m();
    let properties = srp_properties();
    // Lit positions: the sunward side at LEO and GEO radius, and above the pole.
    let positions = [
        sun.normalize() * 7.0e6,
        sun.normalize() * 42_164.0e3,
        sun.normalize().cross(&Vector3::x()).normalize() * 7.0e6,
    ];
    for shadow in [
        ShadowName::None,
        ShadowName::Cylindrical,
        ShadowName::Conical,
    ] {
        let srp = SolarRadiationPressure::new(shadow, earth.equatorial_radius_m);
        for r in &positions {
            let a = srp.acceleration_eci_m_s2(&at, r, &NO_VELOCITY, &properties);
            let to_sun = sun - r;
            let d = to_sun.norm();
            // a = −P C_r (A/m) (AU/d)² û: written out from the parts.
            let expected = -SOLAR_PRESSURE_N_PER_M2 * 1.3 * 1.2 / 100.0
                * (ASTRONOMICAL_UNIT_M / d).powi(2)
                * (to_sun / d);
            assert!(
                (a - expected).norm() <= 1e-14 * expected.norm(),
                "{shadow:?}"
            );
        }
    }
    // At 1 AU: 4.56e-6 × 1.3 × 0.012 = 7.11e-8 m/s².
    let one_au = SolarRadiationPressure::new(ShadowName::None, earth.equatorial_radius_m);
    let r = sun - sun.normalize() * ASTRONOMICAL_UNIT_M;
    let a = one_au.acceleration_eci_m_s2(&at, &r, &NO_VELOCITY, &properties);
    assert!((a.norm() - 7.1136e-8).abs() < 1e-12, "{}", a.norm());
}

#[test]
fn srp_is_zero_in_the_umbra_and_scaled_in_the_penumbra() {
    let earth = EarthModel::WGS84_EGM96;
    let at = instant(-1.4e8);
    let sun = at.sun_eci_m();
    let properties = srp_properties();
    let behind = -sun.normalize() * 7.0e6;
    for shadow in [ShadowName::Cylindrical, ShadowName::Conical] {
        let srp = SolarRadiationPressure::new(shadow, earth.equatorial_radius_m);
        assert_eq!(
            srp.acceleration_eci_m_s2(&at, &behind, &NO_VELOCITY, &properties),
            Vector3::zeros(),
            "{shadow:?}"
        );
    }
    let unshadowed = SolarRadiationPressure::new(ShadowName::None, earth.equatorial_radius_m)
        .acceleration_eci_m_s2(&at, &behind, &NO_VELOCITY, &properties);
    assert!(unshadowed.norm() > 5e-8);
    // In the penumbra: the conical acceleration is the unshadowed one times the lit fraction.
    // Place the satellite behind the Earth at 400 km altitude, at the cylinder's edge (half lit).
    let s_hat = sun.normalize();
    let side = s_hat.cross(&Vector3::z()).normalize();
    let r = earth.equatorial_radius_m + 400.0e3;
    let b = (earth.equatorial_radius_m / r).asin();
    let theta = std::f64::consts::PI - b;
    let position = r * (theta.cos() * s_hat + theta.sin() * side);
    let lit = lit_fraction(
        ShadowName::Conical,
        &position,
        &sun,
        earth.equatorial_radius_m,
    );
    assert!(lit > 0.05 && lit < 0.95, "{lit}");
    let a = SolarRadiationPressure::new(ShadowName::Conical, earth.equatorial_radius_m)
        .acceleration_eci_m_s2(&at, &position, &NO_VELOCITY, &properties);
    let full = SolarRadiationPressure::new(ShadowName::None, earth.equatorial_radius_m)
        .acceleration_eci_m_s2(&at, &position, &NO_VELOCITY, &properties);
    assert!((a - lit * full).norm() <= 1e-15 * full.norm());
}

#[test]
fn srp_alone_integrates_to_a_constant_acceleration() {
    // A satellite at rest 42 164 km sunward of the Earth (never in the shadow), SRP alone, one hour
    // of RK4: Δv = ∫ a dt must equal a(t0) T up to the change of a over the hour. The Sun's
    // direction turns by at most 1.02°/day (the fastest, at perihelion: n (1 + 2e)), 7.4e-4 rad in
    // an hour, and its distance changes by at most 2.5e9 m × 2.0e-7 rad/s × 3600 s = 1.8e6 m
    // (1.2e-5 relative, 2.4e-5 in a): |Δv − a0 T| ≤ |a0| T (7.4e-4 + 2.4e-5). The displacement
    // must be ½ a0 T² to the same relative bound.
    let earth = EarthModel::WGS84_EGM96;
    let t0_s = 2.7e8;
    let duration_s = 3600.0;
    let srp = SolarRadiationPressure::new(ShadowName::Conical, earth.equatorial_radius_m);
    let properties = srp_properties();
    let r0 = Instant::new(t0_s, Bodies::default())
        .sun_eci_m()
        .normalize()
        * 42_164.0e3;
    let acceleration = |t_s: f64, r: &Vector3<f64>| {
        let at = Instant::new(
            t0_s + t_s,
            Bodies {
                sun: true,
                moon: false,
            },
        );
        srp.acceleration_eci_m_s2(&at, r, &NO_VELOCITY, &properties)
    };
    let a0 = acceleration(0.0, &r0);
    let system = |t_s: f64, y: &[f64], dy: &mut [f64]| {
        let a = acceleration(t_s, &Vector3::new(y[0], y[1], y[2]));
        dy[..3].copy_from_slice(&y[3..]);
        dy[3..].copy_from_slice(a.as_slice());
    };
    let mut state = [r0.x, r0.y, r0.z, 0.0, 0.0, 0.0];
    Rk4::new(6).integrate(&system, 0.0, duration_s, &mut state, 60.0);
    let dv = Vector3::new(state[3], state[4], state[5]);
    let dr = Vector3::new(state[0], state[1], state[2]) - r0;
    let bound = 7.4e-4 + 2.4e-5;
    let dv_err = (dv - a0 * duration_s).norm() / (a0.norm() * duration_s);
    let dr_err = (dr - 0.5 * a0 * duration_s * duration_s).norm()
        / (0.5 * a0.norm() * duration_s * duration_s);
    println!(
        "SRP |a0| = {:.4e} m/s², |Δv| = {:.4e} m/s, relative Δv − a0 T = {dv_err:.2e}, Δr − a0 T²/2 \
         = {dr_err:.2e} (bound {bound:.1e})",
        a0.norm(),
        dv.norm()
    );
    assert!(dv_err <= bound);
    assert!(dr_err <= bound);
}

// ----------------------------------------------------------------------------------------------
// Shadow boundaries along a circular orbit
// ----------------------------------------------------------------------------------------------

/// A circular orbit of radius `radius_m` in the plane of the Sun direction `s_hat` and a unit
/// vector `side` normal to it, starting at the subsolar point: r(t) = r (cos nt ŝ + sin nt ê).
struct SunPlaneOrbit {
    radius_m: f64,
    mean_motion_rad_s: f64,
    s_hat: Vector3<f64>,
    side: Vector3<f64>,
}

impl SunPlaneOrbit {
    fn new(radius_m: f64, sun: &Vector3<f64>) -> Self {
        let s_hat = sun.normalize();
        // Any unit vector normal to ŝ: here the one that makes the orbit steeply inclined.
        let side = s_hat.cross(&Vector3::new(0.3, -0.2, 1.0)).normalize();
        Self {
            radius_m,
            mean_motion_rad_s: EarthModel::WGS84_EGM96.mean_motion_rad_s(radius_m),
            s_hat,
            side,
        }
    }

    fn position(&self, t_s: f64) -> Vector3<f64> {
        let (s, c) = (self.mean_motion_rad_s * t_s).sin_cos();
        self.radius_m * (c * self.s_hat + s * self.side)
    }

    /// The time \[s\] at the angle `theta` \[rad\] from the subsolar point.
    fn time_at(&self, theta: f64) -> f64 {
        theta / self.mean_motion_rad_s
    }
}

/// The root of `f` in `[lo, hi]` (`f(lo)` and `f(hi)` of opposite signs, or `f(lo)` true and
/// `f(hi)` false for a predicate) by bisection to 1e-9 s.
fn bisect(mut lo: f64, mut hi: f64, below: impl Fn(f64) -> bool) -> f64 {
    let lo_below = below(lo);
    assert_ne!(lo_below, below(hi), "no transition in [{lo}, {hi}]");
    while hi - lo > 1e-9 {
        let mid = 0.5 * (lo + hi);
        if below(mid) == lo_below {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[test]
fn cylindrical_shadow_boundaries_are_at_the_arcsine_of_the_radius_ratio() {
    // In a plane containing the Sun direction, the cylinder of radius R about the anti-Sun axis is
    // entered and left where the angle from the anti-Sun direction is asin(R/r): at nt = π ∓
    // asin(R/r). The Sun is frozen at one instant.
    let earth = EarthModel::WGS84_EGM96;
    let sun = sun_position_eci_m(2.0e8);
    for altitude_m in [400.0e3, 1_500.0e3, 35_786.0e3] {
        let orbit = SunPlaneOrbit::new(earth.equatorial_radius_m + altitude_m, &sun);
        let half = (earth.equatorial_radius_m / orbit.radius_m).asin();
        let expected_entry = orbit.time_at(std::f64::consts::PI - half);
        let expected_exit = orbit.time_at(std::f64::consts::PI + half);
        let lit = |t: f64| {
            lit_fraction(
                ShadowName::Cylindrical,
                &orbit.position(t),
                &sun,
                earth.equatorial_radius_m,
            )
        };
        let midnight = orbit.time_at(std::f64::consts::PI);
        let entry = bisect(0.5 * midnight, midnight, |t| lit(t) > 0.5);
        let exit = bisect(midnight, 1.5 * midnight, |t| lit(t) > 0.5);
        println!(
            "cylindrical at {:.0} km: entry {:.6} s (expected {:.6}), exit {:.6} s (expected \
             {:.6}), shadow {:.3} s",
            altitude_m / 1e3,
            entry,
            expected_entry,
            exit,
            expected_exit,
            exit - entry
        );
        // The geometry is exact for the cylinder; the bisection resolves 1e-9 s, and the position's
        // rounding (1e-16 relative of 7e6 m, over 7.7 km/s) 1e-13 s: 1e-6 s is ample.
        assert!((entry - expected_entry).abs() < 1e-6);
        assert!((exit - expected_exit).abs() < 1e-6);
    }
}

#[test]
fn conical_shadow_boundaries_at_400_km() {
    // Seen from a satellite on a circular orbit in a plane containing the Sun, the angle c between
    // the Earth's centre and the Sun is π − nt (up to the solar parallax r/d), the Earth's apparent
    // radius b = asin(R/r) is constant and the Sun's is a = asin(R_☉/d). So the penumbra is entered
    // at nt = π − b − a (c = a + b), the umbra at π − b + a (c = b − a), and left symmetrically;
    // the penumbra lasts 2a/n. The parallax shifts each boundary by at most (r/d)/n (0.04 s at
    // 400 km); the bisection resolves 1e-9 s.
    let earth = EarthModel::WGS84_EGM96;
    let sun = sun_position_eci_m(2.0e8);
    let orbit = SunPlaneOrbit::new(earth.equatorial_radius_m + 400.0e3, &sun);
    let n = orbit.mean_motion_rad_s;
    let a = (SUN_RADIUS_M / sun.norm()).asin();
    let b = (earth.equatorial_radius_m / orbit.radius_m).asin();
    let pi = std::f64::consts::PI;
    let parallax_s = orbit.radius_m / sun.norm() / n + 1e-8;
    let lit = |t: f64| {
        lit_fraction(
            ShadowName::Conical,
            &orbit.position(t),
            &sun,
            earth.equatorial_radius_m,
        )
    };
    let midnight = orbit.time_at(pi);
    let penumbra_entry = bisect(0.5 * midnight, midnight, |t| lit(t) >= 1.0);
    let umbra_entry = bisect(0.5 * midnight, midnight, |t| lit(t) > 0.0);
    let umbra_exit = bisect(midnight, 1.5 * midnight, |t| lit(t) <= 0.0);
    let penumbra_exit = bisect(midnight, 1.5 * midnight, |t| lit(t) < 1.0);
    let cylinder_entry = orbit.time_at(pi - b);
    let cylinder_exit = orbit.time_at(pi + b);
    let ingress_s = umbra_entry - penumbra_entry;
    let egress_s = penumbra_exit - umbra_exit;
    println!(
        "conical at 400 km: penumbra entry {penumbra_entry:.4} s (expected {:.4}), umbra entry \
         {umbra_entry:.4} s (expected {:.4}), cylinder entry {cylinder_entry:.4} s; ingress \
         {ingress_s:.4} s, egress {egress_s:.4} s (2a/n = {:.4} s); parallax bound {parallax_s:.3} s",
        orbit.time_at(pi - b - a),
        orbit.time_at(pi - b + a),
        2.0 * a / n
    );
    assert!((penumbra_entry - orbit.time_at(pi - b - a)).abs() <= parallax_s);
    assert!((umbra_entry - orbit.time_at(pi - b + a)).abs() <= parallax_s);
    assert!((umbra_exit - orbit.time_at(pi + b - a)).abs() <= parallax_s);
    assert!((penumbra_exit - orbit.time_at(pi + b + a)).abs() <= parallax_s);
    // The penumbra lasts 2a/n, 8 to 10 s at 400 km (a = 0.262° to 0.271° over the year).
    for duration in [ingress_s, egress_s] {
        assert!((duration - 2.0 * a / n).abs() <= 2.0 * parallax_s);
        assert!((8.0..=10.0).contains(&duration), "{duration}");
    }
    // The umbra lies inside the cylinder's shadow, the penumbra straddles its boundary.
    assert!(penumbra_entry < cylinder_entry && cylinder_entry < umbra_entry);
    assert!(umbra_exit < cylinder_exit && cylinder_exit < penumbra_exit);
    // Through the ingress the lit fraction falls monotonically from 1 to 0.
    let samples = 2000;
    let mut previous = 1.0;
    for k in 0..=samples {
        let t = penumbra_entry + ingress_s * f64::from(k) / f64::from(samples);
        let now = lit(t);
        assert!(now <= previous, "rises at {t}: {previous} -> {now}");
        previous = now;
    }
    // Half the disc is hidden when the Sun's centre is on the Earth's limb, i.e. when the line from
    // the satellite to the Sun's centre grazes the sphere (|r × û| = R, the Earth in front). This
    // geometric instant is found independently of the model; the limb's curvature across the disc
    // moves the half-lit instant from it by a² / (6 b n) (the covered area falls short of half by
    // a/(3πb) of the disc), 3 ms here: allow twice that.
    let grazing = bisect(penumbra_entry, umbra_entry, |t| {
        let r = orbit.position(t);
        let u = (sun - r).normalize();
        r.cross(&u).norm() > earth.equatorial_radius_m
    });
    let half_lit = bisect(penumbra_entry, umbra_entry, |t| lit(t) > 0.5);
    let curvature_s = a * a / (6.0 * b * n);
    println!(
        "half lit at {half_lit:.5} s, Sun's centre on the limb at {grazing:.5} s (curvature {:.4} \
         s)",
        curvature_s
    );
    assert!((half_lit - grazing).abs() <= 2.0 * curvature_s + 1e-8);
}

#[test]
fn shadow_none_is_lit_everywhere() {
    let sun = sun_position_eci_m(0.0);
    for k in 0..36 {
        let theta = f64::from(k) * 10.0 * DEG;
        let r = 7.0e6 * Vector3::new(theta.cos(), theta.sin(), 0.0);
        assert_eq!(lit_fraction(ShadowName::None, &r, &sun, 6_378_137.0), 1.0);
    }
}

// ----------------------------------------------------------------------------------------------
// The force set
// ----------------------------------------------------------------------------------------------

#[test]
fn a_force_set_sums_gravity_srp_and_both_third_bodies() {
    let earth = EarthModel::WGS84_EGM96;
    let epoch = parse_epoch_utc("2026-03-20T12:00:00Z").unwrap();
    let config = ForcesConfig {
        srp: Some(SrpConfig {
            shadow: ShadowName::Conical,
        }),
        third_body: Some(ThirdBodyConfig {
            bodies: vec![BodyName::Sun, BodyName::Moon],
        }),
        ..ForcesConfig::default()
    };
    let set = ForceSet::from_config(&config, &earth, epoch).unwrap();
    let gravity_only = ForceSet::from_config(&ForcesConfig::default(), &earth, epoch).unwrap();
    let t_s = 1234.5;
    let at = set.instant(t_s);
    let position = Vector3::new(4.0e6, -5.0e6, 2.5e6);
    let velocity = Vector3::new(5.0e3, 4.0e3, 1.0e3);
    let properties = srp_properties();
    let total = set.acceleration_eci_m_s2(&at, &position, &velocity, &properties);
    let gravity = gravity_only.acceleration_eci_m_s2(&at, &position, &velocity, &properties);
    let expected = SolarRadiationPressure::new(ShadowName::Conical, earth.equatorial_radius_m)
        .acceleration_eci_m_s2(&at, &position, &velocity, &properties)
        + ThirdBody::new(BodyName::Sun).acceleration_eci_m_s2(
            &at,
            &position,
            &velocity,
            &properties,
        )
        + ThirdBody::new(BodyName::Moon).acceleration_eci_m_s2(
            &at,
            &position,
            &velocity,
            &properties,
        );
    assert!((total - gravity - expected).norm() <= 1e-12 * gravity.norm());
    // The instant is the epoch's TT plus the elapsed seconds.
    let tt = epoch.to_tt_since_j2k().to_seconds() + t_s;
    assert!((at.tt_s_past_j2000 - tt).abs() < 1e-6);
    assert_eq!(at.sun_eci_m(), sun_position_eci_m(at.tt_s_past_j2000));
    let summary = set.summary();
    assert_eq!(summary.ephemerides, vec!["sun", "moon"]);
    assert!(summary
        .models
        .contains(&"solar radiation pressure (conical shadow)".to_owned()));
}
