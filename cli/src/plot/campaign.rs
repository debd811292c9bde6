//! The figure of a campaign (`satflock campaign`), drawn from its table alone: `OUT/plots/outcomes.png`
//! and `.svg`, one panel per headline outcome and numeric varied parameter (a row holds whole groups of
//! one outcome against every parameter, [`ROW_PANELS`] panels or more), each run that completed a point
//! (outcome against the parameter's value; a log-scale range on a log10 axis) and, where a value has
//! several runs (the seeds of a listed value), the median per value as a line.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use satflock::output::outcomes::RunTable;

use super::{
    axes, caption, column_label, empty_panel, figure_title, padded_range, panel,
    register_embedded_font, write_figure, DrawError, Figure, PlotError, PlotReport,
};

/// Panel size \[px\].
const PANEL: (u32, u32) = (420, 290);

/// Panels per row when the parameters are fewer (a row holds whole groups of parameters).
pub const ROW_PANELS: usize = 4;

/// Narrowest figure \[px\] (room for the title).
const MIN_WIDTH: u32 = 2 * PANEL.0;

const POINT_COLOUR: RGBColor = RGBColor(31, 90, 170);
const MEDIAN_COLOUR: RGBColor = RGBColor(200, 80, 0);

/// A varied parameter as the figure draws it.
#[derive(Clone, Debug, PartialEq)]
pub struct PlotParameter {
    /// The dotted key (axis description).
    pub key: String,
    /// Its number column in the table.
    pub column: String,
    /// Drawn on a log10 axis.
    pub log: bool,
}

/// The `outcomes` figure.
struct Outcomes<'a> {
    title: String,
    table: &'a RunTable,
    parameters: &'a [PlotParameter],
    outcomes: &'a [String],
}

impl Outcomes<'_> {
    /// Rows and columns of panels: each row holds `k` outcomes × every parameter, `k` as many as fit
    /// in [`ROW_PANELS`] (at least one).
    fn grid(&self) -> (usize, usize) {
        let p = self.parameters.len().max(1);
        let n = self.outcomes.len().max(1);
        let per_row = (ROW_PANELS / p).clamp(1, n);
        (n.div_ceil(per_row), per_row * p)
    }

    /// Completed runs' (x, y) for one parameter and outcome (x as drawn: log10 on a log axis).
    fn points(&self, parameter: &PlotParameter, outcome: &str) -> Vec<(f64, f64)> {
        let (Some(x), Some(y), Some(status)) = (
            self.table.numbers(&parameter.column),
            self.table.numbers(outcome),
            self.table.text("status"),
        ) else {
            return Vec::new();
        };
        (0..x.len())
            .filter(|&r| status[r] == "completed")
            .map(|r| (if parameter.log { x[r].log10() } else { x[r] }, y[r]))
            .filter(|(x, y)| x.is_finite() && y.is_finite())
            .collect()
    }
}

/// The median of each x that has more than one y, in increasing x (empty if no x repeats).
fn medians(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut sorted = points.to_vec();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let groups: Vec<&[(f64, f64)]> = sorted.chunk_by(|a, b| a.0 == b.0).collect();
    if groups.iter().all(|g| g.len() == 1) {
        return Vec::new();
    }
    groups
        .iter()
        .map(|g| {
            let ys: Vec<f64> = g.iter().map(|p| p.1).collect();
            (g[0].0, satflock::output::spread::Spread::of(&ys).median)
        })
        .collect()
}

impl Figure for Outcomes<'_> {
    fn name(&self) -> &'static str {
        "outcomes"
    }

    fn size(&self) -> (u32, u32) {
        let (rows, cols) = self.grid();
        (
            (cols as u32 * PANEL.0).max(MIN_WIDTH),
            rows as u32 * PANEL.1 + 50,
        )
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), DrawError> {
        let body = figure_title(root, &self.title)?;
        let panels = body.split_evenly(self.grid());
        let cells = self
            .outcomes
            .iter()
            .flat_map(|o| self.parameters.iter().map(move |p| (o, p)));
        for (area, (outcome, parameter)) in panels.iter().zip(cells) {
            let area = caption(area, outcome)?;
            let points = self.points(parameter, outcome);
            if points.is_empty() {
                empty_panel(&area, "no completed run has this outcome")?;
                continue;
            }
            let x = padded_range(points.iter().map(|p| p.0));
            let y = padded_range(points.iter().map(|p| p.1));
            let mut chart = panel(&area, x, y)?;
            // Units in the labels, from the names' suffixes.
            let x_desc = if parameter.log {
                format!("log10 {}", column_label(&parameter.key))
            } else {
                column_label(&parameter.key)
            };
            axes(&mut chart, &x_desc, &column_label(outcome))?;
            chart.draw_series(
                points
                    .iter()
                    .map(|&p| Circle::new(p, 3, POINT_COLOUR.mix(0.7).filled())),
            )?;
            let line = medians(&points);
            if !line.is_empty() {
                chart.draw_series(LineSeries::new(line, MEDIAN_COLOUR.stroke_width(2)))?;
            }
        }
        Ok(())
    }
}

/// Draws the campaign figure from `table` into `out/plots/` (nothing, with the reason in the report,
/// when no parameter is numeric or there is no outcome).
pub fn draw_campaign(
    out: &Path,
    title: &str,
    table: &RunTable,
    parameters: &[PlotParameter],
    outcomes: &[String],
) -> Result<PlotReport, PlotError> {
    let mut report = PlotReport::default();
    if parameters.is_empty() || outcomes.is_empty() {
        report.skipped.push((
            "outcomes".into(),
            if parameters.is_empty() {
                "the campaign varies no numeric parameter".into()
            } else {
                "the campaign has no headline outcome".into()
            },
        ));
        return Ok(report);
    }
    register_embedded_font()?;
    let dir = out.join("plots");
    std::fs::create_dir_all(&dir).map_err(|e| PlotError::Write {
        path: dir.display().to_string(),
        message: e.to_string(),
    })?;
    let figure = Outcomes {
        title: format!("{title}: completed runs (line: median per value)"),
        table,
        parameters,
        outcomes,
    };
    write_figure(&dir, &figure, &mut report)?;
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn medians_only_where_values_repeat() {
        assert!(medians(&[(1.0, 2.0), (2.0, 3.0)]).is_empty());
        let m = medians(&[(2.0, 5.0), (1.0, 1.0), (1.0, 3.0), (2.0, 4.0), (2.0, 9.0)]);
        assert_eq!(m, vec![(1.0, 2.0), (2.0, 5.0)]);
    }
}
