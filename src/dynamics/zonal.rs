//! The Earth's zonal harmonics J2..Jn ([`ZonalGravity`]) and the built-in EGM96 values
//! ([`egm96_zonal_coefficients`], up to degree [`EGM96_MAX_DEGREE`]).
//!
//! # Model
//!
//! The field is axisymmetric about the ECI z axis (taken as the Earth's polar axis):
//!
//! `U(r) = (mu/r) (1 - sum_{n=2..N} J_n (R/r)^n P_n(s))`, `s = z/r = sin(phi)` (geocentric latitude
//! `phi`), with `P_n` the Legendre polynomials and `J_n = -C_n0` the unnormalised zonal coefficients.
//! The acceleration is the gradient of `U`. Writing `rho_n = (R/r)^n`, `r_hat = r/|r|` and `z_hat` the
//! polar axis, differentiating `r^-(n+1) P_n(z/r)` with `grad s = (z_hat - s r_hat)/r` gives
//!
//! `a = -(mu/r^2) [ (1 - sum J_n rho_n ((n+1) P_n + s P_n')) r_hat + (sum J_n rho_n P_n') z_hat ]`,
//!
//! which contains no `1/cos(phi)` and is regular on the polar axis. `P_n` and `P_n' = dP_n/ds` come
//! from Bonnet's recursion `n P_n = (2n-1) s P_{n-1} - (n-1) P_{n-2}` and the derivative identity
//! `P_n' = n P_{n-1} + s P_{n-1}'` (both standard, e.g. Abramowitz & Stegun ch. 8 and 22), carried in
//! a loop (nothing is allocated per call). With `J2` alone the expression reduces term by term to the closed
//! form of [`crate::orbit::GravityModel::J2`].
//!
//! # EGM96 values
//!
//! `J_n = -sqrt(2n+1) C̄_n0` from the fully normalised zonal coefficients of EGM96 (Lemoine et al.,
//! *The Development of the Joint NASA GSFC and NIMA Geopotential Model EGM96*, NASA/TP-1998-206861,
//! 1998), as distributed in the file `egm96_to360.ascii` (tide-free). The table below is that file's
//! `C̄_n0` column verbatim for n = 2..20, read from two independent copies: GMAT's
//! `application/data/gravity/earth/EGM96.cof` (a conversion of `egm96_to360.ascii`, degrees 2..360) and,
//! for n = 3..12, GPSTk's `EGM96GravityModel.cpp` table (GPSTk alters only C̄20 there, to the IERS 2003
//! value); the unnormalised `J_n` this gives agree with the EGM96 zonal table of Vallado,
//! *Fundamentals of Astrodynamics and Applications*, Appendix D, to its 12 significant figures (tested
//! below). `J2` is taken as the crate's [`EarthModel::WGS84_EGM96`] `j2` itself (1.08262668e-3, the
//! EGM96 value `-sqrt(5) C̄20 = 1.0826266836e-3` rounded to 9 significant figures), so that a zonal
//! field of degree 2 is the same physics as the `j2` model.

use nalgebra::Vector3;

use crate::orbit::EarthModel;

/// The highest degree whose EGM96 zonal coefficient is built in (J2..J20).
pub const EGM96_MAX_DEGREE: usize = 20;

/// The highest degree [`ZonalGravity`] accepts (J2..J50, 49 coefficients).
const MAX_DEGREE: usize = 50;

/// EGM96 fully normalised zonal coefficients `C̄_n0` \[dimensionless\], n = 2..=20 (index n - 2),
/// verbatim from `egm96_to360.ascii` (see the module documentation for the sources).
const EGM96_NORMALISED_C_N0: [f64; EGM96_MAX_DEGREE - 1] = [
    -0.484165371736e-03, // n = 2
    0.957254173792e-06,  // n = 3
    0.539873863789e-06,  // n = 4
    0.685323475630e-07,  // n = 5
    -0.149957994714e-06, // n = 6
    0.909789371450e-07,  // n = 7
    0.496711667324e-07,  // n = 8
    0.276714300853e-07,  // n = 9
    0.526222488569e-07,  // n = 10
    -0.509613707522e-07, // n = 11
    0.377252636558e-07,  // n = 12
    0.422982206413e-07,  // n = 13
    -0.242786502921e-07, // n = 14
    0.147910068708e-08,  // n = 15
    -0.315322986722e-08, // n = 16
    0.197605066395e-07,  // n = 17
    0.508691038332e-08,  // n = 18
    -0.325780965394e-08, // n = 19
    0.222384610651e-07,  // n = 20
];

/// The EGM96 unnormalised zonal coefficients `[J2, J3, ..., J_degree]` \[dimensionless\] for
/// `degree` = n (a list of n - 1 values).
///
/// `J_n = -sqrt(2n+1) C̄_n0` for n >= 3; `J2` is exactly [`EarthModel::WGS84_EGM96`]`.j2`
/// (= 1.08262668e-3, the EGM96 value rounded to 9 significant figures), so that degree 2 reproduces
/// the crate's J2 model. J3..J6 are -2.53265649e-6, -1.61962159e-6, -2.27296083e-7, 5.40681239e-7
/// (rounded to 9 figures).
///
/// # Panics
/// If `degree` is outside `2..=`[`EGM96_MAX_DEGREE`].
pub fn egm96_zonal_coefficients(degree: usize) -> Vec<f64> {
    assert!(
        (2..=EGM96_MAX_DEGREE).contains(&degree),
        "EGM96 zonal degree {degree} is outside 2..={EGM96_MAX_DEGREE}"
    );
    (2..=degree)
        .map(|n| {
            if n == 2 {
                EarthModel::WGS84_EGM96.j2
            } else {
                -((2 * n + 1) as f64).sqrt() * EGM96_NORMALISED_C_N0[n - 2]
            }
        })
        .collect()
}

/// Point mass + zonal harmonics J2..Jn of an axisymmetric Earth (see the module documentation for
/// the potential and its gradient). The ECI z axis is the symmetry (polar) axis.
#[derive(Clone, Debug, PartialEq)]
pub struct ZonalGravity {
    /// `mu = G M` \[m^3/s^2\].
    mu_m3_s2: f64,
    /// Reference radius `R` of the expansion \[m\].
    radius_m: f64,
    /// `J2..Jn` \[dimensionless\], index k for degree k + 2.
    coefficients: Vec<f64>,
}

/// The sums over degree of one evaluation (see [`ZonalGravity::sums`]).
struct ZonalSums {
    /// `sum J_n rho_n P_n` (potential).
    potential: f64,
    /// `sum J_n rho_n ((n+1) P_n + s P_n')` (along `r_hat`).
    radial: f64,
    /// `sum J_n rho_n P_n'` (along the polar axis).
    polar: f64,
}

impl ZonalGravity {
    /// The field of `earth`'s `mu_m3_s2` \[m^3/s^2\] and `equatorial_radius_m` \[m\] (the reference
    /// radius `R`) with `coefficients` = `[J2, J3, ..., Jn]` \[dimensionless, unnormalised\]. The
    /// `earth.j2` field is not read: `coefficients[0]` is J2 (zero is allowed, e.g. for a J3-only
    /// field `[0.0, J3]`).
    ///
    /// # Panics
    /// If `coefficients` is empty or longer than 49 (degree above 50).
    pub fn new(earth: &EarthModel, coefficients: Vec<f64>) -> Self {
        assert!(
            (1..MAX_DEGREE).contains(&coefficients.len()),
            "zonal coefficients J2..Jn: {} values given, 1 to {} allowed (degree 2 to {MAX_DEGREE})",
            coefficients.len(),
            MAX_DEGREE - 1
        );
        Self {
            mu_m3_s2: earth.mu_m3_s2,
            radius_m: earth.equatorial_radius_m,
            coefficients,
        }
    }

    /// The highest degree n of the field (2 to 50).
    pub fn degree(&self) -> usize {
        self.coefficients.len() + 1
    }

    /// The coefficients `[J2, ..., Jn]` \[dimensionless, unnormalised\].
    pub fn coefficients(&self) -> &[f64] {
        &self.coefficients
    }

    /// The gravitational potential \[m^2/s^2\] at `position_eci_m` \[m\] (ECI, z on the polar axis):
    /// `U = (mu/r) (1 - sum J_n (R/r)^n P_n(z/r))`, positive (the acceleration is `+grad U`).
    /// Not finite at the origin (not checked).
    #[inline]
    pub fn potential_m2_s2(&self, position_eci_m: &Vector3<f64>) -> f64 {
        let r = position_eci_m.norm();
        let sums = self.sums(position_eci_m.z / r, self.radius_m / r);
        self.mu_m3_s2 / r * (1.0 - sums.potential)
    }

    /// The gravitational acceleration \[m/s^2\], ECI, at `position_eci_m` \[m\] (ECI, z on the polar
    /// axis): point mass plus the zonal terms, the gradient of [`ZonalGravity::potential_m2_s2`].
    /// Regular at any latitude including the poles; allocates nothing. Not finite at the origin (not
    /// checked, as the function sits in the innermost loop).
    #[inline]
    pub fn acceleration_m_s2(&self, position_eci_m: &Vector3<f64>) -> Vector3<f64> {
        let r2 = position_eci_m.norm_squared();
        let r = r2.sqrt();
        let sums = self.sums(position_eci_m.z / r, self.radius_m / r);
        // -(mu/r^2) [(1 - radial) r/|r| + polar z_hat] = -(mu/r^3) [(1 - radial) r + polar |r| z_hat].
        let mu_over_r3 = self.mu_m3_s2 / (r2 * r);
        let along_r = -mu_over_r3 * (1.0 - sums.radial);
        Vector3::new(
            along_r * position_eci_m.x,
            along_r * position_eci_m.y,
            along_r * position_eci_m.z - mu_over_r3 * r * sums.polar,
        )
    }

    /// The three degree sums at `s = z/r` and `ratio = R/r`, by the Legendre recursions.
    #[inline]
    fn sums(&self, s: f64, ratio: f64) -> ZonalSums {
        // Degree 1: P1 = s, P1' = 1; degree 0: P0 = 1.
        let (mut p_prev2, mut p_prev) = (1.0, s);
        let mut dp_prev = 1.0;
        let mut rho = ratio; // (R/r)^1
        let mut out = ZonalSums {
            potential: 0.0,
            radial: 0.0,
            polar: 0.0,
        };
        for (k, &j) in self.coefficients.iter().enumerate() {
            let n = (k + 2) as f64;
            let p = ((2.0 * n - 1.0) * s * p_prev - (n - 1.0) * p_prev2) / n;
            let dp = n * p_prev + s * dp_prev;
            rho *= ratio;
            let j_rho = j * rho;
            out.potential += j_rho * p;
            out.radial += j_rho * ((n + 1.0) * p + s * dp);
            out.polar += j_rho * dp;
            p_prev2 = p_prev;
            p_prev = p;
            dp_prev = dp;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    //! References used here are independent of the code: closed forms of P2..P6, the exact field on
    //! the polar axis, the crate's J2 closed form, the written-out J3 gradient, a finite-difference
    //! gradient of the potential and a second transcription of the EGM96 zonals.

    use super::*;
    use crate::dynamics::{Bodies, ForceModel, Gravity, Instant, PhysicalProperties};
    use crate::orbit::GravityModel;

    const EARTH: EarthModel = EarthModel::WGS84_EGM96;
    const EPS: f64 = f64::EPSILON;

    /// Unit vector at geocentric latitude `lat` and longitude `lon` \[rad\], scaled to `r` \[m\].
    fn at(r: f64, lat: f64, lon: f64) -> Vector3<f64> {
        r * Vector3::new(lat.cos() * lon.cos(), lat.cos() * lon.sin(), lat.sin())
    }

    #[test]
    fn egm96_zonals_match_vallado_appendix_d_and_the_quoted_values() {
        // Vallado, Fundamentals of Astrodynamics and Applications, Appendix D, EGM96 unnormalised
        // zonals C_n0 = -J_n (12 significant figures), as transcribed in Trevor Wolf's
        // `spherical_harmonic_arrays` (2018): an independent source from the normalised file.
        const VALLADO_C_N0: [f64; 19] = [
            -1.08262668355e-03,
            2.53265648533e-06,
            1.61962159137e-06,
            2.27296082869e-07,
            -5.40681239107e-07,
            3.52359908418e-07,
            2.04799466985e-07,
            1.20616967365e-07,
            2.41145438626e-07,
            -2.44402148325e-07,
            1.88626318279e-07,
            2.19788001661e-07,
            -1.30744533118e-07,
            8.23528409456e-09,
            -1.81139265112e-08,
            1.16904733834e-07,
            3.09424678746e-08,
            -2.03450147680e-08,
            1.42395629049e-07,
        ];
        let j = egm96_zonal_coefficients(EGM96_MAX_DEGREE);
        assert_eq!(j.len(), 19);
        // J3..J20: 12-figure rounding of the reference is at most 5e-12 relative (leading digit 1).
        for (k, (&jn, &c)) in j.iter().zip(VALLADO_C_N0.iter()).enumerate().skip(1) {
            let rel = (jn + c).abs() / c.abs();
            assert!(
                rel <= 5e-12,
                "J{}: {jn:e} vs Vallado {:e}: {rel:e}",
                k + 2,
                -c
            );
        }
        // J2 is the crate constant, the EGM96 value rounded to 9 figures (|error| <= 0.5e-11).
        assert_eq!(j[0], EarthModel::WGS84_EGM96.j2);
        let j2_full = -5f64.sqrt() * EGM96_NORMALISED_C_N0[0];
        assert!((j2_full - j[0]).abs() <= 0.5e-11, "{j2_full:e}");
        assert!((j2_full + VALLADO_C_N0[0]).abs() <= 5e-12 * j2_full);
        // The values quoted in the issue (9 figures: 5e-9 relative).
        let quoted = [
            1.08262668e-3,
            -2.53265649e-6,
            -1.61962159e-6,
            -2.27296083e-7,
            5.40681239e-7,
        ];
        for (k, (&jn, &q)) in j.iter().zip(quoted.iter()).enumerate() {
            assert!(
                (jn - q).abs() <= 5e-9 * q.abs(),
                "J{}: {jn:e} vs {q:e}",
                k + 2
            );
        }
        // Prefixes agree.
        assert_eq!(egm96_zonal_coefficients(6), j[..5].to_vec());
        assert_eq!(egm96_zonal_coefficients(2), vec![EARTH.j2]);
    }

    #[test]
    #[should_panic(expected = "outside 2..=20")]
    fn egm96_degree_21_panics() {
        let _ = egm96_zonal_coefficients(21);
    }

    #[test]
    #[should_panic(expected = "outside 2..=20")]
    fn egm96_degree_1_panics() {
        let _ = egm96_zonal_coefficients(1);
    }

    #[test]
    #[should_panic(expected = "1 to 49 allowed")]
    fn empty_coefficients_panic() {
        let _ = ZonalGravity::new(&EARTH, Vec::new());
    }

    #[test]
    #[should_panic(expected = "1 to 49 allowed")]
    fn degree_51_panics() {
        let _ = ZonalGravity::new(&EARTH, vec![0.0; 50]);
    }

    #[test]
    fn degree_name_and_force_model_delegation() {
        let z = ZonalGravity::new(&EARTH, egm96_zonal_coefficients(8));
        assert_eq!(z.degree(), 8);
        assert_eq!(z.coefficients().len(), 7);
        assert_eq!(ZonalGravity::new(&EARTH, vec![1e-3; 49]).degree(), 50);
        // In a force set the zonal field is a `Gravity`, named by its degree, reading only the position.
        let gravity = Gravity::Zonal(z.clone());
        assert_eq!(gravity.name(), "gravity (zonal J2..J8)");
        assert_eq!(gravity.bodies(), Bodies::default());
        let p = at(7.0e6, 0.4, 1.1);
        let a = gravity.acceleration_eci_m_s2(
            &Instant::new(1.0e8, Bodies::default()),
            &p,
            &Vector3::new(1.0, 2.0, 3.0),
            &PhysicalProperties::point_mass(100.0),
        );
        assert_eq!(a, z.acceleration_m_s2(&p));
    }

    #[test]
    fn potential_matches_closed_form_legendre_polynomials() {
        // P2..P6 written out (the explicit forms of e.g. Abramowitz & Stegun ch. 22), one degree at a time.
        let closed: [fn(f64) -> f64; 5] = [
            |s| (3.0 * s * s - 1.0) / 2.0,
            |s| (5.0 * s.powi(3) - 3.0 * s) / 2.0,
            |s| (35.0 * s.powi(4) - 30.0 * s * s + 3.0) / 8.0,
            |s| (63.0 * s.powi(5) - 70.0 * s.powi(3) + 15.0 * s) / 8.0,
            |s| (231.0 * s.powi(6) - 315.0 * s.powi(4) + 105.0 * s * s - 5.0) / 16.0,
        ];
        for (k, pn) in closed.iter().enumerate() {
            let n = k + 2;
            let mut c = vec![0.0; n - 1];
            c[n - 2] = 1e-3;
            let z = ZonalGravity::new(&EARTH, c);
            for &(r, lat) in &[
                (6.5e6, 0.3),
                (7.2e6, -1.2),
                (4.2e7, 0.9),
                (6.4e6, std::f64::consts::FRAC_PI_2 - 1e-4),
            ] {
                let p = at(r, lat, 0.7);
                let s = p.z / p.norm();
                let expected = EARTH.mu_m3_s2 / p.norm()
                    * (1.0 - 1e-3 * (EARTH.equatorial_radius_m / p.norm()).powi(n as i32) * pn(s));
                let got = z.potential_m2_s2(&p);
                // Both sides are a few roundings of a value dominated by mu/r.
                assert!(
                    (got - expected).abs() <= 8.0 * EPS * expected.abs(),
                    "P{n} at r={r} lat={lat}: {got} vs {expected}"
                );
            }
        }
    }

    #[test]
    fn on_the_polar_axis_every_degree_to_50_is_exact() {
        // On the axis P_n(+-1) = (+-1)^n, so U(z) = mu/|z| (1 - sum J_n (R/|z|)^n (sign z)^n) and
        // a_z = dU/dz = -sign(z) mu/z^2 (1 - sum (n+1) J_n (R/|z|)^n (sign z)^n); a_x = a_y = 0.
        let coefficients: Vec<f64> = (2..=50)
            .map(|n| 1e-3 * if n % 3 == 0 { -1.0 } else { 1.0 } / n as f64)
            .collect();
        let z = ZonalGravity::new(&EARTH, coefficients.clone());
        for &zc in &[6.6e6f64, -6.6e6, 7.5e6, -4.0e7] {
            let p = Vector3::new(0.0, 0.0, zc);
            let r: f64 = zc.abs();
            let sign: f64 = zc.signum();
            let (mut su, mut sa) = (0.0, 0.0);
            for (k, &j) in coefficients.iter().enumerate() {
                let n = k + 2;
                let term = j * (EARTH.equatorial_radius_m / r).powi(n as i32) * sign.powi(n as i32);
                su += term;
                sa += (n + 1) as f64 * term;
            }
            let u = EARTH.mu_m3_s2 / r * (1.0 - su);
            let az = -sign * EARTH.mu_m3_s2 / (r * r) * (1.0 - sa);
            assert!((z.potential_m2_s2(&p) - u).abs() <= 8.0 * EPS * u);
            let a = z.acceleration_m_s2(&p);
            assert_eq!((a.x, a.y), (0.0, 0.0));
            assert!((a.z - az).abs() <= 8.0 * EPS * az.abs(), "{} vs {az}", a.z);
        }
    }

    #[test]
    fn j2_alone_is_the_crate_j2_closed_form() {
        let z = ZonalGravity::new(&EARTH, egm96_zonal_coefficients(2));
        let mut worst: f64 = 0.0;
        for &(r, lat, lon) in &[
            (6.6e6, 0.0, 0.0),
            (7.0e6, 0.7, 1.9),
            (7.0e6, -1.3, -2.5),
            (6.4e6, std::f64::consts::FRAC_PI_2 - 3e-8, 0.3),
            (4.2164e7, 0.05, 3.0),
            (2.0e7, -0.9, 0.1),
        ] {
            let p = at(r, lat, lon);
            let reference = GravityModel::J2.acceleration_m_s2(&EARTH, &p);
            let rel = (z.acceleration_m_s2(&p) - reference).norm() / reference.norm();
            worst = worst.max(rel);
        }
        eprintln!("J2 alone vs GravityModel::J2: worst relative difference {worst:.2e}");
        // Same terms, different association of a few roundings: a few ulps of |a|.
        assert!(worst <= 4.0 * EPS, "worst relative difference {worst:e}");
        let pole = Vector3::new(0.0, 0.0, 7.0e6);
        let rel = (z.acceleration_m_s2(&pole) - GravityModel::J2.acceleration_m_s2(&EARTH, &pole))
            .norm()
            / (EARTH.mu_m3_s2 / 4.9e13);
        assert!(rel <= 4.0 * EPS, "{rel:e}");
    }

    #[test]
    fn j3_term_matches_the_written_out_gradient() {
        // Gradient of U3 = -(mu J3 R^3 / 2) (5 z^3 / r^7 - 3 z / r^5), as in Vallado (Ch. 8, the J3
        // terms) and e.g. jdclouse/AstroTools `J3_accel.m`, written here without the 1/z factor:
        // a_x = -(5/2) mu J3 R^3 x / r^7 (3 z - 7 z^3 / r^2), a_y likewise,
        // a_z = -(5/2) mu J3 R^3 / r^7 (6 z^2 - 7 z^4 / r^2 - (3/5) r^2).
        let j3 = egm96_zonal_coefficients(3)[1];
        let z = ZonalGravity::new(&EARTH, vec![0.0, j3]);
        let mu = EARTH.mu_m3_s2;
        let big_r3 = EARTH.equatorial_radius_m.powi(3);
        for &(r, lat, lon) in &[
            (7.0e6, 0.6, 0.2),
            (6.8e6, -0.9, 2.0),
            (7.0e6, 0.0, 1.0),
            (7.1e6, std::f64::consts::FRAC_PI_2, 0.0),
            (6.5e6, -1.5, -3.0),
            (2.6e7, 0.3, 0.5),
        ] {
            let p = at(r, lat, lon);
            let (x, y, zc) = (p.x, p.y, p.z);
            let rn = p.norm();
            let r2 = rn * rn;
            let k = -2.5 * mu * j3 * big_r3 / rn.powi(7);
            let h = 3.0 * zc - 7.0 * zc.powi(3) / r2;
            let a_j3 = Vector3::new(
                k * x * h,
                k * y * h,
                k * (6.0 * zc * zc - 7.0 * zc.powi(4) / r2 - 0.6 * r2),
            );
            let expected = -mu / (r2 * rn) * p + a_j3;
            let got = z.acceleration_m_s2(&p);
            // Rounding of both sums relative to the dominant point-mass term: a few ulps.
            let err = (got - expected).norm();
            assert!(err <= 4.0 * EPS * expected.norm(), "at {p:?}: {err:e}");
            // And the J3 part itself is resolved far above that rounding (1e-9 of it or better).
            let pm = -mu / (r2 * rn) * p;
            let rel = ((got - pm) - a_j3).norm() / a_j3.norm();
            eprintln!(
                "J3 at r={r} lat={lat}: |a - closed form| = {err:.2e} m/s^2, J3 part relative {rel:.2e}"
            );
            assert!(rel <= 1e-9, "J3 part at {p:?}: relative {rel:e}");
        }
    }

    /// Central difference of `potential_m2_s2` along each axis at `p` with step `h` \[m\], the step taken
    /// as the float difference of the two abscissae (exact), and the error bound of the difference:
    /// truncation `h^2/6 M3` (with `M3` a bound on the third derivative, below) plus rounding
    /// `c eps |U| / h` (each U carries at most `c/2 = 2` ulps: `mu/r`, `1 - sum` and their product).
    fn fd_gradient(z: &ZonalGravity, p: &Vector3<f64>, h: f64) -> (Vector3<f64>, f64) {
        let mut g = Vector3::zeros();
        for i in 0..3 {
            let (mut plus, mut minus) = (*p, *p);
            plus[i] += h;
            minus[i] -= h;
            let step = plus[i] - minus[i];
            g[i] = (z.potential_m2_s2(&plus) - z.potential_m2_s2(&minus)) / step;
        }
        let r = p.norm();
        let ratio = z.radius_m / r;
        // |d^3/dx^3 (1/r)| <= 6/r^4; a degree-n term is J_n R^n r^-(n+1) P_n, whose third derivatives
        // are bounded by (n+1)(n+2)(n+3) |J_n| R^n / r^(n+4) (the value of d^3/dz^3 on the axis).
        let mut m3 = 6.0;
        for (k, &j) in z.coefficients.iter().enumerate() {
            let n = (k + 2) as f64;
            m3 += (n + 1.0) * (n + 2.0) * (n + 3.0) * j.abs() * ratio.powi(k as i32 + 2);
        }
        m3 *= z.mu_m3_s2 / r.powi(4);
        let u = z.potential_m2_s2(p).abs();
        let bound = h * h / 6.0 * m3 + 4.0 * EPS * u / h;
        (g, bound)
    }

    #[test]
    fn acceleration_is_the_finite_difference_gradient_of_the_potential() {
        let egm96 = ZonalGravity::new(&EARTH, egm96_zonal_coefficients(EGM96_MAX_DEGREE));
        // Degree 50 with large coefficients, so that the high degrees matter at low altitude.
        let synthetic = ZonalGravity::new(
            &EARTH,
            (2..=50)
                .map(|n| 2e-3 * if n % 2 == 0 { 1.0 } else { -0.7 } / (n as f64).sqrt())
                .collect(),
        );
        for (label, z) in [("EGM96 J2..J20", &egm96), ("synthetic J2..J50", &synthetic)] {
            for &(r, lat, lon) in &[
                (6.378137e6, 0.45, 0.3),
                (7.0e6, 0.7, 1.9),
                (7.0e6, 0.0, -2.0),
                (6.8e6, std::f64::consts::FRAC_PI_2 - 1e-4, 0.8), // 0.7 km from the axis
                (6.8e6, -std::f64::consts::FRAC_PI_2 + 1e-7, -0.4), // 0.7 m from the axis
                (4.2164e7, 0.1, 2.2),
            ] {
                let p = at(r, lat, lon);
                // Step balancing h^2/6 * 6 mu/r^4 against 4 eps (mu/r) / h: h = (4 eps r^3)^(1/3),
                // 67 m at r = 7000 km; the bound is then ~1.5e-9 m/s^2 there (2e-10 relative).
                let h = (4.0 * EPS * r.powi(3)).cbrt();
                let (g, bound) = fd_gradient(z, &p, h);
                let a = z.acceleration_m_s2(&p);
                let err = (a - g).amax();
                eprintln!(
                    "FD {label} r={r} lat={lat:.7}: h={h:.1} m, |a - grad U|max = {err:.2e} m/s^2 \
                     (bound {bound:.2e}, {:.1e} of |a|)",
                    err / a.norm()
                );
                assert!(
                    err <= bound,
                    "{label} at r={r} lat={lat}: |a - grad U|max = {err:e} > bound {bound:e} (h = {h} m)"
                );
                // The zonal part is resolved: the error is far below the J2..Jn acceleration.
                let zonal = (a + z.mu_m3_s2 / r.powi(3) * p).norm();
                assert!(
                    err <= 1e-5 * zonal,
                    "{label}: {err:e} vs zonal part {zonal:e}"
                );
            }
        }
    }

    #[test]
    fn continuous_across_the_pole() {
        // Approaching the axis the acceleration tends to the on-axis value (no 1/cos(phi)).
        let z = ZonalGravity::new(&EARTH, egm96_zonal_coefficients(EGM96_MAX_DEGREE));
        let axis = z.acceleration_m_s2(&Vector3::new(0.0, 0.0, 7.0e6));
        for d in [1e-3, 1.0, 10.0] {
            let a = z.acceleration_m_s2(&Vector3::new(
                d,
                -d,
                (7.0e6f64 * 7.0e6 - 2.0 * d * d).sqrt(),
            ));
            // Horizontal part ~ (mu/r^3) d (1 + O(J2)); vertical change is second order in d/r.
            let horizontal = EARTH.mu_m3_s2 / 7.0e6f64.powi(3) * d * 1.01;
            assert!(a.x.abs() <= horizontal && a.y.abs() <= horizontal, "{a:?}");
            assert!(
                (a.z - axis.z).abs()
                    <= 1e-14 * axis.z.abs() + 8.0 * (d / 7.0e6).powi(2) * axis.z.abs()
            );
        }
    }
}
