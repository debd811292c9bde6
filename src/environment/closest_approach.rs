//! Geometry of the continuous truth monitor: a satellite's path over one integration segment as a cubic
//! Hermite interpolant, and its exact minimum distance to a threat's straight line or to a fixed point.
//!
//! # The problem
//!
//! Over a segment `[t0, t1]` the satellite's Hill position is the cubic Hermite interpolant of the end
//! states ([`HermiteSegment`]); a threat moves on a straight line. In the normalised time
//! `s = (t − t0) / (t1 − t0) ∈ [0, 1]` their difference is a vector cubic
//! `d(s) = c0 + c1 s + c2 s² + c3 s³`, and the squared distance `f(s) = |d(s)|²` is a degree-6
//! polynomial. Its minimum over the closed interval is at an endpoint or at a real root of
//! `g(s) = f'(s) / 2 = d(s)·d'(s)` (degree 5) inside it.
//!
//! # The algorithm: isolation of every root by the derivative cascade
//!
//! A degree-5 polynomial has no closed-form roots, and a scan of sign changes on a uniform grid (say 64
//! sub-intervals) misses a pair of roots that fall in one sub-interval — a local maximum and a local
//! minimum of `f` close together, which is exactly the geometry of a satellite whose path bends near a
//! threat. Instead the roots are *isolated* exactly, using only the fact that between two consecutive
//! roots of `p'` a polynomial `p` is monotone and so has at most one root there, announced by a sign
//! change:
//!
//! * `p₀ = g⁽⁵⁾` is constant (no roots); the break points are `{0, 1}`;
//! * for `k = 1 … 5`, `p_k = g⁽⁵⁻ᵏ⁾` (degree `k`) is monotone between consecutive break points, because
//!   they include every root of its derivative `p_{k−1}` in `[0, 1]`; on each piece with a strict sign
//!   change its single root is refined by safeguarded Newton (Newton steps kept inside the bracket,
//!   bisection when a step leaves it or stalls: `rtsafe`), to within 4 ε of `s`; the roots join the break
//!   points.
//!
//! After level 5 the break points contain every root of `g = p₅` in `[0, 1]`, so `f` is monotone between
//! consecutive break points and its minimum over `[0, 1]` is the smallest `|d(s)|` at a break point. The
//! distance is always evaluated from `d(s)` itself (Horner, per component), never from the expanded
//! polynomial, so it carries only rounding of order `ε·max|c_i|`; an error `δ` in `s` changes the
//! distance by `O(δ²)` at an interior minimum. For the exact polynomials the cascade costs at most 15
//! one-dimensional solves of a degree ≤ 5 polynomial, each a handful of Newton steps (bisection bounds
//! it by ~55 steps); measured at about 0.2 µs a call in a release build on the development machine.
//!
//! Rounding can add spurious sign changes (extra break points) or move a root by a few ulps; it can hide
//! a root only where the exact polynomial barely crosses zero (a near-double root of `g`), where `f` is
//! flat and the lost candidate changes the minimum by a rounding-level amount. Each level at most doubles
//! the number of pieces, so 33 break points always suffice and the work is bounded and allocation-free.
//! Spurious break points are harmless: every break point is a point of the segment, and the distance is
//! taken at the exact cubic.
//!
//! Two extra safeguards: when the segment is straight relative to the line (`c2 = c3 = 0` exactly) the
//! closed form `s* = clamp(−(c0·c1) / (c1·c1), 0, 1)` is used directly; otherwise the minimum of the
//! chord `c0 + (c1 + c2 + c3) s` is added as a candidate, which makes nearly straight segments (whose
//! higher coefficients are rounding noise) as accurate as straight ones.
//!
//! The break points also give incursion counts: `f` is monotone on each piece, so a satellite enters a
//! sphere of radius `R` on a piece exactly when it is outside (`|d| ≥ R`) at the piece's start and
//! inside (`|d| < R`) at its end (used by [`crate::environment::monitor`]).

use nalgebra::Vector3;

use super::motion::{LinearMotion, Motion};
use super::obstacle::Obstacle;
use super::threat::Threat;
use super::{check_finite, check_finite_vector, EnvironmentError};

/// Cubic Hermite interpolant of a satellite's Hill position over one integration segment `[t0_s, t1_s]`,
/// from the positions (m) and velocities (m/s) at both ends, all in the Hill frame.
///
/// It reproduces exactly any path that is a cubic in time (in particular straight-line motion); for a
/// smooth path its position error is at most `h⁴/384 · max|r⁽⁴⁾|` with `h = t1_s − t0_s`.
///
/// Fields are public for construction in the engine's loop; [`HermiteSegment::new`] checks them. A
/// segment needs `t1_s > t0_s`: with `t1_s == t0_s` the functions of this module do not panic but the
/// interpolant is meaningless.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HermiteSegment {
    /// Start time (s).
    pub t0_s: f64,
    /// End time (s), later than `t0_s`.
    pub t1_s: f64,
    /// Position at `t0_s` (Hill frame, m).
    pub p0_hill_m: Vector3<f64>,
    /// Velocity at `t0_s` (Hill frame, m/s).
    pub v0_hill_mps: Vector3<f64>,
    /// Position at `t1_s` (Hill frame, m).
    pub p1_hill_m: Vector3<f64>,
    /// Velocity at `t1_s` (Hill frame, m/s).
    pub v1_hill_mps: Vector3<f64>,
}

impl HermiteSegment {
    /// A segment from the states `(p0_hill_m, v0_hill_mps)` at `t0_s` and `(p1_hill_m, v1_hill_mps)` at
    /// `t1_s` (s, m, m/s, Hill frame).
    ///
    /// # Errors
    /// [`EnvironmentError::NonFinite`] / [`EnvironmentError::NonFiniteVector`] for a NaN or infinite
    /// input, [`EnvironmentError::SegmentTimes`] unless `t1_s > t0_s`.
    pub fn new(
        t0_s: f64,
        t1_s: f64,
        p0_hill_m: Vector3<f64>,
        v0_hill_mps: Vector3<f64>,
        p1_hill_m: Vector3<f64>,
        v1_hill_mps: Vector3<f64>,
    ) -> Result<Self, EnvironmentError> {
        check_finite("segment start time (s)", t0_s)?;
        check_finite("segment end time (s)", t1_s)?;
        if t1_s <= t0_s {
            return Err(EnvironmentError::SegmentTimes { t0_s, t1_s });
        }
        check_finite_vector("segment start position (Hill, m)", &p0_hill_m)?;
        check_finite_vector("segment start velocity (Hill, m/s)", &v0_hill_mps)?;
        check_finite_vector("segment end position (Hill, m)", &p1_hill_m)?;
        check_finite_vector("segment end velocity (Hill, m/s)", &v1_hill_mps)?;
        Ok(Self {
            t0_s,
            t1_s,
            p0_hill_m,
            v0_hill_mps,
            p1_hill_m,
            v1_hill_mps,
        })
    }

    /// Length of the segment `t1_s − t0_s` (s).
    pub fn duration_s(&self) -> f64 {
        self.t1_s - self.t0_s
    }

    /// Interpolated position at time `t_s` (s), Hill frame (m). Exact at both ends (up to rounding);
    /// outside `[t0_s, t1_s]` the cubic is extrapolated.
    pub fn position_hill_m(&self, t_s: f64) -> Vector3<f64> {
        eval_cubic(&self.power_basis(), (t_s - self.t0_s) / self.duration_s())
    }

    /// Interpolated velocity (derivative of the interpolant) at time `t_s` (s), Hill frame (m/s).
    pub fn velocity_hill_mps(&self, t_s: f64) -> Vector3<f64> {
        let s = (t_s - self.t0_s) / self.duration_s();
        eval_cubic_derivative(&self.power_basis(), s) / self.duration_s()
    }

    /// A bound (m) on the distance of every interpolated position of the segment from its end
    /// position, `|a1| + |a2| + |a3|` of the power basis (`p(s) − p(1) = a1 (s − 1) + a2 (s² − 1) +
    /// a3 (s³ − 1)` and `|sᵏ − 1| ≤ 1` on `[0, 1]`).
    pub(crate) fn sweep_bound_m(&self) -> f64 {
        let a = self.power_basis();
        a[1].norm() + a[2].norm() + a[3].norm()
    }

    /// Time (s) of the normalised time `s ∈ [0, 1]`, exactly `t0_s` at 0 and `t1_s` at 1.
    pub(crate) fn time_at(&self, s: f64) -> f64 {
        (1.0 - s) * self.t0_s + s * self.t1_s
    }

    /// Power-basis coefficients `[a0, a1, a2, a3]` (m) of the position in `s = (t − t0) / h`.
    fn power_basis(&self) -> [Vector3<f64>; 4] {
        let h = self.duration_s();
        let (p0, p1) = (self.p0_hill_m, self.p1_hill_m);
        let (hv0, hv1) = (self.v0_hill_mps * h, self.v1_hill_mps * h);
        [
            p0,
            hv0,
            (p1 - p0) * 3.0 - hv0 * 2.0 - hv1,
            (p0 - p1) * 2.0 + hv0 + hv1,
        ]
    }

    /// Coefficients `[c0, c1, c2, c3]` (m) of `d(s) = other(s) − segment(s)` in `s = (t − t0) / h`,
    /// for two segments over the same times (the relative path of `other` seen from `self`).
    pub(crate) fn cubic_to(&self, other: &HermiteSegment) -> [Vector3<f64>; 4] {
        let (a, b) = (self.power_basis(), other.power_basis());
        [b[0] - a[0], b[1] - a[1], b[2] - a[2], b[3] - a[3]]
    }

    /// Coefficients `[c0, c1, c2, c3]` (m) of `d(s) = segment(s) − line(s)` in `s = (t − t0) / h`.
    pub(crate) fn relative_cubic(&self, line: &LinearMotion) -> [Vector3<f64>; 4] {
        let a = self.power_basis();
        let h = self.duration_s();
        [
            a[0] - line.position_hill_m(self.t0_s),
            a[1] - line.velocity_hill_mps * h,
            a[2],
            a[3],
        ]
    }
}

/// Closest approach over one segment: when (s) and how close (m, centre to centre).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Approach {
    /// Time of the minimum distance (s), within the segment; the earliest among exact ties at break
    /// points.
    pub time_s: f64,
    /// Minimum distance (m, ≥ 0).
    pub distance_m: f64,
}

/// Smallest clearance to an obstacle over one segment: when (s) and how far from its surface (m).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Clearance {
    /// Time of the minimum clearance (s), within the segment.
    pub time_s: f64,
    /// Minimum distance to the obstacle's surface (m): negative when the satellite is inside.
    pub clearance_m: f64,
}

/// Minimum over `[segment.t0_s, segment.t1_s]` of the distance (m) between the segment's interpolated
/// position and the threat's centre, and its time (s); both in the Hill frame.
pub fn closest_approach_to_threat(segment: &HermiteSegment, threat: &Threat) -> Approach {
    closest_approach_to(segment, threat.motion())
}

/// Minimum over the segment of the distance (m) between the segment's interpolated position and an
/// object moving by `motion` (Hill frame), and its time (s).
fn closest_approach_to(segment: &HermiteSegment, motion: &Motion) -> Approach {
    let c = motion.relative_cubic(segment);
    let (s, distance_m) = scan(&c).minimum(&c);
    Approach {
        time_s: segment.time_at(s),
        distance_m,
    }
}

/// Minimum over `[segment.t0_s, segment.t1_s]` of the distance (m) between the segment's interpolated
/// position and an object in uniform straight-line motion (Hill frame), and its time (s).
pub fn closest_approach_to_line(segment: &HermiteSegment, line: &LinearMotion) -> Approach {
    closest_approach_to(segment, &Motion::Line(*line))
}

/// Minimum over `[segment.t0_s, segment.t1_s]` of the distance (m) from the segment's interpolated
/// position to the fixed point `point_hill_m` (Hill frame, m), and its time (s). An obstacle's surface
/// clearance is this distance minus its radius ([`obstacle_clearance`]).
pub fn min_distance_to_point(segment: &HermiteSegment, point_hill_m: &Vector3<f64>) -> Approach {
    closest_approach_to_line(segment, &LinearMotion::fixed(*point_hill_m))
}

/// Minimum over the segment of the distance (m) from the satellite's centre to the obstacle's surface
/// (negative inside), and its time (s).
pub fn obstacle_clearance(segment: &HermiteSegment, obstacle: &Obstacle) -> Clearance {
    let a = closest_approach_to(segment, obstacle.motion());
    Clearance {
        time_s: a.time_s,
        clearance_m: a.distance_m - obstacle.radius_m(),
    }
}

/// Most break points the cascade can produce: each of the 5 levels at most doubles the pieces of the
/// previous one (1 piece → 32), whatever the rounding.
const MAX_POINTS: usize = 33;

/// Break points of `[0, 1]` (sorted, starting at 0 and ending at 1) between which the squared distance
/// `|d(s)|²` is monotone, with the distance (m) at each.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Scan {
    s: [f64; MAX_POINTS],
    distance_m: [f64; MAX_POINTS],
    len: usize,
}

impl Scan {
    /// Normalised times `s ∈ [0, 1]` of the break points, ascending.
    pub(crate) fn points_s(&self) -> &[f64] {
        &self.s[..self.len]
    }

    /// Distances (m) at the break points, in order of `s`.
    pub(crate) fn distances_m(&self) -> &[f64] {
        &self.distance_m[..self.len]
    }

    /// `(s, distance_m)` of the minimum distance over `[0, 1]`: the smallest distance at a break point
    /// (the earliest among ties), or the chord candidate when it is strictly smaller.
    pub(crate) fn minimum(&self, c: &[Vector3<f64>; 4]) -> (f64, f64) {
        let mut best = (self.s[0], self.distance_m[0]);
        for i in 1..self.len {
            if self.distance_m[i] < best.1 {
                best = (self.s[i], self.distance_m[i]);
            }
        }
        let s_chord = chord_minimiser(c);
        let d_chord = eval_cubic(c, s_chord).norm();
        if d_chord < best.1 {
            best = (s_chord, d_chord);
        }
        best
    }
}

/// `d(s)` by Horner's rule, per component.
pub(crate) fn eval_cubic(c: &[Vector3<f64>; 4], s: f64) -> Vector3<f64> {
    ((c[3] * s + c[2]) * s + c[1]) * s + c[0]
}

/// `s ∈ [0, 1]` minimising `|c0 + e s|` with `e = c1 + c2 + c3` (the chord of `d` from `s = 0` to 1);
/// 0 when `e = 0`.
fn chord_minimiser(c: &[Vector3<f64>; 4]) -> f64 {
    let e = c[1] + c[2] + c[3];
    let ee = e.dot(&e);
    if ee > 0.0 {
        (-c[0].dot(&e) / ee).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// `d'(s)` (m per unit of `s`), per component.
pub(crate) fn eval_cubic_derivative(c: &[Vector3<f64>; 4], s: f64) -> Vector3<f64> {
    (c[3] * (3.0 * s) + c[2] * 2.0) * s + c[1]
}

/// A lower bound (m) on `min over s ∈ [0, 1] of |d(s)|`, from the chord: `d(s) = c0 + e s + r(s)` with
/// `r(s) = c2 (s² − s) + c3 (s³ − s)`, and on `[0, 1]` `|s² − s| ≤ 1/4`, `|s³ − s| ≤ 2/(3√3) < 0.385`.
/// A relative margin of 1e-12 of the coefficients' size covers the rounding of the bound itself.
pub(crate) fn lower_bound_m(c: &[Vector3<f64>; 4]) -> f64 {
    let s = chord_minimiser(c);
    let e = c[1] + c[2] + c[3];
    let chord = (c[0] + e * s).norm();
    let (n0, n1, n2, n3) = (c[0].norm(), c[1].norm(), c[2].norm(), c[3].norm());
    chord - 0.25 * n2 - 0.385 * n3 - 1e-12 * (n0 + n1 + n2 + n3)
}

/// `p(x)` for the polynomial with coefficients `p[0..=degree]` (lowest first).
fn horner(p: &[f64; 6], degree: usize, x: f64) -> f64 {
    let mut acc = p[degree];
    for i in (0..degree).rev() {
        acc = acc * x + p[i];
    }
    acc
}

/// Break points of `[0, 1]` between which `|d(s)|²` is monotone (see the module docs), with the distance
/// at each.
pub(crate) fn scan(c: &[Vector3<f64>; 4]) -> Scan {
    let mut out = Scan {
        s: [0.0; MAX_POINTS],
        distance_m: [0.0; MAX_POINTS],
        len: 0,
    };
    if c[2] == Vector3::zeros() && c[3] == Vector3::zeros() {
        // Straight relative motion: |d|² is a convex quadratic, monotone on both sides of the
        // closed-form minimiser.
        let s_star = chord_minimiser(c);
        let points = [0.0, s_star, 1.0];
        for (i, s) in points.into_iter().enumerate() {
            out.s[i] = s;
            out.distance_m[i] = eval_cubic(c, s).norm();
        }
        out.len = 3;
        return out;
    }

    // f(s) = |d(s)|² = Σ F_n sⁿ, n = 0..6.
    let mut f = [0.0; 7];
    for i in 0..4 {
        for j in 0..4 {
            f[i + j] += c[i].dot(&c[j]);
        }
    }
    // level[k] = g⁽⁵⁻ᵏ⁾, degree k, with g = f'/2.
    let mut level = [[0.0; 6]; 6];
    for m in 0..6 {
        level[5][m] = 0.5 * (m as f64 + 1.0) * f[m + 1];
    }
    for k in (0..5).rev() {
        for i in 0..=k {
            level[k][i] = (i as f64 + 1.0) * level[k + 1][i + 1];
        }
    }

    let mut points = [0.0; MAX_POINTS];
    points[1] = 1.0;
    let mut len = 2;
    let mut next = [0.0; MAX_POINTS];
    for k in 1..=5 {
        let (p, dp) = (&level[k], &level[k - 1]);
        let mut a = points[0];
        let mut pa = horner(p, k, a);
        next[0] = a;
        let mut n = 1;
        for &b in &points[1..len] {
            let pb = horner(p, k, b);
            if (pa < 0.0 && pb > 0.0) || (pa > 0.0 && pb < 0.0) {
                next[n] = refine_root(p, dp, k, a, b, pa);
                n += 1;
            }
            next[n] = b;
            n += 1;
            a = b;
            pa = pb;
        }
        points = next;
        len = n;
    }
    for (i, &s) in points[..len].iter().enumerate() {
        out.s[i] = s;
        out.distance_m[i] = eval_cubic(c, s).norm();
    }
    out.len = len;
    out
}

/// Root of the degree-`degree` polynomial `p` (derivative `dp`) in `[a, b]`, where `p(a) = pa` and
/// `p(b)` have strict opposite signs: safeguarded Newton (`rtsafe`, Numerical Recipes §9.4), converged
/// to within 4 ε in `s`.
fn refine_root(p: &[f64; 6], dp: &[f64; 6], degree: usize, a: f64, b: f64, pa: f64) -> f64 {
    const S_TOLERANCE: f64 = 4.0 * f64::EPSILON;
    // Orient the bracket so that p(lo) < 0 < p(hi).
    let (mut lo, mut hi) = if pa < 0.0 { (a, b) } else { (b, a) };
    let mut x = 0.5 * (a + b);
    let mut dx_old = (b - a).abs();
    let mut dx = dx_old;
    let mut fx = horner(p, degree, x);
    let mut dfx = horner(dp, degree - 1, x);
    for _ in 0..200 {
        if fx == 0.0 {
            return x;
        }
        let newton_leaves_bracket = ((x - hi) * dfx - fx) * ((x - lo) * dfx - fx) > 0.0;
        let newton_too_slow = (2.0 * fx).abs() > (dx_old * dfx).abs();
        if newton_leaves_bracket || newton_too_slow {
            dx_old = dx;
            dx = 0.5 * (hi - lo);
            x = lo + dx;
            // The bracket has shrunk to adjacent floating-point numbers.
            if x == lo || x == hi {
                return x;
            }
        } else {
            dx_old = dx;
            dx = fx / dfx;
            let x_old = x;
            x -= dx;
            if x == x_old {
                return x;
            }
        }
        if dx.abs() < S_TOLERANCE {
            return x;
        }
        fx = horner(p, degree, x);
        dfx = horner(dp, degree - 1, x);
        if fx < 0.0 {
            lo = x;
        } else {
            hi = x;
        }
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Cascade finds all five roots of g for a polynomial with five closely spaced stationary points of
    /// f in one segment (which a 64-cell uniform scan could not separate).
    #[test]
    fn cascade_isolates_close_roots() {
        // d(s) along x only: d = (s − 0.5)(s − 0.505)(s − 0.51) has |d| = 0 at three points within 0.01.
        let r = [0.5, 0.505, 0.51];
        let coeff = [
            -r[0] * r[1] * r[2],
            r[0] * r[1] + r[0] * r[2] + r[1] * r[2],
            -(r[0] + r[1] + r[2]),
            1.0,
        ];
        let c = coeff.map(|k| Vector3::new(k, 0.0, 0.0));
        let sc = scan(&c);
        let zeros = sc.distances_m().iter().filter(|&&d| d < 1e-15).count();
        assert!(zeros >= 3, "{:?}", &sc.s[..sc.len]);
    }
}
