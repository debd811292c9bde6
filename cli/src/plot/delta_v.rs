//! The `delta_v` figure: each satellite's Δv at the end of the run (`summary.json`
//! `delta_v_mps.per_satellite`; one bar per satellite up to [`MAX_BARS`] satellites, a histogram above),
//! and the swarm's mean and largest Δv so far over time (`metrics.csv` `delta_v_mean_mps`,
//! `delta_v_max_mps`).

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{
    axes, caption, empty_panel, figure_title, finite_runs, legend, padded_range, panel, DrawError,
    Figure, RunContext,
};

/// Largest swarm drawn as one bar per satellite.
pub const MAX_BARS: usize = 50;

const BAR_COLOUR: RGBColor = RGBColor(31, 90, 170);
const MEAN_COLOUR: RGBColor = RGBColor(31, 90, 170);
const MAX_COLOUR: RGBColor = RGBColor(200, 80, 0);

/// The `delta_v` figure.
pub(crate) struct DeltaV<'a> {
    context: &'a RunContext<'a>,
    /// Δv per satellite at the end \[m/s\] (`None`: the summary has none).
    per_satellite: Option<Vec<f64>>,
}

impl<'a> DeltaV<'a> {
    /// The figure of a run.
    pub fn new(context: &'a RunContext<'a>) -> Self {
        let per_satellite = context
            .run
            .summary
            .pointer("/delta_v_mps/per_satellite")
            .and_then(|v| v.as_array())
            .map(|values| {
                values
                    .iter()
                    .map(|v| v.as_f64().unwrap_or(f64::NAN))
                    .collect()
            });
        Self {
            context,
            per_satellite,
        }
    }

    fn draw_per_satellite<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
    ) -> Result<(), DrawError> {
        let Some(dv) = self.per_satellite.as_deref().filter(|v| !v.is_empty()) else {
            let area = caption(area, "Δv per satellite")?;
            return empty_panel(&area, "summary.json has no delta_v_mps.per_satellite");
        };
        let top = dv
            .iter()
            .copied()
            .filter(|v| v.is_finite())
            .fold(0.0, f64::max);
        let top = if top > 0.0 { top } else { 1.0 };
        if dv.len() <= MAX_BARS {
            let area = caption(area, "Δv per satellite at the end of the run")?;
            let n = dv.len() as f64;
            let mut chart = panel(&area, -0.6..n - 0.4, 0.0..1.05 * top)?;
            axes(&mut chart, "satellite id [-]", "Δv [m/s]")?;
            chart.draw_series(dv.iter().enumerate().filter(|(_, v)| v.is_finite()).map(
                |(i, v)| {
                    let x = i as f64;
                    Rectangle::new([(x - 0.4, 0.0), (x + 0.4, *v)], BAR_COLOUR.filled())
                },
            ))?;
        } else {
            let bins = ((dv.len() as f64).sqrt().ceil() as usize).clamp(10, 50);
            let width = top / bins as f64;
            let mut counts = vec![0usize; bins];
            for v in dv.iter().filter(|v| v.is_finite()) {
                counts[((v / width) as usize).min(bins - 1)] += 1;
            }
            let most = counts.iter().copied().max().unwrap_or(1).max(1) as f64;
            let area = caption(
                area,
                &format!(
                    "Δv at the end of the run: histogram of {} satellites",
                    dv.len()
                ),
            )?;
            let mut chart = panel(&area, 0.0..top, 0.0..1.05 * most)?;
            axes(&mut chart, "Δv [m/s]", "satellites per bin [-]")?;
            chart.draw_series(counts.iter().enumerate().map(|(k, c)| {
                let x0 = k as f64 * width;
                Rectangle::new([(x0, 0.0), (x0 + width, *c as f64)], BAR_COLOUR.filled())
            }))?;
        }
        Ok(())
    }

    fn draw_cumulative<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
    ) -> Result<(), DrawError> {
        let time = &self.context.time;
        let metrics = &self.context.run.metrics;
        let area = caption(area, "Δv so far: mean and largest over the live satellites")?;
        let t: Vec<f64> = metrics
            .column("t_s")
            .unwrap_or_default()
            .iter()
            .map(|t| time.value(*t))
            .collect();
        let columns = [
            ("delta_v_mean_mps", "mean", MEAN_COLOUR),
            ("delta_v_max_mps", "largest", MAX_COLOUR),
        ];
        let values: Vec<&[f64]> = columns
            .iter()
            .map(|(c, _, _)| metrics.column(c).unwrap_or_default())
            .collect();
        if values.iter().all(|v| finite_runs(&t, v).is_empty()) {
            return empty_panel(&area, "metrics.csv has no delta-v values");
        }
        let x = padded_range(t.iter().copied());
        let y = padded_range(values.iter().flat_map(|v| v.iter().copied()).chain([0.0]));
        let mut chart = panel(&area, x, y)?;
        axes(&mut chart, &time.label(), "Δv [m/s]")?;
        for ((_, name, colour), v) in columns.iter().zip(&values) {
            let colour = *colour;
            for (k, run) in finite_runs(&t, v).into_iter().enumerate() {
                let series = chart.draw_series(LineSeries::new(run, colour.stroke_width(1)))?;
                if k == 0 {
                    series.label(*name).legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(1))
                    });
                }
            }
        }
        legend(&mut chart, SeriesLabelPosition::UpperLeft)
    }
}

impl Figure for DeltaV<'_> {
    fn name(&self) -> &'static str {
        "delta_v"
    }

    fn size(&self) -> (u32, u32) {
        (1400, 520)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), DrawError> {
        let title = self
            .context
            .title(&format!("delta-v ({})", self.context.epoch_note()));
        let body = figure_title(root, &title)?;
        let halves = body.split_evenly((1, 2));
        self.draw_per_satellite(&halves[0])?;
        self.draw_cumulative(&halves[1])
    }
}
