//! The affine map that best carries a swarm's anchor positions onto its positions now (least squares),
//! and how far each satellite is from it: what lets [`super::SeparationTracker`] bound the distance of
//! every pair without visiting pairs, for a swarm that moves together.
//!
//! For any 3 × 3 matrix M and vector b, with q_k = M p_k + b + ε_k (p at the anchors, q now),
//! |q_i − q_j| ≥ |M (p_i − p_j)| − |ε_i| − |ε_j| ≥ σ_min(M) |p_i − p_j| − e_i − e_j, σ_min the smallest
//! singular value of M and e_k = |ε_k|. The bound holds for any M and b; the fit only makes the residuals
//! small. M = I, b = 0 is the plain displacement bound. A swarm in the Hill frame moves nearly affinely:
//! free relative motion is linear in the initial state (HCW), and initial velocities are usually zero,
//! or linear in position (no-drift), or small; so the residuals stay far below the displacements (metres
//! of drift, millimetres of residual over a minute for a kilometre-wide free-drifting ball).
//!
//! The fit is M = I + D with D the least-squares solution of r_k − r̄ ≈ D (p_k − p̄), r = q − p the
//! displacements, over the pseudo-inverse of the anchors' scatter matrix (a flat or linear swarm leaves
//! M = I along the directions it does not span). Its sums are taken in fixed blocks of satellites added in
//! block order, so the fit, and with it every bound, is the same on any thread count.

use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

/// Satellites per block of the fit's sums (fixed, so the sums do not depend on the thread count).
pub(crate) const SUM_BLOCK: usize = 4096;

/// Eigenvalues of the anchors' scatter matrix below this fraction of the largest are taken as zero: the
/// swarm does not span that direction, and the fit leaves it to M = I.
const FLAT_FRACTION: f64 = 1e-9;

/// Relative slack subtracted from the smallest eigenvalue of MᵀM before its square root: far above the
/// symmetric eigensolver's backward error (a few ε of the largest eigenvalue), so σ_min is never
/// over-estimated.
const EIGEN_SLACK: f64 = 1e-12;

/// A fitted affine motion x ↦ x + r̄ + D (x − p̄) from the anchors to now (m, the positions' frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct AffineMotion {
    /// Mean anchor position p̄ \[m\].
    anchor_mean_m: Vector3<f64>,
    /// Mean displacement r̄ \[m\].
    shift_m: Vector3<f64>,
    /// D: the displacement's linear part (dimensionless).
    stretch: Matrix3<f64>,
    /// A lower bound of σ_min(I + D) (dimensionless, ≥ 0).
    pub contraction: f64,
    /// ‖I + D‖ (Frobenius), for the rounding margin of distances carried through the map.
    pub norm: f64,
}

/// The fit's running sums over a block of satellites, shifted by one origin so that the products stay
/// near the swarm's own scale; `missing` when a satellite of the block had no anchor.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct FitSums {
    missing: bool,
    count: f64,
    p: Vector3<f64>,
    r: Vector3<f64>,
    pp: Matrix3<f64>,
    rp: Matrix3<f64>,
}

impl FitSums {
    /// Adds a satellite at `p` (anchor, relative to the fit's origin) displaced by `r` since (m).
    #[inline]
    pub(crate) fn add(&mut self, p: Vector3<f64>, r: Vector3<f64>) {
        self.count += 1.0;
        self.p += p;
        self.r += r;
        self.pp += p * p.transpose();
        self.rp += r * p.transpose();
    }

    fn merge(mut self, other: &FitSums) -> FitSums {
        self.missing |= other.missing;
        self.count += other.count;
        self.p += other.p;
        self.r += other.r;
        self.pp += other.pp;
        self.rp += other.rp;
        self
    }
}

impl AffineMotion {
    /// The identity (M = I, b = 0; ‖I‖ = √3): the residuals are the displacements.
    pub(crate) const IDENTITY: AffineMotion = AffineMotion {
        anchor_mean_m: Vector3::new(0.0, 0.0, 0.0),
        shift_m: Vector3::new(0.0, 0.0, 0.0),
        stretch: Matrix3::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
        contraction: 1.0,
        norm: 1.732_050_807_568_877_2,
    };

    /// The least-squares affine motion of the `n` satellites whose anchor and current positions
    /// `anchor(k)` and `now(k)` give (m, one frame), `blocks` the reusable buffer of block sums; `None`
    /// when fewer than two satellites, a satellite without an anchor or a non-finite sum.
    pub(crate) fn fit(
        n: usize,
        anchor: impl Fn(usize) -> Option<Vector3<f64>> + Sync,
        now: impl Fn(usize) -> Vector3<f64> + Sync,
        blocks: &mut Vec<FitSums>,
    ) -> Option<AffineMotion> {
        if n < 2 {
            return None;
        }
        let origin_m = anchor(0)?;
        blocks.clear();
        blocks.resize(n.div_ceil(SUM_BLOCK), FitSums::default());
        blocks.par_iter_mut().enumerate().for_each(|(b, sums)| {
            for k in b * SUM_BLOCK..((b + 1) * SUM_BLOCK).min(n) {
                match anchor(k) {
                    Some(p) => sums.add(p - origin_m, now(k) - p),
                    None => sums.missing = true,
                }
            }
        });
        Self::from_sums(blocks, origin_m)
    }

    /// The least-squares motion from the block sums `blocks` (each block's satellites added with
    /// [`FitSums::add`] relative to `origin_m`, blocks of [`SUM_BLOCK`] satellites in order); `None` when
    /// a satellite had no anchor or a sum is not finite.
    pub(crate) fn from_sums(blocks: &[FitSums], origin_m: Vector3<f64>) -> Option<AffineMotion> {
        let total = blocks
            .iter()
            .fold(FitSums::default(), |total, block| total.merge(block));
        if total.missing {
            return None;
        }
        let count = total.count;
        let mean_p = total.p / count;
        let shift_m = total.r / count;
        let scatter = total.pp - mean_p * total.p.transpose();
        let cross = total.rp - shift_m * total.p.transpose();
        let scatter = 0.5 * (scatter + scatter.transpose());
        let eigen = scatter.symmetric_eigen();
        let largest = eigen.eigenvalues.amax();
        if !(largest.is_finite() && cross.iter().all(|v| v.is_finite())) {
            return None;
        }
        let mut inverse = Matrix3::zeros();
        for (k, &lambda) in eigen.eigenvalues.iter().enumerate() {
            if lambda > FLAT_FRACTION * largest {
                let v = eigen.eigenvectors.column(k);
                inverse += v * v.transpose() / lambda;
            }
        }
        Self::with_bounds(mean_p + origin_m, shift_m, cross * inverse)
    }

    /// The motion x ↦ x + `shift_m` + `stretch` (x − `anchor_mean_m`) with its contraction and norm;
    /// `None` when they are not finite.
    fn with_bounds(
        anchor_mean_m: Vector3<f64>,
        shift_m: Vector3<f64>,
        stretch: Matrix3<f64>,
    ) -> Option<AffineMotion> {
        let map = Matrix3::identity() + stretch;
        let gram = (map.transpose() * map).symmetric_eigenvalues();
        let (low, high) = (gram.min(), gram.max());
        if !(low.is_finite() && high.is_finite()) {
            return None;
        }
        Some(AffineMotion {
            anchor_mean_m,
            shift_m,
            stretch,
            contraction: (low - EIGEN_SLACK * high).max(0.0).sqrt(),
            norm: map.norm(),
        })
    }

    /// The motion one more snapshot on, extrapolated linearly from `earlier` (the snapshot before
    /// `self`) to `self`: 2 (r̄, D) − (r̄, D)_earlier about `self`'s anchor mean. Any affine motion gives
    /// a valid bound; this one is close to the next fit while the swarm moves smoothly, so the bound
    /// can be used before that fit is known.
    pub(crate) fn extrapolated_from(&self, earlier: &AffineMotion) -> Option<AffineMotion> {
        Self::with_bounds(
            self.anchor_mean_m,
            2.0 * self.shift_m - earlier.shift_m,
            2.0 * self.stretch - earlier.stretch,
        )
    }

    /// The squared residual |q − (p + r̄ + D (p − p̄))|² \[m²\] of a satellite anchored at `anchor_m`
    /// and at `now_m` (its square root is the residual's norm to the bit: nalgebra's `norm`).
    pub(crate) fn residual_squared_m2(&self, anchor_m: &Vector3<f64>, now_m: &Vector3<f64>) -> f64 {
        let predicted = anchor_m + self.shift_m + self.stretch * (anchor_m - self.anchor_mean_m);
        (now_m - predicted).norm_squared()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn points(n: usize) -> Vec<Vector3<f64>> {
        (0..n)
            .map(|k| {
                let t = k as f64;
                Vector3::new((t * 0.37).sin() * 100.0, (t * 0.11).cos() * 80.0, t % 7.0)
            })
            .collect()
    }

    /// A swarm moved by an exact affine map is fitted to rounding: residuals near zero, and the
    /// contraction is the map's smallest singular value (a stretch of 1.5 and a shrink of 0.8 along two
    /// axes after a rotation).
    #[test]
    fn an_affine_motion_is_recovered() {
        let anchors = points(10_000);
        let rotation = nalgebra::Rotation3::from_euler_angles(0.1, -0.2, 0.3);
        let map = rotation.matrix() * Matrix3::from_diagonal(&Vector3::new(1.5, 0.8, 1.0));
        let b = Vector3::new(3.0, -4.0, 12.0);
        let now: Vec<Vector3<f64>> = anchors.iter().map(|p| map * p + b).collect();
        let mut blocks = Vec::new();
        let fit = AffineMotion::fit(10_000, |k| Some(anchors[k]), |k| now[k], &mut blocks).unwrap();
        let worst = (0..anchors.len())
            .map(|k| fit.residual_squared_m2(&anchors[k], &now[k]).sqrt())
            .fold(0.0, f64::max);
        assert!(worst < 1e-10, "residual {worst} m");
        assert!((fit.contraction - 0.8).abs() < 1e-9, "{}", fit.contraction);
    }

    /// A flat swarm (z = 0) keeps M = I across its plane's normal: the fit of an in-plane motion is still
    /// exact, and the contraction is not driven to zero by the direction the swarm does not span.
    #[test]
    fn a_flat_swarm_keeps_the_identity_off_its_plane() {
        let anchors: Vec<Vector3<f64>> = points(500)
            .into_iter()
            .map(|p| Vector3::new(p.x, p.y, 0.0))
            .collect();
        let now: Vec<Vector3<f64>> = anchors
            .iter()
            .map(|p| Vector3::new(1.01 * p.x + 0.02 * p.y, p.y, 0.0))
            .collect();
        let mut blocks = Vec::new();
        let fit = AffineMotion::fit(500, |k| Some(anchors[k]), |k| now[k], &mut blocks).unwrap();
        assert!((0..500).all(|k| fit.residual_squared_m2(&anchors[k], &now[k]).sqrt() < 1e-10));
        assert!(fit.contraction > 0.98, "{}", fit.contraction);
    }

    /// A swarm whose affine motion grows linearly in time (x ↦ x + t (A x + c)): the motion
    /// extrapolated from the fits at t = 1 and 2 carries the anchors onto the positions at t = 3 to
    /// rounding, as the fit at t = 3 does.
    #[test]
    fn a_motion_linear_in_time_is_extrapolated() {
        let anchors = points(2_000);
        let a = Matrix3::new(0.01, -0.02, 0.0, 0.03, 0.005, 0.01, 0.0, -0.01, 0.02);
        let c = Vector3::new(0.5, -1.5, 2.0);
        let at =
            |t: f64| -> Vec<Vector3<f64>> { anchors.iter().map(|p| p + t * (a * p + c)).collect() };
        let mut blocks = Vec::new();
        let mut fit_at = |t: f64| {
            let now = at(t);
            AffineMotion::fit(2_000, |k| Some(anchors[k]), |k| now[k], &mut blocks).unwrap()
        };
        let (first, second) = (fit_at(1.0), fit_at(2.0));
        let predicted = second.extrapolated_from(&first).unwrap();
        let now = at(3.0);
        let worst = (0..anchors.len())
            .map(|k| predicted.residual_squared_m2(&anchors[k], &now[k]).sqrt())
            .fold(0.0, f64::max);
        assert!(worst < 1e-9, "residual {worst} m");
        let fitted = fit_at(3.0);
        assert!((predicted.contraction - fitted.contraction).abs() < 1e-12);
    }

    /// The lower bound σ_min |p_i − p_j| − e_i − e_j holds for every pair of a swarm whose motion is
    /// affine plus random jitter (checked over all pairs).
    #[test]
    fn the_pair_bound_holds_under_jitter() {
        let anchors = points(400);
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut jitter = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let now: Vec<Vector3<f64>> = anchors
            .iter()
            .map(|p| {
                Vector3::new(0.9 * p.x - 0.1 * p.y, 1.2 * p.y, p.z + 0.3 * p.x)
                    + Vector3::new(jitter(), jitter(), jitter())
            })
            .collect();
        let mut blocks = Vec::new();
        let fit = AffineMotion::fit(400, |k| Some(anchors[k]), |k| now[k], &mut blocks).unwrap();
        let e: Vec<f64> = (0..400)
            .map(|k| fit.residual_squared_m2(&anchors[k], &now[k]).sqrt())
            .collect();
        for i in 0..400 {
            for j in i + 1..400 {
                let lower = fit.contraction * (anchors[i] - anchors[j]).norm() - e[i] - e[j];
                assert!(lower <= (now[i] - now[j]).norm() + 1e-9, "pair ({i}, {j})");
            }
        }
    }
}
