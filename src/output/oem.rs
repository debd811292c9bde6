//! CCSDS Orbit Ephemeris Message (OEM) version 2.0 in keyword = value notation (KVN), the ephemeris
//! format of CCSDS 502.0-B-2 that GMAT, Orekit, STK and most flight-dynamics tools read.
//!
//! One object per file by default (the standard's rule, 502.0-B-2 §5.1.3); a single file with a
//! segment per satellite only when asked for ([`OemLayout::OneFile`], not compliant). Version 2.0 by
//! default, 3.0 (502.0-B-3: a `MESSAGE_ID` in the header) as an option ([`OemVersion`]).
//!
//! One segment per satellite: the header (`CCSDS_OEM_VERS`, `COMMENT`s, `CREATION_DATE`, `ORIGINATOR`),
//! then per segment `META_START`, `COMMENT`s (the frame and the scenario), `OBJECT_NAME`, `OBJECT_ID`,
//! `CENTER_NAME = EARTH`, `REF_FRAME = EME2000` ([`frames::INERTIAL_FRAME`]), `TIME_SYSTEM = UTC`,
//! `START_TIME`, `STOP_TIME`, `INTERPOLATION = LAGRANGE` and `INTERPOLATION_DEGREE` (with at least two
//! states), `META_STOP`, a `COMMENT` giving the units, and one line per state: `epoch x y z vx vy vz`.
//! That is the standard's keyword order (optional keywords it places between them, such as
//! `REF_FRAME_EPOCH` or `USEABLE_START_TIME`, are not written).
//!
//! Units and precision: positions in km printed to [`POSITION_DECIMALS`] decimals (1e-9 km = 1 µm),
//! velocities in km/s to [`VELOCITY_DECIMALS`] decimals (1e-12 km/s = 1 nm/s): finer than the
//! integrator's error, so relative positions of close satellites can be taken from the file. Epochs are
//! ISO 8601 UTC with microseconds ([`time::ccsds_utc`]).
//!
//! `CREATION_DATE` is the time of writing, or `SOURCE_DATE_EPOCH` (seconds since 1970-01-01T00:00:00Z,
//! the reproducible-builds convention) when that variable is set, so tests and archives can compare
//! files byte for byte ([`creation_date`]).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::export::{create_dir, write_whole, ExportError, InertialTrack};
use super::frames;
use super::run_data::RunData;
use crate::time::{self, Epoch};

/// `CCSDS_OEM_VERS` of the default version.
pub const OEM_VERSION: &str = "2.0";

/// Which OEM version a message is written in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum OemVersion {
    /// CCSDS 502.0-B-2, `CCSDS_OEM_VERS = 2.0` (the default: the version most tools read).
    #[default]
    V2,
    /// CCSDS 502.0-B-3, `CCSDS_OEM_VERS = 3.0`: the same body, and a `MESSAGE_ID` in the header.
    V3,
}

impl OemVersion {
    /// The `CCSDS_OEM_VERS` value.
    pub fn keyword(self) -> &'static str {
        match self {
            OemVersion::V2 => OEM_VERSION,
            OemVersion::V3 => "3.0",
        }
    }
}

/// `ORIGINATOR`.
pub const ORIGINATOR: &str = "satflock";

/// `CENTER_NAME`.
pub const CENTER_NAME: &str = "EARTH";

/// Decimals of the positions \[km\]: 9, i.e. 1 µm.
pub const POSITION_DECIMALS: usize = 9;

/// Decimals of the velocities \[km/s\]: 12, i.e. 1 nm/s.
pub const VELOCITY_DECIMALS: usize = 12;

/// `INTERPOLATION_DEGREE` (Lagrange), lowered to the number of states − 1 for a short segment.
pub const INTERPOLATION_DEGREE: usize = 5;

/// The environment variable that fixes `CREATION_DATE` (seconds since the Unix epoch).
pub const SOURCE_DATE_EPOCH: &str = "SOURCE_DATE_EPOCH";

/// The non-standard single OEM file of a run directory (`satflock export oem --single-file`).
pub const RUN_FILE: &str = "swarm.oem";

/// The folder of per-satellite OEM files in a run directory (`[output] oem = true`, or
/// `satflock export oem`).
pub const RUN_DIR_NAME: &str = "oem";

/// Longest `COMMENT` text on one line (the standard allows lines of up to 254 characters).
const COMMENT_WIDTH: usize = 100;

/// One segment of a message: an object and its inertial states.
#[derive(Clone, Debug)]
pub struct OemObject<'a> {
    /// `OBJECT_NAME`.
    pub name: String,
    /// `OBJECT_ID`.
    pub id: String,
    /// The states (m, m/s; written in km, km/s).
    pub track: &'a InertialTrack,
}

/// A whole OEM: header and segments.
#[derive(Clone, Debug)]
pub struct OemMessage<'a> {
    /// `CREATION_DATE` (printed in UTC).
    pub creation_date: Epoch,
    /// The instant of `t_s = 0` of the tracks.
    pub epoch: Epoch,
    /// Header comments (what produced the file).
    pub header_comments: Vec<String>,
    /// Comments of every segment's metadata (the frame is always said first).
    pub segment_comments: Vec<String>,
    /// One segment each.
    pub objects: Vec<OemObject<'a>>,
    /// The version written.
    pub version: OemVersion,
    /// `MESSAGE_ID` (written in version 3.0).
    pub message_id: String,
}

/// `OBJECT_NAME` and `OBJECT_ID` of satellite `id` of a run: `SAT-00007` and `SATFLOCK-00007`.
pub fn satellite_object(track: &InertialTrack) -> OemObject<'_> {
    OemObject {
        name: format!("SAT-{:05}", track.id),
        id: format!("SATFLOCK-{:05}", track.id),
        track,
    }
}

/// The file name of satellite `id`'s own OEM: `sat-00007.oem`.
pub fn satellite_file_name(id: usize) -> String {
    format!("sat-{id:05}.oem")
}

/// `CREATION_DATE`: [`SOURCE_DATE_EPOCH`] when set (whole seconds since 1970-01-01T00:00:00Z), else the
/// system clock. A malformed variable is an error naming it.
pub fn creation_date() -> Result<Epoch, String> {
    match std::env::var(SOURCE_DATE_EPOCH) {
        Ok(text) => {
            let seconds: i64 = text.trim().parse().map_err(|_| {
                format!(
                    "{SOURCE_DATE_EPOCH} = `{text}` is not a whole number of seconds since \
                     1970-01-01T00:00:00Z"
                )
            })?;
            let epoch = Epoch::from_unix_seconds(seconds as f64);
            let (year, ..) = epoch.to_gregorian_utc();
            if !(1970..=2100).contains(&year) {
                return Err(format!(
                    "{SOURCE_DATE_EPOCH} = {seconds} is out of range (allowed: a date from 1970 to 2100)"
                ));
            }
            Ok(epoch)
        }
        Err(_) => {
            Epoch::now().map_err(|e| format!("cannot read the system clock for CREATION_DATE: {e}"))
        }
    }
}

/// Appends `COMMENT` lines holding `text`, split at spaces into lines of at most [`COMMENT_WIDTH`]
/// characters (a longer word stays whole).
fn push_comment(out: &mut String, text: &str) {
    let mut line = String::new();
    for word in text.split_whitespace() {
        if !line.is_empty() && line.len() + 1 + word.len() > COMMENT_WIDTH {
            let _ = writeln!(out, "COMMENT {line}");
            line.clear();
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(word);
    }
    if !line.is_empty() {
        let _ = writeln!(out, "COMMENT {line}");
    }
}

impl OemMessage<'_> {
    /// The message as KVN text. Segments with no state are left out.
    pub fn to_kvn(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(out, "CCSDS_OEM_VERS = {}", self.version.keyword());
        for c in &self.header_comments {
            push_comment(&mut out, c);
        }
        let _ = writeln!(
            out,
            "CREATION_DATE = {}",
            time::ccsds_utc(self.creation_date)
        );
        let _ = writeln!(out, "ORIGINATOR = {ORIGINATOR}");
        if self.version == OemVersion::V3 {
            let _ = writeln!(out, "MESSAGE_ID = {}", self.message_id);
        }
        let at = |t_s: f64| time::ccsds_utc(time::at(self.epoch, t_s));
        for object in &self.objects {
            let track = object.track;
            let (Some(&first), Some(&last)) = (track.t_s.first(), track.t_s.last()) else {
                continue;
            };
            out.push('\n');
            out.push_str("META_START\n");
            push_comment(
                &mut out,
                &format!("Reference frame: {}.", frames::INERTIAL_FRAME_DESCRIPTION),
            );
            for c in &self.segment_comments {
                push_comment(&mut out, c);
            }
            let _ = writeln!(out, "OBJECT_NAME = {}", object.name);
            let _ = writeln!(out, "OBJECT_ID = {}", object.id);
            let _ = writeln!(out, "CENTER_NAME = {CENTER_NAME}");
            let _ = writeln!(out, "REF_FRAME = {}", frames::INERTIAL_FRAME);
            let _ = writeln!(out, "TIME_SYSTEM = {}", frames::TIME_SYSTEM);
            let _ = writeln!(out, "START_TIME = {}", at(first));
            let _ = writeln!(out, "STOP_TIME = {}", at(last));
            if track.t_s.len() >= 2 {
                let degree = INTERPOLATION_DEGREE.min(track.t_s.len() - 1);
                out.push_str("INTERPOLATION = LAGRANGE\n");
                let _ = writeln!(out, "INTERPOLATION_DEGREE = {degree}");
            }
            out.push_str("META_STOP\n\n");
            push_comment(
                &mut out,
                &format!(
                    "epoch ({}) x y z [km] vx vy vz [km/s], to 1e-{POSITION_DECIMALS} km and \
                     1e-{VELOCITY_DECIMALS} km/s",
                    frames::TIME_SYSTEM
                ),
            );
            for (&t, s) in track.t_s.iter().zip(&track.states) {
                let _ = write!(out, "{}", at(t));
                for p in &s[..3] {
                    let _ = write!(out, " {:.*}", POSITION_DECIMALS, p / 1000.0);
                }
                for v in &s[3..] {
                    let _ = write!(out, " {:.*}", VELOCITY_DECIMALS, v / 1000.0);
                }
                out.push('\n');
            }
        }
        out
    }
}

/// Where [`write_run_oem`] writes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum OemLayout {
    /// One file, one segment per satellite: not CCSDS-compliant for more than one satellite
    /// (502.0-B-2 and -B-3 define an OEM for a single object; readers that enforce it refuse it).
    OneFile(PathBuf),
    /// One file per satellite, `sat-NNNNN.oem`, in this directory (created if needed): the standard
    /// layout, and the default.
    PerSatellite(PathBuf),
}

impl OemLayout {
    /// The layout in a run directory: `RUN_DIR/oem/` per satellite (the default), or the
    /// non-standard single file `RUN_DIR/swarm.oem`.
    pub fn in_run_dir(run_dir: &Path, single_file: bool) -> Self {
        if single_file {
            Self::OneFile(run_dir.join(RUN_FILE))
        } else {
            Self::PerSatellite(run_dir.join(RUN_DIR_NAME))
        }
    }
}

/// Writes the OEM of every satellite of a run read back by [`RunData::read`], from its
/// `trajectory.csv` inertial columns. Returns the files written and the number of segments.
pub fn write_run_oem(
    run: &RunData,
    layout: &OemLayout,
    creation_date: Epoch,
    version: OemVersion,
) -> Result<(Vec<PathBuf>, usize), ExportError> {
    let tracks = run.inertial_tracks()?;
    let field = |key: &str| {
        run.summary
            .get(key)
            .map(|v| v.as_str().map_or_else(|| v.to_string(), str::to_string))
            .unwrap_or_else(|| "?".into())
    };
    let scenario = field("scenario");
    let header_comments = vec![format!(
        "Written by satflock {} from the run directory {} (scenario `{scenario}` from {}, seed {}, status \
         {}): one segment per satellite, each ending at its last recorded state.",
        env!("CARGO_PKG_VERSION"),
        run.dir.display(),
        field("source"),
        field("seed"),
        field("status"),
    )];
    let segment_comments = vec![format!("Scenario: {scenario}.")];
    let mut all_comments = header_comments.clone();
    if tracks.len() > 1 {
        all_comments.push(
            "NOT CCSDS-COMPLIANT: several objects, one segment each; CCSDS 502.0-B-2 (5.1.3) and \
             502.0-B-3 define an OEM for a single object, so readers that enforce it need one file \
             per satellite (the default of satflock export oem; this file was asked for with \
             --single-file)."
                .into(),
        );
    }
    let message = |objects: Vec<OemObject<'_>>, header_comments: &[String]| {
        let message_id = match objects.as_slice() {
            [one] => format!("SATFLOCK-{scenario}-{}-{}", field("seed"), one.name),
            _ => format!("SATFLOCK-{scenario}-{}-SWARM", field("seed")),
        }
        .replace(' ', "_");
        OemMessage {
            creation_date,
            epoch: run.epoch,
            header_comments: header_comments.to_vec(),
            segment_comments: segment_comments.clone(),
            objects,
            version,
            message_id,
        }
        .to_kvn()
    };
    match layout {
        OemLayout::OneFile(path) => {
            write_whole(
                path,
                message(tracks.iter().map(satellite_object).collect(), &all_comments).as_bytes(),
            )?;
            Ok((vec![path.clone()], tracks.len()))
        }
        OemLayout::PerSatellite(dir) => {
            create_dir(dir)?;
            let mut written = Vec::with_capacity(tracks.len());
            for track in &tracks {
                let path = dir.join(satellite_file_name(track.id));
                let text = message(vec![satellite_object(track)], &header_comments);
                write_whole(&path, text.as_bytes())?;
                written.push(path);
            }
            Ok((written, tracks.len()))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comments_wrap_at_spaces() {
        let mut out = String::new();
        push_comment(&mut out, &"word ".repeat(60));
        assert!(out
            .lines()
            .all(|l| l.starts_with("COMMENT ") && l.len() <= 8 + COMMENT_WIDTH));
        assert_eq!(out.matches("word").count(), 60);
    }

    #[test]
    fn a_single_state_has_no_interpolation() {
        let track = InertialTrack {
            id: 3,
            t_s: vec![10.0],
            states: vec![[7e6, 0.0, 0.0, 0.0, 7.5e3, 0.0]],
        };
        let text = OemMessage {
            creation_date: time::parse_epoch_utc("2026-01-01T00:00:00Z").unwrap(),
            epoch: time::parse_epoch_utc(time::DEFAULT_EPOCH_UTC).unwrap(),
            header_comments: vec![],
            segment_comments: vec![],
            objects: vec![satellite_object(&track)],
            version: OemVersion::V2,
            message_id: String::new(),
        }
        .to_kvn();
        assert!(!text.contains("INTERPOLATION"), "{text}");
        assert!(text.contains("START_TIME = 2000-01-01T12:00:10.000000"));
        assert!(text.contains(
            "2000-01-01T12:00:10.000000 7000.000000000 0.000000000 0.000000000 0.000000000000 \
             7.500000000000 0.000000000000"
        ));
    }
}
