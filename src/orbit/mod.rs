//! Orbital mechanics of one satellite: Earth constants ([`EarthModel`]), inertial Cartesian states
//! ([`CartesianState`]), Keplerian elements and their conversions ([`KeplerianElements`]), point-mass
//! and J2 gravity ([`GravityModel`]) and LVLH frames in the Hill/RSW and Gao conventions
//! ([`LvlhFrame`], [`RelativeStateHill`], [`RelativeStateGao`]).
//!
//! Everything is SI (m, s, rad). "ECI" is an Earth-centred inertial frame whose z axis is the Earth's
//! polar axis; the module does not depend on which realisation (GCRF, J2000, TEME) the caller uses.
//! This module knows nothing of the rest of the crate.

mod constants;
mod elements;
mod gravity;
mod lvlh;
mod state;

pub use nalgebra::{Matrix3, Vector3};

pub use constants::EarthModel;
pub use elements::{
    KeplerianElements, OrbitError, CIRCULAR_ECCENTRICITY_TOLERANCE,
    EQUATORIAL_SIN_INCLINATION_TOLERANCE,
};
pub use gravity::GravityModel;
pub use lvlh::{gao_to_hill, hill_to_gao, LvlhFrame, RelativeStateGao, RelativeStateHill};
pub use state::CartesianState;
