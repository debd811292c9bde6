//! Atmospheric density models for the drag force: the [`Atmosphere`] trait, one exponential layer
//! ([`Exponential`]), the piecewise exponential table of Vallado ([`ExponentialTable`]) and the
//! modified Harris–Priester model of Montenbruck & Gill ([`HarrisPriester`]); [`build`] makes the one a
//! `[drag]` table names, checking its keys.
//!
//! Every model is valid from [`FLOOR_ALTITUDE_M`] (100 km) up; the engine stops a run when a satellite
//! goes below it. Below the floor each model still returns a finite density (its lowest band,
//! extrapolated), so that an integrator stage that dips under the floor does not poison the state.

mod exp;
mod exponential;
mod harris_priester;
mod table;

use std::fmt;

use nalgebra::Vector3;

pub(crate) use exp::{ExpTable, IndexedExpTable, PermutedExpTable};
pub use exponential::Exponential;
pub use harris_priester::HarrisPriester;
pub use table::ExponentialTable;

use super::config::{AtmosphereName, DragConfig, ForceConfigError};

/// The lowest altitude every density model here is valid at \[m\]: 100 km (the bottom of the
/// Harris–Priester table; the engine stops a run below it).
pub const FLOOR_ALTITUDE_M: f64 = 100_000.0;

/// A density model of the Earth's atmosphere.
pub trait Atmosphere: Send + Sync + fmt::Debug {
    /// The model's name as the force set's summary prints it (`"exponential"`, `"exponential-table"`,
    /// `"harris-priester"`, the `atmosphere` values of `[drag]`).
    fn name(&self) -> &'static str;
    /// The mass density \[kg/m^3\] at `altitude_m` \[m\] (the height the drag model computed, above
    /// the sphere or the WGS-84 ellipsoid), the satellite at `position_eci_m` \[m, ECI\] and the Sun at
    /// `sun_eci_m` \[m, ECI\] (only models whose [`Atmosphere::uses_sun`] is true read the two vectors).
    fn density_kg_per_m3(
        &self,
        altitude_m: f64,
        position_eci_m: &Vector3<f64>,
        sun_eci_m: &Vector3<f64>,
    ) -> f64;
    /// The lowest altitude the model is valid at \[m\]: 100 km for every model here.
    fn floor_altitude_m(&self) -> f64;
    /// Whether the density depends on the Sun's position (then the force set computes it per instant).
    fn uses_sun(&self) -> bool {
        false
    }
}

/// The atmosphere a `[drag]` table describes. Keys are checked: the exponential layer needs
/// `reference_density_kg_per_m3`, `reference_altitude_m` and `scale_height_m` (each in its range) and
/// the other models refuse them; `cosine_exponent` and `lag_deg` are Harris–Priester's alone. Errors
/// name the key (`drag.…`), the value and what is allowed.
pub fn build(config: &DragConfig) -> Result<Box<dyn Atmosphere>, ForceConfigError> {
    Ok(match config.atmosphere {
        AtmosphereName::Exponential => Box::new(Exponential::from_config(config)?),
        AtmosphereName::ExponentialTable => {
            refuse_exponential_keys(config, "exponential-table")?;
            refuse_harris_priester_keys(config, "exponential-table")?;
            Box::new(ExponentialTable)
        }
        AtmosphereName::HarrisPriester => Box::new(HarrisPriester::from_config(config)?),
    })
}

/// An error for a key given with an atmosphere that does not read it.
fn refused(key: &str, value: f64, atmosphere: &str, owner: &str) -> ForceConfigError {
    ForceConfigError::new(
        key,
        value,
        format!(
            "no such key with atmosphere = \"{atmosphere}\" (only \"{owner}\" reads it): leave it out"
        ),
    )
}

/// Refuses the one-layer exponential keys for an `atmosphere` that is not the one-layer exponential.
pub(crate) fn refuse_exponential_keys(
    config: &DragConfig,
    atmosphere: &str,
) -> Result<(), ForceConfigError> {
    for (key, value) in [
        (
            "drag.reference_density_kg_per_m3",
            config.reference_density_kg_per_m3,
        ),
        ("drag.reference_altitude_m", config.reference_altitude_m),
        ("drag.scale_height_m", config.scale_height_m),
    ] {
        if let Some(v) = value {
            return Err(refused(key, v, atmosphere, "exponential"));
        }
    }
    Ok(())
}

/// Refuses the Harris–Priester keys for an `atmosphere` that is not Harris–Priester.
pub(crate) fn refuse_harris_priester_keys(
    config: &DragConfig,
    atmosphere: &str,
) -> Result<(), ForceConfigError> {
    for (key, value) in [
        ("drag.cosine_exponent", config.cosine_exponent),
        ("drag.lag_deg", config.lag_deg),
    ] {
        if let Some(v) = value {
            return Err(refused(key, v, atmosphere, "harris-priester"));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn build_names_each_model() {
        let mut exp = DragConfig::new(AtmosphereName::Exponential);
        exp.reference_density_kg_per_m3 = Some(3.725e-12);
        exp.reference_altitude_m = Some(400e3);
        exp.scale_height_m = Some(58_515.0);
        let built = build(&exp).unwrap();
        assert_eq!(built.name(), "exponential");
        assert!(!built.uses_sun());
        let table = build(&DragConfig::new(AtmosphereName::ExponentialTable)).unwrap();
        assert_eq!(table.name(), "exponential-table");
        assert!(!table.uses_sun());
        let hp = build(&DragConfig::new(AtmosphereName::HarrisPriester)).unwrap();
        assert_eq!(hp.name(), "harris-priester");
        assert!(hp.uses_sun());
        for model in [built, table, hp] {
            assert_eq!(model.floor_altitude_m(), 100e3);
        }
    }

    #[test]
    fn exponential_requires_each_key() {
        let full = || {
            let mut c = DragConfig::new(AtmosphereName::Exponential);
            c.reference_density_kg_per_m3 = Some(3.725e-12);
            c.reference_altitude_m = Some(400e3);
            c.scale_height_m = Some(58_515.0);
            c
        };
        let mut c = full();
        c.reference_density_kg_per_m3 = None;
        let e = build(&c).unwrap_err();
        assert_eq!(e.key, "drag.reference_density_kg_per_m3");
        assert_eq!(e.value, "missing");
        let mut c = full();
        c.reference_altitude_m = None;
        let e = build(&c).unwrap_err();
        assert_eq!(e.key, "drag.reference_altitude_m");
        assert_eq!(e.value, "missing");
        let mut c = full();
        c.scale_height_m = None;
        let e = build(&c).unwrap_err();
        assert_eq!(e.key, "drag.scale_height_m");
        assert_eq!(e.value, "missing");
        let mut c = full();
        c.cosine_exponent = Some(4.0);
        let e = build(&c).unwrap_err();
        assert_eq!(e.key, "drag.cosine_exponent");
        assert!(e.allowed.contains("harris-priester"), "{e}");
        let mut c = full();
        c.lag_deg = Some(30.0);
        assert_eq!(build(&c).unwrap_err().key, "drag.lag_deg");
    }

    #[test]
    fn table_and_harris_priester_refuse_foreign_keys() {
        for name in [
            AtmosphereName::ExponentialTable,
            AtmosphereName::HarrisPriester,
        ] {
            let mut c = DragConfig::new(name);
            c.scale_height_m = Some(58_515.0);
            let e = build(&c).unwrap_err();
            assert_eq!(e.key, "drag.scale_height_m");
            assert_eq!(e.value, "58515");
            assert!(e.allowed.contains("\"exponential\""), "{e}");
            let mut c = DragConfig::new(name);
            c.reference_density_kg_per_m3 = Some(1e-12);
            assert_eq!(
                build(&c).unwrap_err().key,
                "drag.reference_density_kg_per_m3"
            );
            let mut c = DragConfig::new(name);
            c.reference_altitude_m = Some(4e5);
            assert_eq!(build(&c).unwrap_err().key, "drag.reference_altitude_m");
        }
        let mut c = DragConfig::new(AtmosphereName::ExponentialTable);
        c.cosine_exponent = Some(4.0);
        assert_eq!(build(&c).unwrap_err().key, "drag.cosine_exponent");
        let mut c = DragConfig::new(AtmosphereName::ExponentialTable);
        c.lag_deg = Some(30.0);
        assert_eq!(build(&c).unwrap_err().key, "drag.lag_deg");
    }

    /// Below the floor every model still gives a finite, positive density (its lowest band), down to
    /// the surface and below it.
    #[test]
    fn below_the_floor_density_is_finite() {
        let mut exp = DragConfig::new(AtmosphereName::Exponential);
        exp.reference_density_kg_per_m3 = Some(3.725e-12);
        exp.reference_altitude_m = Some(400e3);
        exp.scale_height_m = Some(58_515.0);
        let models = [
            build(&exp).unwrap(),
            build(&DragConfig::new(AtmosphereName::ExponentialTable)).unwrap(),
            build(&DragConfig::new(AtmosphereName::HarrisPriester)).unwrap(),
        ];
        let r = Vector3::new(6.4e6, 0.0, 0.0);
        let sun = Vector3::new(1.5e11, 0.0, 0.0);
        for model in &models {
            for h in [99_999.0, 50e3, 0.0, -10e3, -6.0e6] {
                let rho = model.density_kg_per_m3(h, &r, &sun);
                assert!(
                    rho.is_finite() && rho > 0.0,
                    "{} at {h} m: {rho}",
                    model.name()
                );
            }
        }
    }
}
