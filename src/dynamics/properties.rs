//! The physical properties of one satellite that force models read ([`PhysicalProperties`]: mass,
//! drag area and coefficient, SRP area and reflectivity coefficient) and their table in a
//! `propagate --forces` file ([`PropertiesConfig`]), validated with the key and the allowed range.

use serde::{Deserialize, Serialize};

use super::config::{check, ForceConfigError};

/// What force models know of a satellite besides its state. SI; areas are the projected areas the
/// cannonball models use (constant: attitude-dependent areas are a command of the drag actuator).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PhysicalProperties {
    /// Mass \[kg\] (> 0).
    pub mass_kg: f64,
    /// Drag reference area \[m^2\] (>= 0).
    pub drag_area_m2: f64,
    /// Drag coefficient C_d \[dimensionless\] (>= 0).
    pub drag_coefficient: f64,
    /// Area facing the Sun for radiation pressure \[m^2\] (>= 0).
    pub srp_area_m2: f64,
    /// Reflectivity coefficient C_r \[dimensionless\] (0 to 2: 1 absorbs, 2 mirrors).
    pub reflectivity_coefficient: f64,
}

impl PhysicalProperties {
    /// A satellite of `mass_kg` with no drag or SRP area (point-mass forces only).
    pub fn point_mass(mass_kg: f64) -> Self {
        Self {
            mass_kg,
            drag_area_m2: 0.0,
            drag_coefficient: 0.0,
            srp_area_m2: 0.0,
            reflectivity_coefficient: 0.0,
        }
    }

    /// The drag ballistic term `C_d A / m` \[m^2/kg\].
    #[inline]
    pub fn drag_area_per_mass_m2_per_kg(&self) -> f64 {
        self.drag_coefficient * self.drag_area_m2 / self.mass_kg
    }

    /// The SRP term `C_r A / m` \[m^2/kg\].
    #[inline]
    pub fn srp_area_per_mass_m2_per_kg(&self) -> f64 {
        self.reflectivity_coefficient * self.srp_area_m2 / self.mass_kg
    }

    /// The mean of `properties`, component by component (a virtual reference orbit's default
    /// properties: the swarm's mean). `None` for an empty slice.
    pub fn mean(properties: &[PhysicalProperties]) -> Option<Self> {
        if properties.is_empty() {
            return None;
        }
        let n = properties.len() as f64;
        let sum = |f: fn(&PhysicalProperties) -> f64| properties.iter().map(f).sum::<f64>() / n;
        Some(Self {
            mass_kg: sum(|p| p.mass_kg),
            drag_area_m2: sum(|p| p.drag_area_m2),
            drag_coefficient: sum(|p| p.drag_coefficient),
            srp_area_m2: sum(|p| p.srp_area_m2),
            reflectivity_coefficient: sum(|p| p.reflectivity_coefficient),
        })
    }

    /// Checks every property against its range; `prefix` is the keys' table (`satellite.` or
    /// `satellites.`), `index` the satellite's id when the value came from a per-satellite list.
    pub fn validate(&self, prefix: &str) -> Result<(), ForceConfigError> {
        let key = |name: &str| format!("{prefix}{name}");
        check(&key("mass_kg"), self.mass_kg, |v| v > 0.0, "a mass > 0 kg")?;
        check(
            &key("drag_area_m2"),
            self.drag_area_m2,
            |v| v >= 0.0,
            "an area >= 0 m^2",
        )?;
        check(
            &key("drag_coefficient"),
            self.drag_coefficient,
            |v| (0.0..=10.0).contains(&v),
            "a drag coefficient from 0 to 10 (2.2 is typical)",
        )?;
        check(
            &key("srp_area_m2"),
            self.srp_area_m2,
            |v| v >= 0.0,
            "an area >= 0 m^2",
        )?;
        check(
            &key("reflectivity_coefficient"),
            self.reflectivity_coefficient,
            |v| (0.0..=2.0).contains(&v),
            "a reflectivity coefficient from 0 to 2 (1 absorbs, 2 mirrors)",
        )?;
        Ok(())
    }
}

/// `[satellite]` of a `propagate --forces` file: each key optional, checked against what the force set
/// needs (a drag area when drag acts, an SRP area when SRP acts).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PropertiesConfig {
    /// Mass \[kg\].
    pub mass_kg: Option<f64>,
    /// Drag reference area \[m^2\].
    pub drag_area_m2: Option<f64>,
    /// Drag coefficient (default 2.2 when drag acts).
    pub drag_coefficient: Option<f64>,
    /// SRP area \[m^2\].
    pub srp_area_m2: Option<f64>,
    /// Reflectivity coefficient (default 1.5 when SRP acts).
    pub reflectivity_coefficient: Option<f64>,
}
