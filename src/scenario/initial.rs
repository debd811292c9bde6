//! Initial relative states of the satellites: random draws in a ball, box or shell (seeded; satellite i
//! draws from its own stream `RandomStream::new(seed, Purpose::InitialStates, i, 0)`, so its draw does not
//! depend on the others or on threads), or explicit lists.

use nalgebra::Vector3;

use crate::orbit::RelativeStateHill;
use crate::random::{Purpose, RandomStream};
use crate::relative::j2_averaged::{AveragedJ2, OrbitParameters};
use crate::scenario::schema::InitialVelocity;

/// The random stream of satellite `i`'s initial state for a scenario seed.
fn satellite_stream(seed: u64, i: usize) -> RandomStream {
    RandomStream::new(seed, Purpose::InitialStates, i as u64, 0)
}

/// A point uniform in the unit ball (rejection sampling from the cube: exact uniformity).
fn unit_ball(rng: &mut RandomStream) -> Vector3<f64> {
    loop {
        let p = Vector3::new(
            rng.uniform_range(-1.0, 1.0),
            rng.uniform_range(-1.0, 1.0),
            rng.uniform_range(-1.0, 1.0),
        );
        if p.norm_squared() <= 1.0 {
            return p;
        }
    }
}

/// A direction uniform on the unit sphere.
fn unit_direction(rng: &mut RandomStream) -> Vector3<f64> {
    loop {
        let p = unit_ball(rng);
        let norm = p.norm();
        if norm > 1e-6 {
            return p / norm;
        }
    }
}

/// Positions uniform in a ball of `radius_m` about `center_hill_m` \[m\].
pub fn sphere(
    seed: u64,
    count: usize,
    radius_m: f64,
    center_hill_m: Vector3<f64>,
) -> Vec<Vector3<f64>> {
    (0..count)
        .map(|i| center_hill_m + radius_m * unit_ball(&mut satellite_stream(seed, i)))
        .collect()
}

/// Positions uniform in an axis-aligned box of edge lengths `size_hill_m` about `center_hill_m` \[m\].
pub fn cuboid(
    seed: u64,
    count: usize,
    size_hill_m: Vector3<f64>,
    center_hill_m: Vector3<f64>,
) -> Vec<Vector3<f64>> {
    (0..count)
        .map(|i| {
            let mut rng = satellite_stream(seed, i);
            let u = Vector3::new(
                rng.uniform_range(-0.5, 0.5),
                rng.uniform_range(-0.5, 0.5),
                rng.uniform_range(-0.5, 0.5),
            );
            center_hill_m + size_hill_m.component_mul(&u)
        })
        .collect()
}

/// Positions uniform in the spherical shell inner ≤ r ≤ outer about `center_hill_m` \[m\]
/// (radius drawn with density ∝ r², i.e. r = (r_i³ + u (r_o³ − r_i³))^(1/3)).
pub fn shell(
    seed: u64,
    count: usize,
    inner_radius_m: f64,
    outer_radius_m: f64,
    center_hill_m: Vector3<f64>,
) -> Vec<Vector3<f64>> {
    let (a, b) = (inner_radius_m.powi(3), outer_radius_m.powi(3));
    (0..count)
        .map(|i| {
            let mut rng = satellite_stream(seed, i);
            let direction = unit_direction(&mut rng);
            let u = rng.uniform();
            center_hill_m + (a + u * (b - a)).cbrt() * direction
        })
        .collect()
}

/// Relative states from positions and the velocity rule, with mean motion `n` \[rad/s\].
pub fn with_velocity(
    positions_hill_m: Vec<Vector3<f64>>,
    velocity: InitialVelocity,
    mean_motion_rad_s: f64,
) -> Vec<RelativeStateHill> {
    positions_hill_m
        .into_iter()
        .map(|p| RelativeStateHill {
            position_m: p,
            velocity_mps: match velocity {
                InitialVelocity::Zero => Vector3::zeros(),
                // HCW: ẏ = −2 n x removes the secular along-track drift.
                InitialVelocity::HcwNoDrift => {
                    Vector3::new(0.0, -2.0 * mean_motion_rad_s * p.x, 0.0)
                }
            },
        })
        .collect()
}

/// Relative states of `count` satellites released from one dispenser at the LVLH origin (Hill frame):
/// along-track positions `(i − (count − 1)/2) spacing_m` \[m\], along-track velocities spaced linearly
/// from `release_speed_mps[0]` to `release_speed_mps[1]` \[m/s\], each velocity component dispersed by
/// a Gaussian of `dispersion_mps` (1 σ) \[m/s\] drawn from the satellite's own stream.
pub fn dispenser(
    seed: u64,
    count: usize,
    spacing_m: f64,
    release_speed_mps: [f64; 2],
    dispersion_mps: f64,
) -> Vec<RelativeStateHill> {
    let middle = (count as f64 - 1.0) / 2.0;
    let step_mps = match count {
        0 | 1 => 0.0,
        _ => (release_speed_mps[1] - release_speed_mps[0]) / (count as f64 - 1.0),
    };
    (0..count)
        .map(|i| {
            let mut rng = satellite_stream(seed, i);
            let dispersion = Vector3::new(
                rng.standard_normal(),
                rng.standard_normal(),
                rng.standard_normal(),
            ) * dispersion_mps;
            RelativeStateHill {
                position_m: Vector3::new(0.0, (i as f64 - middle) * spacing_m, 0.0),
                velocity_mps: Vector3::new(0.0, release_speed_mps[0] + i as f64 * step_mps, 0.0)
                    + dispersion,
            }
        })
        .collect()
}

/// Relative states from averaged-J2 parameters drawn uniformly per satellite (Takahashi & Sakai; `docs/methods/j2-distance.md` §10.1):
/// C₁ in ±`c1_max_m`, C₄ in ±`c4_max_m`, C₂, C₃, C₅, C₆ in ±`amplitude_max_m` \[m\], converted with
/// `model` (`docs/methods/j2-distance.md` §3.2). Satellite `origin` (if any) gets C = 0. One stream per satellite.
pub fn averaged_j2(
    seed: u64,
    count: usize,
    model: &AveragedJ2,
    c1_max_m: f64,
    c4_max_m: f64,
    amplitude_max_m: f64,
    origin: Option<usize>,
) -> Vec<RelativeStateHill> {
    (0..count)
        .map(|i| {
            if origin == Some(i) {
                return RelativeStateHill::default();
            }
            let mut rng = satellite_stream(seed, i);
            let mut draw = |bound: f64| bound * rng.uniform_range(-1.0, 1.0);
            let c1_m = draw(c1_max_m);
            let c2_m = draw(amplitude_max_m);
            let c3_m = draw(amplitude_max_m);
            let c4_m = draw(c4_max_m);
            let c5_m = draw(amplitude_max_m);
            let c6_m = draw(amplitude_max_m);
            RelativeStateHill::from_vector6(&model.state(&OrbitParameters {
                c1_m,
                c2_m,
                c3_m,
                c4_m,
                c5_m,
                c6_m,
            }))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn val_draws_stay_in_their_region() {
        let c = Vector3::new(10.0, -5.0, 2.0);
        for p in sphere(7, 500, 100.0, c) {
            assert!((p - c).norm() <= 100.0);
        }
        for p in shell(7, 500, 50.0, 60.0, c) {
            let r = (p - c).norm();
            // the cube root of the shell law can round to within a few ulps of the bounds
            assert!((50.0 - 1e-9..=60.0 + 1e-9).contains(&r), "r = {r}");
        }
        for p in cuboid(7, 500, Vector3::new(2.0, 4.0, 6.0), c) {
            let d = p - c;
            assert!(d.x.abs() <= 1.0 && d.y.abs() <= 2.0 && d.z.abs() <= 3.0);
        }
    }

    #[test]
    fn val_dispenser_release_spacing_speeds_and_dispersion() {
        // Without dispersion: the train and the linear speed ramp exactly.
        let plain = dispenser(5, 5, 2.0, [-0.2, 0.2], 0.0);
        for (i, s) in plain.iter().enumerate() {
            let k = i as f64 - 2.0;
            assert_eq!(s.position_m, Vector3::new(0.0, 2.0 * k, 0.0));
            assert!((s.velocity_mps - Vector3::new(0.0, 0.1 * k, 0.0)).norm() < 1e-15);
        }
        // With dispersion: per axis, the sample mean and standard deviation of 20 000 draws of
        // σ = 0.01 m/s about the ramp are within 5 standard errors of 0 and σ (standard error of the
        // mean σ/√n = 7.1e-5; of the standard deviation σ/√(2n) = 5.0e-5).
        let n = 20_000;
        let sigma = 0.01;
        let spread = dispenser(9, n, 1.0, [0.0, 0.0], sigma);
        for axis in 0..3 {
            let values: Vec<f64> = spread.iter().map(|s| s.velocity_mps[axis]).collect();
            let mean = values.iter().sum::<f64>() / n as f64;
            let sd =
                (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n as f64 - 1.0)).sqrt();
            assert!(
                mean.abs() < 5.0 * sigma / (n as f64).sqrt(),
                "axis {axis}: mean {mean}"
            );
            assert!(
                (sd - sigma).abs() < 5.0 * sigma / (2.0 * n as f64).sqrt(),
                "axis {axis}: sd {sd}"
            );
        }
        // One stream per satellite: the same seed gives the same draws, another seed others; a
        // satellite's draw does not depend on the count.
        let few = dispenser(9, 3, 1.0, [0.0, 0.0], sigma);
        for (a, b) in few.iter().zip(&spread) {
            assert_eq!(a.velocity_mps, b.velocity_mps);
        }
        assert_ne!(
            dispenser(10, 3, 1.0, [0.0, 0.0], sigma)[0].velocity_mps,
            spread[0].velocity_mps
        );
    }

    #[test]
    fn val_ball_draws_are_uniform_in_volume() {
        // For a uniform ball, P(r < R/2) = 1/8. With 20 000 draws the standard error of the fraction is
        // sqrt(0.125 * 0.875 / 20000) = 0.0023; 5 sigma = 0.012.
        let n = 20_000;
        let inner = sphere(3, n, 1.0, Vector3::zeros())
            .iter()
            .filter(|p| p.norm() < 0.5)
            .count();
        let fraction = inner as f64 / n as f64;
        assert!((fraction - 0.125).abs() < 0.012, "fraction {fraction}");
    }

    #[test]
    fn regress_draw_of_one_satellite_does_not_depend_on_count() {
        let a = sphere(11, 10, 1.0, Vector3::zeros());
        let b = sphere(11, 1000, 1.0, Vector3::zeros());
        assert_eq!(a[..], b[..10]);
    }
}
