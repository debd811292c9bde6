//! One encounter of a pair and how it is found on a segment: the local minima of the pair's distance
//! along the cubic of their relative path, with a hysteresis that ignores rounding-level wiggles, and a
//! minimum still open at the segment's end carried to the next segment.
//!
//! **What an encounter is.** Over the run, a pair's distance is a continuous function of time, piecewise
//! the norm of a cubic (each integration segment, [`HermiteSegment`]). An encounter is a local minimum of
//! it below the threshold: the distance falls to the minimum and then rises by more than the tolerance
//! (`1e-9` of the size of the segment's relative cubic, far above its rounding and far below any
//! physical scale). A minimum at a segment boundary (the pair approaching until the end of one segment
//! and separating from the start of the next) is found once, when the next segment shows the rise: the
//! minimum is *carried* from one segment to the next while the distance is still falling or has not yet
//! risen by the tolerance. A pair already separating at the start of the run, or still approaching at its
//! end, has no minimum inside the run and gives no encounter.

use nalgebra::Vector3;

use crate::environment::closest_approach::{eval_cubic, eval_cubic_derivative, scan};
use crate::environment::HermiteSegment;
use crate::orbit::RelativeStateHill;

/// Relative tolerance of a rise (or a fall) that ends a descent (an ascent): a fraction of
/// `|c0| + |c1| + |c2| + |c3|` of the segment's relative cubic.
const RISE_TOLERANCE: f64 = 1e-9;

/// A local minimum of a pair's distance, located on one segment: its time, its distance and the two
/// objects' Hill states then.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Candidate {
    /// Time of the minimum \[s\].
    pub tca_s: f64,
    /// The distance then \[m\].
    pub distance_m: f64,
    /// The primary's state then, Hill frame of the LVLH origin \[m, m/s\].
    pub primary_hill: RelativeStateHill,
    /// The secondary's state then, Hill frame of the LVLH origin \[m, m/s\].
    pub secondary_hill: RelativeStateHill,
}

/// What a pair's walk over one segment found: the minima below the threshold it confirmed, and the
/// minimum below the threshold still open at the segment's end (carried to the next segment).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Walk {
    /// Confirmed minima below the threshold, in time order.
    pub found: Vec<Candidate>,
    /// A descent below the threshold not yet confirmed at the end of the segment.
    pub open: Option<Candidate>,
}

/// Where the walk is: falling towards a minimum (the lowest point so far), or rising from it (the
/// highest point so far).
enum Phase {
    Falling(Candidate),
    Rising(f64),
}

/// Walks one segment of a pair: `primary` is the primary's path over the segment and `c` the cubic of
/// the secondary's position relative to the primary's (`secondary − primary`, Hill frame, m, in the
/// segment's normalised time); `carried` is the open minimum the previous segment handed on. Minima below
/// `threshold_m` \[m\] are confirmed and returned.
pub(crate) fn walk(
    primary: &HermiteSegment,
    c: &[Vector3<f64>; 4],
    carried: Option<Candidate>,
    threshold_m: f64,
) -> Walk {
    let tolerance_m = RISE_TOLERANCE * c.iter().map(|v| v.norm()).sum::<f64>();
    let pieces = scan(c);
    let h = primary.duration_s();
    let at = |s: f64, distance_m: f64| {
        let t = primary.time_at(s);
        let primary_hill = RelativeStateHill {
            position_m: primary.position_hill_m(t),
            velocity_mps: primary.velocity_hill_mps(t),
        };
        let relative = RelativeStateHill {
            position_m: eval_cubic(c, s),
            velocity_mps: eval_cubic_derivative(c, s) / h,
        };
        Candidate {
            tca_s: t,
            distance_m,
            primary_hill,
            secondary_hill: RelativeStateHill {
                position_m: primary_hill.position_m + relative.position_m,
                velocity_mps: primary_hill.velocity_mps + relative.velocity_mps,
            },
        }
    };
    let (points, distances) = (pieces.points_s(), pieces.distances_m());
    let mut phase = match carried {
        Some(open) => Phase::Falling(open),
        None => Phase::Rising(distances[0]),
    };
    let mut walk = Walk::default();
    for (&s, &d) in points.iter().zip(distances) {
        phase = match phase {
            Phase::Falling(low) if d < low.distance_m => Phase::Falling(at(s, d)),
            Phase::Falling(low) if d > low.distance_m + tolerance_m => {
                if low.distance_m < threshold_m {
                    walk.found.push(low);
                }
                Phase::Rising(d)
            }
            Phase::Rising(high) if d > high => Phase::Rising(d),
            Phase::Rising(high) if d < high - tolerance_m => Phase::Falling(at(s, d)),
            unchanged => unchanged,
        };
    }
    if let Phase::Falling(low) = phase {
        walk.open = (low.distance_m < threshold_m).then_some(low);
    }
    walk
}

#[cfg(test)]
mod tests {
    use super::*;

    fn segment(t0: f64, t1: f64, p0: [f64; 3], v: [f64; 3]) -> HermiteSegment {
        let (p0, v) = (Vector3::from(p0), Vector3::from(v));
        HermiteSegment::new(t0, t1, p0, v, p0 + v * (t1 - t0), v).unwrap()
    }

    /// A straight pass: the minimum of |p0 + v t| is at t = −p0·v / v·v, at distance |p0 × v| / |v|.
    #[test]
    fn a_straight_pass_is_one_encounter_at_the_closed_form_minimum() {
        let primary = segment(0.0, 10.0, [0.0; 3], [0.0; 3]);
        let (p0, v) = (Vector3::new(-30.0, 4.0, 3.0), Vector3::new(5.0, 0.5, 0.0));
        let rel = segment(0.0, 10.0, p0.into(), v.into());
        let c = primary.cubic_to(&rel);
        let w = walk(&primary, &c, None, 50.0);
        assert_eq!(w.found.len(), 1, "{w:?}");
        let t_star = -p0.dot(&v) / v.dot(&v);
        let d_star = p0.cross(&v).norm() / v.norm();
        assert!((w.found[0].tca_s - t_star).abs() < 1e-12);
        assert!((w.found[0].distance_m - d_star).abs() < 1e-12);
        assert!(w.open.is_none());
        // Below a threshold under the miss distance, nothing.
        assert!(walk(&primary, &c, None, d_star * 0.999).found.is_empty());
    }

    /// A minimum at the boundary of two segments is found once, by the second segment.
    #[test]
    fn a_minimum_at_a_segment_boundary_is_carried_and_found_once() {
        let primary = segment(0.0, 5.0, [0.0; 3], [0.0; 3]);
        // Closest at t = 5 s: p(t) = (−25 + 5 t, 2, 0).
        let first = primary.cubic_to(&segment(0.0, 5.0, [-25.0, 2.0, 0.0], [5.0, 0.0, 0.0]));
        let w1 = walk(&primary, &first, None, 50.0);
        assert!(w1.found.is_empty());
        let open = w1.open.expect("still falling at the segment's end");
        let primary2 = segment(5.0, 10.0, [0.0; 3], [0.0; 3]);
        let second = primary2.cubic_to(&segment(5.0, 10.0, [0.0, 2.0, 0.0], [5.0, 0.0, 0.0]));
        let w2 = walk(&primary2, &second, Some(open), 50.0);
        assert_eq!(w2.found.len(), 1);
        assert_eq!(w2.found[0].tca_s, 5.0);
        assert!((w2.found[0].distance_m - 2.0).abs() < 1e-12);
        // Without the carried minimum the second segment starts rising: no encounter.
        assert!(walk(&primary2, &second, None, 50.0).found.is_empty());
    }
}
