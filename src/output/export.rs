//! What the CCSDS OEM ([`super::oem`]) and CZML ([`super::czml`]) exports share: each satellite's
//! inertial track read back from a run's `trajectory.csv` (the `*_eme2000_*` columns, see
//! [`super::frames`]), the error of an export, and writing an output file whole.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use thiserror::Error;

use super::frames::INERTIAL_COLUMN_TAG;
use super::run_data::{RunData, RunDataError};

/// One satellite's states in the inertial frame ([`super::frames::INERTIAL_FRAME`]) at its recorded
/// times, in time order.
#[derive(Clone, Debug, PartialEq)]
pub struct InertialTrack {
    /// The satellite's index in the run (the `id` column).
    pub id: usize,
    /// Elapsed times since the epoch \[s\].
    pub t_s: Vec<f64>,
    /// `[x, y, z, vx, vy, vz]` at each time \[m, m/s\].
    pub states: Vec<[f64; 6]>,
}

/// Why an export could not be made.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ExportError {
    /// The run directory cannot be read or does not hold what the export needs (the user's input).
    #[error(transparent)]
    Input(#[from] RunDataError),
    /// An option is out of range (the user's input).
    #[error("{option}: {message}")]
    Option {
        /// The option or key.
        option: String,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// The output file cannot be written.
    #[error("output `{path}`: {message}")]
    Output {
        /// The path.
        path: String,
        /// What the system said.
        message: String,
    },
}

/// The names of the six inertial state columns of `trajectory.csv`: `x_eme2000_m` … `vz_eme2000_mps`.
pub fn inertial_column_names() -> [String; 6] {
    let tag = INERTIAL_COLUMN_TAG;
    [
        format!("x_{tag}_m"),
        format!("y_{tag}_m"),
        format!("z_{tag}_m"),
        format!("vx_{tag}_mps"),
        format!("vy_{tag}_mps"),
        format!("vz_{tag}_mps"),
    ]
}

impl RunData {
    /// Every satellite's inertial track from the trajectory table, ordered by satellite index. A
    /// satellite removed during the run has a track that ends at its last recorded row. Refused (naming
    /// the file) when the run wrote no trajectory, when an inertial column is missing, or when a row has
    /// no inertial state; ids and times were checked by [`RunData::read`].
    pub fn inertial_tracks(&self) -> Result<Vec<InertialTrack>, RunDataError> {
        let path =
            (self.trajectory_path.clone()).unwrap_or_else(|| self.dir.join("trajectory.csv"));
        let fail = |message: String| RunDataError {
            path: path.display().to_string(),
            message,
        };
        let table = self.trajectory.as_ref().ok_or_else(|| {
            fail(
                "not found: the run wrote no trajectory ([output] trajectory = false); the OEM and CZML \
                 exports need it"
                    .into(),
            )
        })?;
        let column = |name: &str| {
            table
                .column(name)
                .ok_or_else(|| fail(format!("has no `{name}` column")))
        };
        let t_s = column("t_s")?;
        let ids = column("id")?;
        let names = inertial_column_names();
        let state_columns: Vec<&[f64]> =
            names.iter().map(|n| column(n)).collect::<Result<_, _>>()?;
        let mut tracks: BTreeMap<usize, InertialTrack> = BTreeMap::new();
        for row in 0..table.rows() {
            let state: [f64; 6] = std::array::from_fn(|k| state_columns[k][row]);
            if let Some(k) = (0..6).find(|&k| !state[k].is_finite()) {
                return Err(fail(format!(
                    "{}: `{}` has no value (the OEM and CZML exports need the inertial state in every \
                     row)",
                    super::run_data::row_name(&path, row),
                    names[k]
                )));
            }
            let id = ids[row] as usize;
            let track = tracks.entry(id).or_insert_with(|| InertialTrack {
                id,
                t_s: Vec::new(),
                states: Vec::new(),
            });
            track.t_s.push(t_s[row]);
            track.states.push(state);
        }
        if tracks.is_empty() {
            return Err(fail("has no rows".into()));
        }
        Ok(tracks.into_values().collect())
    }
}

/// Writes `bytes` to `path` whole: into `path` + `.partial` first, then renamed, so a failure never
/// leaves a partial file under the final name (and the temporary file is removed).
pub fn write_whole(path: &Path, bytes: &[u8]) -> Result<(), ExportError> {
    use std::io::Write as _;
    let mut tmp_name = path.as_os_str().to_owned();
    tmp_name.push(".partial");
    let tmp = PathBuf::from(tmp_name);
    let fail = |p: &Path, e: std::io::Error| ExportError::Output {
        path: p.display().to_string(),
        message: e.to_string(),
    };
    let written = std::fs::File::create(&tmp)
        .and_then(|mut file| file.write_all(bytes).and_then(|_| file.sync_all()))
        .map_err(|e| fail(&tmp, e))
        .and_then(|_| std::fs::rename(&tmp, path).map_err(|e| fail(path, e)));
    if written.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    written
}

/// Creates a directory for export files (and its parents) if it does not exist.
pub fn create_dir(dir: &Path) -> Result<(), ExportError> {
    std::fs::create_dir_all(dir).map_err(|e| ExportError::Output {
        path: dir.display().to_string(),
        message: e.to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn write_whole_leaves_no_partial_file() {
        let dir = std::env::temp_dir().join(format!("satflock-whole-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("a.txt");
        write_whole(&path, b"abc").unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "abc");
        assert!(!dir.join("a.txt.partial").exists());
        let missing = dir.join("no-such-dir").join("b.txt");
        assert!(matches!(
            write_whole(&missing, b"x"),
            Err(ExportError::Output { .. })
        ));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
