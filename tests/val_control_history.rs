//! The control history (`[output] control_history`) checked against what is independent of it: the
//! delta-v ledger the engine integrates with the state, the actuator's own definition of a limited
//! command, and the trajectory of the same run without it. The tables are read by the `csv` crate and
//! the `parquet` crate's Arrow reader, not through satflock's writers.
//!
//! Runs: the built-in `hold` (20 satellites, PD hold with a 2 mm/s^2 norm limit, a 50 m slot move at
//! 1000 s that saturates every satellite for a while, a failed along-track thruster), shortened to
//! 1100 s and recorded at every control tick (1 s); its continuous-control twin; the kinematic `es-e0`.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use arrow_array::cast::AsArray;
use arrow_array::types::{Float64Type, UInt64Type};
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;

use satflock::output::OutputFormat;
use satflock::run::{run_scenario_with, RunOptions};
use satflock::scenario::Scenario;

#[path = "common/builtin.rs"]
mod builtin_variant;
use builtin_variant::builtin_with;

/// The trajectory columns before the control history existed (a `hold` run: no drag attitudes, no law
/// outputs).
const TRAJECTORY_COLUMNS_WITHOUT: &[&str] = &[
    "t_s",
    "time_utc",
    "id",
    "x_lvlh_m",
    "y_lvlh_m",
    "z_lvlh_m",
    "vx_lvlh_mps",
    "vy_lvlh_mps",
    "vz_lvlh_mps",
    "x_eme2000_m",
    "y_eme2000_m",
    "z_eme2000_m",
    "vx_eme2000_mps",
    "vy_eme2000_mps",
    "vz_eme2000_mps",
    "delta_v_mps",
];

/// The control history's trajectory columns, in file order.
const CONTROL_COLUMNS: &[&str] = &[
    "ux_cmd_mps2",
    "uy_cmd_mps2",
    "uz_cmd_mps2",
    "ux_mps2",
    "uy_mps2",
    "uz_mps2",
    "saturated",
];

/// The control period and recording interval of the shortened `hold` \[s\].
const PERIOD_S: f64 = 1.0;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("satflock-control-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// `hold` shortened to 1100 s, recorded every control tick, the thruster failure moved to 1050 s;
/// with the control history when `history`, in continuous control when `continuous`.
fn hold(history: bool, continuous: bool) -> Scenario {
    let mut replacements = vec![
        ("duration_s = 4000.0", "duration_s = 1100.0"),
        (
            "record_interval_s = 10.0",
            if history {
                "record_interval_s = 1.0\n\n[output]\ncontrol_history = true"
            } else {
                "record_interval_s = 1.0"
            },
        ),
        ("time_s = 2000.0", "time_s = 1050.0"),
    ];
    if continuous {
        replacements.push((
            "mode = \"sampled\"\nperiod_s = 1.0",
            "mode = \"continuous\"",
        ));
    }
    builtin_with("hold", &replacements)
}

fn run(scenario: &Scenario, out: &Path, format: OutputFormat) {
    let options = RunOptions {
        cancel: None,
        format: Some(format),
    };
    run_scenario_with(scenario, out, &options, &mut |_| {}).expect("the run completes");
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

/// The named numeric columns of a CSV table (every cell parsed by Rust's float parser).
fn numeric_columns(path: &Path, names: &[&str]) -> Vec<Vec<f64>> {
    let (header, rows) = read_csv(path);
    names
        .iter()
        .map(|name| {
            let k = header
                .iter()
                .position(|h| h == name)
                .unwrap_or_else(|| panic!("{}: no column {name}", path.display()));
            rows.iter().map(|r| r[k].parse::<f64>().unwrap()).collect()
        })
        .collect()
}

/// One trajectory row of the control history.
struct Row {
    t_s: f64,
    id: usize,
    delta_v_mps: f64,
    commanded: [f64; 3],
    applied: [f64; 3],
    saturated: bool,
}

fn history_rows(path: &Path) -> Vec<Row> {
    let mut names = vec!["t_s", "id", "delta_v_mps"];
    names.extend_from_slice(CONTROL_COLUMNS);
    let c = numeric_columns(path, &names);
    (0..c[0].len())
        .map(|r| {
            let saturated = c[9][r];
            assert!(
                saturated == 0.0 || saturated == 1.0,
                "saturated = {saturated}"
            );
            Row {
                t_s: c[0][r],
                id: c[1][r] as usize,
                delta_v_mps: c[2][r],
                commanded: [c[3][r], c[4][r], c[5][r]],
                applied: [c[6][r], c[7][r], c[8][r]],
                saturated: saturated == 1.0,
            }
        })
        .collect()
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// Sampled control, recorded at every tick: each row after t = 0 holds the command held over the
/// control period that ends at its time, so Σ‖u_applied‖·period over a satellite's rows is the
/// ledger's ∫‖u‖dt (the ledger is integrated with the state, RK4 over a constant command) to
/// rounding. Measured: relative difference below 1e-15 on every satellite.
#[test]
fn val_applied_acceleration_integrates_to_the_delta_v_ledger() {
    let out = scratch("ledger");
    run(&hold(true, false), &out, OutputFormat::Csv);
    let rows = history_rows(&out.join("trajectory.csv"));
    let mut integral: BTreeMap<usize, f64> = BTreeMap::new();
    let mut ledger: BTreeMap<usize, f64> = BTreeMap::new();
    for row in &rows {
        if row.t_s == 0.0 {
            assert_eq!(row.applied, [0.0; 3], "no command before the first tick");
        } else {
            *integral.entry(row.id).or_default() += norm(row.applied) * PERIOD_S;
        }
        ledger.insert(row.id, row.delta_v_mps);
    }
    assert_eq!(ledger.len(), 20);
    for (id, dv) in &ledger {
        assert!(
            *dv > 0.1,
            "satellite {id} spent {dv} m/s: the check needs thrust"
        );
        let sum = integral[id];
        assert!(
            (sum - dv).abs() <= 1e-12 * dv,
            "satellite {id}: Σ‖u‖·Δt = {sum} m/s, ledger {dv} m/s"
        );
    }
    let _ = std::fs::remove_dir_all(&out);
}

/// Commanded minus applied is exactly zero on every row whose `saturated` is 0 and nonzero on every
/// row whose `saturated` is 1, and the limit holds: ‖u_applied‖ ≤ 2 mm/s^2 (norm limit) everywhere, and
/// equal to it (to rounding) where a command above it was scaled down. The run saturates (the slot move
/// at 1000 s, the failed axis after 1050 s) and does not (the hold before): both kinds must occur.
/// The `metrics` columns summarise the same rows: `saturated_fraction` is the saturated rows' share
/// and `mean_command_mps2` the mean commanded norm at each time.
fn check_saturation(out: &Path) {
    let rows = history_rows(&out.join("trajectory.csv"));
    let limit = 2e-3;
    let (mut saturated, mut free) = (0usize, 0usize);
    let mut by_time: BTreeMap<u64, (usize, usize, f64)> = BTreeMap::new();
    for row in &rows {
        let difference = [
            row.commanded[0] - row.applied[0],
            row.commanded[1] - row.applied[1],
            row.commanded[2] - row.applied[2],
        ];
        if row.saturated {
            saturated += 1;
            assert!(norm(difference) > 0.0, "t = {} id {}", row.t_s, row.id);
        } else {
            free += 1;
            assert_eq!(difference, [0.0; 3], "t = {} id {}", row.t_s, row.id);
        }
        assert!(norm(row.applied) <= limit * (1.0 + 1e-12));
        if row.saturated && norm(row.commanded) > limit && row.t_s < 1050.0 {
            // Before the thruster failure only the norm limit acts: scaled down to the limit.
            assert!((norm(row.applied) - limit).abs() <= 1e-15);
        }
        let entry = by_time.entry(row.t_s.to_bits()).or_default();
        entry.0 += usize::from(row.saturated);
        entry.1 += 1;
        entry.2 += norm(row.commanded);
    }
    assert!(
        saturated > 0 && free > 0,
        "saturated {saturated}, free {free}"
    );
    let m = numeric_columns(
        &out.join("metrics.csv"),
        &["t_s", "saturated_fraction", "mean_command_mps2"],
    );
    assert_eq!(m[0].len(), by_time.len());
    for r in 0..m[0].len() {
        let (limited, live, norms) = by_time[&m[0][r].to_bits()];
        assert_eq!(m[1][r], limited as f64 / live as f64, "t = {}", m[0][r]);
        assert!((m[2][r] - norms / live as f64).abs() <= 1e-15 * (norms / live as f64).max(1e-30));
    }
}

#[test]
fn val_saturated_exactly_where_the_actuator_limited_the_command() {
    let out = scratch("saturation");
    run(&hold(true, false), &out, OutputFormat::Csv);
    check_saturation(&out);
    let _ = std::fs::remove_dir_all(&out);
}

/// Continuous control: each row holds the command evaluated at its state, so the same saturation
/// checks hold, and the trapezoid rule over the rows' applied norms (1 s apart) approximates the
/// ledger's RK4 integral of the same function (the one jump, the slot move at 1000 s, costs at most
/// ½ · 2 mm/s^2 · 1 s per satellite). Measured: relative difference below 0.3 % on every satellite.
#[test]
fn val_continuous_control_history() {
    let out = scratch("continuous");
    run(&hold(true, true), &out, OutputFormat::Csv);
    check_saturation(&out);
    let rows = history_rows(&out.join("trajectory.csv"));
    let mut by_id: BTreeMap<usize, Vec<&Row>> = BTreeMap::new();
    for row in &rows {
        by_id.entry(row.id).or_default().push(row);
    }
    for (id, rows) in &by_id {
        let trapezoid: f64 = rows
            .windows(2)
            .map(|w| 0.5 * (norm(w[0].applied) + norm(w[1].applied)) * (w[1].t_s - w[0].t_s))
            .sum();
        let dv = rows.last().unwrap().delta_v_mps;
        assert!(
            (trapezoid - dv).abs() <= 0.01 * dv,
            "satellite {id}: trapezoid {trapezoid} m/s, ledger {dv} m/s"
        );
    }
    let _ = std::fs::remove_dir_all(&out);
}

/// With the switch off the tables have exactly the columns they had before the control history
/// existed, and the run is the same: every other cell of the trajectory (CSV text) is identical with
/// the switch on.
#[test]
fn val_switch_off_writes_no_control_columns_and_changes_nothing_else() {
    let (off, on) = (scratch("off"), scratch("on"));
    run(&hold(false, false), &off, OutputFormat::Csv);
    run(&hold(true, false), &on, OutputFormat::Csv);
    let (header_off, rows_off) = read_csv(&off.join("trajectory.csv"));
    let (header_on, rows_on) = read_csv(&on.join("trajectory.csv"));
    assert_eq!(header_off, TRAJECTORY_COLUMNS_WITHOUT);
    let mut expected_on: Vec<&str> = TRAJECTORY_COLUMNS_WITHOUT.to_vec();
    expected_on.extend_from_slice(CONTROL_COLUMNS);
    assert_eq!(header_on, expected_on);
    assert_eq!(rows_off.len(), rows_on.len());
    for (a, b) in rows_off.iter().zip(&rows_on) {
        assert_eq!(a[..], b[..a.len()]);
    }
    let (metrics_off, _) = read_csv(&off.join("metrics.csv"));
    let (metrics_on, _) = read_csv(&on.join("metrics.csv"));
    assert!(!metrics_off.iter().any(|h| h == "saturated_fraction"));
    assert_eq!(
        metrics_on[metrics_off.len()..],
        ["saturated_fraction", "mean_command_mps2"]
    );
    // The scenario's copy carries the key, and reads back to the same scenario.
    let copy = std::fs::read_to_string(on.join("scenario.toml")).unwrap();
    let reread = Scenario::from_toml(&copy, "copy", Path::new(".")).unwrap();
    assert!(reread.file.output.control_history);
    for dir in [off, on] {
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// Parquet carries the same control history as CSV, bit for bit, `saturated` as an unsigned count.
#[test]
fn val_parquet_control_history_equals_csv() {
    let (csv_dir, parquet_dir) = (scratch("csv"), scratch("parquet"));
    run(&hold(true, false), &csv_dir, OutputFormat::Csv);
    run(&hold(true, false), &parquet_dir, OutputFormat::Parquet);
    let expected = numeric_columns(&csv_dir.join("trajectory.csv"), CONTROL_COLUMNS);
    let file = std::fs::File::open(parquet_dir.join("trajectory.parquet")).unwrap();
    let reader = ParquetRecordBatchReaderBuilder::try_new(file)
        .unwrap()
        .build()
        .unwrap();
    let mut got: Vec<Vec<f64>> = vec![Vec::new(); CONTROL_COLUMNS.len()];
    for batch in reader {
        let batch = batch.unwrap();
        for (k, name) in CONTROL_COLUMNS.iter().enumerate() {
            let column = batch.column_by_name(name).expect("the column");
            if *name == "saturated" {
                got[k].extend(
                    column
                        .as_primitive::<UInt64Type>()
                        .values()
                        .iter()
                        .map(|&v| v as f64),
                );
            } else {
                got[k].extend(column.as_primitive::<Float64Type>().values().iter());
            }
        }
    }
    for (k, name) in CONTROL_COLUMNS.iter().enumerate() {
        assert_eq!(got[k].len(), expected[k].len(), "{name}");
        for (a, b) in got[k].iter().zip(&expected[k]) {
            assert_eq!(a.to_bits(), b.to_bits(), "{name}");
        }
    }
    for dir in [csv_dir, parquet_dir] {
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// The kinematic model commands velocities: a scenario asking for the control history gets none (no
/// column named as an acceleration holds a velocity).
#[test]
fn val_kinematic_model_writes_no_control_history() {
    let out = scratch("kinematic");
    let scenario = builtin_with(
        "es-e0",
        &[("[output]\n", "[output]\ncontrol_history = true\n")],
    );
    run(&scenario, &out, OutputFormat::Csv);
    let (header, _) = read_csv(&out.join("trajectory.csv"));
    assert!(header
        .iter()
        .all(|h| !CONTROL_COLUMNS.contains(&h.as_str())));
    let _ = std::fs::remove_dir_all(&out);
}
