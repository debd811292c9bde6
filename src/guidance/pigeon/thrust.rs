//! Step 5 of the paper's Algorithm 1: the thrust that realises the desired accelerations on the
//! Clohessy–Wiltshire (CW/HCW) equations, its per-axis saturation, and the accelerations the saturated
//! thrust actually produces (`docs/methods/pigeon.md`, with the paper's Eq. 18 corrected to the CW y-equation).
//!
//! CW, Hill frame (x radial out, y along-track, z orbit normal), mean motion n \[rad/s\]:
//! ẍ − 2nẏ − 3n²x = f^x, ÿ + 2nẋ = f^y, z̈ + n²z = f^z \[m/s²\].

use nalgebra::{Vector2, Vector3};

/// The thrust of one satellite at one sample and what it achieves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CwThrust {
    /// f: the thrust per unit mass that gives the desired accelerations exactly, Hill \[m/s²\].
    pub required_m_s2: Vector3<f64>,
    /// f̄: f clipped per axis to \[−limit, limit\], Hill \[m/s²\] (the law's command).
    pub saturated_m_s2: Vector3<f64>,
    /// The pigeon-plane acceleration (z̈, ÿ) f̄ produces: (f̄^z − n²z, f̄^y − 2nẋ) \[m/s²\].
    pub pigeon_accel_m_s2: Vector2<f64>,
    /// The radial acceleration ẍ f̄ produces: f̄^x + 2nẏ + 3n²x \[m/s²\].
    pub radial_accel_m_s2: f64,
}

/// The CW inverse, saturation and back-substitution for a satellite at `position_m`, `velocity_mps`
/// (Hill, relative to the LVLH origin \[m, m/s\]) that wants the pigeon-plane acceleration
/// `pigeon_accel_m_s2` = (z̈, ÿ) and the radial acceleration `radial_accel_m_s2` \[m/s²\], on a reference
/// of mean motion `mean_motion_rad_s`, with the per-axis limit `limit_m_s2` \[m/s²\] (may be infinite).
pub fn cw_thrust(
    position_m: &Vector3<f64>,
    velocity_mps: &Vector3<f64>,
    pigeon_accel_m_s2: &Vector2<f64>,
    radial_accel_m_s2: f64,
    mean_motion_rad_s: f64,
    limit_m_s2: f64,
) -> CwThrust {
    let n = mean_motion_rad_s;
    let (x, z) = (position_m.x, position_m.z);
    let (vx, vy) = (velocity_mps.x, velocity_mps.y);
    let required = Vector3::new(
        radial_accel_m_s2 - 2.0 * n * vy - 3.0 * n * n * x,
        pigeon_accel_m_s2[1] + 2.0 * n * vx,
        pigeon_accel_m_s2[0] + n * n * z,
    );
    let saturated = required.map(|f| f.clamp(-limit_m_s2, limit_m_s2));
    CwThrust {
        required_m_s2: required,
        saturated_m_s2: saturated,
        pigeon_accel_m_s2: Vector2::new(saturated.z - n * n * z, saturated.y - 2.0 * n * vx),
        radial_accel_m_s2: saturated.x + 2.0 * n * vy + 3.0 * n * n * x,
    }
}
