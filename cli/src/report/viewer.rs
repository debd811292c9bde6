//! The data of the report's 3-D view: the trajectory's Hill LVLH positions (and the law's per-satellite
//! output columns, to colour the satellites by) cut down to a budget so that the page stays usable for
//! 1 000 satellites over 10 000 recorded times, packed as little-endian `f32` in base64.
//!
//! The cut is deterministic: at most [`MAX_SATELLITES`] satellites, chosen evenly by index
//! (`floor(j n / M)` for j = 0 … M − 1), and every k-th recorded time from t = 0, with k the smallest
//! stride that keeps the floats (3 positions plus one per colour column, per satellite and time) within
//! [`MAX_FLOATS`] and the times within [`MAX_TIMES`]. A satellite without a row at a kept time (removed
//! from the swarm, or not recorded) has NaN there; the page draws nothing for it. The trajectory is one
//! [`satflock::output::RunData`] checked (ids below the summary's `n_satellites`, rows in time order);
//! memory follows the rows and the kept samples, never `n_satellites` itself.

use base64::Engine as _;
use serde::Serialize;

use satflock::output::Table;

/// Most floats the page carries (8 MB of `f32`, about 10.7 MB of base64).
pub const MAX_FLOATS: usize = 2_000_000;

/// Most satellites the page shows.
pub const MAX_SATELLITES: usize = 1_000;

/// Most times the page shows (a slider step stays meaningful).
pub const MAX_TIMES: usize = 5_000;

/// The trajectory column after which the law's per-satellite outputs follow.
const LAST_FIXED_COLUMN: &str = "delta_v_mps";

/// What the view keeps of a trajectory.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Decimation {
    /// The satellite indices kept, ascending.
    pub satellites: Vec<usize>,
    /// Every `time_stride`-th recorded time is kept, from the first.
    pub time_stride: usize,
    /// Number of times kept.
    pub kept_times: usize,
}

impl Decimation {
    /// The cut for `n_satellites` satellites over `n_times` recorded times, with
    /// `floats_per_sample` floats per satellite and time.
    pub fn plan(n_satellites: usize, n_times: usize, floats_per_sample: usize) -> Self {
        let m = n_satellites.min(MAX_SATELLITES);
        let satellites = (0..m)
            .map(|j| (j as u128 * n_satellites as u128 / m as u128) as usize)
            .collect();
        let per_time = (m * floats_per_sample).max(1);
        let max_times = (MAX_FLOATS / per_time).clamp(1, MAX_TIMES);
        let time_stride = n_times.div_ceil(max_times).max(1);
        Self {
            satellites,
            time_stride,
            kept_times: n_times.div_ceil(time_stride),
        }
    }
}

/// A law output column, per kept time and satellite.
#[derive(Clone, Debug, Serialize)]
pub struct ColourColumn {
    /// The trajectory column's name.
    pub name: String,
    /// `[time][satellite]` as little-endian `f32`, base64 (NaN: no value).
    pub values_f32le: String,
}

/// The view's data, as embedded in the page (JSON).
#[derive(Clone, Debug, Serialize)]
pub struct ViewerData {
    /// Satellites in the run (indices 0 … n − 1).
    pub n_satellites_recorded: usize,
    /// Distinct recording times in the trajectory.
    pub n_times_recorded: usize,
    /// Every `time_stride`-th recorded time is kept.
    pub time_stride: usize,
    /// The satellite indices kept, in the order of the data.
    pub satellite_ids: Vec<usize>,
    /// The kept times, elapsed since the epoch \[s\].
    pub times_s: Vec<f64>,
    /// The kept times in UTC (ISO 8601).
    pub times_utc: Vec<String>,
    /// Positions `[time][satellite][x, y, z]`, Hill LVLH \[m\], as little-endian `f32`, base64.
    pub positions_lvlh_m_f32le: String,
    /// The law's per-satellite output columns.
    pub colour_columns: Vec<ColourColumn>,
}

/// A column of a checked trajectory (the law's columns are named from the table itself; the fixed
/// ones are required by [`Table::check_trajectory`]).
fn column<'a>(table: &'a Table, name: &str) -> &'a [f64] {
    table.column(name).unwrap_or_default()
}

fn encode(values: &[f32]) -> String {
    let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    base64::engine::general_purpose::STANDARD.encode(bytes)
}

impl ViewerData {
    /// The view's data from a trajectory table checked by [`satflock::output::RunData::read`], the
    /// run's satellite count (ids run from 0 below it) and a function giving the UTC text of an
    /// elapsed time.
    pub fn from_trajectory(
        table: &Table,
        n_satellites: usize,
        utc: impl Fn(f64) -> String,
    ) -> Self {
        let t = column(table, "t_s");
        let id = column(table, "id");
        let xyz = [
            column(table, "x_lvlh_m"),
            column(table, "y_lvlh_m"),
            column(table, "z_lvlh_m"),
        ];
        let names = table.names();
        let law_columns: Vec<&str> = names
            .iter()
            .position(|n| n == LAST_FIXED_COLUMN)
            .map_or(&names[..0], |k| &names[k + 1..])
            .iter()
            .map(String::as_str)
            .collect();
        let n = n_satellites;
        let mut time_index = Vec::with_capacity(t.len());
        let mut times = Vec::new();
        for &ti in t {
            if times.last() != Some(&ti) {
                times.push(ti);
            }
            time_index.push(times.len() - 1);
        }
        let floats_per_sample = 3 + law_columns.len();
        let plan = Decimation::plan(n, times.len(), floats_per_sample);
        let m = plan.satellites.len();
        let samples = plan.kept_times * m;
        let mut positions = vec![f32::NAN; 3 * samples];
        let mut outputs = vec![vec![f32::NAN; samples]; law_columns.len()];
        let law_values: Vec<&[f64]> = law_columns.iter().map(|name| column(table, name)).collect();
        for row in 0..t.len() {
            let ti = time_index[row];
            // The kept satellites are sorted: a binary search, not a table as long as n_satellites.
            let Ok(k) = plan.satellites.binary_search(&(id[row] as usize)) else {
                continue;
            };
            if ti % plan.time_stride != 0 {
                continue;
            }
            let sample = (ti / plan.time_stride) * m + k;
            for (axis, values) in xyz.iter().enumerate() {
                positions[3 * sample + axis] = values[row] as f32;
            }
            for (out, values) in outputs.iter_mut().zip(&law_values) {
                out[sample] = values[row] as f32;
            }
        }
        let times_s: Vec<f64> = times.iter().step_by(plan.time_stride).copied().collect();
        Self {
            n_satellites_recorded: n,
            n_times_recorded: times.len(),
            time_stride: plan.time_stride,
            satellite_ids: plan.satellites,
            times_utc: times_s.iter().map(|&t| utc(t)).collect(),
            times_s,
            positions_lvlh_m_f32le: encode(&positions),
            colour_columns: law_columns
                .iter()
                .zip(&outputs)
                .map(|(name, values)| ColourColumn {
                    name: name.to_string(),
                    values_f32le: encode(values),
                })
                .collect(),
        }
    }

    /// One sentence saying what the view keeps.
    pub fn kept_sentence(&self) -> String {
        let sats = self.satellite_ids.len();
        let times = self.times_s.len();
        let mut text = format!(
            "Showing {sats} of {} satellites at {times} of {} recorded times",
            self.n_satellites_recorded, self.n_times_recorded
        );
        if sats < self.n_satellites_recorded || self.time_stride > 1 {
            text.push_str(&format!(
                " (the page carries at most {MAX_FLOATS} numbers: {}every {} recorded time from t = 0)",
                if sats < self.n_satellites_recorded {
                    format!("{sats} satellites evenly spread over the indices, ")
                } else {
                    String::new()
                },
                ordinal(self.time_stride)
            ));
        }
        text.push('.');
        text
    }
}

/// "1st", "2nd", "3rd", "4th", … "11th", "12th", "13th", "21st".
fn ordinal(k: usize) -> String {
    let suffix = match (k % 10, k % 100) {
        (_, 11..=13) => "th",
        (1, _) => "st",
        (2, _) => "nd",
        (3, _) => "rd",
        _ => "th",
    };
    format!("{k}{suffix}")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn decode(text: &str) -> Vec<f32> {
        // An independent reading of the packing: 4 bytes per value, little-endian.
        let bytes = base64::engine::general_purpose::STANDARD
            .decode(text)
            .unwrap();
        bytes
            .chunks_exact(4)
            .map(|c| {
                f32::from_bits(
                    u32::from(c[0])
                        | u32::from(c[1]) << 8
                        | u32::from(c[2]) << 16
                        | u32::from(c[3]) << 24,
                )
            })
            .collect()
    }

    #[test]
    fn a_large_run_fits_the_budget_and_keeps_even_satellites_and_times() {
        // 1 000 satellites over 10 001 recorded times, positions only: 666 times fit (2e6 / 3 000), so
        // every 16th time (626 times; every 15th would keep 667).
        let plan = Decimation::plan(1_000, 10_001, 3);
        assert_eq!(plan.satellites, (0..1_000).collect::<Vec<_>>());
        assert_eq!(plan.time_stride, 16);
        assert_eq!(plan.kept_times, 626);
        assert!(plan.kept_times * 1_000 * 3 <= MAX_FLOATS);
        // 10 000 satellites: every 10th index.
        let plan = Decimation::plan(10_000, 11, 4);
        assert_eq!(plan.satellites.len(), MAX_SATELLITES);
        assert!(plan
            .satellites
            .iter()
            .enumerate()
            .all(|(j, &s)| s == 10 * j));
        assert_eq!((plan.time_stride, plan.kept_times), (1, 11));
        // 1 500 satellites: 1 000 distinct indices from 0, spread evenly (gaps of 1 or 2).
        let plan = Decimation::plan(1_500, 3, 3);
        assert_eq!(plan.satellites.len(), 1_000);
        assert!(plan
            .satellites
            .windows(2)
            .all(|w| (1..=2).contains(&(w[1] - w[0]))));
        // Few satellites, many times: the time cap.
        let plan = Decimation::plan(1, 12_000, 3);
        assert_eq!((plan.time_stride, plan.kept_times), (3, 4_000));
        // Nothing recorded.
        let plan = Decimation::plan(0, 0, 3);
        assert_eq!((plan.satellites.len(), plan.kept_times), (0, 0));
    }

    #[test]
    fn a_removed_satellite_has_no_position_after_its_last_row() {
        // Satellite 1 has no row at t = 2: NaN there; satellite 0 keeps its values; es_mode follows.
        let names = [
            "t_s",
            "id",
            "x_lvlh_m",
            "y_lvlh_m",
            "z_lvlh_m",
            "delta_v_mps",
            "es_mode",
        ];
        let rows: [[f64; 7]; 5] = [
            [0.0, 0.0, 1.0, 2.0, 3.0, 0.0, 0.0],
            [0.0, 1.0, 4.0, 5.0, 6.0, 0.0, 1.0],
            [1.0, 0.0, 1.5, 2.5, 3.5, 0.1, 0.0],
            [1.0, 1.0, 4.5, 5.5, 6.5, 0.1, 2.0],
            [2.0, 0.0, 7.0, 8.0, 9.0, 0.2, 1.0],
        ];
        let table = Table::new(
            names.iter().map(|n| n.to_string()).collect(),
            (0..7)
                .map(|c| rows.iter().map(|r| r[c]).collect())
                .collect(),
        );
        let data = ViewerData::from_trajectory(&table, 2, |t| format!("T{t}"));
        assert_eq!(data.times_s, [0.0, 1.0, 2.0]);
        assert_eq!(data.times_utc, ["T0", "T1", "T2"]);
        let p = decode(&data.positions_lvlh_m_f32le);
        assert_eq!(p.len(), 3 * 2 * 3);
        assert_eq!(
            &p[..12],
            &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 1.5, 2.5, 3.5, 4.5, 5.5, 6.5]
        );
        assert_eq!(&p[12..15], &[7.0, 8.0, 9.0]);
        assert!(p[15..].iter().all(|v| v.is_nan()));
        assert_eq!(data.colour_columns.len(), 1);
        assert_eq!(data.colour_columns[0].name, "es_mode");
        let mode = decode(&data.colour_columns[0].values_f32le);
        assert_eq!(&mode[..5], &[0.0, 1.0, 0.0, 2.0, 1.0]);
        assert!(mode[5].is_nan());
        assert_eq!(
            data.kept_sentence(),
            "Showing 2 of 2 satellites at 3 of 3 recorded times."
        );
    }

    #[test]
    fn the_sentence_says_what_was_cut() {
        assert_eq!(ordinal(1), "1st");
        assert_eq!(ordinal(12), "12th");
        assert_eq!(ordinal(22), "22nd");
        assert_eq!(ordinal(103), "103rd");
    }
}
