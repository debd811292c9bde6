//! The modified Harris–Priester atmosphere ([`HarrisPriester`]) of Montenbruck & Gill, *Satellite
//! Orbits* (Springer, 2000), §3.5.2 and Table 3.1: tabulated minimum (night) and maximum (day)
//! densities from 100 to 1 000 km for mean solar activity, interpolated exponentially in height, and
//! a diurnal bulge whose apex lags the Sun by 30° in right ascension.

use nalgebra::Vector3;

use super::{refuse_exponential_keys, Atmosphere, FLOOR_ALTITUDE_M};
use crate::dynamics::config::{check, DragConfig, ForceConfigError};

/// Montenbruck & Gill (2000), Table 3.1, in SI: (height h_i \[m\], minimum density rho_min(h_i)
/// \[kg/m^3\], maximum density rho_max(h_i) \[kg/m^3\]), mean solar activity, 100 to 1 000 km. The book
/// prints g/km^3 (1 g/km^3 = 1e-12 kg/m^3).
///
/// Cross-checked by a script, all 150 numbers, in three independent transcriptions that agree on every
/// digit: Orekit `src/main/java/org/orekit/forces/drag/atmosphere/HarrisPriester.java` (`ALT_RHO`, the
/// default table, "given in the referenced book from Montenbruck & Gill", kg/m^3 and m); the MATLAB
/// port of Montenbruck & Gill's own routine `Density_HP` (vtunghau/ODS-SOFT `SOM/Density_HP.m`,
/// g/km^3 and km); and SpOCK `lib/Astrodynamics/Environment/HarrisPriester.h` (g/km^3 and km). No
/// disagreement was found.
const HARRIS_PRIESTER_TABLE: [(f64, f64, f64); 50] = [
    (100_000.0, 4.974e-07, 4.974e-07),
    (120_000.0, 2.490e-08, 2.490e-08),
    (130_000.0, 8.377e-09, 8.710e-09),
    (140_000.0, 3.899e-09, 4.059e-09),
    (150_000.0, 2.122e-09, 2.215e-09),
    (160_000.0, 1.263e-09, 1.344e-09),
    (170_000.0, 8.008e-10, 8.758e-10),
    (180_000.0, 5.283e-10, 6.010e-10),
    (190_000.0, 3.617e-10, 4.297e-10),
    (200_000.0, 2.557e-10, 3.162e-10),
    (210_000.0, 1.839e-10, 2.396e-10),
    (220_000.0, 1.341e-10, 1.853e-10),
    (230_000.0, 9.949e-11, 1.455e-10),
    (240_000.0, 7.488e-11, 1.157e-10),
    (250_000.0, 5.709e-11, 9.308e-11),
    (260_000.0, 4.403e-11, 7.555e-11),
    (270_000.0, 3.430e-11, 6.182e-11),
    (280_000.0, 2.697e-11, 5.095e-11),
    (290_000.0, 2.139e-11, 4.226e-11),
    (300_000.0, 1.708e-11, 3.526e-11),
    (320_000.0, 1.099e-11, 2.511e-11),
    (340_000.0, 7.214e-12, 1.819e-11),
    (360_000.0, 4.824e-12, 1.337e-11),
    (380_000.0, 3.274e-12, 9.955e-12),
    (400_000.0, 2.249e-12, 7.492e-12),
    (420_000.0, 1.558e-12, 5.684e-12),
    (440_000.0, 1.091e-12, 4.355e-12),
    (460_000.0, 7.701e-13, 3.362e-12),
    (480_000.0, 5.474e-13, 2.612e-12),
    (500_000.0, 3.916e-13, 2.042e-12),
    (520_000.0, 2.819e-13, 1.605e-12),
    (540_000.0, 2.042e-13, 1.267e-12),
    (560_000.0, 1.488e-13, 1.005e-12),
    (580_000.0, 1.092e-13, 7.997e-13),
    (600_000.0, 8.070e-14, 6.390e-13),
    (620_000.0, 6.012e-14, 5.123e-13),
    (640_000.0, 4.519e-14, 4.121e-13),
    (660_000.0, 3.430e-14, 3.325e-13),
    (680_000.0, 2.632e-14, 2.691e-13),
    (700_000.0, 2.043e-14, 2.185e-13),
    (720_000.0, 1.607e-14, 1.779e-13),
    (740_000.0, 1.281e-14, 1.452e-13),
    (760_000.0, 1.036e-14, 1.190e-13),
    (780_000.0, 8.496e-15, 9.776e-14),
    (800_000.0, 7.069e-15, 8.059e-14),
    (840_000.0, 4.680e-15, 5.741e-14),
    (880_000.0, 3.200e-15, 4.210e-14),
    (920_000.0, 2.210e-15, 3.130e-14),
    (960_000.0, 1.560e-15, 2.360e-14),
    (1_000_000.0, 1.150e-15, 1.810e-14),
];

/// The top of the table \[m\]: above it the density is 0.
const TOP_ALTITUDE_M: f64 = 1_000_000.0;

/// The modified Harris–Priester density (Montenbruck & Gill 2000, §3.5.2):
///
/// `rho = rho_min(h) + (rho_max(h) - rho_min(h)) cos^n(psi / 2)`,
///
/// with `rho_min`, `rho_max` interpolated exponentially between the table heights h_i <= h < h_(i+1)
/// (eq. 3.100–3.103: scale heights `H = (h_i - h_(i+1)) / ln(rho(h_(i+1)) / rho(h_i))`, then
/// `rho(h) = rho(h_i) exp((h_i - h) / H)`), and `psi` the angle between the satellite's position and
/// the apex of the diurnal bulge: the unit vector of right ascension = the Sun's + `lag_rad` and
/// declination = the Sun's (ECI; eq. 3.104–3.105), `cos^n(psi/2) = ((1 + cos psi) / 2)^(n/2)`.
///
/// Above 1 000 km (the top of the table) the density is 0, as in Montenbruck & Gill's routine and
/// Orekit. Below 100 km (the floor; Orekit throws there) the 100–120 km band is extrapolated, down to
/// 0 m, below which the 0 m value is returned: finite for every finite altitude.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HarrisPriester {
    /// The cosine exponent n (2 for low-inclination orbits to 6 for polar ones; default 4).
    pub cosine_exponent: f64,
    /// The lag of the bulge apex behind the Sun in right ascension \[rad\] (default 30° = pi/6).
    pub lag_rad: f64,
}

impl HarrisPriester {
    /// The default cosine exponent n (Orekit's default; Montenbruck & Gill's routine fixes n = 6).
    pub const DEFAULT_COSINE_EXPONENT: f64 = 4.0;
    /// The default lag of the bulge apex \[deg\] (Montenbruck & Gill 2000, §3.5.2).
    pub const DEFAULT_LAG_DEG: f64 = 30.0;

    /// The model with cosine exponent `cosine_exponent` (2 to 6) and bulge lag `lag_deg` \[deg\]
    /// (0 to 90).
    ///
    /// # Errors
    /// A [`ForceConfigError`] naming `drag.cosine_exponent` or `drag.lag_deg` when a value is not
    /// finite or out of its range.
    pub fn new(cosine_exponent: f64, lag_deg: f64) -> Result<Self, ForceConfigError> {
        let cosine_exponent = check(
            "drag.cosine_exponent",
            cosine_exponent,
            |v| (2.0..=6.0).contains(&v),
            "a cosine exponent from 2 (low inclination) to 6 (polar); default 4",
        )?;
        let lag_deg = check(
            "drag.lag_deg",
            lag_deg,
            |v| (0.0..=90.0).contains(&v),
            "a lag of the diurnal bulge from 0 to 90 deg; default 30",
        )?;
        Ok(Self {
            cosine_exponent,
            lag_rad: lag_deg.to_radians(),
        })
    }

    /// The model of a `[drag]` table with `atmosphere = "harris-priester"`: `cosine_exponent` and
    /// `lag_deg` or their defaults; the one-layer exponential keys are refused.
    pub(crate) fn from_config(config: &DragConfig) -> Result<Self, ForceConfigError> {
        refuse_exponential_keys(config, "harris-priester")?;
        Self::new(
            config
                .cosine_exponent
                .unwrap_or(Self::DEFAULT_COSINE_EXPONENT),
            config.lag_deg.unwrap_or(Self::DEFAULT_LAG_DEG),
        )
    }

    /// The minimum and maximum densities \[kg/m^3\] at `altitude_m` \[m\], interpolated exponentially
    /// in the table (eq. 3.100–3.103); `None` above the top of the table (1 000 km). Below 100 km the
    /// lowest band is extrapolated (to at most 0 m).
    pub fn min_max_density_kg_per_m3(altitude_m: f64) -> Option<(f64, f64)> {
        if altitude_m > TOP_ALTITUDE_M {
            return None;
        }
        // `<` and not `max`: a NaN altitude stays NaN.
        let h = if altitude_m < 0.0 { 0.0 } else { altitude_m };
        let band = HARRIS_PRIESTER_TABLE
            .partition_point(|row| row.0 <= h)
            .saturating_sub(1)
            .min(HARRIS_PRIESTER_TABLE.len() - 2);
        let (h_i, min_i, max_i) = HARRIS_PRIESTER_TABLE[band];
        let (h_next, min_next, max_next) = HARRIS_PRIESTER_TABLE[band + 1];
        let interpolate = |rho_i: f64, rho_next: f64| {
            let scale_height_m = (h_i - h_next) / (rho_next / rho_i).ln();
            rho_i * ((h_i - h) / scale_height_m).exp()
        };
        Some((interpolate(min_i, min_next), interpolate(max_i, max_next)))
    }

    /// The unit vector of the diurnal bulge's apex, ECI: the Sun's direction `sun_eci_m` (non-zero)
    /// turned by the lag about the ECI z axis, i.e. right ascension = the Sun's + lag, declination =
    /// the Sun's.
    pub fn bulge_apex_unit_eci(&self, sun_eci_m: &Vector3<f64>) -> Vector3<f64> {
        let sun = sun_eci_m.normalize();
        let (sin_lag, cos_lag) = self.lag_rad.sin_cos();
        Vector3::new(
            sun.x * cos_lag - sun.y * sin_lag,
            sun.x * sin_lag + sun.y * cos_lag,
            sun.z,
        )
    }
}

impl Atmosphere for HarrisPriester {
    fn name(&self) -> &'static str {
        "harris-priester"
    }

    fn density_kg_per_m3(
        &self,
        altitude_m: f64,
        position_eci_m: &Vector3<f64>,
        sun_eci_m: &Vector3<f64>,
    ) -> f64 {
        let Some((rho_min, rho_max)) = Self::min_max_density_kg_per_m3(altitude_m) else {
            return 0.0;
        };
        let apex = self.bulge_apex_unit_eci(sun_eci_m);
        let cos_psi = apex.dot(position_eci_m) / position_eci_m.norm();
        // cos^2(psi/2) = (1 + cos psi)/2, kept >= 0 against rounding (a negative base would make the
        // fractional power NaN); `<` so that NaN stays NaN.
        let half = 0.5 + 0.5 * cos_psi;
        let cos2_half_psi = if half < 0.0 { 0.0 } else { half };
        rho_min + (rho_max - rho_min) * cos2_half_psi.powf(0.5 * self.cosine_exponent)
    }

    fn floor_altitude_m(&self) -> f64 {
        FLOOR_ALTITUDE_M
    }

    fn uses_sun(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::FRAC_PI_6;

    use super::*;

    /// 1 AU \[m\], the Sun's distance in these tests (the model reads only its direction).
    const AU: f64 = 1.495_978_707e11;
    /// A radius to put the satellite's direction at (the altitude is passed separately).
    const R: f64 = 6_878_137.0;

    fn default_model() -> HarrisPriester {
        HarrisPriester::new(4.0, 30.0).unwrap()
    }

    /// At every table height, with the satellite at the bulge apex (Sun at right ascension 0,
    /// declination 0, apex at right ascension 30°), the density is rho_max of Table 3.1; at the antapex
    /// it is rho_min. Relative tolerance 2e-15: at the apex cos psi is 1 to within the roundings of two
    /// normalisations, the lag rotation and a dot product (< 1e-15), so cos^4(psi/2) = 1 - O(1e-15);
    /// the interpolation at a table height is exact (exp(0) = 1) except at the top row, 1 000 km,
    /// reached from the 960 km row through a logarithm, a division and an exponential (< 5e-16).
    #[test]
    fn apex_gives_rho_max_and_antapex_rho_min_at_every_table_height() {
        let hp = default_model();
        let sun = Vector3::new(AU, 0.0, 0.0);
        let apex = Vector3::new(FRAC_PI_6.cos(), FRAC_PI_6.sin(), 0.0) * R;
        for (h, rho_min, rho_max) in HARRIS_PRIESTER_TABLE {
            let at_apex = hp.density_kg_per_m3(h, &apex, &sun);
            assert!(
                ((at_apex - rho_max) / rho_max).abs() < 2e-15,
                "apex at {h} m: {at_apex} vs {rho_max}"
            );
            let at_antapex = hp.density_kg_per_m3(h, &-apex, &sun);
            assert!(
                ((at_antapex - rho_min) / rho_min).abs() < 2e-15,
                "antapex at {h} m: {at_antapex} vs {rho_min}"
            );
        }
        // With no lag and the Sun on +x the antapex is exactly -x: cos psi = -1, the bulge term is 0
        // and the density is rho_min to the bit.
        let no_lag = HarrisPriester::new(4.0, 0.0).unwrap();
        let antapex = Vector3::new(-R, 0.0, 0.0);
        for (h, rho_min, _) in HARRIS_PRIESTER_TABLE[..HARRIS_PRIESTER_TABLE.len() - 1].iter() {
            assert_eq!(no_lag.density_kg_per_m3(*h, &antapex, &sun), *rho_min);
        }
    }

    /// At 410 km, halfway between the 400 and 420 km rows, exponential interpolation gives the
    /// geometric means: rho_min = sqrt(2.249e-12 * 1.558e-12) = 1.8718819407216899e-12 and rho_max =
    /// sqrt(7.492e-12 * 5.684e-12) = 6.5256821865610342e-12. With the satellite over the pole and the
    /// Sun on the equator (no lag), psi = 90° exactly, cos^2(psi/2) = 1/2, and cos^n(psi/2) = 2^(-n/2):
    /// n = 2, 4, 6 give rho_min + (rho_max - rho_min) / 2, / 4, / 8 =
    /// 4.1987820636413620e-12, 3.0353320021815259e-12, 2.4536069714516079e-12 (30-digit arithmetic,
    /// mpmath). Relative tolerance 2e-15: two logarithms, divisions, exponentials and products in the
    /// interpolation (< 1e-15) and the final combination (< 4e-16).
    #[test]
    fn mid_band_at_ninety_degrees_matches_hand_computed_values() {
        let sun = Vector3::new(AU, 0.0, 0.0);
        let over_pole = Vector3::new(0.0, 0.0, R);
        let (rho_min, rho_max) = HarrisPriester::min_max_density_kg_per_m3(410e3).unwrap();
        let close = |got: f64, want: f64| ((got - want) / want).abs() < 2e-15;
        assert!(close(rho_min, 1.871_881_940_721_689_8e-12), "{rho_min}");
        assert!(close(rho_max, 6.525_682_186_561_034e-12), "{rho_max}");
        for (n, want) in [
            (2.0, 4.198_782_063_641_362e-12),
            (4.0, 3.035_332_002_181_525_8e-12),
            (6.0, 2.453_606_971_451_608e-12),
        ] {
            let hp = HarrisPriester::new(n, 0.0).unwrap();
            let got = hp.density_kg_per_m3(410e3, &over_pole, &sun);
            assert!(close(got, want), "n = {n}: {got} vs {want}");
        }
        // A quarter of the way from 500 to 520 km: rho = rho_500 (rho_520 / rho_500)^(1/4), i.e.
        // 3.916e-13 (2.819e-13 / 3.916e-13)^0.25 = 3.6070800568567453e-13 and
        // 2.042e-12 (1.605e-12 / 2.042e-12)^0.25 = 1.9226957330646734e-12 (mpmath).
        let (rho_min, rho_max) = HarrisPriester::min_max_density_kg_per_m3(505e3).unwrap();
        assert!(close(rho_min, 3.607_080_056_856_745_5e-13), "{rho_min}");
        assert!(close(rho_max, 1.922_695_733_064_673_5e-12), "{rho_max}");
    }

    /// Orekit's `HarrisPriesterTest` (CS-SI/Orekit, src/test/java/org/orekit/forces/drag/atmosphere/
    /// HarrisPriesterTest.java): default table, n = 4, a point at geodetic latitude 0, longitude 0 and
    /// 500 km height on 2003-03-21 01:00 UTC. Orekit's Sun ephemeris puts that point where
    /// cos^2(psi/2) = 0.02163787 (the value `testParameterN` asserts), and `testStandard` expects
    /// rho = 3.9237e-13 kg/m^3 within 1e-17. The geometry is reproduced here with the satellite on +x and
    /// the Sun at right ascension psi - 30° so that the apex is psi from the satellite; the inputs
    /// and expected values are Orekit's, with Orekit's tolerances. (Rounding c2 to Orekit's 7 digits
    /// moves rho by < 4e-22, far inside 1e-17.)
    #[test]
    fn reproduces_orekit_harris_priester_test() {
        let c2_psi2: f64 = 0.021_637_87;
        let psi = (2.0 * c2_psi2 - 1.0).acos();
        let sun_ra = psi - FRAC_PI_6;
        let sun = Vector3::new(sun_ra.cos(), sun_ra.sin(), 0.0) * AU;
        let satellite = Vector3::new(6_378_136.46 + 500e3, 0.0, 0.0);
        let rho = |n: f64| {
            HarrisPriester::new(n, 30.0)
                .unwrap()
                .density_kg_per_m3(500e3, &satellite, &sun)
        };
        // testStandard.
        assert!((rho(4.0) - 3.9237e-13).abs() < 1e-17, "{}", rho(4.0));
        // testParameterN: (rho6 - rho2) / (rho4 - rho2) - 1 = cos^2(psi/2), within 1e-8.
        let ratio = (rho(6.0) - rho(2.0)) / (rho(4.0) - rho(2.0)) - 1.0;
        assert!((ratio - c2_psi2).abs() < 1e-8, "{ratio}");
        // testMaxAlt: 1500 km is above the table, density 0.
        let high = Vector3::new(6_378_136.46 + 1500e3, 0.0, 0.0);
        assert_eq!(default_model().density_kg_per_m3(1500e3, &high, &sun), 0.0);
    }

    #[test]
    fn top_of_table_and_below_floor() {
        let hp = default_model();
        let sun = Vector3::new(AU, 0.0, 0.0);
        let r = Vector3::new(R, 0.0, 0.0);
        assert!(hp.density_kg_per_m3(1000e3, &r, &sun) > 0.0);
        assert_eq!(hp.density_kg_per_m3(1000e3 + 1e-3, &r, &sun), 0.0);
        assert_eq!(HarrisPriester::min_max_density_kg_per_m3(1000.001e3), None);
        // Below 100 km the 100–120 km band is extrapolated: at 90 km,
        // 4.974e-7 (2.490e-8 / 4.974e-7)^(-1/2) = 4.974e-7 sqrt(4.974e-7 / 2.490e-8) =
        // 2.2230999957998518e-6 (mpmath); both densities are equal there, so the bulge does not
        // matter. Tolerance 2e-15 as above.
        let rho_90 = hp.density_kg_per_m3(90e3, &r, &sun);
        let want = 2.223_099_995_799_852e-6;
        assert!(((rho_90 - want) / want).abs() < 2e-15, "{rho_90} vs {want}");
        assert_eq!(
            hp.density_kg_per_m3(-1e5, &r, &sun),
            hp.density_kg_per_m3(0.0, &r, &sun)
        );
        assert!(hp.density_kg_per_m3(0.0, &r, &sun).is_finite());
        assert!(hp.uses_sun());
        assert_eq!(hp.floor_altitude_m(), 100e3);
    }

    #[test]
    fn defaults_and_validation() {
        let mut config = DragConfig {
            altitude: crate::dynamics::config::AltitudeName::Geodetic,
            ..DragConfig::new(crate::dynamics::config::AtmosphereName::HarrisPriester)
        };
        let hp = HarrisPriester::from_config(&config).unwrap();
        assert_eq!(hp.cosine_exponent, 4.0);
        assert_eq!(hp.lag_rad, 30.0_f64.to_radians());
        config.cosine_exponent = Some(6.5);
        let e = HarrisPriester::from_config(&config).unwrap_err();
        assert_eq!(e.key, "drag.cosine_exponent");
        assert_eq!(e.value, "6.5");
        assert!(e.allowed.contains("from 2"), "{e}");
        config.cosine_exponent = Some(1.5);
        assert_eq!(
            HarrisPriester::from_config(&config).unwrap_err().key,
            "drag.cosine_exponent"
        );
        config.cosine_exponent = Some(2.0);
        config.lag_deg = Some(-1.0);
        let e = HarrisPriester::from_config(&config).unwrap_err();
        assert_eq!(e.key, "drag.lag_deg");
        assert!(e.allowed.contains("0 to 90 deg"), "{e}");
        config.lag_deg = Some(90.5);
        assert_eq!(
            HarrisPriester::from_config(&config).unwrap_err().key,
            "drag.lag_deg"
        );
        config.lag_deg = Some(f64::NAN);
        assert_eq!(
            HarrisPriester::from_config(&config).unwrap_err().key,
            "drag.lag_deg"
        );
        config.lag_deg = Some(90.0);
        let hp = HarrisPriester::from_config(&config).unwrap();
        assert_eq!(hp.cosine_exponent, 2.0);
    }
}
