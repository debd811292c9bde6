//! Rotations into EME2000 (the mean equator and equinox of J2000, satflock's inertial frame): from
//! **TEME** of date, SGP4's output frame ([`teme_to_eme2000`], [`teme_to_eme2000_matrix`]), and from
//! the **GCRF / ICRF** axes by the frame bias ([`gcrf_to_eme2000`], [`frame_bias`]).
//!
//! # TEME → EME2000
//!
//! TEME ("true equator, mean equinox") is the frame SGP4 works in: the true equator of date with the
//! x axis on the *mean* equinox of date, the equinox the IAU 1982 GMST is measured from (Vallado,
//! Crawford, Hujsak & Kelso 2006, "Revisiting Spacetrack Report #3", AIAA 2006-6753, §C and their
//! `teme2eci`). With T the Julian centuries of TT from J2000, and Vallado's passive rotations R1, R2,
//! R3:
//!
//! 1. TEME → true of date (TOD): `r_TOD = R3(−Eq) r_TEME`, Eq = Δψ cos ε̄, the equation of the
//!    equinoxes without the kinematic terms 0.00264″ sin Ω + 0.000063″ sin 2Ω (as Vallado's TEME
//!    conversion; they are below 2.7 mas, 0.13 m at 10 000 km).
//! 2. TOD → mean of date (MOD): `r_MOD = R1(−ε̄) R3(Δψ) R1(ε̄ + Δε) r_TOD`, the IAU 1980 nutation Δψ, Δε
//!    with **all 106 terms** (no truncation) and the IAU 1976 mean obliquity ε̄.
//! 3. MOD → EME2000: `r_J2000 = R3(ζ) R2(−θ) R3(z) r_MOD`, the IAU 1976 precession angles
//!    (Lieske et al. 1977): ζ = 2306.2181″T + 0.30188″T² + 0.017998″T³, θ = 2004.3109″T − 0.42665″T²
//!    − 0.041833″T³, z = 2306.2181″T + 1.09468″T² + 0.018203″T³.
//!
//! Neglected: the IERS celestial-pole offsets dψ, dε (the EOP corrections to the 1980 nutation: tens of
//! mas, **about 1 m** at LEO radius: 0.9 m in Vallado's example); polar motion and UT1 − UTC do not
//! enter (no Earth-fixed frame is involved); the rotation's own rate in the velocity (the precession
//! and nutation rates, below 3·10⁻¹² rad/s: under 3·10⁻⁵ m/s); the difference between TT and TDB in
//! the arguments (under 2 ms). SGP4's own error (a kilometre or more a day from the element set's
//! epoch) dwarfs all of these.
//!
//! # GCRF / ICRF → EME2000
//!
//! `r_EME2000 = B r_GCRF`, B = R1(−η₀) R2(ξ₀) R3(dα₀) the IAU 2000 frame bias (IERS Conventions 2003,
//! §5.4; SOFA `iauBi00`/`iauBp00`): dα₀ = −14.6 mas, ξ₀ = −0.041775″ sin ε₀ = −16.617 mas, η₀ =
//! −6.8192 mas — a rotation of about 23 mas, 0.8 m at 7000 km. ICRF axes are taken as GCRF axes (a
//! geocentric state: `CENTER_NAME = EARTH`), so the relativistic difference between the BCRS and GCRS
//! (a scale of 10⁻⁸ order, no rotation) is neglected.

use hifitime::Epoch;
use nalgebra::Matrix3;

use super::nutation_1980::{mean_obliquity_rad, nutation, ARCSEC_RAD};
use crate::orbit::CartesianState;

/// Vallado's passive rotation about x by `a` \[rad\].
fn r1(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(1.0, 0.0, 0.0, 0.0, c, s, 0.0, -s, c)
}

/// Vallado's passive rotation about y by `a` \[rad\].
fn r2(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(c, 0.0, -s, 0.0, 1.0, 0.0, s, 0.0, c)
}

/// Vallado's passive rotation about z by `a` \[rad\].
fn r3(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0)
}

/// The matrix taking TEME of date at `epoch` to EME2000 (`r_EME2000 = M r_TEME`); see the module
/// documentation for the chain and what it neglects.
pub fn teme_to_eme2000_matrix(epoch: Epoch) -> Matrix3<f64> {
    let t = epoch.to_tt_centuries_j2k();
    let eps = mean_obliquity_rad(t);
    let (dpsi, deps) = nutation(t);
    let teme_to_tod = r3(-dpsi * eps.cos());
    let tod_to_mod = r1(-eps) * r3(dpsi) * r1(eps + deps);
    let poly = |c: [f64; 3]| ((c[2] * t + c[1]) * t + c[0]) * t * ARCSEC_RAD;
    let zeta = poly([2306.2181, 0.30188, 0.017998]);
    let theta = poly([2004.3109, -0.42665, -0.041833]);
    let z = poly([2306.2181, 1.09468, 0.018203]);
    let mod_to_j2000 = r3(zeta) * r2(-theta) * r3(z);
    mod_to_j2000 * tod_to_mod * teme_to_tod
}

/// A TEME-of-date state at `epoch` (m, m/s) rotated to EME2000: position and velocity by
/// [`teme_to_eme2000_matrix`] (the rotation's own rate neglected: under 3·10⁻⁵ m/s). Neglects the
/// IERS nutation corrections dψ, dε (about 1 m at LEO radius); polar motion does not enter.
pub fn teme_to_eme2000(epoch: Epoch, teme: &CartesianState) -> CartesianState {
    let m = teme_to_eme2000_matrix(epoch);
    CartesianState::new(m * teme.position_m, m * teme.velocity_mps)
}

/// The IAU 2000 frame bias matrix B, GCRF (ICRS axes) → EME2000: `r_EME2000 = B r_GCRF`, built from
/// dα₀ = −0.0146″, ξ₀ = −0.041775″ sin(84381.448″), η₀ = −0.0068192″ as SOFA's `iauBi00`.
pub fn frame_bias() -> Matrix3<f64> {
    let eps0 = 84_381.448 * ARCSEC_RAD;
    let d_alpha0 = -0.0146 * ARCSEC_RAD;
    let xi0 = -0.041_775 * ARCSEC_RAD * eps0.sin();
    let eta0 = -0.006_819_2 * ARCSEC_RAD;
    r1(-eta0) * r2(xi0) * r3(d_alpha0)
}

/// A state on GCRF (or ICRF, geocentric) axes rotated to EME2000 by the frame bias ([`frame_bias`]).
pub fn gcrf_to_eme2000(gcrf: &CartesianState) -> CartesianState {
    let b = frame_bias();
    CartesianState::new(b * gcrf.position_m, b * gcrf.velocity_mps)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// SOFA's own test of `iauBp00` (t_sofa_c.c, `t_bp00`): the bias matrix to 1e-16.
    #[test]
    fn frame_bias_matches_sofa() {
        let want = [
            [
                0.999_999_999_999_994_2,
                -0.707_827_974_419_919_7e-7,
                0.805_621_714_697_613_4e-7,
            ],
            [
                0.707_827_947_785_733_7e-7,
                0.999_999_999_999_996_9,
                0.330_604_145_422_213_65e-7,
            ],
            [
                -0.805_621_738_098_697_2e-7,
                -0.330_604_088_398_055_25e-7,
                0.999_999_999_999_996_2,
            ],
        ];
        let b = frame_bias();
        for (i, row) in want.iter().enumerate() {
            for (j, &w) in row.iter().enumerate() {
                let tolerance = if i == j { 1e-12 } else { 1e-16 };
                assert!(
                    (b[(i, j)] - w).abs() < tolerance,
                    "B[{i}][{j}] = {} vs {w}",
                    b[(i, j)]
                );
            }
        }
    }

    /// The rotation is orthonormal and is the identity at J2000 up to nutation (TEME and EME2000
    /// differ there only by nutation, under 20″).
    #[test]
    fn teme_rotation_is_a_rotation() {
        let e = Epoch::from_gregorian_utc(2026, 3, 20, 12, 0, 0, 0);
        let m = teme_to_eme2000_matrix(e);
        assert!((m * m.transpose() - Matrix3::identity()).norm() < 1e-15);
        assert!((m.determinant() - 1.0).abs() < 1e-15);
        let j2000 = Epoch::from_gregorian_utc(2000, 1, 1, 11, 58, 55, 816_000_000);
        let angle = (teme_to_eme2000_matrix(j2000) - Matrix3::identity()).norm();
        assert!(angle < 20.0 * ARCSEC_RAD * 2.0, "{angle}");
    }
}
