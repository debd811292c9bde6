//! How an environment object moves in the Hill frame: on a straight line at constant velocity (a fixed
//! point for a static obstacle), or along a tracked path — a real object's motion, placed by the engine
//! at every segment end from the object's own orbit (SGP4 from its element set, or the run's truth
//! dynamics) and interpolated over the segment by the cubic Hermite of its two end states, exactly as a
//! satellite's own path is ([`HermiteSegment`]).

use nalgebra::Vector3;

use super::closest_approach::HermiteSegment;
use super::{check_finite, check_finite_vector, EnvironmentError};

/// Uniform straight-line motion in the Hill frame: `p(t) = reference_position_hill_m +
/// velocity_hill_mps · (t − reference_time_s)`.
///
/// A plain value (zero velocity allowed: a fixed point); [`crate::environment::Threat`] validates its
/// own line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearMotion {
    /// Time at which the object is at `reference_position_hill_m` (s).
    pub reference_time_s: f64,
    /// Position at `reference_time_s` (Hill frame, m).
    pub reference_position_hill_m: Vector3<f64>,
    /// Constant velocity (Hill frame, m/s).
    pub velocity_hill_mps: Vector3<f64>,
}

impl LinearMotion {
    /// A fixed point (zero velocity) at `position_hill_m` (Hill frame, m).
    pub fn fixed(position_hill_m: Vector3<f64>) -> Self {
        Self {
            reference_time_s: 0.0,
            reference_position_hill_m: position_hill_m,
            velocity_hill_mps: Vector3::zeros(),
        }
    }

    /// Position at time `t_s` (s), Hill frame (m).
    pub fn position_hill_m(&self, t_s: f64) -> Vector3<f64> {
        self.reference_position_hill_m + self.velocity_hill_mps * (t_s - self.reference_time_s)
    }
}

/// One placement of a tracked object: its Hill state at a time.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Placement {
    time_s: f64,
    position_hill_m: Vector3<f64>,
    velocity_hill_mps: Vector3<f64>,
}

/// A real object's path in the Hill frame, known at the ends of the engine's segments: its Hill state
/// at the latest placement and at the one before, the segment between them interpolated by cubic
/// Hermite (the same interpolant, and the same error `h⁴/384 · max|r⁽⁴⁾|`, as the satellites' paths).
///
/// Between placements the path is exact at both ends; before the first segment (one placement only)
/// and after the latest placement it is extrapolated linearly from the nearest placement's state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrackedPath {
    previous: Placement,
    latest: Placement,
}

impl TrackedPath {
    /// A path placed once, at `time_s` (s), at `position_hill_m` (Hill, m) moving at
    /// `velocity_hill_mps` (Hill, m/s).
    ///
    /// # Errors
    /// [`EnvironmentError::NonFinite`] / [`EnvironmentError::NonFiniteVector`] for a NaN or infinite
    /// input.
    pub fn new(
        time_s: f64,
        position_hill_m: Vector3<f64>,
        velocity_hill_mps: Vector3<f64>,
    ) -> Result<Self, EnvironmentError> {
        let placement = placement(time_s, position_hill_m, velocity_hill_mps)?;
        Ok(Self {
            previous: placement,
            latest: placement,
        })
    }

    /// Places the object at `time_s` (s, later than the latest placement): the segment from the latest
    /// placement to this one becomes the path's interpolated segment.
    ///
    /// # Errors
    /// As [`TrackedPath::new`], and [`EnvironmentError::SegmentTimes`] unless `time_s` is later than
    /// the latest placement; the path is unchanged then.
    pub fn advance(
        &mut self,
        time_s: f64,
        position_hill_m: Vector3<f64>,
        velocity_hill_mps: Vector3<f64>,
    ) -> Result<(), EnvironmentError> {
        let next = placement(time_s, position_hill_m, velocity_hill_mps)?;
        if time_s <= self.latest.time_s {
            return Err(EnvironmentError::SegmentTimes {
                t0_s: self.latest.time_s,
                t1_s: time_s,
            });
        }
        self.previous = self.latest;
        self.latest = next;
        Ok(())
    }

    /// Time of the latest placement (s).
    pub fn latest_time_s(&self) -> f64 {
        self.latest.time_s
    }

    /// The segment between the two latest placements (`None` while placed once).
    fn segment(&self) -> Option<HermiteSegment> {
        let (a, b) = (&self.previous, &self.latest);
        (b.time_s > a.time_s).then_some(HermiteSegment {
            t0_s: a.time_s,
            t1_s: b.time_s,
            p0_hill_m: a.position_hill_m,
            v0_hill_mps: a.velocity_hill_mps,
            p1_hill_m: b.position_hill_m,
            v1_hill_mps: b.velocity_hill_mps,
        })
    }

    /// Position at `t_s` (s), Hill frame (m): exact at the placements.
    pub fn position_hill_m(&self, t_s: f64) -> Vector3<f64> {
        match self.placed_at(t_s) {
            Some(p) => p.position_hill_m,
            None => match self.segment_over(t_s) {
                Some(segment) => segment.position_hill_m(t_s),
                None => {
                    let p = self.nearest(t_s);
                    p.position_hill_m + p.velocity_hill_mps * (t_s - p.time_s)
                }
            },
        }
    }

    /// Velocity at `t_s` (s), Hill frame (m/s): exact at the placements.
    pub fn velocity_hill_mps(&self, t_s: f64) -> Vector3<f64> {
        match self.placed_at(t_s) {
            Some(p) => p.velocity_hill_mps,
            None => match self.segment_over(t_s) {
                Some(segment) => segment.velocity_hill_mps(t_s),
                None => self.nearest(t_s).velocity_hill_mps,
            },
        }
    }

    fn placed_at(&self, t_s: f64) -> Option<&Placement> {
        [&self.latest, &self.previous]
            .into_iter()
            .find(|p| p.time_s == t_s)
    }

    fn segment_over(&self, t_s: f64) -> Option<HermiteSegment> {
        self.segment().filter(|s| (s.t0_s..=s.t1_s).contains(&t_s))
    }

    fn nearest(&self, t_s: f64) -> &Placement {
        if t_s < self.previous.time_s {
            &self.previous
        } else {
            &self.latest
        }
    }

    /// The object's path over `[t0_s, t1_s]` as a cubic Hermite segment of its states at both ends
    /// (the path's own segment when the times are its placements).
    fn over(&self, t0_s: f64, t1_s: f64) -> HermiteSegment {
        HermiteSegment {
            t0_s,
            t1_s,
            p0_hill_m: self.position_hill_m(t0_s),
            v0_hill_mps: self.velocity_hill_mps(t0_s),
            p1_hill_m: self.position_hill_m(t1_s),
            v1_hill_mps: self.velocity_hill_mps(t1_s),
        }
    }
}

fn placement(
    time_s: f64,
    position_hill_m: Vector3<f64>,
    velocity_hill_mps: Vector3<f64>,
) -> Result<Placement, EnvironmentError> {
    check_finite("tracked object time (s)", time_s)?;
    check_finite_vector("tracked object position (Hill, m)", &position_hill_m)?;
    check_finite_vector("tracked object velocity (Hill, m/s)", &velocity_hill_mps)?;
    Ok(Placement {
        time_s,
        position_hill_m,
        velocity_hill_mps,
    })
}

/// How a threat or an obstacle moves in the Hill frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Motion {
    /// A straight line at constant velocity (zero for a static obstacle).
    Line(LinearMotion),
    /// A real object's path, placed by the engine at every segment end.
    Tracked(TrackedPath),
}

impl Motion {
    /// Position at `t_s` (s), Hill frame (m).
    pub fn position_hill_m(&self, t_s: f64) -> Vector3<f64> {
        match self {
            Motion::Line(line) => line.position_hill_m(t_s),
            Motion::Tracked(path) => path.position_hill_m(t_s),
        }
    }

    /// Velocity at `t_s` (s), Hill frame (m/s).
    pub fn velocity_hill_mps(&self, t_s: f64) -> Vector3<f64> {
        match self {
            Motion::Line(line) => line.velocity_hill_mps,
            Motion::Tracked(path) => path.velocity_hill_mps(t_s),
        }
    }

    /// Coefficients `[c0, c1, c2, c3]` (m) of `d(s) = segment(s) − object(s)` in
    /// `s = (t − t0) / h` over the segment's times.
    pub(crate) fn relative_cubic(&self, segment: &HermiteSegment) -> [Vector3<f64>; 4] {
        match self {
            Motion::Line(line) => segment.relative_cubic(line),
            Motion::Tracked(path) => path.over(segment.t0_s, segment.t1_s).cubic_to(segment),
        }
    }

    /// A bound (m) on the distance of the object's every position over `[t0_s, t1_s]` from its
    /// position at `t1_s`: `|v| (t1 − t0)` on a line, the Hermite segment's sweep bound on a tracked
    /// path.
    pub(crate) fn travel_bound_m(&self, t0_s: f64, t1_s: f64) -> f64 {
        match self {
            Motion::Line(line) => line.velocity_hill_mps.norm() * (t1_s - t0_s),
            Motion::Tracked(path) => path.over(t0_s, t1_s).sweep_bound_m(),
        }
    }

    /// The tracked path, for the engine to place (`None` for a line).
    pub fn tracked_mut(&mut self) -> Option<&mut TrackedPath> {
        match self {
            Motion::Line(_) => None,
            Motion::Tracked(path) => Some(path),
        }
    }

    /// Whether the object is a tracked real object.
    pub fn is_tracked(&self) -> bool {
        matches!(self, Motion::Tracked(_))
    }
}
