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
//! Criteria, fixed before any run (our reconstruction, `docs/methods/pigeon.md`):
//! * P1: median over seeds of the stabilisation time of the mean pair distance d̄ — the last time d̄
//!   leaves a ±2 % band around its "final" value. "Final" is d̄ at the end of the first
//!   [`WINDOW_S`] = 200 s (the comparison window: the paper's Fig. 4 plots about 100 s, so its "stable at
//!   58 s" is read against the end of a short window; our earlier prototype also reports within 200 s).
//!   The same quantity against d̄(6000 s) is reported beside it. Reproduced when Q1 ≤ Q2 (medians) and
//!   the Q1 median is within 58 s ± 30 %.
//! * P2: first time d̄_T < R_L^2 = 50 m (never = ∞); reproduced when the Q1 median is earlier than Q2's.
//! * P3: time mean of the global order parameter V_a over the first 100 s; reproduced when Q1 ≥ Q2 in
//!   ≥ 60 % of the seeds (paired by seed).
//! * P4 (Q1): d̄_T < 50 m over [500, 6000] s and d̄ within ±10 % of its 500 s value; per seed the maximum
//!   of d̄_T and of |d̄/d̄(500) − 1| over that interval; reproduced when both seed medians meet the bounds.
//! * P5: max_i |x_i| < 0.5 m after 60 s, every Q1 and Q2 run.
//! * P6: obstacle clearance ≥ R_L^4 = 10 m, every Q1 and Q2 run (the engine's continuous monitor).
//! * P7: pair separation in the pigeon plane ≥ 15 m at every tick, every Q1 and Q2 run (design intent
//!   20 m; we gate at 15 m because the barrier is soft under the 5 m/s² cap).

use nalgebra::Vector3;

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
/// End of the comparison window whose end value is P1's "final" value \[s\].
pub const WINDOW_S: f64 = 200.0;
/// Window of P3's time-mean order parameter \[s\].
pub const ORDER_WINDOW_S: f64 = 100.0;
/// Half-width of the stabilisation band (relative).
pub const BAND: f64 = 0.02;
/// P4's interval start \[s\].
pub const P4_FROM_S: f64 = 500.0;
/// P5: time after which the radial offset must be small \[s\].
pub const P5_AFTER_S: f64 = 60.0;
/// P5 bound on |x| \[m\].
pub const P5_MAX_X_M: f64 = 0.5;
/// P7 gate on the pair separation \[m\] (our criterion, see above).
pub const P7_MIN_SEPARATION_M: f64 = 15.0;
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
    /// d̄_T at 61 s \[m\] (the paper's comparison instant).
    pub target_distance_61_m: Option<f64>,
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
    if let Some(k) = job.damping_per_s {
        let law = doc
            .get_mut("law")
            .and_then(toml::Value::as_table_mut)
            .ok_or_else(|| failed("scenario without [law]"))?;
        law.insert(
            "target_velocity_damping_per_s".into(),
            toml::Value::Float(k),
        );
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

/// d̄, d̄_T and V_a in the pigeon plane (z, y) of the given Hill states.
pub fn plane_metrics(states: &[(Vector3<f64>, Vector3<f64>)]) -> (f64, f64, f64, f64) {
    let n = states.len();
    let p: Vec<[f64; 2]> = states.iter().map(|s| [s.0.z, s.0.y]).collect();
    let mut sum = 0.0;
    let mut min = f64::INFINITY;
    let mut pairs = 0usize;
    for i in 0..n {
        for j in i + 1..n {
            let d = (p[i][0] - p[j][0]).hypot(p[i][1] - p[j][1]);
            sum += d;
            min = min.min(d);
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
    let order = heading[0].hypot(heading[1]) / n as f64;
    (mean_distance, mean_target, order, min)
}

/// Last time a series leaves the band ±`BAND` around `reference` (the time it enters for good; 0 if
/// never outside).
fn stabilisation_s(times: &[f64], series: &[f64], reference: f64) -> f64 {
    let tol = BAND * reference.abs();
    match series.iter().rposition(|d| (d - reference).abs() > tol) {
        Some(k) if k + 1 < times.len() => times[k + 1],
        Some(k) => times[k],
        None => times.first().copied().unwrap_or(0.0),
    }
}

/// Runs one job on the current thread's rayon pool.
pub fn run_job(job: &Job) -> Result<Run, ValidateError> {
    let text = scenario_text(job)?;
    let scenario = Scenario::from_toml(
        &text,
        &format!("builtin:{}", job.builtin),
        std::path::Path::new("."),
    )
    .map_err(failed)?;
    let zone_m = law_value(job.builtin, "target_zone_m")?;
    let detection: Vec<(Vector3<f64>, f64)> = scenario
        .file
        .obstacles
        .iter()
        .map(|o| {
            (
                Vector3::from(o.center_hill_m),
                o.radius_m + o.detection_range_m.unwrap_or(scenario.file.sensing.range_m),
            )
        })
        .collect();
    let prepared = scenario.prepare().map_err(failed)?;
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
    let mut min_plane = f64::INFINITY;
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
        let (d, dt, va, min) = plane_metrics(&s);
        times.push(t);
        dbar.push(d);
        dtar.push(dt);
        order.push(va);
        min_plane = min_plane.min(min);
        if t > P5_AFTER_S {
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
        at(WINDOW_S).map(|k| stabilisation_s(&times[..=k], &dbar[..=k], dbar[k]));
    let stabilisation_final_s = stabilisation_s(&times, &dbar, *dbar.last().expect("tick 0"));
    let target_zone_s = dtar.iter().position(|d| *d < zone_m).map(|k| times[k]);
    let order_mean = at(ORDER_WINDOW_S).map(|k| order[..=k].iter().sum::<f64>() / (k + 1) as f64);
    let (p4_max_target_distance_m, p4_max_distance_change) = match at(P4_FROM_S) {
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
        target_distance_61_m: at(61.0).map(|k| dtar[k]),
        order_mean,
        p4_max_target_distance_m,
        p4_max_distance_change,
        max_radial_after_m: max_radial_after,
        min_separation_plane_m: min_plane,
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

/// The jobs of the report: Q1, Q2 and the extension over [`SEEDS`], full length, in that order.
pub fn jobs(damping_per_s: f64) -> Vec<Job> {
    let mut jobs = Vec::new();
    for (builtin, damping) in [(Q1, None), (Q2, None), (Q1, Some(damping_per_s))] {
        jobs.extend(SEEDS.map(|seed| Job {
            builtin,
            seed,
            duration_s: None,
            damping_per_s: damping,
        }));
    }
    jobs
}

/// The full report.
pub fn report() -> Result<Report, ValidateError> {
    let (damping, omega) = extension_damping_per_s()?;
    let all = run_jobs(&jobs(damping))?;
    let seeds = SEEDS.count();
    let (q1, rest) = all.split_at(seeds);
    let (q2, ext) = rest.split_at(seeds);
    let col = |runs: &[Run], f: &dyn Fn(&Run) -> f64| -> Vec<f64> { runs.iter().map(f).collect() };
    let stab = |r: &Run| r.stabilisation_window_s.unwrap_or(f64::NAN);
    let zone = |r: &Run| r.target_zone_s.unwrap_or(f64::INFINITY);
    let order = |r: &Run| r.order_mean.unwrap_or(f64::NAN);
    let mut checks = Vec::new();

    // P1
    let (s1, s2) = (col(q1, &stab), col(q2, &stab));
    let (m1, m2) = (quantile(&s1, 0.5), quantile(&s2, 0.5));
    checks.push(Check {
        id: "P1".into(),
        outcome: format!(
            "d̄ stabilisation time (last exit from ±2 % of d̄({WINDOW_S:.0} s)), seed median: Q1 ≤ Q2 and Q1 within 58 s ± 30 %"
        ),
        paper: "Q1 ≈ 58 s, Q2 ≈ 60 s".into(),
        ours: format!(
            "Q1 {}, Q2 {} (median [5–95 %], {seeds} seeds)",
            spread(&s1, 1, " s"),
            spread(&s2, 1, " s")
        ),
        verdict: verdict(m1 <= m2 && (m1 - 58.0).abs() <= 0.3 * 58.0),
    });
    // P2
    let (z1, z2) = (col(q1, &zone), col(q2, &zone));
    let (m1, m2) = (quantile(&z1, 0.5), quantile(&z2, 0.5));
    let above_61 = q2
        .iter()
        .filter(|r| r.target_distance_61_m.is_some_and(|d| d >= 50.0))
        .count();
    checks.push(Check {
        id: "P2".into(),
        outcome: "first time d̄_T < R_L^2 = 50 m, seed median: Q1 earlier than Q2".into(),
        paper: "Q1 ≈ 61 s; Q2 still above 50 m at 61 s".into(),
        ours: format!(
            "Q1 {}, Q2 {}; Q2 above 50 m at 61 s in {above_61}/{seeds} seeds",
            spread(&z1, 1, " s"),
            spread(&z2, 1, " s")
        ),
        verdict: verdict(m1.is_finite() && m1 < m2),
    });
    // P3
    let (o1, o2) = (col(q1, &order), col(q2, &order));
    let wins = o1.iter().zip(&o2).filter(|(a, b)| a >= b).count();
    checks.push(Check {
        id: "P3".into(),
        outcome: format!(
            "time mean of V_a over the first {ORDER_WINDOW_S:.0} s: Q1 ≥ Q2 in ≥ 60 % of seeds (paired)"
        ),
        paper: "switching reaches higher V_a sooner, higher mean".into(),
        ours: format!(
            "Q1 ≥ Q2 in {wins}/{seeds} seeds; Q1 {}, Q2 {}",
            spread(&o1, 4, ""),
            spread(&o2, 4, "")
        ),
        verdict: verdict(wins as f64 >= 0.6 * seeds as f64),
    });
    // P4
    let t4 = col(q1, &|r| r.p4_max_target_distance_m.unwrap_or(f64::NAN));
    let c4 = col(q1, &|r| {
        100.0 * r.p4_max_distance_change.unwrap_or(f64::NAN)
    });
    let pass4 = q1
        .iter()
        .filter(|r| {
            r.p4_max_target_distance_m.is_some_and(|d| d < 50.0)
                && r.p4_max_distance_change.is_some_and(|c| c <= 0.10)
        })
        .count();
    checks.push(Check {
        id: "P4".into(),
        outcome:
            "Q1 over [500, 6000] s: max d̄_T < 50 m and max |d̄/d̄(500 s) − 1| ≤ 10 % (seed medians)"
                .into(),
        paper: "tracks the target before 500 s, keeps formation to 6000 s (Fig. 2)".into(),
        ours: format!(
            "max d̄_T {}; max d̄ change {}; both met in {pass4}/{seeds} seeds",
            spread(&t4, 1, " m"),
            spread(&c4, 2, " %")
        ),
        verdict: verdict(quantile(&t4, 0.5) < 50.0 && quantile(&c4, 0.5) <= 10.0),
    });
    // P5–P7 over every Q1 and Q2 run.
    let paper_runs: Vec<&Run> = q1.iter().chain(q2).collect();
    let worst = |f: &dyn Fn(&Run) -> f64, max: bool| -> (f64, String) {
        let mut best: Option<&Run> = None;
        for r in &paper_runs {
            let better = match best {
                None => true,
                Some(b) => {
                    if max {
                        f(r) > f(b)
                    } else {
                        f(r) < f(b)
                    }
                }
            };
            if better {
                best = Some(r);
            }
        }
        let r = best.expect("runs");
        (f(r), format!("{} seed {}", r.job.builtin, r.job.seed))
    };
    let (x5, w5) = worst(&|r| r.max_radial_after_m, true);
    checks.push(Check {
        id: "P5".into(),
        outcome: format!(
            "max_i |x_i| after {P5_AFTER_S:.0} s < {P5_MAX_X_M} m, every Q1 and Q2 run (radial PD)"
        ),
        paper: "satellites converge to the y–z plane (Fig. 3a)".into(),
        ours: format!("largest {x5:.3e} m ({w5})"),
        verdict: verdict(x5 < P5_MAX_X_M),
    });
    let clearance = |r: &Run| r.min_clearance.map_or(f64::INFINITY, |c| c.0);
    let (c6, w6) = worst(&clearance, false);
    let detail6 = paper_runs
        .iter()
        .find(|r| clearance(r) == c6)
        .and_then(|r| r.min_clearance)
        .map(|c| format!(", satellite {} obstacle {} at {:.1} s", c.1, c.2, c.3))
        .unwrap_or_default();
    checks.push(Check {
        id: "P6".into(),
        outcome: "min obstacle clearance ≥ R_L^4 = 10 m, every Q1 and Q2 run (continuous monitor)"
            .into(),
        paper: "safe navigation among the obstacles (Fig. 3b)".into(),
        ours: format!(
            "smallest {c6:.2} m ({w6}{detail6}); Q1 {}, Q2 {}",
            spread(&col(q1, &clearance), 2, " m"),
            spread(&col(q2, &clearance), 2, " m")
        ),
        verdict: verdict(c6 >= 10.0),
    });
    let sep = |r: &Run| r.min_separation_plane_m;
    let (s7, w7) = worst(&sep, false);
    let (e7, _) = worst(&|r| r.min_separation_m, false);
    checks.push(Check {
        id: "P7".into(),
        outcome: format!(
            "min pair separation (y–z plane, every tick) ≥ {P7_MIN_SEPARATION_M} m, every Q1 and Q2 run (design intent R_L^3 = 20 m)"
        ),
        paper: "no collisions".into(),
        ours: format!(
            "smallest {s7:.2} m ({w7}; engine 3-D {e7:.2} m); Q1 {}, Q2 {}",
            spread(&col(q1, &sep), 2, " m"),
            spread(&col(q2, &sep), 2, " m")
        ),
        verdict: verdict(s7 >= P7_MIN_SEPARATION_M),
    });

    // Comparison table.
    let ext_label = format!("Q1 + extension K^{{T,v}} = {damping:.3} 1/s (not in the paper)");
    let groups: [(&str, &[Run]); 3] = [
        ("Q1 switching (R_c^1 = 120 m)", q1),
        ("Q2 non-switching (R_c^1 = 150 m)", q2),
        (ext_label.as_str(), ext),
    ];
    type Metric<'a> = (&'a str, usize, &'a str, Box<dyn Fn(&Run) -> f64>);
    let metrics: Vec<Metric> = vec![
        (
            "d̄ stabilisation vs d̄(200 s) [s]",
            1,
            "",
            Box::new(|r: &Run| r.stabilisation_window_s.unwrap_or(f64::NAN)),
        ),
        (
            "d̄ stabilisation vs d̄(6000 s) [s]",
            1,
            "",
            Box::new(|r: &Run| r.stabilisation_final_s),
        ),
        (
            "d̄ at 200 s [m]",
            2,
            "",
            Box::new(|r: &Run| r.mean_distance_m.get(200).copied().unwrap_or(f64::NAN)),
        ),
        (
            "d̄ at 6000 s [m]",
            2,
            "",
            Box::new(|r: &Run| r.mean_distance_m.last().copied().unwrap_or(f64::NAN)),
        ),
        (
            "first d̄_T < 50 m [s]",
            1,
            "",
            Box::new(|r: &Run| r.target_zone_s.unwrap_or(f64::INFINITY)),
        ),
        (
            "max d̄_T over [500, 6000] s [m]",
            1,
            "",
            Box::new(|r: &Run| r.p4_max_target_distance_m.unwrap_or(f64::NAN)),
        ),
        (
            "d̄_T at 6000 s [m]",
            1,
            "",
            Box::new(|r: &Run| r.mean_target_distance_m.last().copied().unwrap_or(f64::NAN)),
        ),
        (
            "time-mean V_a, first 100 s",
            4,
            "",
            Box::new(|r: &Run| r.order_mean.unwrap_or(f64::NAN)),
        ),
        (
            "min separation, y–z plane [m]",
            2,
            "",
            Box::new(|r: &Run| r.min_separation_plane_m),
        ),
        (
            "min obstacle clearance [m]",
            2,
            "",
            Box::new(|r: &Run| r.min_clearance.map_or(f64::INFINITY, |c| c.0)),
        ),
        (
            "last time within detection range of an obstacle [s]",
            1,
            "",
            Box::new(|r: &Run| r.last_near_obstacle_s.unwrap_or(f64::NAN)),
        ),
        (
            "first time every satellite is past the obstacles (nearer the target than every detection sphere) [s]",
            1,
            "",
            Box::new(|r: &Run| r.passed_obstacles_s.unwrap_or(f64::INFINITY)),
        ),
        (
            "Δv per satellite, mean over satellites [m/s]",
            1,
            "",
            Box::new(|r: &Run| r.delta_v_mps.iter().sum::<f64>() / r.delta_v_mps.len() as f64),
        ),
        (
            "pattern switches (law counter, all satellites)",
            0,
            "",
            Box::new(|r: &Run| r.switches.unwrap_or(f64::NAN)),
        ),
    ];
    let mut rows = Vec::new();
    for (name, digits, unit, f) in &metrics {
        let mut row = vec![(*name).to_string()];
        for (_, runs) in &groups {
            row.push(spread(&col(runs, &|r| f(r)), *digits, unit));
        }
        rows.push(row);
    }
    let mut header = vec!["metric (median [5–95 %] over seeds 1–20, 6000 s)".to_string()];
    header.extend(groups.iter().map(|g| g.0.to_string()));
    let tables = vec![Table {
        title: "Q1 vs Q2 vs extension (truth states, pigeon plane, every 0.1 s tick)".into(),
        header,
        rows,
    }];

    let mismatch = all
        .iter()
        .filter_map(|r| r.law_metric_mismatch)
        .fold(0.0, f64::max);
    let ext_sep = quantile(&col(ext, &sep), 0.0);
    let ext_clear = quantile(&col(ext, &clearance), 0.0);
    let notes = vec![
        format!(
            "Runs: {} (Q1, Q2, extension × seeds 1–20), 6000 s each, HCW truth, RK4 0.1 s, law sampled every 0.1 s; \
             {WORKERS} at a time through satflock::campaign::pool::run_bounded. Spreads are nearest-rank 5 % and 95 % quantiles; \
             \"never\" = the event did not happen within the run.",
            all.len()
        ),
        format!(
            "P1's \"final\" value is d̄ at {WINDOW_S:.0} s (end of the comparison window, decided before running: the paper's Fig. 4 \
             shows about 100 s, so its \"stable at 58 s\" is judged against a short window); the same quantity against d̄(6000 s) \
             is in the comparison table."
        ),
        format!(
            "Extension (not in the paper, off by default): K^{{T,v}} = {damping:.3} 1/s on the dominant satellites, chosen as \
             critical damping of the group's centroid: internal forces cancel, so N a_c = |S_d| (−K^T (r − R_L^2)² − K^{{T,v}} v); \
             linearised at r − R_L^2 = {EXTENSION_SWING_M} m (middle of the earlier prototype's 150–600 m swing) ω² = (|S_d|/N) 2 K^T A, \
             ω = {omega:.4} rad/s, and critical damping needs (|S_d|/N) K^{{T,v}} = 2ω. Its worst runs: separation {ext_sep:.2} m, \
             clearance {ext_clear:.2} m."
        ),
        "Q2 has no spread: with p_h = 0 no pattern is drawn, so the seed changes nothing (20 identical runs).".to_string(),
        "Why P2/P4 differ: the y–z law has no absolute damping. The target pull acts only on the dominant satellites and is \
         central about x_T; the formation and alignment terms are internal and cancel in the sum. So, while unsaturated, the \
         group's centroid keeps its angular momentum about the target (Table I's velocities give it some) and circles it at \
         a few hundred metres instead of settling: d̄_T keeps swinging (table rows) and the group crosses obstacle 1's \
         detection zone until late in the run. The extension's absolute damping removes exactly this and the swing decays \
         (max d̄_T over [500, 6000] s ≈ 150 m), but with the target zone R_L^2 = 50 m the pull vanishes inside 50 m for the \
         3 dominant satellites only, and the 10-satellite formation at R_d = 40 m cannot have its mean target distance \
         under 50 m (d̄_T settles ≈ 80 m), so P2 stays unmet there too.".to_string(),
        "Why P7 differs: in the switching runs some pairs meet at closing speeds of ≈ 20 m/s (the group swings at up to \
         ≈ 25 m/s), and the collision barrier acts only inside R_d = 40 m; stopping 20 m/s within R_d − R_L^3 = 20 m needs \
         10 m/s² of relative deceleration, the per-axis cap gives each satellite at most 5√2 m/s² and the barrier shares it \
         with the other terms, so the barrier is crossed (seed 17: satellites 0 and 4 at 1.61 m, 96.0 s).".to_string(),
        format!(
            "Cross-check: the law's own columns pigeon_order_parameter, pigeon_mean_distance_m, pigeon_mean_target_distance_m \
             differ from ours by at most {mismatch:.3e} at the 1 s recordings."
        ),
    ];
    Ok(Report {
        title: "Qiu et al., pigeon-flock switching formation (Q1 switching vs Q2 non-switching, 20 seeds, 6000 s)".into(),
        reference_header: "paper".into(),
        checks,
        tables,
        notes,
    })
}
