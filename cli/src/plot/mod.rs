//! `satflock plot RUN_DIR`, also drawn by `satflock run` unless `--no-plots`: the figures of a run,
//! drawn from its run directory alone ([`satflock::output::RunData`]), each written as
//! `RUN_DIR/plots/NAME.png` and `RUN_DIR/plots/NAME.svg`.
//!
//! | figure | from | module |
//! | --- | --- | --- |
//! | `trajectories`: the relative motion in the three RTN/Hill projections (radial–along-track, along-track–cross-track, radial–cross-track) of all satellites or the chosen ones (`--satellites`), start and end, target formation, threats and obstacles where they meet the slab shown | `trajectory.csv`, `scene.json` | `tracks.rs` |
//! | `snapshots`: the formation in its main plane at t = 0, before each event (timed, or a condition event's firing) and at the end | `trajectory.csv`, `scene.json`, `scenario.toml`, `summary.json` | `tracks.rs` |
//! | `separations`: histogram of each satellite's nearest-neighbour distance at the last recording | `trajectory.csv` | `separation.rs` |
//! | `conjunctions` (runs with `[conjunctions]`): the conjunction timeline, each encounter's miss distance at its time of closest approach, by kind of secondary, with the threshold | `conjunctions.csv` / `.parquet`, `summary.json` | `conjunction.rs` |
//! | `swarm_metrics`: five elements, minimum separation, threat and obstacle monitors over time | `metrics.csv` | `series.rs` |
//! | `law_metrics`: every metric column of the law(s) | `metrics.csv` | `series.rs` |
//! | `delta_v`: Δv per satellite, cumulative mean and max over time | `summary.json`, `metrics.csv` | `delta_v.rs` |
//! | `drag` (runs with drag attitudes): phase, altitude and drag area over time | `trajectory.csv` | `drag.rs` |
//! | `control` (runs with `[output] control_history`): applied and commanded acceleration norms of the first satellites, saturation timeline | `trajectory.csv` | `control.rs` |
//!
//! A campaign's figure (`satflock campaign`, [`draw_campaign`]): `outcomes`, every headline outcome
//! against every varied parameter, from the campaign's table (`campaign.rs`).
//! [`overlay`] draws the figures of several runs at once (`satflock compare`: one metric, every law on
//! one axis) from curves its caller computes.
//!
//! Output is deterministic (same run directory, same bytes): no timestamps, tracks in id order, a fixed
//! embedded font (DejaVu Sans, `cli/assets/fonts/`, drawn by `ab_glyph` without system font libraries).
//! What a figure draws is capped, so its size does not grow with the run's files: swarms larger than
//! [`MAX_TRACKS`] satellites show an evenly spaced subsample of ids; each track keeps at most
//! [`MAX_TRACK_POINTS`] evenly spaced recordings (and its last), and each curve over time at most
//! [`MAX_SERIES_POINTS`]; at most [`MAX_SCENE_OBJECTS`] threats and as many obstacles are drawn (evenly
//! spaced by index). Each cut is said on the figure and on stderr ([`PlotReport::describe`]).

mod campaign;
mod conjunction;
mod control;
mod delta_v;
mod drag;
pub mod overlay;
mod separation;
mod series;
mod tracks;

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::coord::ranged1d::ValueFormatter;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};
use thiserror::Error;

use satflock::output::{RunData, RunDataError};

pub use campaign::{draw_campaign, PlotParameter};

/// Most satellites drawn as tracks; larger swarms show an evenly spaced subsample of ids.
pub const MAX_TRACKS: usize = 200;

/// Most recordings drawn per track (every k-th recording, and the last).
pub const MAX_TRACK_POINTS: usize = 1000;

/// Most points drawn per curve over time (every k-th recording, and the last).
pub const MAX_SERIES_POINTS: usize = 2000;

/// Most threats, and most obstacles, drawn in a figure (an evenly spaced subsample by index beyond).
pub const MAX_SCENE_OBJECTS: usize = 200;

/// The indices of an evenly spaced subsample of at most `max` of `total` items: `floor(k total / max)`
/// (all of them when `total <= max`).
pub(crate) fn evenly_spaced(total: usize, max: usize) -> Vec<usize> {
    if total <= max {
        (0..total).collect()
    } else {
        (0..max).map(|k| k * total / max).collect()
    }
}

/// The font every figure uses (registered under [`FONT`]).
const FONT_BYTES: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// Family name the embedded font is registered under.
const FONT: &str = "sans-serif";

/// Why the figures could not be drawn.
#[derive(Debug, Error)]
pub enum PlotError {
    /// The directory is not a readable run directory (the user's input).
    #[error(transparent)]
    RunData(#[from] RunDataError),
    /// A figure could not be drawn or written.
    #[error("{path}: {message}")]
    Write {
        /// The file or directory.
        path: String,
        /// What went wrong.
        message: String,
    },
    /// The satellites asked for are not in the run's trajectory (the user's input).
    #[error("{0}")]
    Satellites(String),
}

/// A drawing error inside one figure (turned into [`PlotError::Write`] naming the file).
#[derive(Debug)]
pub(crate) struct DrawError(String);

impl<E: std::error::Error + Send + Sync> From<DrawingAreaErrorKind<E>> for DrawError {
    fn from(e: DrawingAreaErrorKind<E>) -> Self {
        Self(e.to_string())
    }
}

/// What [`draw_run`] wrote.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlotReport {
    /// The files written (PNG and SVG of each figure), in drawing order.
    pub written: Vec<PathBuf>,
    /// Figures left out, with the reason (e.g. no `trajectory.csv`).
    pub skipped: Vec<(String, String)>,
    /// What the figures left out of the run's data (e.g. threats beyond [`MAX_SCENE_OBJECTS`]).
    pub cuts: Vec<String>,
}

impl PlotReport {
    /// One line for the terminal: how many figures went where, and which were left out and why.
    pub fn describe(&self, dir: &Path) -> String {
        let mut text = format!(
            "plots: {} figures (PNG and SVG) in {}",
            self.written.len() / 2,
            dir.join("plots").display()
        );
        for (name, why) in &self.skipped {
            text.push_str(&format!("; no {name}: {why}"));
        }
        for cut in &self.cuts {
            text.push_str(&format!("; {cut}"));
        }
        text
    }
}

/// One figure: its file name (without extension), size in pixels and drawing on any backend.
trait Figure {
    /// File name without extension.
    fn name(&self) -> &str;
    /// Width and height \[px\].
    fn size(&self) -> (u32, u32);
    /// Draws the whole figure on `root` (already filled white).
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), DrawError>;
}

/// Registers the embedded font once (text layout needs it for both PNG and SVG).
fn register_embedded_font() -> Result<(), PlotError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| register_font(FONT, FontStyle::Normal, FONT_BYTES).is_ok());
    if ok {
        Ok(())
    } else {
        Err(PlotError::Write {
            path: "cli/assets/fonts/DejaVuSans.ttf".into(),
            message: "the embedded font cannot be read".into(),
        })
    }
}

/// Reads the run directory `dir` and draws every figure it has the data for into `dir/plots/`.
pub fn draw_run(dir: &Path) -> Result<PlotReport, PlotError> {
    draw_run_of(dir, None)
}

/// [`draw_run`] with the tracks of the satellites `only` lists (all when `None`).
pub fn draw_run_of(dir: &Path, only: Option<&[usize]>) -> Result<PlotReport, PlotError> {
    let run = RunData::read(dir)?;
    register_embedded_font()?;
    let out = dir.join("plots");
    std::fs::create_dir_all(&out).map_err(|e| PlotError::Write {
        path: out.display().to_string(),
        message: e.to_string(),
    })?;
    let context = RunContext::new(&run);
    let mut report = PlotReport::default();
    match tracks::Tracks::read(&run, only).map_err(PlotError::Satellites)? {
        Some(tracks) => {
            report.cuts.extend(tracks::scene_cuts(&run.scene));
            write_figure(
                &out,
                &tracks::Trajectories::new(&context, &tracks),
                &mut report,
            )?;
            write_figure(
                &out,
                &tracks::Snapshots::new(&context, &tracks),
                &mut report,
            )?;
        }
        None => {
            for name in ["trajectories", "snapshots", "separations"] {
                report.skipped.push((
                    name.into(),
                    "the run wrote no trajectory.csv ([output] trajectory = false)".into(),
                ));
            }
        }
    }
    if let Some(figure) = separation::Separations::new(&context) {
        write_figure(&out, &figure, &mut report)?;
    }
    write_figure(&out, &series::SwarmMetrics::new(&context), &mut report)?;
    match series::LawMetrics::new(&context) {
        Some(figure) => write_figure(&out, &figure, &mut report)?,
        None => report.skipped.push((
            "law_metrics".into(),
            "the law records no metric columns".into(),
        )),
    }
    write_figure(&out, &delta_v::DeltaV::new(&context), &mut report)?;
    // Only for runs whose satellites have drag attitudes (not "skipped" elsewhere: it does not apply).
    if let Some(figure) = drag::Drag::new(&context) {
        write_figure(&out, &figure, &mut report)?;
    }
    // Only for runs that monitored conjunctions (`[conjunctions]`).
    if let Some(figure) = conjunction::Conjunctions::new(&context) {
        write_figure(&out, &figure, &mut report)?;
    }
    // Only for runs that recorded their control history (`[output] control_history`).
    if let Some(figure) = control::Control::new(&context) {
        write_figure(&out, &figure, &mut report)?;
    }
    Ok(report)
}

/// Draws `figure` as `out/NAME.png` and `out/NAME.svg`.
fn write_figure<F: Figure>(
    out: &Path,
    figure: &F,
    report: &mut PlotReport,
) -> Result<(), PlotError> {
    let png = out.join(format!("{}.png", figure.name()));
    let svg = out.join(format!("{}.svg", figure.name()));
    let failed = |path: &Path, e: DrawError| PlotError::Write {
        path: path.display().to_string(),
        message: e.0,
    };
    {
        let root = BitMapBackend::new(&png, figure.size()).into_drawing_area();
        draw_on(&root, figure)
            .and_then(|_| root.present().map_err(DrawError::from))
            .map_err(|e| failed(&png, e))?;
    }
    {
        let root = SVGBackend::new(&svg, figure.size()).into_drawing_area();
        draw_on(&root, figure)
            .and_then(|_| root.present().map_err(DrawError::from))
            .map_err(|e| failed(&svg, e))?;
    }
    report.written.push(png);
    report.written.push(svg);
    Ok(())
}

fn draw_on<DB: DrawingBackend, F: Figure>(
    root: &DrawingArea<DB, Shift>,
    figure: &F,
) -> Result<(), DrawError> {
    root.fill(&WHITE)?;
    figure.draw(root)
}

/// What every figure's title and time axis need from the run.
pub(crate) struct RunContext<'a> {
    /// The run.
    pub run: &'a RunData,
    /// Scenario name (summary `scenario`).
    pub scenario: String,
    /// `completed`, `interrupted` or `failed`, with the simulated time when not completed.
    pub status_note: Option<String>,
    /// The time axis: seconds, hours or days by the run's length.
    pub time: TimeAxis,
}

impl<'a> RunContext<'a> {
    fn new(run: &'a RunData) -> Self {
        let text = |key: &str| run.summary.get(key).and_then(|v| v.as_str());
        let number = |key: &str| run.summary.get(key).and_then(|v| v.as_f64());
        let status = text("status").unwrap_or("unknown");
        let simulated_s = number("simulated_s").unwrap_or(f64::NAN);
        let last_t = run
            .metrics
            .column("t_s")
            .and_then(|t| t.last().copied())
            .unwrap_or(0.0);
        let duration_s = number("duration_s").unwrap_or(last_t).max(last_t);
        Self {
            run,
            scenario: text("scenario").unwrap_or("run").to_string(),
            status_note: (status != "completed").then(|| {
                format!(
                    "{status} at t = {}",
                    TimeAxis::for_duration(simulated_s).label_value(simulated_s)
                )
            }),
            time: TimeAxis::for_duration(duration_s),
        }
    }

    /// A figure title: the scenario, what the figure shows, and the run's status if not completed.
    pub fn title(&self, what: &str) -> String {
        match &self.status_note {
            Some(note) => format!("{}: {what} (run {note})", self.scenario),
            None => format!("{}: {what}", self.scenario),
        }
    }

    /// The epoch of t = 0, for captions.
    pub fn epoch_note(&self) -> String {
        format!(
            "t = 0 at {}",
            satflock::time::utc_iso(self.run.epoch).replace(".000000Z", "Z")
        )
    }
}

/// The unit of a time axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct TimeAxis {
    /// Seconds per unit.
    pub seconds: f64,
    /// Unit symbol.
    pub unit: &'static str,
}

impl TimeAxis {
    /// Seconds up to 3 h, hours up to 3 days, days beyond.
    pub fn for_duration(duration_s: f64) -> Self {
        match duration_s {
            d if d > 3.0 * 86_400.0 => Self {
                seconds: 86_400.0,
                unit: "d",
            },
            d if d > 3.0 * 3_600.0 => Self {
                seconds: 3_600.0,
                unit: "h",
            },
            _ => Self {
                seconds: 1.0,
                unit: "s",
            },
        }
    }

    /// The axis label.
    pub fn label(&self) -> String {
        format!("t [{}]", self.unit)
    }

    /// `t_s` in this unit.
    pub fn value(&self, t_s: f64) -> f64 {
        t_s / self.seconds
    }

    /// `t_s` as text with its unit (e.g. `1000 s`, `2.5 h`).
    pub fn label_value(&self, t_s: f64) -> String {
        let v = self.value(t_s);
        if v == v.round() {
            format!("{v:.0} {}", self.unit)
        } else {
            format!("{} {}", trim_number(v, 3), self.unit)
        }
    }
}

/// A number with at most `decimals` decimals and no trailing zeros.
pub(crate) fn trim_number(v: f64, decimals: usize) -> String {
    let text = format!("{v:.decimals$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

/// A tick label: at most 6 decimals, no trailing zeros, scientific below 10⁻³ and from 10⁷.
pub(crate) fn tick(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && !(1e-3..1e7).contains(&a) {
        let text = format!("{v:.2e}");
        let (mantissa, exponent) = text.split_once('e').unwrap_or((&text, "0"));
        let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
        return format!("{mantissa}e{exponent}");
    }
    // + 0.0 turns −0 into 0.
    trim_number(v + 0.0, 6)
}

/// The axis label of a CSV column or a dotted outcome or parameter name: the name without its unit
/// suffix, and the unit in brackets (`d_max_m` → `d_max [m]`; `delta_v_mps.mean` → `delta_v.mean [m/s]`,
/// the unit of the last segment that has one; `law.damping_per_s` → `law.damping [1/s]`; no unit
/// suffix → `[-]`, a count or a ratio).
pub(crate) fn column_label(name: &str) -> String {
    const UNITS: &[(&str, &str)] = &[
        ("_kg_per_m_s2", "kg/(m s²)"),
        ("_kg_per_s", "kg/s"),
        ("_per_s2", "1/s²"),
        ("_per_s", "1/s"),
        ("_mps2", "m/s²"),
        ("_mps", "m/s"),
        ("_deg", "deg"),
        ("_rad", "rad"),
        ("_m", "m"),
        ("_s", "s"),
        ("_h", "h"),
    ];
    let segments: Vec<&str> = name.split('.').collect();
    for (k, segment) in segments.iter().enumerate().rev() {
        for (suffix, unit) in UNITS {
            if let Some(stem) = segment.strip_suffix(suffix) {
                let mut parts = segments.clone();
                parts[k] = stem;
                return format!("{} [{unit}]", parts.join("."));
            }
        }
    }
    format!("{name} [-]")
}

/// Font sizes \[px\].
pub(crate) mod size {
    /// Figure title.
    pub const TITLE: u32 = 24;
    /// Panel caption.
    pub const CAPTION: u32 = 17;
    /// Axis description.
    pub const AXIS: u32 = 15;
    /// Tick labels and legend.
    pub const TICKS: u32 = 13;
}

/// Panel layout \[px\]: margin around a chart and the sizes of its axis label areas.
pub(crate) const MARGIN: u32 = 12;
/// Height of the x label area (ticks and description).
pub(crate) const X_LABEL_AREA: u32 = 46;
/// Width of the y label area (ticks and description).
pub(crate) const Y_LABEL_AREA: u32 = 78;

/// A 2-D chart with f64 axes.
pub(crate) type Chart<'a, DB> = ChartContext<
    'a,
    DB,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// Draws `caption` at the top of `area` and builds a chart with the given ranges below it.
pub(crate) fn panel<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    x: Range<f64>,
    y: Range<f64>,
) -> Result<Chart<'a, DB>, DrawError> {
    Ok(ChartBuilder::on(area)
        .margin(MARGIN)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(Y_LABEL_AREA)
        .build_cartesian_2d(x, y)?)
}

/// Draws a figure's title (below a small top margin) and returns the area left below it.
pub(crate) fn figure_title<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    text: &str,
) -> Result<DrawingArea<DB, Shift>, DrawError> {
    Ok(root.margin(8, 0, 0, 0).titled(text, (FONT, size::TITLE))?)
}

/// Draws a panel caption and returns the area left below it.
pub(crate) fn caption<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    text: &str,
) -> Result<DrawingArea<DB, Shift>, DrawError> {
    Ok(area.titled(text, (FONT, size::CAPTION))?)
}

/// Draws the mesh, tick labels and axis descriptions of a chart (linear x; linear or logarithmic y).
pub(crate) fn axes<DB: DrawingBackend, Y>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<plotters::coord::types::RangedCoordf64, Y>>,
    x_desc: &str,
    y_desc: &str,
) -> Result<(), DrawError>
where
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .x_labels(6)
        .y_labels(6)
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .label_style((FONT, size::TICKS))
        .axis_desc_style((FONT, size::AXIS))
        .light_line_style(WHITE.mix(0.0))
        .bold_line_style(BLACK.mix(0.12))
        .draw()?;
    Ok(())
}

/// Draws the legend of a chart's labelled series.
pub(crate) fn legend<'a, DB: DrawingBackend + 'a, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<plotters::coord::types::RangedCoordf64, Y>>,
    position: SeriesLabelPosition,
) -> Result<(), DrawError>
where
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    chart
        .configure_series_labels()
        .position(position)
        .label_font((FONT, size::TICKS))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.5))
        .draw()?;
    Ok(())
}

/// A range holding every finite value of `values`, padded by 5 % (a flat or empty series gets a
/// range of ±1 about its value, or 0..1).
pub(crate) fn padded_range(values: impl IntoIterator<Item = f64>) -> Range<f64> {
    let (lo, hi) = values
        .into_iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if !lo.is_finite() {
        return 0.0..1.0;
    }
    if hi - lo <= 1e-12 * lo.abs().max(1.0) {
        let half = (lo.abs() * 0.1).max(1.0);
        return lo - half..hi + half;
    }
    let pad = 0.05 * (hi - lo);
    lo - pad..hi + pad
}

/// The text of a panel with nothing to draw, centred in it.
pub(crate) fn empty_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    text: &str,
) -> Result<(), DrawError> {
    let (w, h) = area.dim_in_pixel();
    let grey = BLACK.mix(0.6);
    let style = TextStyle::from((FONT, size::AXIS).into_font())
        .color(&grey)
        .pos(plotters::style::text_anchor::Pos::new(
            plotters::style::text_anchor::HPos::Center,
            plotters::style::text_anchor::VPos::Center,
        ));
    area.draw_text(text, &style, (w as i32 / 2, h as i32 / 2))?;
    Ok(())
}

/// Splits a series at its non-finite values into runs of finite points, keeping at most about
/// [`MAX_SERIES_POINTS`] of them: every k-th point, the first of each run and the last.
pub(crate) fn finite_runs(t: &[f64], v: &[f64]) -> Vec<Vec<(f64, f64)>> {
    let n = t.len().min(v.len());
    let stride = n.div_ceil(MAX_SERIES_POINTS).max(1);
    let mut runs = Vec::new();
    let mut current = Vec::new();
    for (k, (&t, &v)) in t.iter().zip(v).enumerate() {
        if t.is_finite() && v.is_finite() {
            if k % stride == 0 || k + 1 == n || current.is_empty() {
                current.push((t, v));
            }
        } else if !current.is_empty() {
            runs.push(std::mem::take(&mut current));
        }
    }
    if !current.is_empty() {
        runs.push(current);
    }
    runs
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn column_labels_name_their_units() {
        assert_eq!(column_label("d_max_m"), "d_max [m]");
        assert_eq!(column_label("delta_v_max_mps"), "delta_v_max [m/s]");
        assert_eq!(column_label("ts_theta_p_min_deg"), "ts_theta_p_min [deg]");
        assert_eq!(
            column_label("ts_min_connectable_time_h"),
            "ts_min_connectable_time [h]"
        );
        assert_eq!(column_label("uniformity_l"), "uniformity_l [-]");
        assert_eq!(column_label("collisions"), "collisions [-]");
        // Dotted campaign names: the unit of the last segment that has one.
        assert_eq!(column_label("delta_v_mps.mean"), "delta_v.mean [m/s]");
        assert_eq!(
            column_label("final.five_elements.d_max_m"),
            "final.five_elements.d_max [m]"
        );
        assert_eq!(column_label("law.stiffness_per_s2"), "law.stiffness [1/s²]");
        assert_eq!(column_label("law.damping_per_s"), "law.damping [1/s]");
        assert_eq!(column_label("law.k_f_kg_per_m_s2"), "law.k_f [kg/(m s²)]");
        assert_eq!(
            column_label("environment.threat_incursions"),
            "environment.threat_incursions [-]"
        );
    }

    #[test]
    fn time_axis_unit_follows_the_run_length() {
        assert_eq!(TimeAxis::for_duration(2000.0).unit, "s");
        assert_eq!(TimeAxis::for_duration(86_400.0).unit, "h");
        assert_eq!(TimeAxis::for_duration(10.0 * 86_400.0).unit, "d");
        assert_eq!(TimeAxis::for_duration(7200.0).label_value(1500.0), "1500 s");
        assert_eq!(
            TimeAxis::for_duration(86_400.0).label_value(5400.0),
            "1.5 h"
        );
    }

    #[test]
    fn tick_labels_are_short() {
        assert_eq!(tick(10000.0), "10000");
        assert_eq!(tick(0.30000000000000004), "0.3");
        assert_eq!(tick(-0.0), "0");
        assert_eq!(tick(2.5e-5), "2.5e-5");
        assert_eq!(tick(1.5e8), "1.5e8");
    }

    #[test]
    fn ranges_and_runs() {
        assert_eq!(padded_range([0.0, 10.0, f64::NAN]), -0.5..10.5);
        assert_eq!(padded_range([f64::NAN]), 0.0..1.0);
        assert_eq!(padded_range([3.0, 3.0]), 2.0..4.0);
        let runs = finite_runs(&[0.0, 1.0, 2.0, 3.0], &[1.0, f64::NAN, 2.0, 3.0]);
        assert_eq!(runs, vec![vec![(0.0, 1.0)], vec![(2.0, 2.0), (3.0, 3.0)]]);
        // Issue 25: a curve of a million recordings is drawn with at most about MAX_SERIES_POINTS points,
        // its first and last included.
        let t: Vec<f64> = (0..1_000_000).map(f64::from).collect();
        let runs = finite_runs(&t, &t);
        assert_eq!(runs.len(), 1);
        assert!(runs[0].len() <= MAX_SERIES_POINTS + 1, "{}", runs[0].len());
        assert_eq!(runs[0].first(), Some(&(0.0, 0.0)));
        assert_eq!(runs[0].last(), Some(&(999_999.0, 999_999.0)));
        assert_eq!(evenly_spaced(3, 5), [0, 1, 2]);
        assert_eq!(evenly_spaced(10, 4), [0, 2, 5, 7]);
    }
}
