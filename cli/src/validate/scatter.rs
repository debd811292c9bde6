//! `satflock validate scatter`: the behaviour-based scatter manoeuvres of S. Nag and L. Summerer,
//! "Behaviour based, autonomous and distributed scatter manoeuvres for satellite swarms", Acta
//! Astronautica 82 (2013) 95–109, reproduced with the `equilibrium-shaping` law from the 13 built-in
//! `es-*` scenarios, every one at full length.
//!
//! The report has three parts:
//!
//! * the outcome table N1–N11 and the physics bounds B1–B2 ([`report`]); every criterion is a constant
//!   or a function of this module, written down before any run and shared with the release-mode tests
//!   (`cli/tests/regress_scatter.rs`), which call the same `check_*` functions on the same runs;
//! * a strategy comparison in the form of the paper's Table 2 (run length, mean Δv, minimum and mean
//!   miss distance, final formation error, final centroid displacement), ours beside the paper's
//!   Tables 1–2 and text;
//! * the cases of the reconstruction's check list, ours beside the paper and beside an earlier numpy
//!   prototype of the same reconstruction.
//!
//! Every measurement is made here from the engine's truth, independently of the law's own metrics:
//! miss distances from the engine's continuous closest-approach monitor
//! ([`satflock::environment::ApproachMonitor`]), Δv from the engine's ledger (∫‖u‖dt after the
//! actuator limit, process noise not counted), formation errors and centroids from the truth Hill
//! states and the node geometry. The nodes are the satellites' initial positions: every `es-*` scenario
//! starts the satellites at rest on their nodes (paper §4: "satellites start at rest on their nodes").
//!
//! Definitions (paper §4 and Table 1): the *miss distance* of a satellite is its closest approach to
//! the threat over the run; *minimum miss* is the minimum over satellites, *average miss* the mean.
//! *Formation error* is the RMS over satellite pairs of ‖x_i − x_j‖ − δ_ij, δ_ij the node distance.
//! *Δv* is the mean over satellites of ∫‖u‖dt. The *centroid displacement* is ‖mean_i (x_i − ξ_i)‖.

use nalgebra::{Vector3, Vector6};

use crate::validate::{Check, Report, Table, ValidateError, Verdict};
use satflock::environment::Threat;
use satflock::guidance::equilibrium_shaping::shaping::pair_attraction_per_s;
use satflock::guidance::equilibrium_shaping::{EquilibriumShaping, EquilibriumShapingParameters};
use satflock::guidance::LawConfig;
use satflock::relative::Hcw;
use satflock::scenario::schema::ActionSection;
use satflock::scenario::Scenario;
use satflock::swarm::{Actuator, DynamicsModel, LimitKind, Recorder, Simulation, Snapshot};

fn failed(e: impl std::fmt::Display) -> ValidateError {
    ValidateError::Failed {
        target: "scatter".into(),
        message: e.to_string(),
    }
}

// ---------------------------------------------------------------------------------------------------
// Criteria, fixed before any run (the paper's numbers and the reconstruction's tolerances).
// ---------------------------------------------------------------------------------------------------

/// N2 (paper §3.1, Fig. 2): after the threat has passed, the rhombus is restored to within this
/// formation error \[m\] ("restored to ≤ 1 mm").
pub const N2_FORMATION_ERROR_M: f64 = 1e-3;
/// N2: "past" means the threat is more than this far beyond satellite 0's node along its own motion
/// \[m\] (the E0 run's own end: "until the threat is 10 m past").
pub const N2_PAST_M: f64 = 10.0;
/// N2: E0 is continued to this time \[s\] (the scenario ends at 40 s, when the threat is exactly 10 m
/// past the node; the extension gives 20 s with the threat more than 10 m past).
pub const N2_EXTENDED_S: f64 = 60.0;
/// N3 (Table 1, sims 2 and 4): the average miss does not depend on the threat speed: sim 4's within
/// this fraction of sim 2's.
pub const N3_RELATIVE: f64 = 0.10;
/// N5 (Table 1, sim 2): the paper's average miss \[m\] and the band the reconstruction allows (reported,
/// not asserted by the tests).
pub const N5_PAPER_MISS_M: f64 = 45.0;
/// N5: relative band.
pub const N5_RELATIVE: f64 = 0.25;
/// N6 (Table 2: 45 vs 7 m; 62 vs 9 m): perpendicular escapes miss by at least this factor more than
/// parallel ones.
pub const N6_RATIO: f64 = 3.0;
/// N7 (S3 keeps the centroid): final centroid displacement at most this \[m\].
pub const N7_CENTROID_M: f64 = 0.1;
/// N8 (S2 moves the centroid, "≈ 1 km" in the paper's Fig. 6): final centroid displacement above this
/// \[m\].
pub const N8_CENTROID_M: f64 = 50.0;
/// N9 (Table 2 Δv, reported): ours within this factor of the paper's.
pub const N9_FACTOR: f64 = 2.5;
/// N10 (electric propulsion, paper §4.2: "could never buy more than about 1 m"): the average miss
/// exceeds the node offset by at most this \[m\].
pub const N10_EXCESS_M: f64 = 1.0;
/// N11 (paper §4.1): danger sphere centre (Hill frame) \[m\] and radius \[m\].
pub const N11_SPHERE_CENTRE_M: [f64; 3] = [0.0, 0.0, 0.0];
/// N11: danger sphere radius \[m\].
pub const N11_SPHERE_RADIUS_M: f64 = 20.0;
/// N11: band about the sphere \[m\].
pub const N11_BAND_M: f64 = 0.5;
/// N11: "at rest" on the sphere: every speed below this \[m/s\] (the law's own settling speed default,
/// 1 mm/s; the paper gives no number).
pub const N11_REST_MPS: f64 = 1e-3;
/// N11: the warning ends (satellites leave the sphere) at this time \[s\] (Table 2: 3000 + 1000 s).
pub const N11_SCATTER_END_S: f64 = 3000.0;
/// N11: Δv within this factor of the paper's 1.8 (scatter) and 0.5 m/s (gather).
pub const N11_FACTOR: f64 = 2.0;
/// B1: rounding allowance, relative. The ledger is the RK4-weighted sum (positive weights summing to
/// one step) of stage values each within the cap, so it cannot exceed the bound but by rounding.
pub const B1_RELATIVE: f64 = 1e-9;
/// B2: allowance for the integration error of the measured displacement \[m\]. RK4 at 0.02–0.05 s on
/// HCW (n·h ≈ 5e-5) is exact to far below a micrometre for smooth motion; each switch of a saturated
/// command costs O(h² Δu) ≈ 4e-6 m; 1 mm covers hundreds of them and is 0.25 % of the smallest bound
/// tested (the electric cap, 0.40 m).
pub const B2_TOLERANCE_M: f64 = 1e-3;

/// Paper Table 2 / Table 1 / text numbers used by the checks.
pub mod paper {
    /// S1 scatter Δv \[m/s\] (Table 2: 1.8 + 0.5).
    pub const S1_SCATTER_DV: f64 = 1.8;
    /// S1 gather Δv \[m/s\].
    pub const S1_GATHER_DV: f64 = 0.5;
    /// S2 parallel Δv \[m/s\] (Table 2).
    pub const S2_PARALLEL_DV: f64 = 1.6;
    /// S2 perpendicular Δv \[m/s\] (Table 2, 700 s).
    pub const S2_PERPENDICULAR_DV: f64 = 0.4;
    /// S3 parallel Δv \[m/s\] (Table 2).
    pub const S3_PARALLEL_DV: f64 = 1.3;
    /// S3 perpendicular Δv \[m/s\] (Table 2).
    pub const S3_PERPENDICULAR_DV: f64 = 0.86;
    /// S4 Δv \[m/s\] (Table 2).
    pub const S4_DV: f64 = 0.9;
}

// ---------------------------------------------------------------------------------------------------
// Runs.
// ---------------------------------------------------------------------------------------------------

/// Runs at once (the brief of the report: a bounded pool of two; fewer if rayon has fewer threads).
pub const WORKERS: usize = 2;

/// One simulation to run: a built-in `es-*` scenario, possibly cut or continued, possibly without
/// process noise or with another common escape direction.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseJob {
    /// Label in the report.
    pub label: String,
    /// Built-in scenario.
    pub builtin: &'static str,
    /// Run length \[s\] instead of the scenario's (events after it dropped).
    pub duration_s: Option<f64>,
    /// Keep the scenario's process noise.
    pub process_noise: bool,
    /// `perp-common` escape direction instead of the scenario's (Hill frame).
    pub escape_direction_hill: Option<[f64; 3]>,
    /// Times at which the whole state is captured besides the end \[s\] (recording or tick times, so that
    /// the run is bitwise the uninterrupted one).
    pub samples_s: Vec<f64>,
}

impl CaseJob {
    /// The scenario as it is.
    pub fn full(builtin: &'static str) -> Self {
        Self {
            label: builtin.to_string(),
            builtin,
            duration_s: None,
            process_noise: true,
            escape_direction_hill: None,
            samples_s: Vec::new(),
        }
    }

    /// The scenario run for `duration_s` instead.
    pub fn until(builtin: &'static str, duration_s: f64) -> Self {
        Self {
            label: format!("{builtin} to {duration_s} s"),
            duration_s: Some(duration_s),
            ..Self::full(builtin)
        }
    }

    /// The scenario without process noise, run to `duration_s` (bound B2: the displacement is then
    /// exactly the free motion plus the control's contribution).
    pub fn noise_free_until(builtin: &'static str, duration_s: f64) -> Self {
        Self {
            label: format!("{builtin} without noise to {duration_s} s"),
            duration_s: Some(duration_s),
            process_noise: false,
            ..Self::full(builtin)
        }
    }

    /// With the state also captured at `samples_s`.
    pub fn with_samples(mut self, samples_s: &[f64]) -> Self {
        self.samples_s = samples_s.to_vec();
        self
    }
}

/// The state of a run at one time.
#[derive(Clone, Debug, PartialEq)]
pub struct Sample {
    /// Time \[s\].
    pub time_s: f64,
    /// Truth Hill positions \[m\].
    pub positions_m: Vec<Vector3<f64>>,
    /// Truth Hill velocities \[m/s\].
    pub velocities_mps: Vec<Vector3<f64>>,
    /// Δv ledger per satellite, ∫‖u‖dt \[m/s\].
    pub delta_v_mps: Vec<f64>,
    /// Δv ledger per satellite and Hill axis, ∫|u_k|dt \[m/s\].
    pub delta_v_axes_mps: Vec<[f64; 3]>,
    /// Closest approach of each satellite to the threat so far (continuous monitor) \[m\]; +∞ without a
    /// threat.
    pub miss_m: Vec<f64>,
}

/// A recording: time and truth Hill positions.
#[derive(Clone, Debug, PartialEq)]
pub struct Record {
    /// Time \[s\].
    pub time_s: f64,
    /// Truth Hill positions \[m\].
    pub positions_m: Vec<Vector3<f64>>,
}

/// A finished run.
#[derive(Clone, Debug)]
pub struct CaseRun {
    /// What was run.
    pub job: CaseJob,
    /// The nodes: the satellites' initial positions, Hill \[m\].
    pub nodes_m: Vec<Vector3<f64>>,
    /// Initial Hill states \[m, m/s\].
    pub initial: Vec<Vector6<f64>>,
    /// Thrusters of each satellite.
    pub actuators: Vec<Actuator>,
    /// The HCW model of the run (`None` for the kinematic model).
    pub hcw: Option<Hcw>,
    /// The law's threat (index 0 of the scenario; every `es-*` scenario has exactly one).
    pub threat: Option<Threat>,
    /// When the ground warning is raised \[s\] (`None`: no warning, physical sensing only).
    pub warning_on_s: Option<f64>,
    /// When the warning is cleared \[s\].
    pub warning_off_s: Option<f64>,
    /// Length of the run \[s\].
    pub duration_s: f64,
    /// The law's parameters (as loaded; events do not change them in the `es-*` scenarios).
    pub law: EquilibriumShapingParameters,
    /// Every recording.
    pub records: Vec<Record>,
    /// The captured samples, in time order, the end of the run last.
    pub samples: Vec<Sample>,
}

struct Collect(Vec<Record>);

impl Recorder for Collect {
    fn record(&mut self, s: &Snapshot<'_>) -> std::io::Result<()> {
        self.0.push(Record {
            time_s: s.time_s,
            positions_m: s.relative_states.iter().map(|r| r.position_m).collect(),
        });
        Ok(())
    }
}

fn sample(sim: &Simulation) -> Sample {
    let states = sim.states_hill();
    let n = states.len();
    let monitor = sim.approach_monitor();
    let state = sim.state();
    Sample {
        time_s: sim.time_s(),
        positions_m: states.iter().map(|s| s.position_m).collect(),
        velocities_mps: states.iter().map(|s| s.velocity_mps).collect(),
        delta_v_mps: (0..n).map(|i| state.ledger(i).1).collect(),
        delta_v_axes_mps: (0..n).map(|i| state.ledger(i).0).collect(),
        miss_m: (0..n)
            .map(|i| {
                monitor
                    .satellite_threat_minimum(i)
                    .map_or(f64::INFINITY, |m| m.minimum.distance_m)
            })
            .collect(),
    }
}

/// The scenario of a job, modified as the job says.
pub fn scenario_of(job: &CaseJob) -> Result<Scenario, ValidateError> {
    let mut scenario = Scenario::load(job.builtin).map_err(failed)?;
    if let Some(d) = job.duration_s {
        scenario.file.duration_s = d;
        scenario.file.events.retain(|e| e.time_s <= d);
    }
    if !job.process_noise {
        scenario.file.dynamics.process_noise_mps2 = 0.0;
    }
    if let Some(direction) = job.escape_direction_hill {
        let LawConfig::EquilibriumShaping(p) = &mut scenario.file.law else {
            return Err(failed(format!(
                "{} does not run the equilibrium-shaping law",
                job.builtin
            )));
        };
        p.escape_direction_hill = Some(direction);
    }
    Ok(scenario)
}

/// Runs one job.
pub fn run_case(job: &CaseJob) -> Result<CaseRun, ValidateError> {
    let scenario = scenario_of(job)?;
    let warning = |active: bool| {
        scenario
            .file
            .events
            .iter()
            .filter(|e| {
                matches!(e.action, ActionSection::ThreatWarning { threat: 0, active: a } if a == active)
            })
            .map(|e| e.time_s)
            .reduce(f64::min)
    };
    let (warning_on_s, warning_off_s) = (warning(true), warning(false));
    let LawConfig::EquilibriumShaping(law) = scenario.file.law.clone() else {
        return Err(failed(format!(
            "{} does not run the equilibrium-shaping law",
            job.builtin
        )));
    };
    let prepared = scenario.prepare().map_err(failed)?;
    let actuators: Vec<Actuator> = prepared.satellites.iter().map(|s| s.actuator).collect();
    let initial: Vec<Vector6<f64>> = prepared
        .satellites
        .iter()
        .map(|s| s.relative_state.to_vector6())
        .collect();
    let nodes_m: Vec<Vector3<f64>> = prepared
        .satellites
        .iter()
        .map(|s| s.relative_state.position_m)
        .collect();
    let hcw = match prepared.config.dynamics {
        DynamicsModel::Hcw(h) => Some(h),
        _ => None,
    };
    let threat = prepared.config.threats.first().cloned();
    let duration_s = prepared.config.duration_s;
    let mut sim = Simulation::new(
        prepared.config,
        &prepared.satellites,
        prepared.law,
        prepared.events,
    )
    .map_err(failed)?;
    let mut collect = Collect(Vec::new());
    let mut samples = Vec::new();
    let mut times = job.samples_s.clone();
    times.sort_by(f64::total_cmp);
    for t in times.into_iter().filter(|t| *t < duration_s) {
        sim.advance_to(t, &mut collect).map_err(failed)?;
        samples.push(sample(&sim));
    }
    sim.advance_to(duration_s, &mut collect).map_err(failed)?;
    samples.push(sample(&sim));
    if sim.active().iter().any(|a| !a) {
        return Err(failed(format!("{}: a satellite was removed", job.label)));
    }
    Ok(CaseRun {
        job: job.clone(),
        nodes_m,
        initial,
        actuators,
        hcw,
        threat,
        warning_on_s,
        warning_off_s,
        duration_s,
        law: *law,
        records: collect.0,
        samples,
    })
}

/// Runs every job through [`satflock::campaign::pool::run_bounded`], [`WORKERS`] at a time, each worker running whole runs one after another on its own
/// single-thread rayon pool (4–6 satellites are too few for the engine's per-step parallelism to pay;
/// results do not depend on the thread count, the engine being bitwise deterministic). Runs come back
/// in job order.
pub fn run_cases(jobs: &[CaseJob]) -> Result<Vec<CaseRun>, ValidateError> {
    satflock::campaign::pool::run_bounded(
        jobs.iter().collect(),
        WORKERS.min(rayon::current_num_threads()),
        run_case,
    )
    .map_err(failed)?
    .into_iter()
    .collect()
}

// ---------------------------------------------------------------------------------------------------
// Measurements (from the truth states and the node geometry; independent of the law's metrics).
// ---------------------------------------------------------------------------------------------------

/// Mean of a non-empty list.
pub fn mean(values: &[f64]) -> f64 {
    values.iter().sum::<f64>() / values.len() as f64
}

/// Minimum of a list (+∞ when empty).
pub fn minimum(values: &[f64]) -> f64 {
    values.iter().copied().fold(f64::INFINITY, f64::min)
}

/// Formation error: RMS over pairs of ‖x_i − x_j‖ − δ_ij, δ_ij = ‖ξ_i − ξ_j‖ \[m\].
pub fn formation_error_m(positions_m: &[Vector3<f64>], nodes_m: &[Vector3<f64>]) -> f64 {
    let n = positions_m.len();
    let (mut sum, mut pairs) = (0.0, 0usize);
    for i in 0..n {
        for j in i + 1..n {
            let e = (positions_m[i] - positions_m[j]).norm() - (nodes_m[i] - nodes_m[j]).norm();
            sum += e * e;
            pairs += 1;
        }
    }
    if pairs == 0 {
        0.0
    } else {
        (sum / pairs as f64).sqrt()
    }
}

/// Centroid displacement ‖mean_i (x_i − ξ_i)‖ \[m\].
pub fn centroid_displacement_m(positions_m: &[Vector3<f64>], nodes_m: &[Vector3<f64>]) -> f64 {
    let sum: Vector3<f64> = positions_m.iter().zip(nodes_m).map(|(x, xi)| x - xi).sum();
    (sum / positions_m.len() as f64).norm()
}

/// Distance of a point from the threat's (infinite) line \[m\].
pub fn line_distance_m(threat: &Threat, point_m: &Vector3<f64>) -> f64 {
    let v = threat.velocity_hill_mps().normalize();
    let r = point_m - threat.position_hill_m(0.0);
    (r - r.dot(&v) * v).norm()
}

/// N10's node offset: the miss the satellites would have if they stayed on their nodes, i.e. the
/// threat line's distance to each node, averaged \[m\].
pub fn node_offset_m(threat: &Threat, nodes_m: &[Vector3<f64>]) -> f64 {
    mean(
        &nodes_m
            .iter()
            .map(|xi| line_distance_m(threat, xi))
            .collect::<Vec<_>>(),
    )
}

/// Time at which the threat passes closest to a point \[s\].
pub fn closest_time_s(threat: &Threat, point_m: &Vector3<f64>) -> f64 {
    let v = threat.velocity_hill_mps();
    (point_m - threat.position_hill_m(0.0)).dot(&v) / v.norm_squared()
}

impl CaseRun {
    /// The state at the end of the run.
    pub fn end(&self) -> &Sample {
        self.samples.last().expect("every run has its end sample")
    }

    /// The captured sample at `time_s` (within 1 µs).
    pub fn at(&self, time_s: f64) -> Option<&Sample> {
        self.samples
            .iter()
            .find(|s| (s.time_s - time_s).abs() < 1e-6)
    }

    /// Headtime: from the warning to the threat's arrival at satellite 0's node \[s\] (`None` without a
    /// warning or a threat).
    pub fn headtime_s(&self) -> Option<f64> {
        let threat = self.threat.as_ref()?;
        Some(closest_time_s(threat, &self.nodes_m[0]) - self.warning_on_s?)
    }

    /// Mean Δv over satellites at a sample \[m/s\].
    pub fn mean_delta_v_mps(s: &Sample) -> f64 {
        mean(&s.delta_v_mps)
    }

    /// Final formation error \[m\].
    pub fn final_formation_error_m(&self) -> f64 {
        formation_error_m(&self.end().positions_m, &self.nodes_m)
    }

    /// Final centroid displacement \[m\].
    pub fn final_centroid_m(&self) -> f64 {
        centroid_displacement_m(&self.end().positions_m, &self.nodes_m)
    }

    /// Average miss over the run \[m\].
    pub fn average_miss_m(&self) -> f64 {
        mean(&self.end().miss_m)
    }

    /// Minimum miss over the run \[m\].
    pub fn minimum_miss_m(&self) -> f64 {
        minimum(&self.end().miss_m)
    }

    /// Largest distance of a satellite from its node over the recordings \[m\].
    pub fn max_node_distance_m(&self) -> f64 {
        self.records
            .iter()
            .flat_map(|r| {
                r.positions_m
                    .iter()
                    .zip(&self.nodes_m)
                    .map(|(x, xi)| (x - xi).norm())
            })
            .fold(0.0, f64::max)
    }

    /// Smallest distance between two satellites over the recordings \[m\].
    pub fn min_separation_m(&self) -> f64 {
        let mut least = f64::INFINITY;
        for r in &self.records {
            let p = &r.positions_m;
            for i in 0..p.len() {
                for j in i + 1..p.len() {
                    least = least.min((p[i] - p[j]).norm());
                }
            }
        }
        least
    }

    /// Largest radial (Hill x) position of a satellite over the recordings \[m\].
    pub fn max_radial_m(&self) -> f64 {
        self.records
            .iter()
            .flat_map(|r| r.positions_m.iter().map(|x| x.x))
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// Per-axis acceleration cap common to every satellite \[m/s²\] (`None`: uncapped, or mixed).
    pub fn common_cap(&self) -> Option<(f64, LimitKind)> {
        let a = self.actuators.first()?;
        let same = self
            .actuators
            .iter()
            .all(|b| b.max_accel_m_s2 == a.max_accel_m_s2 && b.limit == a.limit);
        (same && a.max_accel_m_s2.is_finite()).then_some((a.max_accel_m_s2, a.limit))
    }
}

// ---------------------------------------------------------------------------------------------------
// Bounds.
// ---------------------------------------------------------------------------------------------------

/// Number of Hill axes with a non-zero component perpendicular to a direction: 2 for a frame axis,
/// 3 otherwise (the axes whose thrust can move a satellite away from the threat's line).
pub fn perpendicular_axes(direction: &Vector3<f64>) -> usize {
    let d = direction.normalize();
    if (0..3).any(|k| (d[k].abs() - 1.0).abs() < 1e-12) {
        2
    } else {
        3
    }
}

/// B2 as the reconstruction states it: with a per-axis cap `a`, the control moves a satellite from
/// rest by at most ½ √m a t² perpendicular to the threat on a double integrator, m the number of axes
/// perpendicular to the threat \[m\].
pub fn double_integrator_bound_m(accel_m_s2: f64, time_s: f64, axes: usize) -> f64 {
    0.5 * (axes as f64).sqrt() * accel_m_s2 * time_s * time_s
}

/// Radius of the set of in-plane (Hill x, y) control-only displacements reachable on the HCW equations
/// at each of `times_s` with |u_x|, |u_y| ≤ `accel_m_s2` \[m\]: max over in-plane unit vectors e of
/// a ∫₀^t ‖M(τ)ᵀ e‖₁ dτ, with M(τ) the in-plane block of Φ_rv(τ) (the HCW response of position to a
/// velocity impulse, i.e. to u held for dτ, τ before). This is exact for HCW, unlike the
/// double-integrator ½√2 a t², which the Coriolis coupling exceeds (by 0.15 % at 200 s, 1.8 % at 500 s
/// for n = 1.078e-3 rad/s).
///
/// Numerics, both conservative: trapezoidal quadrature on a 0.01 s grid (the integrand is piecewise
/// smooth; its error is below 1e-8 relative here), and a maximum over 720 directions (0.25° apart)
/// divided by cos(0.125°): the support function h(e) of a convex set obeys h(e') ≥ R cos(∠(e, e'))
/// for the maximising direction e, so the grid maximum over cos(Δ/2) is an upper bound of R.
pub fn hcw_planar_reach_m(hcw: &Hcw, accel_m_s2: f64, times_s: &[f64]) -> Vec<f64> {
    const ANGLES: usize = 720;
    let t_max = times_s.iter().copied().fold(0.0, f64::max);
    let h = 0.01;
    let steps = (t_max / h).ceil() as usize;
    let h = if steps > 0 { t_max / steps as f64 } else { 0.0 };
    let directions: Vec<(f64, f64)> = (0..ANGLES)
        .map(|k| {
            let angle = std::f64::consts::PI * k as f64 / ANGLES as f64;
            (angle.cos(), angle.sin())
        })
        .collect();
    let integrand = |tau: f64| -> Vec<f64> {
        let phi = hcw.state_transition_matrix(tau);
        // Position rows (x, y), velocity columns (vx, vy).
        let (m11, m12, m21, m22) = (phi[(0, 3)], phi[(0, 4)], phi[(1, 3)], phi[(1, 4)]);
        directions
            .iter()
            .map(|(ex, ey)| (m11 * ex + m21 * ey).abs() + (m12 * ex + m22 * ey).abs())
            .collect()
    };
    let mut order: Vec<usize> = (0..times_s.len()).collect();
    order.sort_by(|&a, &b| times_s[a].total_cmp(&times_s[b]));
    let mut out = vec![0.0; times_s.len()];
    let mut cumulative = vec![0.0; ANGLES];
    let mut previous = integrand(0.0);
    let mut k = 0usize;
    let slack = (0.5 * std::f64::consts::PI / ANGLES as f64).cos();
    let reach = |c: &[f64]| accel_m_s2 * c.iter().copied().fold(0.0, f64::max) / slack;
    for &idx in &order {
        let t = times_s[idx];
        while (k as f64) * h < t - 1e-9 && k < steps {
            let next = integrand((k + 1) as f64 * h);
            for a in 0..ANGLES {
                cumulative[a] += 0.5 * h * (previous[a] + next[a]);
            }
            previous = next;
            k += 1;
        }
        // t lies on the grid up to rounding when it is a recording time; otherwise add the partial
        // step (rectangle with the larger end value, an upper bound for the partial integral).
        let tail = t - k as f64 * h;
        if tail > 1e-9 {
            let next = integrand(t);
            let partial: Vec<f64> = cumulative
                .iter()
                .zip(previous.iter().zip(&next))
                .map(|(c, (p, q))| c + tail * p.max(*q))
                .collect();
            out[idx] = reach(&partial);
        } else {
            out[idx] = reach(&cumulative);
        }
    }
    out
}

/// B2 for one run without process noise: the control-only displacement perpendicular to the threat,
/// d⊥_i(t) = P⊥ (x_i(t) − [Φ_HCW(t) x_i(0)]_position), at every recording 0 < t ≤ headtime.
#[derive(Clone, Debug, PartialEq)]
pub struct EscapeBound {
    /// The headtime \[s\].
    pub headtime_s: f64,
    /// Per-axis cap \[m/s²\].
    pub accel_m_s2: f64,
    /// Largest ‖d⊥‖ over satellites at the headtime \[m\].
    pub at_headtime_m: f64,
    /// ½√m a t_h² \[m\].
    pub double_integrator_m: f64,
    /// Exact HCW in-plane reach at the headtime \[m\].
    pub hcw_reach_m: f64,
    /// Largest ‖d⊥‖ / (½√m a t²) over satellites and recordings 0 < t ≤ t_h, and its time \[s\].
    pub worst_double_integrator_ratio: (f64, f64),
    /// Largest (‖d⊥‖ − ½√m a t²) over satellites and recordings 0 < t ≤ t_h \[m\], and its time \[s\].
    pub worst_double_integrator_excess_m: (f64, f64),
    /// Largest (‖d⊥‖ − reach(t)) over satellites and recordings 0 < t ≤ t_h, and its time \[s\]
    /// (negative: inside the reachable set everywhere).
    pub worst_hcw_excess_m: (f64, f64),
}

/// Measures B2 on a run (which must be noise-free, on HCW, with a per-axis cap, a threat along a Hill
/// axis and a warning).
pub fn escape_bound(run: &CaseRun) -> Result<EscapeBound, ValidateError> {
    let label = &run.job.label;
    if run.job.process_noise {
        return Err(failed(format!(
            "{label}: B2 needs a run without process noise"
        )));
    }
    let hcw = run
        .hcw
        .ok_or_else(|| failed(format!("{label}: B2 needs the HCW model")))?;
    let threat = run
        .threat
        .as_ref()
        .ok_or_else(|| failed(format!("{label}: no threat")))?;
    let (a, kind) = run
        .common_cap()
        .ok_or_else(|| failed(format!("{label}: no common cap")))?;
    if kind != LimitKind::PerAxis {
        return Err(failed(format!("{label}: B2 is stated for a per-axis cap")));
    }
    let v = threat.velocity_hill_mps().normalize();
    if (v.z.abs() - 1.0).abs() > 1e-12 {
        return Err(failed(format!(
            "{label}: the HCW reach is computed in the orbital plane, for a threat along z"
        )));
    }
    let axes = perpendicular_axes(&v);
    let warning = run
        .warning_on_s
        .ok_or_else(|| failed(format!("{label}: no warning")))?;
    let headtime = run.headtime_s().unwrap_or(f64::NAN);
    let records: Vec<&Record> = run
        .records
        .iter()
        .filter(|r| r.time_s > warning + 1e-9 && r.time_s <= warning + headtime + 1e-6)
        .collect();
    if records.is_empty() {
        return Err(failed(format!("{label}: no recording before the headtime")));
    }
    let times: Vec<f64> = records.iter().map(|r| r.time_s - warning).collect();
    let reach = hcw_planar_reach_m(&hcw, a, &times);
    let mut worst_ratio = (f64::NEG_INFINITY, f64::NAN);
    let mut worst_di_excess = (f64::NEG_INFINITY, f64::NAN);
    let mut worst_excess = (f64::NEG_INFINITY, f64::NAN);
    let mut last = (0.0, 0.0);
    for (k, r) in records.iter().enumerate() {
        let t = r.time_s;
        let mut largest: f64 = 0.0;
        for (i, x) in r.positions_m.iter().enumerate() {
            let free = hcw.propagate(&run.initial[i], t);
            let d = x - Vector3::new(free[0], free[1], free[2]);
            let perp = d - d.dot(&v) * v;
            largest = largest.max(perp.norm());
        }
        let di = double_integrator_bound_m(a, times[k], axes);
        if largest / di > worst_ratio.0 {
            worst_ratio = (largest / di, t);
        }
        if largest - di > worst_di_excess.0 {
            worst_di_excess = (largest - di, t);
        }
        if largest - reach[k] > worst_excess.0 {
            worst_excess = (largest - reach[k], t);
        }
        last = (largest, reach[k]);
    }
    let t_last = times[times.len() - 1];
    if (t_last - headtime).abs() > 1e-6 {
        return Err(failed(format!(
            "{label}: the last recording before the headtime {headtime} s is at {t_last} s"
        )));
    }
    Ok(EscapeBound {
        headtime_s: headtime,
        accel_m_s2: a,
        at_headtime_m: last.0,
        double_integrator_m: double_integrator_bound_m(a, headtime, axes),
        hcw_reach_m: last.1,
        worst_double_integrator_ratio: worst_ratio,
        worst_double_integrator_excess_m: worst_di_excess,
        worst_hcw_excess_m: worst_excess,
    })
}

/// B1 on one capped run: the largest ledger over satellites against √3 a T (per-axis cap; a T for a
/// norm cap), and the largest per-axis ledger against a T, at every captured sample. Returns
/// (largest ∫‖u‖ / bound, largest ∫|u_k| / (a T)); `None` if the run is uncapped.
pub fn delta_v_cap_ratios(run: &CaseRun) -> Option<(f64, f64)> {
    let (a, kind) = run.common_cap()?;
    let factor = match kind {
        LimitKind::PerAxis => 3f64.sqrt(),
        LimitKind::Norm => 1.0,
    };
    let (mut norm, mut axis) = (0.0f64, 0.0f64);
    for s in &run.samples {
        let t = s.time_s;
        for (dv, axes) in s.delta_v_mps.iter().zip(&s.delta_v_axes_mps) {
            norm = norm.max(dv / (factor * a * t));
            for k in axes {
                axis = axis.max(k / (a * t));
            }
        }
    }
    Some((norm, axis))
}

// ---------------------------------------------------------------------------------------------------
// Checks (shared with the tests).
// ---------------------------------------------------------------------------------------------------

fn verdict(ok: bool) -> Verdict {
    if ok {
        Verdict::Reproduced
    } else {
        Verdict::Differs
    }
}

fn check(id: &str, outcome: &str, paper: String, ours: String, ok: bool) -> Check {
    Check {
        criterion: None,
        id: id.into(),
        outcome: outcome.into(),
        paper,
        ours,
        verdict: verdict(ok),
    }
}

/// A length or ratio with three significant decimals, in scientific notation when very small or large.
fn num(x: f64) -> String {
    if x != 0.0 && (x.abs() < 0.01 || x.abs() >= 1e4) {
        format!("{x:.2e}")
    } else {
        format!("{x:.3}")
    }
}

fn cm(m: f64) -> String {
    format!("{:.2} cm", 100.0 * m)
}

/// N1: the equilibrium-shaping coefficients of the law, for the rhombus (es-e1) and hexagon (es-e3a)
/// gather/avoid/dock fields and the Eq. 4 pair attractions (es-e2b-2). The field at the nodes,
/// recomputed here from the law's coefficients, the scenario's nodes and the paper's c = 3.214e-3 1/s,
/// d = 40 1/s, k₂ = k₃ = 6 m², vanishes to 1e-12 m/s; the coefficients equal the minimum-norm values
/// to their printed digits (rhombus: sides 42.5935, short diagonal 39.9998, long diagonal 8.0e-4 1/s;
/// hexagon: adjacent 47.7805, second neighbours 8.807e-4, opposite 2.911e-6 1/s), and Eq. 4 gives
/// a(6 m) = 0.546474 and a(6√3 m) = 4.0799e-4 1/s. The closed-form pairwise solution
/// b = (c + d e^(−δ²/k₃)) e^(δ²/k₂) is exact too (41.2966 and 2.1107e5 1/s for the rhombus).
pub fn check_n1() -> Result<Check, ValidateError> {
    const C: f64 = 3.214e-3;
    const D: f64 = 40.0;
    const K2: f64 = 6.0;
    const K3: f64 = 6.0;
    // Largest component of the gather + dock + avoid field at any node, pair coefficients b(i, j).
    fn residual(nodes: &[Vector3<f64>], b: &dyn Fn(usize, usize) -> f64) -> f64 {
        let n = nodes.len();
        let mut worst: f64 = 0.0;
        for i in 0..n {
            let mut v = Vector3::zeros();
            for t in 0..n {
                let y = nodes[i] - nodes[t];
                let d2 = y.norm_squared();
                v -= (C + D * (-d2 / K3).exp()) * y;
                if t != i {
                    v += b(i, t) * (-d2 / K2).exp() * y;
                }
            }
            worst = worst.max(v.amax());
        }
        worst
    }
    // A printed value is matched when the difference is at most half a unit of its last digit.
    let printed =
        |ours: f64, value: f64, decimals: i32| (ours - value).abs() <= 0.5 * 10f64.powi(-decimals);
    let mut ok = true;
    let mut ours = Vec::new();
    let mut worst_residual: f64 = 0.0;
    for name in ["es-e1", "es-e3a"] {
        let scenario = scenario_of(&CaseJob::full(name))?;
        let LawConfig::EquilibriumShaping(p) = scenario.file.law.clone() else {
            return Err(failed(format!("{name} does not run equilibrium-shaping")));
        };
        let nodes: Vec<Vector3<f64>> = scenario
            .prepare()
            .map_err(failed)?
            .satellites
            .iter()
            .map(|s| s.relative_state.position_m)
            .collect();
        let law = EquilibriumShaping::new(*p).map_err(failed)?;
        let same_nodes = law.tables().nodes_m.len() == nodes.len()
            && law
                .tables()
                .nodes_m
                .iter()
                .zip(&nodes)
                .all(|(a, b)| (a - b).norm() <= 1e-9);
        ok &= same_nodes;
        let solution = law
            .avoid_solution()
            .ok_or_else(|| failed(format!("{name}: the law has no avoid solution")))?;
        let b = |i: usize, j: usize| solution.coefficient_per_s(i, j);
        let r = residual(&nodes, &b);
        worst_residual = worst_residual.max(r);
        ok &= r <= 1e-12;
        let n = nodes.len();
        // Expected coefficient of a pair: (printed value, decimals), by the pair's class.
        let expected = |i: usize, j: usize| -> (f64, i32) {
            let delta = (nodes[i] - nodes[j]).norm();
            if n == 4 {
                match (i.min(j), i.max(j)) {
                    (0, 1) => (8.0e-4, 5),
                    (2, 3) => (39.9998, 4),
                    _ => (42.5935, 4),
                }
            } else if (delta - 6.0).abs() < 1e-6 {
                (47.7805, 4)
            } else if (delta - 12.0).abs() < 1e-6 {
                (2.911e-6, 9)
            } else {
                (8.807e-4, 7)
            }
        };
        // Per class (printed value): the range of the law's coefficients over the class's pairs.
        let mut classes: Vec<(f64, f64, f64)> = Vec::new();
        for i in 0..n {
            for j in i + 1..n {
                let (value, decimals) = expected(i, j);
                ok &= printed(b(i, j), value, decimals);
                match classes.iter_mut().find(|c| c.0 == value) {
                    Some(c) => {
                        c.1 = c.1.min(b(i, j));
                        c.2 = c.2.max(b(i, j));
                    }
                    None => classes.push((value, b(i, j), b(i, j))),
                }
            }
        }
        let classes: Vec<String> = classes
            .iter()
            .map(|(value, lo, hi)| {
                if lo == hi {
                    format!("{value}: {lo:.7e}")
                } else {
                    format!("{value}: {lo:.7e}…{hi:.7e}")
                }
            })
            .collect();
        let mut line = format!(
            "{name}: b (printed: ours) {} 1/s (rank {}, residual {r:.1e} m/s)",
            classes.join(", "),
            solution.rank
        );
        if n == 4 {
            let closed = |i: usize, j: usize| {
                let d2 = (nodes[i] - nodes[j]).norm_squared();
                (C + D * (-d2 / K3).exp()) * (d2 / K2).exp()
            };
            let rc = residual(&nodes, &closed);
            worst_residual = worst_residual.max(rc);
            ok &= rc <= 1e-12
                && printed(closed(0, 2), 41.2966, 4)
                && printed(closed(0, 1), 2.1107e5, -1);
            line.push_str(&format!(
                "; closed form {:.4} / {:.5e} 1/s, residual {rc:.1e} m/s",
                closed(0, 2),
                closed(0, 1)
            ));
        }
        ours.push(line);
    }
    let scenario = scenario_of(&CaseJob::full("es-e2b-2"))?;
    let LawConfig::EquilibriumShaping(p) = scenario.file.law else {
        return Err(failed("es-e2b-2 does not run equilibrium-shaping"));
    };
    let a6 = pair_attraction_per_s(6.0, p.pair_b_per_s, p.pair_c_m2);
    let a10 = pair_attraction_per_s(6.0 * 3f64.sqrt(), p.pair_b_per_s, p.pair_c_m2);
    ok &= printed(a6, 0.546474, 6) && printed(a10, 4.0799e-4, 8);
    ours.push(format!(
        "Eq. 4: a(6 m) = {a6:.6}, a(10.392 m) = {a10:.4e} 1/s"
    ));
    Ok(check(
        "N1",
        "equilibrium shaping: field at the nodes ≤ 1e-12 m/s from the law's coefficients (recomputed \
         here with the paper's c, d, k₂, k₃); coefficients equal to the minimum-norm and Eq. 4 values to \
         their printed digits; the closed form exact as well",
        "rhombus b 42.5935 / 39.9998 / 8.0e-4; hexagon 47.7805 / 8.807e-4 / 2.911e-6; Eq. 4 a 0.546474, \
         4.0799e-4 1/s (minimum-norm ES of Eqs. 13–15; closed form 41.2966 / 2.1107e5)"
            .into(),
        format!("{}; worst residual {worst_residual:.1e} m/s", ours.join("; ")),
        ok,
    ))
}

/// What E0 (paper Fig. 2) shows after the threat has passed.
#[derive(Clone, Debug, PartialEq)]
pub struct PassedThreat {
    /// Largest formation error over the recordings with the threat more than [`N2_PAST_M`] past
    /// satellite 0's node \[m\] (NaN if there is none).
    pub max_error_m: f64,
    /// Number of such recordings.
    pub recordings: usize,
    /// Formation error at the end of the scenario's own run (40 s: the threat exactly 10 m past) \[m\].
    pub error_at_40_s_m: f64,
    /// At the last recording: smallest (p_T − x_i)·v̂_T over satellites, i.e. how far the threat is past
    /// the satellite it is least past (negative: that satellite is still ahead of the threat) \[m\].
    pub threat_past_satellites_m: f64,
    /// Number of satellites within the physical sensing radius of the threat at the last recording.
    pub within_sensing_at_end: usize,
    /// First recording at which satellite 0 is more than 1 cm from its node \[s\].
    pub reaction_s: f64,
    /// When the threat comes within 10 m of satellite 0's node \[s\].
    pub within_10_m_s: f64,
}

/// N2's measurement on the E0 run continued to [`N2_EXTENDED_S`].
pub fn passed_threat(e0: &CaseRun) -> Result<PassedThreat, ValidateError> {
    let threat = e0
        .threat
        .as_ref()
        .ok_or_else(|| failed("E0 has no threat"))?;
    let v = threat.velocity_hill_mps().normalize();
    let node = e0.nodes_m[0];
    let past = |t: f64| (threat.position_hill_m(t) - node).dot(&v);
    let errors: Vec<f64> = e0
        .records
        .iter()
        .filter(|r| past(r.time_s) > N2_PAST_M)
        .map(|r| formation_error_m(&r.positions_m, &e0.nodes_m))
        .collect();
    let at_40 = e0
        .records
        .iter()
        .find(|r| (past(r.time_s) - N2_PAST_M).abs() < 1e-6)
        .map_or(f64::NAN, |r| formation_error_m(&r.positions_m, &e0.nodes_m));
    let last = e0
        .records
        .last()
        .ok_or_else(|| failed("E0 has no record"))?;
    let p = threat.position_hill_m(last.time_s);
    let threat_past_satellites_m = last
        .positions_m
        .iter()
        .map(|x| (p - x).dot(&v))
        .fold(f64::INFINITY, f64::min);
    let within_sensing_at_end = last
        .positions_m
        .iter()
        .filter(|x| (*x - p).norm() <= e0.law.physical_sensing_radius_m)
        .count();
    let reaction_s = e0
        .records
        .iter()
        .find(|r| (r.positions_m[0] - node).norm() > 0.01)
        .map_or(f64::NAN, |r| r.time_s);
    let speed = threat.velocity_hill_mps().norm();
    Ok(PassedThreat {
        max_error_m: if errors.is_empty() {
            f64::NAN
        } else {
            errors.iter().copied().fold(0.0, f64::max)
        },
        recordings: errors.len(),
        error_at_40_s_m: at_40,
        threat_past_satellites_m,
        within_sensing_at_end,
        reaction_s,
        within_10_m_s: closest_time_s(threat, &node) - 10.0 / speed,
    })
}

/// N2: E0 (kinematic, paper Fig. 2) continued to 60 s; formation error ≤ 1 mm at every recording with
/// the threat more than 10 m past satellite 0's node.
pub fn check_n2(e0_extended: &CaseRun) -> Result<Check, ValidateError> {
    let m = passed_threat(e0_extended)?;
    Ok(check(
        "N2",
        "E0 (kinematic, Eq. 1 + parallel threat term, 10 m physical sensing) continued to 60 s: \
         formation error ≤ 1 mm at every recording with the threat > 10 m past satellite 0's node",
        "flee when the threat is within 10 m (about 10 s to react); rhombus restored to ≤ 1 mm (Fig. 2)"
            .into(),
        format!(
            "max {:.3e} m over {} recordings (40 s: {:.3e} m); threat within 10 m of node 0 at {:.1} s, \
             satellite 0 > 1 cm off its node from {:.1} s; at {:.0} s the threat is {:.2} m past the \
             satellite it is least past",
            m.max_error_m,
            m.recordings,
            m.error_at_40_s_m,
            m.within_10_m_s,
            m.reaction_s,
            e0_extended.duration_s,
            m.threat_past_satellites_m
        ),
        m.recordings > 0 && m.max_error_m <= N2_FORMATION_ERROR_M,
    ))
}

/// N3: Table 1 sims 2 and 4 (threat 1 vs 1000 m/s, headtime 200 s): average misses within 10 %.
pub fn check_n3(sim2: &CaseRun, sim4: &CaseRun) -> Check {
    let (m2, m4) = (sim2.average_miss_m(), sim4.average_miss_m());
    let rel = (m4 - m2).abs() / m2;
    check(
        "N3",
        "miss depends on the headtime, not the threat speed: E2b sims 2 (1 m/s) and 4 (1000 m/s) average \
         miss within 10 % of sim 2's",
        "45 m and 45 m (Table 1)".into(),
        format!(
            "{m2:.2} m and {m4:.2} m ({:.1} %)",
            100.0 * rel
        ),
        rel <= N3_RELATIVE,
    )
}

/// N4: Table 1 sims 2 → 3 (500 s → 700 s): the final formation error decreases.
pub fn check_n4(sim2: &CaseRun, sim3: &CaseRun) -> Check {
    let (e2, e3) = (
        sim2.final_formation_error_m(),
        sim3.final_formation_error_m(),
    );
    check(
        "N4",
        "longer run ⇒ smaller formation error: E2b sim 3 (700 s) < sim 2 (500 s)",
        "45 cm → 29 cm (Table 1)".into(),
        format!("{} → {}", cm(e2), cm(e3)),
        e3 < e2,
    )
}

/// N5 (reported): Table 1 sim 2's average miss, 45 m ± 25 %.
pub fn check_n5(sim2: &CaseRun) -> Check {
    let m = sim2.average_miss_m();
    check(
        "N5",
        "E2b sim 2 (headtime 200 s, diagonal perpendicular escape) average miss within 45 m ± 25 % \
         (reported, not asserted by the tests)",
        "45 m (Table 1)".into(),
        format!("{m:.2} m ({:+.1} %)", 100.0 * (m / N5_PAPER_MISS_M - 1.0)),
        (m / N5_PAPER_MISS_M - 1.0).abs() <= N5_RELATIVE,
    )
}

/// N6: perpendicular ≫ parallel: E2b sim 2 / E2a (h 200) average miss ≥ 3 and E3a / E3b minimum miss
/// ≥ 3.
pub fn check_n6(e2b2: &CaseRun, e2a: &CaseRun, e3a: &CaseRun, e3b: &CaseRun) -> Check {
    let r2 = e2b2.average_miss_m() / e2a.average_miss_m();
    let r3 = e3a.minimum_miss_m() / e3b.minimum_miss_m();
    check(
        "N6",
        "perpendicular ≫ parallel miss: E2b-2 / E2a-h200 average miss ≥ 3; E3a / E3b minimum miss ≥ 3",
        "45 / 7 m (S2), 62 / 9 m (S3) (Table 2)".into(),
        format!(
            "S2: {} / {} m = {}; S3: {} / {} m = {}",
            num(e2b2.average_miss_m()),
            num(e2a.average_miss_m()),
            num(r2),
            num(e3a.minimum_miss_m()),
            num(e3b.minimum_miss_m()),
            num(r3)
        ),
        r2 >= N6_RATIO && r3 >= N6_RATIO,
    )
}

/// N7: S3 keeps the centroid: E3a and E3b final centroid displacement ≤ 0.1 m.
pub fn check_n7(e3a: &CaseRun, e3b: &CaseRun) -> Check {
    let (a, b) = (e3a.final_centroid_m(), e3b.final_centroid_m());
    check(
        "N7",
        "S3 keeps the centroid: E3a (430 s) and E3b (1000 s) final centroid displacement ≤ 0.1 m",
        "same place (paper §4.3)".into(),
        format!("{a:.2e} m, {b:.2e} m"),
        a <= N7_CENTROID_M && b <= N7_CENTROID_M,
    )
}

/// N8: S2 moves the centroid: E2a-h200 and E2b-2 final centroid displacement > 50 m.
pub fn check_n8(e2a: &CaseRun, e2b2: &CaseRun) -> Check {
    let (a, b) = (e2a.final_centroid_m(), e2b2.final_centroid_m());
    check(
        "N8",
        "S2 moves the centroid: E2a-h200 (1000 s) and E2b-2 (500 s) final centroid displacement > 50 m",
        "≈ 1 km (E2a, Fig. 6)".into(),
        format!("{a:.1} m, {b:.1} m"),
        a > N8_CENTROID_M && b > N8_CENTROID_M,
    )
}

/// N9 (reported): one strategy's mean Δv against Table 2, within a factor 2.5.
pub fn check_n9(strategy: &str, runs: &[(&str, f64)], paper_dv: f64) -> Check {
    let within = |x: f64| x / paper_dv <= N9_FACTOR && paper_dv / x <= N9_FACTOR;
    let ok = runs.iter().all(|(_, dv)| within(*dv));
    check(
        &format!("N9 {strategy}"),
        &format!(
            "{strategy} mean Δv within a factor 2.5 of Table 2 (reported, not asserted by the tests)"
        ),
        format!("{paper_dv} m/s (Table 2)"),
        runs.iter()
            .map(|(name, dv)| format!("{name} {dv:.3} m/s (×{:.2})", dv / paper_dv))
            .collect::<Vec<_>>()
            .join("; "),
        ok,
    )
}

/// N10: the electric cap (14 µm/s²) cannot buy more than 1 m of miss: average miss − node offset
/// ≤ 1 m (es-e2b-2-electric).
pub fn check_n10(electric: &CaseRun) -> Result<Check, ValidateError> {
    let threat = electric
        .threat
        .as_ref()
        .ok_or_else(|| failed("es-e2b-2-electric has no threat"))?;
    let offset = node_offset_m(threat, &electric.nodes_m);
    let m = electric.average_miss_m();
    Ok(check(
        "N10",
        "electric cap 14 µm/s² (E2b sim 2): average miss − node offset ≤ 1 m (node offset: the threat \
         line's distance to each node, averaged)",
        "electric propulsion cannot buy more than about 1 m (paper §4.2; ½·14e-6·300² = 0.6 m)".into(),
        format!(
            "{m:.3} − {offset:.3} = {:.3} m",
            m - offset
        ),
        m - offset <= N10_EXCESS_M,
    ))
}

/// N11 a: S1 satellites on the 20 m sphere at rest at the end of the scatter phase (3000 s).
pub fn check_n11_sphere(runs: &[&CaseRun]) -> Result<Check, ValidateError> {
    let centre = Vector3::from(N11_SPHERE_CENTRE_M);
    let mut ok = true;
    let mut ours = Vec::new();
    for run in runs {
        let s = run.at(N11_SCATTER_END_S).ok_or_else(|| {
            failed(format!(
                "{}: no sample at {N11_SCATTER_END_S} s",
                run.job.label
            ))
        })?;
        let radii: Vec<f64> = s.positions_m.iter().map(|x| (x - centre).norm()).collect();
        let speeds: Vec<f64> = s.velocities_mps.iter().map(|v| v.norm()).collect();
        let (rmin, rmax) = (
            minimum(&radii),
            radii.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        );
        let vmax = speeds.iter().copied().fold(0.0, f64::max);
        ok &= (rmin - N11_SPHERE_RADIUS_M).abs() <= N11_BAND_M
            && (rmax - N11_SPHERE_RADIUS_M).abs() <= N11_BAND_M
            && vmax <= N11_REST_MPS;
        ours.push(format!(
            "{}: radii {rmin:.3}–{rmax:.3} m, max speed {:.2e} m/s",
            run.job.builtin, vmax
        ));
    }
    Ok(check(
        "N11 sphere",
        "S1 (E1 uncapped and capped) at 3000 s, before the all-clear: every satellite 20 ± 0.5 m from \
         the sphere centre, speed ≤ 1 mm/s (reported, not asserted by the tests)",
        "satellites stop on the 20 m sphere (Figs. 3–4)".into(),
        ours.join("; "),
        ok,
    ))
}

/// N11 b: S1 Δv of the scatter (0–3000 s) and gather (3000–4000 s) phases against 1.8 and 0.5 m/s,
/// within a factor 2 (capped run).
pub fn check_n11_delta_v(capped: &CaseRun) -> Result<Check, ValidateError> {
    let s = capped
        .at(N11_SCATTER_END_S)
        .ok_or_else(|| failed("es-e1-capped: no sample at 3000 s"))?;
    let scatter = mean(&s.delta_v_mps);
    let gather = mean(&capped.end().delta_v_mps) - scatter;
    let within = |x: f64, p: f64| x / p <= N11_FACTOR && p / x <= N11_FACTOR;
    Ok(check(
        "N11 Δv",
        "S1 capped (es-e1-capped): mean Δv of the scatter (0–3000 s) and gather (3000–4000 s) phases \
         within a factor 2 of the paper's (reported, not asserted by the tests)",
        "1.8 + 0.5 m/s (Table 2)".into(),
        format!("{scatter:.3} + {gather:.3} m/s"),
        within(scatter, paper::S1_SCATTER_DV) && within(gather, paper::S1_GATHER_DV),
    ))
}

/// B1: on every capped run, ∫‖u‖dt ≤ √3 a T and ∫|u_k|dt ≤ a T for every satellite at every sample.
pub fn check_b1(runs: &[&CaseRun]) -> Check {
    let mut ok = true;
    let mut worst = (0.0f64, 0.0f64, String::new());
    let mut count = 0;
    for run in runs {
        if let Some((norm, axis)) = delta_v_cap_ratios(run) {
            count += 1;
            ok &= norm <= 1.0 + B1_RELATIVE && axis <= 1.0 + B1_RELATIVE;
            if norm > worst.0 {
                worst = (norm, axis.max(worst.1), run.job.label.clone());
            } else {
                worst.1 = worst.1.max(axis);
            }
        }
    }
    check(
        "B1",
        "per-axis cap ⇒ ∫‖u‖dt ≤ √3 a_max T and ∫|u_k|dt ≤ a_max T, every satellite of every capped run \
         (rounding 1e-9)",
        "bound (analytic)".into(),
        format!(
            "{count} runs; largest ∫‖u‖dt / (√3 a T) = {:.4} ({}), largest ∫|u_k|dt / (a T) = {:.4}",
            worst.0, worst.2, worst.1
        ),
        ok && count > 0,
    )
}

/// B2: for every noise-free perpendicular-escape run, the control-only displacement perpendicular to
/// the threat at every recording up to the headtime ≤ ½√2 a t² (the reconstruction's double-integrator
/// bound; the brief's criterion, kept although HCW does not obey it exactly, see [`check_b2_hcw`]).
pub fn check_b2(bounds: &[(&str, EscapeBound)]) -> Check {
    let ok = bounds
        .iter()
        .all(|(_, b)| b.worst_double_integrator_excess_m.0 <= B2_TOLERANCE_M);
    check(
        "B2",
        "perpendicular escape from rest, no process noise: control-only displacement ⊥ threat, \
         x(t) − Φ_HCW(t) x(0), ≤ ½√2 a_max t² at every recording t ≤ headtime (tolerance 1 mm)",
        "½√2 a t_h²: 39.6 m at 200 s, 89.1 m at 300 s, 247.5 m at 500 s (double integrator)".into(),
        bounds
            .iter()
            .map(|(name, b)| {
                format!(
                    "{name}: {:.3} m at t_h = {:.0} s vs {:.3} m (largest ratio {:.5} at {:.0} s, \
                     largest excess {:+.4} m at {:.0} s)",
                    b.at_headtime_m,
                    b.headtime_s,
                    b.double_integrator_m,
                    b.worst_double_integrator_ratio.0,
                    b.worst_double_integrator_ratio.1,
                    b.worst_double_integrator_excess_m.0,
                    b.worst_double_integrator_excess_m.1
                )
            })
            .collect::<Vec<_>>()
            .join("; "),
        ok,
    )
}

/// B2 (HCW): the same displacements against the exact in-plane HCW reach [`hcw_planar_reach_m`].
pub fn check_b2_hcw(bounds: &[(&str, EscapeBound)]) -> Check {
    let ok = bounds
        .iter()
        .all(|(_, b)| b.worst_hcw_excess_m.0 <= B2_TOLERANCE_M);
    check(
        "B2 HCW",
        "same displacements ≤ the exact HCW reach of |u_x|, |u_y| ≤ a_max at every recording t ≤ headtime \
         (tolerance 1 mm): the double-integrator bound ignores the Coriolis coupling",
        "exact HCW reach of the per-axis cap at t_h (computed here from Φ_HCW; values in ours)".into(),
        bounds
            .iter()
            .map(|(name, b)| {
                format!(
                    "{name}: {:.3} m vs reach {:.3} m at t_h (largest excess {:+.4} m at {:.0} s)",
                    b.at_headtime_m,
                    b.hcw_reach_m,
                    b.worst_hcw_excess_m.0,
                    b.worst_hcw_excess_m.1
                )
            })
            .collect::<Vec<_>>()
            .join("; "),
        ok,
    )
}

// ---------------------------------------------------------------------------------------------------
// The report.
// ---------------------------------------------------------------------------------------------------

/// The 13 built-in cases.
pub const CASES: [&str; 13] = [
    "es-e0",
    "es-e1",
    "es-e1-capped",
    "es-e2a-h200",
    "es-e2a-h2000",
    "es-e2b-1",
    "es-e2b-2",
    "es-e2b-3",
    "es-e2b-4",
    "es-e2b-2-electric",
    "es-e3a",
    "es-e3b",
    "es-e4",
];

/// The paper's numbers for one case (text, as printed; "–" where the paper gives none).
struct PaperCase {
    case: &'static str,
    what: &'static str,
    length: &'static str,
    delta_v: &'static str,
    min_miss: &'static str,
    mean_miss: &'static str,
    formation_error: &'static str,
    centroid: &'static str,
}

const PAPER: [PaperCase; 13] = [
    PaperCase {
        case: "es-e0",
        what: "Fig. 2, kinematic, Eq. 1 + parallel",
        length: "until 10 m past",
        delta_v: "–",
        min_miss: "–",
        mean_miss: "–",
        formation_error: "≤ 1 mm after",
        centroid: "–",
    },
    PaperCase {
        case: "es-e1",
        what: "S1 scatter + gather, uncapped (Fig. 3)",
        length: "3000 + 1000",
        delta_v: "–",
        min_miss: "n/a (sphere radius 20)",
        mean_miss: "–",
        formation_error: "–",
        centroid: "–",
    },
    PaperCase {
        case: "es-e1-capped",
        what: "S1 scatter + gather, capped (Fig. 4, Table 2)",
        length: "3000 + 1000",
        delta_v: "1.8 + 0.5",
        min_miss: "n/a (sphere radius 20)",
        mean_miss: "–",
        formation_error: "–",
        centroid: "–",
    },
    PaperCase {
        case: "es-e2a-h200",
        what: "S2 parallel, headtime 200 s (Table 2)",
        length: "900",
        delta_v: "1.6",
        min_miss: "7",
        mean_miss: "–",
        formation_error: "8 cm",
        centroid: "≈ 1 km",
    },
    PaperCase {
        case: "es-e2a-h2000",
        what: "S2 parallel, headtime 2000 s (text)",
        length: "–",
        delta_v: "1.6",
        min_miss: "7",
        mean_miss: "–",
        formation_error: "8 cm",
        centroid: "≈ 1 km",
    },
    PaperCase {
        case: "es-e2b-1",
        what: "S2 perpendicular, Table 1 sim 1 (h 50 s)",
        length: "200",
        delta_v: "–",
        min_miss: "–",
        mean_miss: "4",
        formation_error: "4 cm",
        centroid: "–",
    },
    PaperCase {
        case: "es-e2b-2",
        what: "S2 perpendicular, Table 1 sim 2 (h 200 s)",
        length: "500",
        delta_v: "–",
        min_miss: "–",
        mean_miss: "45",
        formation_error: "45 cm",
        centroid: "–",
    },
    PaperCase {
        case: "es-e2b-3",
        what: "S2 perpendicular, Table 1 sim 3; Table 2 S2 perp.",
        length: "700",
        delta_v: "0.4",
        min_miss: "45",
        mean_miss: "45",
        formation_error: "29 cm",
        centroid: "–",
    },
    PaperCase {
        case: "es-e2b-4",
        what: "S2 perpendicular, Table 1 sim 4 (1000 m/s)",
        length: "700",
        delta_v: "0.4 (Table 2)",
        min_miss: "–",
        mean_miss: "45",
        formation_error: "22 cm",
        centroid: "–",
    },
    PaperCase {
        case: "es-e2b-2-electric",
        what: "S2 perpendicular, electric cap (§4.2)",
        length: "–",
        delta_v: "–",
        min_miss: "–",
        mean_miss: "≤ node offset + 1",
        formation_error: "–",
        centroid: "–",
    },
    PaperCase {
        case: "es-e3a",
        what: "S3 perpendicular (hexagon, Figs. 8–9)",
        length: "430",
        delta_v: "0.86",
        min_miss: "62",
        mean_miss: "–",
        formation_error: "–",
        centroid: "same place",
    },
    PaperCase {
        case: "es-e3b",
        what: "S3 parallel (hexagon, Fig. 10)",
        length: "1000",
        delta_v: "1.3",
        min_miss: "9",
        mean_miss: "–",
        formation_error: "–",
        centroid: "same place",
    },
    PaperCase {
        case: "es-e4",
        what: "S4 mix (Fig. 11)",
        length: "2000",
        delta_v: "0.9",
        min_miss: "33",
        mean_miss: "–",
        formation_error: "–",
        centroid: "–",
    },
];

/// es-e2b-3 (Table 1 sim 3) is also sampled at the headtime, the all-clear and 500 s (N4, N9
/// diagnostics) \[s\].
pub const E2B3_SAMPLES_S: [f64; 3] = [200.0, 400.0, 500.0];

/// The standoff of a parallel escape: a satellite on the threat's line flees along the threat's motion
/// at A e^(−d²/K), at least the threat's speed V while d ≤ √(K ln(A/V)); in the kinematic model it
/// therefore rides ahead of the threat at about that distance instead of letting it pass \[m\].
pub fn parallel_standoff_m(scale_mps: f64, width_m2: f64, speed_mps: f64) -> f64 {
    (width_m2 * (scale_mps / speed_mps).ln()).max(0.0).sqrt()
}

/// Peak inward speed of the dock term around a node, d √(k₃/2) e^(−1/2), at distance √(k₃/2) \[m/s\].
pub fn dock_peak_mps(dock_per_s: f64, dock_range_m2: f64) -> f64 {
    dock_per_s * (0.5 * dock_range_m2).sqrt() * (-0.5f64).exp()
}

/// Label of [`e0_continued_job`].
pub const E0_CONTINUED: &str = "es-e0 continued to 60 s";
/// Label of [`e3a_continued_job`].
pub const E3A_CONTINUED: &str = "es-e3a continued to 1000 s";
/// Label of [`axis_escape_job`].
pub const AXIS_ESCAPE: &str = "es-e2b-2 with the −y escape";

/// E0 continued to [`N2_EXTENDED_S`] (N2).
pub fn e0_continued_job() -> CaseJob {
    CaseJob {
        label: E0_CONTINUED.into(),
        ..CaseJob::until("es-e0", N2_EXTENDED_S)
    }
}

/// E3a continued to 1000 s: the threat arrives at 500 s, after the paper's 430 s window.
pub fn e3a_continued_job() -> CaseJob {
    CaseJob {
        label: E3A_CONTINUED.into(),
        ..CaseJob::until("es-e3a", 1000.0)
    }
}

/// E2b sim 2 with an axis-aligned common escape (−y), one saturated axis instead of two.
pub fn axis_escape_job() -> CaseJob {
    CaseJob {
        label: AXIS_ESCAPE.into(),
        escape_direction_hill: Some([0.0, -1.0, 0.0]),
        ..CaseJob::full("es-e2b-2")
    }
}

/// Every run of the report: the 13 cases at full length (es-e1 and es-e1-capped also sampled at the
/// all-clear, 3000 s), E0 continued for N2, E3a continued to 1000 s (the threat arrives at 500 s, after
/// the paper's 430 s window), E2b sim 2 with an axis-aligned escape (−y), and the noise-free runs of B2
/// to their headtimes. Longest first, for load balance.
pub fn report_jobs() -> Vec<CaseJob> {
    let e3a_long = e3a_continued_job();
    let e0_long = e0_continued_job();
    let axis = axis_escape_job();
    vec![
        CaseJob::full("es-e1").with_samples(&[N11_SCATTER_END_S]),
        CaseJob::full("es-e1-capped").with_samples(&[N11_SCATTER_END_S]),
        CaseJob::full("es-e2a-h2000"),
        CaseJob::full("es-e4"),
        CaseJob::full("es-e3b"),
        e3a_long,
        CaseJob::full("es-e2a-h200"),
        CaseJob::noise_free_until("es-e3a", 500.0),
        CaseJob::full("es-e3a"),
        CaseJob::full("es-e2b-3").with_samples(&E2B3_SAMPLES_S),
        CaseJob::full("es-e2b-4"),
        CaseJob::full("es-e2b-2"),
        CaseJob::full("es-e2b-2-electric"),
        axis,
        CaseJob::noise_free_until("es-e4", 300.0),
        CaseJob::full("es-e2b-1"),
        CaseJob::noise_free_until("es-e2b-2", 200.0),
        CaseJob::noise_free_until("es-e2b-4", 200.0),
        CaseJob::noise_free_until("es-e2b-2-electric", 200.0),
        CaseJob::noise_free_until("es-e2b-1", 50.0),
        e0_long,
        CaseJob::full("es-e0"),
    ]
}

/// The noise-free B2 runs among `runs`, measured.
pub fn escape_bounds(runs: &[CaseRun]) -> Result<Vec<(&str, EscapeBound)>, ValidateError> {
    runs.iter()
        .filter(|r| !r.job.process_noise)
        .map(|r| Ok((r.job.builtin, escape_bound(r)?)))
        .collect()
}

/// The run labelled `label` among `runs`.
pub fn find<'a>(runs: &'a [CaseRun], label: &str) -> Result<&'a CaseRun, ValidateError> {
    runs.iter()
        .find(|r| r.job.label == label)
        .ok_or_else(|| failed(format!("no run labelled {label}")))
}

/// The full report (every run at full length).
pub fn report() -> Result<Report, ValidateError> {
    let jobs = report_jobs();
    let runs = run_cases(&jobs)?;
    let get = |label: &str| find(&runs, label);
    let mut checks = Vec::new();
    let mut notes = Vec::new();

    checks.push(check_n1()?);
    checks.push(check_n2(get(E0_CONTINUED)?)?);
    let (e2b1, e2b2, e2b3, e2b4) = (
        get("es-e2b-1")?,
        get("es-e2b-2")?,
        get("es-e2b-3")?,
        get("es-e2b-4")?,
    );
    let (e2a, e3a, e3b, e4) = (
        get("es-e2a-h200")?,
        get("es-e3a")?,
        get("es-e3b")?,
        get("es-e4")?,
    );
    let (e1, e1c) = (get("es-e1")?, get("es-e1-capped")?);
    checks.push(check_n3(e2b2, e2b4));
    checks.push(check_n4(e2b2, e2b3));
    checks.push(check_n5(e2b2));
    checks.push(check_n6(e2b2, e2a, e3a, e3b));
    checks.push(check_n7(e3a, e3b));
    checks.push(check_n8(e2a, e2b2));
    let dv = |r: &CaseRun| CaseRun::mean_delta_v_mps(r.end());
    let s1 = e1c
        .at(N11_SCATTER_END_S)
        .ok_or_else(|| failed("es-e1-capped: no 3000 s sample"))?;
    let s1_scatter = mean(&s1.delta_v_mps);
    checks.push(check_n9(
        "S1 scatter",
        &[("es-e1-capped 0–3000 s", s1_scatter)],
        paper::S1_SCATTER_DV,
    ));
    checks.push(check_n9(
        "S1 gather",
        &[("es-e1-capped 3000–4000 s", dv(e1c) - s1_scatter)],
        paper::S1_GATHER_DV,
    ));
    checks.push(check_n9(
        "S2 parallel",
        &[("es-e2a-h200", dv(e2a))],
        paper::S2_PARALLEL_DV,
    ));
    checks.push(check_n9(
        "S2 perpendicular",
        &[("es-e2b-3", dv(e2b3)), ("es-e2b-4", dv(e2b4))],
        paper::S2_PERPENDICULAR_DV,
    ));
    checks.push(check_n9(
        "S3 parallel",
        &[("es-e3b", dv(e3b))],
        paper::S3_PARALLEL_DV,
    ));
    checks.push(check_n9(
        "S3 perpendicular",
        &[("es-e3a", dv(e3a))],
        paper::S3_PERPENDICULAR_DV,
    ));
    checks.push(check_n9("S4 mix", &[("es-e4", dv(e4))], paper::S4_DV));
    checks.push(check_n10(get("es-e2b-2-electric")?)?);
    checks.push(check_n11_sphere(&[e1, e1c])?);
    checks.push(check_n11_delta_v(e1c)?);
    let all: Vec<&CaseRun> = runs.iter().collect();
    checks.push(check_b1(&all));
    let bounds = escape_bounds(&runs)?;
    checks.push(check_b2(&bounds));
    checks.push(check_b2_hcw(&bounds));

    // Strategy comparison (Table 2 form).
    let mut rows = Vec::new();
    for p in &PAPER {
        let r = get(p.case)?;
        let e = r.end();
        let has_threat = e.miss_m.iter().all(|m| m.is_finite());
        let fmt_miss = |m: f64| {
            if has_threat {
                num(m)
            } else {
                "–".into()
            }
        };
        let delta_v = if r.hcw.is_some() {
            match r.at(N11_SCATTER_END_S) {
                Some(s) => {
                    let a = mean(&s.delta_v_mps);
                    format!("{a:.3} + {:.3}", dv(r) - a)
                }
                None => format!("{:.3}", dv(r)),
            }
        } else {
            "– (kinematic)".into()
        };
        rows.push(vec![
            p.case.to_string(),
            p.what.to_string(),
            format!("{:.0} / {}", r.duration_s, p.length),
            format!("{delta_v} / {}", p.delta_v),
            format!("{} / {}", fmt_miss(r.minimum_miss_m()), p.min_miss),
            format!("{} / {}", fmt_miss(r.average_miss_m()), p.mean_miss),
            format!(
                "{} / {}",
                cm(r.final_formation_error_m()),
                p.formation_error
            ),
            format!("{:.3} m / {}", r.final_centroid_m(), p.centroid),
        ]);
    }
    let strategy_table = Table {
        title: "Strategy comparison (paper Table 2 form; each cell ours / paper)".into(),
        header: [
            "case",
            "paper item",
            "run length (s)",
            "mean Δv (m/s)",
            "minimum miss (m)",
            "average miss (m)",
            "final formation error",
            "final centroid displacement",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect(),
        rows,
    };

    // The reconstruction's check list cases, ours vs the paper vs an earlier prototype.
    let axis = get(AXIS_ESCAPE)?;
    let e3a_long = get(E3A_CONTINUED)?;
    let row = |case: &str, paper: &str, ours: String, prototype: &str| {
        vec![
            case.to_string(),
            paper.to_string(),
            ours,
            prototype.to_string(),
        ]
    };
    let cases_table = Table {
        title: "Cases of the reconstruction (ours vs paper; the earlier prototype: numpy, 0.5 s hold with \
                backward-difference feed-forward, whose Δv are inflated by a sampling limit cycle and are \
                not references)"
            .into(),
        header: ["case", "paper", "ours", "earlier prototype"]
            .iter()
            .map(|s| s.to_string())
            .collect(),
        rows: vec![
            row(
                "E2b sim 1 (h 50 s), diagonal",
                "avg miss 4 m, error 4 cm",
                format!(
                    "Δv {:.3}, avg miss {:.2} m, error {}",
                    dv(e2b1),
                    e2b1.average_miss_m(),
                    cm(e2b1.final_formation_error_m())
                ),
                "Δv 0.36, avg miss 6.1 m, error 0.7 cm",
            ),
            row(
                "E2b sim 2 (h 200 s), −y escape",
                "avg miss 45 m",
                format!(
                    "avg miss {:.2} m, Δv {:.3}",
                    axis.average_miss_m(),
                    dv(axis)
                ),
                "avg miss 27 m, Δv 0.98",
            ),
            row(
                "E2b sim 2 (h 200 s), diagonal (1, 1, 0)/√2",
                "avg miss 45 m, error 45 cm",
                format!(
                    "avg miss {:.2} m, Δv {:.3}, error {}",
                    e2b2.average_miss_m(),
                    dv(e2b2),
                    cm(e2b2.final_formation_error_m())
                ),
                "avg miss 41 m, Δv 1.01, error 67 cm",
            ),
            row(
                "E2b sim 4 (V 1000 m/s), diagonal",
                "avg miss 45 m",
                format!(
                    "avg miss {:.2} m, Δv {:.3}",
                    e2b4.average_miss_m(),
                    dv(e2b4)
                ),
                "avg miss 44 m, Δv 1.45",
            ),
            row(
                "E2a (h 200 s, V 1000 m/s), parallel",
                "min miss 7 m, Δv 1.6",
                format!(
                    "min miss {} m, avg {:.2} m, Δv {:.3}",
                    num(e2a.minimum_miss_m()),
                    e2a.average_miss_m(),
                    dv(e2a)
                ),
                "min miss 0.02–0.1 m, avg 5.6 m, Δv 2.1",
            ),
            row(
                "E3a (430 s), perpendicular radial",
                "min CPA 62 m, Δv 0.86",
                format!(
                    "min CPA {:.2} m in 430 s (continued to 1000 s: {} m), Δv {:.3}",
                    e3a.minimum_miss_m(),
                    num(e3a_long.minimum_miss_m()),
                    dv(e3a)
                ),
                "min CPA 70 m (430 s window), Δv 1.03; 1000 s replay ≈ 0",
            ),
            row(
                "E3b (1000 s), parallel",
                "min CPA 9 m, Δv 1.3",
                format!(
                    "min CPA {} m, Δv {:.3}",
                    num(e3b.minimum_miss_m()),
                    dv(e3b)
                ),
                "min CPA ≈ 0, Δv 2.4",
            ),
            row(
                "E4 (2000 s), mix",
                "min CPA 33 m, Δv 0.9",
                format!(
                    "min CPA {:.2} m, Δv {:.3}, final error {}, centroid {:.3} m",
                    e4.minimum_miss_m(),
                    dv(e4),
                    cm(e4.final_formation_error_m()),
                    e4.final_centroid_m()
                ),
                "min CPA 55–78 m, Δv 3.7–4.0, not re-formed at 2000 s",
            ),
        ],
    };

    // Diagnostics behind the rows that differ, computed from the runs and the equations.
    let e0x = get(E0_CONTINUED)?;
    let pt = passed_threat(e0x)?;
    let lp = &e0x.law;
    let width = 2.0 * (lp.physical_sensing_radius_m / 3.0).powi(2);
    let v_t = e0x
        .threat
        .as_ref()
        .map_or(f64::NAN, |t| t.velocity_hill_mps().norm());
    let centroid_at = |run: &CaseRun, t: f64| -> Option<Vector3<f64>> {
        let r = run.records.iter().find(|r| (r.time_s - t).abs() < 1e-6)?;
        Some(
            r.positions_m
                .iter()
                .zip(&run.nodes_m)
                .map(|(x, xi)| x - xi)
                .sum::<Vector3<f64>>()
                / r.positions_m.len() as f64,
        )
    };
    let drift = match (centroid_at(e0x, 50.0), centroid_at(e0x, 60.0)) {
        (Some(a), Some(b)) => (b - a).norm() / 10.0,
        _ => f64::NAN,
    };
    notes.push(format!(
        "N2: the threat never gets past. A satellite on the threat's line flees along the threat's \
         motion (parallel escape) at A e^(−d²/K) ≥ V_T while d ≤ √(K ln(A/V_T)) = {:.2} m (A = {} m/s, \
         K = 2 (R_s/3)² = {width:.2} m², V_T = {v_t} m/s), so in the kinematic model it rides ahead of \
         the threat; the pair field pulls the others after it until they sense the threat too, and the \
         rhombus travels ahead of the threat folded out of its plane: at {:.0} s the threat is still \
         {:.2} m behind the nearest satellite, {} of the {} satellites are within R_s of it, the centroid \
         moves at {drift:.3} m/s (50–60 s) and the formation error is {:.1} mm. The paper reports the \
         rhombus restored after the threat has passed (Fig. 2); with the threat aimed exactly at \
         satellite 0's node (our choice; the paper does not give its geometry) that cannot happen under \
         this escape rule.",
        parallel_standoff_m(lp.threat_scale_mps, width, v_t),
        lp.threat_scale_mps,
        e0x.duration_s,
        -pt.threat_past_satellites_m,
        pt.within_sensing_at_end,
        e0x.nodes_m.len(),
        1e3 * pt.max_error_m
    ));
    let sample = |s: f64| {
        e2b3.at(s)
            .ok_or_else(|| failed(format!("es-e2b-3: no sample at {s} s")))
    };
    let (s200, s400, s700) = (sample(200.0)?, sample(400.0)?, e2b3.end());
    let a_chem = e2b3.common_cap().map_or(f64::NAN, |c| c.0);
    let min_vx400 = s400
        .velocities_mps
        .iter()
        .map(|v| v.x)
        .fold(f64::INFINITY, f64::min);
    let min_vx200 = s200
        .velocities_mps
        .iter()
        .map(|v| v.x)
        .fold(f64::INFINITY, f64::min);
    let s500 = sample(500.0)?;
    // Radial Δv ledger gained between 500 and 700 s, as a fraction of a_max · 200 s (1: saturated).
    let radial_duty = s700
        .delta_v_axes_mps
        .iter()
        .zip(&s500.delta_v_axes_mps)
        .map(|(b, a)| (b[0] - a[0]) / (a_chem * (s700.time_s - s500.time_s)))
        .fold(f64::INFINITY, f64::min);
    let min_vx700 = s700
        .velocities_mps
        .iter()
        .map(|v| v.x)
        .fold(f64::INFINITY, f64::min);
    notes.push(format!(
        "N4, N9 S2 perpendicular: Table 2's 0.4 m/s is what the diagonal escape costs by the headtime \
         alone (√2 a_max t_h = {:.3} m/s; ours at 200 s: {:.3} m/s). In our runs the warning lasts until \
         400 s (Table 1) and the warned threat term, whose width K_i = 2 (R_s,i/3)² is set by the \
         distance at the warning (200 m), keeps the satellites accelerating outwards after the threat \
         has passed: radially ≥ {min_vx200:.3} m/s at the headtime, ≥ {min_vx400:.3} m/s at the \
         all-clear. Braking radially at most at a_max (less the gravity gradient 3n²x the controller \
         also cancels) takes ≥ {:.0} s, so at 500 s and 700 s both runs are still braking (radial speeds \
         at 700 s ≥ {min_vx700:.3} m/s; between 500 and 700 s every satellite's radial thrust averages \
         ≥ {:.1} % of the cap): the formation error is set by the braking transient ({} at 500 s, {} at 700 s), \
         not by the pair field's relaxation, and Δv reaches {:.3} m/s at 700 s.",
        2f64.sqrt() * a_chem * 200.0,
        mean(&s200.delta_v_mps),
        min_vx400 / a_chem,
        100.0 * radial_duty,
        cm(formation_error_m(&s500.positions_m, &e2b3.nodes_m)),
        cm(e2b3.final_formation_error_m()),
        mean(&s700.delta_v_mps)
    ));
    let e3_law = &e3a.law;
    notes.push(format!(
        "N9 S3, E3a/E3b misses: the dock term's peak inward speed d √(k₃/2) e^(−1/2) = {:.2} m/s (d = {} \
         1/s, k₃ = {} m², at {:.2} m from the node) exceeds the threat term's largest speed A = {} m/s, so \
         no warned threat term can pull a satellite out of its dock well: the satellites stay within \
         {:.3} m (E3a) and {:.3} m (E3b) of their nodes, Δv is {:.3} and {:.3} m/s, and the centroid does \
         not move. E3a's {:.2} m \"miss\" is the threat's remaining distance at the end of the 430 s run \
         (it reaches node 0 at 500 s; continued to 1000 s the minimum is {} m); E3b's parallel escape \
         lets the threat pass through satellite 0's well ({} m). The paper's satellites, which spread \
         hundreds of metres, are not reproducible with these coefficients.",
        dock_peak_mps(e3_law.dock_per_s, e3_law.dock_range_m2),
        e3_law.dock_per_s,
        e3_law.dock_range_m2,
        (0.5 * e3_law.dock_range_m2).sqrt(),
        e3_law.threat_scale_mps,
        e3a.max_node_distance_m(),
        e3b.max_node_distance_m(),
        dv(e3a),
        dv(e3b),
        e3a.minimum_miss_m(),
        num(e3a_long.minimum_miss_m()),
        num(e3b.minimum_miss_m())
    ));
    let n_orbit = e4.hcw.map_or(f64::NAN, |h| h.mean_motion_rad_s);
    let a_e4 = e4.common_cap().map_or(f64::NAN, |c| c.0);
    notes.push(format!(
        "N9 S4, E4: the diagonal escape (radial and along-track) lasts 500 s; the satellites reach \
         x = {:.0} m radially, beyond x = a_max/(3n²) = {:.0} m where the gravity gradient the controller \
         must cancel exceeds the per-axis cap, so the gather/avoid/dock return cannot hold or bring them \
         back: Δv is {:.3} m/s (two axes saturated for the whole run would give √2 a_max T = \
         {:.3} m/s), the centroid ends {:.0} m away and the formation \
         error is {:.1} m at 2000 s.",
        e4.max_radial_m(),
        a_e4 / (3.0 * n_orbit * n_orbit),
        dv(e4),
        2f64.sqrt() * a_e4 * e4.duration_s,
        e4.final_centroid_m(),
        e4.final_formation_error_m()
    ));
    let scatter_law = &e1c.law;
    notes.push(format!(
        "N9 S1, N11: the scatter speed is set by the scatter gain κ, which the paper does not give \
         (default {} 1/(m s): {:.3}–{:.3} m/s demanded at the nodes), so the capped satellites \
         never thrust at the cap for 1500–2000 s as the paper's did; they stop on the sphere \
         (N11 sphere). The gather back is the gather/avoid/dock field, whose gather term sums over all \
         nodes (it pulls towards their centroid) and whose dock wells peak {:.2} m from each node: capped, the \
         satellites cross their wells too fast to stop, overshoot through the formation (closest pair \
         {:.2} m over the 10 s recordings) and are not re-formed at 4000 s ({:.2} m formation error, \
         {:.3} m/s gather Δv). Uncapped, the controller follows the dock well's {:.1} m/s peak speed \
         into each node and brakes from it again: {:.1} m/s gather Δv.",
        scatter_law.scatter_gain_per_m_s,
        scatter_law.scatter_gain_per_m_s
            * (scatter_law.danger_radius_m.powi(2)
                - e1c
                    .nodes_m
                    .iter()
                    .map(|x| x.norm_squared())
                    .fold(0.0, f64::max)),
        scatter_law.scatter_gain_per_m_s
            * (scatter_law.danger_radius_m.powi(2)
                - e1c
                    .nodes_m
                    .iter()
                    .map(|x| x.norm_squared())
                    .fold(f64::INFINITY, f64::min)),
        (0.5 * scatter_law.dock_range_m2).sqrt(),
        e1c.min_separation_m(),
        e1c.final_formation_error_m(),
        dv(e1c) - s1_scatter,
        dock_peak_mps(scatter_law.dock_per_s, scatter_law.dock_range_m2),
        dv(e1) - e1.at(N11_SCATTER_END_S).map_or(f64::NAN, |s| mean(&s.delta_v_mps))
    ));
    let electric = get("es-e2b-2-electric")?;
    let apex = electric
        .nodes_m
        .iter()
        .map(|x| x.x.abs())
        .fold(0.0, f64::max);
    let n_e = electric.hcw.map_or(f64::NAN, |h| h.mean_motion_rad_s);
    notes.push(format!(
        "N10, electric cap: the escape buys {:.3} m over the node offset (bound ½√2 a t_h² = {:.3} m). \
         The cap {:.1e} m/s² is below the gravity gradient 3n²|x| = {:.2e} m/s² at the rhombus's radial \
         apexes (|x| = {apex:.3} m), so those satellites cannot even be held on their nodes: the \
         formation error is {:.2} m at 500 s.",
        electric.average_miss_m() - electric
            .threat
            .as_ref()
            .map_or(f64::NAN, |t| node_offset_m(t, &electric.nodes_m)),
        double_integrator_bound_m(
            electric.common_cap().map_or(f64::NAN, |c| c.0),
            200.0,
            2
        ),
        electric.common_cap().map_or(f64::NAN, |c| c.0),
        3.0 * n_e * n_e * apex,
        electric.final_formation_error_m()
    ));
    let offset = e2b1
        .threat
        .as_ref()
        .map_or(f64::NAN, |t| node_offset_m(t, &e2b1.nodes_m));
    notes.push(format!(
        "Threat geometry (a gap of the paper): ours aims at satellite 0's node from +z, so the node offset \
         (average distance of the nodes from the threat line) is {offset:.2} m, above the paper's 4 m \
         average miss for the 50 s headtime (ours {:.2} m), and a parallel escape keeps the aimed \
         satellite on the line (E2a minimum miss {} m vs the paper's 7 m). With an axis-aligned \
         common escape (−y) E2b sim 2 misses by {:.2} m on average; the diagonal one, which saturates \
         two axes, {:.2} m (paper 45 m).",
        e2b1.average_miss_m(),
        num(e2a.minimum_miss_m()),
        axis.average_miss_m(),
        e2b2.average_miss_m()
    ));
    let hcw = e4.hcw.ok_or_else(|| failed("es-e4 does not run on HCW"))?;
    let reach = hcw_planar_reach_m(&hcw, a_e4, &[200.0, 300.0, 500.0]);
    notes.push(format!(
        "B2: ½√2 a t² is the reach of a double integrator. On the HCW equations the Coriolis terms couple \
         the radial and along-track responses and the exact reach of |u_x|, |u_y| ≤ a is larger ({:.2} \
         vs {:.2} m at 200 s, {:.2} vs {:.2} m at 300 s, {:.2} vs {:.2} m at 500 s); an escape that \
         saturates both axes for the whole headtime attains the exact reach and so exceeds the \
         double-integrator bound by that margin (row B2) while staying inside the exact one (row B2 \
         HCW). The tests assert the HCW form; this was decided from the equations before the first run.",
        reach[0],
        double_integrator_bound_m(a_e4, 200.0, 2),
        reach[1],
        double_integrator_bound_m(a_e4, 300.0, 2),
        reach[2],
        double_integrator_bound_m(a_e4, 500.0, 2),
    ));
    let k2 = e3a.law.avoid_range_m2;
    notes.push(format!(
        "N1: within a symmetry class of the hexagon the law's minimum-norm coefficients of the small \
         classes (second neighbours, opposite nodes; ranges in the row) are not exactly equal: their \
         columns of the shaping system are scaled by e^(−δ²/k₂) = {:.1e} and {:.1e}, so the SVD \
         determines them only to ~1e-16 / (that scale × δ) 1/s while the field at the nodes stays \
         exact; the printed values are matched.",
        (-3.0 * 36.0 / k2).exp(),
        (-144.0 / k2).exp()
    ));
    notes.push(
        "Runs: every es-* scenario at full length (HCW, RK4, continuous control, process noise 1e-6 m/s², \
         seed 1), two at a time; miss distances from the engine's continuous closest-approach monitor; \
         formation error, centroid and B2 displacements computed here from the truth Hill states and the \
         nodes (the satellites' initial positions). Criteria and tolerances are constants of \
         cli/src/validate/scatter.rs, fixed before the first run."
            .into(),
    );
    Ok(Report {
        measured: None,
        title: "Nag & Summerer 2013, behaviour-based scatter manoeuvres (equilibrium shaping)"
            .into(),
        reference_header: "paper".into(),
        checks,
        tables: vec![strategy_table, cases_table],
        notes,
    })
}
