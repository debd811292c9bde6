//! Parquet outputs checked against the CSV files of the same run, each read by an independent reader:
//! the CSV by the `csv` crate and Rust's float parser, the Parquet by the `parquet` crate's own Arrow
//! reader (not through satflock's writer or `RunData`). Every column must agree bit for bit
//! (`f64::to_bits`; an empty CSV cell is a null), with the same names in the same order, and the columns
//! and the file must carry their metadata (unit, frame; scenario, seed, epoch, version). `RunData` must
//! read both formats into the same numbers.
//!
//! Runs: `es-e3a` (threats, a per-satellite law output, law metrics) and `pigeon-switching` (obstacles,
//! a per-satellite output), both shortened; a run interrupted through `RunOptions::cancel` and a run that
//! diverges must leave Parquet files readable up to where they stopped.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use arrow_array::cast::AsArray;
use arrow_array::types::{Float64Type, UInt64Type};
use arrow_array::{Array, RecordBatch};
use arrow_schema::{DataType, SchemaRef};
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use parquet::file::reader::{FileReader, SerializedFileReader};

use satflock::output::{OutputFormat, RunData, Table};
use satflock::run::{run_scenario_with, RunError, RunOptions};
use satflock::scenario::Scenario;
use satflock::swarm::SimError;

#[path = "common/builtin.rs"]
mod builtin_variant;
use builtin_variant::builtin_with;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("satflock-parquet-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn run(
    scenario: &Scenario,
    out: &Path,
    format: OutputFormat,
    cancel_at_s: Option<f64>,
) -> Result<(), RunError> {
    let cancel = Arc::new(AtomicBool::new(false));
    let options = RunOptions {
        cancel: Some(cancel.clone()),
        format: Some(format),
    };
    let mut progress = |t_s: f64| {
        if cancel_at_s.is_some_and(|at| t_s >= at) {
            cancel.store(true, Ordering::Relaxed);
        }
    };
    run_scenario_with(scenario, out, &options, &mut progress).map(|_| ())
}

/// A CSV file as its header and rows of cells, by the `csv` crate.
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut reader = csv::Reader::from_path(path).unwrap();
    let header = reader.headers().unwrap().iter().map(String::from).collect();
    let rows = reader
        .records()
        .map(|r| r.unwrap().iter().map(String::from).collect())
        .collect();
    (header, rows)
}

/// A Parquet file's Arrow schema and record batches, by the `parquet` crate's reader.
fn read_parquet(path: &Path) -> (SchemaRef, Vec<RecordBatch>) {
    let file = std::fs::File::open(path).unwrap();
    let builder = ParquetRecordBatchReaderBuilder::try_new(file)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let schema = builder.schema().clone();
    let batches = builder.build().unwrap().map(|b| b.unwrap()).collect();
    (schema, batches)
}

/// Asserts that every column of the Parquet file equals the CSV's, bit for bit; returns the row count.
fn assert_same_table(csv_path: &Path, parquet_path: &Path) -> usize {
    let (header, rows) = read_csv(csv_path);
    let (schema, batches) = read_parquet(parquet_path);
    let names: Vec<&str> = schema.fields().iter().map(|f| f.name().as_str()).collect();
    assert_eq!(names, header, "{}: column names", parquet_path.display());
    let total: usize = batches.iter().map(RecordBatch::num_rows).sum();
    assert_eq!(total, rows.len(), "{}: rows", parquet_path.display());
    for (c, field) in schema.fields().iter().enumerate() {
        let mut r = 0;
        for batch in &batches {
            let array = batch.column(c);
            for k in 0..array.len() {
                let cell = &rows[r][c];
                let what = || {
                    format!(
                        "{} row {} column `{}`",
                        parquet_path.display(),
                        r,
                        field.name()
                    )
                };
                match field.data_type() {
                    DataType::Float64 => {
                        let a = array.as_primitive::<Float64Type>();
                        if cell.is_empty() {
                            assert!(a.is_null(k), "{}: empty CSV cell, not null", what());
                        } else {
                            assert!(!a.is_null(k), "{}: null, CSV has `{cell}`", what());
                            let csv_value: f64 = cell.parse().unwrap();
                            assert_eq!(
                                a.value(k).to_bits(),
                                csv_value.to_bits(),
                                "{}: {} vs CSV `{cell}`",
                                what(),
                                a.value(k)
                            );
                        }
                    }
                    DataType::UInt64 => {
                        let a = array.as_primitive::<UInt64Type>();
                        assert!(!a.is_null(k), "{}", what());
                        assert_eq!(a.value(k), cell.parse::<u64>().unwrap(), "{}", what());
                    }
                    DataType::Utf8 => {
                        assert_eq!(array.as_string::<i32>().value(k), cell, "{}", what());
                    }
                    other => panic!("{}: unexpected type {other}", what()),
                }
                r += 1;
            }
        }
    }
    rows.len()
}

/// Runs a scenario in both formats and compares both tables; returns the Parquet run's directory.
fn assert_formats_agree(name: &str, scenario: &Scenario) -> PathBuf {
    let csv_dir = scratch(&format!("{name}-csv"));
    let parquet_dir = scratch(&format!("{name}-parquet"));
    run(scenario, &csv_dir, OutputFormat::Csv, None).unwrap();
    run(scenario, &parquet_dir, OutputFormat::Parquet, None).unwrap();
    assert!(!parquet_dir.join("metrics.csv").exists());
    assert!(!parquet_dir.join("trajectory.csv").exists());
    assert!(!csv_dir.join("trajectory.parquet").exists());
    for table in ["metrics", "trajectory"] {
        let rows = assert_same_table(
            &csv_dir.join(format!("{table}.csv")),
            &parquet_dir.join(format!("{table}.parquet")),
        );
        assert!(rows > 10, "{name} {table}: {rows} rows");
    }
    // RunData reads either format into the same numbers.
    let from_csv = RunData::read(&csv_dir).unwrap();
    let from_parquet = RunData::read(&parquet_dir).unwrap();
    for (a, b) in [
        (&from_csv.metrics, &from_parquet.metrics),
        (
            from_csv.trajectory.as_ref().unwrap(),
            from_parquet.trajectory.as_ref().unwrap(),
        ),
    ] {
        assert_eq!(a.names(), b.names());
        for name in a.names() {
            let bits = |t: &Table| -> Vec<u64> {
                t.column(name)
                    .unwrap()
                    .iter()
                    .map(|v| v.to_bits())
                    .collect()
            };
            assert_eq!(bits(a), bits(b), "RunData column `{name}`");
        }
    }
    let _ = std::fs::remove_dir_all(&csv_dir);
    parquet_dir
}

#[test]
fn val_parquet_equals_csv_threats_and_law_outputs() {
    let scenario = builtin_with("es-e3a", &[("duration_s = 430.0", "duration_s = 140.0")]);
    let dir = assert_formats_agree("es", &scenario);
    // The CSV's empty cells are nulls here: the threat distance before the first observation.
    let (schema, batches) = read_parquet(&dir.join("metrics.parquet"));
    let c = schema.index_of("min_threat_distance_m").unwrap();
    assert!(batches[0].column(c).is_null(0));

    // Column metadata: unit and frame.
    let (schema, _) = read_parquet(&dir.join("trajectory.parquet"));
    let meta = |name: &str, key: &str| {
        schema
            .field_with_name(name)
            .unwrap()
            .metadata()
            .get(key)
            .cloned()
    };
    assert_eq!(meta("x_lvlh_m", "unit").as_deref(), Some("m"));
    assert_eq!(meta("x_lvlh_m", "frame").as_deref(), Some("Hill LVLH"));
    assert_eq!(meta("vy_eme2000_mps", "unit").as_deref(), Some("m/s"));
    assert_eq!(meta("vy_eme2000_mps", "frame").as_deref(), Some("EME2000"));
    assert_eq!(meta("t_s", "unit").as_deref(), Some("s"));
    assert_eq!(meta("t_s", "frame"), None);
    assert_eq!(meta("es_mode", "unit").as_deref(), Some("1"));
    assert_eq!(meta("time_utc", "unit").as_deref(), Some("UTC"));

    // File metadata, read by the plain Parquet file reader.
    let reader =
        SerializedFileReader::new(std::fs::File::open(dir.join("trajectory.parquet")).unwrap())
            .unwrap();
    let kv = reader
        .metadata()
        .file_metadata()
        .key_value_metadata()
        .unwrap()
        .clone();
    let value = |key: &str| {
        kv.iter()
            .find(|e| e.key == key)
            .and_then(|e| e.value.clone())
    };
    assert_eq!(value("scenario").as_deref(), Some("es-e3a"));
    assert_eq!(value("seed").as_deref(), Some("1"));
    assert_eq!(
        value("epoch_utc").as_deref(),
        Some("2000-01-01T12:00:00.000000Z")
    );
    assert_eq!(
        value("satflock_version").as_deref(),
        Some(env!("CARGO_PKG_VERSION"))
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn val_parquet_equals_csv_obstacles() {
    let scenario = builtin_with(
        "pigeon-switching",
        &[
            ("duration_s = 6000.0", "duration_s = 120.0"),
            ("trajectory = false", "trajectory = true"),
        ],
    );
    let dir = assert_formats_agree("pigeon", &scenario);
    let (schema, _) = read_parquet(&dir.join("metrics.parquet"));
    assert!(schema.index_of("min_obstacle_clearance_m").is_ok());
    assert!(schema.index_of("pigeon_order_parameter").is_ok());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn regress_interrupted_run_leaves_readable_parquet() {
    let scenario = builtin_with("es-e3a", &[]);
    let csv_dir = scratch("interrupted-csv");
    let parquet_dir = scratch("interrupted-parquet");
    for (dir, format) in [
        (&csv_dir, OutputFormat::Csv),
        (&parquet_dir, OutputFormat::Parquet),
    ] {
        let outcome = run(&scenario, dir, format, Some(50.0));
        assert!(
            matches!(
                outcome,
                Err(RunError::Simulation(SimError::Interrupted { .. }))
            ),
            "{outcome:?}"
        );
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap())
                .unwrap();
        assert_eq!(summary["status"], "interrupted");
    }
    // Stopped at the same segment both times: the Parquet files hold what the CSV files hold.
    let rows = assert_same_table(
        &csv_dir.join("metrics.csv"),
        &parquet_dir.join("metrics.parquet"),
    );
    assert!((50..430).contains(&rows), "{rows} metrics rows");
    assert_same_table(
        &csv_dir.join("trajectory.csv"),
        &parquet_dir.join("trajectory.parquet"),
    );
    let _ = std::fs::remove_dir_all(&csv_dir);
    let _ = std::fs::remove_dir_all(&parquet_dir);
}

#[test]
fn regress_diverged_run_leaves_readable_parquet() {
    // Satellites start 589.5 m apart, drifting apart, with a 600 m divergence bound: the run stops at
    // t = 11 s (see cli/tests/cli.rs).
    let scenario = Scenario::from_toml(
        "name = \"diverge\"\nseed = 1\nduration_s = 100.0\nrecord_interval_s = 1.0\n[dynamics]\n\
         max_distance_m = 600.0\n[reference]\naltitude_m = 600e3\ninclination_deg = 97.8\n\
         [satellites]\ncount = 2\nmass_kg = 1.0\ninitial = { distribution = \"list\", states = \
         [[0,0,0,0,0,0],[0,589.5,0,0,1.0,0]] }\n[law]\nname = \"none\"\n",
        "diverge",
        Path::new("."),
    )
    .unwrap();
    let dir = scratch("diverge");
    let outcome = run(&scenario, &dir, OutputFormat::Parquet, None);
    assert!(
        matches!(
            outcome,
            Err(RunError::Simulation(SimError::Diverged { .. }))
        ),
        "{outcome:?}"
    );
    let (schema, batches) = read_parquet(&dir.join("trajectory.parquet"));
    let t = schema.index_of("t_s").unwrap();
    let times: Vec<f64> = batches
        .iter()
        .flat_map(|b| b.column(t).as_primitive::<Float64Type>().values().to_vec())
        .collect();
    assert_eq!(times.len(), 2 * 11, "two satellites at t = 0 … 10 s");
    assert_eq!(times.last(), Some(&10.0));

    // A file cut short (no footer: what SIGKILL leaves) is refused with the reason.
    let path = dir.join("trajectory.parquet");
    let length = std::fs::metadata(&path).unwrap().len();
    std::fs::OpenOptions::new()
        .write(true)
        .open(&path)
        .unwrap()
        .set_len(length / 2)
        .unwrap();
    let e = Table::read(&path).unwrap_err().to_string();
    assert!(e.contains("SIGKILL") && e.contains("CSV"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}
