//! `satflock validate core`: the core's physics against analytic references, at full length — J2
//! secular rates over 30 days, the sun-synchronous condition, integrator accuracy over a day, HCW against
//! the two-body truth, and the Schweighart–Sedwick drift against the J2 truth; then the force models
//! (rows F1–F9, `validate::forces`).

use nalgebra::{DMatrix, DVector, Vector3};

use crate::validate::{Check, Report, ValidateError, Verdict};
use std::sync::Arc;

use satflock::dynamics::{ForceSet, PhysicalProperties};
use satflock::integrate::{IntegratorMethod, Tolerances};
use satflock::orbit::{CartesianState, EarthModel, GravityModel, KeplerianElements, LvlhFrame};
use satflock::propagate::{propagate, PropagationSettings};
use satflock::relative::{Hcw, SchweighartSedwick};

const DAY_S: f64 = 86_400.0;

fn failed(e: impl std::fmt::Display) -> ValidateError {
    ValidateError::Failed {
        target: "core".into(),
        message: e.to_string(),
    }
}

fn settings(
    integrator: IntegratorMethod,
    step_s: f64,
    rtol: f64,
    duration_s: f64,
    output_step_s: f64,
) -> PropagationSettings {
    PropagationSettings {
        earth: EarthModel::WGS84_EGM96,
        forces: Arc::new(ForceSet::gravity(GravityModel::J2, EarthModel::WGS84_EGM96)),
        properties: PhysicalProperties::point_mass(1.0),
        integrator,
        step_s,
        tolerances: Tolerances {
            relative: rtol,
            absolute: 1e-9,
        },
        duration_s,
        output_step_s,
    }
}

fn orbit(a_m: f64, e: f64, i_deg: f64, u_deg: f64) -> Result<CartesianState, ValidateError> {
    KeplerianElements {
        semi_major_axis_m: a_m,
        eccentricity: e,
        inclination_rad: i_deg.to_radians(),
        raan_rad: 0.5,
        arg_perigee_rad: 0.0,
        true_anomaly_rad: u_deg.to_radians(),
    }
    .to_cartesian(EarthModel::WGS84_EGM96.mu_m3_s2)
    .map_err(failed)
}

/// Least-squares fit of `columns` (functions of t) to samples; returns the coefficients.
fn fit(
    times: &[f64],
    values: &[f64],
    columns: &[&dyn Fn(f64) -> f64],
) -> Result<DVector<f64>, ValidateError> {
    let a = DMatrix::from_fn(times.len(), columns.len(), |k, j| columns[j](times[k]));
    let b = DVector::from_column_slice(values);
    a.svd(true, true).solve(&b, 1e-14).map_err(failed)
}

/// Secular RAAN and perigee rates [rad/s] fitted to hourly osculating elements.
fn fitted_rates(
    initial: CartesianState,
    days: f64,
) -> Result<(f64, f64, KeplerianElements), ValidateError> {
    let mu = EarthModel::WGS84_EGM96.mu_m3_s2;
    let (mut t, mut raan, mut argp) = (Vec::new(), Vec::new(), Vec::new());
    let mut error = None;
    propagate(
        &[initial],
        &settings(IntegratorMethod::Dop853, 300.0, 1e-12, days * DAY_S, 3600.0),
        |time, s| match KeplerianElements::from_cartesian(&s[0], mu) {
            Ok(el) => {
                let unwrap = |series: &Vec<f64>, angle: f64| match series.last() {
                    Some(prev) => {
                        prev + (angle - prev + std::f64::consts::PI)
                            .rem_euclid(std::f64::consts::TAU)
                            - std::f64::consts::PI
                    }
                    None => angle,
                };
                let (r, w) = (
                    unwrap(&raan, el.raan_rad),
                    unwrap(&argp, el.arg_perigee_rad),
                );
                t.push(time);
                raan.push(r);
                argp.push(w);
            }
            Err(e) => error = Some(e),
        },
    )
    .map_err(failed)?;
    if let Some(e) = error {
        return Err(failed(e));
    }
    let one = |_t: f64| 1.0;
    let linear = |t: f64| t;
    let raan_rate = fit(&t, &raan, &[&one, &linear])?[1];
    let argp_rate = fit(&t, &argp, &[&one, &linear])?[1];
    let el0 = KeplerianElements::from_cartesian(&initial, mu).map_err(failed)?;
    Ok((raan_rate, argp_rate, el0))
}

fn verdict(ok: bool) -> Verdict {
    if ok {
        Verdict::Reproduced
    } else {
        Verdict::Differs
    }
}

fn j2_rates(checks: &mut Vec<Check>) -> Result<(), ValidateError> {
    let earth = EarthModel::WGS84_EGM96;
    let (raan, argp, el) = fitted_rates(orbit(7_200e3, 0.05, 50.0, 10.0)?, 30.0)?;
    // First-order secular rates (Vallado 4th ed., Eqs. 9-41 and 9-42).
    let p = el.semi_major_axis_m * (1.0 - el.eccentricity.powi(2));
    let k = earth.mean_motion_rad_s(el.semi_major_axis_m)
        * earth.j2
        * (earth.equatorial_radius_m / p).powi(2);
    let c = el.inclination_rad.cos();
    let (raan_ref, argp_ref) = (-1.5 * k * c, 0.75 * k * (5.0 * c * c - 1.0));
    let per_day = |r: f64| r.to_degrees() * DAY_S;
    for (id, what, ours, reference) in [
        ("C1", "RAAN", raan, raan_ref),
        ("C2", "argument of perigee", argp, argp_ref),
    ] {
        let rel = (ours - reference).abs() / reference.abs();
        checks.push(Check {
            criterion: None,
            id: id.into(),
            outcome: format!(
                "{what} secular rate, a = 7200 km, e = 0.05, i = 50°, 30 days, J2 (tolerance 1 %)"
            ),
            paper: format!("{:.5} °/day (first-order analytic)", per_day(reference)),
            ours: format!("{:.5} °/day ({:.2} %)", per_day(ours), 100.0 * rel),
            verdict: verdict(rel < 0.01),
        });
    }
    let (sso, _, _) = fitted_rates(orbit(6_978_137.0, 0.0, 97.8, 0.0)?, 30.0)?;
    let sso_day = per_day(sso);
    checks.push(Check {
        criterion: None,
        id: "C3".into(),
        outcome: "sun-synchronous node rate, 600 km, i = 97.8° (tolerance 1 %)".into(),
        paper: "0.9856 °/day (360° per tropical year)".into(),
        ours: format!("{sso_day:.5} °/day"),
        verdict: verdict((sso_day - 0.9856).abs() < 0.01 * 0.9856),
    });
    Ok(())
}

fn integrators(checks: &mut Vec<Check>, notes: &mut Vec<String>) -> Result<(), ValidateError> {
    let initial = orbit(6_978_137.0, 0.0002, 98.0, 10.0)?;
    let final_position = |method, step, rtol| -> Result<Vector3<f64>, ValidateError> {
        let mut last = None;
        propagate(
            &[initial],
            &settings(method, step, rtol, DAY_S, DAY_S),
            |_, s| last = Some(s[0].position_m),
        )
        .map_err(failed)?;
        last.ok_or_else(|| failed("no output"))
    };
    let reference = final_position(IntegratorMethod::Dop853, 60.0, 1e-15)?;
    let rk4 = (final_position(IntegratorMethod::Rk4, 1.0, 1e-12)? - reference).norm();
    let rk78 = (final_position(IntegratorMethod::Rk78, 600.0, 1e-12)? - reference).norm();
    let rk78_tight = (final_position(IntegratorMethod::Rk78, 600.0, 1e-13)? - reference).norm();
    checks.push(Check {
        criterion: None,
        id: "C4".into(),
        outcome: "RK4 at 1 s, 600 km / e 0.0002 / i 98°, J2, one day, vs DOP853 at rtol 1e-15 (tolerance 1e-4 m)".into(),
        paper: "< 1e-4 m (RK4 truncation ~ (n h)^4 n t r)".into(),
        ours: format!("{rk4:.2e} m"),
        verdict: verdict(rk4 < 1e-4),
    });
    checks.push(Check {
        criterion: None,
        id: "C5".into(),
        outcome: "RKF7(8) at rtol 1e-12 vs the same reference (our original target: agreement with RK4 < 1e-3 m)".into(),
        paper: "< 1e-3 m".into(),
        ours: format!("{rk78:.2e} m (rtol 1e-13: {rk78_tight:.2e} m)"),
        verdict: verdict(rk78 < 1e-3),
    });
    notes.push(format!(
        "C5: RKF7(8) controls the local error of its 7th-order solution to rtol·|y_i| per component and \
         propagates the 8th-order one; its global error is proportional to rtol ({rk78:.2e} m at 1e-12, \
         {rk78_tight:.2e} m at 1e-13), because velocity errors become along-track drift over 15 orbits. \
         The 1 mm agreement we first expected holds from rtol 1e-13."
    ));
    Ok(())
}

/// Relative state of `deputy` in the Hill frame of `chief` as a position vector [m].
fn hill_position(deputy: &CartesianState, chief: &CartesianState) -> Vector3<f64> {
    LvlhFrame::from_reference(chief).to_hill(deputy).position_m
}

fn relative_motion(checks: &mut Vec<Check>, notes: &mut Vec<String>) -> Result<(), ValidateError> {
    let earth = EarthModel::WGS84_EGM96;
    let a = 6_978_137.0;
    let n = earth.mean_motion_rad_s(a);
    let period = earth.period_s(a);
    let hcw = Hcw::new(n);

    // C6: HCW vs two-body truth, 100 m, one orbit.
    let chief = orbit(a, 0.0, 98.0, 20.0)?;
    let rel0 = satflock::orbit::RelativeStateHill {
        position_m: Vector3::new(60.0, 50.0, 60.0),
        velocity_mps: Vector3::new(0.01, hcw.no_drift_velocity_y_mps(60.0), 0.02),
    };
    let deputy = LvlhFrame::from_reference(&chief).from_hill(&rel0);
    let x0 = nalgebra::Vector6::new(
        60.0,
        50.0,
        60.0,
        0.01,
        hcw.no_drift_velocity_y_mps(60.0),
        0.02,
    );
    let mut two_body = settings(
        IntegratorMethod::Dop853,
        300.0,
        1e-13,
        period,
        period / 50.0,
    );
    two_body.forces = Arc::new(ForceSet::gravity(
        GravityModel::TwoBody,
        EarthModel::WGS84_EGM96,
    ));
    let mut worst: f64 = 0.0;
    propagate(&[deputy, chief], &two_body, |t, s| {
        let p = hcw.propagate(&x0, t);
        worst = worst.max((hill_position(&s[0], &s[1]) - Vector3::new(p[0], p[1], p[2])).norm());
    })
    .map_err(failed)?;
    let rho = rel0.position_m.norm();
    let bound = 1.5 * n * n * rho * rho * period * period / a;
    checks.push(Check {
        criterion: None,
        id: "C6".into(),
        outcome: "two-body truth vs HCW closed form, ρ = 100 m, one orbit".into(),
        paper: format!("≤ (3/2) n² ρ² T² / r = {bound:.3} m (second-order term)"),
        ours: format!("{worst:.3e} m"),
        verdict: verdict(worst < bound),
    });

    // C7/C8: the HCW 2:1 ellipse on the J2 truth drifts at rate A + B cos 2u0.
    let inc = 97.8f64.to_radians();
    let ss = SchweighartSedwick::new(a, inc, earth.mu_m3_s2, earth.equatorial_radius_m, earth.j2);
    let x_off = 100.0;
    let state = nalgebra::Vector6::new(
        x_off,
        0.0,
        0.0,
        0.0,
        hcw.no_drift_velocity_y_mps(x_off),
        0.0,
    );
    let predicted = ss.along_track_drift_mps(&state);
    let omega = ss.omega_xy_rad_s();
    let mut rates = Vec::new();
    for u0 in [0.0, 90.0] {
        let chief = orbit(a, 0.0, 97.8, u0)?;
        let rel = satflock::orbit::RelativeStateHill {
            position_m: Vector3::new(x_off, 0.0, 0.0),
            velocity_mps: Vector3::new(0.0, state[4], 0.0),
        };
        let deputy = LvlhFrame::from_reference(&chief).from_hill(&rel);
        let (mut t, mut y) = (Vec::new(), Vec::new());
        propagate(
            &[deputy, chief],
            &settings(IntegratorMethod::Dop853, 300.0, 1e-13, 20.0 * period, 20.0),
            |time, s| {
                t.push(time);
                y.push(hill_position(&s[0], &s[1]).y);
            },
        )
        .map_err(failed)?;
        let one = |_t: f64| 1.0;
        let linear = |t: f64| t;
        let cosine = move |t: f64| (omega * t).cos();
        let sine = move |t: f64| (omega * t).sin();
        rates.push(fit(&t, &y, &[&one, &linear, &cosine, &sine])?[1]);
    }
    let average = 0.5 * (rates[0] + rates[1]);
    let amplitude = 0.5 * (rates[0] - rates[1]);
    let r_over_a = earth.equatorial_radius_m / a;
    let kozai = -6.75 * n * earth.j2 * r_over_a * r_over_a * inc.sin().powi(2) * x_off;
    let rel_avg = (average - predicted).abs() / predicted.abs();
    let rel_amp = (amplitude - kozai).abs() / kozai.abs();
    checks.push(Check {
        criterion: None,
        id: "C7".into(),
        outcome: "HCW 2:1 ellipse (x0 = 100 m) on the J2 truth, 20 orbits: along-track drift averaged over u0 = 0°, 90° vs Schweighart–Sedwick (tolerance 10 %)".into(),
        paper: format!("{predicted:.4e} m/s (SS secular rate)"),
        ours: format!("{average:.4e} m/s ({:.1} %)", 100.0 * rel_avg),
        verdict: verdict(rel_avg < 0.10),
    });
    checks.push(Check {
        criterion: None,
        id: "C8".into(),
        outcome: "same, cos 2u0 amplitude of the drift vs first-order Kozai short-period theory (tolerance 10 %)".into(),
        paper: format!("{kozai:.4e} m/s"),
        ours: format!("{amplitude:.4e} m/s ({:.1} %)", 100.0 * rel_amp),
        verdict: verdict(rel_amp < 0.10),
    });
    notes.push(format!(
        "C7–C8: the drift of an osculating HCW initial state on the J2 truth depends on where it starts \
         (u0 = 0°: {:.3e} m/s, u0 = 90°: {:.3e} m/s). A mean model such as Schweighart–Sedwick sees only the \
         orbit average; the cos 2u0 part is the difference of the J2 short-period semi-major-axis term \
         between the two radii.",
        rates[0], rates[1]
    ));
    Ok(())
}

/// Runs every core check (about a minute in release mode).
pub fn report() -> Result<Report, ValidateError> {
    let mut checks = Vec::new();
    let mut notes = Vec::new();
    j2_rates(&mut checks)?;
    integrators(&mut checks, &mut notes)?;
    relative_motion(&mut checks, &mut notes)?;
    crate::validate::forces::checks(&mut checks, &mut notes)?;
    Ok(Report {
        measured: None,
        title: "Core physics against analytic references".into(),
        reference_header: "reference".into(),
        checks,
        tables: Vec::new(),
        notes,
    })
}
