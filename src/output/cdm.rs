//! CCSDS Conjunction Data Messages (CDM, 508.0-B-1, keyword = value notation): one file per encounter
//! of a run's conjunction table ([`super::conjunctions`]).
//!
//! Each message holds, in the standard's order, every keyword 508.0-B-1 makes mandatory: the header
//! (`CCSDS_CDM_VERS = 1.0`, `CREATION_DATE`, `ORIGINATOR`, `MESSAGE_ID`), the relative metadata and data
//! (`TCA` in UTC, `MISS_DISTANCE`, and the optional `RELATIVE_SPEED`, `RELATIVE_POSITION_R/T/N`,
//! `RELATIVE_VELOCITY_R/T/N` in the primary's RTN frame), then for `OBJECT1` (the primary) and `OBJECT2`
//! the metadata (`OBJECT`, `OBJECT_DESIGNATOR`, `CATALOG_NAME`, `OBJECT_NAME`,
//! `INTERNATIONAL_DESIGNATOR`, `OBJECT_TYPE`, `EPHEMERIS_NAME`, `COVARIANCE_METHOD`, `MANEUVERABLE`,
//! `REF_FRAME = EME2000`), the state at TCA (`X` … `Z_DOT`, km and km/s) and the 21 mandatory terms of
//! the RTN covariance (`CR_R` … `CNDOT_NDOT`).
//!
//! Objects are named as in the OEM export (`SAT-00007`, designator `SATFLOCK-00007`); a threat or an
//! obstacle is `THREAT-00000` / `OBSTACLE-00000` (designators `SATFLOCK-THREAT-00000` …). The
//! catalogue is `SATFLOCK` (the run's own ids) and the international designator `UNKNOWN`.
//!
//! **Covariance.** The states are the simulation's truth, not an orbit determination. A satellite's
//! covariance is the diagonal of its navigation noise (`[sensing] position_noise_m²` on `CR_R`, `CT_T`,
//! `CN_N`, `velocity_noise_mps²` on `CRDOT_RDOT`, `CTDOT_TDOT`, `CNDOT_NDOT`; the noise is independent
//! per Hill axis with one sigma, so it is diagonal in RTN too), all zero without navigation noise;
//! `COVARIANCE_METHOD = DEFAULT`. A threat's or obstacle's covariance is zero (its path is given). Each
//! object's `COMMENT` lines say so.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::conjunctions::{encounter_of_row, id_column_names, value_column_names};
use super::export::{create_dir, write_whole, ExportError};
use super::run_data::{RunData, RunDataError};
use crate::conjunction::{Encounter, Secondary};
use crate::time::{self, Epoch};

/// `CCSDS_CDM_VERS`.
pub const CDM_VERSION: &str = "1.0";

/// The folder of CDM files in a run directory (`satflock export cdm`).
pub const RUN_DIR_NAME: &str = "cdm";

/// Which encounters to write.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Selection {
    /// Every encounter.
    All,
    /// The `k` with the smallest miss distances (the earliest among ties).
    Top(usize),
    /// Those with a miss distance below this \[m\].
    Below(f64),
}

/// `OBJECT_NAME` and `OBJECT_DESIGNATOR` of a primary satellite or a secondary object.
fn names(object: Option<Secondary>, primary: usize) -> (String, String) {
    match object {
        None | Some(Secondary::Satellite(_)) => {
            let id = object.map_or(primary, |s| s.index());
            (format!("SAT-{id:05}"), format!("SATFLOCK-{id:05}"))
        }
        Some(Secondary::Threat(k)) => (format!("THREAT-{k:05}"), format!("SATFLOCK-THREAT-{k:05}")),
        Some(Secondary::Obstacle(k)) => (
            format!("OBSTACLE-{k:05}"),
            format!("SATFLOCK-OBSTACLE-{k:05}"),
        ),
    }
}

/// The file name of encounter `index` (from 1, the table's order): `00003-sat-00001-sat-00004.cdm`.
pub fn file_name(index: usize, e: &Encounter) -> String {
    let (primary, _) = names(None, e.primary);
    let (secondary, _) = names(Some(e.secondary), e.primary);
    format!(
        "{index:05}-{}-{}.cdm",
        primary.to_lowercase(),
        secondary.to_lowercase()
    )
}

/// What a message states beyond the encounter.
#[derive(Clone, Debug)]
pub struct CdmContext {
    /// `CREATION_DATE`.
    pub creation_date: Epoch,
    /// The instant of t = 0.
    pub epoch: Epoch,
    /// The scenario's name and seed, for `MESSAGE_ID` and a comment.
    pub scenario: String,
    /// The run's seed.
    pub seed: String,
    /// The satellites' navigation noise, one sigma per axis \[m\] and \[m/s\].
    pub sigma_m: f64,
    /// See `sigma_m`.
    pub sigma_mps: f64,
}

/// The KVN text of the CDM of encounter `index` (from 1).
pub fn to_kvn(e: &Encounter, index: usize, context: &CdmContext) -> String {
    let mut out = String::new();
    let mut line = |key: &str, value: &str| {
        let _ = if key == "COMMENT" {
            writeln!(out, "COMMENT {value}")
        } else {
            writeln!(out, "{key:<26} = {value}")
        };
    };
    line("CCSDS_CDM_VERS", CDM_VERSION);
    line(
        "COMMENT",
        &format!(
            "Written by satflock {} from the scenario `{}` (seed {}): encounter {index} of its conjunction table",
            env!("CARGO_PKG_VERSION"),
            context.scenario,
            context.seed
        ),
    );
    line("CREATION_DATE", &time::ccsds_utc(context.creation_date));
    line("ORIGINATOR", "SATFLOCK");
    line(
        "MESSAGE_ID",
        &format!(
            "SATFLOCK-{}-{}-{index:05}",
            context.scenario.replace(' ', "_"),
            context.seed
        ),
    );
    line(
        "COMMENT",
        "Relative position and velocity: the secondary's relative to the primary, in the primary's RTN frame (inertial velocities)",
    );
    line("TCA", &time::ccsds_utc(time::at(context.epoch, e.tca_s)));
    line("MISS_DISTANCE", &format!("{:.6} [m]", e.miss_distance_m));
    line(
        "RELATIVE_SPEED",
        &format!("{:.9} [m/s]", e.relative_speed_mps),
    );
    for (axis, v) in ["R", "T", "N"].iter().zip(e.relative_position_rtn_m) {
        line(&format!("RELATIVE_POSITION_{axis}"), &format!("{v:.6} [m]"));
    }
    for (axis, v) in ["R", "T", "N"].iter().zip(e.relative_velocity_rtn_mps) {
        line(
            &format!("RELATIVE_VELOCITY_{axis}"),
            &format!("{v:.9} [m/s]"),
        );
    }
    for (k, (object, state)) in [
        (None, e.primary_eme2000),
        (Some(e.secondary), e.secondary_eme2000),
    ]
    .into_iter()
    .enumerate()
    {
        let (name, designator) = names(object, e.primary);
        let satellite = !matches!(object, Some(Secondary::Threat(_) | Secondary::Obstacle(_)));
        let (sp, sv) = if satellite {
            (context.sigma_m, context.sigma_mps)
        } else {
            (0.0, 0.0)
        };
        line(
            "COMMENT",
            if satellite {
                "State: the simulation's truth at TCA. Covariance: the diagonal of the satellite's navigation noise ([sensing] position_noise_m and velocity_noise_mps squared; zero without noise), not an orbit determination"
            } else {
                "State: the object's given straight-line path in the LVLH frame, at TCA. Covariance: zero (the path is given, not estimated)"
            },
        );
        line("OBJECT", &format!("OBJECT{}", k + 1));
        line("OBJECT_DESIGNATOR", &designator);
        line("CATALOG_NAME", "SATFLOCK");
        line("OBJECT_NAME", &name);
        line("INTERNATIONAL_DESIGNATOR", "UNKNOWN");
        line("OBJECT_TYPE", if satellite { "PAYLOAD" } else { "UNKNOWN" });
        line("EPHEMERIS_NAME", "NONE");
        line("COVARIANCE_METHOD", "DEFAULT");
        line("MANEUVERABLE", if satellite { "YES" } else { "NO" });
        line("REF_FRAME", super::frames::INERTIAL_FRAME);
        for (key, v) in ["X", "Y", "Z"].iter().zip(&state[..3]) {
            line(key, &format!("{:.9} [km]", v / 1000.0));
        }
        for (key, v) in ["X_DOT", "Y_DOT", "Z_DOT"].iter().zip(&state[3..]) {
            line(key, &format!("{:.12} [km/s]", v / 1000.0));
        }
        let (p2, v2) = (sp * sp, sv * sv);
        let terms: [(&str, f64, &str); 21] = [
            ("CR_R", p2, "m**2"),
            ("CT_R", 0.0, "m**2"),
            ("CT_T", p2, "m**2"),
            ("CN_R", 0.0, "m**2"),
            ("CN_T", 0.0, "m**2"),
            ("CN_N", p2, "m**2"),
            ("CRDOT_R", 0.0, "m**2/s"),
            ("CRDOT_T", 0.0, "m**2/s"),
            ("CRDOT_N", 0.0, "m**2/s"),
            ("CRDOT_RDOT", v2, "m**2/s**2"),
            ("CTDOT_R", 0.0, "m**2/s"),
            ("CTDOT_T", 0.0, "m**2/s"),
            ("CTDOT_N", 0.0, "m**2/s"),
            ("CTDOT_RDOT", 0.0, "m**2/s**2"),
            ("CTDOT_TDOT", v2, "m**2/s**2"),
            ("CNDOT_R", 0.0, "m**2/s"),
            ("CNDOT_T", 0.0, "m**2/s"),
            ("CNDOT_N", 0.0, "m**2/s"),
            ("CNDOT_RDOT", 0.0, "m**2/s**2"),
            ("CNDOT_TDOT", 0.0, "m**2/s**2"),
            ("CNDOT_NDOT", v2, "m**2/s**2"),
        ];
        for (key, v, unit) in terms {
            line(key, &format!("{v:e} [{unit}]"));
        }
    }
    out
}

/// The encounters of a run's conjunction table, in its order.
///
/// # Errors
/// [`ExportError::Input`] when the run has no conjunction table or a row names no secondary.
pub fn run_encounters(run: &RunData) -> Result<Vec<Encounter>, ExportError> {
    let table = run.conjunctions.as_ref().ok_or_else(|| {
        ExportError::Input(RunDataError {
            path: run.dir.display().to_string(),
            message: "holds neither conjunctions.csv nor conjunctions.parquet (the run needs a \
                      [conjunctions] section with threshold_m)"
                .into(),
        })
    })?;
    let column = |name: &str| table.column(name).unwrap_or_default();
    let tca = column("tca_s");
    let ids = id_column_names().map(column);
    let values = value_column_names().map(column);
    (0..table.rows())
        .map(|row| {
            encounter_of_row(
                tca[row],
                std::array::from_fn(|k| ids[k][row]),
                &std::array::from_fn(|k| values[k][row]),
            )
            .ok_or_else(|| {
                ExportError::Input(RunDataError {
                    path: run.dir.display().to_string(),
                    message: format!(
                        "conjunction row {}: exactly one of `secondary`, `secondary_threat`, \
                         `secondary_obstacle` must hold an id, and `primary` one",
                        row + 1
                    ),
                })
            })
        })
        .collect()
}

/// Writes one CDM per selected encounter of `run` into `dir` (created if needed); returns the files.
///
/// # Errors
/// Those of [`run_encounters`]; [`ExportError::Output`] when a file cannot be written.
pub fn write_run_cdm(
    run: &RunData,
    dir: &Path,
    selection: Selection,
    creation_date: Epoch,
) -> Result<Vec<PathBuf>, ExportError> {
    let encounters = run_encounters(run)?;
    let mut chosen: Vec<usize> = (0..encounters.len()).collect();
    match selection {
        Selection::All => {}
        Selection::Below(m) => chosen.retain(|&k| encounters[k].miss_distance_m < m),
        Selection::Top(k) => {
            chosen.sort_by(|&a, &b| {
                let (x, y) = (&encounters[a], &encounters[b]);
                x.miss_distance_m
                    .total_cmp(&y.miss_distance_m)
                    .then(x.tca_s.total_cmp(&y.tca_s))
                    .then(a.cmp(&b))
            });
            chosen.truncate(k);
            chosen.sort_unstable();
        }
    }
    let field = |key: &str| {
        run.summary
            .get(key)
            .map(|v| v.as_str().map_or_else(|| v.to_string(), str::to_string))
            .unwrap_or_else(|| "?".into())
    };
    let sigma = |key: &str| {
        run.summary
            .pointer(&format!("/conjunctions/{key}"))
            .and_then(serde_json::Value::as_f64)
            .unwrap_or(0.0)
    };
    let context = CdmContext {
        creation_date,
        epoch: run.epoch,
        scenario: field("scenario"),
        seed: field("seed"),
        sigma_m: sigma("position_sigma_m"),
        sigma_mps: sigma("velocity_sigma_mps"),
    };
    create_dir(dir)?;
    let mut written = Vec::with_capacity(chosen.len());
    for k in chosen {
        let path = dir.join(file_name(k + 1, &encounters[k]));
        write_whole(&path, to_kvn(&encounters[k], k + 1, &context).as_bytes())?;
        written.push(path);
    }
    Ok(written)
}
