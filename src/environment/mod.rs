//! Environment objects of a run and the geometry of the continuous truth monitor.
//!
//! Everything here lives in the Hill/RSW LVLH frame of the reference orbit (x radial out, y along-track,
//! z orbit normal; see [`crate::orbit::LvlhFrame`]), in SI units (m, s, m/s).
//!
//! | module | holds |
//! | --- | --- |
//! | [`motion`] | [`Motion`]: how an object moves — a straight line ([`LinearMotion`], a fixed point for a static obstacle) or a real object's [`TrackedPath`], placed by the engine at every segment end |
//! | [`threat`] | [`Threat`]: an object on a straight line at constant velocity in the Hill frame or on a tracked path, with a danger radius |
//! | [`obstacle`] | [`Obstacle`]: a sphere static in the Hill frame or centred on a tracked path |
//! | [`closest_approach`] | [`HermiteSegment`] (a satellite's path over one integration segment) and the exact minimum distance of such a segment to a moving line or a fixed point |
//! | [`monitor`] | [`ApproachMonitor`]: per-run minima of satellite–threat distance and satellite–obstacle clearance, and incursion counts |
//!
//! The monitor is "continuous": it does not sample states at recording times but takes the exact minimum
//! over each integration segment of the segment's cubic Hermite interpolant (built from the states and
//! velocities at both ends, which the integrator already has), so a fast threat cannot slip between two
//! samples unseen.

use thiserror::Error;

pub mod closest_approach;
pub mod monitor;
pub mod motion;
pub mod obstacle;
pub mod threat;

pub use closest_approach::{
    closest_approach_to_line, closest_approach_to_threat, min_distance_to_point,
    obstacle_clearance, Approach, Clearance, HermiteSegment,
};
pub use monitor::{ApproachMonitor, PairMinimum};
pub use motion::{LinearMotion, Motion, TrackedPath};
pub use obstacle::Obstacle;
pub use threat::Threat;

/// Why an environment object, a segment or a monitor call was refused. Each variant carries the
/// offending numbers.
#[derive(Clone, Debug, PartialEq, Error)]
#[non_exhaustive]
pub enum EnvironmentError {
    /// A scalar input is NaN or infinite.
    #[error("{what} = {value} must be finite")]
    NonFinite {
        /// Which input, with its unit (e.g. "arrival time (s)").
        what: &'static str,
        /// The rejected value.
        value: f64,
    },
    /// A vector input has a NaN or infinite component.
    #[error("{what} = {value:?} has a non-finite component; all must be finite")]
    NonFiniteVector {
        /// Which input, with its frame and unit (e.g. "threat position (Hill, m)").
        what: &'static str,
        /// The rejected vector's components.
        value: [f64; 3],
    },
    /// A radius that may be zero is negative.
    #[error("{what} {radius_m} m must be >= 0")]
    NegativeRadius {
        /// Which radius (e.g. "danger radius").
        what: &'static str,
        /// The rejected radius (m).
        radius_m: f64,
    },
    /// An obstacle radius is zero or negative.
    #[error("obstacle radius {radius_m} m must be > 0")]
    NonPositiveRadius {
        /// The rejected radius (m).
        radius_m: f64,
    },
    /// A per-object detection range is zero, negative or not finite.
    #[error("detection range {detection_range_m} m must be finite and > 0 (leave it unset to use the satellites' own sensing range)")]
    InvalidDetectionRange {
        /// The rejected range (m).
        detection_range_m: f64,
    },
    /// A threat speed given as a scalar is zero, negative or not finite.
    #[error(
        "threat speed {speed_mps} m/s must be finite and > 0 (a static object is an Obstacle)"
    )]
    InvalidSpeed {
        /// The rejected speed (m/s).
        speed_mps: f64,
    },
    /// A threat velocity vector is zero.
    #[error("threat velocity {velocity_hill_mps:?} m/s (Hill) is zero; a threat must move (a static object is an Obstacle)")]
    ZeroVelocity {
        /// The rejected velocity (Hill frame, m/s).
        velocity_hill_mps: [f64; 3],
    },
    /// A direction of travel is the zero vector.
    #[error("direction of travel {direction_hill:?} (Hill) has zero length")]
    ZeroDirection {
        /// The rejected direction (Hill frame, any scale).
        direction_hill: [f64; 3],
    },
    /// A segment does not run forward in time.
    #[error("segment end time {t1_s} s must be later than its start time {t0_s} s")]
    SegmentTimes {
        /// Start time (s).
        t0_s: f64,
        /// End time (s).
        t1_s: f64,
    },
    /// A satellite index is out of range for the monitor.
    #[error(
        "satellite index {index} is out of range: the monitor was built for {count} satellites"
    )]
    SatelliteIndex {
        /// The rejected index.
        index: usize,
        /// Number of satellites the monitor holds.
        count: usize,
    },
    /// The objects passed to the monitor are not as many as it was built for.
    #[error("{what}: {got} given, the monitor was built for {expected}")]
    ObjectCount {
        /// Which objects ("threats" or "obstacles").
        what: &'static str,
        /// Number the monitor was built for.
        expected: usize,
        /// Number given.
        got: usize,
    },
}

/// `Ok(())` if `value` is finite, else [`EnvironmentError::NonFinite`] naming `what`.
pub(crate) fn check_finite(what: &'static str, value: f64) -> Result<(), EnvironmentError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(EnvironmentError::NonFinite { what, value })
    }
}

/// `Ok(())` if every component of `v` is finite, else [`EnvironmentError::NonFiniteVector`].
pub(crate) fn check_finite_vector(
    what: &'static str,
    v: &nalgebra::Vector3<f64>,
) -> Result<(), EnvironmentError> {
    if v.iter().all(|c| c.is_finite()) {
        Ok(())
    } else {
        Err(EnvironmentError::NonFiniteVector {
            what,
            value: [v.x, v.y, v.z],
        })
    }
}

/// Checks a per-object detection range: finite and > 0 m.
pub(crate) fn check_detection_range(detection_range_m: f64) -> Result<f64, EnvironmentError> {
    if detection_range_m.is_finite() && detection_range_m > 0.0 {
        Ok(detection_range_m)
    } else {
        Err(EnvironmentError::InvalidDetectionRange { detection_range_m })
    }
}
