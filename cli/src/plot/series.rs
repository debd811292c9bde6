//! Time series of `metrics.csv`, one small panel per column:
//!
//! * `swarm_metrics`: the five elements (d_max, diameter, d_min, uniformity L, live count N), the
//!   minimum separation and collisions, and with threats or obstacles the monitors' columns;
//! * `law_metrics`: every column after the standard ones ([`METRICS_HEADER`], [`THREAT_COLUMNS`],
//!   [`OBSTACLE_COLUMNS`]): the metrics of the law or laws the run used (blank while a law without that
//!   column runs, drawn as gaps).

use plotters::coord::Shift;
use plotters::prelude::*;

use satflock::output::columns::{METRICS_HEADER, OBSTACLE_COLUMNS, THREAT_COLUMNS};

use super::{
    axes, caption, column_label, empty_panel, figure_title, finite_runs, padded_range, panel,
    DrawError, Figure, RunContext,
};

/// Columns of the `swarm_metrics` figure, with their captions (those present are drawn).
const SWARM_COLUMNS: &[(&str, &str)] = &[
    ("d_max_m", "d_max: largest distance from the centre"),
    ("diameter_m", "diameter: largest pair distance"),
    ("d_min_m", "d_min: smallest surface gap"),
    ("uniformity_l", "uniformity L"),
    ("min_separation_m", "minimum separation (centres)"),
    ("n", "N: live satellites"),
    ("collisions", "colliding pairs"),
    ("min_threat_distance_m", "closest threat approach so far"),
    ("threat_incursions", "danger-sphere entries so far"),
    (
        "min_obstacle_clearance_m",
        "smallest obstacle clearance so far",
    ),
    ("obstacle_incursions", "obstacle entries so far"),
];

/// Panels per row.
const COLUMNS: usize = 4;
/// Panel size \[px\].
const PANEL: (u32, u32) = (420, 290);

const LINE_COLOUR: RGBColor = RGBColor(31, 90, 170);

/// A grid of time-series panels, one per metrics column.
struct Panels<'a> {
    context: &'a RunContext<'a>,
    /// Column names and captions.
    columns: Vec<(String, String)>,
}

impl Panels<'_> {
    fn size(&self) -> (u32, u32) {
        let n = self.columns.len().max(1);
        let cols = n.min(COLUMNS) as u32;
        let rows = n.div_ceil(COLUMNS) as u32;
        (cols * PANEL.0, rows * PANEL.1 + 50)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        what: &str,
    ) -> Result<(), DrawError> {
        let time = &self.context.time;
        let metrics = &self.context.run.metrics;
        let title = self
            .context
            .title(&format!("{what} ({})", self.context.epoch_note()));
        let body = figure_title(root, &title)?;
        let n = self.columns.len().max(1);
        let panels = body.split_evenly((n.div_ceil(COLUMNS), n.min(COLUMNS)));
        let t: Vec<f64> = metrics
            .column("t_s")
            .unwrap_or_default()
            .iter()
            .map(|t| time.value(*t))
            .collect();
        for (area, (name, text)) in panels.iter().zip(&self.columns) {
            let area = caption(area, text)?;
            let values = metrics.column(name).unwrap_or_default();
            let runs = finite_runs(&t, values);
            if runs.is_empty() {
                empty_panel(&area, &format!("{name}: no values recorded"))?;
                continue;
            }
            let x = padded_range(t.iter().copied());
            let y = padded_range(values.iter().copied());
            let mut chart = panel(&area, x, y)?;
            axes(&mut chart, &time.label(), &column_label(name))?;
            for run in runs {
                if run.len() == 1 {
                    chart.draw_series(std::iter::once(Circle::new(
                        run[0],
                        2,
                        LINE_COLOUR.filled(),
                    )))?;
                } else {
                    chart.draw_series(LineSeries::new(run, LINE_COLOUR.stroke_width(1)))?;
                }
            }
        }
        Ok(())
    }
}

/// The `swarm_metrics` figure.
pub(crate) struct SwarmMetrics<'a>(Panels<'a>);

impl<'a> SwarmMetrics<'a> {
    /// The standard columns the run's `metrics.csv` has.
    pub fn new(context: &'a RunContext<'a>) -> Self {
        let names = context.run.metrics.names();
        Self(Panels {
            context,
            columns: SWARM_COLUMNS
                .iter()
                .filter(|(c, _)| names.iter().any(|n| n == c))
                .map(|(c, text)| (c.to_string(), text.to_string()))
                .collect(),
        })
    }
}

impl Figure for SwarmMetrics<'_> {
    fn name(&self) -> &'static str {
        "swarm_metrics"
    }

    fn size(&self) -> (u32, u32) {
        self.0.size()
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), DrawError> {
        self.0
            .draw(root, "five elements, separation and monitors over time")
    }
}

/// The `law_metrics` figure.
pub(crate) struct LawMetrics<'a>(Panels<'a>);

impl<'a> LawMetrics<'a> {
    /// The law's metric columns of the run's `metrics.csv` (`None` if it has none).
    pub fn new(context: &'a RunContext<'a>) -> Option<Self> {
        let columns: Vec<(String, String)> = context
            .run
            .metrics
            .names()
            .iter()
            .filter(|n| {
                ![METRICS_HEADER, THREAT_COLUMNS, OBSTACLE_COLUMNS]
                    .iter()
                    .any(|standard| standard.contains(&n.as_str()))
            })
            .map(|n| (n.clone(), n.clone()))
            .collect();
        (!columns.is_empty()).then_some(Self(Panels { context, columns }))
    }
}

impl Figure for LawMetrics<'_> {
    fn name(&self) -> &'static str {
        "law_metrics"
    }

    fn size(&self) -> (u32, u32) {
        self.0.size()
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), DrawError> {
        self.0.draw(root, "the law's metrics over time")
    }
}
