//! CCSDS epochs and time systems: `TIME_SYSTEM` values satflock converts ([`TimeSystem`]: UTC, TAI,
//! TT, GPS, through hifitime, leap seconds included) and the CCSDS ASCII time code
//! ([`parse_ccsds_epoch`]: `YYYY-MM-DDThh:mm:ss[.d…][Z]` or `YYYY-DDDThh:mm:ss[.d…][Z]`).

use hifitime::{Epoch, TimeScale};

/// A CCSDS `TIME_SYSTEM` satflock can convert to an instant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimeSystem {
    /// Coordinated Universal Time (leap seconds from hifitime's table).
    Utc,
    /// International Atomic Time.
    Tai,
    /// Terrestrial Time (TAI + 32.184 s).
    Tt,
    /// GPS time (TAI − 19 s).
    Gps,
}

impl TimeSystem {
    /// The values of `TIME_SYSTEM` satflock accepts, for error messages.
    pub const ALLOWED: &'static str = "UTC, TAI, TT or GPS";

    /// The time system a CCSDS `TIME_SYSTEM` value names (case-insensitive), if satflock converts it.
    pub fn from_ccsds(value: &str) -> Option<Self> {
        match value.trim().to_ascii_uppercase().as_str() {
            "UTC" => Some(Self::Utc),
            "TAI" => Some(Self::Tai),
            "TT" => Some(Self::Tt),
            "GPS" => Some(Self::Gps),
            _ => None,
        }
    }

    /// hifitime's time scale.
    pub fn time_scale(self) -> TimeScale {
        match self {
            Self::Utc => TimeScale::UTC,
            Self::Tai => TimeScale::TAI,
            Self::Tt => TimeScale::TT,
            Self::Gps => TimeScale::GPST,
        }
    }
}

/// What [`parse_ccsds_epoch`] accepts, for error messages.
pub(crate) const EPOCH_FORMATS: &str =
    "a CCSDS date-time YYYY-MM-DDThh:mm:ss[.d…] or YYYY-DDDThh:mm:ss[.d…] (an optional trailing Z), \
     years 1900 to 2100";

/// Days before each month in a common year.
const DAYS_BEFORE_MONTH: [u16; 12] = [0, 31, 59, 90, 120, 151, 181, 212, 243, 273, 304, 334];

fn is_leap_year(year: i32) -> bool {
    (year % 4 == 0 && year % 100 != 0) || year % 400 == 0
}

/// Month and day of day-of-year `doy` (1-based).
fn month_day(year: i32, doy: u16) -> Option<(u8, u8)> {
    let leap = u16::from(is_leap_year(year));
    if doy == 0 || doy > 365 + leap {
        return None;
    }
    let month = (1..=12u8)
        .rev()
        .find(|&m| {
            let before = DAYS_BEFORE_MONTH[usize::from(m - 1)] + if m > 2 { leap } else { 0 };
            before < doy
        })
        .unwrap_or(1);
    let before = DAYS_BEFORE_MONTH[usize::from(month - 1)] + if month > 2 { leap } else { 0 };
    Some((month, (doy - before) as u8))
}

fn number<T: std::str::FromStr>(text: &str, digits: usize) -> Option<T> {
    (text.len() == digits && text.bytes().all(|b| b.is_ascii_digit()))
        .then(|| text.parse().ok())
        .flatten()
}

/// The instant a CCSDS ASCII time code names in `system`: `2026-03-20T12:00:00.123456` or the
/// day-of-year form `2026-079T12:00:00`, an optional `Z`; fractional seconds to the nanosecond (finer
/// digits are dropped). The error says what is accepted.
pub fn parse_ccsds_epoch(text: &str, system: TimeSystem) -> Result<Epoch, String> {
    let bad = || format!("not a date-time (allowed: {EPOCH_FORMATS})");
    let trimmed = text.trim();
    let bare = trimmed.strip_suffix('Z').unwrap_or(trimmed);
    let (date, time) = bare.split_once('T').ok_or_else(bad)?;
    let mut date_parts = date.split('-');
    let year: i32 = number(date_parts.next().ok_or_else(bad)?, 4).ok_or_else(bad)?;
    let (month, day) = match (date_parts.next(), date_parts.next(), date_parts.next()) {
        (Some(doy), None, None) => {
            month_day(year, number(doy, 3).ok_or_else(bad)?).ok_or_else(bad)?
        }
        (Some(m), Some(d), None) => (number(m, 2).ok_or_else(bad)?, number(d, 2).ok_or_else(bad)?),
        _ => return Err(bad()),
    };
    let (whole, fraction) = time.split_once('.').unwrap_or((time, ""));
    let mut time_parts = whole.split(':');
    let mut field =
        || -> Result<u8, String> { number(time_parts.next().ok_or_else(bad)?, 2).ok_or_else(bad) };
    let (hour, minute, second) = (field()?, field()?, field()?);
    if time_parts.next().is_some() || !fraction.bytes().all(|b| b.is_ascii_digit()) {
        return Err(bad());
    }
    if hour > 23 || minute > 59 || second > 60 {
        return Err(bad());
    }
    let nanos: u32 = format!("{:0<9}", &fraction[..fraction.len().min(9)])
        .parse()
        .map_err(|_| bad())?;
    if !(1900..=2100).contains(&year) {
        return Err(format!("out of range (allowed: {EPOCH_FORMATS})"));
    }
    Epoch::maybe_from_gregorian(
        year,
        month,
        day,
        hour,
        minute,
        second,
        nanos,
        system.time_scale(),
    )
    .map_err(|e| format!("not a valid date-time ({e}; allowed: {EPOCH_FORMATS})"))
}

/// Elapsed SI seconds from `earlier` to `later` (counted in TAI: hifitime subtracts in the first
/// epoch's own scale, and UTC's count skips leap seconds).
pub(crate) fn elapsed_s(later: Epoch, earlier: Epoch) -> f64 {
    (later.to_time_scale(TimeScale::TAI) - earlier.to_time_scale(TimeScale::TAI)).to_seconds()
}

/// The instant `seconds` elapsed SI seconds after `epoch` (added in TAI).
pub(crate) fn after_s(epoch: Epoch, seconds: f64) -> Epoch {
    epoch.to_time_scale(TimeScale::TAI) + hifitime::Duration::from_seconds(seconds)
}

/// An instant as UTC text for messages: `2026-03-20T12:00:00 UTC`.
pub(crate) fn utc_text(epoch: Epoch) -> String {
    epoch.to_time_scale(TimeScale::UTC).to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn calendar_and_day_of_year_forms_agree() {
        let a = parse_ccsds_epoch("2024-03-01T06:30:15.25", TimeSystem::Utc).unwrap();
        let b = parse_ccsds_epoch("2024-061T06:30:15.250000Z", TimeSystem::Utc).unwrap();
        assert_eq!(a, b);
        assert_eq!(
            parse_ccsds_epoch("2023-365T00:00:00", TimeSystem::Utc).unwrap(),
            parse_ccsds_epoch("2023-12-31T00:00:00", TimeSystem::Utc).unwrap()
        );
        assert!(parse_ccsds_epoch("2023-366T00:00:00", TimeSystem::Utc).is_err());
        assert!(parse_ccsds_epoch("2023-02-29T00:00:00", TimeSystem::Utc).is_err());
        assert!(parse_ccsds_epoch("2023-02-28 00:00:00", TimeSystem::Utc)
            .unwrap_err()
            .contains("YYYY-MM-DD"));
        assert!(parse_ccsds_epoch("1850-01-01T00:00:00", TimeSystem::Utc).is_err());
    }

    /// The offsets between the scales at 2026 (IERS: TAI − UTC = 37 s since 2017; TT = TAI + 32.184 s;
    /// GPS = TAI − 19 s), independent of hifitime's own tests.
    #[test]
    fn time_systems_name_the_same_instant() {
        let utc = parse_ccsds_epoch("2026-03-20T12:00:00", TimeSystem::Utc).unwrap();
        let tai = parse_ccsds_epoch("2026-03-20T12:00:37", TimeSystem::Tai).unwrap();
        let tt = parse_ccsds_epoch("2026-03-20T12:01:09.184", TimeSystem::Tt).unwrap();
        let gps = parse_ccsds_epoch("2026-03-20T12:00:18", TimeSystem::Gps).unwrap();
        for other in [tai, tt, gps] {
            assert!((other - utc).to_seconds().abs() < 1e-9, "{other} vs {utc}");
        }
    }
}
