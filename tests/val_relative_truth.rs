//! Relative motion: the nonlinear inertial truth, differenced into the LVLH frame, against the linear
//! models (HCW, Schweighart–Sedwick) for small separations.

use nalgebra::{Vector3, Vector6};
use satflock::integrate::{IntegratorMethod, Tolerances};
use satflock::orbit::{
    CartesianState, EarthModel, GravityModel, KeplerianElements, LvlhFrame, RelativeStateHill,
};
use satflock::propagate::{propagate, PropagationSettings};
use satflock::relative::Hcw;

#[test]
fn val_two_body_truth_matches_hcw_for_100_m_separation_over_one_orbit() {
    let earth = EarthModel::WGS84_EGM96;
    let a = 6_978_137.0;
    let chief = KeplerianElements {
        semi_major_axis_m: a,
        eccentricity: 0.0,
        inclination_rad: 98f64.to_radians(),
        raan_rad: 0.3,
        arg_perigee_rad: 0.0,
        true_anomaly_rad: 0.2,
    }
    .to_cartesian(earth.mu_m3_s2)
    .unwrap();
    let n = earth.mean_motion_rad_s(a);
    let hcw = Hcw::new(n);
    // 100 m apart, on a bounded (no-drift) HCW orbit with out-of-plane motion.
    let rel0 = RelativeStateHill {
        position_m: Vector3::new(60.0, 50.0, 60.0),
        velocity_mps: Vector3::new(0.01, hcw.no_drift_velocity_y_mps(60.0), 0.02),
    };
    let deputy = LvlhFrame::from_reference(&chief).from_hill(&rel0);
    let period = earth.period_s(a);
    let settings = PropagationSettings {
        earth,
        forces: std::sync::Arc::new(satflock::dynamics::ForceSet::gravity(
            GravityModel::TwoBody,
            earth,
        )),
        properties: satflock::dynamics::PhysicalProperties::point_mass(1.0),
        integrator: IntegratorMethod::Rk78,
        step_s: 300.0,
        tolerances: Tolerances {
            relative: 1e-13,
            absolute: 1e-9,
        },
        duration_s: period,
        output_step_s: period / 20.0,
    };
    let x0 = Vector6::new(
        rel0.position_m.x,
        rel0.position_m.y,
        rel0.position_m.z,
        rel0.velocity_mps.x,
        rel0.velocity_mps.y,
        rel0.velocity_mps.z,
    );
    let rho = rel0.position_m.norm();
    let mut worst: f64 = 0.0;
    propagate(
        &[deputy, chief],
        &settings,
        |t, states: &[CartesianState]| {
            let rel = LvlhFrame::from_reference(&states[1]).to_hill(&states[0]);
            let predicted = hcw.propagate(&x0, t);
            let err =
                (rel.position_m - Vector3::new(predicted[0], predicted[1], predicted[2])).norm();
            worst = worst.max(err);
        },
    )
    .unwrap();
    // Linearisation error bound: the neglected second-order relative acceleration is at most
    // ~3 n² ρ²/r; integrated twice over one orbit T it displaces by ≤ (3/2) n² ρ² T² / r, which for
    // ρ = 98.5 m is 0.082 m (measured: 6.1e-3 m). The truth must be within that bound, and it must not be trivially zero (a
    // truth that copied HCW would prove nothing): the second-order effect is > 1 mm.
    let bound = 1.5 * n * n * rho * rho * period * period / a;
    assert!(worst < bound, "HCW vs truth {worst} m, bound {bound} m");
    assert!(worst > 1e-3, "suspiciously exact: {worst} m");
}
