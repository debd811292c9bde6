//! The columns of a run's two tables and the values of a snapshot's rows, computed in one place for
//! every writer (CSV and Parquet format the same [`Record`]).
//!
//! `metrics` has one row per recording time: [`METRICS_HEADER`], then the threat and obstacle monitor
//! columns where the scenario has threats or obstacles, then the law's own metrics. `trajectory` has one
//! row per live satellite per recording time: [`TRAJECTORY_HEADER`], then the laws' per-satellite
//! outputs. Every table starts with `t_s` (elapsed SI seconds) and `time_utc` (that instant, ISO 8601
//! UTC, see [`crate::time`]); a [`Record`] holds the values of the columns after those two.
//!
//! A value that does not exist (a ratio at t = 0, a metric of an empty set, a law column while a law
//! without it runs, the five elements of fewer than two satellites) is NaN in a [`Record`]: an empty CSV
//! cell, a Parquet null.

use crate::output::frames;
use crate::swarm::{Simulation, Snapshot};
use crate::time::{self, Epoch};

/// Columns of `metrics` (`time_utc`: the instant, ISO 8601 UTC, see [`crate::time`]).
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

/// Columns of `trajectory`: elapsed time and UTC instant, Hill LVLH relative to the LVLH origin, then
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

/// Columns of `metrics` with threats: the swarm's smallest distance to any threat so far (continuous
/// closest approach) and the entries into danger spheres so far.
pub const THREAT_COLUMNS: &[&str] = &["min_threat_distance_m", "threat_incursions"];

/// Columns of `metrics` with obstacles: the smallest clearance to an obstacle's surface so far
/// (negative: inside) and the entries into obstacles so far.
pub const OBSTACLE_COLUMNS: &[&str] = &["min_obstacle_clearance_m", "obstacle_incursions"];

/// Columns holding whole counts (written as integers; never missing).
const COUNT_COLUMNS: &[&str] = &[
    "n",
    "collisions",
    "id",
    "threat_incursions",
    "obstacle_incursions",
    "drag_switches",
    "saturated",
];

/// Columns whose vector components are in the inertial frame besides the `*_eme2000_*` ones: the five
/// elements' centroid position and velocity.
const INERTIAL_COLUMNS: &[&str] = &[
    "r_o_x_m",
    "r_o_y_m",
    "r_o_z_m",
    "v_o_x_mps",
    "v_o_y_mps",
    "v_o_z_mps",
];

/// Columns whose components are along the Hill LVLH axes besides the `*_lvlh_*` ones: the mean delta-v
/// ledger per axis, the commanded and applied accelerations of the control history.
const LVLH_COLUMNS: &[&str] = &[
    "delta_v_x_mean_mps",
    "delta_v_y_mean_mps",
    "delta_v_z_mean_mps",
    "ux_cmd_mps2",
    "uy_cmd_mps2",
    "uz_cmd_mps2",
    "ux_mps2",
    "uy_mps2",
    "uz_mps2",
];

/// Units by the last `_` part of a column name (SI and the few non-SI units the laws report).
const UNIT_SUFFIXES: &[(&str, &str)] = &[
    ("m", "m"),
    ("mps", "m/s"),
    ("mps2", "m/s^2"),
    ("m2", "m^2"),
    ("s", "s"),
    ("h", "h"),
    ("deg", "deg"),
    ("rad", "rad"),
    ("kg", "kg"),
];

/// What a column holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColumnKind {
    /// A real number; NaN (a value that does not exist) is an empty cell or a null.
    Float,
    /// A whole count (satellites, pairs, entries, an id).
    Count,
    /// The `time_utc` text (ISO 8601 UTC).
    Text,
}

/// One column of a table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Column {
    /// Its name (with the unit as its last `_` part where it has one).
    pub name: &'static str,
    /// What it holds.
    pub kind: ColumnKind,
}

impl ColumnKind {
    /// What the column named `name` holds (for readers of a table, which know the names only).
    pub fn of(name: &str) -> Self {
        if name == "time_utc" {
            ColumnKind::Text
        } else if COUNT_COLUMNS.contains(&name) {
            ColumnKind::Count
        } else {
            ColumnKind::Float
        }
    }
}

impl Column {
    fn new(name: &'static str) -> Self {
        Self {
            name,
            kind: ColumnKind::of(name),
        }
    }

    /// The column's unit, read from its name: `m`, `m/s`, `s`, `deg`, …; `1` for counts and
    /// dimensionless numbers; `UTC` for `time_utc` (an ISO 8601 instant).
    pub fn unit(&self) -> &'static str {
        if self.kind == ColumnKind::Text {
            return frames::TIME_SYSTEM;
        }
        let suffix = self.name.rsplit('_').next().unwrap_or_default();
        UNIT_SUFFIXES
            .iter()
            .find(|(s, _)| *s == suffix)
            .map_or("1", |(_, unit)| unit)
    }

    /// The frame of a vector component ([`frames::LVLH_FRAME`] or [`frames::INERTIAL_FRAME`]); `None`
    /// for scalars (distances, counts, times, law values).
    pub fn frame(&self) -> Option<&'static str> {
        let inertial_tag = format!("_{}_", frames::INERTIAL_COLUMN_TAG);
        if self.name.contains("_lvlh_") || LVLH_COLUMNS.contains(&self.name) {
            Some(frames::LVLH_FRAME)
        } else if self.name.contains(&inertial_tag) || INERTIAL_COLUMNS.contains(&self.name) {
            Some(frames::INERTIAL_FRAME)
        } else {
            None
        }
    }
}

/// The variable columns of a run's tables.
#[derive(Clone, Debug, Default)]
pub struct OutputColumns {
    /// Whether the scenario has threats ([`THREAT_COLUMNS`]).
    pub threats: bool,
    /// Whether the scenario has obstacles ([`OBSTACLE_COLUMNS`]).
    pub obstacles: bool,
    /// Law metric columns of `metrics` (every law the run can switch to).
    pub law_metrics: Vec<&'static str>,
    /// Per-satellite law output columns of `trajectory`.
    pub law_outputs: Vec<&'static str>,
    /// Whether a satellite has drag attitudes: the drag area of every satellite in `trajectory`
    /// ([`DRAG_TRAJECTORY_COLUMN`]) and the drag changes so far in `metrics` ([`DRAG_METRIC_COLUMN`]).
    pub drag: bool,
    /// Whether the control history is recorded (`[output] control_history`): the commands and their
    /// saturation in `trajectory` ([`CONTROL_TRAJECTORY_COLUMNS`]) and their summary in `metrics`
    /// ([`CONTROL_METRIC_COLUMNS`]).
    pub control: bool,
}

/// The `trajectory` column of the drag area of each satellite \[m^2\] (runs with drag attitudes).
pub const DRAG_TRAJECTORY_COLUMN: &str = "drag_area_m2";
/// The `metrics` column of the drag-area changes of every satellite so far (runs with drag attitudes).
pub const DRAG_METRIC_COLUMN: &str = "drag_switches";

/// The `trajectory` columns of the control history (`[output] control_history`), per satellite: the
/// law's commanded acceleration before the actuator (`u*_cmd_mps2`) and the applied acceleration after
/// it (`u*_mps2`: saturation and failed axes; process noise not included), Hill LVLH axes \[m/s^2\],
/// and `saturated`, 1 where the actuator limited the command (the two differ), else 0. In sampled
/// control a row holds the command of the last control tick at or before its time (zeros at t = 0,
/// before the first tick); in continuous control the command evaluated at the row's state.
pub const CONTROL_TRAJECTORY_COLUMNS: &[&str] = &[
    "ux_cmd_mps2",
    "uy_cmd_mps2",
    "uz_cmd_mps2",
    "ux_mps2",
    "uy_mps2",
    "uz_mps2",
    "saturated",
];

/// The `metrics` columns of the control history: the fraction of the live satellites whose command
/// the actuator limited, and the mean norm of the live satellites' commanded accelerations \[m/s^2\]
/// (NaN without a live satellite).
pub const CONTROL_METRIC_COLUMNS: &[&str] = &["saturated_fraction", "mean_command_mps2"];

impl OutputColumns {
    /// The columns of a simulation's tables: threat and obstacle monitors where its scenario has
    /// threats or obstacles, and the metrics and outputs of every law it can run.
    pub fn of(simulation: &Simulation) -> Self {
        Self {
            threats: !simulation.config().threats.is_empty(),
            obstacles: !simulation.config().obstacles.is_empty(),
            law_metrics: simulation.law_metric_names(),
            law_outputs: simulation.law_output_names(),
            drag: simulation.has_drag_attitudes(),
            control: simulation.records_control_history(),
        }
    }

    /// The columns of `metrics`, in file order.
    pub fn metrics(&self) -> Vec<Column> {
        let mut names: Vec<&'static str> = METRICS_HEADER.to_vec();
        if self.threats {
            names.extend_from_slice(THREAT_COLUMNS);
        }
        if self.obstacles {
            names.extend_from_slice(OBSTACLE_COLUMNS);
        }
        if self.drag {
            names.push(DRAG_METRIC_COLUMN);
        }
        if self.control {
            names.extend_from_slice(CONTROL_METRIC_COLUMNS);
        }
        names.extend_from_slice(&self.law_metrics);
        names.into_iter().map(Column::new).collect()
    }

    /// The columns of `trajectory`, in file order.
    pub fn trajectory(&self) -> Vec<Column> {
        TRAJECTORY_HEADER
            .iter()
            .chain(self.drag.then_some(&DRAG_TRAJECTORY_COLUMN))
            .chain(CONTROL_TRAJECTORY_COLUMNS.iter().filter(|_| self.control))
            .chain(&self.law_outputs)
            .map(|n| Column::new(n))
            .collect()
    }
}

/// Which of the two tables a writer writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tables {
    /// `metrics`.
    pub metrics: bool,
    /// `trajectory`.
    pub trajectory: bool,
}

/// The rows of one recording time: the values of every column after `t_s` and `time_utc`, in column
/// order (counts as exact whole numbers, NaN where a value does not exist).
#[derive(Clone, Debug, Default)]
pub struct Record {
    /// Time since the scenario start \[s\].
    pub time_s: f64,
    /// That instant, ISO 8601 UTC.
    pub time_utc: String,
    /// The `metrics` row.
    pub metrics: Vec<f64>,
    /// The `trajectory` rows, one per live satellite, row after row ([`Self::trajectory_rows`]).
    pub trajectory: Vec<f64>,
    /// Values per `trajectory` row.
    pub trajectory_width: usize,
}

impl Record {
    /// Fills the record from a snapshot (reusing its buffers); the trajectory rows only if asked.
    pub fn fill(
        &mut self,
        columns: &OutputColumns,
        epoch: Epoch,
        s: &Snapshot<'_>,
        with_trajectory: bool,
    ) {
        self.time_s = s.time_s;
        self.time_utc = time::utc_iso(time::at(epoch, s.time_s));
        let live: Vec<usize> = (0..s.active.len()).filter(|&i| s.active[i]).collect();
        let m = &mut self.metrics;
        m.clear();
        m.push(live.len() as f64);
        match &s.five_elements {
            Some(e) => {
                m.extend(e.r_o_m.iter().chain(e.v_o_mps.iter()));
                m.extend([e.d_max_m, e.diameter_m, e.d_min_m, e.uniformity_l]);
            }
            None => m.extend([f64::NAN; 10]),
        }
        m.push(s.min_separation_m);
        m.push(s.collisions as f64);
        let count = live.len().max(1) as f64;
        m.push(live.iter().map(|&i| s.delta_v_mps[i]).fold(0.0, f64::max));
        m.push(live.iter().map(|&i| s.delta_v_mps[i]).sum::<f64>() / count);
        for k in 0..3 {
            m.push(live.iter().map(|&i| s.delta_v_axes_mps[i][k]).sum::<f64>() / count);
        }
        let env = &s.environment;
        if columns.threats {
            m.push(env.min_threat_distance_m.unwrap_or(f64::NAN));
            m.push(env.threat_incursions as f64);
        }
        if columns.obstacles {
            m.push(env.min_obstacle_clearance_m.unwrap_or(f64::NAN));
            m.push(env.obstacle_incursions as f64);
        }
        if columns.drag {
            m.push(s.drag_switches as f64);
        }
        // The control history is empty when the simulation does not record it (NaN then).
        let control = |i: usize| s.commanded_hill_mps2.get(i).zip(s.applied_hill_mps2.get(i));
        if columns.control {
            let (mut limited, mut norms, mut known) = (0usize, 0.0, 0usize);
            for &i in &live {
                if let Some((commanded, applied)) = control(i) {
                    limited += usize::from(commanded != applied);
                    norms += commanded.norm();
                    known += 1;
                }
            }
            let per = |x: f64| {
                if known > 0 {
                    x / known as f64
                } else {
                    f64::NAN
                }
            };
            m.push(per(limited as f64));
            m.push(per(norms));
        }
        // Law metrics: a value where the running law has the column, NaN where it does not.
        for column in &columns.law_metrics {
            m.push(
                s.law_metric_names
                    .iter()
                    .position(|n| n == column)
                    .map_or(f64::NAN, |k| s.law_metrics[k]),
            );
        }

        self.trajectory.clear();
        self.trajectory_width = TRAJECTORY_HEADER.len() - 2
            + usize::from(columns.drag)
            + if columns.control {
                CONTROL_TRAJECTORY_COLUMNS.len()
            } else {
                0
            }
            + columns.law_outputs.len();
        if !with_trajectory {
            return;
        }
        let t = &mut self.trajectory;
        t.reserve(live.len() * self.trajectory_width);
        let k = s.law_output_names.len();
        // Where each trajectory law column sits in the running law's outputs.
        let outputs: Vec<Option<usize>> = columns
            .law_outputs
            .iter()
            .map(|column| s.law_output_names.iter().position(|n| n == column))
            .collect();
        for &i in &live {
            t.push(i as f64);
            let r = &s.relative_states[i];
            let e = &s.inertial_states[i];
            t.extend(
                r.position_m
                    .iter()
                    .chain(r.velocity_mps.iter())
                    .chain(e.position_m.iter())
                    .chain(e.velocity_mps.iter()),
            );
            t.push(s.delta_v_mps[i]);
            if columns.drag {
                t.push(s.drag_areas_m2.get(i).copied().unwrap_or(f64::NAN));
            }
            if columns.control {
                match control(i) {
                    Some((commanded, applied)) => {
                        t.extend(commanded.iter().chain(applied.iter()));
                        t.push(f64::from(u8::from(commanded != applied)));
                    }
                    // A count is never missing: 0 where the history is unknown.
                    None => t.extend([
                        f64::NAN,
                        f64::NAN,
                        f64::NAN,
                        f64::NAN,
                        f64::NAN,
                        f64::NAN,
                        0.0,
                    ]),
                }
            }
            t.extend(
                outputs
                    .iter()
                    .map(|j| j.map_or(f64::NAN, |j| s.law_outputs[i * k + j])),
            );
        }
    }

    /// The `trajectory` rows (each [`Self::trajectory_width`] values).
    pub fn trajectory_rows(&self) -> std::slice::ChunksExact<'_, f64> {
        self.trajectory.chunks_exact(self.trajectory_width.max(1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_and_frames_come_from_the_names() {
        let columns = OutputColumns {
            threats: true,
            obstacles: false,
            law_metrics: vec!["ts_min_connectable_time_h", "ts_theta_p_min_deg"],
            law_outputs: vec!["es_mode"],
            drag: true,
            control: true,
        };
        let metrics = columns.metrics();
        let find = |cs: &[Column], name: &str| *cs.iter().find(|c| c.name == name).unwrap();
        let t = columns.trajectory();
        assert_eq!(find(&t, "x_lvlh_m").unit(), "m");
        assert_eq!(find(&t, "x_lvlh_m").frame(), Some(frames::LVLH_FRAME));
        assert_eq!(find(&t, "vz_eme2000_mps").unit(), "m/s");
        assert_eq!(find(&t, "vz_eme2000_mps").frame(), Some("EME2000"));
        assert_eq!(find(&t, "id").kind, ColumnKind::Count);
        assert_eq!(find(&t, "time_utc").kind, ColumnKind::Text);
        assert_eq!(find(&t, "time_utc").unit(), "UTC");
        assert_eq!(find(&t, "es_mode").unit(), "1");
        assert_eq!(find(&t, "t_s").unit(), "s");
        assert_eq!(find(&metrics, "r_o_x_m").frame(), Some("EME2000"));
        assert_eq!(
            find(&metrics, "delta_v_y_mean_mps").frame(),
            Some(frames::LVLH_FRAME)
        );
        assert_eq!(find(&metrics, "d_max_m").frame(), None);
        assert_eq!(find(&metrics, "threat_incursions").kind, ColumnKind::Count);
        assert_eq!(find(&metrics, "uniformity_l").unit(), "1");
        assert_eq!(find(&metrics, "ts_min_connectable_time_h").unit(), "h");
        assert_eq!(find(&metrics, "ts_theta_p_min_deg").unit(), "deg");
        assert_eq!(find(&t, "drag_area_m2").unit(), "m^2");
        assert_eq!(find(&metrics, "drag_switches").kind, ColumnKind::Count);
        assert_eq!(find(&t, "ux_cmd_mps2").unit(), "m/s^2");
        assert_eq!(find(&t, "uz_mps2").frame(), Some(frames::LVLH_FRAME));
        assert_eq!(find(&t, "saturated").kind, ColumnKind::Count);
        assert_eq!(find(&metrics, "mean_command_mps2").unit(), "m/s^2");
        assert_eq!(find(&metrics, "saturated_fraction").unit(), "1");
        assert_eq!(metrics.len(), METRICS_HEADER.len() + 2 + 1 + 2 + 2);
        assert_eq!(t.len(), TRAJECTORY_HEADER.len() + 1 + 7 + 1);
    }
}
