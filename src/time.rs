//! Absolute time: the scenario epoch (UTC) and the times of a run's outputs, with the time-scale offsets
//! done by [hifitime](https://docs.rs/hifitime) (leap seconds included).
//!
//! The engine integrates in elapsed SI seconds `t_s` from the epoch: a uniform (TAI-like) time, so an
//! output time is `epoch + t_s` as an instant, printed in UTC. A run that spans a leap second therefore
//! prints a UTC clock that repeats 23:59:60, never a wrong instant.

use hifitime::{Duration, TimeScale};

pub use hifitime::Epoch;

/// The default scenario epoch, `2000-01-01T12:00:00Z`: at that instant the engine's inertial frame (z
/// axis on Earth's rotation axis, see [`crate::output::frames`]) and EME2000 coincide up to nutation.
pub const DEFAULT_EPOCH_UTC: &str = "2000-01-01T12:00:00Z";

/// Parses an ISO 8601 UTC date-time (`2026-03-20T12:00:00Z`, fractional seconds allowed, the `Z` or a
/// ` UTC` suffix optional); the message of an error says what is accepted.
pub fn parse_epoch_utc(text: &str) -> Result<Epoch, String> {
    let trimmed = text.trim();
    let bare = trimmed
        .strip_suffix('Z')
        .or_else(|| trimmed.strip_suffix(" UTC"))
        .unwrap_or(trimmed);
    let accepted =
        "allowed: an ISO 8601 UTC date-time such as \"2026-03-20T12:00:00Z\", years 1900 to 2100";
    let epoch = Epoch::from_gregorian_str(&format!("{bare} UTC"))
        .map_err(|e| format!("`{text}` is not a date-time ({e}; {accepted})"))?;
    let (year, ..) = epoch.to_gregorian_utc();
    if !(1900..=2100).contains(&year) {
        return Err(format!("`{text}` is out of range ({accepted})"));
    }
    Ok(epoch)
}

/// The instant `t_s` elapsed SI seconds after `epoch`.
pub fn at(epoch: Epoch, t_s: f64) -> Epoch {
    // Add in TAI (uniform): hifitime adds a duration in the epoch's own scale, and UTC's count of
    // seconds skips leap seconds.
    epoch.to_time_scale(TimeScale::TAI) + Duration::from_seconds(t_s)
}

/// An instant as ISO 8601 UTC with microseconds and the zone letter: `2026-03-20T12:00:00.000000Z`
/// (`summary.json`, the tables' `time_utc`, Parquet metadata, CZML, the report).
pub fn utc_iso(instant: Epoch) -> String {
    format!("{}Z", ccsds_utc(instant))
}

/// An instant as CCSDS time-code text, ISO 8601 with microseconds and no zone letter (the OEM's
/// `TIME_SYSTEM = UTC` line names the scale): `2026-03-20T12:00:00.000000`.
pub fn ccsds_utc(instant: Epoch) -> String {
    let (y, mo, d, h, mi, s, ns) = instant.to_gregorian_utc();
    // Round to the microsecond without carrying into the seconds (a 999 999 500 ns remainder prints as
    // .999999: the printed value is a truncation below the microsecond, never a later instant).
    format!(
        "{y:04}-{mo:02}-{d:02}T{h:02}:{mi:02}:{s:02}.{:06}",
        ns / 1000
    )
}

/// TAI − UTC at `instant` \[s\] (the leap seconds so far, from hifitime's table).
pub fn tai_minus_utc_s(instant: Epoch) -> f64 {
    (instant.to_time_scale(TimeScale::TAI).to_tai_seconds()
        - instant.to_time_scale(TimeScale::UTC).to_utc_seconds())
    .round()
}

/// TT − UTC at `instant` \[s\] (TAI − UTC + 32.184 s).
pub fn tt_minus_utc_s(instant: Epoch) -> f64 {
    tai_minus_utc_s(instant) + 32.184
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_prints_utc() {
        let e = parse_epoch_utc("2026-03-20T12:00:00Z").unwrap();
        assert_eq!(utc_iso(e), "2026-03-20T12:00:00.000000Z");
        assert_eq!(ccsds_utc(e), "2026-03-20T12:00:00.000000");
        assert_eq!(utc_iso(at(e, 90.5)), "2026-03-20T12:01:30.500000Z");
        assert_eq!(utc_iso(at(e, 86_400.0)), "2026-03-21T12:00:00.000000Z");
        assert_eq!(parse_epoch_utc(&utc_iso(at(e, 90.5))).unwrap(), at(e, 90.5));
        assert!(parse_epoch_utc("yesterday")
            .unwrap_err()
            .contains("ISO 8601"));
        assert!(parse_epoch_utc("1066-10-14T09:00:00Z").is_err());
    }

    /// TAI − UTC from the IERS bulletins (independent of hifitime): 32 s in 2000, 37 s since 2017.
    #[test]
    fn leap_seconds_match_the_iers_table() {
        let e2000 = parse_epoch_utc(DEFAULT_EPOCH_UTC).unwrap();
        assert_eq!(tai_minus_utc_s(e2000), 32.0);
        assert_eq!(tt_minus_utc_s(e2000), 64.184);
        let e2026 = parse_epoch_utc("2026-03-20T12:00:00Z").unwrap();
        assert_eq!(tai_minus_utc_s(e2026), 37.0);
    }

    /// Across the leap second at the end of 2016, one elapsed second after 23:59:59 UTC is 23:59:60.
    #[test]
    fn a_leap_second_is_a_repeated_clock_not_a_lost_second() {
        let before = parse_epoch_utc("2016-12-31T23:59:59Z").unwrap();
        assert_eq!(utc_iso(at(before, 2.0)), "2017-01-01T00:00:00.000000Z");
        assert_eq!(tai_minus_utc_s(at(before, 3.0)), 37.0);
    }
}
