//! Validation of the `orbit` module.
//!
//! `val_*` tests compare against a reference independent of the code under test (a textbook worked
//! example, a closed form, a finite-difference derivative, a published constant). `regress_*` tests
//! check self-consistency (round trips, invariants). Every tolerance carries the reason for its size.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use proptest::prelude::*;
use satflock::orbit::{
    gao_to_hill, hill_to_gao, CartesianState, EarthModel, GravityModel, KeplerianElements,
    LvlhFrame, Matrix3, OrbitError, RelativeStateGao, RelativeStateHill, Vector3,
};

const EARTH: EarthModel = EarthModel::WGS84_EGM96;
const MU: f64 = EarthModel::WGS84_EGM96.mu_m3_s2;
const DEG: f64 = PI / 180.0;

/// Signed difference of two angles reduced to (-pi, pi].
fn angle_diff(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(TAU);
    if d > PI {
        d - TAU
    } else {
        d
    }
}

/// Relative position and velocity errors |dr|/|r|, |dv|/|v| of `got` against `want`.
fn relative_errors(got: &CartesianState, want: &CartesianState) -> (f64, f64) {
    (
        (got.position_m - want.position_m).norm() / want.position_m.norm(),
        (got.velocity_mps - want.velocity_mps).norm() / want.velocity_mps.norm(),
    )
}

fn elements(a: f64, e: f64, i: f64, raan: f64, argp: f64, nu: f64) -> KeplerianElements {
    KeplerianElements {
        semi_major_axis_m: a,
        eccentricity: e,
        inclination_rad: i,
        raan_rad: raan,
        arg_perigee_rad: argp,
        true_anomaly_rad: nu,
    }
}

/// Checks one elements -> Cartesian -> elements -> Cartesian round trip; returns the worst relative
/// Cartesian error and the worst error of any angle that is defined for these elements.
fn round_trip(input: &KeplerianElements) -> (f64, f64) {
    let state = input.to_cartesian(MU).unwrap();
    let back = KeplerianElements::from_cartesian(&state, MU).unwrap();
    let again = back.to_cartesian(MU).unwrap();
    let (dr, dv) = relative_errors(&again, &state);
    for angle in [
        back.raan_rad,
        back.arg_perigee_rad,
        back.true_anomaly_rad,
        back.inclination_rad,
    ] {
        assert!(angle.is_finite() && (0.0..TAU).contains(&angle), "{back:?}");
    }
    assert!((0.0..=PI).contains(&back.inclination_rad));

    // Element errors. Shape quantities are always defined.
    let mut worst_angle = 0.0_f64;
    let da = (back.semi_major_axis_m - input.semi_major_axis_m).abs() / input.semi_major_axis_m;
    let de = (back.eccentricity - input.eccentricity).abs();
    let di = (back.inclination_rad - input.inclination_rad).abs();
    // a: energy -> a amplifies rounding by v^2 r / mu <= (1+e)/(1-e) = 19 at e = 0.9 (perigee);
    // 1e-13 is ~450 ulp and still catches any formula error.
    assert!(da < 1e-13, "a rel err {da:e} for {input:?}");
    // e: the eccentricity vector is a difference of O(1) terms, absolute error a few ulp; the
    // same 1e-13 bound as a.
    assert!(de < 1e-13, "e err {de:e} for {input:?}");
    worst_angle = worst_angle.max(di);

    let sin_i = input.inclination_rad.sin();
    let equatorial = sin_i < 1e-12;
    let circular = input.eccentricity < 1e-12;
    let u_in = input.arg_perigee_rad + input.true_anomaly_rad;
    let u_back = back.arg_perigee_rad + back.true_anomaly_rad;
    if !equatorial {
        worst_angle = worst_angle.max(angle_diff(back.raan_rad, input.raan_rad).abs());
        worst_angle = worst_angle.max(angle_diff(u_back, u_in).abs());
        if !circular {
            worst_angle =
                worst_angle.max(angle_diff(back.arg_perigee_rad, input.arg_perigee_rad).abs());
        }
    } else {
        // Equatorial: only the longitude from the x axis is defined (raan + u prograde, raan - u
        // retrograde, as seen from +z), and the convention says raan = 0.
        assert_eq!(back.raan_rad, 0.0);
        let sign = if input.inclination_rad > FRAC_PI_2 {
            -1.0
        } else {
            1.0
        };
        let lon_in = input.raan_rad + sign * u_in;
        let lon_back = back.raan_rad + sign * u_back;
        worst_angle = worst_angle.max(angle_diff(lon_back, lon_in).abs());
        if !circular {
            let peri_in = input.raan_rad + sign * input.arg_perigee_rad;
            let peri_back = back.raan_rad + sign * back.arg_perigee_rad;
            worst_angle = worst_angle.max(angle_diff(peri_back, peri_in).abs());
        }
    }
    if circular {
        assert_eq!(back.eccentricity, 0.0, "circular convention e = 0");
        assert_eq!(back.arg_perigee_rad, 0.0, "circular convention omega = 0");
    } else {
        worst_angle =
            worst_angle.max(angle_diff(back.true_anomaly_rad, input.true_anomaly_rad).abs());
    }
    (dr.max(dv), worst_angle)
}

// ---------------------------------------------------------------------------------------------
// Elements <-> Cartesian
// ---------------------------------------------------------------------------------------------

#[test]
fn regress_elements_cartesian_round_trip_grid() {
    let mut worst_state = 0.0_f64;
    let mut worst_angle = 0.0_f64;
    let mut count = 0;
    for a in [6_878_137.0, 26_560_000.0, 42_164_000.0] {
        for e in [0.0, 1e-6, 0.01, 0.5, 0.9] {
            for i in [
                0.0,
                1e-6,
                28.5 * DEG,
                90.0 * DEG,
                98.0 * DEG,
                180.0 * DEG - 1e-6,
                PI,
            ] {
                for raan in [0.0, 1.0, 4.0] {
                    for argp in [0.0, 2.0, 5.5] {
                        for nu in [0.0, FRAC_PI_2, PI, 3.5, 6.0] {
                            let (ds, dang) = round_trip(&elements(a, e, i, raan, argp, nu));
                            worst_state = worst_state.max(ds);
                            // Angles of nearly singular orbits are conditioned as eps / e and
                            // eps / sin i: scale them back to an absolute rounding level.
                            let conditioning = e.max(1e-12).min(i.sin().max(1e-12)).min(1.0);
                            let scaled = if e < 1e-12 && i.sin() < 1e-12 {
                                dang
                            } else {
                                dang * conditioning
                            };
                            worst_angle = worst_angle.max(scaled);
                            count += 1;
                        }
                    }
                }
            }
        }
    }
    println!("{count} cases: worst relative Cartesian error {worst_state:e}, worst scaled angle error {worst_angle:e} rad");
    // Cartesian round trip: a handful of trigonometric evaluations and products, each ~1 ulp, and
    // an amplification up to (1+e)/(1-e) = 19 at e = 0.9 through r = p/(1+e cos nu): 1e-14 relative
    // (~45 ulp) is rounding, a formula error would be >= 1e-6.
    assert!(worst_state < 1e-14, "{worst_state:e}");
    // Angles: a few ulp of 2 pi (~1e-15) divided by the conditioning e or sin i, scaled back above;
    // 1e-13 rad leaves margin for the x19 amplification at e = 0.9.
    assert!(worst_angle < 1e-13, "{worst_angle:e}");
}

proptest! {
    #[test]
    fn regress_elements_cartesian_round_trip_random(
        a in 6.6e6_f64..5.0e7,
        e in 0.0_f64..0.95,
        i in 0.0_f64..=PI,
        raan in 0.0_f64..TAU,
        argp in 0.0_f64..TAU,
        nu in -10.0_f64..10.0,
    ) {
        let input = elements(a, e, i, raan, argp, nu);
        let state = input.to_cartesian(MU).unwrap();
        let back = KeplerianElements::from_cartesian(&state, MU).unwrap();
        let again = back.to_cartesian(MU).unwrap();
        let (dr, dv) = relative_errors(&again, &state);
        // Same reasoning as the grid: rounding amplified at most (1+e)/(1-e) = 39 at e = 0.95.
        prop_assert!(dr < 2e-14 && dv < 2e-14, "dr {:e} dv {:e}", dr, dv);
        // Elements where they are well defined (e and sin i above 1e-3, so the angle conditioning
        // eps/e stays below ~1e-12 rad; 1e-10 rad leaves the x39 amplification room).
        if e > 1e-3 && i.sin() > 1e-3 {
            prop_assert!((back.semi_major_axis_m - a).abs() / a < 1e-13);
            prop_assert!((back.eccentricity - e).abs() < 1e-13);
            prop_assert!((back.inclination_rad - i).abs() < 1e-10);
            prop_assert!(angle_diff(back.raan_rad, raan).abs() < 1e-10);
            prop_assert!(angle_diff(back.arg_perigee_rad, argp).abs() < 1e-10);
            prop_assert!(angle_diff(back.true_anomaly_rad, nu).abs() < 1e-10);
        }
    }
}

#[test]
fn regress_singular_orbits_follow_the_documented_conventions() {
    // Circular equatorial prograde at true longitude 1.2 rad.
    let state = elements(7.0e6, 0.0, 0.0, 0.0, 0.0, 1.2)
        .to_cartesian(MU)
        .unwrap();
    let back = KeplerianElements::from_cartesian(&state, MU).unwrap();
    assert_eq!(
        (
            back.eccentricity,
            back.inclination_rad,
            back.raan_rad,
            back.arg_perigee_rad
        ),
        (0.0, 0.0, 0.0, 0.0)
    );
    // True longitude from the x axis, to a few ulp of the angle.
    assert!((back.true_anomaly_rad - 1.2).abs() < 1e-15);
    assert_eq!(back.argument_of_latitude_rad(), back.true_anomaly_rad);

    // Circular retrograde equatorial: i = pi exactly, raan = 0, angle measured about -z.
    let state = CartesianState::new(
        Vector3::new(0.0, 7.0e6, 0.0),
        Vector3::new((MU / 7.0e6).sqrt(), 0.0, 0.0),
    );
    let back = KeplerianElements::from_cartesian(&state, MU).unwrap();
    assert_eq!(back.inclination_rad, PI);
    assert_eq!(back.raan_rad, 0.0);
    // Position +y seen about -z is at angle -pi/2, i.e. 3 pi / 2; rounding of atan2 only.
    assert!((back.argument_of_latitude_rad() - 1.5 * PI).abs() < 1e-15);
}

#[test]
fn val_perigee_and_apogee_closed_form() {
    // At perigee r = a (1-e) along P, v = sqrt(mu (1+e) / (a (1-e))) along Q; at apogee
    // r = a (1+e) along -P, v = sqrt(mu (1-e) / (a (1+e))) along -Q, with
    // P = (cO cw - sO sw ci, sO cw + cO sw ci, sw si), Q = (-cO sw - sO cw ci, -sO sw + cO cw ci, cw si)
    // (the perifocal-to-ECI rotation R3(-raan) R1(-i) R3(-argp), written out here independently).
    let (a, e, i, raan, argp): (f64, f64, f64, f64, f64) = (1.2e7, 0.35, 63.4 * DEG, 0.7, 4.1);
    let (so, co) = raan.sin_cos();
    let (sw, cw) = argp.sin_cos();
    let (si, ci) = i.sin_cos();
    let p_hat = Vector3::new(co * cw - so * sw * ci, so * cw + co * sw * ci, sw * si);
    let q_hat = Vector3::new(-co * sw - so * cw * ci, -so * sw + co * cw * ci, cw * si);
    for (nu, r, v, sign) in [
        (
            0.0,
            a * (1.0 - e),
            (MU * (1.0 + e) / (a * (1.0 - e))).sqrt(),
            1.0,
        ),
        (
            PI,
            a * (1.0 + e),
            (MU * (1.0 - e) / (a * (1.0 + e))).sqrt(),
            -1.0,
        ),
    ] {
        let state = elements(a, e, i, raan, argp, nu).to_cartesian(MU).unwrap();
        let want = CartesianState::new(sign * r * p_hat, sign * v * q_hat);
        let (dr, dv) = relative_errors(&state, &want);
        println!("apsis nu = {nu}: dr {dr:e}, dv {dv:e}");
        // Two independent evaluations of the same trigonometry: a few ulp (sin(pi) = 1.2e-16 adds
        // one more at apogee).
        assert!(dr < 1e-15 && dv < 1e-15, "dr {dr:e} dv {dv:e}");
    }
}

/// Vallado, *Fundamentals of Astrodynamics and Applications*, 4th ed. (2013), Example 2-5 (RV2COE),
/// mu = 398600.4418 km^3/s^2:
/// r = (6524.834, 6862.875, 6448.296) km, v = (4.901327, 5.533756, -1.976341) km/s gives
/// p = 11067.790 km, a = 36127.343 km, e = 0.832853, i = 87.870 deg, RAAN = 227.898 deg,
/// argp = 53.38 deg, nu = 92.335 deg.
///
/// The book works to about 7 significant figures: a direct double-precision evaluation of its own
/// formulas on the printed r, v (a separate Python script, `h = r x v`, `p = h.h/mu`,
/// `e = ((v^2 - mu/r) r - (r.v) v)/mu`, `a = 1/(2/r - v^2/mu)`, `cos i = h_z/|h|`, node and
/// perigee angles by `acos` with quadrant checks) gives p = 11067.79834266182 km,
/// a = 36127.33761967866 km, e = 0.8328533984875214, i = 87.86912617702644 deg,
/// RAAN = 227.8982603572737 deg, argp = 53.38493061845976 deg, nu = 92.33515676213736 deg.
/// The book's p and a differ from these in the 7th figure, and its "87.870" is 87.87 (the
/// two-decimal value its Example 2-6 reuses) padded: printed-input rounding moves i by only ~1e-5 deg
/// (jacobian di/dv ~ 6 deg per km/s times 5e-7 km/s). So the test checks the book to the precision
/// it actually carries, and the double-precision evaluation tightly.
#[test]
fn val_vallado_example_2_5_rv2coe() {
    let mu = 3.986_004_418e14;
    let state = CartesianState::new(
        Vector3::new(6524.834e3, 6862.875e3, 6448.296e3),
        Vector3::new(4.901327e3, 5.533756e3, -1.976341e3),
    );
    let el = KeplerianElements::from_cartesian(&state, mu).unwrap();
    let p_km = el.semi_major_axis_m * (1.0 - el.eccentricity * el.eccentricity) / 1e3;
    let a_km = el.semi_major_axis_m / 1e3;
    let (i, raan, argp, nu) = (
        el.inclination_rad / DEG,
        el.raan_rad / DEG,
        el.arg_perigee_rad / DEG,
        el.true_anomaly_rad / DEG,
    );
    println!(
        "Vallado 2-5: p {p_km} km, a {a_km} km, e {}, i {i} deg, raan {raan} deg, argp {argp} deg, nu {nu} deg",
        el.eccentricity
    );
    // Book: p and a to one unit in the 7th significant figure (0.01 km), the book's working
    // precision; the other elements to half a unit in the last printed digit, with i and argp at
    // two decimals (0.005 deg).
    assert!((p_km - 11067.790).abs() < 0.01);
    assert!((a_km - 36127.343).abs() < 0.01);
    assert!((el.eccentricity - 0.832853).abs() < 0.0000005);
    assert!((i - 87.87).abs() < 0.005);
    assert!((raan - 227.898).abs() < 0.0005);
    assert!((argp - 53.38).abs() < 0.005);
    assert!((nu - 92.335).abs() < 0.0005);
    // Independent double-precision evaluation: same quantities by different formulas (acos vs
    // atan2, p from h vs from a and e), agreement to rounding amplified by the 1/(1-e^2) = 3.3 and
    // the acos conditioning near 0 and pi: 1e-12 relative / 1e-10 deg.
    assert!((p_km / 11067.79834266182 - 1.0).abs() < 1e-12);
    assert!((a_km / 36127.33761967866 - 1.0).abs() < 1e-12);
    assert!((el.eccentricity - 0.8328533984875214).abs() < 1e-12);
    for (got, want) in [
        (i, 87.86912617702644),
        (raan, 227.8982603572737),
        (argp, 53.38493061845976),
        (nu, 92.33515676213736),
    ] {
        assert!((got - want).abs() < 1e-10, "{got} vs {want}");
    }
}

/// Vallado, 4th ed., Example 2-6 (COE2RV), mu = 398600.4418 km^3/s^2: p = 11067.790 km,
/// e = 0.83285, i = 87.87 deg, RAAN = 227.89 deg, argp = 53.38 deg, nu = 92.335 deg gives
/// r = (6525.368, 6861.532, 6449.119) km, v = (4.902279, 5.533140, -1.975710) km/s.
#[test]
fn val_vallado_example_2_6_coe2rv() {
    let mu = 3.986_004_418e14;
    let (p, e) = (11_067.790e3, 0.83285);
    let el = elements(
        p / (1.0 - e * e),
        e,
        87.87 * DEG,
        227.89 * DEG,
        53.38 * DEG,
        92.335 * DEG,
    );
    let state = el.to_cartesian(mu).unwrap();
    let r_km = state.position_m / 1e3;
    let v_kms = state.velocity_mps / 1e3;
    println!("Vallado 2-6: r {r_km:?} km, v {v_kms:?} km/s");
    let r_want = Vector3::new(6525.368, 6861.532, 6449.119);
    let v_want = Vector3::new(4.902279, 5.533140, -1.975710);
    for k in 0..3 {
        // Half a unit in the last printed digit: 0.5 m and 0.5 mm/s.
        assert!((r_km[k] - r_want[k]).abs() < 0.0005, "r[{k}]");
        assert!((v_kms[k] - v_want[k]).abs() < 0.0000005, "v[{k}]");
    }
}

#[test]
fn regress_invalid_inputs_name_their_value() {
    let err = elements(7e6, 0.95, 0.1, 0.0, 0.0, 0.0)
        .to_cartesian(MU)
        .map(|_| ());
    assert_eq!(err, Ok(()));
    let err = elements(7e6, -0.1, 0.1, 0.0, 0.0, 0.0)
        .to_cartesian(MU)
        .unwrap_err();
    assert_eq!(err, OrbitError::InvalidEccentricity { eccentricity: -0.1 });
    assert!(err.to_string().contains("-0.1"));
    // Parabolic: v = escape speed exactly at r (energy 0 to rounding, e = 1).
    let r = 7.0e6;
    let parabolic = CartesianState::new(
        Vector3::new(r, 0.0, 0.0),
        Vector3::new(0.0, (2.0 * MU / r).sqrt() * (1.0 + 1e-12), 0.0),
    );
    assert!(matches!(
        KeplerianElements::from_cartesian(&parabolic, MU),
        Err(OrbitError::NotElliptic { .. })
    ));
}

// ---------------------------------------------------------------------------------------------
// Constants
// ---------------------------------------------------------------------------------------------

#[test]
fn val_constants_against_published_values() {
    // J2 = -sqrt(5) C20bar with the EGM96 C20bar = -0.484165371736e-3 (NASA/TP-1998-206861):
    // 1.0826266836e-3; the constant is that value to 9 significant figures, so agreement to half
    // a unit in the 9th figure (5e-12 absolute).
    let j2_egm96 = 5.0_f64.sqrt() * 0.484165371736e-3;
    assert!((EARTH.j2 - j2_egm96).abs() < 5e-12);
    assert_eq!(EarthModel::default(), EARTH);
    // Gao, Li & Wei 2022 (`docs/methods/bifurcating.md` §1.3): a = 6978.137 km gives omega = 1.08308e-3 rad/s and a period of 5801.2 s
    // (printed to 6 and 5 figures: half a unit in the last digit).
    let a = 6_978_137.0;
    assert!((EARTH.mean_motion_rad_s(a) - 1.08308e-3).abs() < 0.000005e-3);
    assert!((EARTH.period_s(a) - 5801.2).abs() < 0.05);
}

// ---------------------------------------------------------------------------------------------
// Gravity
// ---------------------------------------------------------------------------------------------

/// J2 part of the potential, U_J2 = -(mu/r) J2 (R/r)^2 P2(z/r), written independently of the crate.
fn j2_potential(p: &Vector3<f64>) -> f64 {
    let r = p.norm();
    let s = p.z / r;
    let p2 = 0.5 * (3.0 * s * s - 1.0);
    let ratio = EARTH.equatorial_radius_m / r;
    -(EARTH.mu_m3_s2 / r) * EARTH.j2 * ratio * ratio * p2
}

fn test_positions() -> [Vector3<f64>; 5] {
    [
        Vector3::new(7.0e6, 0.0, 0.0),
        Vector3::new(1.2e6, -4.5e6, 5.1e6),
        Vector3::new(-3.0e6, 2.0e6, -6.2e6),
        Vector3::new(0.0, 0.0, 6.9e6),
        Vector3::new(3.0e7, 2.5e7, 1.0e6),
    ]
}

#[test]
fn val_two_body_acceleration_is_point_mass() {
    for p in test_positions() {
        let got = GravityModel::TwoBody.acceleration_m_s2(&EARTH, &p);
        let want = -MU * p / p.norm().powi(3);
        // Same formula, different operation order: a few ulp.
        assert!((got - want).norm() / want.norm() < 1e-15);
    }
    // Hand value at the equatorial radius: mu / R^2 = 9.7982854791873 m/s^2 (computed with
    // python float arithmetic); rounding only.
    let a = GravityModel::TwoBody
        .acceleration_m_s2(&EARTH, &Vector3::new(EARTH.equatorial_radius_m, 0.0, 0.0));
    assert!((a.x + 9.798_285_479_187_3).abs() < 1e-13 && a.y == 0.0 && a.z == 0.0);
}

#[test]
fn val_j2_acceleration_is_gradient_of_potential() {
    // Central differences of the J2 potential with step h = 10 m. Truncation error ~ U''' h^2 / 6,
    // relative (h/r)^2 ~ 2e-12; rounding ~ eps |U_J2| / h ~ 1e-16 * 7e4 / 10 ~ 1e-12 m/s^2 against a
    // J2 acceleration of ~1e-2 m/s^2, i.e. ~1e-10 relative. 1e-7 relative (the brief's bound) is
    // therefore a loose check, so the measured value is printed too.
    let h = 10.0;
    let mut worst = 0.0_f64;
    for p in test_positions() {
        let mut grad = Vector3::zeros();
        for k in 0..3 {
            let mut plus = p;
            let mut minus = p;
            plus[k] += h;
            minus[k] -= h;
            grad[k] = (j2_potential(&plus) - j2_potential(&minus)) / (2.0 * h);
        }
        let j2_part = GravityModel::J2.acceleration_m_s2(&EARTH, &p)
            - GravityModel::TwoBody.acceleration_m_s2(&EARTH, &p);
        let rel = (j2_part - grad).norm() / grad.norm();
        worst = worst.max(rel);
    }
    println!("J2 acceleration vs finite-difference gradient: worst relative error {worst:e}");
    assert!(worst < 1e-7, "{worst:e}");
}

#[test]
fn val_j2_acceleration_at_equator_and_pole() {
    // Hand formula: equator a = -mu/R^2 (1 + 3/2 J2) x_hat = -9.814197307104337 m/s^2;
    // pole a = -mu/R^2 (1 - 3 J2) z_hat = -9.766461823353225 m/s^2 (python float arithmetic).
    // Rounding of a handful of operations: 1e-13 m/s^2 ~ 10 ulp.
    let r = EARTH.equatorial_radius_m;
    for (p, want) in [
        (
            Vector3::new(r, 0.0, 0.0),
            Vector3::new(-9.814_197_307_104_337, 0.0, 0.0),
        ),
        (
            Vector3::new(0.0, r, 0.0),
            Vector3::new(0.0, -9.814_197_307_104_337, 0.0),
        ),
        (
            Vector3::new(0.0, 0.0, r),
            Vector3::new(0.0, 0.0, -9.766_461_823_353_225),
        ),
        (
            Vector3::new(0.0, 0.0, -r),
            Vector3::new(0.0, 0.0, 9.766_461_823_353_225),
        ),
    ] {
        let got = GravityModel::J2.acceleration_m_s2(&EARTH, &p);
        assert!((got - want).norm() < 1e-13, "{got} vs {want}");
    }
}

// ---------------------------------------------------------------------------------------------
// LVLH frames
// ---------------------------------------------------------------------------------------------

fn reference_states() -> Vec<(&'static str, CartesianState)> {
    vec![
        (
            "circular equatorial",
            elements(6_878_137.0, 0.0, 0.0, 0.0, 0.0, 0.3)
                .to_cartesian(MU)
                .unwrap(),
        ),
        (
            "eccentric inclined",
            elements(9.0e6, 0.3, 63.0 * DEG, 1.1, 2.2, 2.5)
                .to_cartesian(MU)
                .unwrap(),
        ),
        (
            "near-circular polar",
            elements(7.0e6, 1e-3, 90.0 * DEG, 5.0, 0.4, 4.0)
                .to_cartesian(MU)
                .unwrap(),
        ),
    ]
}

fn frames() -> Vec<(String, LvlhFrame)> {
    let mut out = Vec::new();
    for (name, reference) in reference_states() {
        out.push((name.to_owned(), LvlhFrame::from_reference(&reference)));
        let accel = GravityModel::J2.acceleration_m_s2(&EARTH, &reference.position_m);
        out.push((
            format!("{name}, J2-aware"),
            LvlhFrame::from_reference_with_acceleration(&reference, &accel),
        ));
    }
    out
}

fn relative_offsets() -> [RelativeStateHill; 3] {
    [
        RelativeStateHill {
            position_m: Vector3::new(10.0, -20.0, 5.0),
            velocity_mps: Vector3::new(0.01, -0.02, 0.005),
        },
        RelativeStateHill {
            position_m: Vector3::new(-3.0e3, 8.0e3, 1.5e3),
            velocity_mps: Vector3::new(1.0, -2.0, 0.7),
        },
        RelativeStateHill {
            position_m: Vector3::new(5.0e4, -1.0e5, -2.0e4),
            velocity_mps: Vector3::new(-30.0, 10.0, 20.0),
        },
    ]
}

#[test]
fn regress_lvlh_round_trips_both_conventions() {
    let eps = f64::EPSILON;
    let mut worst_eci = 0.0_f64;
    let mut worst_rel = 0.0_f64;
    for (name, frame) in frames() {
        let r = frame.origin().position_m.norm();
        let v = frame.origin().velocity_mps.norm();
        for rel in relative_offsets() {
            // Hill -> ECI -> Hill (and through Gao). The ECI detour adds |r_o| to the offset, so the
            // offset comes back with an absolute error of a few ulp of |r_o| (~1e-9 m) and of |v_o|.
            let sat = frame.from_hill(&rel);
            let hill = frame.to_hill(&sat);
            let gao = RelativeStateGao::from(hill);
            let via_gao = frame.from_hill(&RelativeStateHill::from(gao));
            let pos_err = (hill.position_m - rel.position_m).norm() / (r * eps);
            let vel_err = (hill.velocity_mps - rel.velocity_mps).norm() / (v * eps);
            worst_rel = worst_rel.max(pos_err).max(vel_err);
            // The Gao permutation is exact, so the Gao path reproduces the ECI state bit for bit.
            assert_eq!(via_gao, frame.from_hill(&hill), "{name}");

            // ECI -> Hill -> ECI.
            let back = frame.from_hill(&frame.to_hill(&sat));
            let pos_err = (back.position_m - sat.position_m).norm() / (r * eps);
            let vel_err = (back.velocity_mps - sat.velocity_mps).norm() / (v * eps);
            worst_eci = worst_eci.max(pos_err).max(vel_err);
        }
    }
    println!("LVLH round trips: worst Hill error {worst_rel:.2} ulp, worst ECI error {worst_eci:.2} ulp (of |r_o|, |v_o|)");
    // A rotation, its transpose, a cross product and two additions: each ulp-level; 8 ulp of the
    // reference's |r| and |v| is rounding, a wrong sign or transport term would be >= 1e3 m.
    assert!(worst_rel < 8.0 && worst_eci < 8.0);
}

#[test]
fn regress_reference_sits_at_origin() {
    for (name, frame) in frames() {
        let rel = frame.to_hill(frame.origin());
        // dr and dv are exactly zero, so the result is exactly zero.
        assert_eq!(rel, RelativeStateHill::default(), "{name}");
        assert_eq!(
            frame.from_hill(&RelativeStateHill::default()),
            *frame.origin(),
            "{name}"
        );
    }
}

#[test]
fn regress_vector_rotations_are_inverse_and_orthonormal() {
    for (name, frame) in frames() {
        let rot = frame.rotation_eci_to_hill();
        // Orthonormal to rounding of unit vectors built from r and h: a few ulp.
        assert!(
            (rot * rot.transpose() - Matrix3::identity()).norm() < 1e-15,
            "{name}"
        );
        assert!((rot.determinant() - 1.0).abs() < 1e-15, "{name}");
        let a = Vector3::new(1.0e-3, -2.0e-3, 5.0e-4);
        let back = frame.vector_hill_to_eci(&frame.vector_eci_to_hill(&a));
        assert!((back - a).norm() < 1e-15 * a.norm(), "{name}");
    }
}

#[test]
fn regress_gao_hill_conversion_is_the_spec_rotation() {
    // C built from the images of the Hill basis vectors (its columns).
    let c = Matrix3::from_columns(&[
        hill_to_gao(&Vector3::x()),
        hill_to_gao(&Vector3::y()),
        hill_to_gao(&Vector3::z()),
    ]);
    let spec = Matrix3::new(0.0, 1.0, 0.0, 0.0, 0.0, -1.0, -1.0, 0.0, 0.0);
    assert_eq!(c, spec);
    assert_eq!(c.determinant(), 1.0);
    assert_eq!(c * c.transpose(), Matrix3::identity());
    let v = Vector3::new(1.5, -2.25, 3.125);
    assert_eq!(gao_to_hill(&hill_to_gao(&v)), v);
    assert_eq!(hill_to_gao(&gao_to_hill(&v)), v);
    assert_eq!(gao_to_hill(&v), c.transpose() * v);
}

#[test]
fn val_gao_axes_from_r_and_h() {
    // Gao, Li & Wei 2022 (`docs/methods/bifurcating.md` §1.1): z = -r/|r|, y = -h/|h|, x = y x z, built here directly from r and v.
    for (name, reference) in reference_states() {
        let frame = LvlhFrame::from_reference(&reference);
        let r = reference.position_m;
        let h = r.cross(&reference.velocity_mps);
        let z = -r / r.norm();
        let y = -h / h.norm();
        let x = y.cross(&z);
        for (axis_gao, want) in [(Vector3::x(), x), (Vector3::y(), y), (Vector3::z(), z)] {
            let got = frame.vector_hill_to_eci(&gao_to_hill(&axis_gao));
            // Unit vectors from the same r and h by different operations: a few ulp.
            assert!((got - want).norm() < 1e-15, "{name}: {got} vs {want}");
        }
    }
}

#[test]
fn val_along_track_offset_on_same_circular_orbit_is_hcw_equilibrium() {
    // HCW: x = 0, y = y0, z = 0 with zero relative velocity is an equilibrium. A satellite on the
    // same circular orbit, ahead by du, is at Hill (r (cos du - 1), r sin du, 0) and, because the frame
    // turns at exactly the orbital rate, has exactly zero velocity in the rotating frame.
    let (a, i, raan, u0, du) = (6_978_137.0, 51.7 * DEG, 0.4, 1.3, 1e-4);
    let reference = elements(a, 0.0, i, raan, 0.0, u0).to_cartesian(MU).unwrap();
    let satellite = elements(a, 0.0, i, raan, 0.0, u0 + du)
        .to_cartesian(MU)
        .unwrap();
    let frame = LvlhFrame::from_reference(&reference);
    let rel = frame.to_hill(&satellite);
    let exact = Vector3::new(a * (du.cos() - 1.0), a * du.sin(), 0.0);
    let hcw = Vector3::new(0.0, a * du, 0.0);
    println!(
        "along-track offset: rel pos {} m, rel vel {} m/s",
        rel.position_m, rel.velocity_mps
    );
    // Geometry: differences of two ~7e6 m vectors, rounding ~ few ulp of 7e6 m = ~1e-8 m.
    assert!((rel.position_m - exact).norm() < 1e-8);
    // HCW is first order: it misses the radial a du^2/2 = 0.035 m (and a du^3/6 along-track).
    assert!((rel.position_m - hcw).norm() < 0.5 * a * du * du * 1.001);
    // Velocity: rounding of the 7.5 km/s velocities, a few ulp = ~1e-11 m/s.
    assert!(rel.velocity_mps.norm() < 1e-11, "{}", rel.velocity_mps);
}

#[test]
fn val_radial_offset_circular_orbit_drifts_as_hcw_predicts() {
    // HCW: a satellite on a circular orbit dr above the reference keeps x = dr only with
    // y_dot = -3/2 n dr. Exactly, y_dot = sqrt(mu/(r+dr)) - sqrt(mu/r) - n dr
    // = n r (-3/2 eps + 3/8 eps^2 - 5/16 eps^3 + ...), eps = dr/r. Checked to second order, so the
    // residual is the third-order term.
    let (r, dr, i, raan, u) = (6_978_137.0, 1000.0, 51.7 * DEG, 0.4, 1.3);
    let reference = elements(r, 0.0, i, raan, 0.0, u).to_cartesian(MU).unwrap();
    let satellite = elements(r + dr, 0.0, i, raan, 0.0, u)
        .to_cartesian(MU)
        .unwrap();
    let frame = LvlhFrame::from_reference(&reference);
    let rel = frame.to_hill(&satellite);
    let n = EARTH.mean_motion_rad_s(r);
    let eps = dr / r;
    let hcw_y_dot = -1.5 * n * dr;
    let second_order = n * r * (-1.5 * eps + 0.375 * eps * eps);
    let third_order_bound = n * r * 0.3125 * eps.powi(3) * 1.1;
    println!(
        "radial offset {dr} m: y_dot {} m/s, HCW {hcw_y_dot} m/s, difference {:e} m/s",
        rel.velocity_mps.y,
        rel.velocity_mps.y - hcw_y_dot
    );
    // Position: rounding of 7e6 m vectors, ~1e-8 m.
    assert!((rel.position_m - Vector3::new(dr, 0.0, 0.0)).norm() < 1e-8);
    // Radial and cross-track velocity: rounding of the 7.5 km/s velocities.
    assert!(rel.velocity_mps.x.abs() < 1e-11 && rel.velocity_mps.z.abs() < 1e-11);
    // HCW agreement to its first-order accuracy (the 3/8 eps^2 term, 5.8e-5 m/s here, +10 %).
    assert!((rel.velocity_mps.y - hcw_y_dot).abs() < n * r * 0.375 * eps * eps * 1.1);
    // And the exact expansion to third order (6.9e-9 m/s here, +10 %, rounding is ~1e-12 m/s).
    assert!((rel.velocity_mps.y - second_order).abs() < third_order_bound);
}

/// One classical RK4 step of the J2 dynamics (test-local, independent of the crate's integrators).
fn rk4_j2(state: &CartesianState, dt: f64) -> CartesianState {
    let f = |s: &CartesianState| {
        (
            s.velocity_mps,
            GravityModel::J2.acceleration_m_s2(&EARTH, &s.position_m),
        )
    };
    let shift = |s: &CartesianState, k: &(Vector3<f64>, Vector3<f64>), h: f64| {
        CartesianState::new(s.position_m + h * k.0, s.velocity_mps + h * k.1)
    };
    let k1 = f(state);
    let k2 = f(&shift(state, &k1, dt / 2.0));
    let k3 = f(&shift(state, &k2, dt / 2.0));
    let k4 = f(&shift(state, &k3, dt));
    CartesianState::new(
        state.position_m + dt / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0),
        state.velocity_mps + dt / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1),
    )
}

#[test]
fn val_frame_rate_matches_numerical_derivative_under_j2() {
    // Under J2 the orbit plane turns about the radius vector; the Hill axes e_k obey
    // de_k/dt = omega x e_k, so (dR/dt) R^T = [[0, w_z, -w_y], [-w_z, 0, w_x], [w_y, -w_x, 0]] in Hill
    // components. dR/dt is taken by central differences of the frames at t +- dt, the states there
    // from one RK4 step of the J2 dynamics.
    let reference = elements(6_978_137.0, 0.01, 51.7 * DEG, 0.4, 1.0, 0.8)
        .to_cartesian(MU)
        .unwrap();
    let dt = 1.0;
    let rot = |s: &CartesianState| LvlhFrame::from_reference(s).rotation_eci_to_hill();
    let r_dot = (rot(&rk4_j2(&reference, dt)) - rot(&rk4_j2(&reference, -dt))) / (2.0 * dt);
    let skew = r_dot * rot(&reference).transpose();
    let numeric = Vector3::new(skew[(1, 2)], skew[(2, 0)], skew[(0, 1)]);

    let accel = GravityModel::J2.acceleration_m_s2(&EARTH, &reference.position_m);
    let exact = LvlhFrame::from_reference_with_acceleration(&reference, &accel);
    let keplerian = LvlhFrame::from_reference(&reference);
    let exact_hill = exact.vector_eci_to_hill(&exact.angular_velocity_eci_rad_s());
    let kepler_hill = keplerian.vector_eci_to_hill(&keplerian.angular_velocity_eci_rad_s());
    let err_exact = (exact_hill - numeric).norm();
    let err_kepler = (kepler_hill - numeric).norm();
    println!(
        "frame rate: numeric {numeric:?}, exact {exact_hill:?} (err {err_exact:e}), keplerian err {err_kepler:e} rad/s"
    );
    // Central difference truncation ~ |omega|^3 dt^2 / 6 ~ 2e-10 rad/s; RK4 error over 1 s ~ 1e-10 m,
    // i.e. ~1e-17 rad in the axes; differencing rounding ~ eps / dt ~ 2e-16 rad/s. 1e-9 rad/s is
    // three orders below the J2 radial rate (~1.4e-6 rad/s) the Keplerian frame misses.
    assert!(err_exact < 1e-9, "{err_exact:e}");
    // The radial component alone (the J2 term under test): its truncation error is
    // ~|w_x| |omega|^2 dt^2 ~ 2e-12 rad/s, so 1e-11 rad/s is a 1e-5 relative check of (r/h)(a.h_hat).
    let err_radial = (exact_hill.x - numeric.x).abs();
    assert!(err_radial < 1e-11, "{err_radial:e}");
    assert!(
        err_kepler > 1e-7,
        "the test must be able to see the radial rate: {err_kepler:e}"
    );
}
