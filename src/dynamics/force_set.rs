//! The force set of a run ([`ForceSet`]): the gravity field, then drag, solar radiation pressure and
//! third bodies (each a [`ForceModel`]), summed in that order; which fused kernel covers it ([`FastForces`]); what
//! `summary.json` names ([`ForceSetSummary`]).

use hifitime::Epoch;
use nalgebra::Vector3;
use serde::Serialize;

use super::atmosphere::Exponential;
use super::config::{ForceConfigError, ForcesConfig, GravityModelName};
use super::drag::Drag;
use super::gravity::Gravity;
use super::srp::SolarRadiationPressure;
use super::third_body::ThirdBody;
use super::zonal::{egm96_zonal_coefficients, ZonalGravity, EGM96_MAX_DEGREE};
use super::{Bodies, ForceModel, Instant, PhysicalProperties};
use crate::orbit::{EarthModel, GravityModel};

/// The forces of a run, summed: gravity, drag (if any), then SRP and third bodies in the order of the
/// configuration (each model typed, so the set knows which fused kernel covers it). Built once; evaluating it allocates nothing.
#[derive(Debug)]
pub struct ForceSet {
    /// The Earth constants the models were built with.
    earth: EarthModel,
    gravity: Gravity,
    drag: Option<Drag>,
    srp: Option<SolarRadiationPressure>,
    third_bodies: Vec<ThirdBody>,
    bodies: Bodies,
    /// The scenario epoch in TT seconds past J2000 (the engine's `t_s = 0`).
    epoch_tt_s_past_j2000: f64,
}

/// A force set the fused structure-of-arrays RK4 kernel computes itself, with the generic path's bits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FastForces {
    /// Point mass or point mass + J2 only.
    Gravity(GravityModel, EarthModel),
    /// Point mass or point mass + J2, and drag in a one-layer exponential atmosphere at the height above
    /// the sphere of the equatorial radius.
    GravityExponentialDrag {
        /// The gravity field.
        gravity: GravityModel,
        /// Its constants (the sphere's radius is `equatorial_radius_m`).
        earth: EarthModel,
        /// The atmosphere.
        atmosphere: Exponential,
        /// Whether the atmosphere co-rotates with the Earth.
        corotation: bool,
    },
}

/// What `summary.json` names of a force set: each model's name and the propagation path taken.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ForceSetSummary {
    /// The models, in the order they are summed.
    pub models: Vec<String>,
    /// The ephemerides read: `sun`, `moon`.
    pub ephemerides: Vec<&'static str>,
}

impl ForceSet {
    /// Gravity alone (`[dynamics] model = "j2"` or `"two-body"`): no model reads the epoch, so the set's
    /// instants count from J2000.
    pub fn gravity(model: GravityModel, earth: EarthModel) -> Self {
        Self {
            earth,
            gravity: Gravity::Field(model, earth),
            drag: None,
            srp: None,
            third_bodies: Vec::new(),
            bodies: Bodies::default(),
            epoch_tt_s_past_j2000: 0.0,
        }
    }

    /// The set a `[dynamics.forces]` table describes, for the Earth constants `earth`, the epoch at
    /// `t_s = 0`. Every parameter is checked (key, value and the allowed range in the error).
    pub fn from_config(
        config: &ForcesConfig,
        earth: &EarthModel,
        epoch: Epoch,
    ) -> Result<Self, ForceConfigError> {
        let gravity = match config.gravity.model {
            GravityModelName::PointMass | GravityModelName::J2 => {
                if config.gravity.degree.is_some() || config.gravity.zonal_coefficients.is_some() {
                    return Err(ForceConfigError::new(
                        "gravity.model",
                        format!("\"{}\"", gravity_name(config.gravity.model)),
                        "\"zonal\" when `degree` or `zonal_coefficients` is given",
                    ));
                }
                let model = if config.gravity.model == GravityModelName::J2 {
                    GravityModel::J2
                } else {
                    GravityModel::TwoBody
                };
                Gravity::Field(model, *earth)
            }
            GravityModelName::Zonal => {
                Gravity::Zonal(ZonalGravity::new(earth, zonal_coefficients(config)?))
            }
        };
        let drag = config
            .drag
            .as_ref()
            .map(|d| Drag::from_config(d, earth))
            .transpose()?;
        let srp = config
            .srp
            .as_ref()
            .map(|s| SolarRadiationPressure::new(s.shadow, earth.equatorial_radius_m));
        let mut third_bodies = Vec::new();
        if let Some(third) = &config.third_body {
            if third.bodies.is_empty() {
                return Err(ForceConfigError::new(
                    "third_body.bodies",
                    "[]",
                    "one or both of \"sun\", \"moon\" (or leave out [third_body])",
                ));
            }
            for (k, body) in third.bodies.iter().enumerate() {
                if third.bodies[..k].contains(body) {
                    return Err(ForceConfigError::new(
                        "third_body.bodies",
                        format!("{:?}", third.bodies),
                        "each body at most once",
                    ));
                }
                third_bodies.push(ThirdBody::new(*body));
            }
        }
        let bodies = third_bodies
            .iter()
            .map(ForceModel::bodies)
            .chain(drag.as_ref().map(ForceModel::bodies))
            .chain(srp.as_ref().map(ForceModel::bodies))
            .fold(Bodies::default(), Bodies::union);
        Ok(Self {
            earth: *earth,
            gravity,
            drag,
            srp,
            third_bodies,
            bodies,
            epoch_tt_s_past_j2000: tt_s_past_j2000(epoch),
        })
    }

    /// The instant `t_s` elapsed SI seconds after the epoch, with the ephemerides the set reads.
    #[inline]
    pub fn instant(&self, t_s: f64) -> Instant {
        Instant::new(self.epoch_tt_s_past_j2000 + t_s, self.bodies)
    }

    /// The Earth constants the set was built with.
    pub fn earth(&self) -> EarthModel {
        self.earth
    }

    /// The gravity field.
    pub fn gravity_field(&self) -> &Gravity {
        &self.gravity
    }

    /// The drag model, if drag acts.
    pub fn drag(&self) -> Option<&Drag> {
        self.drag.as_ref()
    }

    /// Whether a force of the set reads the satellite's drag properties (area, C_d, mass).
    pub fn uses_drag_properties(&self) -> bool {
        self.drag.is_some()
    }

    /// Whether a force of the set reads the satellite's SRP properties (area, C_r, mass).
    pub fn uses_srp_properties(&self) -> bool {
        self.srp.is_some()
    }

    /// Whether the set is gravity alone (no force reads the satellite's properties or the epoch).
    pub fn is_gravity_only(&self) -> bool {
        self.drag.is_none() && self.srp.is_none() && self.third_bodies.is_empty()
    }

    /// The total acceleration \[m/s^2\], ECI, of a satellite at `position_eci_m` \[m\] with velocity
    /// `velocity_eci_mps` \[m/s\] and `properties`, at `at` (from [`ForceSet::instant`]): gravity, plus
    /// drag, plus each further model, summed in that order.
    #[inline]
    pub fn acceleration_eci_m_s2(
        &self,
        at: &Instant,
        position_eci_m: &Vector3<f64>,
        velocity_eci_mps: &Vector3<f64>,
        properties: &PhysicalProperties,
    ) -> Vector3<f64> {
        let mut a = self.gravity.acceleration_m_s2(position_eci_m);
        if let Some(drag) = &self.drag {
            a += drag.acceleration_eci_m_s2(at, position_eci_m, velocity_eci_mps, properties);
        }
        if let Some(srp) = &self.srp {
            a += srp.acceleration_eci_m_s2(at, position_eci_m, velocity_eci_mps, properties);
        }
        for body in &self.third_bodies {
            a += body.acceleration_eci_m_s2(at, position_eci_m, velocity_eci_mps, properties);
        }
        a
    }

    /// The fused kernel's form of this set, if it has one: gravity alone, or gravity and exponential
    /// drag at spherical altitude (nothing else).
    pub fn fast_forces(&self) -> Option<FastForces> {
        let Gravity::Field(gravity, earth) = self.gravity else {
            return None;
        };
        if self.srp.is_some() || !self.third_bodies.is_empty() {
            return None;
        }
        match &self.drag {
            None => Some(FastForces::Gravity(gravity, earth)),
            Some(drag) => drag.fast_exponential().map(|(atmosphere, corotation)| {
                FastForces::GravityExponentialDrag {
                    gravity,
                    earth,
                    atmosphere,
                    corotation,
                }
            }),
        }
    }

    /// The altitude \[m\] of a satellite at `position_eci_m` if it is below the atmosphere's floor
    /// (the run must stop), with the floor; `None` when above it or without drag.
    pub fn below_floor(&self, position_eci_m: &Vector3<f64>) -> Option<(f64, f64)> {
        let drag = self.drag.as_ref()?;
        let altitude_m = drag.altitude_m(position_eci_m);
        let floor_m = drag.atmosphere().floor_altitude_m();
        (altitude_m < floor_m || !altitude_m.is_finite()).then_some((altitude_m, floor_m))
    }

    /// A squared distance from the Earth's centre \[m²\] beyond which no position is below the
    /// atmosphere's floor ([`Self::below_floor`] is `None`); `None` without drag.
    pub fn clear_of_floor_m2(&self) -> Option<f64> {
        self.drag
            .as_ref()
            .map(|drag| drag.clear_of_floor_radius_m().powi(2))
    }

    /// The models' names and the ephemerides read, for `summary.json`.
    pub fn summary(&self) -> ForceSetSummary {
        let mut models = vec![self.gravity.name()];
        models.extend(self.drag.iter().map(ForceModel::name));
        models.extend(self.srp.iter().map(ForceModel::name));
        models.extend(self.third_bodies.iter().map(ForceModel::name));
        let mut ephemerides = Vec::new();
        if self.bodies.sun {
            ephemerides.push("sun");
        }
        if self.bodies.moon {
            ephemerides.push("moon");
        }
        ForceSetSummary {
            models,
            ephemerides,
        }
    }
}

/// The kebab-case name of a gravity model, for errors.
fn gravity_name(model: GravityModelName) -> &'static str {
    match model {
        GravityModelName::PointMass => "point-mass",
        GravityModelName::J2 => "j2",
        GravityModelName::Zonal => "zonal",
    }
}

/// J2..Jn of a zonal `[gravity]`: the override list, or the built-in EGM96 values to `degree`
/// (default 6).
fn zonal_coefficients(config: &ForcesConfig) -> Result<Vec<f64>, ForceConfigError> {
    match (&config.gravity.zonal_coefficients, config.gravity.degree) {
        (Some(_), Some(degree)) => Err(ForceConfigError::new(
            "gravity.degree",
            degree,
            "either `degree` (built-in EGM96 values) or `zonal_coefficients` (your own), not both",
        )),
        (Some(list), None) => {
            if list.is_empty() || list.len() > 49 {
                return Err(ForceConfigError::new(
                    "gravity.zonal_coefficients",
                    format!("a list of {}", list.len()),
                    "J2..Jn, 1 to 49 values",
                ));
            }
            if let Some((k, v)) = list
                .iter()
                .enumerate()
                .find(|(_, v)| !v.is_finite() || v.abs() > 1e-2)
            {
                return Err(ForceConfigError::new(
                    format!("gravity.zonal_coefficients[{k}] (J{})", k + 2),
                    v,
                    "a finite coefficient of magnitude at most 1e-2 (the Earth's J2 is 1.08e-3)",
                ));
            }
            Ok(list.clone())
        }
        (None, degree) => {
            let degree = degree.unwrap_or(6);
            if !(2..=EGM96_MAX_DEGREE).contains(&degree) {
                return Err(ForceConfigError::new(
                    "gravity.degree",
                    degree,
                    format!("a degree from 2 to {EGM96_MAX_DEGREE} (built-in EGM96 zonals)"),
                ));
            }
            Ok(egm96_zonal_coefficients(degree))
        }
    }
}

/// `epoch` in TT seconds past J2000 (2000-01-01T12:00:00 TT).
fn tt_s_past_j2000(epoch: Epoch) -> f64 {
    epoch.to_tt_since_j2k().to_seconds()
}
