//! The `conjunctions` figure: the conjunction timeline of a run that monitored conjunctions
//! (`[conjunctions] threshold_m`): each encounter below the threshold as a point at its time of
//! closest approach and miss distance, satellite pairs and satellite–threat / satellite–obstacle
//! encounters told apart, with the threshold drawn. From `conjunctions.csv` / `.parquet` and
//! `summary.json`.

use plotters::coord::Shift;
use plotters::prelude::*;

use satflock::conjunction::{Encounter, Secondary};

use super::{axes, figure_title, legend, panel, tick, DrawError, Figure, RunContext};

/// Most encounters drawn (the closest ones; the cut is said in the title).
pub const MAX_ENCOUNTERS: usize = 5000;

/// The `conjunctions` figure.
pub(crate) struct Conjunctions<'a> {
    context: &'a RunContext<'a>,
    /// The encounters drawn, the closest [`MAX_ENCOUNTERS`] at most.
    encounters: Vec<Encounter>,
    /// Encounters the run found.
    found: usize,
    /// The monitor's threshold \[m\] (`summary.json` `conjunctions.threshold_m`).
    threshold_m: f64,
}

impl<'a> Conjunctions<'a> {
    /// The figure of a run that monitored conjunctions (`None` when it did not, or when its table
    /// cannot be read as encounters: the CDM export reports that).
    pub fn new(context: &'a RunContext<'a>) -> Option<Self> {
        let threshold_m = context
            .run
            .summary
            .get("conjunctions")?
            .get("threshold_m")?
            .as_f64()?;
        let mut encounters = satflock::output::cdm::run_encounters(context.run).ok()?;
        let found = encounters.len();
        if found > MAX_ENCOUNTERS {
            encounters.sort_by(|a, b| a.miss_distance_m.total_cmp(&b.miss_distance_m));
            encounters.truncate(MAX_ENCOUNTERS);
        }
        Some(Self {
            context,
            encounters,
            found,
            threshold_m,
        })
    }
}

/// The marker style of each kind of secondary: satellite pairs, threats, obstacles.
const KINDS: [(&str, RGBColor); 3] = [
    ("satellite pairs", RGBColor(31, 119, 180)),
    ("with a threat", RGBColor(200, 0, 0)),
    ("with an obstacle", RGBColor(90, 90, 90)),
];

fn kind_index(secondary: &Secondary) -> usize {
    match secondary {
        Secondary::Satellite(_) => 0,
        Secondary::Threat(_) => 1,
        Secondary::Obstacle(_) => 2,
    }
}

impl Figure for Conjunctions<'_> {
    fn name(&self) -> &'static str {
        "conjunctions"
    }

    fn size(&self) -> (u32, u32) {
        (1000, 560)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), DrawError> {
        let time = self.context.time;
        let shown = if self.encounters.len() < self.found {
            format!(
                "the {} closest of {} encounters",
                self.encounters.len(),
                self.found
            )
        } else {
            format!("{} encounters", self.found)
        };
        let title = self.context.title(&format!(
            "conjunction timeline: {shown} below {} m (miss distance at TCA)",
            tick(self.threshold_m)
        ));
        let body = figure_title(root, &title)?;
        let duration_s = self
            .context
            .run
            .summary
            .get("duration_s")
            .and_then(|v| v.as_f64())
            .unwrap_or(0.0);
        let last_tca_s = self.encounters.iter().map(|e| e.tca_s).fold(0.0, f64::max);
        let x_max = time
            .value(duration_s.max(last_tca_s))
            .max(f64::MIN_POSITIVE);
        let y_max = (self.threshold_m * 1.1).max(f64::MIN_POSITIVE);
        let mut chart = panel(&body, 0.0..x_max, 0.0..y_max)?;
        axes(&mut chart, &time.label(), "miss distance [m]")?;
        chart
            .draw_series(std::iter::once(PathElement::new(
                vec![(0.0, self.threshold_m), (x_max, self.threshold_m)],
                BLACK.mix(0.6).stroke_width(1),
            )))?
            .label(format!("threshold {} m", tick(self.threshold_m)))
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK.mix(0.6)));
        for (k, (what, colour)) in KINDS.iter().enumerate() {
            let points: Vec<(f64, f64)> = self
                .encounters
                .iter()
                .filter(|e| kind_index(&e.secondary) == k)
                .map(|e| (time.value(e.tca_s), e.miss_distance_m))
                .collect();
            if points.is_empty() {
                continue;
            }
            let colour = *colour;
            chart
                .draw_series(
                    points
                        .iter()
                        .map(|&p| Circle::new(p, 4, colour.mix(0.8).filled())),
                )?
                .label(format!("{what} ({})", points.len()))
                .legend(move |(x, y)| Circle::new((x + 10, y), 4, colour.filled()));
        }
        legend(&mut chart, SeriesLabelPosition::UpperRight)?;
        Ok(())
    }
}
