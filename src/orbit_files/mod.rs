//! Orbit files satflock reads: CCSDS Orbit Ephemeris Messages (OEM, KVN, versions 2.0 and 3.0), CCSDS
//! Orbit Mean-elements Messages (OMM: KVN, XML and the catalogue's JSON) and two- and three-line element
//! sets (TLE), each turned into an **EME2000** state (m, m/s) at a requested epoch.
//!
//! # API (what the scenario layer calls)
//!
//! ```text
//! // OEM: one OemObject per OBJECT_ID, in order of first appearance over the files given; the
//! // segments of one object merge (across files too).
//! let objects: Vec<OemObject> = orbit_files::read_oem_files(&[a_oem, b_oem])?;
//! let s: CartesianState = objects[0].state_eme2000(epoch)?;   // EME2000, m and m/s
//! objects[0].name, objects[0].id, objects[0].start()          // start(): first usable instant
//!
//! // OMM (KVN, XML or JSON, told apart by the content) and TLE (two- or three-line) through SGP4:
//! let flock: Vec<Sgp4Object> = orbit_files::read_omm_file(path)?;   // in file order
//! let flock: Vec<Sgp4Object> = orbit_files::read_tle_file(path)?;   // in file order
//! let one = Sgp4Object::from_tle_lines("flock.toml [reference] tle", None, line1, line2)?;
//! one.epoch()                      // the element set's epoch (an instant; printed in UTC)
//! one.state_eme2000(epoch)?        // CartesianState, EME2000, m and m/s (at initialisation or in a run)
//! one.state_teme(epoch)?           // CartesianState in TEME of date, m and m/s (SGP4's own output)
//!
//! // Frames, for callers with states of their own:
//! orbit_files::teme_to_eme2000(epoch, &teme)    // TEME of date -> EME2000
//! orbit_files::gcrf_to_eme2000(&gcrf)           // GCRF / ICRF axes -> EME2000 (frame bias)
//! ```
//!
//! Every failure is an [`OrbitFileError`] naming the file (or, for TLE lines given inline, the source
//! the caller names), the line or the keyword, the value and what is allowed: user input, which the
//! scenario layer maps to exit code 2. Every file is read through [`crate::input_file`] (a regular file
//! of at most [`MAX_ORBIT_FILE_BYTES`]).
//!
//! # What each reader does
//!
//! * [`oem`]: header, metadata and data lines (optional accelerations), `COMMENT`s, covariance blocks
//!   skipped; the state at an epoch interpolated with the segment's own `INTERPOLATION` (Lagrange, or
//!   Hermite with the velocities) and `INTERPOLATION_DEGREE`; frames EME2000, GCRF and ICRF;
//!   `CENTER_NAME = EARTH`; time systems UTC, TAI, TT and GPS; km and km/s in the file, m and m/s out.
//! * [`omm`] and [`tle`]: element sets read into [`sgp4::Elements`] and propagated by the `sgp4` crate
//!   (Vallado's 2006 SGP4, WGS-72 constants, the AFSPC-compatible mode the element sets are fitted
//!   with) to TEME of date, then rotated to EME2000 by [`teme`].
//! * [`teme`]: TEME → true of date (equation of the equinoxes) → mean of date (IAU 1980 nutation, all
//!   106 terms) → EME2000 (IAU 1976 precession); the frame bias GCRF → EME2000. What this neglects
//!   (polar motion does not enter; the IERS corrections dψ, dε to the 1980 nutation; the
//!   rotation's own rate in the velocity) is said there.
//!
//! The user's page is `docs/inputs.md`.

mod epoch;
mod error;
mod interpolation;
mod kvn;
mod nutation_1980;
pub mod oem;
pub mod omm;
mod sgp4_object;
pub mod teme;
pub mod tle;

use std::path::Path;

pub use epoch::{parse_ccsds_epoch, TimeSystem};
pub use error::OrbitFileError;
pub use interpolation::Interpolation;
pub use oem::{parse_oem, read_oem_files, OemFrame, OemObject, OemSegment};
pub use omm::{parse_omm, read_omm_file};
pub use sgp4_object::Sgp4Object;
pub use teme::{gcrf_to_eme2000, teme_to_eme2000};
pub use tle::{parse_tle, read_tle_file};

/// Largest orbit file read \[bytes\] (256 MiB, [`crate::input_file::MAX_DOCUMENT_BYTES`]): about two
/// million OEM states, or every element set of the public catalogue several times over. A bigger file
/// (a file of 10⁹ lines is at least 10⁹ bytes) is refused before anything is read.
pub const MAX_ORBIT_FILE_BYTES: u64 = crate::input_file::MAX_DOCUMENT_BYTES;

/// The text of an orbit file, read through [`crate::input_file`] with [`MAX_ORBIT_FILE_BYTES`].
fn read_text(path: &Path) -> Result<String, OrbitFileError> {
    crate::input_file::read_to_string(path, MAX_ORBIT_FILE_BYTES).map_err(|source| {
        OrbitFileError::Read {
            file: path.display().to_string(),
            source,
        }
    })
}
