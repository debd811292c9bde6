//! Obstacles: spheres the swarm must keep out of, static in the Hill LVLH frame or centred on a real
//! object's tracked path.

use nalgebra::Vector3;

use super::motion::{LinearMotion, Motion, TrackedPath};
use super::{check_detection_range, check_finite, check_finite_vector, EnvironmentError};

/// A named sphere fixed in the Hill frame (centre `center_hill_m`, m) or centred on a tracked real
/// object, of radius `radius_m` (m, > 0), with an optional per-object detection range (m).
#[derive(Clone, Debug, PartialEq)]
pub struct Obstacle {
    name: String,
    motion: Motion,
    radius_m: f64,
    detection_range_m: Option<f64>,
}

impl Obstacle {
    /// A sphere of radius `radius_m` (m, finite and > 0) centred at `center_hill_m` (Hill frame, m).
    /// No detection range is set (see [`Obstacle::with_detection_range_m`]).
    ///
    /// # Errors
    /// [`EnvironmentError::NonFiniteVector`] / [`EnvironmentError::NonFinite`] for a NaN or infinite
    /// input, [`EnvironmentError::NonPositiveRadius`] for a radius that is not > 0.
    pub fn new(
        name: impl Into<String>,
        center_hill_m: Vector3<f64>,
        radius_m: f64,
    ) -> Result<Self, EnvironmentError> {
        check_finite_vector("obstacle centre (Hill, m)", &center_hill_m)?;
        Self::with_motion(
            name,
            Motion::Line(LinearMotion::fixed(center_hill_m)),
            radius_m,
        )
    }

    /// A sphere of radius `radius_m` (m, finite and > 0) centred on a real object on the tracked `path`
    /// (placed by the engine at every segment end).
    ///
    /// # Errors
    /// As [`Obstacle::new`].
    pub fn tracked(
        name: impl Into<String>,
        path: TrackedPath,
        radius_m: f64,
    ) -> Result<Self, EnvironmentError> {
        Self::with_motion(name, Motion::Tracked(path), radius_m)
    }

    fn with_motion(
        name: impl Into<String>,
        motion: Motion,
        radius_m: f64,
    ) -> Result<Self, EnvironmentError> {
        check_finite("obstacle radius (m)", radius_m)?;
        if radius_m <= 0.0 {
            return Err(EnvironmentError::NonPositiveRadius { radius_m });
        }
        Ok(Self {
            name: name.into(),
            motion,
            radius_m,
            detection_range_m: None,
        })
    }

    /// The same obstacle with a per-object detection range `detection_range_m` (m, finite and > 0),
    /// replacing the satellites' own sensing range for it.
    ///
    /// # Errors
    /// [`EnvironmentError::InvalidDetectionRange`] when the range is not finite and > 0.
    pub fn with_detection_range_m(
        mut self,
        detection_range_m: f64,
    ) -> Result<Self, EnvironmentError> {
        self.detection_range_m = Some(check_detection_range(detection_range_m)?);
        Ok(self)
    }

    /// The obstacle's name (used in outputs).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Centre of the sphere at time `t_s` (s), Hill frame (m).
    pub fn center_hill_m(&self, t_s: f64) -> Vector3<f64> {
        self.motion.position_hill_m(t_s)
    }

    /// How the centre moves in the Hill frame (a fixed point, or a tracked path).
    pub fn motion(&self) -> &Motion {
        &self.motion
    }

    /// The motion, for the engine to place a tracked obstacle.
    pub fn motion_mut(&mut self) -> &mut Motion {
        &mut self.motion
    }

    /// Radius of the sphere (m, > 0).
    pub fn radius_m(&self) -> f64 {
        self.radius_m
    }

    /// Per-object detection range (m); `None` means the satellites' own sensing range applies.
    pub fn detection_range_m(&self) -> Option<f64> {
        self.detection_range_m
    }

    /// Signed distance (m) from `point_hill_m` (Hill frame, m) at time `t_s` (s) to the sphere's
    /// surface: positive outside, zero on the surface, negative inside (down to `−radius_m` at the
    /// centre).
    pub fn surface_distance_m(&self, point_hill_m: &Vector3<f64>, t_s: f64) -> f64 {
        (point_hill_m - self.center_hill_m(t_s)).norm() - self.radius_m
    }
}
