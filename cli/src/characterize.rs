//! `satflock characterize`: the five-element characterisation of a set of positions, printed as JSON.
//!
//! The positions come from a CSV file with columns `x_m,y_m,z_m[,radius_m]` (any common frame), or from a
//! run's trajectory file (`trajectory.csv` or `trajectory.parquet`): the Hill LVLH positions
//! (`x_lvlh_m`, `y_lvlh_m`, `z_lvlh_m`) of the rows at one recorded time, the one nearest to `--time-s`
//! or, without it, the last; stderr says which time was used. A trajectory file passes the checks of
//! every run-directory reader ([`Table::check_trajectory`]). A file must be a regular file of at most
//! [`satflock::input_file::MAX_TABLE_BYTES`] (the whole file is read, through
//! [`satflock::input_file`]).
//!
//! Positions carry no velocities, so the centre velocity `v_o_mps` is printed as `null` ("not given",
//! stderr says so), never as a zero vector.

use std::path::Path;

use anyhow::Result;

use satflock::input_file::{self, MAX_TABLE_BYTES};
use satflock::metrics::{five_elements, FiveElementsWorkspace};
use satflock::output::Table;

use crate::{print_out, usage};

/// Columns that mark a run's trajectory table.
const TRAJECTORY_COLUMNS: [&str; 4] = ["t_s", "x_lvlh_m", "y_lvlh_m", "z_lvlh_m"];

/// Positions \[m\] and, if the file gives them, radii \[m\].
type PointSet = (Vec<[f64; 3]>, Option<Vec<f64>>);

/// Runs the command on `path`; `time_s` picks the recorded time of a trajectory file.
pub fn run(path: &Path, time_s: Option<f64>) -> Result<()> {
    let shown = path.display();
    // A device, FIFO or oversized file is refused before anything is read.
    input_file::open(path, MAX_TABLE_BYTES).map_err(|e| usage(format!("{shown}: {e}")))?;
    let (positions, radii) = if path.extension().is_some_and(|e| e == "parquet") {
        (trajectory_positions(path, time_s)?, None)
    } else {
        let file =
            input_file::open(path, MAX_TABLE_BYTES).map_err(|e| usage(format!("{shown}: {e}")))?;
        let mut reader = csv::Reader::from_reader(file);
        let header: Vec<String> = reader
            .headers()
            .map_err(|e| usage(format!("{shown}: {e}")))?
            .iter()
            .map(|h| h.trim().to_string())
            .collect();
        if TRAJECTORY_COLUMNS
            .iter()
            .all(|c| header.iter().any(|h| h == c))
        {
            (trajectory_positions(path, time_s)?, None)
        } else if time_s.is_some() {
            return Err(usage(format!(
                "{shown}: --time-s applies to a run's trajectory file (columns {}), not to a \
                 positions file",
                TRAJECTORY_COLUMNS.join(",")
            )));
        } else {
            positions_csv(path, reader, &header)?
        }
    };
    let velocities = vec![[0.0; 3]; positions.len()];
    let mut workspace = FiveElementsWorkspace::new();
    let elements = five_elements(&positions, &velocities, radii.as_deref(), &mut workspace)
        .map_err(|e| usage(format!("{shown}: {e}")))?;
    let mut json = serde_json::to_value(elements)?;
    json["v_o_mps"] = serde_json::Value::Null;
    eprintln!("characterize: centre velocity v_o_mps not given (positions only): null");
    print_out(&(serde_json::to_string_pretty(&json)? + "\n"))
}

/// The Hill LVLH positions of a trajectory table's rows at the recorded time nearest to `time_s` (or
/// the last recorded time); says on stderr which time it used.
fn trajectory_positions(path: &Path, time_s: Option<f64>) -> Result<Vec<[f64; 3]>> {
    let shown = path.display();
    let table = Table::read(path).map_err(|e| usage(e.to_string()))?;
    table
        .check_trajectory(path, None)
        .map_err(|e| usage(e.to_string()))?;
    let column = |name: &str| table.column(name).unwrap_or_default();
    let t = column("t_s");
    let (x, y, z) = (column("x_lvlh_m"), column("y_lvlh_m"), column("z_lvlh_m"));
    // check_trajectory refuses a table without rows.
    let (first, last) = (t[0], t[t.len() - 1]);
    let (chosen, how) = match time_s {
        None => (last, "the last recorded time".to_string()),
        Some(wanted) => {
            if !(wanted.is_finite() && first <= wanted && wanted <= last) {
                return Err(usage(format!(
                    "--time-s {wanted} is outside the recorded times of {shown} (allowed: [{first}, \
                     {last}] s)"
                )));
            }
            // Rows are in time order: the nearest recorded time, the earlier one on a tie.
            let nearest = t.iter().copied().fold(first, |best, v| {
                if (v - wanted).abs() < (best - wanted).abs() {
                    v
                } else {
                    best
                }
            });
            let how = if nearest == wanted {
                format!("--time-s {wanted}")
            } else {
                format!("the recorded time nearest to --time-s {wanted}")
            };
            (nearest, how)
        }
    };
    let positions: Vec<[f64; 3]> = (0..t.len())
        .filter(|&r| t[r] == chosen)
        .map(|r| [x[r], y[r], z[r]])
        .collect();
    eprintln!(
        "characterize: {} satellites at t_s = {chosen} s ({how}), Hill LVLH positions",
        positions.len()
    );
    Ok(positions)
}

/// Positions (and radii) from a CSV file with columns `x_m,y_m,z_m[,radius_m]`.
fn positions_csv(
    path: &Path,
    mut reader: csv::Reader<std::fs::File>,
    header: &[String],
) -> Result<PointSet> {
    let shown = path.display();
    let with_radius = match header.iter().map(String::as_str).collect::<Vec<_>>()[..] {
        ["x_m", "y_m", "z_m"] => false,
        ["x_m", "y_m", "z_m", "radius_m"] => true,
        _ => {
            return Err(usage(format!(
                "{shown}: header is `{}` (required: `x_m,y_m,z_m` or `x_m,y_m,z_m,radius_m`, or a \
                 run's trajectory file)",
                header.join(",")
            )))
        }
    };
    let mut positions = Vec::new();
    let mut radii = Vec::new();
    for (row, record) in reader.records().enumerate() {
        let record = record.map_err(|e| usage(format!("{shown}: {e}")))?;
        let values: Vec<f64> = record
            .iter()
            .map(|v| v.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .ok()
            .filter(|v: &Vec<f64>| v.len() == header.len() && v.iter().all(|x| x.is_finite()))
            .ok_or_else(|| {
                usage(format!(
                    "{shown} line {}: expected {} finite numbers",
                    row + 2,
                    header.len()
                ))
            })?;
        positions.push([values[0], values[1], values[2]]);
        if with_radius {
            if values[3] < 0.0 {
                return Err(usage(format!(
                    "{shown} line {}: radius_m = {} is out of range (allowed: >= 0)",
                    row + 2,
                    values[3]
                )));
            }
            radii.push(values[3]);
        }
    }
    Ok((positions, with_radius.then_some(radii)))
}
