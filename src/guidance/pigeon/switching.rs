//! Interaction-pattern switching of the `pigeon` law: the egalitarian link rule with hysteresis (paper
//! Eq. 3), the hierarchical link rule (Eq. 4), the order parameter of a set of velocities (§2.6) and the
//! probability p_h of the hierarchical pattern (Eq. 13). Distances and velocities are 2-D, in the
//! law's pigeon plane (z, y) of the Hill frame.

use nalgebra::Vector2;

/// Speed below which a velocity has no heading: its unit vector v* counts as zero \[m/s\].
pub const HEADING_SPEED_FLOOR_MPS: f64 = 1e-9;

/// Whether a pair is linked in the egalitarian set at this sample (Eq. 3): an existing link persists
/// while the distance `distance_m` \[m\] is ≤ R_c^1 (`range_m`); a new link forms only at ≤ R_c^1 − R_L^1
/// (`range_m − delay_m`). The initial set (no previous links) is the second rule alone.
pub fn egalitarian_link(
    previously_linked: bool,
    distance_m: f64,
    range_m: f64,
    delay_m: f64,
) -> bool {
    if previously_linked {
        distance_m <= range_m
    } else {
        distance_m <= range_m - delay_m
    }
}

/// Whether a pair is linked in the hierarchical set (Eq. 4): distance `distance_m` ≤ R_c^2
/// (`range_m`) \[m\], no hysteresis.
pub fn hierarchical_link(distance_m: f64, range_m: f64) -> bool {
    distance_m <= range_m
}

/// The unit heading v* = v/‖v‖ of a pigeon-plane velocity \[m/s\] (zero below
/// [`HEADING_SPEED_FLOOR_MPS`]).
pub fn unit_heading(velocity_mps: &Vector2<f64>) -> Vector2<f64> {
    let speed = velocity_mps.norm();
    if speed < HEADING_SPEED_FLOOR_MPS {
        Vector2::zeros()
    } else {
        velocity_mps / speed
    }
}

/// Order parameter ‖Σ v*_j‖ / m of a set of m velocities \[m/s\] (the Vicsek order parameter, in
/// \[0, 1\]; 0 for an empty set).
pub fn order_parameter<'a>(velocities_mps: impl IntoIterator<Item = &'a Vector2<f64>>) -> f64 {
    let (mut sum, mut count) = (Vector2::zeros(), 0usize);
    for v in velocities_mps {
        sum += unit_heading(v);
        count += 1;
    }
    if count == 0 {
        0.0
    } else {
        sum.norm() / count as f64
    }
}

/// Probability of the hierarchical pattern, p_h = 1/(1 + α e^(−β(1 − V_a))) (Eq. 13), for an order
/// parameter V_a in \[0, 1\], α > 1, β > 0.
pub fn hierarchical_probability(order_parameter: f64, alpha: f64, beta: f64) -> f64 {
    1.0 / (1.0 + alpha * (-beta * (1.0 - order_parameter)).exp())
}
