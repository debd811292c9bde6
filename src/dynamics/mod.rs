//! Truth dynamics of one satellite: the forces that act on it, behind one interface.
//!
//! A force model ([`ForceModel`]) gives the inertial (ECI, SI) acceleration of one satellite from the
//! instant ([`Instant`]: TT seconds past J2000 and, computed once per instant, the Sun's and Moon's
//! positions), its inertial state and its physical properties ([`PhysicalProperties`]). The models of
//! a run are summed by one [`ForceSet`]: gravity first, then drag, solar radiation pressure and third
//! bodies, in that order. The engine, `propagate`, the reference orbit and the Python package all use
//! the same set. No force model knows about laws, the grid or the scheduler.
//!
//! | module | holds |
//! | --- | --- |
//! | `config` | the `[dynamics.forces]` table (serde) and [`ForceConfigError`] |
//! | `properties` | [`PhysicalProperties`] of a satellite |
//! | `force_set` | [`ForceSet`]: the models of a run, summed; which fast kernel covers them ([`FastForces`]) |
//! | `gravity` | point mass and J2 (today's bits, [`crate::orbit::GravityModel`]) or zonal J2..Jn |
//! | `zonal` | the zonal harmonics J2..Jn and the built-in EGM96 values |
//! | `atmosphere` | densities: one-layer exponential, Vallado's piecewise table, Harris–Priester |
//! | `drag` | atmospheric drag from a density, the satellite's area and C_d, a co-rotating atmosphere |
//! | `srp`, `shadow` | cannonball solar radiation pressure; cylindrical and conical shadow |
//! | `third_body`, `ephemeris` | Sun and Moon point masses; their low-precision analytic positions |
//!
//! Frames and time: ECI is the engine's inertial frame, taken as EME2000 (mean equator and equinox of
//! J2000; precession and nutation since J2000 are neglected, as in the rest of the crate). Instants are
//! TT (the engine's elapsed SI seconds added to the epoch's TT).

mod atmosphere;
mod config;
mod drag;
mod ephemeris;
mod force_set;
mod gravity;
mod properties;
mod shadow;
mod srp;
mod third_body;
mod zonal;

use std::fmt;

use nalgebra::Vector3;

pub use atmosphere::{Atmosphere, Exponential, ExponentialTable, HarrisPriester, FLOOR_ALTITUDE_M};
pub(crate) use atmosphere::{ExpTable, IndexedExpTable, PermutedExpTable};
pub use config::{
    AltitudeName, AtmosphereName, BodyName, DragConfig, ForceConfigError, ForcesConfig,
    ForcesFileError, GravityConfig, GravityModelName, ShadowName, SrpConfig, ThirdBodyConfig,
    MAX_FORCES_FILE_BYTES,
};
pub use drag::{
    drag_acceleration_m_s2, geodetic_altitude_m, speed_from_square_m_s, Drag, EARTH_ROTATION_RAD_S,
};
pub use ephemeris::{
    moon_position_eci_m, sun_position_eci_m, ASTRONOMICAL_UNIT_M, GM_MOON_M3_S2, GM_SUN_M3_S2,
};
pub use force_set::{FastForces, ForceSet, ForceSetSummary};
pub use gravity::Gravity;
pub use properties::{PhysicalProperties, PropertiesConfig};
pub use shadow::{lit_fraction, SUN_RADIUS_M};
pub use srp::{SolarRadiationPressure, SOLAR_PRESSURE_N_PER_M2};
pub use third_body::ThirdBody;
pub use zonal::{egm96_zonal_coefficients, ZonalGravity, EGM96_MAX_DEGREE};

/// Which ephemerides a force model reads, so that a [`ForceSet`] computes each once per instant.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Bodies {
    /// The Sun's position.
    pub sun: bool,
    /// The Moon's position.
    pub moon: bool,
}

impl Bodies {
    /// Both sets' bodies.
    pub fn union(self, other: Bodies) -> Bodies {
        Bodies {
            sun: self.sun || other.sun,
            moon: self.moon || other.moon,
        }
    }
}

/// One instant as force models see it: TT seconds past J2000 (2000-01-01T12:00:00 TT) and the Sun's
/// and Moon's ECI positions when the force set computed them (else computed on request).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Instant {
    /// TT seconds past J2000 \[s\].
    pub tt_s_past_j2000: f64,
    sun_eci_m: Option<Vector3<f64>>,
    moon_eci_m: Option<Vector3<f64>>,
}

impl Instant {
    /// The instant `tt_s_past_j2000` with the ephemerides of `bodies` computed now.
    pub fn new(tt_s_past_j2000: f64, bodies: Bodies) -> Self {
        Self {
            tt_s_past_j2000,
            sun_eci_m: bodies.sun.then(|| sun_position_eci_m(tt_s_past_j2000)),
            moon_eci_m: bodies.moon.then(|| moon_position_eci_m(tt_s_past_j2000)),
        }
    }

    /// The Sun's position, ECI (EME2000) \[m\].
    #[inline]
    pub fn sun_eci_m(&self) -> Vector3<f64> {
        self.sun_eci_m
            .unwrap_or_else(|| sun_position_eci_m(self.tt_s_past_j2000))
    }

    /// The Moon's position, ECI (EME2000) \[m\].
    #[inline]
    pub fn moon_eci_m(&self) -> Vector3<f64> {
        self.moon_eci_m
            .unwrap_or_else(|| moon_position_eci_m(self.tt_s_past_j2000))
    }
}

/// A force acting on one satellite: its acceleration in ECI from the instant, the satellite's inertial
/// state and its physical properties. Implementations are pure functions of their inputs (no state, no
/// allocation), so the engine may call them from any thread in any order.
pub trait ForceModel: Send + Sync + fmt::Debug {
    /// The model's name as `summary.json` and `propagate` print it (`"drag (exponential)"`).
    fn name(&self) -> String;

    /// The acceleration \[m/s^2\], ECI, of a satellite at `position_eci_m` \[m\] with velocity
    /// `velocity_eci_mps` \[m/s\] (both ECI) and `properties`, at `at`.
    fn acceleration_eci_m_s2(
        &self,
        at: &Instant,
        position_eci_m: &Vector3<f64>,
        velocity_eci_mps: &Vector3<f64>,
        properties: &PhysicalProperties,
    ) -> Vector3<f64>;

    /// The ephemerides the model reads from `at` (none by default).
    fn bodies(&self) -> Bodies {
        Bodies::default()
    }
}
