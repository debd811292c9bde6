//! [`Sgp4Object`]: one element set (from an OMM or a TLE) and its SGP4 propagator, giving the
//! object's TEME and EME2000 states at any epoch — at initialisation, or at every step of a run for an
//! object propagated by SGP4.
//!
//! Propagation is the `sgp4` crate's (a Rust port of Vallado et al. 2006, "Revisiting Spacetrack
//! Report #3", checked there against Vallado's test vectors) in its AFSPC-compatible mode: WGS-72
//! constants and the AFSPC sidereal time, the constants the catalogue's element sets are fitted with.
//! The time since the element set's epoch is counted in UTC, leap seconds not counted (the convention
//! of SGP4 and of the element sets: time since epoch from the difference of UTC dates).

use hifitime::{Epoch, TimeScale};
use nalgebra::Vector3;

use super::epoch::utc_text;
use super::error::OrbitFileError;
use super::teme::teme_to_eme2000;
use crate::orbit::CartesianState;

/// One element set and its SGP4 propagator.
#[derive(Clone, Debug)]
pub struct Sgp4Object {
    source: String,
    elements: sgp4::Elements,
    constants: sgp4::Constants,
    epoch: Epoch,
}

/// The element set's epoch (UTC) as an instant.
fn instant_of(datetime: &sgp4::chrono::NaiveDateTime) -> Option<Epoch> {
    use sgp4::chrono::{Datelike, Timelike};
    let nanos = datetime.nanosecond();
    // chrono puts a leap second in the nanoseconds (≥ 10⁹): hifitime takes it as second 60.
    let (second, nanos) = if nanos >= 1_000_000_000 {
        (60, nanos - 1_000_000_000)
    } else {
        (datetime.second() as u8, nanos)
    };
    Epoch::maybe_from_gregorian(
        datetime.year(),
        datetime.month() as u8,
        datetime.day() as u8,
        datetime.hour() as u8,
        datetime.minute() as u8,
        second,
        nanos,
        TimeScale::UTC,
    )
    .ok()
}

/// Two propagators are equal when they hold the same element set from the same source (the SGP4
/// constants follow from the elements).
impl PartialEq for Sgp4Object {
    fn eq(&self, other: &Self) -> bool {
        self.source == other.source && self.elements == other.elements && self.epoch == other.epoch
    }
}

impl Sgp4Object {
    /// The propagator of `elements`; `source` names where they come from (`flock.tle line 4`,
    /// `scenario.toml [reference] tle`) in every later error.
    pub fn from_elements(
        source: impl Into<String>,
        elements: sgp4::Elements,
    ) -> Result<Self, OrbitFileError> {
        let source = source.into();
        let bad = |problem: String| {
            OrbitFileError::invalid(
                &source,
                None,
                "element set",
                &elements.datetime.to_string(),
                problem,
                "an element set SGP4 accepts: 0 <= eccentricity < 1, a mean motion that gives a \
                 bound orbit, an epoch from 1900 to 2100",
            )
        };
        let epoch = instant_of(&elements.datetime)
            .ok_or_else(|| bad("its epoch is not a valid date".into()))?;
        let constants = sgp4::Constants::from_elements_afspc_compatibility_mode(&elements)
            .map_err(|e| bad(format!("SGP4 refuses it: {e}")))?;
        Ok(Self {
            source,
            elements,
            constants,
            epoch,
        })
    }

    /// The propagator of a two-line element set, `name` from a title line if there is one; the
    /// checksums are checked ([`super::tle`]). `source` names the lines in errors.
    pub fn from_tle_lines(
        source: &str,
        name: Option<&str>,
        line1: &str,
        line2: &str,
    ) -> Result<Self, OrbitFileError> {
        super::tle::element_set(source, None, name, line1, line2)
    }

    /// Where the element set comes from (file and line, or the caller's name).
    pub fn source(&self) -> &str {
        &self.source
    }

    /// The element set as parsed (angles in degrees, mean motion in revolutions per day).
    pub fn elements(&self) -> &sgp4::Elements {
        &self.elements
    }

    /// `OBJECT_NAME` (or the TLE title line), if the element set has one.
    pub fn name(&self) -> Option<&str> {
        self.elements.object_name.as_deref()
    }

    /// The catalogue number (`NORAD_CAT_ID`; Alpha-5 numbers decoded).
    pub fn norad_id(&self) -> u64 {
        self.elements.norad_id
    }

    /// `NAME (12345)` or `12345`: the object in messages.
    pub fn label(&self) -> String {
        match self.name() {
            Some(n) => format!("{n} ({})", self.norad_id()),
            None => self.norad_id().to_string(),
        }
    }

    /// The element set's epoch (given in UTC).
    pub fn epoch(&self) -> Epoch {
        self.epoch
    }

    /// Minutes from the element set's epoch to `at`, counted in UTC (leap seconds not counted).
    fn minutes_since_epoch(&self, at: Epoch) -> f64 {
        (at.to_utc_duration() - self.epoch.to_utc_duration()).to_seconds() / 60.0
    }

    /// The state at `at` in TEME of date (m, m/s), SGP4's own output.
    pub fn state_teme(&self, at: Epoch) -> Result<CartesianState, OrbitFileError> {
        let minutes = self.minutes_since_epoch(at);
        let p = self
            .constants
            .propagate_afspc_compatibility_mode(sgp4::MinutesSinceEpoch(minutes))
            .map_err(|e| OrbitFileError::Propagation {
                source_name: self.source.clone(),
                object: self.label(),
                epoch: utc_text(at),
                message: e.to_string(),
            })?;
        let km = |v: [f64; 3]| Vector3::new(v[0], v[1], v[2]) * 1000.0;
        Ok(CartesianState::new(km(p.position), km(p.velocity)))
    }

    /// The state at `at` in EME2000 (m, m/s): [`Self::state_teme`] rotated by
    /// [`super::teme_to_eme2000`] (which neglects the IERS nutation corrections, about 1 m).
    pub fn state_eme2000(&self, at: Epoch) -> Result<CartesianState, OrbitFileError> {
        Ok(teme_to_eme2000(at, &self.state_teme(at)?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Across the leap second at the end of 2016, SGP4's minutes count UTC dates: one UTC-clock
    /// second, though two SI seconds elapse.
    #[test]
    fn minutes_count_utc_dates() {
        let object = Sgp4Object::from_tle_lines(
            "test",
            None,
            "1 00005U 58002B   00179.78495062  .00000023  00000-0  28098-4 0  4753",
            "2 00005  34.2682 348.7242 1859667 331.7664  19.3264 10.82419157413667",
        )
        .unwrap();
        let before = Epoch::from_gregorian_utc(2016, 12, 31, 23, 59, 59, 0);
        let after = Epoch::from_gregorian_utc(2017, 1, 1, 0, 0, 0, 0);
        assert_eq!(super::super::epoch::elapsed_s(after, before), 2.0);
        let dm = object.minutes_since_epoch(after) - object.minutes_since_epoch(before);
        assert!((dm * 60.0 - 1.0).abs() < 1e-6, "{}", dm * 60.0);
    }
}
