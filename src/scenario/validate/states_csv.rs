//! The CSV files of initial states: confined to the scenario's folder, read through the bounded reader.
//! Errors name the file, the line and the column, never the file's content.

use std::path::{Path, PathBuf};

use crate::invalid::Invalid;
use crate::scenario::ScenarioError;

use super::{Checker, MAX_STATES_CSV_BYTES};

/// Resolves the `path` given by `key`: it must name a file inside the scenario's folder `base_dir`
/// (after following `..` and symbolic links); [`read_states_csv`] opens it through the bounded reader
/// (a regular file of at most [`MAX_STATES_CSV_BYTES`]).
pub(super) fn resolve(
    c: &Checker<'_>,
    key: &str,
    base_dir: &Path,
    path: &str,
) -> Result<PathBuf, ScenarioError> {
    let allowed = "a file in the scenario's folder or below it";
    let base = base_dir.canonicalize().map_err(|e| {
        c.io(
            Invalid::new(
                key,
                format!("`{path}`"),
                format!(
                    "cannot be found: the scenario's folder {}: {e}",
                    base_dir.display()
                ),
                allowed,
            ),
            e,
        )
    })?;
    let full = base_dir.join(path).canonicalize().map_err(|e| {
        c.io(
            Invalid::new(
                key,
                format!("`{path}`"),
                format!("cannot be opened: {e}"),
                allowed,
            ),
            e,
        )
    })?;
    if !full.starts_with(&base) {
        return Err(c.bad(
            key,
            format!("`{path}`"),
            format!(
                "resolves to {}, outside the scenario's folder {}",
                full.display(),
                base.display()
            ),
            allowed,
        ));
    }
    Ok(full)
}

/// Reads the CSV of states at `path` (given by `key`) with header `x_m,y_m,z_m,vx_mps,vy_mps,vz_mps`.
pub(super) fn read_states_csv(
    c: &Checker<'_>,
    key: &str,
    path: &Path,
) -> Result<Vec<[f64; 6]>, ScenarioError> {
    const HEADER: [&str; 6] = ["x_m", "y_m", "z_m", "vx_mps", "vy_mps", "vz_mps"];
    let file = path.display();
    let allowed = format!(
        "a CSV file with the header `{}` and 6 finite numbers a row, at most {MAX_STATES_CSV_BYTES} \
         bytes",
        HEADER.join(",")
    );
    let csv_error = |line: String, e: csv::Error| {
        let problem = format!("{line}: {e}");
        match e.into_kind() {
            csv::ErrorKind::Io(io) => c.io(Invalid::new(key, &file, problem, &allowed), io),
            _ => c.bad(key, &file, problem, &allowed),
        }
    };
    let mut reader = crate::input_file::open(path, MAX_STATES_CSV_BYTES)
        .map(csv::Reader::from_reader)
        .map_err(|e| {
            c.io(
                Invalid::new(key, &file, format!("cannot be read: {e}"), &allowed),
                e,
            )
        })?;
    let header = reader
        .headers()
        .map_err(|e| csv_error("line 1".into(), e))?
        .clone();
    let columns: Vec<&str> = header.iter().map(str::trim).collect();
    if columns != HEADER {
        return Err(c.bad(key, &file, "line 1 is not the required header", &allowed));
    }
    let mut rows = Vec::new();
    for (line, record) in reader.records().enumerate() {
        let line = line + 2;
        let record = record.map_err(|e| csv_error(format!("line {line}"), e))?;
        let mut row = [0.0; 6];
        for (k, field) in record.iter().enumerate().take(6) {
            row[k] = field.trim().parse::<f64>().map_err(|_| {
                c.bad(
                    key,
                    &file,
                    format!("line {line}: column {} is not a number", HEADER[k]),
                    &allowed,
                )
            })?;
        }
        if record.len() != 6 || row.iter().any(|v| !v.is_finite()) {
            return Err(c.bad(
                key,
                &file,
                format!("line {line}: expected 6 finite numbers"),
                &allowed,
            ));
        }
        rows.push(row);
    }
    Ok(rows)
}
