//! Inertial Cartesian state of one satellite ([`CartesianState`]) and the two-body invariants it
//! carries (specific energy and specific angular momentum).

use nalgebra::Vector3;

/// Position and velocity of a satellite in the Earth-centred inertial frame (ECI; the realisation,
/// e.g. GCRF/J2000, is the caller's choice, the z axis is the Earth's polar axis).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct CartesianState {
    /// Position relative to the Earth's centre, ECI \[m\].
    pub position_m: Vector3<f64>,
    /// Inertial velocity, ECI \[m/s\].
    pub velocity_mps: Vector3<f64>,
}

impl CartesianState {
    /// State from an ECI position \[m\] and ECI velocity \[m/s\].
    pub fn new(position_m: Vector3<f64>, velocity_mps: Vector3<f64>) -> Self {
        CartesianState {
            position_m,
            velocity_mps,
        }
    }

    /// `[x, y, z, vx, vy, vz]`, ECI \[m, m/s\]: the flat layout of the integrators' state slices.
    pub fn to_array(&self) -> [f64; 6] {
        let (p, v) = (self.position_m, self.velocity_mps);
        [p.x, p.y, p.z, v.x, v.y, v.z]
    }

    /// Two-body specific orbital energy `v^2/2 - mu/r` \[J/kg = m^2/s^2\] for the gravitational
    /// parameter `mu` \[m^3/s^2\]. Negative for a bound (elliptic) orbit.
    pub fn specific_energy_j_kg(&self, mu: f64) -> f64 {
        0.5 * self.velocity_mps.norm_squared() - mu / self.position_m.norm()
    }

    /// Specific angular momentum `h = r x v`, ECI \[m^2/s\].
    pub fn specific_angular_momentum_m2_s(&self) -> Vector3<f64> {
        self.position_m.cross(&self.velocity_mps)
    }
}
