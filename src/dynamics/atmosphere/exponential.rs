//! One exponential layer of the atmosphere ([`Exponential`]): `rho = rho_0 exp((h_0 - h) / H)` with an
//! explicit reference density, reference altitude and scale height, checked at construction. The fused
//! SIMD kernel reproduces [`Exponential::density_at_kg_per_m3`] bit for bit, so its operation order is
//! fixed.

use nalgebra::Vector3;

use super::exp::{exp_lanes, ExpTable, IndexedExpTable};
use super::{refuse_harris_priester_keys, Atmosphere, FLOOR_ALTITUDE_M};
use crate::dynamics::config::{check, DragConfig, ForceConfigError};

/// One exponential layer: `rho(h) = reference_density * exp((reference_altitude - h) / scale_height)`,
/// for every altitude (no bands). SI: kg/m^3 and m.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Exponential {
    /// Density at the reference altitude \[kg/m^3\] (`> 0`, at most 2).
    pub reference_density_kg_per_m3: f64,
    /// Reference altitude \[m\] (0 to 2 000 km).
    pub reference_altitude_m: f64,
    /// Scale height \[m\] (`> 0`, at most 1 000 km).
    pub scale_height_m: f64,
}

impl Exponential {
    /// The layer of `reference_density_kg_per_m3` \[kg/m^3\] at `reference_altitude_m` \[m\] with the
    /// scale height `scale_height_m` \[m\].
    ///
    /// # Errors
    /// A [`ForceConfigError`] naming the key (`drag.reference_density_kg_per_m3`,
    /// `drag.reference_altitude_m`, `drag.scale_height_m`) when a value is not finite or out of its
    /// range: density in (0, 2] kg/m^3, altitude in [0, 2e6] m, scale height in (0, 1e6] m.
    pub fn new(
        reference_density_kg_per_m3: f64,
        reference_altitude_m: f64,
        scale_height_m: f64,
    ) -> Result<Self, ForceConfigError> {
        Ok(Self {
            reference_density_kg_per_m3: check(
                "drag.reference_density_kg_per_m3",
                reference_density_kg_per_m3,
                |v| v > 0.0 && v <= 2.0,
                DENSITY_ALLOWED,
            )?,
            reference_altitude_m: check(
                "drag.reference_altitude_m",
                reference_altitude_m,
                |v| (0.0..=2.0e6).contains(&v),
                ALTITUDE_ALLOWED,
            )?,
            scale_height_m: check(
                "drag.scale_height_m",
                scale_height_m,
                |v| v > 0.0 && v <= 1.0e6,
                SCALE_HEIGHT_ALLOWED,
            )?,
        })
    }

    /// The layer of a `[drag]` table with `atmosphere = "exponential"`: the three keys are required
    /// (a missing one is an error with the value `missing`), the Harris–Priester keys refused.
    pub(crate) fn from_config(config: &DragConfig) -> Result<Self, ForceConfigError> {
        refuse_harris_priester_keys(config, "exponential")?;
        let required = |key: &str, value: Option<f64>, allowed: &str| {
            value.ok_or_else(|| {
                ForceConfigError::new(
                    key,
                    "missing",
                    format!("required with atmosphere = \"exponential\": {allowed}"),
                )
            })
        };
        Self::new(
            required(
                "drag.reference_density_kg_per_m3",
                config.reference_density_kg_per_m3,
                DENSITY_ALLOWED,
            )?,
            required(
                "drag.reference_altitude_m",
                config.reference_altitude_m,
                ALTITUDE_ALLOWED,
            )?,
            required(
                "drag.scale_height_m",
                config.scale_height_m,
                SCALE_HEIGHT_ALLOWED,
            )?,
        )
    }

    /// The density \[kg/m^3\] at `altitude_m` \[m\]:
    /// `reference_density * exp((reference_altitude - altitude) * (1 / scale_height))` (a loop
    /// invariant reciprocal instead of a division per lane) with the crate's own vectorisable
    /// exponential (within 1 ulp of `f64::exp`): the arithmetic the fused kernel runs per lane
    /// (`densities_kg_per_m3`), so both paths give the same bits. The exponent is clamped to
    /// \[−708, 709\] (a density of 1e−308 of the reference, or e^709 of it for an altitude far below
    /// the layer);
    /// NaN for a NaN altitude.
    #[inline(always)]
    pub fn density_at_kg_per_m3(&self, altitude_m: f64) -> f64 {
        self.densities_kg_per_m3(&[altitude_m], IndexedExpTable)[0]
    }

    /// [`Exponential::density_at_kg_per_m3`] of each of `L` lanes, the exponential's table read by
    /// `table` (the fused kernel's copies read it their own way; the same bits either way).
    #[inline(always)]
    pub(crate) fn densities_kg_per_m3<const L: usize>(
        &self,
        altitudes_m: &[f64; L],
        table: impl ExpTable,
    ) -> [f64; L] {
        let exponents =
            altitudes_m.map(|h| (self.reference_altitude_m - h) * (1.0 / self.scale_height_m));
        exp_lanes(&exponents, table).map(|e| self.reference_density_kg_per_m3 * e)
    }
}

/// What `drag.reference_density_kg_per_m3` allows.
const DENSITY_ALLOWED: &str = "a density > 0 and at most 2 kg/m^3 (e.g. 3.725e-12 at 400 km)";
/// What `drag.reference_altitude_m` allows.
const ALTITUDE_ALLOWED: &str = "an altitude from 0 to 2e6 m (2 000 km)";
/// What `drag.scale_height_m` allows.
const SCALE_HEIGHT_ALLOWED: &str = "a scale height > 0 and at most 1e6 m (e.g. 58515 at 400 km)";

impl Atmosphere for Exponential {
    fn name(&self) -> &'static str {
        "exponential"
    }

    #[inline]
    fn density_kg_per_m3(
        &self,
        altitude_m: f64,
        _position_eci_m: &Vector3<f64>,
        _sun_eci_m: &Vector3<f64>,
    ) -> f64 {
        self.density_at_kg_per_m3(altitude_m)
    }

    fn floor_altitude_m(&self) -> f64 {
        FLOOR_ALTITUDE_M
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// At the reference altitude the density is the reference density exactly (exp(0) = 1); one scale
    /// height above it, rho_0 / e = 3.725e-12 * 0.367879441171442321... = 1.3703509183636226e-12
    /// (30-digit arithmetic outside this code). Relative tolerance 5e-16: the division (exact here,
    /// -58515/58515 = -1), exp (within 1 ulp), the product and the decimal literal each round by at
    /// most 1.1e-16.
    #[test]
    fn density_at_reference_and_one_scale_height_up() {
        let layer = Exponential::new(3.725e-12, 400e3, 58_515.0).unwrap();
        assert_eq!(layer.density_at_kg_per_m3(400e3), 3.725e-12);
        let expected = 1.370_350_918_363_622_7e-12;
        let got = layer.density_at_kg_per_m3(400e3 + 58_515.0);
        assert!(
            ((got - expected) / expected).abs() < 5e-16,
            "{got} vs {expected}"
        );
        let r = Vector3::new(7e6, 0.0, 0.0);
        assert_eq!(
            layer.density_kg_per_m3(410e3, &r, &r),
            layer.density_at_kg_per_m3(410e3)
        );
        assert_eq!(layer.floor_altitude_m(), 100e3);
    }

    #[test]
    fn validation_names_the_key_and_range() {
        let e = Exponential::new(0.0, 400e3, 58_515.0).unwrap_err();
        assert_eq!(e.key, "drag.reference_density_kg_per_m3");
        assert_eq!(e.value, "0");
        assert!(e.allowed.contains("> 0 and at most 2"), "{e}");
        let e = Exponential::new(2.5, 400e3, 58_515.0).unwrap_err();
        assert_eq!(e.key, "drag.reference_density_kg_per_m3");
        let e = Exponential::new(f64::NAN, 400e3, 58_515.0).unwrap_err();
        assert_eq!(e.key, "drag.reference_density_kg_per_m3");
        let e = Exponential::new(1e-12, -1.0, 58_515.0).unwrap_err();
        assert_eq!(e.key, "drag.reference_altitude_m");
        assert!(e.allowed.contains("0 to 2e6 m"), "{e}");
        let e = Exponential::new(1e-12, 2.0e6 + 1.0, 58_515.0).unwrap_err();
        assert_eq!(e.key, "drag.reference_altitude_m");
        let e = Exponential::new(1e-12, 400e3, 0.0).unwrap_err();
        assert_eq!(e.key, "drag.scale_height_m");
        assert!(e.allowed.contains("> 0 and at most 1e6 m"), "{e}");
        let e = Exponential::new(1e-12, 400e3, f64::INFINITY).unwrap_err();
        assert_eq!(e.key, "drag.scale_height_m");
        // The bounds themselves are allowed.
        assert!(Exponential::new(2.0, 0.0, 1.0e6).is_ok());
        assert!(Exponential::new(1e-20, 2.0e6, 1.0).is_ok());
    }
}
