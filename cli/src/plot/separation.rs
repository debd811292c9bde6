//! The `separations` figure: the histogram of every recorded satellite's distance to its nearest
//! neighbour at the last recording of `trajectory.csv` (Hill LVLH positions; exact, by a sweep along
//! x), with the smallest and the median marked.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{axes, figure_title, legend, panel, tick, DrawError, Figure, RunContext};

/// Bins of the histogram.
const BINS: usize = 40;

/// The `separations` figure.
pub(crate) struct Separations<'a> {
    context: &'a RunContext<'a>,
    /// The last recording time \[s\].
    t_s: f64,
    /// Each satellite's nearest-neighbour distance then \[m\], ascending.
    nearest_m: Vec<f64>,
}

impl<'a> Separations<'a> {
    /// The figure of a run's trajectory (`None` without one, or with fewer than two satellites at
    /// its last recording).
    pub fn new(context: &'a RunContext<'a>) -> Option<Self> {
        let table = context.run.trajectory.as_ref()?;
        let t = table.column("t_s")?;
        let xyz = [
            table.column("x_lvlh_m")?,
            table.column("y_lvlh_m")?,
            table.column("z_lvlh_m")?,
        ];
        let t_s = t.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let positions: Vec<[f64; 3]> = (0..table.rows())
            .filter(|&row| t[row] == t_s)
            .map(|row| [xyz[0][row], xyz[1][row], xyz[2][row]])
            .collect();
        let mut nearest_m = nearest_neighbour_distances_m(&positions);
        nearest_m.sort_by(f64::total_cmp);
        (nearest_m.len() >= 2).then_some(Self {
            context,
            t_s,
            nearest_m,
        })
    }
}

/// Each point's distance to its nearest other point \[m\] (empty with fewer than two points): exact,
/// by a sweep from each point both ways along x that stops once the x gap exceeds its best distance.
pub(crate) fn nearest_neighbour_distances_m(points: &[[f64; 3]]) -> Vec<f64> {
    if points.len() < 2 {
        return Vec::new();
    }
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&a, &b| points[a][0].total_cmp(&points[b][0]));
    let distance = |i: usize, j: usize| {
        (0..3)
            .map(|c| (points[i][c] - points[j][c]).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    let mut best = vec![f64::INFINITY; points.len()];
    for (k, &i) in order.iter().enumerate() {
        // Forward, then backward, until the x gap alone exceeds the best distance found.
        for &j in &order[k + 1..] {
            if points[j][0] - points[i][0] >= best[i] {
                break;
            }
            best[i] = best[i].min(distance(i, j));
        }
        for &j in order[..k].iter().rev() {
            if points[i][0] - points[j][0] >= best[i] {
                break;
            }
            best[i] = best[i].min(distance(i, j));
        }
    }
    best
}

impl Figure for Separations<'_> {
    fn name(&self) -> &'static str {
        "separations"
    }

    fn size(&self) -> (u32, u32) {
        (1000, 560)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), DrawError> {
        let n = self.nearest_m.len();
        let min_m = self.nearest_m[0];
        let median_m = self.nearest_m[n / 2];
        let max_m = self.nearest_m[n - 1];
        let title = self.context.title(&format!(
            "distance to the nearest neighbour at t = {}, {n} satellites (Hill LVLH)",
            self.context.time.label_value(self.t_s)
        ));
        let body = figure_title(root, &title)?;
        let width = (max_m / BINS as f64).max(f64::MIN_POSITIVE);
        let mut counts = [0u32; BINS];
        for d in &self.nearest_m {
            counts[((d / width) as usize).min(BINS - 1)] += 1;
        }
        let top = f64::from(counts.iter().copied().max().unwrap_or(1)) * 1.1;
        let mut chart = panel(&body, 0.0..max_m * 1.05, 0.0..top)?;
        axes(
            &mut chart,
            "nearest-neighbour distance [m]",
            "satellites [-]",
        )?;
        chart.draw_series(counts.iter().enumerate().map(|(k, &c)| {
            let x0 = k as f64 * width;
            Rectangle::new(
                [(x0, 0.0), (x0 + width, f64::from(c))],
                RGBColor(31, 119, 180).mix(0.7).filled(),
            )
        }))?;
        for (value, colour, what) in [
            (min_m, RGBColor(200, 0, 0), "smallest"),
            (median_m, BLACK, "median"),
        ] {
            chart
                .draw_series(std::iter::once(PathElement::new(
                    vec![(value, 0.0), (value, top)],
                    colour.stroke_width(2),
                )))?
                .label(format!("{what}: {} m", tick(value)))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
                });
        }
        legend(&mut chart, SeriesLabelPosition::UpperRight)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sweep_finds_every_nearest_neighbour_of_the_brute_force() {
        // A deterministic scatter (a quadratic-residue lattice) with close pairs and spread in x.
        let points: Vec<[f64; 3]> = (0..300u64)
            .map(|k| {
                let a = (k * k * 7919 % 1009) as f64;
                let b = (k * 104_729 % 997) as f64;
                let c = (k * 31 % 101) as f64;
                [a * 0.37, b * 0.11, c]
            })
            .collect();
        let swept = nearest_neighbour_distances_m(&points);
        for (i, p) in points.iter().enumerate() {
            let brute = points
                .iter()
                .enumerate()
                .filter(|(j, _)| *j != i)
                .map(|(_, q)| (0..3).map(|c| (p[c] - q[c]).powi(2)).sum::<f64>().sqrt())
                .fold(f64::INFINITY, f64::min);
            assert_eq!(swept[i], brute, "point {i}");
        }
        assert!(nearest_neighbour_distances_m(&points[..1]).is_empty());
    }
}
