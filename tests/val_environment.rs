//! Validation of `environment` (threats, obstacles, closest approach of Hermite segments, the approach
//! monitor) against independent references: the closed-form closest approach of two straight lines, the
//! Hill–Clohessy–Wiltshire closed-form trajectory (written out here, not taken from the crate) evaluated
//! densely, brute-force dense evaluation of cubics, analytic sphere clearances, and folds over segments.

use nalgebra::Vector3;
use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};
use satflock::environment::{
    closest_approach_to_line, closest_approach_to_threat, min_distance_to_point,
    obstacle_clearance, Approach, ApproachMonitor, EnvironmentError, HermiteSegment, LinearMotion,
    Motion, Obstacle, Threat,
};

fn rel_err(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

fn v(x: f64, y: f64, z: f64) -> Vector3<f64> {
    Vector3::new(x, y, z)
}

/// Hermite segments of a trajectory given as a function `t -> (position, velocity)` at the times
/// `t_k = t_start + k h`, k = 0..=steps.
fn segments(
    state: impl Fn(f64) -> (Vector3<f64>, Vector3<f64>),
    t_start: f64,
    h: f64,
    steps: usize,
) -> Vec<HermiteSegment> {
    (0..steps)
        .map(|k| {
            let (t0, t1) = (t_start + k as f64 * h, t_start + (k + 1) as f64 * h);
            let (p0, v0) = state(t0);
            let (p1, v1) = state(t1);
            HermiteSegment::new(t0, t1, p0, v0, p1, v1).unwrap()
        })
        .collect()
}

/// The segment minimum with the smallest distance (the earliest among ties), as the monitor keeps it.
fn fold_min(approaches: impl IntoIterator<Item = Approach>) -> Approach {
    approaches
        .into_iter()
        .reduce(|best, a| {
            if a.distance_m < best.distance_m {
                a
            } else {
                best
            }
        })
        .unwrap()
}

/// Minimum of `dist(t)` over `[t_lo, t_hi]` by brute force: a dense grid of `n` steps, then a second
/// grid of `n` steps over the two cells around the best sample, three times. Returns `(t, dist)`.
fn brute_min(dist: impl Fn(f64) -> f64, t_lo: f64, t_hi: f64, n: usize) -> (f64, f64) {
    let (mut lo, mut hi) = (t_lo, t_hi);
    let mut best = (t_lo, dist(t_lo));
    for _ in 0..4 {
        let step = (hi - lo) / n as f64;
        for k in 0..=n {
            let t = lo + k as f64 * step;
            let d = dist(t);
            if d < best.1 {
                best = (t, d);
            }
        }
        lo = (best.0 - step).max(t_lo);
        hi = (best.0 + step).min(t_hi);
    }
    best
}

// ---------------------------------------------------------------------------------------------------
// Straight-line flyby: closed form t* = −(r·v)/(v·v).

#[test]
fn straight_line_flyby_matches_closed_form() {
    let p_sat = v(100.0, -2000.0, 50.0);
    let u_sat = v(0.5, 10.0, -0.2);
    let w_thr = v(-3.0, -40.0, 1.5);
    let v_rel = u_sat - w_thr;
    // The threat misses by 25 m at t = 37.3 s, strictly inside the segment [30, 40] s.
    let miss = v_rel.cross(&v(0.0, 0.0, 1.0)).normalize() * 25.0;
    let r0 = miss - v_rel * 37.3;
    let threat = Threat::from_state("flyby", 0.0, p_sat - r0, w_thr, 5.0).unwrap();

    // Reference from the actual floating-point data: r(t) = r0 + v t, relative satellite − threat.
    let r0 = p_sat - threat.position_hill_m(0.0);
    let v_rel = u_sat - threat.velocity_hill_mps(0.0);
    let t_star = -r0.dot(&v_rel) / v_rel.dot(&v_rel);
    let d_star = (r0 + v_rel * t_star).norm();
    assert!(t_star > 30.0 && t_star < 40.0 && (d_star - 25.0).abs() < 1e-9);

    let segs = segments(|t| (p_sat + u_sat * t, u_sat), 0.0, 10.0, 10);
    let best = fold_min(segs.iter().map(|s| closest_approach_to_threat(s, &threat)));
    let (et, ed) = (
        rel_err(best.time_s, t_star),
        rel_err(best.distance_m, d_star),
    );
    println!(
        "flyby: t {} vs {t_star} (rel {et:.1e}), d {} vs {d_star} (rel {ed:.1e})",
        best.time_s, best.distance_m
    );
    assert!(et < 1e-6 && ed < 1e-6);
    // Much better than asked: rounding of the data (positions ~2e3 m, distance 25 m).
    assert!(
        et < 1e-12 && ed < 1e-11,
        "time rel {et:e}, distance rel {ed:e}"
    );

    // The segment holding the minimum, alone, and through the monitor.
    let seg = &segs[3];
    let a = closest_approach_to_threat(seg, &threat);
    assert!(rel_err(a.time_s, t_star) < 1e-12 && rel_err(a.distance_m, d_star) < 1e-11);
    let mut monitor = ApproachMonitor::new(1, 1, 0);
    for s in &segs {
        monitor
            .observe_segment(0, s, std::slice::from_ref(&threat), &[])
            .unwrap();
    }
    assert_eq!(monitor.threat_approach(0, 0), Some(best));
    // 25 m miss, 5 m danger radius: no incursion.
    assert_eq!(monitor.threat_incursions(0, 0), 0);

    // A segment whose interior holds no stationary point: the minimum is at an end.
    let end = closest_approach_to_threat(&segs[7], &threat);
    assert_eq!(end.time_s, 70.0);
    assert!(rel_err(end.distance_m, (r0 + v_rel * 70.0).norm()) < 1e-13);
}

// ---------------------------------------------------------------------------------------------------
// Curved path: HCW closed form, written out independently of the crate.

/// Mean motion of a circular orbit at 600 km altitude (WGS 84 μ and radius), rad/s.
fn mean_motion() -> f64 {
    let a = 6_378_137.0 + 600e3;
    (3.986_004_418e14_f64 / (a * a * a)).sqrt()
}

/// HCW closed-form state at time t from (r0, v0) at t = 0 (Hill frame: x radial, y along-track, z normal).
fn hcw_state(n: f64, r0: Vector3<f64>, v0: Vector3<f64>, t: f64) -> (Vector3<f64>, Vector3<f64>) {
    let (x0, y0, z0) = (r0.x, r0.y, r0.z);
    let (vx0, vy0, vz0) = (v0.x, v0.y, v0.z);
    let th = n * t;
    let (s, c) = th.sin_cos();
    let x = 4.0 * x0 - 3.0 * x0 * c + vx0 / n * s + 2.0 * vy0 / n * (1.0 - c);
    let y = 6.0 * x0 * (s - th) + y0 - 2.0 * vx0 / n * (1.0 - c) + vy0 / n * (4.0 * s - 3.0 * th);
    let z = z0 * c + vz0 / n * s;
    let vx = 3.0 * n * x0 * s + vx0 * c + 2.0 * vy0 * s;
    let vy = 6.0 * n * x0 * (c - 1.0) - 2.0 * vx0 * s + vy0 * (4.0 * c - 3.0);
    let vz = -z0 * n * s + vz0 * c;
    (v(x, y, z), v(vx, vy, vz))
}

/// Upper bound on |r⁽⁴⁾(t)| (m/s⁴) of an HCW trajectory: the secular terms are linear in t, the
/// periodic ones have amplitudes (B, C) per axis and fourth derivative n⁴ times themselves.
fn hcw_fourth_derivative_bound(n: f64, r0: Vector3<f64>, v0: Vector3<f64>) -> f64 {
    let (bx, cx) = (-3.0 * r0.x - 2.0 * v0.y / n, v0.x / n);
    let (by, cy) = (2.0 * v0.x / n, 6.0 * r0.x + 4.0 * v0.y / n);
    let (bz, cz) = (r0.z, v0.z / n);
    n.powi(4) * (bx * bx + cx * cx + by * by + cy * cy + bz * bz + cz * cz).sqrt()
}

/// The reference itself: the closed form above satisfies the HCW equations and its velocity is the
/// derivative of its position (central differences).
#[test]
fn hcw_reference_is_consistent() {
    let n = mean_motion();
    let (r0, v0) = (
        v(200.0, -100.0, 150.0),
        v(0.1, -2.0 * n * 200.0 + 0.05, -0.05),
    );
    let dt = 1e-2;
    for &t in &[0.0, 700.0, 2345.6, 5000.0] {
        let (r, vel) = hcw_state(n, r0, v0, t);
        let (rp, vp) = hcw_state(n, r0, v0, t + dt);
        let (rm, vm) = hcw_state(n, r0, v0, t - dt);
        let vel_fd = (rp - rm) / (2.0 * dt);
        let acc_fd = (vp - vm) / (2.0 * dt);
        assert!((vel_fd - vel).norm() < 1e-7, "{vel_fd} vs {vel}");
        let acc = v(
            3.0 * n * n * r.x + 2.0 * n * vel.y,
            -2.0 * n * vel.x,
            -n * n * r.z,
        );
        assert!((acc_fd - acc).norm() < 1e-10, "{acc_fd} vs {acc}");
    }
}

#[test]
fn curved_hcw_path_matches_dense_exact_trajectory() {
    let n = mean_motion();
    let (r0, v0) = (
        v(200.0, -100.0, 150.0),
        v(0.1, -2.0 * n * 200.0 + 0.05, -0.05),
    );
    let exact = |t: f64| hcw_state(n, r0, v0, t);
    let m4 = hcw_fourth_derivative_bound(n, r0, v0);

    // A threat crossing 30 m from the satellite's path at t = 1234.5 s (not a multiple of any segment
    // length below), moving at 50 m/s across it.
    let t_cross = 1234.5;
    let (p_cross, v_cross) = exact(t_cross);
    let across = v_cross.cross(&v(0.3, -0.2, 1.0)).normalize();
    let offset = v_cross.cross(&across).normalize() * 30.0;
    let threat =
        Threat::from_aim("crossing", p_cross + offset, across, 50.0, t_cross, 10.0).unwrap();
    let dist = |t: f64| (exact(t).0 - threat.position_hill_m(t)).norm();

    let (t_lo, t_hi) = (0.0, 3000.0);
    let (t_ref, d_ref) = brute_min(dist, t_lo, t_hi, 300_000);
    // Curvature of the distance at its minimum, for the time tolerance.
    let dd = 0.1;
    let curvature = (dist(t_ref + dd) - 2.0 * dist(t_ref) + dist(t_ref - dd)) / (dd * dd);
    assert!(curvature > 0.0);

    for &h in &[10.0, 30.0, 60.0] {
        let segs = segments(exact, t_lo, h, ((t_hi - t_lo) / h) as usize);
        let best = fold_min(segs.iter().map(|s| closest_approach_to_threat(s, &threat)));
        // |Hermite − exact| ≤ h⁴/384 · max|r⁽⁴⁾| bounds the difference of the minima; the brute force
        // and rounding add < 1e-9 m. The minimiser moves by at most √(4 Δ / f'') (f ≥ f* + f''/2 δt²).
        let delta = h.powi(4) / 384.0 * m4;
        let tol_d = delta + 1e-9;
        let tol_t = (4.0 * tol_d / curvature).sqrt() + 1e-6;
        println!(
            "h = {h} s: d {} vs {d_ref} (|err| {:.1e}, tol {tol_d:.1e}); t {} vs {t_ref} (|err| {:.1e}, tol {tol_t:.1e})",
            best.distance_m,
            (best.distance_m - d_ref).abs(),
            best.time_s,
            (best.time_s - t_ref).abs()
        );
        assert!((best.distance_m - d_ref).abs() <= tol_d);
        assert!((best.time_s - t_ref).abs() <= tol_t);
    }
}

// ---------------------------------------------------------------------------------------------------
// Exactness on arbitrary cubics: brute force on the interpolant itself.

#[test]
fn random_cubics_match_brute_force_on_the_interpolant() {
    let mut rng = ChaCha8Rng::seed_from_u64(20_240_611);
    let mut r = |lo: f64, hi: f64| rng.random_range(lo..hi);
    for case in 0..300 {
        let h = r(1.0, 60.0);
        let t0 = r(-1000.0, 1000.0);
        let seg = HermiteSegment::new(
            t0,
            t0 + h,
            v(r(-500.0, 500.0), r(-500.0, 500.0), r(-500.0, 500.0)),
            v(r(-50.0, 50.0), r(-50.0, 50.0), r(-50.0, 50.0)),
            v(r(-500.0, 500.0), r(-500.0, 500.0), r(-500.0, 500.0)),
            v(r(-50.0, 50.0), r(-50.0, 50.0), r(-50.0, 50.0)),
        )
        .unwrap();
        // A line through a point of the segment (plus a small miss), so that minima are close ones.
        let tm = t0 + r(0.0, h);
        let line = LinearMotion {
            reference_time_s: tm,
            reference_position_hill_m: seg.position_hill_m(tm) + v(r(-5.0, 5.0), r(-5.0, 5.0), 0.0),
            velocity_hill_mps: v(r(-30.0, 30.0), r(-30.0, 30.0), r(-30.0, 30.0)),
        };
        let a = closest_approach_to_line(&seg, &line);
        let dist = |t: f64| (seg.position_hill_m(t) - line.position_hill_m(t)).norm();
        let (t_bf, d_bf) = brute_min(dist, seg.t0_s, seg.t1_s, 20_000);
        assert!(a.time_s >= seg.t0_s && a.time_s <= seg.t1_s);
        // Our minimum is a true value of the distance at our time...
        assert!((dist(a.time_s) - a.distance_m).abs() < 1e-9, "case {case}");
        // ...and no point found by brute force is below it.
        assert!(
            a.distance_m <= d_bf + 1e-9,
            "case {case}: {} > {d_bf} at {t_bf}",
            a.distance_m
        );
    }
}

/// Three closely spaced near-contacts within 0.01 of one segment (a hairpin), which a 64-cell uniform
/// scan of the derivative cannot separate.
#[test]
fn hairpin_segment_with_close_minima() {
    // d(s) = (L (s − 0.300)(s − 0.302)(s − 0.304), 1 + 0.5 s, 0) relative to the origin: x vanishes three
    // times within Δs = 0.004, y grows, so the global minimum is near s = 0.300, with two local minima
    // and two local maxima of the distance within 0.005 of it.
    let l = 1e6;
    let roots = [0.300, 0.302, 0.304];
    // x(s) = L (s³ − Σr s² + Σrr s − Πr); y(s) = 1 + 0.5 s.
    let sr: f64 = roots.iter().sum();
    let srr = roots[0] * roots[1] + roots[0] * roots[2] + roots[1] * roots[2];
    let pr = roots[0] * roots[1] * roots[2];
    let pos = |s: f64| v(l * (((s - sr) * s + srr) * s - pr), 1.0 + 0.5 * s, 0.0);
    let vel_s = |s: f64| v(l * ((3.0 * s - 2.0 * sr) * s + srr), 0.5, 0.0);
    let h = 10.0;
    let seg =
        HermiteSegment::new(0.0, h, pos(0.0), vel_s(0.0) / h, pos(1.0), vel_s(1.0) / h).unwrap();
    let a = min_distance_to_point(&seg, &Vector3::zeros());
    let dist = |t: f64| seg.position_hill_m(t).norm();
    let (t_bf, d_bf) = brute_min(dist, 0.0, h, 1_000_000);
    println!("hairpin: {a:?} vs brute force ({t_bf}, {d_bf})");
    // The slope of y moves the minimum slightly before the first root of x (s ≈ 0.2988).
    assert!((a.time_s / h - 0.300).abs() < 2e-3 && (a.time_s - t_bf).abs() < 1e-6);
    assert!(rel_err(a.distance_m, d_bf) < 1e-9 && a.distance_m <= d_bf * (1.0 + 1e-12));
}

// ---------------------------------------------------------------------------------------------------
// Constructors.

#[test]
fn from_aim_passes_the_aim_point_at_arrival() {
    let aim = v(12.5, -300.0, 7.0);
    let dir = v(3.0, 4.0, 0.0); // not unit: normalised by the constructor
    let t = Threat::from_aim("aimed", aim, dir, 20.0, 432.1, 15.0).unwrap();
    assert_eq!(t.position_hill_m(432.1), aim);
    let expected_v = v(12.0, 16.0, 0.0);
    assert!((t.velocity_hill_mps(0.0) - expected_v).norm() < 1e-13);
    let later = t.position_hill_m(442.1);
    assert!((later - (aim + expected_v * 10.0)).norm() < 1e-11);
    assert_eq!(t.name(), "aimed");
    assert_eq!(t.danger_radius_m(), 15.0);
    assert_eq!(t.detection_range_m(), None);
    let t = t.with_detection_range_m(2000.0).unwrap();
    assert_eq!(t.detection_range_m(), Some(2000.0));
    // Huge and tiny direction vectors are normalised without overflow or underflow.
    let big = Threat::from_aim("big", aim, v(1e300, 1e300, 0.0), 2.0, 0.0, 0.0).unwrap();
    assert!((big.velocity_hill_mps(0.0) - v(2f64.sqrt(), 2f64.sqrt(), 0.0)).norm() < 1e-14);
    let tiny = Threat::from_aim("tiny", aim, v(0.0, 0.0, -1e-310), 2.0, 0.0, 0.0).unwrap();
    assert_eq!(tiny.velocity_hill_mps(0.0), v(0.0, 0.0, -2.0));

    let s = Threat::from_state("state", 5.0, aim, expected_v, 0.0).unwrap();
    assert_eq!(s.position_hill_m(5.0), aim);
    let Motion::Line(line) = s.motion() else {
        panic!("a threat from a state moves on a line")
    };
    assert_eq!(line.reference_time_s, 5.0);
}

#[test]
fn constructors_refuse_bad_numbers() {
    let p = v(1.0, 2.0, 3.0);
    let d = v(0.0, 1.0, 0.0);
    use EnvironmentError as E;
    let e = Threat::from_aim("t", p, Vector3::zeros(), 1.0, 0.0, 1.0).unwrap_err();
    assert_eq!(
        e,
        E::ZeroDirection {
            direction_hill: [0.0; 3]
        }
    );
    let e = Threat::from_aim("t", p, v(f64::NAN, 0.0, 1.0), 1.0, 0.0, 1.0).unwrap_err();
    assert!(matches!(e, E::NonFiniteVector { .. }));
    assert_eq!(
        Threat::from_aim("t", p, d, 0.0, 0.0, 1.0).unwrap_err(),
        E::InvalidSpeed { speed_mps: 0.0 }
    );
    assert_eq!(
        Threat::from_aim("t", p, d, -3.0, 0.0, 1.0).unwrap_err(),
        E::InvalidSpeed { speed_mps: -3.0 }
    );
    assert!(matches!(
        Threat::from_aim("t", p, d, f64::INFINITY, 0.0, 1.0).unwrap_err(),
        E::InvalidSpeed { .. }
    ));
    assert_eq!(
        Threat::from_aim("t", p, d, 1.0, 0.0, -2.0).unwrap_err(),
        E::NegativeRadius {
            what: "threat danger radius",
            radius_m: -2.0
        }
    );
    assert!(matches!(
        Threat::from_aim("t", p, d, 1.0, f64::NAN, 1.0).unwrap_err(),
        E::NonFinite {
            what: "threat arrival time (s)",
            ..
        }
    ));
    assert!(matches!(
        Threat::from_aim("t", v(f64::INFINITY, 0.0, 0.0), d, 1.0, 0.0, 1.0).unwrap_err(),
        E::NonFiniteVector {
            value: [f64::INFINITY, 0.0, 0.0],
            ..
        }
    ));
    assert_eq!(
        Threat::from_state("t", 0.0, p, Vector3::zeros(), 1.0).unwrap_err(),
        E::ZeroVelocity {
            velocity_hill_mps: [0.0; 3]
        }
    );
    assert!(matches!(
        Threat::from_state("t", 0.0, p, v(0.0, f64::NAN, 0.0), 1.0).unwrap_err(),
        E::NonFiniteVector { .. }
    ));
    assert!(matches!(
        Threat::from_state("t", f64::NEG_INFINITY, p, d, 1.0).unwrap_err(),
        E::NonFinite { .. }
    ));
    assert!(matches!(
        Threat::from_state("t", 0.0, p, d, f64::NAN).unwrap_err(),
        E::NonFinite { .. }
    ));
    let ok = Threat::from_state("t", 0.0, p, d, 0.0).unwrap();
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let e = ok.clone().with_detection_range_m(bad).unwrap_err();
        assert!(matches!(e, E::InvalidDetectionRange { .. }), "{bad}");
    }

    assert_eq!(
        Obstacle::new("o", p, 0.0).unwrap_err(),
        E::NonPositiveRadius { radius_m: 0.0 }
    );
    assert_eq!(
        Obstacle::new("o", p, -1.0).unwrap_err(),
        E::NonPositiveRadius { radius_m: -1.0 }
    );
    assert!(matches!(
        Obstacle::new("o", p, f64::NAN).unwrap_err(),
        E::NonFinite { .. }
    ));
    assert!(matches!(
        Obstacle::new("o", v(0.0, 0.0, f64::NAN), 1.0).unwrap_err(),
        E::NonFiniteVector { .. }
    ));
    assert!(matches!(
        Obstacle::new("o", p, 1.0)
            .unwrap()
            .with_detection_range_m(-5.0)
            .unwrap_err(),
        E::InvalidDetectionRange {
            detection_range_m: -5.0
        }
    ));

    let z = Vector3::zeros();
    assert_eq!(
        HermiteSegment::new(1.0, 1.0, z, z, z, z).unwrap_err(),
        E::SegmentTimes {
            t0_s: 1.0,
            t1_s: 1.0
        }
    );
    assert!(matches!(
        HermiteSegment::new(0.0, 1.0, z, v(f64::NAN, 0.0, 0.0), z, z).unwrap_err(),
        E::NonFiniteVector { .. }
    ));
}

#[test]
fn hermite_segment_interpolates_end_states() {
    let seg = HermiteSegment::new(
        100.0,
        110.0,
        v(1.0, 2.0, 3.0),
        v(0.1, -0.2, 0.3),
        v(4.0, -5.0, 6.0),
        v(-0.4, 0.5, 0.6),
    )
    .unwrap();
    assert!((seg.position_hill_m(100.0) - seg.p0_hill_m).norm() < 1e-14);
    assert!((seg.position_hill_m(110.0) - seg.p1_hill_m).norm() < 1e-13);
    assert!((seg.velocity_hill_mps(100.0) - seg.v0_hill_mps).norm() < 1e-14);
    assert!((seg.velocity_hill_mps(110.0) - seg.v1_hill_mps).norm() < 1e-14);
}

// ---------------------------------------------------------------------------------------------------
// Obstacles.

/// A straight segment from `a` to `b` over `[t0, t1]`.
fn straight(t0: f64, t1: f64, a: Vector3<f64>, b: Vector3<f64>) -> HermiteSegment {
    let vel = (b - a) / (t1 - t0);
    HermiteSegment::new(t0, t1, a, vel, b, vel).unwrap()
}

#[test]
fn obstacle_surface_distance() {
    let o = Obstacle::new("rock", v(10.0, 0.0, 0.0), 5.0).unwrap();
    assert_eq!(o.surface_distance_m(&v(10.0, 0.0, 0.0), 0.0), -5.0);
    assert_eq!(o.surface_distance_m(&v(10.0, 3.0, 0.0), 0.0), -2.0);
    assert_eq!(o.surface_distance_m(&v(10.0, 0.0, 5.0), 0.0), 0.0);
    assert_eq!(o.surface_distance_m(&v(22.0, 0.0, 0.0), 0.0), 7.0);
    assert_eq!(o.name(), "rock");
    assert_eq!(o.center_hill_m(0.0), v(10.0, 0.0, 0.0));
    assert_eq!(o.radius_m(), 5.0);
}

#[test]
fn segment_through_a_sphere() {
    let o = Obstacle::new("o", v(0.0, 0.0, 0.0), 10.0).unwrap();
    // Passes 3 m from the centre at t = 5 s.
    let seg = straight(0.0, 10.0, v(-50.0, 3.0, 0.0), v(50.0, 3.0, 0.0));
    let c = obstacle_clearance(&seg, &o);
    assert!(
        (c.clearance_m - (3.0 - 10.0)).abs() < 1e-12 && (c.time_s - 5.0).abs() < 1e-12,
        "{c:?}"
    );
    let a = min_distance_to_point(&seg, &o.center_hill_m(0.0));
    assert!((a.distance_m - 3.0).abs() < 1e-12);
    let mut m = ApproachMonitor::new(1, 0, 1);
    m.observe_segment(0, &seg, &[], std::slice::from_ref(&o))
        .unwrap();
    assert_eq!(m.obstacle_incursions(0, 0), 1);
    assert_eq!(m.obstacle_clearance(0, 0), Some(c));
    assert_eq!(m.swarm_obstacle_minimum().unwrap().minimum, c);
}

#[test]
fn two_passes_give_two_incursions() {
    let o = Obstacle::new("o", v(0.0, 0.0, 0.0), 10.0).unwrap();
    let obstacles = [o];
    // Out and back: one pass per segment.
    let mut m = ApproachMonitor::new(3, 0, 1);
    m.observe_segment(
        0,
        &straight(0.0, 10.0, v(-50.0, 0.0, 1.0), v(50.0, 0.0, 1.0)),
        &[],
        &obstacles,
    )
    .unwrap();
    m.observe_segment(
        0,
        &straight(10.0, 20.0, v(50.0, 0.0, 1.0), v(-50.0, 0.0, 1.0)),
        &[],
        &obstacles,
    )
    .unwrap();
    assert_eq!(m.obstacle_incursions(0, 0), 2);

    // Enter in one segment, stay inside across the boundary, leave in the next: one incursion.
    m.observe_segment(
        1,
        &straight(0.0, 10.0, v(-50.0, 0.0, 0.0), v(0.0, 0.0, 0.0)),
        &[],
        &obstacles,
    )
    .unwrap();
    m.observe_segment(
        1,
        &straight(10.0, 20.0, v(0.0, 0.0, 0.0), v(50.0, 0.0, 0.0)),
        &[],
        &obstacles,
    )
    .unwrap();
    assert_eq!(m.obstacle_incursions(1, 0), 1);
    assert!((m.obstacle_clearance(1, 0).unwrap().clearance_m + 10.0).abs() < 1e-12);

    // Three passes within one segment: x(s) = 30 T3(2s − 1) (Chebyshev, ±30 m three times).
    let x = |s: f64| {
        let u = 2.0 * s - 1.0;
        30.0 * (4.0 * u * u * u - 3.0 * u)
    };
    let dx = |s: f64| {
        let u = 2.0 * s - 1.0;
        30.0 * (12.0 * u * u - 3.0) * 2.0
    };
    let h = 20.0;
    let seg = HermiteSegment::new(
        0.0,
        h,
        v(x(0.0), 2.0, 0.0),
        v(dx(0.0) / h, 0.0, 0.0),
        v(x(1.0), 2.0, 0.0),
        v(dx(1.0) / h, 0.0, 0.0),
    )
    .unwrap();
    m.observe_segment(2, &seg, &[], &obstacles).unwrap();
    assert_eq!(m.obstacle_incursions(2, 0), 3);
    // Closest: |x| = 0 (three times), 2 m from the centre; the earliest is kept.
    let c = m.obstacle_clearance(2, 0).unwrap();
    assert!((c.clearance_m - (2.0 - 10.0)).abs() < 1e-12);
    let s_first = 0.5 * (1.0 - 3f64.sqrt() / 2.0); // first zero of T3(2s − 1)
    assert!((c.time_s - s_first * h).abs() < 1e-9, "{c:?}");
    assert_eq!(m.satellite_obstacle_incursions(2), 3);
    assert_eq!(m.total_obstacle_incursions(), 6);
}

#[test]
fn grazing_segment_outside_the_sphere() {
    let o = Obstacle::new("o", v(5.0, -2.0, 1.0), 10.0).unwrap();
    // Straight path at 10.5 m from the centre, closest at t = 3 + 0.4·10 s.
    let dir = v(1.0, 1.0, 0.0).normalize();
    let normal = v(0.0, 0.0, 1.0);
    let closest = o.center_hill_m(0.0) + normal * 10.5;
    let seg = straight(3.0, 13.0, closest - dir * 40.0, closest + dir * 60.0);
    let c = obstacle_clearance(&seg, &o);
    assert!((c.clearance_m - 0.5).abs() < 1e-12, "{c:?}");
    assert!((c.time_s - 7.0).abs() < 1e-12, "{c:?}");
    let mut m = ApproachMonitor::new(1, 0, 1);
    m.observe_segment(0, &seg, &[], std::slice::from_ref(&o))
        .unwrap();
    assert_eq!(m.obstacle_incursions(0, 0), 0);
    assert!(m.obstacle_clearance(0, 0).unwrap().clearance_m > 0.0);
}

#[test]
fn threat_danger_radius_incursions() {
    // The threat sweeps through a satellite at rest at the origin: one incursion per crossing.
    let threat = Threat::from_state("t", 0.0, v(-100.0, 1.0, 0.0), v(10.0, 0.0, 0.0), 5.0).unwrap();
    let rest = |t0: f64, t1: f64| straight(t0, t1, Vector3::zeros(), Vector3::zeros());
    let mut m = ApproachMonitor::new(1, 1, 0);
    for k in 0..30 {
        m.observe_segment(
            0,
            &rest(k as f64, k as f64 + 1.0),
            std::slice::from_ref(&threat),
            &[],
        )
        .unwrap();
    }
    let a = m.threat_approach(0, 0).unwrap();
    assert!(
        (a.distance_m - 1.0).abs() < 1e-12 && (a.time_s - 10.0).abs() < 1e-12,
        "{a:?}"
    );
    assert_eq!(m.threat_incursions(0, 0), 1);
    assert_eq!(m.total_threat_incursions(), 1);
}

// ---------------------------------------------------------------------------------------------------
// The monitor against folds over segments.

#[test]
fn monitor_minima_equal_minimum_over_segments() {
    let n = mean_motion();
    let sats: Vec<(Vector3<f64>, Vector3<f64>)> = vec![
        (
            v(200.0, -100.0, 150.0),
            v(0.1, -2.0 * n * 200.0 + 0.05, -0.05),
        ),
        (v(-150.0, 300.0, -80.0), v(-0.05, 2.0 * n * 150.0, 0.12)),
        (v(50.0, 0.0, 0.0), v(0.2, -2.0 * n * 50.0, 0.0)),
        (v(0.0, -400.0, 20.0), v(0.0, 0.1, -0.02)),
    ];
    let threats = vec![
        // Aimed 20 m from satellite 0 at t = 800 s, danger radius 60 m: an incursion.
        Threat::from_aim(
            "t0",
            hcw_state(n, sats[0].0, sats[0].1, 800.0).0 + v(0.0, 0.0, 20.0),
            v(1.0, 0.2, -0.3),
            12.0,
            800.0,
            60.0,
        )
        .unwrap(),
        Threat::from_state(
            "t1",
            100.0,
            v(-500.0, 200.0, 100.0),
            v(0.8, -0.3, -0.1),
            40.0,
        )
        .unwrap(),
    ];
    let obstacles = vec![
        Obstacle::new("o0", v(0.0, 0.0, 0.0), 120.0).unwrap(),
        Obstacle::new("o1", v(100.0, -200.0, 50.0), 60.0).unwrap(),
    ];
    let h = 10.0;
    let steps = 600;
    let all: Vec<Vec<HermiteSegment>> = sats
        .iter()
        .map(|&(r0, v0)| segments(|t| hcw_state(n, r0, v0, t), 0.0, h, steps))
        .collect();

    let mut m = ApproachMonitor::new(sats.len(), threats.len(), obstacles.len());
    for k in 0..steps {
        for (i, segs) in all.iter().enumerate() {
            m.observe_segment(i, &segs[k], &threats, &obstacles)
                .unwrap();
        }
    }

    let mut swarm_threat: Option<(f64, usize, usize)> = None;
    let mut swarm_obstacle: Option<(f64, usize, usize)> = None;
    for (i, segs) in all.iter().enumerate() {
        let mut sat_threat: Option<(f64, usize)> = None;
        for (j, t) in threats.iter().enumerate() {
            let reference = fold_min(segs.iter().map(|s| closest_approach_to_threat(s, t)));
            assert_eq!(
                m.threat_approach(i, j),
                Some(reference),
                "satellite {i} threat {j}"
            );
            if sat_threat.is_none_or(|b| reference.distance_m < b.0) {
                sat_threat = Some((reference.distance_m, j));
            }
            // Incursions counted independently: outside → inside steps on a dense sampling.
            let dense = dense_entries(segs, t, |t, time| t.position_hill_m(time));
            assert_eq!(m.threat_incursions(i, j), dense, "satellite {i} threat {j}");
        }
        let sm = m.satellite_threat_minimum(i).unwrap();
        assert_eq!((sm.minimum.distance_m, sm.object), sat_threat.unwrap());
        if swarm_threat.is_none_or(|b| sat_threat.unwrap().0 < b.0) {
            swarm_threat = Some((sat_threat.unwrap().0, i, sat_threat.unwrap().1));
        }

        let mut sat_obstacle: Option<(f64, usize)> = None;
        for (j, o) in obstacles.iter().enumerate() {
            let reference = segs
                .iter()
                .map(|s| obstacle_clearance(s, o))
                .reduce(|b, c| if c.clearance_m < b.clearance_m { c } else { b })
                .unwrap();
            assert_eq!(
                m.obstacle_clearance(i, j),
                Some(reference),
                "satellite {i} obstacle {j}"
            );
            if sat_obstacle.is_none_or(|b| reference.clearance_m < b.0) {
                sat_obstacle = Some((reference.clearance_m, j));
            }
            let dense = dense_entries(segs, o, |o, _| o.center_hill_m(0.0));
            assert_eq!(
                m.obstacle_incursions(i, j),
                dense,
                "satellite {i} obstacle {j}"
            );
        }
        let sm = m.satellite_obstacle_minimum(i).unwrap();
        assert_eq!((sm.minimum.clearance_m, sm.object), sat_obstacle.unwrap());
        if swarm_obstacle.is_none_or(|b| sat_obstacle.unwrap().0 < b.0) {
            swarm_obstacle = Some((sat_obstacle.unwrap().0, i, sat_obstacle.unwrap().1));
        }
    }
    let st = m.swarm_threat_minimum().unwrap();
    assert_eq!(
        (st.minimum.distance_m, st.satellite, st.object),
        swarm_threat.unwrap()
    );
    let so = m.swarm_obstacle_minimum().unwrap();
    assert_eq!(
        (so.minimum.clearance_m, so.satellite, so.object),
        swarm_obstacle.unwrap()
    );
    println!(
        "monitor: swarm threat minimum {st:?}, swarm obstacle minimum {so:?}, incursions {} (threats) {} (obstacles)",
        m.total_threat_incursions(),
        m.total_obstacle_incursions()
    );
    // The scenario is built to exercise incursions of both kinds.
    assert!(m.total_threat_incursions() > 0 && m.total_obstacle_incursions() > 0);

    // Bad calls are refused and change nothing.
    let seg = all[0][0];
    assert_eq!(
        m.observe_segment(4, &seg, &threats, &obstacles)
            .unwrap_err(),
        EnvironmentError::SatelliteIndex { index: 4, count: 4 }
    );
    assert_eq!(
        m.observe_segment(0, &seg, &threats[..1], &obstacles)
            .unwrap_err(),
        EnvironmentError::ObjectCount {
            what: "threats",
            expected: 2,
            got: 1
        }
    );
    assert_eq!(
        m.observe_segment(0, &seg, &threats, &[]).unwrap_err(),
        EnvironmentError::ObjectCount {
            what: "obstacles",
            expected: 2,
            got: 0
        }
    );
}

/// Outside → inside transitions of the centre distance to an object's centre against its radius
/// (danger radius or obstacle radius), sampling each segment at 2000 points; a satellite inside at the
/// first sample counts once. `centre(object, t)` is the object's centre at time t.
fn dense_entries<O: Radius>(
    segs: &[HermiteSegment],
    object: &O,
    centre: impl Fn(&O, f64) -> Vector3<f64>,
) -> u64 {
    let mut inside = false;
    let mut entries = 0;
    for s in segs {
        for k in 0..=2000 {
            let t = s.t0_s + (s.t1_s - s.t0_s) * k as f64 / 2000.0;
            let now = (s.position_hill_m(t) - centre(object, t)).norm() < object.radius();
            if now && !inside {
                entries += 1;
            }
            inside = now;
        }
    }
    entries
}

trait Radius {
    fn radius(&self) -> f64;
}
impl Radius for Threat {
    fn radius(&self) -> f64 {
        self.danger_radius_m()
    }
}
impl Radius for Obstacle {
    fn radius(&self) -> f64 {
        self.radius_m()
    }
}

/// `observe_segments` (every satellite at once, in parallel) leaves the monitor as observing each
/// satellite in turn with `observe_segment` does: 700 satellites (several parallel work items) on
/// three successive segments through two threats' danger spheres and an obstacle, some satellites not
/// observed on some segments; with threats only, obstacles only and both; on 1 and 2 threads.
#[test]
fn observing_all_satellites_at_once_equals_one_at_a_time() {
    let n = 700;
    let threats = [
        Threat::from_state("a", 0.0, v(-60.0, 0.0, 0.0), v(4.0, 0.0, 0.0), 12.0).unwrap(),
        Threat::from_state("b", 0.0, v(0.0, 80.0, 5.0), v(0.0, -5.0, 0.0), 8.0).unwrap(),
    ];
    let obstacles = [Obstacle::new("o", v(10.0, -10.0, 0.0), 15.0).unwrap()];
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    let mut point = || {
        v(
            rng.random_range(-40.0..40.0),
            rng.random_range(-40.0..40.0),
            rng.random_range(-10.0..10.0),
        )
    };
    // Positions at t = 0, 10, 20, 30 s; satellite i is not observed on segment k when (i + k) % 7 == 0.
    let waypoints: Vec<[Vector3<f64>; 4]> = (0..n)
        .map(|_| [point(), point(), point(), point()])
        .collect();
    let segment = |i: usize, k: usize| {
        (!(i + k).is_multiple_of(7)).then(|| {
            let t0 = 10.0 * k as f64;
            straight(t0, t0 + 10.0, waypoints[i][k], waypoints[i][k + 1])
        })
    };
    let configurations: [(&[Threat], &[Obstacle]); 3] =
        [(&threats, &[]), (&[], &obstacles), (&threats, &obstacles)];
    for (threats, obstacles) in configurations {
        let mut one_at_a_time = ApproachMonitor::new(n, threats.len(), obstacles.len());
        for k in 0..3 {
            for i in 0..n {
                if let Some(s) = segment(i, k) {
                    one_at_a_time
                        .observe_segment(i, &s, threats, obstacles)
                        .unwrap();
                }
            }
        }
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut at_once = ApproachMonitor::new(n, threats.len(), obstacles.len());
            for k in 0..3 {
                pool.install(|| at_once.observe_segments(|i| segment(i, k), threats, obstacles))
                    .unwrap();
            }
            for i in 0..n {
                for t in 0..threats.len() {
                    assert_eq!(
                        at_once.threat_approach(i, t),
                        one_at_a_time.threat_approach(i, t)
                    );
                    assert_eq!(
                        at_once.threat_incursions(i, t),
                        one_at_a_time.threat_incursions(i, t)
                    );
                }
                for o in 0..obstacles.len() {
                    assert_eq!(
                        at_once.obstacle_clearance(i, o),
                        one_at_a_time.obstacle_clearance(i, o)
                    );
                    assert_eq!(
                        at_once.obstacle_incursions(i, o),
                        one_at_a_time.obstacle_incursions(i, o)
                    );
                }
            }
        }
        // The passages cross the spheres: incursions were counted.
        assert!(
            one_at_a_time.total_threat_incursions() + one_at_a_time.total_obstacle_incursions() > 0
        );
    }
}
