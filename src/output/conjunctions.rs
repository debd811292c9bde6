//! The conjunction table of a run (`conjunctions.csv` or `conjunctions.parquet`, in the format of the
//! run's metrics table): one row per encounter ([`crate::conjunction::Encounter`]), in the order they
//! were found (segment by segment, each sorted by TCA, primary, secondary), written when the run ends.
//!
//! Columns: `tca_s` (s since the epoch), `tca_utc` (ISO 8601 UTC text), `primary` (satellite id),
//! `secondary` (satellite id; empty / null when the other object is a threat or obstacle),
//! `secondary_threat` and `secondary_obstacle` (the object's index in the scenario's `[[threats]]` /
//! `[[obstacles]]`, else empty / null), `miss_distance_m`, `relative_speed_mps`, the secondary's
//! position and inertial velocity relative to the primary in the primary's RTN frame
//! (`relative_r_rtn_m`, `relative_t_rtn_m`, `relative_n_rtn_m`, `relative_vr_rtn_mps`,
//! `relative_vt_rtn_mps`, `relative_vn_rtn_mps`), and both objects' states at TCA in EME2000
//! (`primary_x_eme2000_m` … `primary_vz_eme2000_mps`, `secondary_x_eme2000_m` …), from which the CDM
//! export writes its state vectors. Parquet fields carry `unit` and `frame` metadata (`RTN (primary)` or
//! `EME2000`), as the other tables do.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use arrow_array::{ArrayRef, Float64Array, RecordBatch, StringArray, UInt64Array};
use arrow_schema::{DataType, Field, Schema};
use parquet::arrow::ArrowWriter;
use parquet::file::properties::WriterProperties;

use super::export::{write_whole, ExportError};
use super::frames;
use super::parquet_recorder::RunMetadata;
use super::recorder::OutputFormat;
use crate::conjunction::{Encounter, Secondary};
use crate::time::{self, Epoch};

/// The table's name (`conjunctions.csv`, `conjunctions.parquet`).
pub const TABLE: &str = "conjunctions";

/// The frame name of the relative columns.
pub const RTN_FRAME: &str = "RTN (primary)";

/// The id columns: whole numbers, empty where the other object is of another kind.
const ID_COLUMNS: [&str; 4] = [
    "primary",
    "secondary",
    "secondary_threat",
    "secondary_obstacle",
];

/// The number columns after the ids, with their units and frames.
const VALUE_COLUMNS: [(&str, &str, Option<&str>); 20] = [
    ("miss_distance_m", "m", None),
    ("relative_speed_mps", "m/s", None),
    ("relative_r_rtn_m", "m", Some(RTN_FRAME)),
    ("relative_t_rtn_m", "m", Some(RTN_FRAME)),
    ("relative_n_rtn_m", "m", Some(RTN_FRAME)),
    ("relative_vr_rtn_mps", "m/s", Some(RTN_FRAME)),
    ("relative_vt_rtn_mps", "m/s", Some(RTN_FRAME)),
    ("relative_vn_rtn_mps", "m/s", Some(RTN_FRAME)),
    ("primary_x_eme2000_m", "m", Some(frames::INERTIAL_FRAME)),
    ("primary_y_eme2000_m", "m", Some(frames::INERTIAL_FRAME)),
    ("primary_z_eme2000_m", "m", Some(frames::INERTIAL_FRAME)),
    (
        "primary_vx_eme2000_mps",
        "m/s",
        Some(frames::INERTIAL_FRAME),
    ),
    (
        "primary_vy_eme2000_mps",
        "m/s",
        Some(frames::INERTIAL_FRAME),
    ),
    (
        "primary_vz_eme2000_mps",
        "m/s",
        Some(frames::INERTIAL_FRAME),
    ),
    ("secondary_x_eme2000_m", "m", Some(frames::INERTIAL_FRAME)),
    ("secondary_y_eme2000_m", "m", Some(frames::INERTIAL_FRAME)),
    ("secondary_z_eme2000_m", "m", Some(frames::INERTIAL_FRAME)),
    (
        "secondary_vx_eme2000_mps",
        "m/s",
        Some(frames::INERTIAL_FRAME),
    ),
    (
        "secondary_vy_eme2000_mps",
        "m/s",
        Some(frames::INERTIAL_FRAME),
    ),
    (
        "secondary_vz_eme2000_mps",
        "m/s",
        Some(frames::INERTIAL_FRAME),
    ),
];

/// An encounter's id cells: primary, and the secondary in the column of its kind.
fn ids(e: &Encounter) -> [Option<u64>; 4] {
    let (mut satellite, mut threat, mut obstacle) = (None, None, None);
    match e.secondary {
        Secondary::Satellite(k) => satellite = Some(k as u64),
        Secondary::Threat(k) => threat = Some(k as u64),
        Secondary::Obstacle(k) => obstacle = Some(k as u64),
    }
    [Some(e.primary as u64), satellite, threat, obstacle]
}

/// An encounter's number cells, in the order of [`VALUE_COLUMNS`].
fn values(e: &Encounter) -> [f64; 20] {
    let mut v = [0.0; 20];
    v[0] = e.miss_distance_m;
    v[1] = e.relative_speed_mps;
    v[2..5].copy_from_slice(&e.relative_position_rtn_m);
    v[5..8].copy_from_slice(&e.relative_velocity_rtn_mps);
    v[8..14].copy_from_slice(&e.primary_eme2000);
    v[14..20].copy_from_slice(&e.secondary_eme2000);
    v
}

/// The encounter of a row read back: `tca_s`, the four id cells (NaN where empty) and the values of
/// [`value_column_names`]; `None` unless exactly one secondary cell holds a whole number.
pub fn encounter_of_row(tca_s: f64, id_cells: [f64; 4], v: &[f64; 20]) -> Option<Encounter> {
    let whole = |x: f64| (x.is_finite() && x >= 0.0 && x.fract() == 0.0).then_some(x as usize);
    let primary = whole(id_cells[0])?;
    let secondary = match (whole(id_cells[1]), whole(id_cells[2]), whole(id_cells[3])) {
        (Some(k), None, None) => Secondary::Satellite(k),
        (None, Some(k), None) => Secondary::Threat(k),
        (None, None, Some(k)) => Secondary::Obstacle(k),
        _ => return None,
    };
    let three = |k: usize| [v[k], v[k + 1], v[k + 2]];
    let six = |k: usize| [v[k], v[k + 1], v[k + 2], v[k + 3], v[k + 4], v[k + 5]];
    Some(Encounter {
        tca_s,
        primary,
        secondary,
        miss_distance_m: v[0],
        relative_speed_mps: v[1],
        relative_position_rtn_m: three(2),
        relative_velocity_rtn_mps: three(5),
        primary_eme2000: six(8),
        secondary_eme2000: six(14),
    })
}

/// The names of the number columns after the ids, in file order.
pub fn value_column_names() -> [&'static str; 20] {
    VALUE_COLUMNS.map(|c| c.0)
}

/// The names of the id columns, in file order.
pub fn id_column_names() -> [&'static str; 4] {
    ID_COLUMNS
}

/// Writes the table into `dir` in `format` (the whole file at once); returns its path.
///
/// # Errors
/// [`ExportError::Output`] when the file cannot be written.
pub fn write_table(
    dir: &Path,
    format: OutputFormat,
    encounters: &[Encounter],
    run: &RunMetadata,
) -> Result<PathBuf, ExportError> {
    let (path, bytes) = match format {
        OutputFormat::Csv => (dir.join(format!("{TABLE}.csv")), csv(encounters, run.epoch)),
        OutputFormat::Parquet => {
            let path = dir.join(format!("{TABLE}.parquet"));
            let bytes = parquet(encounters, run).map_err(|e| ExportError::Output {
                path: path.display().to_string(),
                message: e.to_string(),
            })?;
            (path, bytes)
        }
    };
    write_whole(&path, &bytes)?;
    Ok(path)
}

/// The CSV text: header, one line per encounter (numbers in Rust's shortest round-trip form).
fn csv(encounters: &[Encounter], epoch: Epoch) -> Vec<u8> {
    let mut out = String::from("tca_s,tca_utc");
    for name in ID_COLUMNS.iter().chain(VALUE_COLUMNS.iter().map(|c| &c.0)) {
        let _ = write!(out, ",{name}");
    }
    out.push('\n');
    for e in encounters {
        let _ = write!(
            out,
            "{},{}",
            e.tca_s,
            time::utc_iso(time::at(epoch, e.tca_s))
        );
        for id in ids(e) {
            out.push(',');
            if let Some(id) = id {
                let _ = write!(out, "{id}");
            }
        }
        for v in values(e) {
            let _ = write!(out, ",{v}");
        }
        out.push('\n');
    }
    out.into_bytes()
}

/// The Parquet file's bytes: typed columns with `unit` and `frame`, the run's key-value metadata.
fn parquet(
    encounters: &[Encounter],
    run: &RunMetadata,
) -> Result<Vec<u8>, parquet::errors::ParquetError> {
    let field =
        |name: &str, data_type: DataType, nullable: bool, unit: &str, frame: Option<&str>| {
            let mut metadata = HashMap::from([("unit".to_string(), unit.to_string())]);
            if let Some(frame) = frame {
                metadata.insert("frame".into(), frame.into());
            }
            Field::new(name, data_type, nullable).with_metadata(metadata)
        };
    let mut fields = vec![
        field("tca_s", DataType::Float64, false, "s", None),
        field("tca_utc", DataType::Utf8, false, frames::TIME_SYSTEM, None),
    ];
    let mut arrays: Vec<ArrayRef> = vec![
        Arc::new(Float64Array::from_iter_values(
            encounters.iter().map(|e| e.tca_s),
        )),
        Arc::new(StringArray::from_iter_values(
            encounters
                .iter()
                .map(|e| time::utc_iso(time::at(run.epoch, e.tca_s))),
        )),
    ];
    for (k, name) in ID_COLUMNS.iter().enumerate() {
        fields.push(field(name, DataType::UInt64, k > 0, "1", None));
        arrays.push(Arc::new(UInt64Array::from_iter(
            encounters.iter().map(|e| ids(e)[k]),
        )));
    }
    for (k, (name, unit, frame)) in VALUE_COLUMNS.iter().enumerate() {
        fields.push(field(name, DataType::Float64, false, unit, *frame));
        arrays.push(Arc::new(Float64Array::from_iter_values(
            encounters.iter().map(|e| values(e)[k]),
        )));
    }
    let run_keys = HashMap::from([
        ("scenario".to_string(), run.scenario.clone()),
        ("seed".to_string(), run.seed.to_string()),
        ("epoch_utc".to_string(), time::utc_iso(run.epoch)),
        (
            "satflock_version".to_string(),
            env!("CARGO_PKG_VERSION").to_string(),
        ),
    ]);
    let schema = Arc::new(Schema::new_with_metadata(fields, run_keys));
    let batch = RecordBatch::try_new(schema.clone(), arrays)?;
    let mut bytes = Vec::new();
    let mut writer = ArrowWriter::try_new(
        &mut bytes,
        schema,
        Some(WriterProperties::builder().build()),
    )?;
    writer.write(&batch)?;
    writer.close()?;
    Ok(bytes)
}
