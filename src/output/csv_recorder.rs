//! A [`Recorder`] that streams snapshots to `metrics.csv` (one row per recording time, with the law's own
//! metrics as extra columns after [`METRICS_HEADER`]) and, optionally,
//! `trajectory.csv` (one row per live satellite per recording time). Each snapshot is flushed as soon as it
//! is written, so the files are complete, valid CSV up to the last recorded time even if a run stops.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

use crate::swarm::{Recorder, Snapshot};

/// Columns of `metrics.csv`.
pub const METRICS_HEADER: &[&str] = &[
    "t_s",
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

/// Columns of `trajectory.csv`: Hill LVLH relative to the LVLH origin, then ECI, then the delta-v ledger.
pub const TRAJECTORY_HEADER: &[&str] = &[
    "t_s",
    "id",
    "x_lvlh_m",
    "y_lvlh_m",
    "z_lvlh_m",
    "vx_lvlh_mps",
    "vy_lvlh_mps",
    "vz_lvlh_mps",
    "x_eci_m",
    "y_eci_m",
    "z_eci_m",
    "vx_eci_mps",
    "vy_eci_mps",
    "vz_eci_mps",
    "delta_v_mps",
];

/// Streams snapshots to CSV files in a directory.
pub struct CsvRecorder {
    metrics: BufWriter<File>,
    /// Law metric columns, in header order.
    law_columns: Vec<&'static str>,
    trajectory: Option<BufWriter<File>>,
    line: String,
}

impl CsvRecorder {
    /// Creates `dir/metrics.csv` (with the law metric columns `law_columns` after the standard ones) and,
    /// if asked, `dir/trajectory.csv`, and writes their headers.
    pub fn create(
        dir: &Path,
        write_trajectory: bool,
        law_columns: &[&'static str],
    ) -> std::io::Result<Self> {
        let mut metrics = BufWriter::new(File::create(dir.join("metrics.csv"))?);
        let mut header = METRICS_HEADER.join(",");
        for name in law_columns {
            header.push(',');
            header.push_str(name);
        }
        writeln!(metrics, "{header}")?;
        metrics.flush()?;
        let trajectory = if write_trajectory {
            let mut t = BufWriter::new(File::create(dir.join("trajectory.csv"))?);
            writeln!(t, "{}", TRAJECTORY_HEADER.join(","))?;
            t.flush()?;
            Some(t)
        } else {
            None
        };
        Ok(Self {
            metrics,
            law_columns: law_columns.to_vec(),
            trajectory,
            line: String::with_capacity(512),
        })
    }
}

/// Formats a float so that it reads back to the same value (Rust's shortest round-trip form).
fn push(line: &mut String, value: f64) {
    use std::fmt::Write as _;
    line.push(',');
    if value.is_finite() {
        let _ = write!(line, "{value}");
    } else if value.is_nan() {
        line.push_str("NaN");
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
        let _ = write!(line, "{}", s.time_s);
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
        // Law metrics: a value where the running law has the column, empty where it does not.
        for column in &self.law_columns {
            match s.law_metric_names.iter().position(|n| n == column) {
                Some(k) => push(line, s.law_metrics[k]),
                None => line.push(','),
            }
        }
        writeln!(self.metrics, "{line}")?;
        self.metrics.flush()?;

        if let Some(t) = &mut self.trajectory {
            for &i in &live {
                line.clear();
                let _ = write!(line, "{},{}", s.time_s, i);
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
                writeln!(t, "{line}")?;
            }
            t.flush()?;
        }
        Ok(())
    }
}
