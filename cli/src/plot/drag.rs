//! The `drag` figure of a run whose satellites have drag attitudes (the trajectory's `drag_area_m2`
//! column): each satellite's phase along the orbit relative to satellite 0 (the argument-of-latitude
//! difference, from the trajectory's EME2000 states, unwrapped over time), its osculating altitude above
//! the equatorial radius, and its
//! drag area over time (the mode timeline). Up to [`MAX_LINES`] satellites are drawn, chosen evenly by
//! id.

use std::collections::BTreeMap;

use nalgebra::Vector3;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::{
    axes, caption, empty_panel, figure_title, padded_range, panel, DrawError, Figure, RunContext,
};

/// Most satellites drawn.
pub const MAX_LINES: usize = 60;

/// Equatorial radius the altitudes are measured from \[m\] (WGS-84, as the engine's Earth model).
const EQUATORIAL_RADIUS_M: f64 = 6_378_137.0;

/// One satellite's series: (time on the figure's axis, value).
type Series = Vec<(f64, f64)>;

/// The `drag` figure.
pub(crate) struct Drag<'a> {
    context: &'a RunContext<'a>,
    /// Per drawn satellite id: phase relative to satellite 0 \[deg\], altitude \[km\], drag area \[m^2\].
    series: BTreeMap<usize, [Series; 3]>,
}

impl<'a> Drag<'a> {
    /// The figure, if the run's trajectory has drag areas and inertial states.
    pub fn new(context: &'a RunContext<'a>) -> Option<Self> {
        let table = context.run.trajectory.as_ref()?;
        let column = |name: &str| table.column(name);
        let (t, id, area) = (column("t_s")?, column("id")?, column("drag_area_m2")?);
        let r: Vec<&[f64]> = ["x", "y", "z"]
            .iter()
            .map(|k| column(&format!("{k}_eme2000_m")))
            .collect::<Option<_>>()?;
        let v: Vec<&[f64]> = ["vx", "vy", "vz"]
            .iter()
            .map(|k| column(&format!("{k}_eme2000_mps")))
            .collect::<Option<_>>()?;
        let n = context.run.n_satellites.max(1);
        let stride = n.div_ceil(MAX_LINES);
        let time = &context.time;
        let mut series: BTreeMap<usize, [Series; 3]> = BTreeMap::new();
        // Satellite 0's position and orbit normal at each recording time (rows come in time order,
        // satellite 0 first when it is live).
        let mut reference: Option<(f64, Vector3<f64>, Vector3<f64>)> = None;
        for k in 0..t.len() {
            let sat = id[k] as usize;
            let position = Vector3::new(r[0][k], r[1][k], r[2][k]);
            if sat == 0 {
                let velocity = Vector3::new(v[0][k], v[1][k], v[2][k]);
                reference = Some((t[k], position, position.cross(&velocity).normalize()));
            }
            if !sat.is_multiple_of(stride) {
                continue;
            }
            let x = time.value(t[k]);
            let entry = series.entry(sat).or_default();
            if let Some((_, p0, h0)) = reference.filter(|(t0, _, _)| *t0 == t[k]) {
                let mut phase = p0
                    .cross(&position)
                    .dot(&h0)
                    .atan2(p0.dot(&position))
                    .to_degrees();
                // Continuous over time: a step of more than half a turn is a wrap, not a motion.
                if let Some(&(_, last)) = entry[0].last() {
                    phase += 360.0 * ((last - phase) / 360.0).round();
                }
                entry[0].push((x, phase));
            }
            entry[1].push((x, (position.norm() - EQUATORIAL_RADIUS_M) / 1e3));
            entry[2].push((x, area[k]));
        }
        Some(Self { context, series })
    }

    fn draw_panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        which: usize,
        title: &str,
        y_label: &str,
    ) -> Result<(), DrawError> {
        let area = caption(area, title)?;
        let all = || self.series.values().flat_map(|s| s[which].iter());
        if all().next().is_none() {
            return empty_panel(&area, "no values");
        }
        let x = padded_range(all().map(|p| p.0));
        let y = padded_range(all().map(|p| p.1));
        let mut chart = panel(&area, x, y)?;
        axes(&mut chart, &self.context.time.label(), y_label)?;
        let count = self.series.len().max(1);
        for (k, s) in self.series.values().enumerate() {
            let colour = HSLColor(k as f64 / count as f64 * 0.8, 0.7, 0.45);
            chart.draw_series(LineSeries::new(
                s[which].iter().copied(),
                colour.stroke_width(1),
            ))?;
        }
        Ok(())
    }
}

impl Figure for Drag<'_> {
    fn name(&self) -> &'static str {
        "drag"
    }

    fn size(&self) -> (u32, u32) {
        (1400, 1200)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), DrawError> {
        let title = self.context.title(&format!(
            "drag attitudes: phase, altitude, area ({} of {} satellites; {})",
            self.series.len(),
            self.context.run.n_satellites,
            self.context.epoch_note()
        ));
        let body = figure_title(root, &title)?;
        let rows = body.split_evenly((3, 1));
        self.draw_panel(
            &rows[0],
            0,
            "phase along the orbit ahead of satellite 0 (argument of latitude, EME2000)",
            "phase [deg]",
        )?;
        self.draw_panel(
            &rows[1],
            1,
            "osculating altitude above the equatorial radius",
            "altitude [km]",
        )?;
        self.draw_panel(&rows[2], 2, "drag area (the commanded mode)", "area [m²]")
    }
}
