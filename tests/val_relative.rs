//! Validation of `satflock::relative` (HCW and Schweighart–Sedwick) against independent references:
//! a fixed-step RK4 written here (not the crate's integrator), textbook HCW results (Vallado 4th ed.
//! §6.8, Curtis §7.5) and the statements and verified table of
//! `docs/methods/j2-distance.md` §1.3, §2.3 and §2.4 (the "method page" below).
//!
//! Relative errors of a state use the scaled norm `‖[r; v/n]‖` (velocities turned into lengths with
//! the mean motion), so that positions and velocities weigh alike.

use std::f64::consts::PI;

use nalgebra::{Matrix6, SMatrix, Vector3, Vector6};
use satflock::relative::{Hcw, SchweighartSedwick};

/// WGS-84 / EGM-96 gravitational parameter [m³/s²].
const MU: f64 = 3.986_004_418e14;
/// WGS-84 equatorial radius [m].
const RE: f64 = 6_378_137.0;
/// Second zonal harmonic [-] (the value our earlier derivation used for §1.3).
const J2: f64 = 1.082_63e-3;
/// Reference radius of a 600 km circular orbit [m].
const R600: f64 = RE + 600e3;
/// Mean motion at 600 km used by the HCW tests [rad/s] (√(μ/r³) = 1.0830778e-3, rounded).
const N600: f64 = 1.0831e-3;

/// Classic fixed-step RK4 over `steps` equal steps of length `h` [s], for an autonomous 6-state ODE.
fn rk4(
    f: impl Fn(&Vector6<f64>) -> Vector6<f64>,
    x0: &Vector6<f64>,
    h: f64,
    steps: usize,
) -> Vector6<f64> {
    let mut x = *x0;
    for _ in 0..steps {
        let k1 = f(&x);
        let k2 = f(&(x + 0.5 * h * k1));
        let k3 = f(&(x + 0.5 * h * k2));
        let k4 = f(&(x + h * k3));
        x += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
    x
}

/// `‖[r; v/n]‖` [m].
fn scaled_norm(v: &Vector6<f64>, n: f64) -> f64 {
    let mut s = *v;
    for k in 3..6 {
        s[k] /= n;
    }
    s.norm()
}

/// Relative error of `got` against `want`, in the scaled norm.
fn rel_err(got: &Vector6<f64>, want: &Vector6<f64>, n: f64) -> f64 {
    scaled_norm(&(got - want), n) / scaled_norm(want, n)
}

/// Initial states exercising every coupling: bounded ellipse, radial and along-track offsets,
/// pure cross-track, and a generic mixture [m, m/s].
fn test_states(n: f64) -> Vec<Vector6<f64>> {
    vec![
        Vector6::new(100.0, 0.0, 0.0, 0.0, -2.0 * n * 100.0, 0.0),
        Vector6::new(100.0, 0.0, 0.0, 0.0, 0.0, 0.0),
        Vector6::new(0.0, 200.0, 0.0, 0.0, 0.0, 0.0),
        Vector6::new(0.0, 0.0, 50.0, 0.0, 0.0, 0.05),
        Vector6::new(37.0, -120.0, 15.0, 0.021, -0.05, -0.013),
    ]
}

fn ss_600km_sso() -> SchweighartSedwick {
    SchweighartSedwick::new(R600, 98f64.to_radians(), MU, RE, J2)
}

// ---------------------------------------------------------------------------------------------
// HCW
// ---------------------------------------------------------------------------------------------

#[test]
fn val_hcw_stm_matches_rk4_over_one_orbit() {
    let hcw = Hcw::new(N600);
    let period = 2.0 * PI / N600;
    // 6000 steps of ~0.97 s: n·h ≈ 1.05e-3, so RK4's global error is of order (n h)⁴ · n T ≈ 1e-11
    // relative. 1e-9 (the brief's bar) leaves margin for that while any wrong coefficient in Φ
    // shows up as an O(1) error.
    let steps_per_segment = 600;
    let segments = 10;
    let h = period / (steps_per_segment * segments) as f64;
    let mut worst: f64 = 0.0;
    for x0 in test_states(N600) {
        let mut x_num = x0;
        for k in 1..=segments {
            x_num = rk4(
                |x| hcw.derivative(x, &Vector3::zeros()),
                &x_num,
                h,
                steps_per_segment,
            );
            let t = h * (k * steps_per_segment) as f64;
            let x_cf = hcw.propagate(&x0, t);
            let err = rel_err(&x_cf, &x_num, N600);
            assert!(
                err < 1e-9,
                "state {x0:?} at t = {t} s: relative error {err:e}"
            );
            worst = worst.max(err);
        }
    }
    println!("HCW closed form vs RK4, worst relative error over one orbit: {worst:e}");
}

/// Φ scaled to be dimensionless: D Φ D⁻¹ with D = diag(1, 1, 1, 1/n, 1/n, 1/n).
fn dimensionless(phi: &Matrix6<f64>, n: f64) -> Matrix6<f64> {
    let d = Matrix6::from_diagonal(&Vector6::new(1.0, 1.0, 1.0, 1.0 / n, 1.0 / n, 1.0 / n));
    let d_inv = Matrix6::from_diagonal(&Vector6::new(1.0, 1.0, 1.0, n, n, n));
    d * phi * d_inv
}

#[test]
fn val_hcw_stm_identity_and_semigroup() {
    let hcw = Hcw::new(N600);
    assert_eq!(hcw.state_transition_matrix(0.0), Matrix6::identity());
    assert_eq!(hcw.control_input_matrix(0.0), SMatrix::<f64, 6, 3>::zeros());
    let times = [
        (1234.5, 4321.0),
        (5801.0, 5801.0),
        (-700.0, 3000.0),
        (3.0e4, -1.0e4),
    ];
    for (t1, t2) in times {
        let lhs = dimensionless(&hcw.state_transition_matrix(t1 + t2), N600);
        let rhs = dimensionless(
            &(hcw.state_transition_matrix(t2) * hcw.state_transition_matrix(t1)),
            N600,
        );
        // Entries are O(1) plus secular terms O(n t) ≤ ~200 here; each product entry sums six
        // terms, so rounding is ~1e-14 of the largest entry. 1e-12 is rounding, not modelling.
        let scale = lhs.amax().max(1.0);
        let err = (lhs - rhs).amax() / scale;
        assert!(err < 1e-12, "Φ({t1}+{t2}) ≠ Φ({t2})Φ({t1}): {err:e}");
    }
}

#[test]
fn val_hcw_no_drift_ellipse_is_periodic() {
    let hcw = Hcw::new(N600);
    let x0 = 100.0;
    let vy0 = hcw.no_drift_velocity_y_mps(x0);
    assert_eq!(vy0, -2.0 * N600 * x0);
    let state = Vector6::new(x0, 50.0, 20.0, 0.03, vy0, 0.01);
    assert_eq!(hcw.along_track_drift_mps(&state), 0.0);
    let period = 2.0 * PI / N600;
    for orbits in [1.0, 10.0] {
        let back = hcw.propagate(&state, orbits * period);
        // The closed form is exactly periodic; what remains is rounding of sin/cos at θ = 2πk
        // (~1e-15 · θ). 1e-12 is a rounding bound.
        let err = rel_err(&back, &state, N600);
        assert!(err < 1e-12, "{orbits} orbits: {err:e}");
    }
    // Independent check by RK4 over one orbit (6000 steps, same error budget as above).
    let back = rk4(
        |x| hcw.derivative(x, &Vector3::zeros()),
        &state,
        period / 6000.0,
        6000,
    );
    let err = rel_err(&back, &state, N600);
    assert!(err < 1e-9, "RK4: {err:e}");
}

#[test]
fn val_hcw_radial_offset_drift_textbook() {
    // Textbook (Vallado §6.8, Curtis Eq. 7.53 with vx0 = vy0 = 0): y(t) = y0 + 6 x0 (sin nt − nt),
    // x(t) = x0 (4 − 3 cos nt). Zero relative velocity at radial offset x0 therefore drifts at
    // −6 n x0 on average, i.e. y loses 12π x0 per orbit. The often-quoted −(3/2) n x0 is the rate
    // of a *co-circular* orbit at offset x0, which needs vy0 = −(3/2) n x0 (x then stays at x0).
    let hcw = Hcw::new(N600);
    let period = 2.0 * PI / N600;
    let x0 = 100.0;
    let at_rest = Vector6::new(x0, 0.0, 0.0, 0.0, 0.0, 0.0);
    // Rounding of a 0.65 m/s value: a few ulp.
    let rate = hcw.along_track_drift_mps(&at_rest);
    assert!((rate + 6.0 * N600 * x0).abs() < 4.0 * f64::EPSILON * rate.abs());
    let after = hcw.propagate(&at_rest, period);
    // Rounding bound: |y| ≈ 3770 m, relative rounding ~1e-15 of it.
    assert!(
        (after[1] + 12.0 * PI * x0).abs() < 1e-10,
        "y(T) = {}",
        after[1]
    );
    assert!((after[0] - x0).abs() < 1e-10, "x(T) = {}", after[0]);
    let t = 1000.0;
    let mid = hcw.propagate(&at_rest, t);
    let nt = N600 * t;
    // Same textbook formulas at an arbitrary time; rounding bound again.
    assert!((mid[0] - x0 * (4.0 - 3.0 * nt.cos())).abs() < 1e-11);
    assert!((mid[1] - 6.0 * x0 * (nt.sin() - nt)).abs() < 1e-11);
    // RK4 (independent of the closed form): same drift over one orbit to the RK4 budget.
    let num = rk4(
        |x| hcw.derivative(x, &Vector3::zeros()),
        &at_rest,
        period / 6000.0,
        6000,
    );
    assert!(
        (num[1] + 12.0 * PI * x0).abs() / (12.0 * PI * x0) < 1e-9,
        "RK4 y(T) = {}",
        num[1]
    );

    let co_circular = Vector6::new(x0, 0.0, 0.0, 0.0, -1.5 * N600 * x0, 0.0);
    // Rounding of a 0.16 m/s value: a few ulp.
    let rate = hcw.along_track_drift_mps(&co_circular);
    assert!((rate + 1.5 * N600 * x0).abs() < 4.0 * f64::EPSILON * rate.abs());
    for t in [500.0, 2000.0, period, 3.3 * period] {
        let s = hcw.propagate(&co_circular, t);
        // Rounding bounds on O(100 m) and O(3000 m) quantities.
        assert!((s[0] - x0).abs() < 1e-11, "x({t}) = {}", s[0]);
        assert!(
            (s[1] + 1.5 * N600 * x0 * t).abs() < 1e-10,
            "y({t}) = {}",
            s[1]
        );
    }
}

#[test]
fn val_hcw_control_input_matrix_matches_rk4() {
    let hcw = Hcw::new(N600);
    let controls = [
        Vector3::new(1e-5, 0.0, 0.0),
        Vector3::new(0.0, -2e-5, 0.0),
        Vector3::new(0.0, 0.0, 3e-6),
        Vector3::new(4e-6, -1e-5, 2e-6),
    ];
    let mut worst: f64 = 0.0;
    for (dt, steps) in [(600.0, 600), (2.0 * PI / N600, 6000)] {
        let (phi, gamma) = (
            hcw.state_transition_matrix(dt),
            hcw.control_input_matrix(dt),
        );
        for x0 in test_states(N600) {
            for u in &controls {
                let num = rk4(|x| hcw.derivative(x, u), &x0, dt / steps as f64, steps);
                let cf = phi * x0 + gamma * u;
                // RK4 with n h ≈ 1e-3: error ~1e-11 relative (see the STM test); 1e-9 is that
                // budget with margin. A wrong Γ entry is off by O(1).
                let err = rel_err(&cf, &num, N600);
                assert!(err < 1e-9, "dt {dt}, x0 {x0:?}, u {u:?}: {err:e}");
                worst = worst.max(err);
            }
        }
    }
    println!("HCW ZOH response vs RK4, worst relative error: {worst:e}");
}

#[test]
fn val_hcw_small_mean_motion_tends_to_double_integrator() {
    let t = 100.0;
    let mut double_integrator = SMatrix::<f64, 6, 3>::zeros();
    for k in 0..3 {
        double_integrator[(k, k)] = 0.5 * t * t;
        double_integrator[(k + 3, k)] = t;
    }
    // n = 0 exactly: the well-conditioned kernels give the double integrator and free flight.
    let still = Hcw::new(0.0);
    assert_eq!(still.control_input_matrix(t), double_integrator);
    let mut free_flight = Matrix6::identity();
    for k in 0..3 {
        free_flight[(k, k + 3)] = t;
    }
    assert_eq!(still.state_transition_matrix(t), free_flight);
    // Small n: the leading deviation is the Coriolis coupling 2(θ − S)/n² ≈ n t³/3 on position and
    // 2(1 − C)/n ≈ n t² on velocity (series of the Γ entries). Bound by 0.5 n t³ and 1.5 n t².
    for n in [1e-4, 1e-6, 1e-8, 1e-10, 1e-14] {
        let dev = Hcw::new(n).control_input_matrix(t) - double_integrator;
        let pos = dev.fixed_rows::<3>(0).amax();
        let vel = dev.fixed_rows::<3>(3).amax();
        assert!(
            pos <= 0.5 * n * t.powi(3),
            "n = {n}: position deviation {pos:e}"
        );
        assert!(
            vel <= 1.5 * n * t * t,
            "n = {n}: velocity deviation {vel:e}"
        );
        // ...and it is indeed that Coriolis term (not cancellation noise): within 1e-3 relative,
        // the size of the next series term θ²/10 at θ = 1e-2.
        let coupling = dev[(0, 1)];
        assert!(
            (coupling / (n * t.powi(3) / 3.0) - 1.0).abs() < 1e-3,
            "n = {n}: {coupling:e}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Schweighart–Sedwick
// ---------------------------------------------------------------------------------------------

#[test]
fn val_ss_constants_600km_sso_by_hand() {
    // Hand computation, r = 6 978 137 m, i = 98°, μ = 3.986004418e14, R = 6 378 137 m,
    // J2 = 1.08263e-3:
    //   r³ = 3.397962e20 m³;  μ/r³ = 1.173058e-6 s⁻²;  n = √ = 1.083078e-3 rad/s (T = 5801.2 s)
    //   (R/r)² = 0.8354274;  cos 196° = −0.9612617;  1 + 3 cos 2i = −1.8837851
    //   s = (3 J2 / 8)(R/r)²(1 + 3 cos 2i) = 4.059863e-4 × 0.8354274 × (−1.8837851) = −6.389272e-4
    //   c₊ = √(1 + s) ≈ 1 + s/2 − s²/8 = 0.9996805;   c₋ = √(1 − s) ≈ 1.0003194
    //   ω_z = n (c₊ + (3/2) J2 (R/r)² cos² i) = n (0.9996805 + 2.627790e-5) = 1.082760e-3 rad/s
    let ss = ss_600km_sso();
    // Tolerances: half a unit in the last hand-carried digit.
    assert!((ss.mean_motion_rad_s() - 1.083078e-3).abs() < 0.5e-9);
    assert!((ss.s_j2() - -6.389272e-4).abs() < 0.5e-10);
    assert!((ss.c_plus() - 0.9996805).abs() < 0.5e-7);
    assert!((ss.c_minus() - 1.0003194).abs() < 0.5e-7);
    assert!((ss.omega_z_rad_s() - 1.082760e-3).abs() < 0.5e-9);
    assert!((2.0 * PI / ss.mean_motion_rad_s() - 5801.2).abs() < 0.05);
}

#[test]
fn val_ss_constants_reproduce_spec_table() {
    // Method page §1.3 table ([verified] there): r = 6871 km, i = 51.7°, μ = 3.986e14 and
    // k_J2 = 2.633e25 m⁵/s², i.e. J2 R² = k_J2 / (1.5 μ).
    let mu = 3.986e14;
    let j2 = 2.633e25 / (1.5 * mu * RE * RE);
    let ss = SchweighartSedwick::new(6_871e3, 51.7f64.to_radians(), mu, RE, j2);
    // Each value to half a unit in the table's last printed digit.
    let checks = [
        ("k_J2", ss.k_j2_m5_s2(), 2.633e25, 0.5e21),
        ("s_J2", ss.s_j2(), 1.066022e-4, 0.5e-10),
        ("c+", ss.c_plus(), 1.0000533, 0.5e-7),
        ("c-", ss.c_minus(), 0.9999467, 0.5e-7),
        ("omega_o", ss.mean_motion_rad_s(), 1.1085077e-3, 0.5e-10),
        ("omega_xy", ss.omega_xy_rad_s(), 1.1084486e-3, 0.5e-10),
        ("omega_z", ss.omega_z_rad_s(), 1.1091626e-3, 0.5e-10),
        ("epsilon_2", ss.epsilon_2_rad_s(), 3.3259368e-3, 0.5e-10),
        ("k0", ss.k0_s(), 1804.516, 0.5e-3),
        ("k1", ss.k1(), 0.7500533, 0.5e-7),
        (
            "T_orb [min]",
            2.0 * PI / ss.mean_motion_rad_s() / 60.0,
            94.47,
            0.005,
        ),
    ];
    for (name, got, want, tol) in checks {
        assert!((got - want).abs() < tol, "{name}: {got} vs table {want}");
    }
    // Identity 3 + 5s = 4c₊² − c₋² (rounding of squares of O(1) numbers).
    let (cp, cm) = (ss.c_plus(), ss.c_minus());
    assert!((3.0 + 5.0 * ss.s_j2() - (4.0 * cp * cp - cm * cm)).abs() < 1e-15);
    // Same product in the crate: equal to rounding (one ulp of 1.1e-3 is 2e-19).
    assert!((ss.omega_ref_rad_s() - cp * ss.mean_motion_rad_s()).abs() < 1e-18);
}

#[test]
fn val_ss_without_j2_is_hcw() {
    let ss = SchweighartSedwick::new(R600, 98f64.to_radians(), MU, RE, 0.0);
    let n = (MU / (R600 * R600 * R600)).sqrt();
    let hcw = Hcw::new(n);
    assert_eq!(ss.s_j2(), 0.0);
    assert_eq!(ss.c_plus(), 1.0);
    assert_eq!(ss.c_minus(), 1.0);
    assert_eq!(ss.mean_motion_rad_s(), n);
    assert_eq!(ss.omega_z_rad_s(), n);
    // Method page §1.3: ε₂ → 3 ω_o and k₁ → 3/4 in the Clohessy–Wiltshire limit.
    // A few ulp of 3.2e-3 (one ulp is 4.3e-19).
    assert!((ss.epsilon_2_rad_s() - 3.0 * n).abs() < 2e-18);
    assert_eq!(ss.k1(), 0.75);
    let u = Vector3::new(1e-5, -2e-5, 3e-6);
    for x0 in test_states(n) {
        // Same arithmetic with c₊ = 1 and s = 0: equal to the last ulp or two.
        let (a, b) = (ss.derivative(&x0, &u), hcw.derivative(&x0, &u));
        assert!(
            (a - b).amax() <= 4.0 * f64::EPSILON * b.amax(),
            "{a:?} vs {b:?}"
        );
        for t in [100.0, 2500.0, 2.0 * PI / n, 10.0 * 2.0 * PI / n] {
            // Two independently written closed forms (textbook HCW vs general SS); they differ by
            // rounding only, growing with the secular terms O(n t) ≤ 63 here. 1e-12 is rounding.
            let err = rel_err(&ss.propagate(&x0, t), &hcw.propagate(&x0, t), n);
            assert!(err < 1e-12, "propagate, t = {t}: {err:e}");
            let g = (ss.control_input_matrix(t) - hcw.control_input_matrix(t)).amax();
            let scale = hcw.control_input_matrix(t).amax();
            assert!(g / scale < 1e-12, "Γ, t = {t}: {:e}", g / scale);
        }
        assert_eq!(
            ss.along_track_drift_mps(&x0),
            hcw.along_track_drift_mps(&x0)
        );
    }
    assert_eq!(
        ss.no_drift_velocity_y_mps(42.0),
        hcw.no_drift_velocity_y_mps(42.0)
    );
}

#[test]
fn val_ss_closed_form_matches_rk4() {
    let mu = 3.986e14;
    let spec_orbit = SchweighartSedwick::new(
        6_871e3,
        51.7f64.to_radians(),
        mu,
        RE,
        2.633e25 / (1.5 * mu * RE * RE),
    );
    let u = Vector3::new(4e-6, -1e-5, 2e-6);
    let mut worst: f64 = 0.0;
    for ss in [ss_600km_sso(), spec_orbit] {
        let n = ss.mean_motion_rad_s();
        let period = 2.0 * PI / n;
        assert_eq!(ss.state_transition_matrix(0.0), Matrix6::identity());
        for x0 in test_states(n) {
            // Free motion over one orbit and a ZOH step of 600 s, RK4 at n h ≈ 1e-3 as in the HCW
            // test: error ~1e-11 relative, so 1e-9 is that budget with margin.
            let num = rk4(
                |x| ss.derivative(x, &Vector3::zeros()),
                &x0,
                period / 6000.0,
                6000,
            );
            let err = rel_err(&ss.propagate(&x0, period), &num, n);
            assert!(err < 1e-9, "free, {x0:?}: {err:e}");
            worst = worst.max(err);
            let num = rk4(|x| ss.derivative(x, &u), &x0, 1.0, 600);
            let cf = ss.state_transition_matrix(600.0) * x0 + ss.control_input_matrix(600.0) * u;
            let err = rel_err(&cf, &num, n);
            assert!(err < 1e-9, "ZOH, {x0:?}: {err:e}");
            worst = worst.max(err);
        }
        // Semigroup property, dimensionless as in the HCW test (rounding bound 1e-12).
        let lhs = dimensionless(&ss.state_transition_matrix(7000.0), n);
        let rhs = dimensionless(
            &(ss.state_transition_matrix(3000.0) * ss.state_transition_matrix(4000.0)),
            n,
        );
        assert!((lhs - rhs).amax() / lhs.amax() < 1e-12);
    }
    println!("SS closed form vs RK4, worst relative error: {worst:e}");
}

/// Method page §1.3 constants computed here from the table's formulas, independently of the crate.
struct SpecConstants {
    n: f64,
    s: f64,
    cp: f64,
    cm: f64,
    wxy: f64,
    wz: f64,
    eps2: f64,
}

fn spec_constants(r: f64, i: f64) -> SpecConstants {
    let k_j2 = 1.5 * J2 * MU * RE * RE;
    let s = k_j2 * (1.0 + 3.0 * (2.0 * i).cos()) / (4.0 * MU * r * r);
    let (cp, cm) = ((1.0 + s).sqrt(), (1.0 - s).sqrt());
    let n = (MU / r.powi(3)).sqrt();
    let wxy = cm * n;
    SpecConstants {
        n,
        s,
        cp,
        cm,
        wxy,
        wz: n * (cp + k_j2 * i.cos().powi(2) / (MU * r * r)),
        eps2: (4.0 * cp * cp - cm * cm) / (cp * cm) * wxy,
    }
}

/// Paper Eq. 4 in the scaled coordinates [x̄, ȳ, z, x̄', ȳ', z'] exactly as printed in §2.3
/// (l_z = 0, no disturbance), with control acceleration `u` in {O}.
fn spec_eq4(k: &SpecConstants, q: &Vector6<f64>, u: &Vector3<f64>) -> Vector6<f64> {
    let (xb, z, dxb, dyb) = (q[0], q[2], q[3], q[4]);
    let w = k.wxy;
    let xbb = 2.0 * w * dyb
        + 3.0 * w * w * xb
        + 4.0 * w * w * k.s / (k.cm * k.cm) * (2.0 * xb + dyb / w)
        + k.cp * u.x;
    let ybb = -2.0 * w * dxb + k.cm * u.y;
    let zz = -k.wz * k.wz * z + u.z;
    Vector6::new(dxb, dyb, q[5], xbb, ybb, zz)
}

/// Physical → scaled: x̄ = c₊x, ȳ = c₋y (method page §1.1).
fn to_scaled(k: &SpecConstants, x: &Vector6<f64>) -> Vector6<f64> {
    Vector6::new(
        k.cp * x[0],
        k.cm * x[1],
        x[2],
        k.cp * x[3],
        k.cm * x[4],
        x[5],
    )
}

fn from_scaled(k: &SpecConstants, q: &Vector6<f64>) -> Vector6<f64> {
    Vector6::new(
        q[0] / k.cp,
        q[1] / k.cm,
        q[2],
        q[3] / k.cp,
        q[4] / k.cm,
        q[5],
    )
}

/// Method page §3.1: (C₁, C₂, C₃, C₄, C₅, C₆) from a physical Hill state.
fn spec_c_params(k: &SpecConstants, x: &Vector6<f64>) -> [f64; 6] {
    let q = to_scaled(k, x);
    let c1 = k.cp / (k.cm * k.cm) * (2.0 * q[0] + q[4] / k.wxy);
    let c4 = (q[1] - 2.0 * q[3] / k.wxy) / k.cm;
    let c2 = q[3] / k.wxy;
    let c3 = q[0] - 2.0 * k.cp * c1;
    [c1, c2, c3, c4, x[5] / k.wz, x[2]]
}

/// Method page §2.4 (Eq. 5) position at time t from the C-parameters (l_z = 0).
fn spec_eq5_position(k: &SpecConstants, c: &[f64; 6], t: f64) -> Vector3<f64> {
    let (rxy, thxy) = (c[1].hypot(c[2]), c[2].atan2(c[1]));
    let (rz, thz) = (c[4].hypot(c[5]), c[5].atan2(c[4]));
    Vector3::new(
        2.0 * c[0] + rxy / k.cp * (k.wxy * t + thxy).sin(),
        c[3] - k.eps2 * c[0] * t + 2.0 / k.cm * rxy * (k.wxy * t + thxy).cos(),
        rz * (k.wz * t + thz).sin(),
    )
}

#[test]
fn val_ss_spec_eq4_eq5_and_physical_form_agree() {
    let i = 98f64.to_radians();
    let k = spec_constants(R600, i);
    let ss = ss_600km_sso();
    // The crate's constants against the method page's formulas as coded here. The test writes ε₂ with
    // 4c₊² − c₋² instead of 3 + 5s, so allow ~20 ulp (one ulp of 3.2e-3 is 4.3e-19); ω_z and s
    // are the same expressions: a few ulp (ulp of 1.1e-3 is 2e-19, of 6.4e-4 is 1e-19).
    assert!((ss.epsilon_2_rad_s() - k.eps2).abs() < 1e-17);
    assert!((ss.omega_z_rad_s() - k.wz).abs() < 1e-18);
    assert!((ss.s_j2() - k.s).abs() < 1e-18);
    let u = Vector3::new(1e-5, -2e-5, 3e-6);
    let period = 2.0 * PI / k.n;
    let mut worst_eq5: f64 = 0.0;
    for x0 in test_states(k.n) {
        // 1. Eq. 4 (scaled) and the crate's physical form are the same ODE: compare derivatives
        //    after mapping back. Rounding of O(1e-2) accelerations: 1e-13 relative.
        let dq = spec_eq4(&k, &to_scaled(&k, &x0), &u);
        let dx = ss.derivative(&x0, &u);
        let err = rel_err(&from_scaled(&k, &dq), &dx, k.n);
        assert!(err < 1e-13, "Eq. 4 vs physical form at {x0:?}: {err:e}");

        // 2. Eq. 5 solves Eq. 4: integrate Eq. 4 (scaled, RK4 as before, 1e-9 budget) over ten
        //    orbits and compare the positions with Eq. 5 evaluated from the §3.1 C-parameters,
        //    and with the crate's closed form.
        let c = spec_c_params(&k, &x0);
        let mut q = to_scaled(&k, &x0);
        let steps = 6000;
        let h = period / steps as f64;
        for seg in 1..=10 {
            q = rk4(|q| spec_eq4(&k, q, &Vector3::zeros()), &q, h, steps);
            let t = h * (seg * steps) as f64;
            let num = from_scaled(&k, &q);
            let pos_num = num.fixed_rows::<3>(0).into_owned();
            let scale = scaled_norm(&num, k.n);
            let e5 = (spec_eq5_position(&k, &c, t) - pos_num).norm() / scale;
            assert!(e5 < 1e-9, "Eq. 5 vs Eq. 4 at t = {t}: {e5:e}");
            let ecf = rel_err(&ss.propagate(&x0, t), &num, k.n);
            assert!(ecf < 1e-9, "closed form vs Eq. 4 at t = {t}: {ecf:e}");
            worst_eq5 = worst_eq5.max(e5);
        }
        // 3. The drift rates agree: −ε₂C₁ (method page) and the crate's along_track_drift_mps. For the
        //    HCW-bounded state, C₁ ∝ 200 (c₊ − 1) ≈ −0.064 m is computed from terms of 200 m, so
        //    cancellation costs ~3.5 digits: 1e-11 relative is that rounding with margin.
        let drift = ss.along_track_drift_mps(&x0);
        let spec_drift = -k.eps2 * c[0];
        assert!(
            (drift - spec_drift).abs() <= 1e-11 * drift.abs(),
            "{drift:e} vs {spec_drift:e}"
        );
    }
    println!("paper Eq. 5 vs RK4 of Eq. 4, worst relative position error: {worst_eq5:e}");
}

#[test]
fn val_ss_no_drift_condition_bounded_and_hcw_condition_drifts() {
    let ss = ss_600km_sso();
    let k = spec_constants(R600, 98f64.to_radians());
    let x0 = 100.0;
    let t_xy = 2.0 * PI / ss.omega_xy_rad_s();
    let (steps_per_period, periods) = (6000, 10);
    let h = t_xy / steps_per_period as f64;
    let integrate = |s0: &Vector6<f64>| {
        // y at the end of every in-plane period, by RK4 of the SS derivative (not the closed form).
        let mut s = *s0;
        let mut ys = Vec::new();
        for _ in 0..periods {
            s = rk4(
                |x| ss.derivative(x, &Vector3::zeros()),
                &s,
                h,
                steps_per_period,
            );
            ys.push(s[1]);
        }
        ys
    };

    // SS condition: C₁ = 0 ⇒ bounded. y returns to y0 after each in-plane period.
    let vy_ss = ss.no_drift_velocity_y_mps(x0);
    let bounded = Vector6::new(x0, 30.0, 20.0, 0.02, vy_ss, -0.01);
    assert_eq!(ss.along_track_drift_mps(&bounded), 0.0);
    assert!(
        spec_c_params(&k, &bounded)[0].abs() < 1e-12,
        "C1 of the SS no-drift state"
    );
    let ys = integrate(&bounded);
    let worst = ys
        .iter()
        .map(|y| (y - bounded[1]).abs())
        .fold(0.0, f64::max);
    // RK4 error over 10 periods at n h ≈ 1e-3: at most ~1e-11 relative of the ~200 m state, i.e.
    // ~2e-9 m. A drift of 1e-12 m/s (8 orders below the HCW-condition drift measured below) would
    // already move y by 6e-8 m, so 1e-8 m separates "bounded" from "drifting".
    assert!(
        worst < 1e-8,
        "SS no-drift state moved {worst:e} m after whole periods"
    );
    println!("SS no-drift: max |y(k T_xy) − y0| over {periods} periods = {worst:e} m");

    // HCW condition vy = −2 n x under SS dynamics: drifts at −(3+5s)/(1−s) · 2 n x0 (c₊ − 1).
    let hcw_state = Vector6::new(
        x0,
        30.0,
        20.0,
        0.02,
        -2.0 * ss.mean_motion_rad_s() * x0,
        -0.01,
    );
    let analytic = -(3.0 + 5.0 * k.s) / (1.0 - k.s) * 2.0 * k.n * x0 * (k.cp - 1.0);
    let predicted = ss.along_track_drift_mps(&hcw_state);
    let spec_rate = -k.eps2 * spec_c_params(&k, &hcw_state)[0];
    // The hand formula and the crate's differ in rounding only; c₊ − 1 ≈ −3.2e-4 costs ~4 digits
    // to cancellation in the hand formula, hence 1e-11 relative.
    assert!(
        (predicted - analytic).abs() < 1e-11 * analytic.abs(),
        "{predicted:e} vs {analytic:e}"
    );
    assert!(
        (predicted - spec_rate).abs() < 1e-11 * analytic.abs(),
        "{predicted:e} vs {spec_rate:e}"
    );
    let ys = integrate(&hcw_state);
    let measured = (ys[periods - 1] - hcw_state[1]) / (periods as f64 * t_xy);
    // Measured by RK4 over 58 000 s: the y error (≤ ~2e-9 m, see above) over a ~12 m drift is
    // ≤ ~2e-10 relative, hence 1e-9.
    assert!(
        (measured - predicted).abs() < 1e-9 * predicted.abs(),
        "measured {measured:e} m/s vs predicted {predicted:e} m/s"
    );
    // Linear growth: the drift after k periods is k times the per-period drift.
    let first = ys[0] - hcw_state[1];
    for (kk, y) in ys.iter().enumerate() {
        let expected = first * (kk + 1) as f64;
        // Same RK4 budget as above, on drifts of 1.2 m to 12 m.
        assert!(((y - hcw_state[1]) - expected).abs() < 1e-9 * expected.abs());
    }
    println!(
        "HCW no-drift state under SS: measured drift {measured:e} m/s, predicted {predicted:e} m/s, \
         {:.3} m after {periods} periods",
        ys[periods - 1] - hcw_state[1]
    );
}
