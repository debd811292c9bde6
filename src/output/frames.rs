//! The names of the frames and the time system that every output states (CSV and Parquet column names,
//! `summary.json`, CCSDS OEM `REF_FRAME`, CZML `referenceFrame`, the report), in one place.
//!
//! The engine's inertial frame is Earth-centred with its z axis on Earth's rotation axis (the J2 term's
//! axis) and no precession or nutation: it stands for **EME2000** (mean equator and equinox of J2000).
//! The approximation: Earth's real pole drifts from the EME2000 z axis by precession (about 20″ per year
//! in declination, 0.14° by 2026) and nutation (about 9″), so the J2 acceleration is applied about an
//! axis off by that angle. For the relative motion of a swarm this changes the differential J2 terms by
//! a fraction of the same order (about 2·10⁻³ of an already 10⁻³ effect); for absolute positions it
//! tilts the orbit plane's precession axis by that angle. At the default epoch (2000-01-01T12:00:00Z)
//! the two agree up to nutation.

/// CCSDS name of the inertial frame (OEM `REF_FRAME`).
pub const INERTIAL_FRAME: &str = "EME2000";

/// The inertial frame's short name in column names (`x_eme2000_m`).
pub const INERTIAL_COLUMN_TAG: &str = "eme2000";

/// One sentence saying what the inertial frame is.
pub const INERTIAL_FRAME_DESCRIPTION: &str = "EME2000 (Earth-centred; z on Earth's rotation axis for \
the J2 term, no precession or nutation: the model's stand-in for the mean equator and equinox of J2000)";

/// CZML `referenceFrame` of inertial positions (Cesium's `INERTIAL` is ICRF, which differs from EME2000
/// by the 23 mas frame bias: under a metre at orbital radii).
pub const CZML_INERTIAL_FRAME: &str = "INERTIAL";

/// Short name of the relative frame (Parquet column metadata `frame`, beside [`INERTIAL_FRAME`]).
pub const LVLH_FRAME: &str = "Hill LVLH";

/// One sentence saying what the LVLH columns are.
pub const LVLH_FRAME_DESCRIPTION: &str = "Hill LVLH centred on the reference orbit (or the origin \
member): x radial outward, y along-track, z along the orbit normal";

/// The time system of absolute times in text outputs.
pub const TIME_SYSTEM: &str = "UTC";
