//! Figures of the satellites' positions in Hill LVLH (x radial out, y along-track, z orbit normal,
//! relative to the LVLH origin), from `trajectory.csv` and `scene.json`:
//!
//! * `trajectories`: the relative motion in the three projections of the RTN/Hill frame
//!   (radial–along-track, along-track–cross-track, radial–cross-track) of every drawn track (all
//!   satellites, a subsample, or those `satflock plot --satellites` chooses), start (open circle) and
//!   end (dot), the law's target formation at t = 0 (grey crosses), threats (their line over the run,
//!   and the danger sphere at the threat's closest recorded approach to a drawn satellite) and
//!   obstacles (their spheres, which project to circles);
//! * `snapshots`: the formation in its main plane (the two axes of largest extent) at t = 0, at the last
//!   recording before each event of `scenario.toml` and at the end (at most [`MAX_SNAPSHOTS`] panels;
//!   with no events, at t = 0, T/3, 2T/3 and T), with the target formation in the panels before the first
//!   event.
//!
//! Both use equal scales on their two axes, so circles look round. A projection shows the box the drawn
//! tracks span along its third axis: a threat or obstacle is drawn in a projection only where its
//! sphere meets that box (a threat's path only over the times it does, its danger sphere only at a
//! time it does), never projected onto the formation from far out of the plane. At most
//! [`MAX_SCENE_OBJECTS`](super::MAX_SCENE_OBJECTS) threats and as many obstacles are drawn (evenly spaced
//! by index; the figure's title and [`scene_cuts`] say so).

use std::collections::{BTreeMap, BTreeSet};
use std::ops::Range;

use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

use satflock::output::scene::{SceneObstacle, SceneThreat};
use satflock::output::RunData;
use satflock::scenario::ScenarioFile;

use super::{
    axes, caption, evenly_spaced, figure_title, legend, panel, size, DrawError, Figure, RunContext,
    FONT, MARGIN, MAX_SCENE_OBJECTS, MAX_TRACKS, MAX_TRACK_POINTS, X_LABEL_AREA, Y_LABEL_AREA,
};

/// Most snapshot panels.
pub const MAX_SNAPSHOTS: usize = 8;

/// Axis names of Hill LVLH, with units.
const AXIS_NAMES: [&str; 3] = ["x radial [m]", "y along-track [m]", "z orbit normal [m]"];

/// The three projections: (horizontal axis, vertical axis, caption).
const PROJECTIONS: [(usize, usize, &str); 3] = [
    (1, 0, "radial–along-track (x–y, orbital plane)"),
    (1, 2, "along-track–cross-track (y–z)"),
    (0, 2, "radial–cross-track (x–z)"),
];

/// The Hill axis a projection onto axes `h` and `v` leaves out.
fn third_axis(h: usize, v: usize) -> usize {
    3 - h - v
}

/// Most target-formation points drawn (evenly spaced by index beyond).
pub const MAX_TARGET_POINTS: usize = 1000;

/// Points drawn per obstacle or danger-sphere outline.
const CIRCLE_POINTS: usize = 96;

/// One satellite's recordings.
pub(crate) struct Track {
    /// Satellite id.
    pub id: usize,
    /// Recording times \[s\].
    pub t: Vec<f64>,
    /// Positions, Hill LVLH \[m\].
    pub p: Vec<[f64; 3]>,
}

impl Track {
    /// Position at recording time `t_s`, if the satellite was recorded then.
    fn at(&self, t_s: f64) -> Option<[f64; 3]> {
        self.t
            .binary_search_by(|t| t.total_cmp(&t_s))
            .ok()
            .map(|k| self.p[k])
    }

    /// Every k-th recording (and the last), at most [`MAX_TRACK_POINTS`].
    fn decimated(&self) -> impl Iterator<Item = &[f64; 3]> {
        let n = self.p.len();
        let stride = n.div_ceil(MAX_TRACK_POINTS).max(1);
        self.p
            .iter()
            .enumerate()
            .filter(move |(k, _)| k % stride == 0 || *k + 1 == n)
            .map(|(_, p)| p)
    }
}

/// The drawn tracks of a run.
pub(crate) struct Tracks {
    /// Satellites in `trajectory.csv`.
    pub total: usize,
    /// Drawn satellites (all, an evenly spaced subsample of ids, or the chosen ones), in id order.
    pub drawn: Vec<Track>,
    /// Whether the drawn satellites are the ones the caller chose.
    chosen: bool,
    /// Every recording time \[s\], sorted.
    pub times: Vec<f64>,
}

impl Tracks {
    /// The tracks of the run's trajectory (`Ok(None)` when the run wrote none): of the satellites
    /// `only` lists, or of all (an evenly spaced subsample beyond [`MAX_TRACKS`]). The rows were
    /// checked by [`RunData::read`]: times and positions have values, ids are satellite indices.
    ///
    /// # Errors
    /// A satellite of `only` that the trajectory does not hold, with the ids it holds.
    pub fn read(run: &RunData, only: Option<&[usize]>) -> Result<Option<Self>, String> {
        let Some(table) = run.trajectory.as_ref() else {
            return Ok(None);
        };
        let (Some(t), Some(id), Some(x), Some(y), Some(z)) = (
            table.column("t_s"),
            table.column("id"),
            table.column("x_lvlh_m"),
            table.column("y_lvlh_m"),
            table.column("z_lvlh_m"),
        ) else {
            return Ok(None);
        };
        let xyz = [x, y, z];
        let ids: BTreeSet<usize> = id.iter().map(|v| *v as usize).collect();
        let ids: Vec<usize> = ids.into_iter().collect();
        let total = ids.len();
        let chosen: BTreeSet<usize> = match only {
            Some(only) => {
                if let Some(missing) = only.iter().find(|i| ids.binary_search(i).is_err()) {
                    return Err(format!(
                        "satellite {missing} is not in the trajectory (allowed: ids 0..{}; {} \
                         satellites recorded)",
                        ids.last().map_or(0, |last| last + 1),
                        total
                    ));
                }
                only.iter().copied().collect()
            }
            None => evenly_spaced(total, MAX_TRACKS)
                .into_iter()
                .map(|k| ids[k])
                .collect(),
        };
        let mut tracks: BTreeMap<usize, Track> = BTreeMap::new();
        let mut times = BTreeSet::new();
        for row in 0..table.rows() {
            times.insert(t[row].to_bits());
            let i = id[row] as usize;
            if !chosen.contains(&i) {
                continue;
            }
            let track = tracks.entry(i).or_insert_with(|| Track {
                id: i,
                t: Vec::new(),
                p: Vec::new(),
            });
            track.t.push(t[row]);
            track.p.push([xyz[0][row], xyz[1][row], xyz[2][row]]);
        }
        let mut times: Vec<f64> = times.into_iter().map(f64::from_bits).collect();
        times.sort_by(f64::total_cmp);
        let drawn: Vec<Track> = tracks.into_values().collect();
        Ok((!drawn.is_empty()).then_some(Self {
            total,
            drawn,
            chosen: only.is_some(),
            times,
        }))
    }

    /// What the tracks show, for a title: all satellites, the chosen ones, or the subsample.
    fn coverage(&self) -> String {
        if self.chosen {
            let ids: Vec<String> = self.drawn.iter().map(|t| t.id.to_string()).collect();
            format!("satellites {} of {}", ids.join(", "), self.total)
        } else if self.drawn.len() < self.total {
            format!(
                "{} of {} satellites shown (evenly spaced ids)",
                self.drawn.len(),
                self.total
            )
        } else {
            format!("{} satellites", self.total)
        }
    }

    fn t_end(&self) -> f64 {
        self.times.last().copied().unwrap_or(0.0)
    }

    /// Every position of every drawn track.
    fn points(&self) -> impl Iterator<Item = &[f64; 3]> {
        self.drawn.iter().flat_map(|t| t.p.iter())
    }

    /// The extent of the drawn tracks along Hill axis `axis` \[m\]: the depth a projection leaving
    /// that axis out shows.
    fn depth(&self, axis: usize) -> Depth {
        let (lo, hi) = self
            .points()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p[axis]), hi.max(p[axis]))
            });
        Depth { axis, lo, hi }
    }
}

/// The slab a projection shows along the axis it leaves out: the drawn tracks' extent \[m\].
#[derive(Clone, Copy, Debug, PartialEq)]
struct Depth {
    axis: usize,
    lo: f64,
    hi: f64,
}

impl Depth {
    /// Whether a sphere of radius `r` about `c` meets the slab.
    fn meets(&self, c: &[f64; 3], r: f64) -> bool {
        c[self.axis] + r >= self.lo && c[self.axis] - r <= self.hi
    }

    /// The times within `span` \[s\] at which `threat`'s danger sphere meets the slab (its path is
    /// a straight line: one interval, or none).
    fn threat_span(&self, threat: &SceneThreat, span: (f64, f64)) -> Option<(f64, f64)> {
        let r = threat.danger_radius_m;
        let (lo, hi) = (self.lo - r, self.hi + r);
        let c0 = threat.position_lvlh_m(0.0)[self.axis];
        let rate = threat.velocity_lvlh_mps[self.axis];
        let (a, b) = if rate == 0.0 {
            if (lo..=hi).contains(&c0) {
                span
            } else {
                return None;
            }
        } else {
            let (t1, t2) = ((lo - c0) / rate, (hi - c0) / rate);
            (t1.min(t2).max(span.0), t1.max(t2).min(span.1))
        };
        (a <= b).then_some((a, b))
    }
}

/// The target formation as drawn: all of `scene.json`'s points, or an evenly spaced subsample.
pub(crate) struct Targets {
    /// Drawn points, Hill LVLH \[m\].
    points: Vec<[f64; 3]>,
    /// Points in `scene.json`.
    total: usize,
}

impl Targets {
    /// The target formation of a run's scene (`None` when it has none).
    pub fn of(scene: &satflock::output::Scene) -> Option<Self> {
        let all = scene.target_formation_lvlh_m.as_deref()?;
        let total = all.len();
        let points = evenly_spaced(total, MAX_TARGET_POINTS)
            .into_iter()
            .map(|k| all[k])
            .collect();
        Some(Self { points, total })
    }

    fn legend(&self) -> String {
        if self.points.len() < self.total {
            format!(
                "target formation (law at t = 0; {} of {} points)",
                self.points.len(),
                self.total
            )
        } else {
            "target formation (law at t = 0)".into()
        }
    }
}

/// The threats and obstacles a figure draws: at most [`MAX_SCENE_OBJECTS`] of each, evenly spaced by
/// index.
struct DrawnObjects<'a> {
    threats: Vec<&'a SceneThreat>,
    obstacles: Vec<SceneObstacle>,
}

impl<'a> DrawnObjects<'a> {
    fn of(scene: &'a satflock::output::Scene) -> Self {
        Self {
            threats: evenly_spaced(scene.threats.len(), MAX_SCENE_OBJECTS)
                .into_iter()
                .map(|k| &scene.threats[k])
                .filter(|t| !t.tracked)
                .collect(),
            obstacles: evenly_spaced(scene.obstacles.len(), MAX_SCENE_OBJECTS)
                .into_iter()
                .map(|k| scene.obstacles[k].clone())
                .filter(|o| !o.tracked)
                .collect(),
        }
    }
}

/// What the figures leave out of a scene (empty when every threat and obstacle is drawn), for the
/// figure's title and stderr.
pub(crate) fn scene_cuts(scene: &satflock::output::Scene) -> Vec<String> {
    [
        ("threats", scene.threats.len()),
        ("obstacles", scene.obstacles.len()),
    ]
    .into_iter()
    .filter(|(_, n)| *n > MAX_SCENE_OBJECTS)
    .map(|(what, n)| format!("{MAX_SCENE_OBJECTS} of {n} {what} drawn (evenly spaced by index)"))
    .chain(
        [
            ("threat", scene.threats.iter().filter(|t| t.tracked).count()),
            (
                "obstacle",
                scene.obstacles.iter().filter(|o| o.tracked).count(),
            ),
        ]
        .into_iter()
        .filter(|(_, n)| *n > 0)
        .map(|(what, n)| format!("{n} tracked {what}(s) not drawn (real objects' paths)")),
    )
    .collect()
}

/// A threat as drawn: its danger sphere's centre at the chosen time and that time.
struct ThreatMark<'a> {
    threat: &'a SceneThreat,
    t_s: f64,
    center: [f64; 3],
}

/// The time at which `threat` came closest to a drawn satellite over the recordings (t = 0 without any).
fn closest_recorded_approach<'a>(threat: &'a SceneThreat, tracks: &Tracks) -> ThreatMark<'a> {
    let mut best = (f64::INFINITY, 0.0);
    for track in &tracks.drawn {
        for (t, p) in track.t.iter().zip(&track.p) {
            let c = threat.position_lvlh_m(*t);
            let d2: f64 = (0..3).map(|k| (p[k] - c[k]).powi(2)).sum();
            if d2 < best.0 {
                best = (d2, *t);
            }
        }
    }
    ThreatMark {
        threat,
        t_s: best.1,
        center: threat.position_lvlh_m(best.1),
    }
}

/// Horizontal and vertical ranges with equal scales for a plotting area of `pixels` (w, h), holding
/// `bounds` (h range, v range) with a 5 % margin.
fn equal_scale_ranges(bounds: [Range<f64>; 2], pixels: (u32, u32)) -> (Range<f64>, Range<f64>) {
    let [h, v] = bounds;
    let (w_px, h_px) = (f64::from(pixels.0.max(1)), f64::from(pixels.1.max(1)));
    let span_h = (h.end - h.start).max(0.0);
    let span_v = (v.end - v.start).max(0.0);
    let mut per_px = (1.1 * span_h / w_px).max(1.1 * span_v / h_px);
    if per_px <= 0.0 || !per_px.is_finite() {
        per_px = 2.0 / w_px.min(h_px); // a single point: ±1 m
    }
    let (ch, cv) = (0.5 * (h.start + h.end), 0.5 * (v.start + v.end));
    let (half_h, half_v) = (0.5 * per_px * w_px, 0.5 * per_px * h_px);
    (ch - half_h..ch + half_h, cv - half_v..cv + half_v)
}

/// Bounds of a set of points projected on axes (h, v).
struct Bounds {
    h: (f64, f64),
    v: (f64, f64),
}

impl Bounds {
    fn new() -> Self {
        Self {
            h: (f64::INFINITY, f64::NEG_INFINITY),
            v: (f64::INFINITY, f64::NEG_INFINITY),
        }
    }

    fn add(&mut self, h: f64, v: f64) {
        self.h = (self.h.0.min(h), self.h.1.max(h));
        self.v = (self.v.0.min(v), self.v.1.max(v));
    }

    fn add_circle(&mut self, h: f64, v: f64, r: f64) {
        self.add(h - r, v - r);
        self.add(h + r, v + r);
    }

    fn ranges(&self) -> [Range<f64>; 2] {
        if self.h.0 > self.h.1 {
            return [0.0..0.0, 0.0..0.0];
        }
        [self.h.0..self.h.1, self.v.0..self.v.1]
    }
}

/// The plotting area's size inside a panel area (margins and label areas taken off) \[px\].
fn plotting_pixels(area_px: (u32, u32)) -> (u32, u32) {
    (
        area_px.0.saturating_sub(2 * MARGIN + Y_LABEL_AREA),
        area_px.1.saturating_sub(2 * MARGIN + X_LABEL_AREA),
    )
}

/// The outline of a circle of radius `r` about (h, v).
fn circle(h: f64, v: f64, r: f64) -> Vec<(f64, f64)> {
    (0..=CIRCLE_POINTS)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / CIRCLE_POINTS as f64;
            (h + r * a.cos(), v + r * a.sin())
        })
        .collect()
}

/// The part of segment a–b inside the rectangle `h × v` (Liang–Barsky), if any.
fn clip_segment(
    a: (f64, f64),
    b: (f64, f64),
    h: &Range<f64>,
    v: &Range<f64>,
) -> Option<[(f64, f64); 2]> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, a.0 - h.start),
        (dx, h.end - a.0),
        (-dy, a.1 - v.start),
        (dy, v.end - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    (t0 <= t1).then_some([
        (a.0 + t0 * dx, a.1 + t0 * dy),
        (a.0 + t1 * dx, a.1 + t1 * dy),
    ])
}

/// Track colours (matplotlib's "tab10": dark enough on white to read as thin lines).
const TRACK_COLOURS: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// Colour of satellite `id`'s track (the same in every figure), and of the k-th series of an overlay.
pub(crate) fn track_colour(id: usize) -> RGBColor {
    TRACK_COLOURS[id % TRACK_COLOURS.len()]
}

const TARGET_COLOUR: RGBColor = RGBColor(90, 90, 90);
const THREAT_COLOUR: RGBColor = RGBColor(200, 0, 0);
const OBSTACLE_COLOUR: RGBColor = RGBColor(150, 90, 30);

/// What one projection panel shows besides the tracks.
struct Scene<'a> {
    targets: Option<&'a Targets>,
    obstacles: &'a [SceneObstacle],
    threats: Vec<ThreatMark<'a>>,
    /// Time span of the threat lines \[s\].
    threat_span_s: (f64, f64),
    /// The slab the panel shows along its third axis: obstacles, danger spheres and threat paths
    /// are drawn only where they meet it.
    depth: Depth,
}

impl Scene<'_> {
    /// The obstacles whose sphere meets the panel's slab.
    fn obstacles(&self) -> impl Iterator<Item = &SceneObstacle> {
        self.obstacles
            .iter()
            .filter(|o| self.depth.meets(&o.center_lvlh_m, o.radius_m))
    }

    /// The danger spheres that meet the panel's slab.
    fn threats(&self) -> impl Iterator<Item = &ThreatMark<'_>> {
        self.threats
            .iter()
            .filter(|m| self.depth.meets(&m.center, m.threat.danger_radius_m))
    }

    /// Adds what must be inside the panel (targets, obstacles, danger spheres) to `bounds`.
    fn bound(&self, bounds: &mut Bounds, h: usize, v: usize) {
        for p in self.targets.map_or(&[][..], |t| &t.points) {
            bounds.add(p[h], p[v]);
        }
        for o in self.obstacles() {
            bounds.add_circle(o.center_lvlh_m[h], o.center_lvlh_m[v], o.radius_m);
        }
        for m in self.threats() {
            bounds.add_circle(m.center[h], m.center[v], m.threat.danger_radius_m);
        }
    }

    /// Draws obstacles, threats and targets on a chart of axes (h, v); with `labelled`, their legend
    /// entries.
    fn draw<DB: DrawingBackend>(
        &self,
        chart: &mut super::Chart<'_, DB>,
        h: usize,
        v: usize,
        labelled: bool,
        time: &super::TimeAxis,
    ) -> Result<(), DrawError> {
        let (x_range, y_range) = (chart.x_range(), chart.y_range());
        for (k, o) in self.obstacles().enumerate() {
            let outline = circle(o.center_lvlh_m[h], o.center_lvlh_m[v], o.radius_m);
            chart.draw_series(std::iter::once(Polygon::new(
                outline.clone(),
                OBSTACLE_COLOUR.mix(0.18).filled(),
            )))?;
            let series = chart.draw_series(std::iter::once(PathElement::new(
                outline,
                OBSTACLE_COLOUR.stroke_width(1),
            )))?;
            if labelled && k == 0 {
                series
                    .label("obstacle (sphere)")
                    .legend(|(x, y)| Circle::new((x + 10, y), 6, OBSTACLE_COLOUR.stroke_width(1)));
            }
            chart.draw_series(std::iter::once(Text::new(
                o.name.clone(),
                (o.center_lvlh_m[h], o.center_lvlh_m[v]),
                (FONT, size::TICKS).into_font().color(&OBSTACLE_COLOUR),
            )))?;
        }
        for (k, m) in self.threats.iter().enumerate() {
            // The path over the times its danger sphere meets the slab.
            let segment = self
                .depth
                .threat_span(m.threat, self.threat_span_s)
                .and_then(|(t0, t1)| {
                    let (a, b) = (m.threat.position_lvlh_m(t0), m.threat.position_lvlh_m(t1));
                    clip_segment((a[h], a[v]), (b[h], b[v]), &x_range, &y_range)
                });
            if let Some(segment) = segment {
                let series = chart.draw_series(std::iter::once(DashedPathElement::new(
                    segment,
                    6,
                    4,
                    THREAT_COLOUR.stroke_width(1),
                )))?;
                if labelled && k == 0 {
                    series
                        .label("threat path (where it is in the slab shown)")
                        .legend(|(x, y)| {
                            DashedPathElement::new(
                                vec![(x, y), (x + 20, y)],
                                6,
                                4,
                                THREAT_COLOUR.stroke_width(1),
                            )
                        });
                }
            }
            if !self.depth.meets(&m.center, m.threat.danger_radius_m) {
                continue;
            }
            let series = chart.draw_series(std::iter::once(PathElement::new(
                circle(m.center[h], m.center[v], m.threat.danger_radius_m),
                THREAT_COLOUR.mix(0.8),
            )))?;
            if labelled && k == 0 {
                series
                    .label("danger sphere at closest approach")
                    .legend(|(x, y)| Circle::new((x + 10, y), 6, THREAT_COLOUR.mix(0.8)));
            }
            chart.draw_series(std::iter::once(Text::new(
                format!("{} (t = {})", m.threat.name, time.label_value(m.t_s)),
                (m.center[h], m.center[v]),
                (FONT, size::TICKS).into_font().color(&THREAT_COLOUR),
            )))?;
        }
        if let Some(targets) = self.targets {
            let series = chart.draw_series(
                targets
                    .points
                    .iter()
                    .map(|p| Cross::new((p[h], p[v]), 4, TARGET_COLOUR.stroke_width(1))),
            )?;
            if labelled {
                series
                    .label(targets.legend())
                    .legend(|(x, y)| Cross::new((x + 10, y), 4, TARGET_COLOUR.stroke_width(1)));
            }
        }
        Ok(())
    }
}

/// The `trajectories` figure.
pub(crate) struct Trajectories<'a> {
    context: &'a RunContext<'a>,
    tracks: &'a Tracks,
    targets: Option<Targets>,
    objects: DrawnObjects<'a>,
}

impl<'a> Trajectories<'a> {
    /// The figure of a run's tracks.
    pub fn new(context: &'a RunContext<'a>, tracks: &'a Tracks) -> Self {
        Self {
            context,
            tracks,
            targets: Targets::of(&context.run.scene),
            objects: DrawnObjects::of(&context.run.scene),
        }
    }

    fn scene(&self, depth: Depth) -> Scene<'_> {
        Scene {
            targets: self.targets.as_ref(),
            obstacles: &self.objects.obstacles,
            threats: self
                .objects
                .threats
                .iter()
                .map(|t| closest_recorded_approach(t, self.tracks))
                .collect(),
            threat_span_s: (0.0, self.tracks.t_end()),
            depth,
        }
    }
}

impl Figure for Trajectories<'_> {
    fn name(&self) -> &'static str {
        "trajectories"
    }

    fn size(&self) -> (u32, u32) {
        (1800, 680)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), DrawError> {
        let time = &self.context.time;
        let mut what = format!(
            "trajectories in Hill LVLH, t = 0 to {}; {}",
            time.label_value(self.tracks.t_end()),
            self.tracks.coverage()
        );
        for cut in scene_cuts(&self.context.run.scene) {
            what.push_str(&format!("; {cut}"));
        }
        let title = self.context.title(&what);
        let body = figure_title(root, &title)?;
        for (k, (area, (h, v, name))) in body
            .split_evenly((1, 3))
            .iter()
            .zip(PROJECTIONS)
            .enumerate()
        {
            let area = caption(area, name)?;
            let scene = self.scene(self.tracks.depth(third_axis(h, v)));
            let mut bounds = Bounds::new();
            for p in self.tracks.points() {
                bounds.add(p[h], p[v]);
            }
            scene.bound(&mut bounds, h, v);
            let (hr, vr) =
                equal_scale_ranges(bounds.ranges(), plotting_pixels(area.dim_in_pixel()));
            let mut chart = panel(&area, hr, vr)?;
            axes(&mut chart, AXIS_NAMES[h], AXIS_NAMES[v])?;
            for track in &self.tracks.drawn {
                chart.draw_series(LineSeries::new(
                    track.decimated().map(|p| (p[h], p[v])),
                    track_colour(track.id).stroke_width(1),
                ))?;
            }
            let first = k == 0;
            let starts = chart.draw_series(
                self.tracks
                    .drawn
                    .iter()
                    .map(|t| Circle::new((t.p[0][h], t.p[0][v]), 3, BLACK.stroke_width(1))),
            )?;
            if first {
                starts
                    .label("start (t = 0 or first recording)")
                    .legend(|(x, y)| Circle::new((x + 10, y), 3, BLACK.stroke_width(1)));
            }
            let ends = chart.draw_series(self.tracks.drawn.iter().map(|t| {
                let p = t.p[t.p.len() - 1];
                Circle::new((p[h], p[v]), 3, BLACK.filled())
            }))?;
            if first {
                ends.label("end (last recording)")
                    .legend(|(x, y)| Circle::new((x + 10, y), 3, BLACK.filled()));
            }
            scene.draw(&mut chart, h, v, first, time)?;
            if first {
                legend(&mut chart, SeriesLabelPosition::UpperRight)?;
            }
        }
        Ok(())
    }
}

/// The `snapshots` figure.
pub(crate) struct Snapshots<'a> {
    context: &'a RunContext<'a>,
    tracks: &'a Tracks,
    /// Recording times shown \[s\], with what each is.
    times: Vec<(f64, String)>,
    /// First event time \[s\] (the target formation is the law's at t = 0: drawn only before it).
    first_event_s: f64,
    /// Horizontal and vertical axes (Hill components).
    plane: (usize, usize),
    targets: Option<Targets>,
    objects: DrawnObjects<'a>,
}

impl<'a> Snapshots<'a> {
    /// The snapshots of a run: at t = 0, before each event of `scenario.toml` and at the end.
    pub fn new(context: &'a RunContext<'a>, tracks: &'a Tracks) -> Self {
        let events = event_times_s(context.run);
        let first_event_s = events.first().copied().unwrap_or(f64::INFINITY);
        Self {
            context,
            tracks,
            times: snapshot_times(&tracks.times, &events, &context.time),
            first_event_s,
            targets: Targets::of(&context.run.scene),
            objects: DrawnObjects::of(&context.run.scene),
            plane: main_plane(tracks),
        }
    }
}

/// Event times of the run, sorted: the timed events of its `scenario.toml` and the firings of its
/// condition events (`summary.json` `events`); none of a file that is missing or unreadable.
fn event_times_s(run: &RunData) -> Vec<f64> {
    let mut times: Vec<f64> = run
        .summary
        .get("events")
        .and_then(|e| e.as_array())
        .map(|firings| {
            firings
                .iter()
                .filter_map(|f| f.get("time_s")?.as_f64())
                .collect()
        })
        .unwrap_or_default();
    let file = satflock::input_file::read_document(&run.dir.join("scenario.toml"))
        .ok()
        .and_then(|text| toml::from_str::<ScenarioFile>(&text).ok());
    if let Some(file) = file {
        times.extend(file.events.iter().filter_map(|e| e.time_s));
    }
    times.retain(|t| t.is_finite());
    times.sort_by(f64::total_cmp);
    times.dedup();
    times
}

/// The recording times to show: the first, the last at or before each event, and the last (or, with no
/// event inside the recordings, the first, those nearest below T/3 and 2T/3, and the last); at most
/// [`MAX_SNAPSHOTS`], evenly picked.
fn snapshot_times(
    recordings: &[f64],
    events: &[f64],
    time: &super::TimeAxis,
) -> Vec<(f64, String)> {
    let (Some(&first), Some(&last)) = (recordings.first(), recordings.last()) else {
        return Vec::new();
    };
    let at_or_before = |t: f64| {
        let k = recordings.partition_point(|r| *r <= t);
        recordings[k.saturating_sub(1)]
    };
    let inside: Vec<f64> = events
        .iter()
        .copied()
        .filter(|t| *t > first && *t < last)
        .collect();
    let mut chosen: Vec<(f64, String)> = vec![(first, "start".to_string())];
    if inside.is_empty() {
        for fraction in [1.0 / 3.0, 2.0 / 3.0] {
            chosen.push((
                at_or_before(first + fraction * (last - first)),
                String::new(),
            ));
        }
    } else {
        for t in inside {
            chosen.push((
                at_or_before(t),
                format!("before the event at {}", time.label_value(t)),
            ));
        }
    }
    chosen.push((last, "end".to_string()));
    chosen.dedup_by(|a, b| a.0 == b.0);
    if chosen.len() > MAX_SNAPSHOTS {
        let n = chosen.len();
        chosen = (0..MAX_SNAPSHOTS)
            .map(|k| chosen[k * (n - 1) / (MAX_SNAPSHOTS - 1)].clone())
            .collect();
    }
    chosen
}

/// The two Hill axes along which the drawn tracks extend most, as (horizontal, vertical) in the order
/// of [`PROJECTIONS`].
fn main_plane(tracks: &Tracks) -> (usize, usize) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in tracks.points() {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let extent: Vec<f64> = (0..3).map(|k| hi[k] - lo[k]).collect();
    // The axis left out: the smallest extent (the first on ties, so z before y before x is kept out last).
    let dropped = (0..3)
        .rev()
        .min_by(|&a, &b| extent[a].total_cmp(&extent[b]))
        .unwrap_or(2);
    let (h, v, _) = PROJECTIONS
        .iter()
        .copied()
        .find(|(h, v, _)| *h != dropped && *v != dropped)
        .unwrap_or(PROJECTIONS[0]);
    (h, v)
}

impl Figure for Snapshots<'_> {
    fn name(&self) -> &'static str {
        "snapshots"
    }

    fn size(&self) -> (u32, u32) {
        let n = self.times.len().max(1) as u32;
        let cols = n.min(4);
        let rows = n.div_ceil(4);
        (cols * 480, rows * 480 + 50)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), DrawError> {
        let time = &self.context.time;
        let (h, v) = self.plane;
        let plane_name = PROJECTIONS
            .iter()
            .find(|p| (p.0, p.1) == (h, v))
            .map_or("", |p| p.2);
        let title = self.context.title(&format!(
            "formation in the {plane_name}, Hill LVLH; {}",
            self.tracks.coverage()
        ));
        let body = figure_title(root, &title)?;
        let n = self.times.len().max(1);
        let panels = body.split_evenly((n.div_ceil(4), n.min(4)));
        // One range for every panel (all recordings, the targets and obstacles), so sizes compare.
        let objects = &self.objects;
        let depth = self.tracks.depth(third_axis(h, v));
        let mut bounds = Bounds::new();
        for p in self.tracks.points() {
            bounds.add(p[h], p[v]);
        }
        Scene {
            targets: self.targets.as_ref(),
            obstacles: &objects.obstacles,
            threats: Vec::new(),
            threat_span_s: (0.0, 0.0),
            depth,
        }
        .bound(&mut bounds, h, v);
        for (area, (t, what)) in panels.iter().zip(&self.times) {
            let label = if what.is_empty() {
                format!("t = {}", time.label_value(*t))
            } else {
                format!("t = {} ({what})", time.label_value(*t))
            };
            let area = caption(area, &label)?;
            let (hr, vr) =
                equal_scale_ranges(bounds.ranges(), plotting_pixels(area.dim_in_pixel()));
            let mut chart = panel(&area, hr.clone(), vr.clone())?;
            axes(&mut chart, AXIS_NAMES[h], AXIS_NAMES[v])?;
            // Threats whose danger sphere at this time is inside the panel and its slab.
            let threats: Vec<ThreatMark<'_>> = objects
                .threats
                .iter()
                .map(|&threat| ThreatMark {
                    threat,
                    t_s: *t,
                    center: threat.position_lvlh_m(*t),
                })
                .filter(|m| {
                    hr.contains(&m.center[h])
                        && vr.contains(&m.center[v])
                        && depth.meets(&m.center, m.threat.danger_radius_m)
                })
                .collect();
            let before_events = *t < self.first_event_s;
            Scene {
                targets: self.targets.as_ref().filter(|_| before_events),
                obstacles: &objects.obstacles,
                threats,
                threat_span_s: (*t, *t),
                depth,
            }
            .draw(&mut chart, h, v, false, time)?;
            chart.draw_series(self.tracks.drawn.iter().filter_map(|track| {
                track
                    .at(*t)
                    .map(|p| Circle::new((p[h], p[v]), 3, track_colour(track.id).filled()))
            }))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segments_are_clipped_to_the_panel() {
        let (h, v) = (0.0..10.0, 0.0..10.0);
        assert_eq!(
            clip_segment((-5.0, 5.0), (15.0, 5.0), &h, &v),
            Some([(0.0, 5.0), (10.0, 5.0)])
        );
        assert_eq!(clip_segment((-5.0, -5.0), (-1.0, 20.0), &h, &v), None);
        assert_eq!(
            clip_segment((2.0, 2.0), (3.0, 3.0), &h, &v),
            Some([(2.0, 2.0), (3.0, 3.0)])
        );
    }

    /// Issue 30: a threat 1500 km out of the plotted plane was drawn on the formation. A projection
    /// shows a threat only where its danger sphere meets the slab of the drawn tracks.
    #[test]
    fn threats_are_drawn_only_where_they_meet_the_slab() {
        let depth = Depth {
            axis: 2,
            lo: -100.0,
            hi: 100.0,
        };
        let threat = SceneThreat {
            name: "t".into(),
            danger_radius_m: 10.0,
            position_at_t0_lvlh_m: [0.0, 0.0, 1.5e6],
            velocity_lvlh_mps: [0.0, 0.0, -500.0],
            tracked: false,
        };
        // Its sphere meets z in [-110, 110] m from t = (1.5e6 - 110) / 500 to (1.5e6 + 110) / 500.
        let (a, b) = depth.threat_span(&threat, (0.0, 6000.0)).unwrap();
        assert!((a - (1.5e6 - 110.0) / 500.0).abs() < 1e-9, "{a}");
        assert!((b - (1.5e6 + 110.0) / 500.0).abs() < 1e-9, "{b}");
        assert!(!depth.meets(&threat.position_lvlh_m(0.0), 10.0));
        assert!(depth.meets(&threat.position_lvlh_m(3000.0), 10.0));
        assert_eq!(depth.threat_span(&threat, (0.0, 2000.0)), None);
        let parked = SceneThreat {
            velocity_lvlh_mps: [1.0, 0.0, 0.0],
            ..threat
        };
        assert_eq!(parked.position_lvlh_m(0.0)[2], 1.5e6);
        assert_eq!(depth.threat_span(&parked, (0.0, 6000.0)), None);
    }

    #[test]
    fn equal_scales_hold_the_bounds() {
        let (h, v) = equal_scale_ranges([0.0..100.0, 0.0..10.0], (200, 100));
        let per_px_h = (h.end - h.start) / 200.0;
        let per_px_v = (v.end - v.start) / 100.0;
        assert!((per_px_h - per_px_v).abs() < 1e-12);
        assert!(h.start <= 0.0 && h.end >= 100.0 && v.start <= 0.0 && v.end >= 10.0);
    }

    #[test]
    fn snapshots_before_each_event_and_at_the_ends() {
        let recordings: Vec<f64> = (0..=80).map(|k| k as f64 * 100.0).collect();
        let axis = crate::plot::TimeAxis::for_duration(8000.0);
        let times: Vec<f64> = snapshot_times(&recordings, &[3000.0, 4050.0], &axis)
            .iter()
            .map(|t| t.0)
            .collect();
        assert_eq!(times, [0.0, 3000.0, 4000.0, 8000.0]);
        let times: Vec<f64> = snapshot_times(&recordings, &[], &axis)
            .iter()
            .map(|t| t.0)
            .collect();
        assert_eq!(times, [0.0, 2600.0, 5300.0, 8000.0]);
        let many: Vec<f64> = (1..40).map(|k| k as f64 * 200.0).collect();
        let times = snapshot_times(&recordings, &many, &axis);
        assert_eq!(times.len(), MAX_SNAPSHOTS);
        assert_eq!((times[0].0, times[MAX_SNAPSHOTS - 1].0), (0.0, 8000.0));
    }
}
