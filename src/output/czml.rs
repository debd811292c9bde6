//! CZML, the JSON scene format of CesiumJS: a run's satellites moving in 3-D on the globe.
//!
//! The document is a JSON array: first the `document` packet (`id` `"document"`, `name`, `version`
//! `"1.0"`, a `description` saying what was kept, and the `clock`: the run's interval, looping, playing
//! the run in about [`PLAYBACK_S`] seconds), then one packet per satellite (`id` `sat-NNNNN`) with its
//! `availability`, a `point`, a `path` (see below) and its `position`: `epoch` (the run's t = 0),
//! `cartesian` `[t, x, y, z, …]` with t in seconds from the epoch and x, y, z in metres in the inertial
//! frame (`referenceFrame` [`frames::CZML_INERTIAL_FRAME`], Cesium's ICRF, which the engine's EME2000
//! meets to within a metre), interpolated by `LAGRANGE` of degree [`INTERPOLATION_DEGREE`].
//!
//! Decimation, so a large run stays a file a browser can load: at most [`CzmlOptions::max_satellites`]
//! satellites (evenly spaced among the run's indices) and at most [`CzmlOptions::max_samples`] samples
//! per satellite (every k-th recorded time, from the first). Paths (the trail behind each satellite) are
//! drawn by default only for at most [`PATHS_MAX_SATELLITES`] satellites. [`CzmlDecimation::describe`]
//! says what was kept; the document's `description` carries the same text.

use std::path::Path;

use serde_json::{json, Value};

use super::export::{write_whole, ExportError, InertialTrack};
use super::frames;
use super::run_data::RunData;
use crate::time;

/// The CZML file a run directory holds (`satflock export czml`).
pub const RUN_FILE: &str = "swarm.czml";

/// Default most satellites in a document.
pub const DEFAULT_MAX_SATELLITES: usize = 1000;

/// Default most samples per satellite.
pub const DEFAULT_MAX_SAMPLES: usize = 2000;

/// Paths are drawn by default for at most this many satellites.
pub const PATHS_MAX_SATELLITES: usize = 100;

/// Lagrange interpolation degree of the positions (lowered to the number of samples − 1).
pub const INTERPOLATION_DEGREE: usize = 5;

/// The clock's multiplier plays the whole run in about this many seconds of wall time \[s\].
pub const PLAYBACK_S: f64 = 60.0;

/// Colour of the satellites' points and paths (RGBA).
const COLOUR_RGBA: [u8; 4] = [255, 200, 40, 255];

/// What a CZML document keeps of a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CzmlOptions {
    /// Most satellites (>= 1), evenly spaced among the run's indices.
    pub max_satellites: usize,
    /// Most samples per satellite (>= 1): every k-th recorded time, with the smallest k that fits.
    pub max_samples: usize,
    /// Draw paths: `Some(true)` always, `Some(false)` never, `None` for at most
    /// [`PATHS_MAX_SATELLITES`] satellites.
    pub paths: Option<bool>,
}

impl Default for CzmlOptions {
    fn default() -> Self {
        Self {
            max_satellites: DEFAULT_MAX_SATELLITES,
            max_samples: DEFAULT_MAX_SAMPLES,
            paths: None,
        }
    }
}

/// What a document kept: the numbers behind its `description`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CzmlDecimation {
    /// Satellites in the run's trajectory.
    pub satellites_total: usize,
    /// Satellites in the document.
    pub satellites_kept: usize,
    /// Distinct recorded times in the run's trajectory.
    pub times_total: usize,
    /// Recorded times kept (samples of a satellite alive throughout).
    pub times_kept: usize,
    /// Every k-th recorded time was kept.
    pub every_kth_time: usize,
    /// Whether paths are drawn.
    pub paths: bool,
    /// The limits asked for.
    pub options: CzmlOptions,
}

impl CzmlDecimation {
    /// One sentence saying what was kept and how to keep more.
    pub fn describe(&self) -> String {
        let satellites = if self.satellites_kept < self.satellites_total {
            format!(
                "{} of {} satellites (evenly spaced indices; at most {}: `satflock export czml \
                 --max-satellites N` keeps more)",
                self.satellites_kept, self.satellites_total, self.options.max_satellites
            )
        } else {
            format!("all {} satellites", self.satellites_total)
        };
        let times = if self.every_kth_time > 1 {
            format!(
                "{} of {} recorded times (one in {}, from the first; at most {} samples per satellite: \
                 `--max-samples N` keeps more)",
                self.times_kept, self.times_total, self.every_kth_time, self.options.max_samples
            )
        } else {
            format!("all {} recorded times", self.times_total)
        };
        let paths = match (self.paths, self.options.paths) {
            (true, _) => "paths drawn".to_string(),
            (false, Some(false)) => "paths off".to_string(),
            (false, _) => format!(
                "paths off (more than {PATHS_MAX_SATELLITES} satellites; `--paths` draws them)"
            ),
        };
        format!("{satellites}, {times}, {paths}")
    }
}

/// The CZML packets of a run read back by [`RunData::read`], from its `trajectory.csv` inertial
/// columns, and what they kept.
pub fn czml_packets(
    run: &RunData,
    options: &CzmlOptions,
) -> Result<(Vec<Value>, CzmlDecimation), ExportError> {
    for (name, value) in [
        ("max_satellites", options.max_satellites),
        ("max_samples", options.max_samples),
    ] {
        if value == 0 {
            return Err(ExportError::Option {
                option: name.into(),
                message: "0 is out of range (allowed: >= 1)".into(),
            });
        }
    }
    let tracks = run.inertial_tracks()?;
    let mut times: Vec<f64> = tracks.iter().flat_map(|t| t.t_s.iter().copied()).collect();
    times.sort_by(f64::total_cmp);
    times.dedup();
    let every = times.len().div_ceil(options.max_samples).max(1);
    let kept = options.max_satellites.min(tracks.len());
    let chosen: Vec<&InertialTrack> = (0..kept)
        .map(|i| &tracks[i * tracks.len() / kept])
        .collect();
    let paths = options
        .paths
        .unwrap_or(chosen.len() <= PATHS_MAX_SATELLITES);
    let at = |t_s: f64| time::utc_iso(time::at(run.epoch, t_s));
    let scenario = run
        .summary
        .get("scenario")
        .and_then(Value::as_str)
        .unwrap_or("satflock run")
        .to_string();

    let mut packets = vec![Value::Null];
    let (mut first, mut last) = (f64::INFINITY, f64::NEG_INFINITY);
    let step_s = times.get(every).map_or(1.0, |&t| t - times[0]);
    for track in chosen {
        let mut cartesian = Vec::new();
        let mut span = (f64::INFINITY, f64::NEG_INFINITY);
        for (&t, s) in track.t_s.iter().zip(&track.states) {
            let index = times
                .binary_search_by(|x| x.total_cmp(&t))
                .expect("every track time is in the run's times");
            if index % every == 0 {
                cartesian.extend([t, s[0], s[1], s[2]]);
                span = (span.0.min(t), span.1.max(t));
            }
        }
        let samples = cartesian.len() / 4;
        if samples == 0 {
            continue;
        }
        first = first.min(span.0);
        last = last.max(span.1);
        let mut packet = json!({
            "id": format!("sat-{:05}", track.id),
            "name": format!("SAT-{:05}", track.id),
            "description": format!("Satellite {} of scenario `{scenario}`", track.id),
            "availability": format!("{}/{}", at(span.0), at(span.1)),
            "position": {
                "epoch": time::utc_iso(run.epoch),
                "referenceFrame": frames::CZML_INERTIAL_FRAME,
                "interpolationAlgorithm": "LAGRANGE",
                "interpolationDegree": INTERPOLATION_DEGREE.min(samples.saturating_sub(1)).max(1),
                "cartesian": cartesian,
            },
            "point": {"pixelSize": 5, "color": {"rgba": COLOUR_RGBA}},
        });
        if paths {
            packet["path"] = json!({
                "show": true,
                "width": 1,
                "leadTime": 0,
                "trailTime": span.1 - span.0,
                "resolution": step_s,
                "material": {"solidColor": {"color": {"rgba": COLOUR_RGBA}}},
            });
        }
        packets.push(packet);
    }
    let decimation = CzmlDecimation {
        satellites_total: tracks.len(),
        satellites_kept: packets.len() - 1,
        times_total: times.len(),
        times_kept: times.len().div_ceil(every),
        every_kth_time: every,
        paths,
        options: *options,
    };
    let interval = format!("{}/{}", at(first), at(last));
    packets[0] = json!({
        "id": "document",
        "name": scenario,
        "version": "1.0",
        "description": format!(
            "satflock run `{scenario}`, inertial positions ({}) in metres: {}.",
            frames::INERTIAL_FRAME,
            decimation.describe()
        ),
        "clock": {
            "interval": interval,
            "currentTime": at(first),
            "multiplier": ((last - first) / PLAYBACK_S).round().max(1.0),
            "range": "LOOP_STOP",
            "step": "SYSTEM_CLOCK_MULTIPLIER",
        },
    });
    Ok((packets, decimation))
}

/// Writes the CZML of a run (see [`czml_packets`]) to `path`; returns what it kept.
pub fn write_run_czml(
    run: &RunData,
    path: &Path,
    options: &CzmlOptions,
) -> Result<CzmlDecimation, ExportError> {
    let (packets, decimation) = czml_packets(run, options)?;
    let text = serde_json::to_string(&packets).expect("CZML packets serialise");
    write_whole(path, text.as_bytes())?;
    Ok(decimation)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::export::inertial_column_names;
    use crate::output::Table;

    /// A run of `n` satellites on circles of 7000 km, recorded at t = 0, 10, …, 10·(times − 1) s.
    fn run(n: usize, times: usize) -> RunData {
        let mut names = vec!["t_s".to_string(), "id".to_string()];
        names.extend(inertial_column_names());
        let mut columns = vec![Vec::new(); names.len()];
        for k in 0..times {
            for id in 0..n {
                let angle = k as f64 * 1e-3 + id as f64 * 1e-4;
                let row = [
                    10.0 * k as f64,
                    id as f64,
                    7e6 * angle.cos(),
                    7e6 * angle.sin(),
                    0.0,
                    -7.5e3 * angle.sin(),
                    7.5e3 * angle.cos(),
                    0.0,
                ];
                for (c, v) in columns.iter_mut().zip(row) {
                    c.push(v);
                }
            }
        }
        RunData {
            dir: "memory".into(),
            summary: json!({"scenario": "test"}),
            epoch: time::parse_epoch_utc(time::DEFAULT_EPOCH_UTC).unwrap(),
            metrics: Table::default(),
            trajectory: Some(Table::new(names, columns)),
            scene: Default::default(),
            conjunctions: None,
            n_satellites: n,
            trajectory_path: None,
            files: Vec::new(),
        }
    }

    #[test]
    fn paths_are_off_by_default_above_the_limit_and_on_when_asked() {
        let many = run(PATHS_MAX_SATELLITES + 1, 3);
        let (packets, kept) = czml_packets(&many, &CzmlOptions::default()).unwrap();
        assert!(!kept.paths && packets[1..].iter().all(|p| p.get("path").is_none()));
        assert!(kept.describe().contains("`--paths`"), "{}", kept.describe());
        let asked = CzmlOptions {
            paths: Some(true),
            ..CzmlOptions::default()
        };
        let (packets, kept) = czml_packets(&many, &asked).unwrap();
        assert!(kept.paths && packets[1..].iter().all(|p| p["path"].is_object()));
        let few = run(PATHS_MAX_SATELLITES, 3);
        assert!(czml_packets(&few, &CzmlOptions::default()).unwrap().1.paths);
    }

    #[test]
    fn decimation_keeps_evenly_spaced_satellites_and_every_kth_time() {
        let options = CzmlOptions {
            max_satellites: 4,
            max_samples: 5,
            paths: None,
        };
        let (packets, kept) = czml_packets(&run(10, 21), &options).unwrap();
        // 10 satellites → indices 0, 2, 5, 7; 21 times → one in 5: t = 0, 50, 100, 150, 200.
        let ids: Vec<&str> = packets[1..]
            .iter()
            .map(|p| p["id"].as_str().unwrap())
            .collect();
        assert_eq!(ids, ["sat-00000", "sat-00002", "sat-00005", "sat-00007"]);
        assert_eq!((kept.every_kth_time, kept.times_kept), (5, 5));
        let cartesian = packets[1]["position"]["cartesian"].as_array().unwrap();
        let times: Vec<f64> = cartesian
            .iter()
            .step_by(4)
            .map(|v| v.as_f64().unwrap())
            .collect();
        assert_eq!(times, [0.0, 50.0, 100.0, 150.0, 200.0]);
        assert!(czml_packets(
            &run(2, 2),
            &CzmlOptions {
                max_samples: 0,
                ..options
            }
        )
        .is_err());
    }
}
