//! Overlay figures of several runs' groups (the laws of `satflock compare`): one metric over time, every
//! group on one axis in its own colour, as the median over the group's runs with a light 5–95 % band
//! (on a logarithmic axis when the values are positive and span more than three decades).
//! The curves are computed by the caller (from the runs' metrics tables); this module only draws them.

use std::path::{Path, PathBuf};

use plotters::coord::ranged1d::ValueFormatter;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::tracks::track_colour;
use super::{
    axes, column_label, figure_title, finite_runs, legend, padded_range, panel,
    register_embedded_font, write_figure, DrawError, Figure, PlotError, PlotReport, TimeAxis,
    MARGIN, X_LABEL_AREA, Y_LABEL_AREA,
};

/// One group's curve: the median and the 5 % and 95 % percentiles over its runs at each recording time
/// (NaN where no run has a value).
#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    /// Legend label (the law's label).
    pub label: String,
    /// Recording times \[s\].
    pub t_s: Vec<f64>,
    /// Median at each time.
    pub median: Vec<f64>,
    /// 5 % percentile at each time.
    pub p05: Vec<f64>,
    /// 95 % percentile at each time.
    pub p95: Vec<f64>,
}

/// One overlay figure: a metrics column, every group's curve on one axis.
#[derive(Clone, Debug, PartialEq)]
pub struct Overlay {
    /// File name without extension (`min_separation` → `min_separation.png` and `.svg`).
    pub name: String,
    /// Figure title.
    pub title: String,
    /// The metrics column shown (its unit labels the y axis).
    pub column: String,
    /// The curves, one per group, in legend order (colour k for curve k).
    pub curves: Vec<Curve>,
}

impl Figure for Overlay {
    fn name(&self) -> &str {
        &self.name
    }

    fn size(&self) -> (u32, u32) {
        (1000, 620)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), DrawError> {
        let body = figure_title(root, &self.title)?;
        let end_s = self
            .curves
            .iter()
            .flat_map(|c| c.t_s.iter().copied())
            .fold(0.0, f64::max);
        let time = TimeAxis::for_duration(end_s);
        let x = 0.0..time.value(end_s).max(f64::MIN_POSITIVE);
        let values = || {
            self.curves
                .iter()
                .flat_map(|c| c.p05.iter().chain(&c.p95).chain(&c.median).copied())
                .filter(|v| v.is_finite())
        };
        match log_range(values()) {
            Some(y) => {
                let mut chart = ChartBuilder::on(&body)
                    .margin(MARGIN)
                    .x_label_area_size(X_LABEL_AREA)
                    .y_label_area_size(Y_LABEL_AREA)
                    .build_cartesian_2d(x, y.log_scale())?;
                self.draw_curves(&mut chart, &time, " (log scale)")
            }
            None => {
                let mut chart = panel(&body, x, padded_range(values()))?;
                self.draw_curves(&mut chart, &time, "")
            }
        }
    }
}

impl Overlay {
    /// The axes, every curve's band and median, and the legend, on a linear or logarithmic y axis.
    fn draw_curves<'a, DB: DrawingBackend + 'a, Y>(
        &self,
        chart: &mut ChartContext<'a, DB, Cartesian2d<RangedCoordf64, Y>>,
        time: &TimeAxis,
        y_note: &str,
    ) -> Result<(), DrawError>
    where
        Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    {
        axes(
            chart,
            &time.label(),
            &format!("{}{y_note}", column_label(&self.column)),
        )?;
        for (k, curve) in self.curves.iter().enumerate() {
            let colour = track_colour(k);
            let t: Vec<f64> = curve.t_s.iter().map(|t| time.value(*t)).collect();
            // The band: one polygon per run of times where both percentiles exist.
            for band in finite_bands(&t, &curve.p05, &curve.p95) {
                chart.draw_series(std::iter::once(Polygon::new(
                    band,
                    colour.mix(0.15).filled(),
                )))?;
            }
            let mut labelled = false;
            for run in finite_runs(&t, &curve.median) {
                let series = if run.len() == 1 {
                    chart.draw_series(std::iter::once(PathElement::new(
                        run,
                        colour.stroke_width(2),
                    )))?
                } else {
                    chart.draw_series(LineSeries::new(run, colour.stroke_width(2)))?
                };
                if !labelled {
                    labelled = true;
                    series.label(curve.label.clone()).legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
                    });
                }
            }
        }
        legend(chart, SeriesLabelPosition::UpperRight)
    }
}

/// A logarithmic y range for values spanning more than [`LOG_AXIS_DECADES`] decades, all positive
/// (a threat's distance falls from its start to metres); `None`: a linear axis.
fn log_range(values: impl Iterator<Item = f64>) -> Option<std::ops::Range<f64>> {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    (lo > 0.0 && hi.is_finite() && hi / lo > 10f64.powi(LOG_AXIS_DECADES))
        .then(|| lo / 1.5..hi * 1.5)
}

/// Decades beyond which an overlay's y axis is logarithmic.
const LOG_AXIS_DECADES: i32 = 3;

/// The closed outlines (p95 forward, p05 back) of the runs of times where both percentiles are finite.
fn finite_bands(t: &[f64], lo: &[f64], hi: &[f64]) -> Vec<Vec<(f64, f64)>> {
    let mut bands = Vec::new();
    let mut current: Vec<(f64, f64, f64)> = Vec::new();
    let mut close = |current: &mut Vec<(f64, f64, f64)>| {
        if current.len() > 1 {
            let mut outline: Vec<(f64, f64)> = current.iter().map(|p| (p.0, p.2)).collect();
            outline.extend(current.iter().rev().map(|p| (p.0, p.1)));
            bands.push(outline);
        }
        current.clear();
    };
    for ((&t, &l), &h) in t.iter().zip(lo).zip(hi) {
        if t.is_finite() && l.is_finite() && h.is_finite() {
            current.push((t, l, h));
        } else {
            close(&mut current);
        }
    }
    close(&mut current);
    bands
}

/// Draws every overlay into `dir` (created if needed) as `NAME.png` and `NAME.svg`; returns the files.
pub fn draw_overlays(dir: &Path, overlays: &[Overlay]) -> Result<Vec<PathBuf>, PlotError> {
    register_embedded_font()?;
    std::fs::create_dir_all(dir).map_err(|e| PlotError::Write {
        path: dir.display().to_string(),
        message: e.to_string(),
    })?;
    let mut report = PlotReport::default();
    for overlay in overlays {
        write_figure(dir, overlay, &mut report)?;
    }
    Ok(report.written)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bands_close_around_finite_runs() {
        let t = [0.0, 1.0, 2.0, 3.0];
        let lo = [0.0, 1.0, f64::NAN, 3.0];
        let hi = [1.0, 2.0, 5.0, 4.0];
        // The first two times make a band; time 3 alone makes none.
        assert_eq!(
            finite_bands(&t, &lo, &hi),
            vec![vec![(0.0, 1.0), (1.0, 2.0), (1.0, 1.0), (0.0, 0.0)]]
        );
    }

    #[test]
    fn the_axis_is_logarithmic_only_for_positive_values_over_three_decades() {
        assert_eq!(log_range([3.0, 1.5e6].into_iter()), Some(2.0..2.25e6));
        assert_eq!(log_range([3.0, 2000.0].into_iter()), None);
        assert_eq!(log_range([0.0, 1.5e6].into_iter()), None);
        assert_eq!(log_range(std::iter::empty()), None);
    }
}
