//! Reproduction of H. Qiu, Q. Zhou, C. Sun, X. Wang, Y. Feng, "Distributed Satellite Formation Based on
//! Swarm Intelligence of Pigeon Flocks" (IEEE conference paper): the switching run Q1
//! (`pigeon-switching`) against the non-switching baseline Q2 (`pigeon-baseline`), 20 seeds each (the
//! seed changes only the pattern draws), 6000 s, plus Q1 with the off-by-default extension
//! `target_velocity_damping_per_s` (not in the paper), clearly labelled.
//!
//! Every quantity is measured here from the truth Hill states at every control tick (0.1 s), in the
//! pigeon plane (z, y), independently of the law's own metric columns (which are only cross-checked);
//! the obstacle clearance comes from the engine's continuous monitor.
//!
//! What each outcome is compared with, its criterion and the numbers the criterion uses are data:
//! `validation/pigeon.toml` (P1–P7, with the rows at the former R_c^1 default of 120 m). This module
//! measures and judges; every note it prints is computed from the runs.

use nalgebra::Vector3;

use crate::validate::data::{Outcome, PaperData};
use crate::validate::{Check, Report, Table, ValidateError, Verdict};
use satflock::scenario::{builtin, Scenario};
use satflock::swarm::{Recorder, Simulation, Snapshot};

fn failed(e: impl std::fmt::Display) -> ValidateError {
    ValidateError::Failed {
        target: "pigeon".into(),
        message: e.to_string(),
    }
}

/// Switching run Q1.
pub const Q1: &str = "pigeon-switching";
/// Non-switching baseline Q2.
pub const Q2: &str = "pigeon-baseline";
/// Seeds of every configuration.
pub const SEEDS: std::ops::RangeInclusive<u64> = 1..=20;
/// Runs at once (the machine's cores are shared).
pub const WORKERS: usize = 2;
/// Amplitude of the group's swing about the target at which the extension's damping is chosen
/// critically damped: the middle of the earlier prototype's band d̄_T ≈ 150–600 m, i.e. r − R_L^2 ≈ 325 m.
pub const EXTENSION_SWING_M: f64 = 325.0;

/// One run: a built-in scenario, a seed, optionally shortened, optionally with the extension.
#[derive(Clone, Debug, PartialEq)]
pub struct Job {
    /// Built-in scenario name.
    pub builtin: &'static str,
    /// Seed (changes only the pattern draws).
    pub seed: u64,
    /// Run length \[s\] (`None`: the scenario's 6000 s).
    pub duration_s: Option<f64>,
    /// `target_velocity_damping_per_s` (the extension; `None`: the scenario's, i.e. off).
    pub damping_per_s: Option<f64>,
    /// `egalitarian_range_m`, R_c^1 \[m\] (`None`: the scenario's).
    pub egalitarian_range_m: Option<f64>,
}

/// The windows and bands the per-run measurements use, from `validation/pigeon.toml`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Windows {
    /// End of the comparison window whose end value is P1's "final" value \[s\].
    pub window_s: f64,
    /// Half-width of the stabilisation band (relative).
    pub band_rel: f64,
    /// Window of P3's time-mean order parameter \[s\].
    pub order_window_s: f64,
    /// Start of P4's interval \[s\].
    pub p4_from_s: f64,
    /// P5: time after which the radial offset must be small \[s\].
    pub p5_after_s: f64,
    /// P2's comparison instant \[s\].
    pub compare_at_s: f64,
}

/// The paper's data file.
pub fn data() -> Result<PaperData, ValidateError> {
    PaperData::of("pigeon").ok_or_else(|| failed("no validation/pigeon.toml"))?
}

impl Windows {
    /// The windows of the data file.
    pub fn from_data(data: &PaperData) -> Result<Self, ValidateError> {
        let p1 = data.outcome("P1")?;
        Ok(Self {
            window_s: p1.value("window_s")?,
            band_rel: p1.value("band_rel")?,
            order_window_s: data.outcome("P3")?.value("window_s")?,
            p4_from_s: data.outcome("P4")?.value("from_s")?,
            p5_after_s: data.outcome("P5")?.value("after_s")?,
            compare_at_s: data.outcome("P2")?.value("compare_at_s")?,
        })
    }
}

/// P7's gate on the pair separation \[m\], from the data file.
pub fn p7_min_separation_m() -> Result<f64, ValidateError> {
    data()?.outcome("P7")?.value("min_separation_m")
}

/// Measurements of one run (truth states, pigeon plane (z, y), every control tick).
#[derive(Clone, Debug, PartialEq)]
pub struct Run {
    /// The job.
    pub job: Job,
    /// Control ticks \[s\].
    pub tick_s: f64,
    /// Mean pair distance d̄ at every whole second \[m\].
    pub mean_distance_m: Vec<f64>,
    /// Mean target distance d̄_T at every whole second \[m\].
    pub mean_target_distance_m: Vec<f64>,
    /// Global order parameter V_a at every whole second.
    pub order_parameter: Vec<f64>,
    /// P1: stabilisation time against d̄(200 s) \[s\] (`None` if the run is shorter).
    pub stabilisation_window_s: Option<f64>,
    /// Stabilisation time against d̄ at the end of the run \[s\].
    pub stabilisation_final_s: f64,
    /// P2: first time d̄_T < R_L^2 \[s\].
    pub target_zone_s: Option<f64>,
    /// d̄_T at P2's comparison instant (the paper's 61 s) \[m\].
    pub target_distance_compare_m: Option<f64>,
    /// P3: time mean of V_a over the first 100 s.
    pub order_mean: Option<f64>,
    /// P4: maximum d̄_T over [500 s, end] \[m\].
    pub p4_max_target_distance_m: Option<f64>,
    /// P4: maximum |d̄/d̄(500 s) − 1| over [500 s, end].
    pub p4_max_distance_change: Option<f64>,
    /// P5: max_i |x_i| over (60 s, end] \[m\].
    pub max_radial_after_m: f64,
    /// P7: minimum pair separation in the pigeon plane over the ticks \[m\].
    pub min_separation_plane_m: f64,
    /// The pair and the time of that minimum: (satellite, satellite, time \[s\]).
    pub min_separation_pair: (usize, usize, f64),
    /// How often the sign of the centroid's angular momentum about the target (pigeon plane) changes.
    pub centroid_momentum_sign_changes: usize,
    /// The centroid's closest approach to the target in the pigeon plane, and when: (\[m\], \[s\]).
    pub centroid_closest: (f64, f64),
    /// The engine's minimum 3-D separation (every step) \[m\].
    pub min_separation_m: f64,
    /// P6: the engine's continuous minimum clearance: (clearance \[m\], satellite, obstacle, time \[s\]).
    pub min_clearance: Option<(f64, usize, usize, f64)>,
    /// Last tick at which a satellite was within detection range (surface + R_c^3) of an obstacle \[s\].
    pub last_near_obstacle_s: Option<f64>,
    /// First tick at which every satellite is past the obstacles on the way in: nearer the target (in
    /// the plane) than the nearest point of every obstacle's detection sphere, min_j(|c_j| − ρ_j) \[s\].
    pub passed_obstacles_s: Option<f64>,
    /// Δv per satellite, ∫‖f̄‖dt \[m/s\].
    pub delta_v_mps: Vec<f64>,
    /// Pattern switches so far at the end (the law's counter).
    pub switches: Option<f64>,
    /// Largest difference between the law's V_a, d̄, d̄_T columns and ours at the recordings.
    pub law_metric_mismatch: Option<f64>,
    /// Final truth states, Hill frame: position \[m\], velocity \[m/s\].
    pub final_states: Vec<(Vector3<f64>, Vector3<f64>)>,
}

/// The TOML of a job: the built-in with the seed, duration and extension set.
pub fn scenario_text(job: &Job) -> Result<String, ValidateError> {
    let b =
        builtin::find(job.builtin).ok_or_else(|| failed(format!("no built-in {}", job.builtin)))?;
    let mut doc: toml::Table = toml::from_str(b.toml).map_err(failed)?;
    doc.insert("seed".into(), toml::Value::Integer(job.seed as i64));
    if let Some(d) = job.duration_s {
        doc.insert("duration_s".into(), toml::Value::Float(d));
    }
    let law = doc
        .get_mut("law")
        .and_then(toml::Value::as_table_mut)
        .ok_or_else(|| failed("scenario without [law]"))?;
    if let Some(k) = job.damping_per_s {
        law.insert(
            "target_velocity_damping_per_s".into(),
            toml::Value::Float(k),
        );
    }
    if let Some(r) = job.egalitarian_range_m {
        law.insert("egalitarian_range_m".into(), toml::Value::Float(r));
    }
    toml::to_string(&doc).map_err(failed)
}

/// A law parameter of a built-in, as a float (integers accepted).
fn law_value(name: &str, key: &str) -> Result<f64, ValidateError> {
    let b = builtin::find(name).ok_or_else(|| failed(format!("no built-in {name}")))?;
    let doc: toml::Table = toml::from_str(b.toml).map_err(failed)?;
    let v = doc
        .get("law")
        .and_then(|l| l.get(key))
        .ok_or_else(|| failed(format!("{name}: no law key {key}")))?;
    v.as_float()
        .or_else(|| v.as_integer().map(|i| i as f64))
        .ok_or_else(|| failed(format!("{name}: {key} is not a number")))
}

/// The extension's damping, chosen critically damped for the group's centroid at the swing amplitude
/// [`EXTENSION_SWING_M`]: internal forces cancel in the centroid, so N·a_c = |S_d|·(−K^T(r−R_L^2)² −
/// K^{T,v} v); linearised at r − R_L^2 = A the stiffness is ω² = (|S_d|/N)·2K^T·A and critical damping
/// needs (|S_d|/N)·K^{T,v} = 2ω. Returns (K^{T,v}, ω).
pub fn extension_damping_per_s() -> Result<(f64, f64), ValidateError> {
    let b = builtin::find(Q1).ok_or_else(|| failed("no Q1"))?;
    let doc: toml::Table = toml::from_str(b.toml).map_err(failed)?;
    let dominant = doc
        .get("law")
        .and_then(|l| l.get("dominant"))
        .and_then(toml::Value::as_array)
        .map_or(0, Vec::len) as f64;
    let n = doc
        .get("satellites")
        .and_then(|s| s.get("count"))
        .and_then(toml::Value::as_integer)
        .ok_or_else(|| failed("Q1: no satellites.count"))? as f64;
    let k_t = law_value(Q1, "k_target_per_m_s2")?;
    let share = dominant / n;
    let omega = (share * 2.0 * k_t * EXTENSION_SWING_M).sqrt();
    Ok((2.0 * omega / share, omega))
}

struct LawColumns {
    names: &'static [&'static str],
    rows: Vec<(f64, Vec<f64>)>,
}

impl Recorder for LawColumns {
    fn record(&mut self, s: &Snapshot<'_>) -> std::io::Result<()> {
        self.names = s.law_metric_names;
        self.rows.push((s.time_s, s.law_metrics.to_vec()));
        Ok(())
    }
}

/// What [`plane_metrics`] measures at one instant, in the pigeon plane (z, y).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneMetrics {
    /// Mean pair distance d̄ \[m\].
    pub mean_distance_m: f64,
    /// Mean target distance d̄_T \[m\].
    pub mean_target_distance_m: f64,
    /// Global order parameter V_a.
    pub order_parameter: f64,
    /// Smallest pair distance \[m\] and its pair.
    pub min_pair: (f64, usize, usize),
}

/// d̄, d̄_T, V_a and the closest pair in the pigeon plane (z, y) of the given Hill states.
pub fn plane_metrics(states: &[(Vector3<f64>, Vector3<f64>)]) -> PlaneMetrics {
    let n = states.len();
    let p: Vec<[f64; 2]> = states.iter().map(|s| [s.0.z, s.0.y]).collect();
    let mut sum = 0.0;
    let mut min = (f64::INFINITY, 0, 0);
    let mut pairs = 0usize;
    for i in 0..n {
        for j in i + 1..n {
            let d = (p[i][0] - p[j][0]).hypot(p[i][1] - p[j][1]);
            sum += d;
            if d < min.0 {
                min = (d, i, j);
            }
            pairs += 1;
        }
    }
    let mean_distance = if pairs > 0 { sum / pairs as f64 } else { 0.0 };
    let mean_target = p.iter().map(|q| q[0].hypot(q[1])).sum::<f64>() / n as f64;
    let mut heading = [0.0, 0.0];
    for s in states {
        let v = [s.1.z, s.1.y];
        let norm = v[0].hypot(v[1]);
        if norm >= 1e-9 {
            heading[0] += v[0] / norm;
            heading[1] += v[1] / norm;
        }
    }
    PlaneMetrics {
        mean_distance_m: mean_distance,
        mean_target_distance_m: mean_target,
        order_parameter: heading[0].hypot(heading[1]) / n as f64,
        min_pair: min,
    }
}

/// The centroid's position and velocity in the pigeon plane (z, y).
fn centroid_plane(states: &[(Vector3<f64>, Vector3<f64>)]) -> ([f64; 2], [f64; 2]) {
    let n = states.len().max(1) as f64;
    let (mut c, mut v) = ([0.0; 2], [0.0; 2]);
    for (p, u) in states {
        c[0] += p.z / n;
        c[1] += p.y / n;
        v[0] += u.z / n;
        v[1] += u.y / n;
    }
    (c, v)
}

/// Last time a series leaves the band ±`band_rel` around `reference` (the time it enters for good; 0
/// if never outside).
fn stabilisation_s(times: &[f64], series: &[f64], reference: f64, band_rel: f64) -> f64 {
    let tol = band_rel * reference.abs();
    match series.iter().rposition(|d| (d - reference).abs() > tol) {
        Some(k) if k + 1 < times.len() => times[k + 1],
        Some(k) => times[k],
        None => times.first().copied().unwrap_or(0.0),
    }
}

/// Runs one job on the current thread's rayon pool.
pub fn run_job(job: &Job) -> Result<Run, ValidateError> {
    let w = Windows::from_data(&data()?)?;
    let text = scenario_text(job)?;
    let scenario = Scenario::from_toml(
        &text,
        &format!("builtin:{}", job.builtin),
        std::path::Path::new("."),
    )
    .map_err(failed)?;
    let zone_m = law_value(job.builtin, "target_zone_m")?;
    let prepared = scenario.prepare().map_err(failed)?;
    // The paper's obstacles are static: their centres at t = 0 hold for the whole run.
    let detection: Vec<(Vector3<f64>, f64)> = prepared
        .config
        .obstacles
        .iter()
        .map(|o| {
            (
                o.center_hill_m(0.0),
                o.radius_m()
                    + o.detection_range_m()
                        .unwrap_or(prepared.config.sensing.range_m),
            )
        })
        .collect();
    let duration = prepared.config.duration_s;
    let mut sim = Simulation::new(
        prepared.config,
        &prepared.satellites,
        prepared.law,
        prepared.events,
    )
    .map_err(failed)?;
    let tick = sim.config().base_step_s();
    let ticks = (duration / tick).round() as u64;
    let per_second = (1.0 / tick).round() as u64;
    let states = |sim: &Simulation| -> Vec<(Vector3<f64>, Vector3<f64>)> {
        sim.states_hill()
            .iter()
            .map(|s| (s.position_m, s.velocity_mps))
            .collect()
    };
    let mut columns = LawColumns {
        names: &[],
        rows: Vec::new(),
    };
    let mut times = Vec::with_capacity(ticks as usize + 1);
    let mut dbar = Vec::with_capacity(ticks as usize + 1);
    let mut dtar = Vec::with_capacity(ticks as usize + 1);
    let mut order = Vec::with_capacity(ticks as usize + 1);
    let mut min_plane = (f64::INFINITY, 0, 0, 0.0);
    let mut momentum_sign = 0.0f64;
    let mut sign_changes = 0usize;
    let mut centroid_closest = (f64::INFINITY, 0.0);
    let mut max_radial_after = 0.0f64;
    let mut last_near = None;
    let mut passed = None;
    let inner_m = detection
        .iter()
        .map(|(c, reach)| c.yz().norm() - reach)
        .fold(f64::INFINITY, f64::min);
    for k in 0..=ticks {
        if k > 0 {
            sim.advance_to(k as f64 * tick, &mut columns)
                .map_err(failed)?;
        }
        let t = sim.time_s();
        let s = states(&sim);
        let m = plane_metrics(&s);
        times.push(t);
        dbar.push(m.mean_distance_m);
        dtar.push(m.mean_target_distance_m);
        order.push(m.order_parameter);
        if m.min_pair.0 < min_plane.0 {
            min_plane = (m.min_pair.0, m.min_pair.1, m.min_pair.2, t);
        }
        let (c, v) = centroid_plane(&s);
        let momentum = c[0] * v[1] - c[1] * v[0];
        if momentum != 0.0 {
            if momentum_sign != 0.0 && momentum.signum() != momentum_sign {
                sign_changes += 1;
            }
            momentum_sign = momentum.signum();
        }
        let r = c[0].hypot(c[1]);
        if r < centroid_closest.0 {
            centroid_closest = (r, t);
        }
        if t > w.p5_after_s {
            for (p, _) in &s {
                max_radial_after = max_radial_after.max(p.x.abs());
            }
        }
        if s.iter()
            .any(|(p, _)| detection.iter().any(|(c, reach)| (p - c).norm() <= *reach))
        {
            last_near = Some(t);
        }
        if passed.is_none() && s.iter().all(|(p, _)| p.yz().norm() < inner_m) {
            passed = Some(t);
        }
    }
    if sim.active().iter().any(|a| !a) {
        return Err(failed(format!("{job:?}: a satellite was removed")));
    }
    let at = |t: f64| -> Option<usize> {
        (t <= duration + 1e-9).then(|| ((t / tick).round() as usize).min(times.len() - 1))
    };
    let stabilisation_window_s =
        at(w.window_s).map(|k| stabilisation_s(&times[..=k], &dbar[..=k], dbar[k], w.band_rel));
    let stabilisation_final_s =
        stabilisation_s(&times, &dbar, *dbar.last().expect("tick 0"), w.band_rel);
    let target_zone_s = dtar.iter().position(|d| *d < zone_m).map(|k| times[k]);
    let order_mean = at(w.order_window_s).map(|k| order[..=k].iter().sum::<f64>() / (k + 1) as f64);
    let (p4_max_target_distance_m, p4_max_distance_change) = match at(w.p4_from_s) {
        Some(k) => (
            Some(dtar[k..].iter().copied().fold(f64::NEG_INFINITY, f64::max)),
            Some(
                dbar[k..]
                    .iter()
                    .map(|d| (d / dbar[k] - 1.0).abs())
                    .fold(0.0, f64::max),
            ),
        ),
        None => (None, None),
    };
    // Cross-check of the law's own columns at the recordings.
    let find = |name: &str| columns.names.iter().position(|n| *n == name);
    let law_metric_mismatch = match (
        find("pigeon_order_parameter"),
        find("pigeon_mean_distance_m"),
        find("pigeon_mean_target_distance_m"),
    ) {
        (Some(a), Some(b), Some(c)) => Some(
            columns
                .rows
                .iter()
                .filter_map(|(t, v)| {
                    let k = ((t / tick).round() as usize).min(times.len() - 1);
                    ((times[k] - t).abs() < 1e-6).then(|| {
                        (v[a] - order[k])
                            .abs()
                            .max((v[b] - dbar[k]).abs())
                            .max((v[c] - dtar[k]).abs())
                    })
                })
                .fold(0.0, f64::max),
        ),
        _ => None,
    };
    let switches = find("pigeon_switches").and_then(|i| columns.rows.last().map(|(_, v)| v[i]));
    let monitor = sim.approach_monitor();
    let min_clearance = monitor.swarm_obstacle_minimum().map(|m| {
        (
            m.minimum.clearance_m,
            m.satellite,
            m.object,
            m.minimum.time_s,
        )
    });
    let n = sim.states_hill().len();
    let every_second =
        |v: &[f64]| -> Vec<f64> { v.iter().step_by(per_second as usize).copied().collect() };
    let state = sim.state();
    Ok(Run {
        job: job.clone(),
        tick_s: tick,
        mean_distance_m: every_second(&dbar),
        mean_target_distance_m: every_second(&dtar),
        order_parameter: every_second(&order),
        stabilisation_window_s,
        stabilisation_final_s,
        target_zone_s,
        target_distance_compare_m: at(w.compare_at_s).map(|k| dtar[k]),
        order_mean,
        p4_max_target_distance_m,
        p4_max_distance_change,
        max_radial_after_m: max_radial_after,
        min_separation_plane_m: min_plane.0,
        min_separation_pair: (min_plane.1, min_plane.2, min_plane.3),
        centroid_momentum_sign_changes: sign_changes,
        centroid_closest,
        min_separation_m: sim.totals().min_separation_m,
        min_clearance,
        last_near_obstacle_s: last_near,
        passed_obstacles_s: passed,
        delta_v_mps: (0..n).map(|i| state.ledger(i).1).collect(),
        switches,
        law_metric_mismatch,
        final_states: states(&sim),
    })
}

/// Runs every job through the bounded pool, [`WORKERS`] at a time, each on its own single-thread rayon
/// pool (results do not depend on the pool size); runs in job order.
pub fn run_jobs(jobs: &[Job]) -> Result<Vec<Run>, ValidateError> {
    satflock::campaign::pool::run_bounded(
        jobs.iter().collect(),
        WORKERS.min(rayon::current_num_threads()),
        run_job,
    )
    .map_err(failed)?
    .into_iter()
    .collect()
}

/// Nearest-rank quantile (`q` in [0, 1]) of values that may hold +∞ ("never").
pub fn quantile(values: &[f64], q: f64) -> f64 {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        return f64::NAN;
    }
    v[((q * (v.len() - 1) as f64).round() as usize).min(v.len() - 1)]
}

fn fmt_v(x: f64, digits: usize, unit: &str) -> String {
    if x.is_infinite() {
        "never".into()
    } else {
        format!("{x:.digits$}{unit}")
    }
}

/// "median [p5–p95]".
fn spread(values: &[f64], digits: usize, unit: &str) -> String {
    format!(
        "{} [{} – {}]",
        fmt_v(quantile(values, 0.5), digits, unit),
        fmt_v(quantile(values, 0.05), digits, ""),
        fmt_v(quantile(values, 0.95), digits, unit)
    )
}

fn verdict(ok: bool) -> Verdict {
    if ok {
        Verdict::Reproduced
    } else {
        Verdict::Differs
    }
}

/// The runs of the report, by configuration (each over [`SEEDS`], full length).
pub struct Groups {
    /// Q1 at the scenario's R_c^1 (130 m).
    pub q1: Vec<Run>,
    /// Q1 at the former default R_c^1 (P3's and P7's rows at 120 m).
    pub q1_former: Vec<Run>,
    /// The former default R_c^1 \[m\].
    pub former_range_m: f64,
    /// Q2.
    pub q2: Vec<Run>,
    /// Q1 with the extension.
    pub extension: Vec<Run>,
}

impl Groups {
    /// Runs the four configurations.
    pub fn run(data: &PaperData, damping_per_s: f64) -> Result<Self, ValidateError> {
        let former = data
            .outcome("P7 (R_c^1 = 120 m)")?
            .value("egalitarian_range_m")?;
        let configs = [
            (Q1, None, None),
            (Q1, None, Some(former)),
            (Q2, None, None),
            (Q1, Some(damping_per_s), None),
        ];
        let mut jobs = Vec::new();
        for (builtin, damping, range) in configs {
            jobs.extend(SEEDS.map(|seed| Job {
                builtin,
                seed,
                duration_s: None,
                damping_per_s: damping,
                egalitarian_range_m: range,
            }));
        }
        let mut runs = run_jobs(&jobs)?.into_iter();
        let seeds = SEEDS.count();
        let mut take = || runs.by_ref().take(seeds).collect::<Vec<_>>();
        Ok(Self {
            q1: take(),
            q1_former: take(),
            former_range_m: former,
            q2: take(),
            extension: take(),
        })
    }

    /// Every run of the paper's two configurations (Q1 at the default, Q2).
    fn paper_runs(&self) -> impl Iterator<Item = &Run> {
        self.q1.iter().chain(&self.q2)
    }
}

fn col(runs: &[Run], f: impl Fn(&Run) -> f64) -> Vec<f64> {
    runs.iter().map(f).collect()
}

/// The run with the smallest (or largest) value of `f`, and the value.
fn extreme<'a>(
    runs: impl Iterator<Item = &'a Run>,
    f: impl Fn(&Run) -> f64,
    largest: bool,
) -> (&'a Run, f64) {
    runs.map(|r| (r, f(r)))
        .reduce(|a, b| {
            let better = if largest { b.1 > a.1 } else { b.1 < a.1 };
            if better {
                b
            } else {
                a
            }
        })
        .expect("runs")
}

fn label(r: &Run) -> String {
    match r.job.egalitarian_range_m {
        Some(range) => format!("{} R_c^1 = {range} m seed {}", r.job.builtin, r.job.seed),
        None => format!("{} seed {}", r.job.builtin, r.job.seed),
    }
}

fn p1(o: &Outcome, g: &Groups) -> Result<Check, ValidateError> {
    let stab = |r: &Run| r.stabilisation_window_s.unwrap_or(f64::NAN);
    let (s1, s2) = (col(&g.q1, stab), col(&g.q2, stab));
    let (m1, m2) = (quantile(&s1, 0.5), quantile(&s2, 0.5));
    let target = o.value("paper_q1_s")?;
    Ok(o.check(
        format!(
            "Q1 {}, Q2 {} (median [5–95 %], {} seeds)",
            spread(&s1, 1, " s"),
            spread(&s2, 1, " s"),
            s1.len()
        ),
        verdict(m1 <= m2 && (m1 - target).abs() <= o.value("tolerance_rel")? * target),
    ))
}

fn p2(o: &Outcome, g: &Groups) -> Result<Check, ValidateError> {
    let zone = |r: &Run| r.target_zone_s.unwrap_or(f64::INFINITY);
    let (z1, z2) = (col(&g.q1, zone), col(&g.q2, zone));
    let (m1, m2) = (quantile(&z1, 0.5), quantile(&z2, 0.5));
    let at = o.value("compare_at_s")?;
    let zone_m = law_value(Q1, "target_zone_m")?;
    let above =
        g.q2.iter()
            .filter(|r| r.target_distance_compare_m.is_some_and(|d| d >= zone_m))
            .count();
    Ok(o.check(
        format!(
            "Q1 {}, Q2 {}; Q2 above {zone_m} m at {at} s in {above}/{} seeds",
            spread(&z1, 1, " s"),
            spread(&z2, 1, " s"),
            g.q2.len()
        ),
        verdict(m1.is_finite() && m1 < m2),
    ))
}

fn p3(o: &Outcome, q1: &[Run], q2: &[Run]) -> Result<Check, ValidateError> {
    let order = |r: &Run| r.order_mean.unwrap_or(f64::NAN);
    let (o1, o2) = (col(q1, order), col(q2, order));
    let wins = o1.iter().zip(&o2).filter(|(a, b)| a >= b).count();
    Ok(o.check(
        format!(
            "Q1 ≥ Q2 in {wins}/{} seeds; Q1 {}, Q2 {}",
            o1.len(),
            spread(&o1, 4, ""),
            spread(&o2, 4, "")
        ),
        verdict(wins as f64 >= o.value("share_min")? * o1.len() as f64),
    ))
}

fn p4(o: &Outcome, g: &Groups) -> Result<Check, ValidateError> {
    let (max_target_m, max_change) = (
        o.value("max_target_distance_m")?,
        o.value("max_distance_change_rel")?,
    );
    let t4 = col(&g.q1, |r| r.p4_max_target_distance_m.unwrap_or(f64::NAN));
    let c4 = col(&g.q1, |r| {
        100.0 * r.p4_max_distance_change.unwrap_or(f64::NAN)
    });
    let both =
        g.q1.iter()
            .filter(|r| {
                r.p4_max_target_distance_m.is_some_and(|d| d < max_target_m)
                    && r.p4_max_distance_change.is_some_and(|c| c <= max_change)
            })
            .count();
    Ok(o.check(
        format!(
            "max d̄_T {}; max d̄ change {}; both met in {both}/{} seeds",
            spread(&t4, 1, " m"),
            spread(&c4, 2, " %"),
            g.q1.len()
        ),
        verdict(quantile(&t4, 0.5) < max_target_m && quantile(&c4, 0.5) <= 100.0 * max_change),
    ))
}

fn p5(o: &Outcome, g: &Groups) -> Result<Check, ValidateError> {
    let (worst, x) = extreme(g.paper_runs(), |r| r.max_radial_after_m, true);
    Ok(o.check(
        format!("largest {x:.3e} m ({})", label(worst)),
        verdict(x < o.value("max_radial_m")?),
    ))
}

fn clearance(r: &Run) -> f64 {
    r.min_clearance.map_or(f64::INFINITY, |c| c.0)
}

fn p6(o: &Outcome, g: &Groups) -> Result<Check, ValidateError> {
    let (worst, c) = extreme(g.paper_runs(), clearance, false);
    let detail = worst
        .min_clearance
        .map(|c| format!(", satellite {} obstacle {} at {:.1} s", c.1, c.2, c.3))
        .unwrap_or_default();
    Ok(o.check(
        format!(
            "smallest {c:.2} m ({}{detail}); Q1 {}, Q2 {}",
            label(worst),
            spread(&col(&g.q1, clearance), 2, " m"),
            spread(&col(&g.q2, clearance), 2, " m")
        ),
        verdict(c >= o.value("min_clearance_m")?),
    ))
}

fn p7(o: &Outcome, q1: &[Run], q2: &[Run]) -> Result<Check, ValidateError> {
    let gate = o.value("min_separation_m")?;
    let design = o.value("design_separation_m")?;
    let runs = || q1.iter().chain(q2);
    let (worst, s) = extreme(runs(), |r| r.min_separation_plane_m, false);
    let (_, engine) = extreme(runs(), |r| r.min_separation_m, false);
    let (i, j, t) = worst.min_separation_pair;
    let below = |bound: f64| {
        q1.iter()
            .filter(|r| r.min_separation_plane_m < bound)
            .count()
    };
    Ok(o.check(
        format!(
            "smallest {s:.2} m ({}: satellites {i} and {j} at {t:.1} s; engine 3-D {engine:.2} m); \
             Q1 below {gate} m in {}/{} seeds, below {design} m in {}; Q1 {}, Q2 {}",
            label(worst),
            below(gate),
            q1.len(),
            below(design),
            spread(&col(q1, |r| r.min_separation_plane_m), 2, " m"),
            spread(&col(q2, |r| r.min_separation_plane_m), 2, " m")
        ),
        verdict(s >= gate),
    ))
}

/// The comparison table of the four configurations.
fn comparison(g: &Groups, damping: f64) -> Result<Table, ValidateError> {
    let ext_label = format!("Q1 + extension K^{{T,v}} = {damping:.3} 1/s (not in the paper)");
    let range = law_value(Q1, "egalitarian_range_m")?;
    let groups: [(String, &[Run]); 4] = [
        (format!("Q1 switching (R_c^1 = {range} m, default)"), &g.q1),
        (
            format!(
                "Q1 switching (R_c^1 = {} m, former default)",
                g.former_range_m
            ),
            &g.q1_former,
        ),
        ("Q2 non-switching (R_c^1 = 150 m)".into(), &g.q2),
        (ext_label, &g.extension),
    ];
    type Metric<'a> = (&'a str, usize, Box<dyn Fn(&Run) -> f64>);
    let metrics: Vec<Metric> = vec![
        (
            "d̄ stabilisation vs d̄(200 s) [s]",
            1,
            Box::new(|r: &Run| r.stabilisation_window_s.unwrap_or(f64::NAN)),
        ),
        (
            "d̄ stabilisation vs d̄(6000 s) [s]",
            1,
            Box::new(|r: &Run| r.stabilisation_final_s),
        ),
        (
            "d̄ at 200 s [m]",
            2,
            Box::new(|r: &Run| r.mean_distance_m.get(200).copied().unwrap_or(f64::NAN)),
        ),
        (
            "d̄ at 6000 s [m]",
            2,
            Box::new(|r: &Run| r.mean_distance_m.last().copied().unwrap_or(f64::NAN)),
        ),
        (
            "first d̄_T < 50 m [s]",
            1,
            Box::new(|r: &Run| r.target_zone_s.unwrap_or(f64::INFINITY)),
        ),
        (
            "max d̄_T over [500, 6000] s [m]",
            1,
            Box::new(|r: &Run| r.p4_max_target_distance_m.unwrap_or(f64::NAN)),
        ),
        (
            "d̄_T at 6000 s [m]",
            1,
            Box::new(|r: &Run| r.mean_target_distance_m.last().copied().unwrap_or(f64::NAN)),
        ),
        (
            "sign changes of the centroid's angular momentum about the target",
            0,
            Box::new(|r: &Run| r.centroid_momentum_sign_changes as f64),
        ),
        (
            "centroid's closest approach to the target [m]",
            2,
            Box::new(|r: &Run| r.centroid_closest.0),
        ),
        (
            "time-mean V_a, first 100 s",
            4,
            Box::new(|r: &Run| r.order_mean.unwrap_or(f64::NAN)),
        ),
        (
            "min separation, y–z plane [m]",
            2,
            Box::new(|r: &Run| r.min_separation_plane_m),
        ),
        ("min obstacle clearance [m]", 2, Box::new(clearance)),
        (
            "last time within detection range of an obstacle [s]",
            1,
            Box::new(|r: &Run| r.last_near_obstacle_s.unwrap_or(f64::NAN)),
        ),
        (
            "first time every satellite is past the obstacles (nearer the target than every detection sphere) [s]",
            1,
            Box::new(|r: &Run| r.passed_obstacles_s.unwrap_or(f64::INFINITY)),
        ),
        (
            "Δv per satellite, mean over satellites [m/s]",
            1,
            Box::new(|r: &Run| r.delta_v_mps.iter().sum::<f64>() / r.delta_v_mps.len() as f64),
        ),
        (
            "pattern switches (law counter, all satellites)",
            0,
            Box::new(|r: &Run| r.switches.unwrap_or(f64::NAN)),
        ),
    ];
    let rows = metrics
        .iter()
        .map(|(name, digits, f)| {
            let mut row = vec![(*name).to_string()];
            row.extend(
                groups
                    .iter()
                    .map(|(_, runs)| spread(&col(runs, f), *digits, "")),
            );
            row
        })
        .collect();
    let mut header = vec![format!(
        "metric (median [5–95 %] over seeds {}–{}, 6000 s)",
        SEEDS.start(),
        SEEDS.end()
    )];
    header.extend(groups.iter().map(|g| g.0.clone()));
    Ok(Table {
        title: "Q1 vs Q2 vs extension (truth states, pigeon plane, every 0.1 s tick)".into(),
        header,
        rows,
    })
}

/// The initial link graph of Table I at a link-forming radius: for every satellite its nearest
/// neighbour's distance in the pigeon plane; returns the satellites farther than `radius_m` from every
/// other, with that distance.
fn unlinked_at_start(radius_m: f64) -> Result<Vec<(usize, f64)>, ValidateError> {
    let text = scenario_text(&Job {
        builtin: Q1,
        seed: 1,
        duration_s: None,
        damping_per_s: None,
        egalitarian_range_m: None,
    })?;
    let scenario = Scenario::from_toml(&text, Q1, std::path::Path::new(".")).map_err(failed)?;
    let prepared = scenario.prepare().map_err(failed)?;
    let sim = Simulation::new(
        prepared.config,
        &prepared.satellites,
        prepared.law,
        prepared.events,
    )
    .map_err(failed)?;
    let p: Vec<[f64; 2]> = sim
        .states_hill()
        .iter()
        .map(|s| [s.position_m.z, s.position_m.y])
        .collect();
    Ok((0..p.len())
        .filter_map(|i| {
            let nearest = (0..p.len())
                .filter(|&j| j != i)
                .map(|j| (p[i][0] - p[j][0]).hypot(p[i][1] - p[j][1]))
                .fold(f64::INFINITY, f64::min);
            (nearest > radius_m).then_some((i, nearest))
        })
        .collect())
}

fn describe_unlinked(unlinked: &[(usize, f64)]) -> String {
    if unlinked.is_empty() {
        return "every satellite has a neighbour within it".into();
    }
    unlinked
        .iter()
        .map(|(i, d)| format!("satellite {i} has none (nearest {d:.1} m)"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The notes: every number in them measured from the runs or computed from the scenarios.
fn notes(g: &Groups, damping: f64, omega: f64, all: usize) -> Result<Vec<String>, ValidateError> {
    let delay = law_value(Q1, "link_delay_m")?;
    let range = law_value(Q1, "egalitarian_range_m")?;
    let window = Windows::from_data(&data()?)?.window_s;
    let ext_sep = quantile(&col(&g.extension, |r| r.min_separation_plane_m), 0.0);
    let ext_clear = quantile(&col(&g.extension, clearance), 0.0);
    let q2_identical = g.q2.windows(2).all(|w| {
        w[0].final_states
            .iter()
            .zip(&w[1].final_states)
            .all(|(a, b)| a.0 == b.0 && a.1 == b.1)
    });
    let changes = |runs: &[Run]| {
        spread(
            &col(runs, |r| r.centroid_momentum_sign_changes as f64),
            0,
            "",
        )
    };
    let closest = |runs: &[Run]| spread(&col(runs, |r| r.centroid_closest.0), 1, " m");
    let closest_t = |runs: &[Run]| spread(&col(runs, |r| r.centroid_closest.1), 0, " s");
    let former_worst = extreme(g.q1_former.iter(), |r| r.min_separation_plane_m, false).0;
    let involving_0: Vec<&Run> = g
        .q1_former
        .iter()
        .filter(|r| r.min_separation_pair.0 == 0 || r.min_separation_pair.1 == 0)
        .collect();
    let times: Vec<f64> = involving_0
        .iter()
        .map(|r| r.min_separation_pair.2)
        .collect();
    let t_range = if times.is_empty() {
        "–".to_string()
    } else {
        format!(
            "{:.0}–{:.0} s",
            quantile(&times, 0.0),
            quantile(&times, 1.0)
        )
    };
    let (i, j, t) = former_worst.min_separation_pair;
    let mismatch =
        g.q1.iter()
            .chain(&g.q1_former)
            .chain(&g.q2)
            .chain(&g.extension)
            .filter_map(|r| r.law_metric_mismatch)
            .fold(0.0, f64::max);
    Ok(vec![
        format!(
            "Runs: {all} (Q1 at R_c^1 = {range} m and at {former} m, Q2, extension × seeds {}–{}), 6000 s each, HCW truth, RK4 0.1 s, \
             law sampled every 0.1 s; {WORKERS} at a time through satflock::campaign::pool::run_bounded. Spreads are nearest-rank \
             5 % and 95 % quantiles; \"never\" = the event did not happen within the run.",
            SEEDS.start(),
            SEEDS.end(),
            former = g.former_range_m,
        ),
        format!(
            "Initial link graph (links form at R_c^1 − R_L^1, pigeon plane, Table I's positions): at R_c^1 = {former} m \
             ({:.0} m) {}; at R_c^1 = {range} m ({:.0} m) {}. An unlinked satellite feels only the target pull (if dominant) \
             and flies at the thrust cap: in the {former} m runs the closest pair involves satellite 0 in {}/{} seeds, \
             at {t_range}. The default was raised to {range} m for this reason after the {former} m results were seen \
             (rows P3 and P7 at {former} m).",
            g.former_range_m - delay,
            describe_unlinked(&unlinked_at_start(g.former_range_m - delay)?),
            range - delay,
            describe_unlinked(&unlinked_at_start(range - delay)?),
            involving_0.len(),
            g.q1_former.len(),
            former = g.former_range_m,
        ),
        format!(
            "Why P2 and P4 differ: the y–z law damps only the neighbours' relative velocities (alignment) and the target acts \
             only through its position potential on the dominant satellites, so the centroid feels a conservative pull with no \
             dashpot in the y–z plane: a weakly damped swing through the target region, not a circling. Over 6000 s the sign of \
             the centroid's angular momentum about the target changes {} times in Q1 and {} in Q2 (median [5–95 %]), and the \
             centroid passes within {} of the target (Q1, closest at {}; Q2 {}). d̄_T keeps swinging (max over [500, 6000] s \
             in the table), so the mean target distance does not stay under 50 m.",
            changes(&g.q1),
            changes(&g.q2),
            closest(&g.q1),
            closest_t(&g.q1),
            closest(&g.q2),
        ),
        format!(
            "P1's \"final\" value is d̄ at {window:.0} s (end of the comparison window, decided before running: the paper's Fig. 4 \
             shows about 100 s); the same quantity against d̄(6000 s) is in the comparison table."
        ),
        format!(
            "Extension (not in the paper, off by default): K^{{T,v}} = {damping:.3} 1/s on the dominant satellites, chosen as \
             critical damping of the group's centroid: internal forces cancel, so N a_c = |S_d| (−K^T (r − R_L^2)² − K^{{T,v}} v); \
             linearised at r − R_L^2 = {EXTENSION_SWING_M} m (middle of the earlier prototype's 150–600 m swing) ω² = (|S_d|/N) 2 K^T A, \
             ω = {omega:.4} rad/s, and critical damping needs (|S_d|/N) K^{{T,v}} = 2ω. Its centroid's angular momentum changes sign \
             {} times; worst runs: separation {ext_sep:.2} m, clearance {ext_clear:.2} m.",
            changes(&g.extension),
        ),
        format!(
            "Q2 draws no pattern (p_h = 0), so the seed changes nothing: its {} runs' final states are {}.",
            g.q2.len(),
            if q2_identical { "bitwise identical" } else { "NOT identical (unexpected)" }
        ),
        format!(
            "P7 at {former} m: the smallest separation is {:.2} m ({}: satellites {i} and {j} at {t:.1} s).",
            former_worst.min_separation_plane_m,
            label(former_worst),
            former = g.former_range_m,
        ),
        format!(
            "Cross-check: the law's own columns pigeon_order_parameter, pigeon_mean_distance_m, pigeon_mean_target_distance_m \
             differ from ours by at most {mismatch:.3e} at the 1 s recordings."
        ),
    ])
}

/// The full report.
pub fn report() -> Result<Report, ValidateError> {
    let data = data()?;
    let (damping, omega) = extension_damping_per_s()?;
    let g = Groups::run(&data, damping)?;
    let checks = vec![
        p1(data.outcome("P1")?, &g)?,
        p2(data.outcome("P2")?, &g)?,
        p3(data.outcome("P3")?, &g.q1, &g.q2)?,
        p3(data.outcome("P3 (R_c^1 = 120 m)")?, &g.q1_former, &g.q2)?,
        p4(data.outcome("P4")?, &g)?,
        p5(data.outcome("P5")?, &g)?,
        p6(data.outcome("P6")?, &g)?,
        p7(data.outcome("P7")?, &g.q1, &g.q2)?,
        p7(data.outcome("P7 (R_c^1 = 120 m)")?, &g.q1_former, &g.q2)?,
    ];
    let all = 4 * SEEDS.count();
    Ok(data.report(
        checks,
        vec![comparison(&g, damping)?],
        notes(&g, damping, omega, all)?,
    ))
}
