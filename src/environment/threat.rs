//! Threats: kinematic objects with a danger radius the swarm must stay out of, moving either on a
//! straight line at constant velocity in the Hill LVLH frame or along a real object's tracked path.
//!
//! A threat given by a line takes the Hill frame as the frame of its straight line, as the threat paper
//! does: it is not propagated under gravity, its Hill position is `p(t) = p_ref + v (t − t_ref)`. A
//! threat from an element set or a state is a real object: the engine places it in the Hill frame at
//! every segment end from its own orbit ([`TrackedPath`]).

use nalgebra::Vector3;

use super::motion::{LinearMotion, Motion, TrackedPath};
use super::{check_detection_range, check_finite, check_finite_vector, EnvironmentError};

/// A threat: a named object on a straight line at constant, non-zero velocity in the Hill frame or on a
/// tracked path, with a danger radius (m) around its centre and an optional per-object detection range
/// (m).
#[derive(Clone, Debug, PartialEq)]
pub struct Threat {
    name: String,
    motion: Motion,
    danger_radius_m: f64,
    detection_range_m: Option<f64>,
}

impl Threat {
    /// A threat at `position_hill_m` (Hill, m) at time `reference_time_s` (s), moving at the constant
    /// `velocity_hill_mps` (Hill, m/s), with danger radius `danger_radius_m` (m, ≥ 0; 0 is a point).
    /// No detection range is set (see [`Threat::with_detection_range_m`]).
    ///
    /// # Errors
    /// [`EnvironmentError::NonFinite`] / [`EnvironmentError::NonFiniteVector`] for a NaN or infinite
    /// input, [`EnvironmentError::NegativeRadius`] for a negative danger radius,
    /// [`EnvironmentError::ZeroVelocity`] for a threat that does not move.
    pub fn from_state(
        name: impl Into<String>,
        reference_time_s: f64,
        position_hill_m: Vector3<f64>,
        velocity_hill_mps: Vector3<f64>,
        danger_radius_m: f64,
    ) -> Result<Self, EnvironmentError> {
        check_finite("threat reference time (s)", reference_time_s)?;
        check_finite_vector("threat position (Hill, m)", &position_hill_m)?;
        check_finite_vector("threat velocity (Hill, m/s)", &velocity_hill_mps)?;
        check_danger_radius(danger_radius_m)?;
        if velocity_hill_mps == Vector3::zeros() {
            return Err(EnvironmentError::ZeroVelocity {
                velocity_hill_mps: [
                    velocity_hill_mps.x,
                    velocity_hill_mps.y,
                    velocity_hill_mps.z,
                ],
            });
        }
        Ok(Self {
            name: name.into(),
            motion: Motion::Line(LinearMotion {
                reference_time_s,
                reference_position_hill_m: position_hill_m,
                velocity_hill_mps,
            }),
            danger_radius_m,
            detection_range_m: None,
        })
    }

    /// A threat that travels along `direction_hill` (Hill frame, any non-zero length: it is normalised
    /// here) at `speed_mps` (m/s, > 0) and passes the aim point `aim_point_hill_m` (Hill, m) at
    /// `arrival_time_s` (s), with danger radius `danger_radius_m` (m, ≥ 0).
    ///
    /// The line's reference time is the arrival time, so `position_hill_m(arrival_time_s)` returns the
    /// aim point exactly.
    ///
    /// # Errors
    /// [`EnvironmentError::NonFinite`] / [`EnvironmentError::NonFiniteVector`] for a NaN or infinite
    /// input, [`EnvironmentError::ZeroDirection`] for a zero direction, [`EnvironmentError::InvalidSpeed`]
    /// for a speed that is not > 0, [`EnvironmentError::NegativeRadius`] for a negative danger radius.
    pub fn from_aim(
        name: impl Into<String>,
        aim_point_hill_m: Vector3<f64>,
        direction_hill: Vector3<f64>,
        speed_mps: f64,
        arrival_time_s: f64,
        danger_radius_m: f64,
    ) -> Result<Self, EnvironmentError> {
        check_finite_vector("threat aim point (Hill, m)", &aim_point_hill_m)?;
        check_finite_vector("threat direction of travel (Hill)", &direction_hill)?;
        check_finite("threat arrival time (s)", arrival_time_s)?;
        if !(speed_mps.is_finite() && speed_mps > 0.0) {
            return Err(EnvironmentError::InvalidSpeed { speed_mps });
        }
        check_danger_radius(danger_radius_m)?;
        // Scaled by its largest component first, so that neither overflow (components near f64::MAX)
        // nor underflow (denormal components) spoils the norm; the scaled norm is in [1, √3].
        let scale = direction_hill.amax();
        if scale == 0.0 {
            return Err(EnvironmentError::ZeroDirection {
                direction_hill: [direction_hill.x, direction_hill.y, direction_hill.z],
            });
        }
        let scaled = direction_hill / scale;
        let norm = scaled.norm();
        let velocity_hill_mps = scaled * (speed_mps / norm);
        if velocity_hill_mps == Vector3::zeros() {
            // Only reachable by underflow (a denormal speed): the threat would not move.
            return Err(EnvironmentError::InvalidSpeed { speed_mps });
        }
        Ok(Self {
            name: name.into(),
            motion: Motion::Line(LinearMotion {
                reference_time_s: arrival_time_s,
                reference_position_hill_m: aim_point_hill_m,
                velocity_hill_mps,
            }),
            danger_radius_m,
            detection_range_m: None,
        })
    }

    /// A real object as a threat: on the tracked `path` (placed by the engine at every segment end),
    /// with danger radius `danger_radius_m` (m, ≥ 0). Its velocity may be anything, zero included.
    ///
    /// # Errors
    /// [`EnvironmentError::NonFinite`] / [`EnvironmentError::NegativeRadius`] for a bad danger radius.
    pub fn tracked(
        name: impl Into<String>,
        path: TrackedPath,
        danger_radius_m: f64,
    ) -> Result<Self, EnvironmentError> {
        check_danger_radius(danger_radius_m)?;
        Ok(Self {
            name: name.into(),
            motion: Motion::Tracked(path),
            danger_radius_m,
            detection_range_m: None,
        })
    }

    /// The same threat with a per-object detection range `detection_range_m` (m, finite and > 0): the
    /// distance at which satellites sense this threat, replacing their own sensing range for it.
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

    /// The threat's name (used in outputs).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Danger radius around the threat's centre (m, ≥ 0): a satellite closer than this is inside.
    pub fn danger_radius_m(&self) -> f64 {
        self.danger_radius_m
    }

    /// Per-object detection range (m); `None` means the satellites' own sensing range applies.
    pub fn detection_range_m(&self) -> Option<f64> {
        self.detection_range_m
    }

    /// How the threat moves in the Hill frame.
    pub fn motion(&self) -> &Motion {
        &self.motion
    }

    /// The motion, for the engine to place a tracked threat.
    pub fn motion_mut(&mut self) -> &mut Motion {
        &mut self.motion
    }

    /// Position at time `t_s` (s), Hill frame (m).
    pub fn position_hill_m(&self, t_s: f64) -> Vector3<f64> {
        self.motion.position_hill_m(t_s)
    }

    /// Velocity at time `t_s` (s), Hill frame (m/s) (constant on a line).
    pub fn velocity_hill_mps(&self, t_s: f64) -> Vector3<f64> {
        self.motion.velocity_hill_mps(t_s)
    }
}

fn check_danger_radius(danger_radius_m: f64) -> Result<(), EnvironmentError> {
    check_finite("threat danger radius (m)", danger_radius_m)?;
    if danger_radius_m < 0.0 {
        return Err(EnvironmentError::NegativeRadius {
            what: "threat danger radius",
            radius_m: danger_radius_m,
        });
    }
    Ok(())
}
