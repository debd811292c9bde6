//! CCSDS Orbit Ephemeris Messages (OEM, CCSDS 502.0-B-2 and -3: `CCSDS_OEM_VERS = 2.0` or `3.0`) in
//! keyword = value notation (KVN), read into one [`OemObject`] per `OBJECT_ID` ([`read_oem_files`],
//! [`parse_oem`]), whose [`OemObject::state_eme2000`] is the state at any epoch its segments cover.
//!
//! # What is read
//!
//! * Header: `CCSDS_OEM_VERS` first, then `CREATION_DATE` and `ORIGINATOR` (mandatory) and
//!   `MESSAGE_ID`; `COMMENT`s anywhere a comment is allowed; blank lines.
//! * Each segment's metadata between `META_START` and `META_STOP`: `OBJECT_NAME`, `OBJECT_ID`,
//!   `CENTER_NAME`, `REF_FRAME`, `TIME_SYSTEM`, `START_TIME`, `STOP_TIME` (mandatory),
//!   `REF_FRAME_EPOCH` (read, unused: the frames read have no epoch), `USEABLE_START_TIME`,
//!   `USEABLE_STOP_TIME`, `INTERPOLATION` (`LAGRANGE`, `HERMITE`, or `LINEAR` = Lagrange of degree 1)
//!   and `INTERPOLATION_DEGREE` (mandatory with `LAGRANGE` and `HERMITE`). Any other keyword is an
//!   error naming it.
//! * Data lines `epoch x y z vx vy vz [ax ay az]` in km, km/s (and km/s²), converted to m, m/s,
//!   m/s²; epochs strictly increasing and within `START_TIME`…`STOP_TIME`.
//! * Covariance blocks (`COVARIANCE_START` … `COVARIANCE_STOP`) are skipped.
//!
//! Convertible: `CENTER_NAME = EARTH`; `REF_FRAME` `EME2000` (as is), `GCRF` and `ICRF` (rotated by
//! the frame bias, [`super::gcrf_to_eme2000`]); `TIME_SYSTEM` UTC, TAI, TT or GPS ([`TimeSystem`]).
//! Anything else is refused with the file, the line and what is allowed.
//!
//! # Objects, segments and the state at an epoch
//!
//! Segments with the same `OBJECT_ID` (in one file or several) are one object, in order of first
//! appearance. A segment holds states from `max(START_TIME, USEABLE_START_TIME, first sample)` to
//! `min(STOP_TIME, USEABLE_STOP_TIME, last sample)`; the state at an epoch comes from the first
//! segment (in file order) whose window holds it, interpolated with that segment's own method and
//! degree ([`Interpolation`]) over the samples nearest the epoch (a window centred on it, shifted
//! inside the segment at its ends); times are elapsed SI seconds, so a UTC file across a leap second
//! interpolates correctly. An epoch outside every window is an error listing the windows; a segment
//! without `INTERPOLATION` gives states only at its sample epochs.

use std::path::Path;

use hifitime::Epoch;
use nalgebra::Vector3;

use super::epoch::{after_s, elapsed_s, parse_ccsds_epoch, utc_text, TimeSystem, EPOCH_FORMATS};
use super::error::OrbitFileError;
use super::interpolation::{hermite, lagrange, Interpolation};
use super::kvn::{self, Kvn};
use super::teme::gcrf_to_eme2000;
use crate::orbit::CartesianState;

/// The `REF_FRAME`s satflock converts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OemFrame {
    /// `EME2000`: satflock's inertial frame, taken as is.
    Eme2000,
    /// `GCRF`: rotated to EME2000 by the frame bias.
    Gcrf,
    /// `ICRF` (geocentric, `CENTER_NAME = EARTH`): as GCRF.
    Icrf,
}

impl OemFrame {
    /// The `REF_FRAME` values accepted, for error messages.
    pub const ALLOWED: &'static str = "EME2000, GCRF or ICRF";

    fn from_ccsds(value: &str) -> Option<Self> {
        match value.trim().to_ascii_uppercase().as_str() {
            "EME2000" => Some(Self::Eme2000),
            "GCRF" => Some(Self::Gcrf),
            "ICRF" => Some(Self::Icrf),
            _ => None,
        }
    }
}

/// Header keywords besides `CCSDS_OEM_VERS`.
const HEADER_KEYWORDS: [&str; 3] = ["CREATION_DATE", "ORIGINATOR", "MESSAGE_ID"];

/// Metadata keywords.
const METADATA_KEYWORDS: [&str; 12] = [
    "OBJECT_NAME",
    "OBJECT_ID",
    "CENTER_NAME",
    "REF_FRAME",
    "REF_FRAME_EPOCH",
    "TIME_SYSTEM",
    "START_TIME",
    "USEABLE_START_TIME",
    "USEABLE_STOP_TIME",
    "STOP_TIME",
    "INTERPOLATION",
    "INTERPOLATION_DEGREE",
];

/// Mandatory metadata keywords.
const METADATA_MANDATORY: [&str; 7] = [
    "OBJECT_NAME",
    "OBJECT_ID",
    "CENTER_NAME",
    "REF_FRAME",
    "TIME_SYSTEM",
    "START_TIME",
    "STOP_TIME",
];

/// What a data line is, for error messages.
const DATA_LINE: &str =
    "epoch x y z [km] vx vy vz [km/s], optionally ax ay az [km/s²], separated by spaces";

/// The largest `INTERPOLATION_DEGREE` read (higher degrees ring and no producer writes them).
pub const MAX_INTERPOLATION_DEGREE: usize = 32;

/// One OEM segment: its metadata and its states.
#[derive(Clone, Debug)]
pub struct OemSegment {
    /// The file.
    pub file: String,
    /// The line of its `META_START`.
    pub line: usize,
    /// `OBJECT_NAME`.
    pub object_name: String,
    /// `OBJECT_ID`.
    pub object_id: String,
    /// `REF_FRAME`.
    pub frame: OemFrame,
    /// `TIME_SYSTEM`.
    pub time_system: TimeSystem,
    /// `START_TIME`.
    pub start: Epoch,
    /// `STOP_TIME`.
    pub stop: Epoch,
    /// `USEABLE_START_TIME`, if given.
    pub useable_start: Option<Epoch>,
    /// `USEABLE_STOP_TIME`, if given.
    pub useable_stop: Option<Epoch>,
    /// `INTERPOLATION` and `INTERPOLATION_DEGREE`, if given.
    pub interpolation: Option<Interpolation>,
    /// The line of `INTERPOLATION_DEGREE` (or `INTERPOLATION`).
    interpolation_line: Option<usize>,
    /// The epoch of the first sample; `t_s` counts from it.
    reference: Epoch,
    /// Sample times \[s\] from `reference`, strictly increasing.
    t_s: Vec<f64>,
    /// Samples `[x, y, z, vx, vy, vz]` in `frame` \[m, m/s\].
    states: Vec<[f64; 6]>,
    /// Accelerations \[m/s²\], when every sample gives them.
    accelerations: Option<Vec<[f64; 3]>>,
}

impl OemSegment {
    /// The number of samples.
    pub fn samples(&self) -> usize {
        self.t_s.len()
    }

    /// The instants the segment gives states for: from `max(START_TIME, USEABLE_START_TIME, first
    /// sample)` to `min(STOP_TIME, USEABLE_STOP_TIME, last sample)`.
    pub fn window(&self) -> (Epoch, Epoch) {
        let first = self.reference;
        let last = self.at(self.t_s[self.t_s.len() - 1]);
        let lo = [Some(self.start), self.useable_start, Some(first)]
            .into_iter()
            .flatten()
            .fold(first, |a, b| if b > a { b } else { a });
        let hi = [Some(self.stop), self.useable_stop, Some(last)]
            .into_iter()
            .flatten()
            .fold(last, |a, b| if b < a { b } else { a });
        (lo, hi)
    }

    fn at(&self, t_s: f64) -> Epoch {
        after_s(self.reference, t_s)
    }

    fn window_text(&self) -> String {
        let (lo, hi) = self.window();
        format!(
            "{} to {} ({} line {})",
            utc_text(lo),
            utc_text(hi),
            self.file,
            self.line
        )
    }

    /// The state at `epoch` in the segment's own frame \[m, m/s\]; `epoch` is inside the window.
    fn state_in_frame(&self, epoch: Epoch) -> Result<[f64; 6], OrbitFileError> {
        let tau = elapsed_s(epoch, self.reference);
        let Some(method) = self.interpolation else {
            // No method: only the samples themselves.
            if let Some(i) = self.t_s.iter().position(|&t| (t - tau).abs() < 1e-9) {
                return Ok(self.states[i]);
            }
            return Err(OrbitFileError::missing(
                &self.file,
                Some(self.line),
                "OEM segment metadata",
                "INTERPOLATION",
                Some(format!(
                    "a state between the samples (epoch {}; the segment gives no interpolation, \
                     so only its sample epochs can be used)",
                    utc_text(epoch)
                )),
            ));
        };
        let n = method.samples();
        let total = self.t_s.len();
        if n > total {
            let (keyword, allowed) = match method {
                Interpolation::Lagrange { .. } => (
                    "INTERPOLATION_DEGREE",
                    format!("at most {} for LAGRANGE with {total} samples", total - 1),
                ),
                Interpolation::Hermite { .. } => (
                    "INTERPOLATION_DEGREE",
                    format!("at most {} for HERMITE with {total} samples", 2 * total - 1),
                ),
            };
            let degree = match method {
                Interpolation::Lagrange { degree } | Interpolation::Hermite { degree } => degree,
            };
            return Err(OrbitFileError::invalid(
                &self.file,
                self.interpolation_line,
                keyword,
                &degree.to_string(),
                format!("needs {n} samples, the segment has {total}"),
                allowed,
            ));
        }
        let below = self.t_s.partition_point(|&t| t <= tau);
        let first = below.saturating_sub(n / 2).min(total - n);
        let t = &self.t_s[first..first + n];
        let column =
            |k: usize| -> Vec<f64> { self.states[first..first + n].iter().map(|s| s[k]).collect() };
        let mut out = [0.0; 6];
        match method {
            Interpolation::Lagrange { .. } => {
                for (k, o) in out.iter_mut().enumerate() {
                    *o = lagrange(t, &column(k), tau);
                }
            }
            Interpolation::Hermite { .. } => {
                for k in 0..3 {
                    let (p, dp) = hermite(t, &column(k), &column(k + 3), tau);
                    out[k] = p;
                    out[k + 3] = match &self.accelerations {
                        Some(acc) => {
                            let a: Vec<f64> = acc[first..first + n].iter().map(|a| a[k]).collect();
                            hermite(t, &column(k + 3), &a, tau).0
                        }
                        None => dp,
                    };
                }
            }
        }
        Ok(out)
    }
}

/// One object of one or more OEM files: its segments in file order.
#[derive(Clone, Debug)]
pub struct OemObject {
    /// `OBJECT_NAME` of its first segment.
    pub name: String,
    /// `OBJECT_ID`.
    pub id: String,
    /// Its segments, in file order.
    pub segments: Vec<OemSegment>,
}

impl OemObject {
    /// The first instant any segment gives a state for.
    pub fn start(&self) -> Epoch {
        self.segments
            .iter()
            .map(|s| s.window().0)
            .fold(None, |a: Option<Epoch>, b| {
                Some(a.map_or(b, |a| if b < a { b } else { a }))
            })
            .expect("an object has a segment")
    }

    /// The last instant any segment gives a state for.
    pub fn stop(&self) -> Epoch {
        self.segments
            .iter()
            .map(|s| s.window().1)
            .fold(None, |a: Option<Epoch>, b| {
                Some(a.map_or(b, |a| if b > a { b } else { a }))
            })
            .expect("an object has a segment")
    }

    /// The files the object's segments come from, in order, each once.
    fn files(&self) -> String {
        let mut files: Vec<&str> = Vec::new();
        for s in &self.segments {
            if !files.contains(&s.file.as_str()) {
                files.push(&s.file);
            }
        }
        files.join(", ")
    }

    /// The state at `epoch` in EME2000 (m, m/s): interpolated in the first segment whose window holds
    /// `epoch` with the segment's own method and degree, then rotated to EME2000 if the segment's frame
    /// is GCRF or ICRF. An epoch outside every window is an error listing them.
    pub fn state_eme2000(&self, epoch: Epoch) -> Result<CartesianState, OrbitFileError> {
        let Some(segment) = self.segments.iter().find(|s| {
            let (lo, hi) = s.window();
            lo <= epoch && epoch <= hi
        }) else {
            return Err(OrbitFileError::EpochOutside {
                file: self.files(),
                object: format!("{} ({})", self.name, self.id),
                epoch: utc_text(epoch),
                allowed: self
                    .segments
                    .iter()
                    .map(OemSegment::window_text)
                    .collect::<Vec<_>>()
                    .join("; "),
            });
        };
        let s = segment.state_in_frame(epoch)?;
        let state = CartesianState::new(
            Vector3::new(s[0], s[1], s[2]),
            Vector3::new(s[3], s[4], s[5]),
        );
        Ok(match segment.frame {
            OemFrame::Eme2000 => state,
            OemFrame::Gcrf | OemFrame::Icrf => gcrf_to_eme2000(&state),
        })
    }
}

/// The objects of several OEM files, in order of first appearance (file order, then segment order);
/// segments of one `OBJECT_ID` merge, across files too.
pub fn read_oem_files<P: AsRef<Path>>(paths: &[P]) -> Result<Vec<OemObject>, OrbitFileError> {
    let mut segments = Vec::new();
    for path in paths {
        let path = path.as_ref();
        let text = super::read_text(path)?;
        segments.extend(parse_segments(&text, &path.display().to_string())?);
    }
    Ok(merge(segments))
}

/// The objects of one OEM's text; `file` names it in errors.
pub fn parse_oem(text: &str, file: &str) -> Result<Vec<OemObject>, OrbitFileError> {
    Ok(merge(parse_segments(text, file)?))
}

fn merge(segments: Vec<OemSegment>) -> Vec<OemObject> {
    let mut objects: Vec<OemObject> = Vec::new();
    for segment in segments {
        match objects.iter_mut().find(|o| o.id == segment.object_id) {
            Some(object) => object.segments.push(segment),
            None => objects.push(OemObject {
                name: segment.object_name.clone(),
                id: segment.object_id.clone(),
                segments: vec![segment],
            }),
        }
    }
    objects
}

/// Where the parser is.
enum Section {
    Header,
    Metadata {
        line: usize,
        fields: Vec<(String, String, usize)>,
    },
    Data(Box<OemSegment>),
    Covariance {
        line: usize,
    },
    AfterCovariance,
}

fn parse_segments(text: &str, file: &str) -> Result<Vec<OemSegment>, OrbitFileError> {
    let invalid = |line: usize, keyword: &str, value: &str, problem: &str, allowed: &str| {
        OrbitFileError::invalid(
            file,
            Some(line),
            keyword,
            value,
            problem.to_string(),
            allowed.to_string(),
        )
    };
    let mut version_seen = false;
    let mut header: Vec<&str> = Vec::new();
    let mut section = Section::Header;
    let mut segments = Vec::new();
    for (line, kind) in kvn::lines(text) {
        if matches!(kind, Kvn::Blank)
            || (matches!(kind, Kvn::Comment) && !matches!(section, Section::Covariance { .. }))
        {
            continue;
        }
        section = match section {
            Section::Header => match kind {
                Kvn::Pair("CCSDS_OEM_VERS", v) if !version_seen => {
                    if !matches!(v, "2.0" | "3.0") {
                        return Err(invalid(
                            line,
                            "CCSDS_OEM_VERS",
                            v,
                            "an OEM version satflock does not read",
                            "2.0 or 3.0",
                        ));
                    }
                    version_seen = true;
                    Section::Header
                }
                _ if !version_seen => {
                    return Err(invalid(
                        line,
                        "line",
                        &kvn_text(kind),
                        "the first keyword of an OEM must be CCSDS_OEM_VERS",
                        "`CCSDS_OEM_VERS = 2.0` or `3.0` first",
                    ));
                }
                Kvn::Pair(key, value) if HEADER_KEYWORDS.contains(&key) => {
                    if header.contains(&key) {
                        return Err(invalid(
                            line,
                            key,
                            value,
                            "given twice in the header",
                            "each header keyword once",
                        ));
                    }
                    header.push(key);
                    Section::Header
                }
                Kvn::Other("META_START") => {
                    for key in ["CREATION_DATE", "ORIGINATOR"] {
                        if !header.contains(&key) {
                            return Err(OrbitFileError::missing(
                                file,
                                Some(line),
                                "OEM header",
                                key,
                                None,
                            ));
                        }
                    }
                    Section::Metadata {
                        line,
                        fields: Vec::new(),
                    }
                }
                other => {
                    return Err(invalid(
                        line,
                        "header",
                        &kvn_text(other),
                        "not an OEM header line",
                        "CREATION_DATE, ORIGINATOR, MESSAGE_ID, COMMENT, then META_START",
                    ));
                }
            },
            Section::Metadata {
                line: start,
                mut fields,
            } => match kind {
                Kvn::Pair(key, value) if METADATA_KEYWORDS.contains(&key) => {
                    if fields.iter().any(|(k, ..)| k == key) {
                        return Err(invalid(
                            line,
                            key,
                            value,
                            "given twice in one segment's metadata",
                            "each metadata keyword once",
                        ));
                    }
                    fields.push((key.to_string(), value.to_string(), line));
                    Section::Metadata {
                        line: start,
                        fields,
                    }
                }
                Kvn::Other("META_STOP") => Section::Data(Box::new(metadata(file, start, &fields)?)),
                Kvn::Pair(key, value) => {
                    return Err(invalid(
                        line,
                        key,
                        value,
                        "not an OEM metadata keyword",
                        &METADATA_KEYWORDS.join(", "),
                    ));
                }
                other => {
                    return Err(invalid(
                        line,
                        "metadata",
                        &kvn_text(other),
                        "not a `KEYWORD = value` line",
                        "metadata keywords and COMMENT lines, closed by META_STOP",
                    ));
                }
            },
            Section::Data(mut segment) => match kind {
                Kvn::Other("META_START") => {
                    segments.push(finish(*segment)?);
                    Section::Metadata {
                        line,
                        fields: Vec::new(),
                    }
                }
                Kvn::Other("COVARIANCE_START") => {
                    segments.push(finish(*segment)?);
                    Section::Covariance { line }
                }
                Kvn::Other(data) => {
                    data_line(&mut segment, line, data)?;
                    Section::Data(segment)
                }
                other => {
                    return Err(invalid(
                        line,
                        "data line",
                        &kvn_text(other),
                        "a keyword among the data lines",
                        DATA_LINE,
                    ));
                }
            },
            Section::Covariance { line: start } => match kind {
                Kvn::Other("COVARIANCE_STOP") => Section::AfterCovariance,
                _ => Section::Covariance { line: start },
            },
            Section::AfterCovariance => match kind {
                Kvn::Other("META_START") => Section::Metadata {
                    line,
                    fields: Vec::new(),
                },
                other => {
                    return Err(invalid(
                        line,
                        "line",
                        &kvn_text(other),
                        "after a covariance block",
                        "META_START (a new segment), COMMENT lines or the end of the file",
                    ));
                }
            },
        };
    }
    match section {
        Section::Header => Err(OrbitFileError::invalid(
            file,
            None,
            "structure",
            "",
            if version_seen { "no segment (no META_START)" } else { "no CCSDS_OEM_VERS: not an OEM" },
            "an OEM in KVN: CCSDS_OEM_VERS, the header, then segments of metadata (META_START … META_STOP) and data lines",
        )),
        Section::Metadata { line, .. } => Err(invalid(line, "META_START", "", "metadata never closed by META_STOP", "META_START … META_STOP")),
        Section::Covariance { line } => Err(invalid(line, "COVARIANCE_START", "", "never closed by COVARIANCE_STOP", "COVARIANCE_START … COVARIANCE_STOP")),
        Section::Data(segment) => {
            segments.push(finish(*segment)?);
            Ok(segments)
        }
        Section::AfterCovariance => Ok(segments),
    }
}

/// A line's text again, for messages.
fn kvn_text(kind: Kvn<'_>) -> String {
    match kind {
        Kvn::Blank => String::new(),
        Kvn::Comment => "COMMENT".into(),
        Kvn::Pair(k, v) => format!("{k} = {v}"),
        Kvn::Other(o) => o.to_string(),
    }
}

/// A segment (with no samples yet) from its metadata.
fn metadata(
    file: &str,
    start: usize,
    fields: &[(String, String, usize)],
) -> Result<OemSegment, OrbitFileError> {
    let get = |key: &str| {
        fields
            .iter()
            .find(|(k, ..)| k == key)
            .map(|(_, v, l)| (v.as_str(), *l))
    };
    for key in METADATA_MANDATORY {
        if get(key).is_none() {
            return Err(OrbitFileError::missing(
                file,
                Some(start),
                "OEM segment metadata",
                key,
                None,
            ));
        }
    }
    let field = |key: &str| get(key).expect("mandatory keywords checked");
    let invalid = |key: &str, (value, line): (&str, usize), problem: &str, allowed: &str| {
        OrbitFileError::invalid(
            file,
            Some(line),
            key,
            value,
            problem.to_string(),
            allowed.to_string(),
        )
    };
    let center = field("CENTER_NAME");
    if !center.0.eq_ignore_ascii_case("EARTH") {
        return Err(invalid(
            "CENTER_NAME",
            center,
            "not a centre satflock converts",
            "EARTH",
        ));
    }
    let frame_field = field("REF_FRAME");
    let frame = OemFrame::from_ccsds(frame_field.0).ok_or_else(|| {
        invalid(
            "REF_FRAME",
            frame_field,
            "not a frame satflock converts",
            OemFrame::ALLOWED,
        )
    })?;
    let ts_field = field("TIME_SYSTEM");
    let time_system = TimeSystem::from_ccsds(ts_field.0).ok_or_else(|| {
        invalid(
            "TIME_SYSTEM",
            ts_field,
            "not a time system satflock converts",
            TimeSystem::ALLOWED,
        )
    })?;
    let epoch = |key: &str| -> Result<Option<Epoch>, OrbitFileError> {
        get(key)
            .map(|f| {
                parse_ccsds_epoch(f.0, time_system).map_err(|e| invalid(key, f, &e, EPOCH_FORMATS))
            })
            .transpose()
    };
    let start_time = epoch("START_TIME")?.expect("mandatory");
    let stop_time = epoch("STOP_TIME")?.expect("mandatory");
    if stop_time < start_time {
        return Err(invalid(
            "STOP_TIME",
            field("STOP_TIME"),
            "before START_TIME",
            "STOP_TIME >= START_TIME",
        ));
    }
    let useable_start = epoch("USEABLE_START_TIME")?;
    let useable_stop = epoch("USEABLE_STOP_TIME")?;
    for (key, value) in [
        ("USEABLE_START_TIME", useable_start),
        ("USEABLE_STOP_TIME", useable_stop),
    ] {
        if let Some(v) = value {
            if v < start_time || v > stop_time {
                return Err(invalid(
                    key,
                    field(key),
                    "outside START_TIME … STOP_TIME",
                    "an instant from START_TIME to STOP_TIME",
                ));
            }
        }
    }
    if let (Some(a), Some(b)) = (useable_start, useable_stop) {
        if b < a {
            return Err(invalid(
                "USEABLE_STOP_TIME",
                field("USEABLE_STOP_TIME"),
                "before USEABLE_START_TIME",
                "USEABLE_STOP_TIME >= USEABLE_START_TIME",
            ));
        }
    }
    let degree = get("INTERPOLATION_DEGREE")
        .map(|f| {
            f.0.parse::<usize>()
                .ok()
                .filter(|d| (1..=MAX_INTERPOLATION_DEGREE).contains(d))
                .ok_or_else(|| {
                    invalid(
                        "INTERPOLATION_DEGREE",
                        f,
                        "not a whole number in range",
                        &format!("1 to {MAX_INTERPOLATION_DEGREE}"),
                    )
                })
        })
        .transpose()?;
    let (interpolation, interpolation_line) = match get("INTERPOLATION") {
        None => (None, None),
        Some(f) => {
            let needs_degree = |name: &str| {
                degree.ok_or_else(|| {
                    OrbitFileError::missing(
                        file,
                        Some(start),
                        "OEM segment metadata",
                        "INTERPOLATION_DEGREE",
                        Some(format!("INTERPOLATION = {name}")),
                    )
                })
            };
            let method = match f.0.to_ascii_uppercase().as_str() {
                "LAGRANGE" => Interpolation::Lagrange {
                    degree: needs_degree("LAGRANGE")?,
                },
                "HERMITE" => Interpolation::Hermite {
                    degree: needs_degree("HERMITE")?,
                },
                "LINEAR" => Interpolation::Lagrange { degree: 1 },
                _ => {
                    return Err(invalid(
                        "INTERPOLATION",
                        f,
                        "not a method satflock interpolates with",
                        "LAGRANGE, HERMITE or LINEAR",
                    ))
                }
            };
            (
                Some(method),
                Some(get("INTERPOLATION_DEGREE").map_or(f.1, |d| d.1)),
            )
        }
    };
    Ok(OemSegment {
        file: file.to_string(),
        line: start,
        object_name: field("OBJECT_NAME").0.to_string(),
        object_id: field("OBJECT_ID").0.to_string(),
        frame,
        time_system,
        start: start_time,
        stop: stop_time,
        useable_start,
        useable_stop,
        interpolation,
        interpolation_line,
        reference: start_time,
        t_s: Vec::new(),
        states: Vec::new(),
        accelerations: Some(Vec::new()),
    })
}

/// Adds one data line's sample to `segment`.
fn data_line(segment: &mut OemSegment, line: usize, text: &str) -> Result<(), OrbitFileError> {
    let file = segment.file.clone();
    let invalid = |problem: String, allowed: &str| {
        OrbitFileError::invalid(
            &file,
            Some(line),
            "data line",
            text,
            problem,
            allowed.to_string(),
        )
    };
    let mut tokens = text.split_whitespace();
    let epoch_text = tokens.next().unwrap_or("");
    let epoch = parse_ccsds_epoch(epoch_text, segment.time_system)
        .map_err(|e| invalid(format!("its epoch `{epoch_text}` is {e}"), DATA_LINE))?;
    let numbers: Vec<f64> = tokens
        .map(|t| t.parse::<f64>().ok().filter(|v| v.is_finite()))
        .collect::<Option<_>>()
        .ok_or_else(|| invalid("a value is not a number".into(), DATA_LINE))?;
    if numbers.len() != 6 && numbers.len() != 9 {
        return Err(invalid(
            format!("{} numbers after the epoch", numbers.len()),
            DATA_LINE,
        ));
    }
    if epoch < segment.start || epoch > segment.stop {
        return Err(invalid(
            format!(
                "epoch {} is outside the segment's START_TIME … STOP_TIME",
                utc_text(epoch)
            ),
            &format!(
                "epochs from {} to {} (the metadata of line {})",
                utc_text(segment.start),
                utc_text(segment.stop),
                segment.line
            ),
        ));
    }
    if segment.t_s.is_empty() {
        segment.reference = epoch;
    }
    let t = elapsed_s(epoch, segment.reference);
    if let Some(&previous) = segment.t_s.last() {
        if t <= previous {
            return Err(invalid(
                format!(
                    "the time axis is not increasing: epoch {} after {}",
                    utc_text(epoch),
                    utc_text(segment.at(previous))
                ),
                "strictly increasing epochs within a segment",
            ));
        }
    }
    segment.t_s.push(t);
    let km = |v: f64| v * 1000.0;
    segment.states.push([
        km(numbers[0]),
        km(numbers[1]),
        km(numbers[2]),
        km(numbers[3]),
        km(numbers[4]),
        km(numbers[5]),
    ]);
    match (&mut segment.accelerations, numbers.len()) {
        (Some(acc), 9) => acc.push([km(numbers[6]), km(numbers[7]), km(numbers[8])]),
        (acc, _) => *acc = None,
    }
    Ok(())
}

/// Checks a segment whose data lines are all read.
fn finish(segment: OemSegment) -> Result<OemSegment, OrbitFileError> {
    if segment.t_s.is_empty() {
        return Err(OrbitFileError::invalid(
            &segment.file,
            Some(segment.line),
            "META_START",
            &segment.object_id,
            "a segment with no data line",
            DATA_LINE,
        ));
    }
    Ok(segment)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A UTC file across the leap second at the end of 2016: 23:59:58, 23:59:59, 00:00:00 and
    /// 00:00:01 are 0, 1, 3 and 4 SI seconds apart, so samples on a straight line in SI seconds
    /// interpolate exactly (counting UTC clock seconds would bend the line).
    #[test]
    fn a_utc_file_interpolates_across_a_leap_second() {
        let text = "CCSDS_OEM_VERS = 2.0\nCREATION_DATE = 2017-01-01T00:00:00\nORIGINATOR = test\n\
            META_START\nOBJECT_NAME = A\nOBJECT_ID = A\nCENTER_NAME = EARTH\nREF_FRAME = EME2000\n\
            TIME_SYSTEM = UTC\nSTART_TIME = 2016-12-31T23:59:58\nSTOP_TIME = 2017-01-01T00:00:01\n\
            INTERPOLATION = LAGRANGE\nINTERPOLATION_DEGREE = 3\nMETA_STOP\n\
            2016-12-31T23:59:58 7000 0 0 0 7 0\n2016-12-31T23:59:59 7000 7 0 0 7 0\n\
            2017-01-01T00:00:00 7000 21 0 0 7 0\n2017-01-01T00:00:01 7000 28 0 0 7 0\n";
        let objects = parse_oem(text, "leap.oem").unwrap();
        let at = after_s(
            parse_ccsds_epoch("2016-12-31T23:59:59", TimeSystem::Utc).unwrap(),
            1.5,
        );
        let s = objects[0].state_eme2000(at).unwrap();
        assert!(
            (s.position_m.y - 17_500.0).abs() < 1e-6,
            "{}",
            s.position_m.y
        );
        assert!((s.velocity_mps.y - 7_000.0).abs() < 1e-9);
    }

    #[test]
    fn structure_errors_name_the_line() {
        let head = "CCSDS_OEM_VERS = 2.0\nCREATION_DATE = 2017-01-01T00:00:00\nORIGINATOR = test\n";
        let meta = "META_START\nOBJECT_NAME = A\nOBJECT_ID = A\nCENTER_NAME = EARTH\nREF_FRAME = EME2000\n\
            TIME_SYSTEM = UTC\nSTART_TIME = 2017-01-01T00:00:00\nSTOP_TIME = 2017-01-01T00:01:00\nMETA_STOP\n";
        let data = "2017-01-01T00:00:00 7000 0 0 0 7 0\n";
        let error = |text: &str| parse_oem(text, "x.oem").unwrap_err().to_string();
        assert!(error("CCSDS_OEM_VERS = 1.0\n").contains("x.oem line 1: CCSDS_OEM_VERS = `1.0`"));
        assert!(
            error(&format!("{head}{}", meta.replace("OBJECT_ID = A\n", "")))
                .contains("x.oem line 4: OEM segment metadata has no OBJECT_ID")
        );
        assert!(error(&format!(
            "{head}{}",
            meta.replace("META_STOP", "SPEED = 1\nMETA_STOP")
        ))
        .contains("SPEED = `1`: not an OEM metadata keyword"));
        assert!(
            error(&format!("{head}{meta}2017-01-01T00:00:00 7000 0 0 0 7\n"))
                .contains("x.oem line 13: data line")
        );
        assert!(
            error(&format!("{head}{meta}2017-01-01T00:02:00 7000 0 0 0 7 0\n"))
                .contains("outside the segment's START_TIME")
        );
        assert!(error(&format!("{head}{meta}{data}COVARIANCE_START\n"))
            .contains("never closed by COVARIANCE_STOP"));
        let ok = parse_oem(
            &format!("{head}{meta}{data}COVARIANCE_START\nEPOCH = x\n1 2\nCOVARIANCE_STOP\n"),
            "x.oem",
        )
        .unwrap();
        // No INTERPOLATION: the sample itself, and nothing between samples.
        let t = parse_ccsds_epoch("2017-01-01T00:00:00", TimeSystem::Utc).unwrap();
        assert_eq!(ok[0].state_eme2000(t).unwrap().position_m.x, 7.0e6);
    }
}
