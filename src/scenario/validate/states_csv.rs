//! The files a scenario names, confined to its folder; the CSV files of initial states, read through
//! the bounded reader.
//! Errors name the file, the line and the column, never the file's content.

use std::path::{Path, PathBuf};

use crate::invalid::Invalid;
use crate::scenario::schema::ListFrame;
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

/// Opens the CSV file at `path` (given by `key`) through the bounded reader (a regular file of at most
/// [`MAX_STATES_CSV_BYTES`]); `allowed` says what the file must be.
pub(super) fn open_csv(
    c: &Checker<'_>,
    key: &str,
    path: &Path,
    allowed: &str,
) -> Result<csv::Reader<std::fs::File>, ScenarioError> {
    crate::input_file::open(path, MAX_STATES_CSV_BYTES)
        .map(csv::Reader::from_reader)
        .map_err(|e| {
            c.io(
                Invalid::new(key, path.display(), format!("cannot be read: {e}"), allowed),
                e,
            )
        })
}

/// The error of reading `line` (`line N`) of the CSV file at `path` (given by `key`): the system's
/// error kept as the source when it is one.
pub(super) fn read_error(
    c: &Checker<'_>,
    key: &str,
    path: &Path,
    allowed: &str,
    line: &str,
    e: csv::Error,
) -> ScenarioError {
    let file = path.display();
    let problem = format!("{line}: {e}");
    match e.into_kind() {
        csv::ErrorKind::Io(io) => c.io(Invalid::new(key, file, problem, allowed), io),
        _ => c.bad(key, file, problem, allowed),
    }
}

/// One row of a states CSV: the state and, with a `frame` column, its frame.
pub(super) struct StateRow {
    /// `[x, y, z, vx, vy, vz]` \[m, m/s\].
    pub state: [f64; 6],
    /// The row's frame (`None` without a `frame` column).
    pub frame: Option<ListFrame>,
}

/// Reads the CSV of states at `path` (given by `key`) with the header `x_m,y_m,z_m,vx_mps,vy_mps,vz_mps`,
/// optionally led by `sat` (each row's satellite id: every id of `0..rows` once, rows returned by id)
/// and followed by `frame` (`hill`, `gao` or `eme2000` per row).
pub(super) fn read_states_csv(
    c: &Checker<'_>,
    key: &str,
    path: &Path,
) -> Result<Vec<StateRow>, ScenarioError> {
    const HEADER: [&str; 6] = ["x_m", "y_m", "z_m", "vx_mps", "vy_mps", "vz_mps"];
    let file = path.display();
    let allowed = format!(
        "a CSV file with the header `[sat,]{}[,frame]` (frame: hill, gao or eme2000), 6 finite numbers \
         a row, at most {MAX_STATES_CSV_BYTES} bytes",
        HEADER.join(",")
    );
    let csv_error = |line: String, e: csv::Error| read_error(c, key, path, &allowed, &line, e);
    let mut reader = open_csv(c, key, path, &allowed)?;
    let header = reader
        .headers()
        .map_err(|e| csv_error("line 1".into(), e))?
        .clone();
    let columns: Vec<&str> = header.iter().map(str::trim).collect();
    let has_sat = columns.first() == Some(&"sat");
    let first = usize::from(has_sat);
    let has_frame = columns.len() == first + 7 && columns[first + 6] == "frame";
    if columns.len() != first + 6 + usize::from(has_frame) || columns[first..first + 6] != HEADER {
        return Err(c.bad(key, &file, "line 1 is not the required header", &allowed));
    }
    let mut rows: Vec<(Option<usize>, StateRow)> = Vec::new();
    for (line, record) in reader.records().enumerate() {
        let line = line + 2;
        let record = record.map_err(|e| csv_error(format!("line {line}"), e))?;
        let bad_line =
            |problem: String| c.bad(key, &file, format!("line {line}: {problem}"), &allowed);
        if record.len() != columns.len() {
            return Err(bad_line(format!(
                "expected {} columns, found {}",
                columns.len(),
                record.len()
            )));
        }
        let sat = if has_sat {
            let text = record[0].trim();
            Some(
                text.parse::<usize>()
                    .map_err(|_| bad_line("column sat is not a satellite id".into()))?,
            )
        } else {
            None
        };
        let mut state = [0.0; 6];
        for (k, value) in state.iter_mut().enumerate() {
            *value = record[first + k]
                .trim()
                .parse::<f64>()
                .map_err(|_| bad_line(format!("column {} is not a number", HEADER[k])))?;
            if !value.is_finite() {
                return Err(bad_line(format!("column {} is not finite", HEADER[k])));
            }
        }
        let frame = if has_frame {
            let text = record[first + 6].trim();
            Some(match text {
                "hill" => ListFrame::Hill,
                "gao" => ListFrame::Gao,
                "eme2000" => ListFrame::Eme2000,
                _ => {
                    return Err(bad_line(
                        "column frame is not one of hill, gao, eme2000".into(),
                    ))
                }
            })
        } else {
            None
        };
        rows.push((sat, StateRow { state, frame }));
    }
    if has_sat {
        let n = rows.len();
        let mut seen = vec![false; n];
        for (line, (sat, _)) in rows.iter().enumerate() {
            let id = sat.expect("a sat column");
            if id >= n || std::mem::replace(&mut seen[id], true) {
                return Err(c.bad(
                    key,
                    &file,
                    format!(
                        "line {}: sat {id} is out of range or repeated (the ids of the rows are \
                         0..={} once each)",
                        line + 2,
                        n.saturating_sub(1)
                    ),
                    &allowed,
                ));
            }
        }
        rows.sort_by_key(|(sat, _)| *sat);
    }
    Ok(rows.into_iter().map(|(_, row)| row).collect())
}
