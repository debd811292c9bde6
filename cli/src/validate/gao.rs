//! `satflock validate gao`: the outcomes O1–O14 of `docs/methods/bifurcating.md` §6
//! (Gao, Li & Wei 2022), reproduced at full length from the built-in `gao-*` scenarios, several seeds
//! where the outcome depends on the random initial state (the median is reported).
//!
//! The run helpers ([`run_builtin`], [`Trace`]) are public so that the release-mode tests
//! (`tests/regress_gao.rs`) exercise the same code on fewer seeds.

use nalgebra::Vector3;

use crate::validate::{Check, Report, ValidateError, Verdict};
use satflock::dynamics::{ForceSet, PhysicalProperties};
use satflock::guidance::bifurcating::{BifurcatingParameters, ShapeError};
use satflock::guidance::LawConfig;
use satflock::integrate::{IntegratorMethod, Tolerances};
use satflock::metrics::{five_elements, FiveElements, FiveElementsWorkspace};
use satflock::orbit::{hill_to_gao, CartesianState, EarthModel, GravityModel};
use satflock::propagate::{propagate, PropagationSettings};
use satflock::scenario::schema::ActionSection;
use satflock::scenario::{merge_law_parameters, Scenario};
use satflock::swarm::{Recorder, Simulation, Snapshot};

/// Seeds of the seed-dependent reproductions (method page §6: at least 5, median reported).
pub const SEEDS: [u64; 5] = [1, 2, 3, 4, 5];

/// Offset between the `gao-reconfiguration` clock and Table 5's clock \[s\]: the disk forms for 2000 s
/// before Table 5's t = 0 (method page §4.2).
pub const TABLE5_OFFSET_S: f64 = 2000.0;

fn failed(e: impl std::fmt::Display) -> ValidateError {
    ValidateError::Failed {
        target: "gao".into(),
        message: e.to_string(),
    }
}

/// A recorded run of a `bifurcating` scenario.
#[derive(Clone, Debug)]
pub struct Trace {
    /// Recording times \[s\].
    pub times_s: Vec<f64>,
    /// Positions relative to the formation centre, Gao `o-xyz` \[m\], per recording time and satellite.
    pub positions_gao_m: Vec<Vec<Vector3<f64>>>,
    /// Five elements (ECI) per recording time.
    pub five: Vec<FiveElements>,
    /// Law parameters in force at each recording time (events applied).
    pub parameters: Vec<BifurcatingParameters>,
    /// Final delta-v per satellite, ∫‖u‖dt \[m/s\].
    pub delta_v_mps: Vec<f64>,
}

impl Trace {
    /// Shape error at recording `k` against the parameters then in force.
    pub fn shape_error(&self, k: usize) -> ShapeError {
        self.parameters[k].shape_error(&self.positions_gao_m[k])
    }

    /// Index of the recording at time `t_s` (the nearest one).
    pub fn index_at(&self, t_s: f64) -> usize {
        let mut best = 0;
        for (k, t) in self.times_s.iter().enumerate() {
            if (t - t_s).abs() < (self.times_s[best] - t_s).abs() {
                best = k;
            }
        }
        best
    }

    /// Time from `from_s` to the first recording in [`from_s`, `until_s`] where the shape is reached
    /// (5 % criterion of [`ShapeError::reached`]) \[s\]; `None` if never.
    pub fn time_to_shape_s(&self, from_s: f64, until_s: f64) -> Option<f64> {
        (0..self.times_s.len())
            .filter(|&k| self.times_s[k] >= from_s && self.times_s[k] <= until_s)
            .find(|&k| self.shape_error(k).reached() == Some(true))
            .map(|k| self.times_s[k] - from_s)
    }

    /// Uniformity L at recording `k`.
    pub fn l(&self, k: usize) -> f64 {
        self.five[k].uniformity_l
    }
}

struct Collect {
    trace: Trace,
    schedule: Vec<(f64, BifurcatingParameters)>,
    workspace: FiveElementsWorkspace,
}

impl Recorder for Collect {
    fn record(&mut self, s: &Snapshot<'_>) -> std::io::Result<()> {
        let t = s.time_s;
        self.trace.times_s.push(t);
        self.trace.positions_gao_m.push(
            s.relative_states
                .iter()
                .map(|r| hill_to_gao(&r.position_m))
                .collect(),
        );
        let p: Vec<[f64; 3]> = s
            .inertial_states
            .iter()
            .map(|c| c.position_m.into())
            .collect();
        let v: Vec<[f64; 3]> = s
            .inertial_states
            .iter()
            .map(|c| c.velocity_mps.into())
            .collect();
        let five = five_elements(&p, &v, None, &mut self.workspace)
            .map_err(|e| std::io::Error::other(e.to_string()))?;
        self.trace.five.push(five);
        let current = self
            .schedule
            .iter()
            .rev()
            .find(|(ts, _)| *ts <= t + 1e-9)
            .map(|(_, p)| p.clone())
            .unwrap_or_else(|| self.schedule[0].1.clone());
        self.trace.parameters.push(current);
        self.trace.delta_v_mps = s.delta_v_mps.to_vec();
        Ok(())
    }
}

/// Runs the built-in scenario `name` with `seed`, optionally cut to `duration_s` (later events dropped),
/// recording every `record_interval_s` of the scenario.
pub fn run_builtin(name: &str, seed: u64, duration_s: Option<f64>) -> Result<Trace, ValidateError> {
    let mut scenario = Scenario::load(name).map_err(failed)?;
    scenario.file.seed = seed;
    if let Some(d) = duration_s {
        scenario.file.duration_s = d;
        scenario.file.events.retain(|e| e.time_s <= d);
    }
    let LawConfig::Bifurcating(initial) = &scenario.file.law else {
        return Err(failed(format!("{name} does not run the bifurcating law")));
    };
    let mut schedule = vec![(0.0, initial.clone())];
    let mut events: Vec<_> = scenario.file.events.iter().collect();
    events.sort_by(|a, b| a.time_s.total_cmp(&b.time_s));
    for e in events {
        if let ActionSection::SetLawParameters { parameters } = &e.action {
            let last = schedule
                .last()
                .map(|s| s.1.clone())
                .unwrap_or(initial.clone());
            let merged =
                merge_law_parameters(&LawConfig::Bifurcating(last), parameters).map_err(failed)?;
            let LawConfig::Bifurcating(merged) = merged else {
                unreachable!("set-law-parameters keeps the law");
            };
            schedule.push((e.time_s, merged));
        }
    }
    let prepared = scenario.prepare().map_err(failed)?;
    let mut sim = Simulation::new(
        prepared.config,
        &prepared.satellites,
        prepared.law,
        prepared.events,
    )
    .map_err(failed)?;
    let mut collect = Collect {
        trace: Trace {
            times_s: Vec::new(),
            positions_gao_m: Vec::new(),
            five: Vec::new(),
            parameters: Vec::new(),
            delta_v_mps: Vec::new(),
        },
        schedule,
        workspace: FiveElementsWorkspace::new(),
    };
    sim.run(&mut collect, &mut |_| {}).map_err(failed)?;
    Ok(collect.trace)
}

/// Shape error of `trace` at the stage ending at `end_s` (the recording at that time, against the
/// parameters in force just before it): residual and |y| relative to the shape's size, or in metres for
/// the line family (no size, or a size that is the line offset).
pub fn stage_end_error(trace: &Trace, end_s: f64) -> f64 {
    let k = trace.index_at(end_s);
    let before = trace.index_at(end_s - 1e-3).min(k.saturating_sub(1));
    let p = &trace.parameters[before];
    let e = p.shape_error(&trace.positions_gao_m[k]);
    let err = e
        .max_residual_m
        .unwrap_or(f64::INFINITY)
        .max(e.max_out_of_plane_m);
    match e.size_m {
        Some(size) if p.b != 0.0 => err / size,
        _ => err,
    }
}

/// Median of a non-empty list (mean of the two middle values for even lengths).
pub fn median(values: &[f64]) -> f64 {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Table 5 cluster-centre states (ECI, km and km/s as printed) at 0, 1000, 1500 and 2000 s.
pub const TABLE5_CENTRE: [(f64, [f64; 6]); 4] = [
    (
        0.0,
        [
            -443.54295,
            899.34186,
            -6898.0861,
            7.4271828,
            1.3587345,
            -0.29933858,
        ],
    ),
    (
        1000.0,
        [
            5850.6303,
            1530.4312,
            -3471.9062,
            3.9039044,
            -0.22348015,
            6.4713810,
        ],
    ),
    (
        1500.0,
        [
            6869.2879,
            1204.6086,
            106.34651,
            0.069789521,
            -1.0478601,
            7.4884619,
        ],
    ),
    (
        2000.0,
        [
            5917.3955, 533.21440, 3654.0846, -3.7823796, -1.5714632, 6.3527428,
        ],
    ),
];

/// O3: propagates Table 5's t = 0 centre with `gravity` (the paper's constants: μ = 398600.4418 km³/s²,
/// R = 6378.137 km, J2 = 1.08263e-3) and returns, at 1000/1500/2000 s, the position and velocity
/// differences from Table 5 \[m, m/s\].
pub fn table5_centre_errors(gravity: GravityModel) -> Result<Vec<(f64, f64, f64)>, ValidateError> {
    let earth = EarthModel {
        mu_m3_s2: 398_600.441_8e9,
        equatorial_radius_m: 6_378_137.0,
        j2: 1.082_63e-3,
    };
    let s0 = TABLE5_CENTRE[0].1;
    let initial = CartesianState::new(
        Vector3::new(s0[0], s0[1], s0[2]) * 1e3,
        Vector3::new(s0[3], s0[4], s0[5]) * 1e3,
    );
    let settings = PropagationSettings {
        earth,
        forces: std::sync::Arc::new(ForceSet::gravity(gravity, earth)),
        properties: PhysicalProperties::point_mass(1.0),
        integrator: IntegratorMethod::Rk78,
        step_s: 60.0,
        tolerances: Tolerances {
            relative: 1e-12,
            absolute: 1e-6,
        },
        duration_s: 2000.0,
        output_step_s: 500.0,
    };
    let mut out = Vec::new();
    propagate(&[initial], &settings, |t, states| {
        if let Some((_, e)) = TABLE5_CENTRE[1..]
            .iter()
            .find(|(tt, _)| (tt - t).abs() < 1e-6)
        {
            let dr = states[0].position_m - Vector3::new(e[0], e[1], e[2]) * 1e3;
            let dv = states[0].velocity_mps - Vector3::new(e[3], e[4], e[5]) * 1e3;
            out.push((t, dr.norm(), dv.norm()));
        }
    })
    .map_err(failed)?;
    Ok(out)
}

/// Fraction of satellites whose final in-plane radius is within `tolerance` (relative) of one of
/// `radii_m`, and the fraction that ended on the ring nearer to its radius at `from_k` (`boundary_m`:
/// below → inner ring). Radii are ρ = √(x² + z²) (Gao, a = b = 1).
pub fn ring_assignment(
    trace: &Trace,
    from_k: usize,
    to_k: usize,
    radii_m: [f64; 2],
    boundary_m: f64,
    tolerance: f64,
) -> (f64, f64) {
    let rho = |q: &Vector3<f64>| (q.x * q.x + q.z * q.z).sqrt();
    let n = trace.positions_gao_m[to_k].len() as f64;
    let mut on_ring = 0.0;
    let mut nearest = 0.0;
    for (q0, q1) in trace.positions_gao_m[from_k]
        .iter()
        .zip(&trace.positions_gao_m[to_k])
    {
        let r1 = rho(q1);
        if radii_m.iter().any(|r| (r1 - r).abs() <= tolerance * r) {
            on_ring += 1.0;
        }
        let inner_start = rho(q0) < boundary_m;
        let inner_end = (r1 - radii_m[0]).abs() < (r1 - radii_m[1]).abs();
        if inner_start == inner_end {
            nearest += 1.0;
        }
    }
    (on_ring / n, nearest / n)
}

/// How well a filled shape (disk, ellipse disk, ball, solid ellipsoid) is formed at recording `k`.
///
/// The paper gives no size for its filled shapes (the repulsion sets it), so "all satellites inside the
/// level set" is judged by the level set ρ ≤ ρ_max that encloses them all: it must have the commanded
/// shape, be filled rather than a shell, and (2-D) lie in the orbital plane.
#[derive(Clone, Copy, Debug)]
pub struct FilledShape {
    /// Median over satellites of ρ/ρ_max (uniform disk 0.71, uniform ball 0.79, any ring or shell 1.0);
    /// reported only: this law piles satellites at the boundary (our 1+8+16+25 disk lattice
    /// already gives 0.83), so it does not separate filled from hollow.
    pub median_ratio: f64,
    /// Widest empty annulus (shell in 3-D) of the shape coordinate, largest gap between consecutive
    /// sorted values of ρ/ρ_max counting from the centre (0): a single ring or shell has ≈ 1, two rings
    /// at ρ_max/3 and ρ_max 0.67, our 1+8+16+25 disk lattice (method page §5) 1/3.
    pub largest_radial_gap: f64,
    /// Aspect error: the RMS extents along the shape's axes, divided by the commanded semi-axis ratios
    /// (a : b in 2-D, a : b : c in 3-D), max/min − 1 (0 for a level set of the commanded shape).
    pub aspect_error: f64,
    /// Largest |y| over the smallest semi-axis of the enclosing level set (2-D; 0 in 3-D).
    pub out_of_plane: f64,
}

impl FilledShape {
    /// Filled (no empty annulus wider than 0.4 ρ_max: a lattice of rings as sparse as our
    /// reference disk passes, one or two rings do not), commanded aspect within 10 % (finite-N sampling
    /// of 50 points), in-plane within 3 % (as the surfaces).
    pub fn formed(&self) -> bool {
        self.largest_radial_gap <= 0.4 && self.aspect_error <= 0.10 && self.out_of_plane <= 0.03
    }
}

/// [`FilledShape`] of recording `k` of `trace`, against the parameters then in force.
pub fn filled_shape(trace: &Trace, k: usize) -> FilledShape {
    let p = &trace.parameters[k];
    let mut probe = p.clone();
    probe.radius_m = 0.0;
    let q = &trace.positions_gao_m[k];
    let coordinates: Vec<f64> = q
        .iter()
        .map(|q| {
            probe
                .shape_error(std::slice::from_ref(q))
                .max_shape_coordinate_m
        })
        .collect();
    let max = coordinates.iter().copied().fold(0.0, f64::max);
    let planar = p.dimension == satflock::guidance::bifurcating::Dimension::Planar;
    // Semi-axes of a level set of ρ are ∝ (a, b) along (x, z) in 2-D and (a, b, c) along (x, y, z) in
    // 3-D (method page §3.4 table), so RMS extent / factor is the same on every axis for a filled level set.
    let rms = |f: fn(&Vector3<f64>) -> f64| {
        (q.iter().map(|v| f(v).powi(2)).sum::<f64>() / q.len() as f64).sqrt()
    };
    let mut scaled = vec![rms(|v| v.x) / p.a];
    if planar {
        scaled.push(rms(|v| v.z) / p.b);
    } else {
        scaled.push(rms(|v| v.y) / p.b);
        scaled.push(rms(|v| v.z) / p.c);
    }
    let hi = scaled.iter().copied().fold(0.0, f64::max);
    let lo = scaled.iter().copied().fold(f64::INFINITY, f64::min);
    let out_of_plane = if planar {
        let smallest_semi_axis = max / p.a.max(p.b);
        q.iter().map(|v| v.y.abs()).fold(0.0, f64::max) / smallest_semi_axis
    } else {
        0.0
    };
    let mut sorted: Vec<f64> = coordinates.iter().map(|c| c / max).collect();
    sorted.sort_by(f64::total_cmp);
    let largest_radial_gap = sorted
        .iter()
        .scan(0.0, |prev, &c| {
            let gap = c - *prev;
            *prev = c;
            Some(gap)
        })
        .fold(0.0, f64::max);
    FilledShape {
        median_ratio: median(&coordinates) / max,
        largest_radial_gap,
        aspect_error: hi / lo - 1.0,
        out_of_plane,
    }
}

/// Largest distance of a satellite from the target line(s) of a line-family shape (b = 0), |z| for the
/// single line or ||z| − μ/a| for the double line, and |y|, at recording `k` \[m\].
pub fn line_distance_m(trace: &Trace, k: usize) -> f64 {
    let e = trace.shape_error(k);
    e.max_residual_m
        .unwrap_or(f64::INFINITY)
        .max(e.max_out_of_plane_m)
}

/// Linear stability of a straight line of satellites (method page §3.2 repulsion, line potential b = 0,
/// μ < 0): the alternating "zigzag" mode z_j = ±ε at along-track spacing δ feels the outward stiffness
/// 2 Σ_{odd j, both sides, jδ < s} k_c (s/(jδ) − 1) against the line's restoring stiffness k_f a²|μ|
/// (φ''(0) = |μ|). Returns the smallest spacing at which the straight line is stable \[m\].
pub fn zigzag_critical_spacing_m(k_c: f64, s_m: f64, restoring_n_per_m: f64) -> f64 {
    let outward = |delta: f64| {
        let mut sum = 0.0;
        let mut j = 1.0;
        while j * delta < s_m {
            sum += 4.0 * k_c * (s_m / (j * delta) - 1.0);
            j += 2.0;
        }
        sum
    };
    // The outward stiffness decreases with δ: bisect on [s/1e4, s].
    let (mut lo, mut hi) = (s_m * 1e-4, s_m);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if outward(mid) > restoring_n_per_m {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Mean along-track (Gao x) gap between consecutive satellites of the middle 40 % of a line at
/// recording `k` \[m\] (the most compressed part of a line spreading under repulsion alone).
pub fn central_line_spacing_m(trace: &Trace, k: usize) -> f64 {
    let mut x: Vec<f64> = trace.positions_gao_m[k].iter().map(|q| q.x).collect();
    x.sort_by(f64::total_cmp);
    let n = x.len();
    let (i0, i1) = (n * 3 / 10, n * 7 / 10);
    (x[i1] - x[i0]) / (i1 - i0) as f64
}

fn check(id: &str, outcome: &str, paper: String, ours: String, ok: bool) -> Check {
    Check {
        criterion: None,
        id: id.into(),
        outcome: outcome.into(),
        paper,
        ours,
        verdict: if ok {
            Verdict::Reproduced
        } else {
            Verdict::Differs
        },
    }
}

/// Runs every `(built-in name, seed, duration)` job through [`satflock::campaign::pool::run_bounded`] with as
/// many workers as the current rayon pool has threads (`--threads`, default all cores), each worker
/// running whole runs one after another on its own single-thread rayon pool: 50 satellites are too few for the engine's per-step parallelism to
/// pay (a G3 run takes 3.0 s of CPU on one thread and more wall time on two), so runs, not steps, are
/// spread over the cores. (A rayon `par_iter` over the runs would not bound the concurrency: a worker
/// waiting in another pool's `install` steals and starts further runs.) Results do not depend on the
/// thread count (the engine is bitwise deterministic). Traces come back in job order.
pub fn run_all(jobs: &[(&str, u64, Option<f64>)]) -> Result<Vec<Trace>, ValidateError> {
    satflock::campaign::pool::run_bounded(
        jobs.to_vec(),
        rayon::current_num_threads(),
        |(name, seed, duration_s)| run_builtin(name, seed, duration_s),
    )
    .map_err(failed)?
    .into_iter()
    .collect()
}

/// [`run_all`] of one scenario over `seeds`.
pub fn run_seeds(
    name: &str,
    seeds: &[u64],
    duration_s: Option<f64>,
) -> Result<Vec<Trace>, ValidateError> {
    let jobs: Vec<_> = seeds.iter().map(|&s| (name, s, duration_s)).collect();
    run_all(&jobs)
}

/// G6 (concentric double circle) is run this long besides the paper's 2000 s (same run, evaluated at
/// both times): the ring stiffness k_f·μ = 1.5 N/m gives a time constant k_v/(k_f μ) ≈ 1330 s, and
/// satellites starting near the ridge ρ = 1 km leave it at the same rate \[s\].
pub const G6_LONG_S: f64 = 8000.0;

/// G1 (single line) is run this long besides the paper's 2000 s, to follow the zigzag relaxing \[s\].
pub const G1_LONG_S: f64 = 10000.0;

/// The full report.
pub fn report() -> Result<Report, ValidateError> {
    let mut checks = Vec::new();
    let mut notes = Vec::new();

    // Every simulated run of the report, once, in one parallel batch (no run is repeated).
    let scenarios: [(&str, Option<f64>); 14] = [
        ("gao-circle", None),
        ("gao-circle-steep", None),
        ("gao-line", Some(G1_LONG_S)),
        ("gao-double-line", None),
        ("gao-circle-large", None),
        ("gao-double-circle", Some(G6_LONG_S)),
        ("gao-ellipse", None),
        ("gao-double-ellipse", None),
        ("gao-ellipsoid-surface", None),
        ("gao-sphere-surface", None),
        ("gao-disk", None),
        ("gao-ellipse-disk", None),
        ("gao-spherical-space", None),
        ("gao-reconfiguration", None),
    ];
    // Longest runs first, for load balance.
    let mut jobs: Vec<(&str, u64, Option<f64>)> = Vec::new();
    for &(name, d) in scenarios
        .iter()
        .filter(|x| x.1.is_some() || x.0 == "gao-reconfiguration")
    {
        jobs.extend(SEEDS.iter().map(|&s| (name, s, d)));
    }
    for &(name, d) in scenarios
        .iter()
        .filter(|x| x.1.is_none() && x.0 != "gao-reconfiguration")
    {
        jobs.extend(SEEDS.iter().map(|&s| (name, s, d)));
    }
    let all = run_all(&jobs)?;
    let runs = |name: &str, _duration: Option<f64>| -> Result<Vec<Trace>, ValidateError> {
        Ok(jobs
            .iter()
            .zip(&all)
            .filter(|(j, _)| j.0 == name)
            .map(|(_, t)| t.clone())
            .collect())
    };

    // O1: closed form of L for 50 evenly spaced points on a circle (method page §2).
    let n = 50usize;
    let ring: Vec<[f64; 3]> = (0..n)
        .map(|k| {
            let t = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
            [t.cos(), 0.0, t.sin()]
        })
        .collect();
    let mut ws = FiveElementsWorkspace::new();
    let l_ring = five_elements(&ring, &vec![[0.0; 3]; n], None, &mut ws)
        .map_err(failed)?
        .uniformity_l;
    let s = (std::f64::consts::PI / n as f64).sin();
    let closed = n as f64 * (s / (1.0 + s)).powi(3);
    checks.push(check(
        "O1",
        "L of 50 evenly spaced points on a circle (Eq. 28); exact closed form N(s/(1+s))³, s = sin(π/N), 1e-9",
        "≈ 0.01 (its own formula gives 0.008695)".into(),
        format!("{l_ring:.7} (closed form {closed:.7})"),
        ((l_ring - closed) / closed).abs() <= 1e-9,
    ));

    // Circle G3 and steeper G4 (O6–O8).
    let g3 = runs("gao-circle", None)?;
    let g4 = runs("gao-circle-steep", None)?;
    let t3: Vec<f64> = g3
        .iter()
        .map(|t| t.time_to_shape_s(0.0, 2000.0).unwrap_or(f64::INFINITY))
        .collect();
    let t4: Vec<f64> = g4
        .iter()
        .map(|t| t.time_to_shape_s(0.0, 2000.0).unwrap_or(f64::INFINITY))
        .collect();
    let l3: Vec<f64> = g3.iter().map(|t| t.l(t.times_s.len() - 1)).collect();
    let (mt3, mt4, ml3) = (median(&t3), median(&t4), median(&l3));
    checks.push(check(
        "O6",
        "G3 circle: 5 % band (radial and |y|) reached before 1000 s; L(2000 s) in [0.009, 0.0104]",
        "ring by ~1000 s, L → 0.01".into(),
        format!("median {mt3:.0} s, L(2000 s) = {ml3:.4}"),
        mt3 < 1000.0 && (0.009..=0.0104).contains(&ml3),
    ));
    let ratio = mt4 / mt3;
    checks.push(check(
        "O7",
        "G4 (μ = −20 km) vs G3 (μ = −5 km) time to the 5 % band; ratio ≤ 0.6",
        "\"roughly halves\" (ratio ≈ 0.5)".into(),
        format!("{mt4:.0} s vs {mt3:.0} s, ratio {ratio:.2}"),
        ratio <= 0.6,
    ));
    let dv3: Vec<f64> = g3.iter().map(|t| median(&t.delta_v_mps)).collect();
    let dv4: Vec<f64> = g4.iter().map(|t| median(&t.delta_v_mps)).collect();
    let max3 = g3
        .iter()
        .flat_map(|t| t.delta_v_mps.iter().copied())
        .fold(0.0, f64::max);
    checks.push(Check {
        criterion: None,
        id: "O8".into(),
        outcome: "G3 Δv per satellite over 2000 s (Fig. 13)".into(),
        paper: "< 1 m/s".into(),
        ours: format!(
            "median {:.1} m/s, max {max3:.1} m/s (G4: {:.1} m/s)",
            median(&dv3),
            median(&dv4)
        ),
        verdict: Verdict::NotReproduced,
    });
    notes.push(
        "O8: with the stated gains the initial push k_f·|e|·(|e|+|μ|) ≈ 7.4 kN on 100 kg drives each \
         satellite to F/k_v ≈ 3.7 m/s, which it must shed again, and holding a radial offset costs \
         3ω²|z| (≈ 1.3 m/s per 1000 s at 0.5 km); any rest-to-rest move of 0.45 km in 1000 s needs ≥ 0.9 \
         m/s. The paper's < 1 m/s is not reachable with these gains; the law is not altered to match."
            .into(),
    );

    // O10: lines, at the paper's (assumed) 2000 s; G1 also followed to G1_LONG_S.
    let g1 = runs("gao-line", None)?;
    let g2 = runs("gao-double-line", None)?;
    let z1: Vec<f64> = g1
        .iter()
        .map(|t| line_distance_m(t, t.index_at(2000.0)))
        .collect();
    let z1_long: Vec<f64> = g1
        .iter()
        .map(|t| line_distance_m(t, t.times_s.len() - 1))
        .collect();
    let z2: Vec<f64> = g2
        .iter()
        .map(|t| line_distance_m(t, t.times_s.len() - 1))
        .collect();
    let gap1 = median(
        &g1.iter()
            .map(|t| central_line_spacing_m(t, t.index_at(2000.0)))
            .collect::<Vec<_>>(),
    );
    let gap1_long = median(
        &g1.iter()
            .map(|t| central_line_spacing_m(t, t.times_s.len() - 1))
            .collect::<Vec<_>>(),
    );
    let p1 = &g1[0].parameters[0];
    let critical = zigzag_critical_spacing_m(
        p1.k_c_kg_per_s2,
        p1.avoidance_radius_m,
        p1.k_f_kg_per_m_s2 * p1.a * p1.a * p1.mu_m.abs(),
    );
    checks.push(check(
        "O10",
        "G1 line z = 0 and G2 lines z = ±0.5 km: largest distance from the target lines (|z| or ||z|−0.5 km|, and |y|) at 2000 s ≤ 5 m",
        "lines formed (Fig. 11)".into(),
        format!(
            "G1 {:.1} m ({:.0} s: {:.1} m), G2 {:.1} m (medians)",
            median(&z1),
            G1_LONG_S,
            median(&z1_long),
            median(&z2)
        ),
        median(&z1) <= 5.0 && median(&z2) <= 5.0,
    ));
    notes.push(format!(
        "O10: the line is free along-track and spreads only by repulsion, so at 2000 s it is still \
         compressed: central spacing {gap1:.1} m (median of 5 seeds; {gap1_long:.1} m at {G1_LONG_S:.0} s) \
         with s = {:.0} m. A straight line is then unstable to the zigzag mode: its outward stiffness \
         4 Σ_(odd j ≥ 1, jδ < s) k_c (s/(jδ) − 1) exceeds the line's restoring stiffness k_f a²|μ| = {:.0} N/m for \
         spacings δ below {critical:.1} m (linear stability, from the gains alone). The thickness is this \
         buckling, not an error of the law; it shrinks as the line lengthens. G2 starts from the same \
         0.1 km ball on the ridge z = 0 of the double-well, which is unstable with stiffness −k_f a² μ = \
         −{:.0} N/m, i.e. a growth time k_v/(k_f a² μ) = {:.0} s: a satellite starting 1 m from z = 0 \
         needs ln(500) ≈ 6.2 growth times to reach its line, longer than 2000 s.",
        p1.avoidance_radius_m,
        p1.k_f_kg_per_m_s2 * p1.a * p1.a * p1.mu_m.abs(),
        g2[0].parameters[0].k_f_kg_per_m_s2 * g2[0].parameters[0].mu_m,
        g2[0].parameters[0].k_v_kg_per_s
            / (g2[0].parameters[0].k_f_kg_per_m_s2 * g2[0].parameters[0].mu_m),
    ));

    // O11: large circle.
    let g5 = runs("gao-circle-large", None)?;
    let e5: Vec<f64> = g5
        .iter()
        .map(|t| {
            let e = t.shape_error(t.times_s.len() - 1);
            e.max_residual_m.unwrap_or(f64::INFINITY) / e.size_m.unwrap_or(f64::NAN)
        })
        .collect();
    checks.push(check(
        "O11",
        "G5 circle r = 5 km: largest radial error at 2000 s ≤ 3 %",
        "circle formed (Fig. 16)".into(),
        format!("{:.2} % (median)", 100.0 * median(&e5)),
        median(&e5) <= 0.03,
    ));

    // O9: concentric double circle, at 2000 s (paper) and G6_LONG_S (same runs).
    let g6 = runs("gao-double-circle", None)?;
    let at = |t: &Trace, time: f64| {
        ring_assignment(t, 0, t.index_at(time), [500.0, 1500.0], 1000.0, 0.03)
    };
    let summary = |time: f64| {
        let on: Vec<(f64, f64)> = g6.iter().map(|t| at(t, time)).collect();
        (
            median(&on.iter().map(|x| x.0).collect::<Vec<_>>()),
            median(&on.iter().map(|x| x.1).collect::<Vec<_>>()),
        )
    };
    let (on_ring, nearest) = summary(2000.0);
    let (on_long, nearest_long) = summary(G6_LONG_S);
    let radii = |time: f64| {
        let rho: Vec<f64> = g6
            .iter()
            .flat_map(|t| {
                t.positions_gao_m[t.index_at(time)]
                    .iter()
                    .map(|q| (q.x * q.x + q.z * q.z).sqrt())
            })
            .collect();
        let lo = rho.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = rho.iter().copied().fold(0.0, f64::max);
        (lo, hi)
    };
    let (lo2, hi2) = radii(2000.0);
    let (lo8, hi8) = radii(G6_LONG_S);
    checks.push(check(
        "O9",
        "G6 double circle 0.5/1.5 km at 2000 s: every satellite within 3 % of a ring; ≥ 95 % on the ring nearer its start (ρ < 1 km → inner)",
        "two rings, satellites to the nearer ring (Fig. 17)".into(),
        format!(
            "2000 s: {:.0} % within 3 % of a ring, {:.0} % on the nearer ring, ρ {lo2:.0}–{hi2:.0} m; \
             {G6_LONG_S:.0} s: {:.0} %, {:.0} %, ρ {lo8:.0}–{hi8:.0} m (medians; ρ range over all seeds)",
            100.0 * on_ring,
            100.0 * nearest,
            100.0 * on_long,
            100.0 * nearest_long
        ),
        on_ring >= 1.0 && nearest >= 0.95,
    ));
    notes.push(
        "O9: with μ = +0.5 km the ring stiffness is k_f·φ''(±μ) = k_f·μ = 1.5 N/m, so the damped time \
         constant is k_v/(k_f μ) ≈ 1330 s; satellites starting near the ridge ρ = 1 km leave it at the \
         same slow rate, and 2000 s is not enough for all of them to settle from a 2 km cube. The same \
         runs are continued to the longer time to show where the physics converges."
            .into(),
    );

    // O12: Fig. 19 shapes.
    let surfaces = [
        ("gao-ellipse", "ellipse 1/0.6"),
        ("gao-double-ellipse", "double ellipse"),
        ("gao-ellipsoid-surface", "ellipsoid surface"),
        ("gao-sphere-surface", "sphere surface"),
    ];
    let mut ours12 = Vec::new();
    let mut ok12 = true;
    let mut l19 = Vec::new();
    for (name, label) in surfaces {
        let tr = runs(name, None)?;
        let rel: Vec<f64> = tr
            .iter()
            .map(|t| {
                let e = t.shape_error(t.times_s.len() - 1);
                e.max_residual_m
                    .unwrap_or(f64::INFINITY)
                    .max(e.max_out_of_plane_m)
                    / e.size_m.unwrap_or(f64::NAN)
            })
            .collect();
        let m = median(&rel);
        ok12 &= m <= 0.03;
        ours12.push(format!("{label} {:.1} %", 100.0 * m));
        l19.push((
            label,
            median(
                &tr.iter()
                    .map(|t| t.l(t.times_s.len() - 1))
                    .collect::<Vec<_>>(),
            ),
        ));
    }
    for (name, label) in [
        ("gao-disk", "disk"),
        ("gao-ellipse-disk", "ellipse disk"),
        ("gao-spherical-space", "spherical space"),
    ] {
        let tr = runs(name, None)?;
        let f: Vec<FilledShape> = tr
            .iter()
            .map(|t| filled_shape(t, t.times_s.len() - 1))
            .collect();
        let fill = median(&f.iter().map(|x| x.median_ratio).collect::<Vec<_>>());
        let gap = median(&f.iter().map(|x| x.largest_radial_gap).collect::<Vec<_>>());
        let aspect = median(&f.iter().map(|x| x.aspect_error).collect::<Vec<_>>());
        let plane = median(&f.iter().map(|x| x.out_of_plane).collect::<Vec<_>>());
        let formed = f.iter().filter(|x| x.formed()).count();
        ok12 &= 2 * formed > f.len();
        ours12.push(format!(
            "{label} widest empty annulus {gap:.2} ρ_max (median ρ/ρ_max {fill:.2}), aspect error {:.1} %, |y| {:.1} % ({formed}/{} seeds formed)",
            100.0 * aspect,
            100.0 * plane,
            f.len()
        ));
        l19.push((
            label,
            median(
                &tr.iter()
                    .map(|t| t.l(t.times_s.len() - 1))
                    .collect::<Vec<_>>(),
            ),
        ));
    }
    checks.push(check(
        "O12",
        "Fig. 18–19 shapes at 2000 s: surfaces within 3 % of their size (residual and |y|); filled shapes: the level set ρ ≤ ρ_max enclosing all satellites has the commanded aspect (RMS extents, 10 %), is filled (no empty annulus wider than 0.4 ρ_max; ring or shell ≈ 1) and in-plane (|y| ≤ 3 %); majority of seeds",
        "every shape formed".into(),
        ours12.join("; "),
        ok12,
    ));

    // O2: Table 3 rows from our simulated end states (the analytic rows are tests/val_metrics.rs).
    let table3 = [
        ("ellipse 1/0.6", 0.005165),
        ("double ellipse", f64::NAN),
        ("ellipsoid surface", 0.202120),
        ("sphere surface", 0.341012),
        ("disk", 0.071897),
        ("ellipse disk", 0.050474),
        ("spherical space", 0.765401),
    ];
    for (label, paper) in table3 {
        if paper.is_nan() {
            continue;
        }
        let ours = l19
            .iter()
            .find(|x| x.0 == label)
            .map(|x| x.1)
            .unwrap_or(f64::NAN);
        let ratio = ours / paper;
        checks.push(Check {
            criterion: None,
            id: "O2".into(),
            outcome: format!(
                "Table 3 L, {label}: our simulated end state at 2000 s (median of 5 seeds)"
            ),
            paper: format!("{paper}"),
            ours: format!("{ours:.5} (ratio {ratio:.2})"),
            verdict: if (ratio - 1.0).abs() <= 0.1 {
                Verdict::Reproduced
            } else if label == "ellipse disk" || label == "spherical space" {
                Verdict::NotReproduced
            } else {
                Verdict::Differs
            },
        });
    }
    notes.push(
        "O2: the analytic Table 3 rows (circle 0.8 %, sphere surface, double circle 35/15, disk rings) are \
         asserted in tests/val_metrics.rs. The filled rows ellipse disk, ellipsoidal and spherical space \
         exceed every point set confined to the shape that we tried (spherical space 0.765 exceeds \
         close packing), so the generating sets are unknown; the Table 3 ellipse disk is 1/0.5, Fig. 19c \
         (simulated here) 1/0.6."
            .into(),
    );

    // O3: centre propagation.
    let j2 = table5_centre_errors(GravityModel::J2)?;
    let kepler = table5_centre_errors(GravityModel::TwoBody)?;
    let worst = |v: &[(f64, f64, f64)]| {
        v.iter()
            .fold((0.0_f64, 0.0_f64), |a, x| (a.0.max(x.1), a.1.max(x.2)))
    };
    let (wr, wv) = worst(&j2);
    let (kr, _) = worst(&kepler);
    checks.push(check(
        "O3",
        "Table 5 cluster centre at 1000/1500/2000 s from its t = 0 state, point mass + J2: ≤ 0.5 km, ≤ 1 m/s (two-body must miss)",
        "Table 5 (r_o, v_o)".into(),
        format!(
            "J2: {} (worst {:.3} km, {:.2} m/s); two-body worst {:.1} km",
            j2.iter()
                .map(|x| format!("{:.0} s {:.3} km", x.0, x.1 / 1e3))
                .collect::<Vec<_>>()
                .join(", "),
            wr / 1e3,
            wv,
            kr / 1e3
        ),
        wr <= 500.0 && wv <= 1.0 && kr > 5_000.0,
    ));

    // G9: the Table 4 sequence (O4, O5, O13, O14).
    let g9 = runs("gao-reconfiguration", None)?;
    let n_all = g9.iter().all(|t| t.five.iter().all(|f| f.n == 50));
    checks.push(check(
        "O4",
        "N = 50 at every recorded time of G9",
        "50".into(),
        if n_all { "50" } else { "lost satellites" }.into(),
        n_all,
    ));
    let sw = TABLE5_OFFSET_S + 1000.0;
    let mut dip = Vec::new();
    let mut l_end = Vec::new();
    let mut diam_end = Vec::new();
    let mut l_disk = Vec::new();
    let mut t5 = Vec::new();
    for t in &g9 {
        let k_sw = t.index_at(sw);
        let k_min = (k_sw..=t.index_at(sw + 150.0))
            .min_by(|&a, &b| t.l(a).total_cmp(&t.l(b)))
            .unwrap_or(k_sw);
        dip.push(t.l(k_sw) / t.l(k_min));
        let k_end = t.index_at(sw + 1000.0 - 1e-6);
        l_end.push(t.l(k_end));
        diam_end.push(t.five[k_end].diameter_m);
        let disk: Vec<f64> = (t.index_at(TABLE5_OFFSET_S)..=k_sw)
            .map(|k| t.l(k))
            .collect();
        l_disk.push(median(&disk));
        t5.push([0.0, 1000.0, 1050.0, 1100.0, 1500.0, 2000.0].map(|x| {
            let k = t.index_at(TABLE5_OFFSET_S + x);
            (t.five[k].diameter_m, t.five[k].d_min_m, t.l(k))
        }));
    }
    let (md, mle, mde) = (median(&dip), median(&l_end), median(&diam_end));
    checks.push(check(
        "O5",
        "G9 disk → circle (Table 5 t = 1000 s): L dips ≥ 5× within 150 s; L(2000 s) in [0.006, 0.0105]; diameter(2000 s) in [0.98, 1.08] km",
        "L 0.0709 → 0.0046 (1100 s) → 0.0086; diameter 1.003 km".into(),
        format!("dip ×{md:.1}, L(2000 s) = {mle:.4}, diameter {:.3} km", mde / 1e3),
        md >= 5.0 && (0.006..=0.0105).contains(&mle) && (980.0..=1080.0).contains(&mde),
    ));
    let table5_ours = (0..6)
        .map(|j| {
            let d = median(&t5.iter().map(|r| r[j].0).collect::<Vec<_>>()) / 1e3;
            let m = median(&t5.iter().map(|r| r[j].1).collect::<Vec<_>>()) / 1e3;
            let l = median(&t5.iter().map(|r| r[j].2).collect::<Vec<_>>());
            format!("{d:.3}/{m:.4}/{l:.4}")
        })
        .collect::<Vec<_>>()
        .join(", ");
    notes.push(format!(
        "Table 5 (diameter km / d_min km / L at 0, 1000, 1050, 1100, 1500, 2000 s), paper: \
         0.923/0.0916/0.0697, 0.921/0.0944/0.0709, 0.966/0.0509/0.0210, 1.004/0.0033/0.0046, \
         1.003/0.0275/0.0066, 1.003/0.0468/0.0086; ours (medians of 5 seeds): {table5_ours}. Our disk \
         (s = 1 km, μ = −1 km) is larger than the paper's 0.923 km: the paper's disk s is not given."
    ));
    let ml_disk = median(&l_disk);
    checks.push(check(
        "O14",
        "G9 L while in the disk (Table 5 0–1000 s) in [0.05, 0.09] (the text's \"0.7\" is a typo for 0.07)",
        "≈ 0.07".into(),
        format!("{ml_disk:.4} (median)"),
        (0.05..=0.09).contains(&ml_disk),
    ));
    // O13: every stage at its end (the recording at the switch time, judged against the stage that
    // ends there), with O9–O12's criteria; nearest-ring assignment on ellipse → double circle.
    let stage_ends = [
        (TABLE5_OFFSET_S + 2000.0, "circle"),
        (TABLE5_OFFSET_S + 3000.0, "line"),
        (TABLE5_OFFSET_S + 4000.0, "double line"),
        (TABLE5_OFFSET_S + 5000.0, "ellipse"),
        (TABLE5_OFFSET_S + 6000.0, "double circle"),
    ];
    let mut ours13 = Vec::new();
    let mut ok13 = true;
    for (end, label) in stage_ends {
        let errors: Vec<f64> = g9.iter().map(|t| stage_end_error(t, end)).collect();
        let m = median(&errors);
        match label {
            "line" | "double line" => {
                ok13 &= m <= 5.0;
                ours13.push(format!("{label} {m:.1} m"));
            }
            "double circle" => {
                let on: Vec<f64> = g9
                    .iter()
                    .map(|t| {
                        let k = t.index_at(end);
                        ring_assignment(t, k, k, [500.0, 1500.0], 1000.0, 0.03).0
                    })
                    .collect();
                let m_on = median(&on);
                ok13 &= m_on >= 1.0;
                ours13.push(format!(
                    "{label} {:.0} % within 3 % of a ring",
                    100.0 * m_on
                ));
            }
            _ => {
                ok13 &= m <= 0.03;
                ours13.push(format!("{label} {:.1} %", 100.0 * m));
            }
        }
    }
    let nearest13 = median(
        &g9.iter()
            .map(|t| {
                let from = t.index_at(TABLE5_OFFSET_S + 5000.0);
                ring_assignment(t, from, t.times_s.len() - 1, [500.0, 1500.0], 1000.0, 0.03).1
            })
            .collect::<Vec<_>>(),
    );
    ok13 &= nearest13 >= 0.95;
    checks.push(check(
        "O13",
        "G9 Table 4, each stage at its end: circle, ellipse residual and |y| ≤ 3 % of size; line, double line ≤ 5 m; double circle every satellite within 3 % of a ring; ellipse → double circle ≥ 95 % on the nearer ring",
        "every reconfiguration succeeds, no slots".into(),
        format!("{}; nearer ring {:.0} % (medians)", ours13.join(", "), 100.0 * nearest13),
        ok13,
    ));
    let line_gap = median(
        &g9.iter()
            .map(|t| central_line_spacing_m(t, t.index_at(TABLE5_OFFSET_S + 3000.0)))
            .collect::<Vec<_>>(),
    );
    let p9 = &g9[0].parameters[g9[0].index_at(TABLE5_OFFSET_S + 2500.0)];
    let critical9 = zigzag_critical_spacing_m(
        p9.k_c_kg_per_s2,
        p9.avoidance_radius_m,
        p9.k_f_kg_per_m_s2 * p9.mu_m.abs(),
    );
    let inner: Vec<(f64, f64)> = g9
        .iter()
        .map(|t| {
            let rho: Vec<f64> = t.positions_gao_m[t.times_s.len() - 1]
                .iter()
                .map(|q| (q.x * q.x + q.z * q.z).sqrt())
                .collect();
            (
                rho.iter().copied().fold(f64::INFINITY, f64::min),
                rho.iter().copied().fold(0.0, f64::max),
            )
        })
        .collect();
    notes.push(format!(
        "O13: line stage (k_f = 3 kg/(km s²) here, restoring k_f|μ| = 3 N/m): central spacing {line_gap:.1} m \
         at the stage end against a zigzag-critical spacing of {critical9:.1} m, so the line buckles as \
         in O10, more (weaker restoring). The double line starts from that line, i.e. from the unstable \
         ridge z = 0, with growth time k_v/(k_f μ) ≈ 1330 s: 1000 s is not enough. Every satellite goes \
         to the 0.5 km ring (the Table 4 ellipse, \
         semi-axes 1 and 0.6 km, lies inside ρ = 1 km), but after 1000 s with ring stiffness \
         k_f·μ = 1.5 N/m (time constant ≈ 1330 s) the radii still span {:.0}–{:.0} m (median over \
         seeds of the smallest and largest); satellites that ended the ellipse at x ≈ ±1 km start on \
         the ridge ρ = 1 km.",
        median(&inner.iter().map(|x| x.0).collect::<Vec<_>>()),
        median(&inner.iter().map(|x| x.1).collect::<Vec<_>>()),
    ));
    Ok(Report {
        measured: None,
        title: "Gao, Li & Wei 2022, bifurcating potential field (Aerospace 9(3):137)".into(),
        reference_header: "reference".into(),
        checks,
        tables: Vec::new(),
        notes,
    })
}
