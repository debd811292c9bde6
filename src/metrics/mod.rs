//! Cluster metrics: pure functions of a swarm's state snapshot.
//!
//! | module | holds |
//! | --- | --- |
//! | [`mod@five_elements`] | the five-element cluster characterisation of Gao et al. 2022 (N, r_o/v_o, d_max, d_min, L), `docs/methods/bifurcating.md` §2 |
//! | [`separation`] | minimum centre-to-centre separation and hard-body collision counts |
//! | `close_pairs` | the pairs of satellites close at the separation tracker's last full search, for swarms whose satellites tie at their nearest distances |
//! | `motion_fit` | the least-squares affine motion of a swarm between two snapshots: the separation tracker's bound |
//!
//! Large swarms (N = 1e5) are handled exactly, without O(N²) loops in the common cases: nearest
//! neighbours come from the cell-list grid [`crate::grid::NeighbourGrid`].

use thiserror::Error;

use crate::grid::NeighbourError;

mod close_pairs;
pub mod five_elements;
mod motion_fit;
pub mod separation;

pub use five_elements::{five_elements, FiveElements, FiveElementsWorkspace};
pub(crate) use separation::TrackedPositions;
pub use separation::{min_separation, Separation, SeparationTracker};

/// Why a metric could not be computed.
#[derive(Clone, Debug, PartialEq, Error)]
#[non_exhaustive]
pub enum MetricsError {
    /// The metric needs pairs of satellites.
    #[error("at least 2 satellites are needed, got {n}")]
    TooFewSatellites {
        /// Number of satellites given.
        n: usize,
    },
    /// An input slice does not have one entry per satellite.
    #[error("{what} has {got} entries, expected {expected} (one per satellite)")]
    LengthMismatch {
        /// Which input (e.g. "velocities").
        what: &'static str,
        /// Number of satellites.
        expected: usize,
        /// Length given.
        got: usize,
    },
    /// A position or velocity component is NaN or infinite.
    #[error("{what} of satellite {index} is not finite")]
    NonFinite {
        /// Which input (e.g. "position").
        what: &'static str,
        /// Index of the offending satellite.
        index: usize,
    },
    /// A position or velocity component is finite but so large that squares of distances overflow.
    #[error(
        "{what} of satellite {index} has a coordinate of magnitude {value:e}, too large for distances \
         (allowed: |coordinate| <= {limit:e}; check the units)"
    )]
    OutOfRange {
        /// Which input (e.g. "position").
        what: &'static str,
        /// Index of the offending satellite.
        index: usize,
        /// The largest magnitude of its coordinates.
        value: f64,
        /// The limit, [`MAX_COORDINATE`].
        limit: f64,
    },
    /// A physical radius is negative, NaN or infinite.
    #[error("radius of satellite {index} must be finite and >= 0 m, got {radius_m} m")]
    InvalidRadius {
        /// Index of the offending satellite.
        index: usize,
        /// The rejected radius (m).
        radius_m: f64,
    },
    /// Satellite identifiers that should be strictly ascending are not.
    #[error(
        "satellite ids must be strictly ascending; entry {index} is not above the one before it"
    )]
    UnorderedIds {
        /// Position of the first offending entry.
        index: usize,
    },
    /// A satellite identifier too large for the separation tracker, which keeps 32 bytes per id up
    /// to the largest (ids are meant to be dense, like storage indices).
    #[error("satellite id {id} is too large for the separation tracker (allowed: id < {limit})")]
    IdTooLarge {
        /// The largest id given.
        id: usize,
        /// The bound, [`crate::grid::MAX_POINTS`].
        limit: usize,
    },
    /// The neighbour grid rejected its input.
    #[error(transparent)]
    Grid(#[from] NeighbourError),
}

/// Largest coordinate magnitude accepted by the metrics: squares of differences of coordinates up to
/// 1e150 stay far below f64's 1.8e308, so no distance overflows to infinity.
pub const MAX_COORDINATE: f64 = 1e150;

/// Checks that `radii_m` has `n` finite, non-negative entries and returns the largest (m).
pub(crate) fn check_radii(radii_m: &[f64], n: usize) -> Result<f64, MetricsError> {
    if radii_m.len() != n {
        return Err(MetricsError::LengthMismatch {
            what: "radii",
            expected: n,
            got: radii_m.len(),
        });
    }
    // One branch-free pass (it vectorises): every radius valid, and their maximum; the first invalid
    // one is looked for only when there is one.
    let (all_valid, a_max) = radii_m.iter().fold((true, 0.0_f64), |(valid, a_max), &r| {
        let ok = r.is_finite() & (r >= 0.0);
        (valid & ok, if ok & (r > a_max) { r } else { a_max })
    });
    if !all_valid {
        let (index, &radius_m) = radii_m
            .iter()
            .enumerate()
            .find(|(_, r)| !(r.is_finite() && **r >= 0.0))
            .expect("an invalid radius was seen");
        return Err(MetricsError::InvalidRadius { index, radius_m });
    }
    Ok(a_max)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The largest radius of valid radii (zero for none), and the first invalid one (NaN, infinite or
    /// negative) named by its index even when later ones are invalid too.
    #[test]
    fn radii_are_checked_and_their_largest_returned() {
        assert_eq!(check_radii(&[0.5, 2.0, 0.0, 1.5], 4), Ok(2.0));
        assert_eq!(check_radii(&[], 0), Ok(0.0));
        for (bad, index) in [(f64::NAN, 2), (f64::INFINITY, 2), (-0.1, 2)] {
            let radii = [0.5, 3.0, bad, -7.0, f64::NAN];
            match check_radii(&radii, 5) {
                Err(MetricsError::InvalidRadius { index: i, radius_m }) => {
                    assert_eq!(i, index);
                    assert_eq!(radius_m.to_bits(), bad.to_bits());
                }
                other => panic!("{bad}: {other:?}"),
            }
        }
        assert!(matches!(
            check_radii(&[1.0], 2),
            Err(MetricsError::LengthMismatch { .. })
        ));
    }
}
