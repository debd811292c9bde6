//! A [`Recorder`] that streams snapshots to `metrics.csv` (one row per recording time: [`METRICS_HEADER`],
//! then the threat and obstacle monitor columns where the scenario has threats or obstacles, then the
//! law's own metrics) and, optionally, `trajectory.csv` (one row per live satellite per recording time:
//! [`TRAJECTORY_HEADER`], then the laws' per-satellite outputs). Each snapshot is flushed as soon as it
//! is written, so the files are complete, valid CSV up to the last recorded time even if a run stops.
//!
//! Whole records: each snapshot's rows are formatted into one buffer per file and handed to the system in
//! one `write` (no `BufWriter` splitting a row across flushes), so a process killed outright (SIGKILL)
//! loses whole records at the end of a file, never part of a row. A value that does not exist (NaN: a
//! ratio at t = 0, a metric of an empty set) is an empty cell, never `NaN`.

use std::fs::File;
use std::io::Write;
use std::path::Path;

use crate::swarm::{Recorder, Snapshot};
use crate::time::{self, Epoch};

/// Columns of `metrics.csv` (`time_utc`: the instant, ISO 8601 UTC, see [`crate::time`]).
pub const METRICS_HEADER: &[&str] = &[
    "t_s",
    "time_utc",
    "n",
    "r_o_x_m",
    "r_o_y_m",
    "r_o_z_m",
    "v_o_x_mps",
    "v_o_y_mps",
    "v_o_z_mps",
    "d_max_m",
    "diameter_m",
    "d_min_m",
    "uniformity_l",
    "min_separation_m",
    "collisions",
    "delta_v_max_mps",
    "delta_v_mean_mps",
    "delta_v_x_mean_mps",
    "delta_v_y_mean_mps",
    "delta_v_z_mean_mps",
];

/// Columns of `trajectory.csv`: elapsed time and UTC instant, Hill LVLH relative to the LVLH origin, then
/// the inertial frame ([`crate::output::frames::INERTIAL_FRAME`]), then the delta-v ledger.
pub const TRAJECTORY_HEADER: &[&str] = &[
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

/// Columns of `metrics.csv` with threats: the swarm's smallest distance to any threat so far (continuous
/// closest approach) and the entries into danger spheres so far.
pub const THREAT_COLUMNS: &[&str] = &["min_threat_distance_m", "threat_incursions"];

/// Columns of `metrics.csv` with obstacles: the smallest clearance to an obstacle's surface so far
/// (negative: inside) and the entries into obstacles so far.
pub const OBSTACLE_COLUMNS: &[&str] = &["min_obstacle_clearance_m", "obstacle_incursions"];

/// The variable columns of a run's CSV files.
#[derive(Clone, Debug, Default)]
pub struct CsvColumns {
    /// Whether the scenario has threats ([`THREAT_COLUMNS`]).
    pub threats: bool,
    /// Whether the scenario has obstacles ([`OBSTACLE_COLUMNS`]).
    pub obstacles: bool,
    /// Law metric columns of `metrics.csv` (every law the run can switch to).
    pub law_metrics: Vec<&'static str>,
    /// Per-satellite law output columns of `trajectory.csv`.
    pub law_outputs: Vec<&'static str>,
}

/// Streams snapshots to CSV files in a directory.
pub struct CsvRecorder {
    metrics: File,
    columns: CsvColumns,
    trajectory: Option<File>,
    epoch: Epoch,
    line: String,
    block: String,
}

impl CsvRecorder {
    /// Creates `dir/metrics.csv` and, if asked, `dir/trajectory.csv`, with the variable `columns`, and
    /// writes their headers; `epoch` is the instant of t = 0 (for the `time_utc` column).
    pub fn create(
        dir: &Path,
        write_trajectory: bool,
        columns: CsvColumns,
        epoch: Epoch,
    ) -> std::io::Result<Self> {
        let mut metrics = File::create(dir.join("metrics.csv"))?;
        let mut header: Vec<&str> = METRICS_HEADER.to_vec();
        if columns.threats {
            header.extend_from_slice(THREAT_COLUMNS);
        }
        if columns.obstacles {
            header.extend_from_slice(OBSTACLE_COLUMNS);
        }
        header.extend_from_slice(&columns.law_metrics);
        metrics.write_all(format!("{}\n", header.join(",")).as_bytes())?;
        let trajectory = if write_trajectory {
            let mut t = File::create(dir.join("trajectory.csv"))?;
            let mut header: Vec<&str> = TRAJECTORY_HEADER.to_vec();
            header.extend_from_slice(&columns.law_outputs);
            t.write_all(format!("{}\n", header.join(",")).as_bytes())?;
            Some(t)
        } else {
            None
        };
        Ok(Self {
            metrics,
            columns,
            trajectory,
            epoch,
            line: String::with_capacity(512),
            block: String::new(),
        })
    }
}

/// Appends an optional value: the number, or an empty cell.
fn push_optional(line: &mut String, value: Option<f64>) {
    match value {
        Some(v) => push(line, v),
        None => line.push(','),
    }
}

/// Formats a float so that it reads back to the same value (Rust's shortest round-trip form); NaN (a
/// value that does not exist) is an empty cell.
fn push(line: &mut String, value: f64) {
    use std::fmt::Write as _;
    line.push(',');
    if value.is_finite() {
        let _ = write!(line, "{value}");
    } else if value.is_nan() {
        // Empty cell.
    } else if value > 0.0 {
        line.push_str("inf");
    } else {
        line.push_str("-inf");
    }
}

impl Recorder for CsvRecorder {
    fn record(&mut self, s: &Snapshot<'_>) -> std::io::Result<()> {
        use std::fmt::Write as _;
        let line = &mut self.line;
        line.clear();
        let utc = time::utc_iso(time::at(self.epoch, s.time_s));
        let _ = write!(line, "{},{utc}", s.time_s);
        let live: Vec<usize> = (0..s.active.len()).filter(|&i| s.active[i]).collect();
        let _ = write!(line, ",{}", live.len());
        match &s.five_elements {
            Some(e) => {
                for v in e.r_o_m.iter().chain(e.v_o_mps.iter()) {
                    push(line, *v);
                }
                for v in [e.d_max_m, e.diameter_m, e.d_min_m, e.uniformity_l] {
                    push(line, v);
                }
            }
            None => line.push_str(&",".repeat(10)),
        }
        push(line, s.min_separation_m);
        let _ = write!(line, ",{}", s.collisions);
        let count = live.len().max(1) as f64;
        let max = live.iter().map(|&i| s.delta_v_mps[i]).fold(0.0, f64::max);
        let mean = live.iter().map(|&i| s.delta_v_mps[i]).sum::<f64>() / count;
        push(line, max);
        push(line, mean);
        for k in 0..3 {
            push(
                line,
                live.iter().map(|&i| s.delta_v_axes_mps[i][k]).sum::<f64>() / count,
            );
        }
        let env = &s.environment;
        if self.columns.threats {
            push_optional(line, env.min_threat_distance_m);
            let _ = write!(line, ",{}", env.threat_incursions);
        }
        if self.columns.obstacles {
            push_optional(line, env.min_obstacle_clearance_m);
            let _ = write!(line, ",{}", env.obstacle_incursions);
        }
        // Law metrics: a value where the running law has the column, empty where it does not.
        for column in &self.columns.law_metrics {
            match s.law_metric_names.iter().position(|n| n == column) {
                Some(k) => push(line, s.law_metrics[k]),
                None => line.push(','),
            }
        }
        line.push('\n');
        self.metrics.write_all(line.as_bytes())?;

        if let Some(t) = &mut self.trajectory {
            let line = &mut self.block;
            line.clear();
            for &i in &live {
                let _ = write!(line, "{},{utc},{}", s.time_s, i);
                let r = &s.relative_states[i];
                let e = &s.inertial_states[i];
                for v in r
                    .position_m
                    .iter()
                    .chain(r.velocity_mps.iter())
                    .chain(e.position_m.iter())
                    .chain(e.velocity_mps.iter())
                {
                    push(line, *v);
                }
                push(line, s.delta_v_mps[i]);
                let k = s.law_output_names.len();
                for column in &self.columns.law_outputs {
                    match s.law_output_names.iter().position(|n| n == column) {
                        Some(j) => push(line, s.law_outputs[i * k + j]),
                        None => line.push(','),
                    }
                }
                line.push('\n');
            }
            // The whole record in one piece.
            t.write_all(line.as_bytes())?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regress_nan_is_an_empty_cell_never_nan() {
        let mut line = String::from("0");
        push(&mut line, f64::NAN);
        push(&mut line, 1.5);
        push(&mut line, f64::INFINITY);
        push_optional(&mut line, None);
        push(&mut line, -f64::NAN);
        assert_eq!(line, "0,,1.5,inf,,");
        assert!(!line.to_ascii_lowercase().contains("nan"));
    }
}
