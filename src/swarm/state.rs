//! The swarm's state as structure-of-arrays: one flat `f64` buffer that the integrators step as a whole.
//!
//! Layout (component-major, so each component of all satellites is contiguous):
//!
//! | range | holds | unit |
//! | --- | --- | --- |
//! | `0..6` | reference orbit: x, y, z, vx, vy, vz | m, m/s, ECI |
//! | `6 + k*N .. 6 + (k+1)*N`, k = 0..6 | satellites' x, y, z, vx, vy, vz | m, m/s, in the dynamics frame |
//! | `6 + 6N + k*N ..`, k = 0..4 | delta-v ledger: ∫\|a_x\|dt, ∫\|a_y\|dt, ∫\|a_z\|dt (LVLH Hill axes), ∫‖a‖dt | m/s |
//!
//! The dynamics frame is ECI for the inertial truth models and the Hill LVLH frame of the reference orbit
//! for the linear relative models (see [`super::dynamics::DynamicsModel`]). Keeping the ledger inside the
//! integrated state makes the delta-v the integral of the applied acceleration to the integrator's own order.

use nalgebra::Vector3;

/// Number of state components per satellite (position and velocity).
pub const SATELLITE_COMPONENTS: usize = 6;
/// Number of delta-v ledger components per satellite (three LVLH axes and the norm).
pub const LEDGER_COMPONENTS: usize = 4;
/// Number of state components of the reference orbit.
pub const REFERENCE_COMPONENTS: usize = 6;

/// Structure-of-arrays state of the reference orbit, N satellites and their delta-v ledgers.
#[derive(Clone, Debug, PartialEq)]
pub struct SwarmState {
    n: usize,
    data: Vec<f64>,
}

impl SwarmState {
    /// A zeroed state for `n` satellites.
    pub fn zeros(n: usize) -> Self {
        Self {
            n,
            data: vec![0.0; Self::len_for(n)],
        }
    }

    /// Length of the flat buffer for `n` satellites.
    pub fn len_for(n: usize) -> usize {
        REFERENCE_COMPONENTS + (SATELLITE_COMPONENTS + LEDGER_COMPONENTS) * n
    }

    /// Number of satellites.
    pub fn n(&self) -> usize {
        self.n
    }

    /// The whole flat buffer (what the integrator steps).
    pub fn as_slice(&self) -> &[f64] {
        &self.data
    }

    /// The whole flat buffer, mutable.
    pub fn as_mut_slice(&mut self) -> &mut [f64] {
        &mut self.data
    }

    /// Reference orbit position \[m\] and velocity \[m/s\], ECI.
    pub fn reference(&self) -> (Vector3<f64>, Vector3<f64>) {
        reference_of(&self.data)
    }

    /// Sets the reference orbit position \[m\] and velocity \[m/s\], ECI.
    pub fn set_reference(&mut self, position_m: &Vector3<f64>, velocity_mps: &Vector3<f64>) {
        self.data[0..3].copy_from_slice(position_m.as_slice());
        self.data[3..6].copy_from_slice(velocity_mps.as_slice());
    }

    /// Position \[m\] and velocity \[m/s\] of satellite `i`, in the dynamics frame.
    pub fn satellite(&self, i: usize) -> (Vector3<f64>, Vector3<f64>) {
        satellite_of(&self.data, self.n, i)
    }

    /// Sets satellite `i`'s position \[m\] and velocity \[m/s\], in the dynamics frame.
    pub fn set_satellite(
        &mut self,
        i: usize,
        position_m: &Vector3<f64>,
        velocity_mps: &Vector3<f64>,
    ) {
        let n = self.n;
        for k in 0..3 {
            self.data[satellite_index(n, k, i)] = position_m[k];
            self.data[satellite_index(n, k + 3, i)] = velocity_mps[k];
        }
    }

    /// Every per-satellite component (x, y, z, vx, vy, vz, then the four ledger components), each as
    /// one slice over the satellites.
    pub(crate) fn satellite_components(&self) -> impl Iterator<Item = &[f64]> {
        self.data[REFERENCE_COMPONENTS..].chunks_exact(self.n.max(1))
    }

    /// [`Self::satellite_components`], mutable.
    pub(crate) fn satellite_components_mut(&mut self) -> impl Iterator<Item = &mut [f64]> {
        let n = self.n;
        self.data[REFERENCE_COMPONENTS..].chunks_exact_mut(n.max(1))
    }

    /// Delta-v ledger of satellite `i`: per LVLH Hill axis \[m/s\] and in norm \[m/s\].
    pub fn ledger(&self, i: usize) -> ([f64; 3], f64) {
        let n = self.n;
        let d = &self.data;
        (
            [
                d[ledger_index(n, 0, i)],
                d[ledger_index(n, 1, i)],
                d[ledger_index(n, 2, i)],
            ],
            d[ledger_index(n, 3, i)],
        )
    }
}

/// Index in the flat buffer of component `k` (0..6) of satellite `i`, for `n` satellites.
#[inline]
pub fn satellite_index(n: usize, k: usize, i: usize) -> usize {
    REFERENCE_COMPONENTS + k * n + i
}

/// Index in the flat buffer of ledger component `k` (0..4) of satellite `i`, for `n` satellites.
#[inline]
pub fn ledger_index(n: usize, k: usize, i: usize) -> usize {
    REFERENCE_COMPONENTS + SATELLITE_COMPONENTS * n + k * n + i
}

/// Reference position \[m\] and velocity \[m/s\] (ECI) read from a flat buffer.
#[inline]
pub fn reference_of(data: &[f64]) -> (Vector3<f64>, Vector3<f64>) {
    (
        Vector3::new(data[0], data[1], data[2]),
        Vector3::new(data[3], data[4], data[5]),
    )
}

/// Satellite `i`'s position \[m\] and velocity \[m/s\] read from a flat buffer of `n` satellites.
#[inline]
pub fn satellite_of(data: &[f64], n: usize, i: usize) -> (Vector3<f64>, Vector3<f64>) {
    let at = |k| data[satellite_index(n, k, i)];
    (
        Vector3::new(at(0), at(1), at(2)),
        Vector3::new(at(3), at(4), at(5)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regress_layout_round_trip() {
        let mut s = SwarmState::zeros(3);
        s.set_reference(&Vector3::new(1.0, 2.0, 3.0), &Vector3::new(4.0, 5.0, 6.0));
        s.set_satellite(
            1,
            &Vector3::new(7.0, 8.0, 9.0),
            &Vector3::new(10.0, 11.0, 12.0),
        );
        assert_eq!(s.reference().0, Vector3::new(1.0, 2.0, 3.0));
        assert_eq!(s.satellite(1).1, Vector3::new(10.0, 11.0, 12.0));
        assert_eq!(s.satellite(0).0, Vector3::zeros());
        assert_eq!(s.as_slice().len(), 6 + 10 * 3);
        // x components are contiguous: satellites 0, 1, 2 then y components
        assert_eq!(s.as_slice()[6 + 1], 7.0);
        assert_eq!(s.as_slice()[6 + 3 + 1], 8.0);
    }
}
