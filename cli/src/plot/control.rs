//! The `control` figure of a run that recorded its control history (`[output] control_history`: the
//! trajectory's `ux_cmd_mps2` … `uz_mps2` and `saturated` columns): for the first [`MAX_SATELLITES`]
//! satellite ids in the trajectory, the norm of the applied acceleration over time (solid) with the
//! norm of the commanded one (dashed, the law's command before the actuator), and a saturation
//! timeline (a bar over each stretch of recordings where the actuator limited the command). Each curve
//! keeps at most [`super::MAX_SERIES_POINTS`] evenly spaced recordings (and its last); the timeline
//! merges consecutive saturated recordings into one bar.

use std::collections::BTreeMap;

use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

use super::{
    axes, caption, empty_panel, figure_title, legend, padded_range, panel, DrawError, Figure,
    RunContext, MAX_SERIES_POINTS,
};

/// Most satellites drawn: the first ids of the trajectory.
pub const MAX_SATELLITES: usize = 5;

/// One satellite's control history, in recording order.
#[derive(Default)]
struct History {
    /// Time on the figure's axis.
    t: Vec<f64>,
    /// ‖applied acceleration‖ \[m/s^2\].
    applied: Vec<f64>,
    /// ‖commanded acceleration‖ \[m/s^2\].
    commanded: Vec<f64>,
    /// Whether the actuator limited the command.
    saturated: Vec<bool>,
}

impl History {
    /// (t, value) of every k-th recording and the last, at most about [`MAX_SERIES_POINTS`].
    fn points(&self, values: &[f64]) -> Vec<(f64, f64)> {
        let n = self.t.len();
        let stride = n.div_ceil(MAX_SERIES_POINTS).max(1);
        (0..n)
            .filter(|&k| k % stride == 0 || k + 1 == n)
            .map(|k| (self.t[k], values[k]))
            .filter(|(t, v)| t.is_finite() && v.is_finite())
            .collect()
    }

    /// The stretches of saturated recordings, each from its first recording to the next recording
    /// after its last (or its last, at the end of the run).
    fn saturated_spans(&self) -> Vec<(f64, f64)> {
        let mut spans = Vec::new();
        let mut start: Option<f64> = None;
        for (k, &s) in self.saturated.iter().enumerate() {
            match (s, start) {
                (true, None) => start = Some(self.t[k]),
                (false, Some(t0)) => {
                    spans.push((t0, self.t[k]));
                    start = None;
                }
                _ => {}
            }
        }
        if let (Some(t0), Some(&t1)) = (start, self.t.last()) {
            spans.push((t0, t1));
        }
        spans
    }
}

/// The `control` figure.
pub(crate) struct Control<'a> {
    context: &'a RunContext<'a>,
    /// Per drawn satellite id, its history.
    satellites: BTreeMap<usize, History>,
}

impl<'a> Control<'a> {
    /// The figure, if the run's trajectory has the control history's columns.
    pub fn new(context: &'a RunContext<'a>) -> Option<Self> {
        let table = context.run.trajectory.as_ref()?;
        let column = |name: &str| table.column(name);
        let (t, id, saturated) = (column("t_s")?, column("id")?, column("saturated")?);
        let commanded: Vec<&[f64]> = ["ux_cmd_mps2", "uy_cmd_mps2", "uz_cmd_mps2"]
            .iter()
            .map(|name| column(name))
            .collect::<Option<_>>()?;
        let applied: Vec<&[f64]> = ["ux_mps2", "uy_mps2", "uz_mps2"]
            .iter()
            .map(|name| column(name))
            .collect::<Option<_>>()?;
        let mut ids: Vec<usize> = id.iter().map(|&i| i as usize).collect();
        ids.sort_unstable();
        ids.dedup();
        ids.truncate(MAX_SATELLITES);
        let norm =
            |c: &[&[f64]], k: usize| (c[0][k].powi(2) + c[1][k].powi(2) + c[2][k].powi(2)).sqrt();
        let mut satellites: BTreeMap<usize, History> =
            ids.iter().map(|&i| (i, History::default())).collect();
        for k in 0..t.len() {
            let Some(history) = satellites.get_mut(&(id[k] as usize)) else {
                continue;
            };
            history.t.push(context.time.value(t[k]));
            history.applied.push(norm(&applied, k));
            history.commanded.push(norm(&commanded, k));
            history.saturated.push(saturated[k] != 0.0);
        }
        Some(Self {
            context,
            satellites,
        })
    }

    fn colour(&self, k: usize) -> HSLColor {
        HSLColor(
            k as f64 / self.satellites.len().max(1) as f64 * 0.8,
            0.7,
            0.42,
        )
    }

    fn draw_norms<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
    ) -> Result<(), DrawError> {
        let area = caption(
            area,
            "acceleration norm: applied (solid, after the actuator) and commanded (dashed, the law's)",
        )?;
        if self.satellites.values().all(|h| h.t.is_empty()) {
            return empty_panel(&area, "no recordings");
        }
        let x = padded_range(self.satellites.values().flat_map(|h| h.t.iter().copied()));
        let y = padded_range(
            self.satellites
                .values()
                .flat_map(|h| h.applied.iter().chain(&h.commanded).copied())
                .chain([0.0]),
        );
        let mut chart = panel(&area, x, y)?;
        axes(&mut chart, &self.context.time.label(), "‖u‖ [m/s²]")?;
        for (k, (id, h)) in self.satellites.iter().enumerate() {
            let colour = self.colour(k);
            chart.draw_series(std::iter::once(DashedPathElement::new(
                h.points(&h.commanded),
                5,
                4,
                colour.stroke_width(1),
            )))?;
            chart
                .draw_series(LineSeries::new(
                    h.points(&h.applied),
                    colour.stroke_width(2),
                ))?
                .label(format!("satellite {id}"))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
                });
        }
        legend(&mut chart, SeriesLabelPosition::UpperRight)
    }

    fn draw_timeline<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
    ) -> Result<(), DrawError> {
        let area = caption(
            area,
            "saturation timeline: the actuator limited the command",
        )?;
        if self.satellites.values().all(|h| h.t.is_empty()) {
            return empty_panel(&area, "no recordings");
        }
        let x = padded_range(self.satellites.values().flat_map(|h| h.t.iter().copied()));
        let rows = self.satellites.len() as f64;
        let mut chart = ChartBuilder::on(&area)
            .margin(super::MARGIN)
            .x_label_area_size(super::X_LABEL_AREA)
            .y_label_area_size(super::Y_LABEL_AREA)
            .build_cartesian_2d(x, -0.6..rows - 0.4)?;
        let ids: Vec<usize> = self.satellites.keys().copied().collect();
        chart
            .configure_mesh()
            .x_desc(self.context.time.label())
            .y_desc("satellite id [-]")
            .x_labels(6)
            .y_labels(ids.len().max(1))
            .x_label_formatter(&|v| super::tick(*v))
            .y_label_formatter(&|v| {
                let row = v.round();
                if (v - row).abs() < 1e-6 && row >= 0.0 && (row as usize) < ids.len() {
                    ids[row as usize].to_string()
                } else {
                    String::new()
                }
            })
            .label_style((super::FONT, super::size::TICKS))
            .axis_desc_style((super::FONT, super::size::AXIS))
            .light_line_style(WHITE.mix(0.0))
            .bold_line_style(BLACK.mix(0.12))
            .draw()?;
        for (k, h) in self.satellites.values().enumerate() {
            let y = k as f64;
            let colour = self.colour(k);
            chart.draw_series(
                h.saturated_spans().into_iter().map(|(t0, t1)| {
                    Rectangle::new([(t0, y - 0.3), (t1, y + 0.3)], colour.filled())
                }),
            )?;
        }
        Ok(())
    }
}

impl Figure for Control<'_> {
    fn name(&self) -> &'static str {
        "control"
    }

    fn size(&self) -> (u32, u32) {
        (1400, 900)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), DrawError> {
        let title = self.context.title(&format!(
            "control history, Hill frame (the first {} of {} satellites; {})",
            self.satellites.len(),
            self.context.run.n_satellites,
            self.context.epoch_note()
        ));
        let body = figure_title(root, &title)?;
        let (top, bottom) = body.split_vertically(560);
        self.draw_norms(&top)?;
        self.draw_timeline(&bottom)
    }
}
