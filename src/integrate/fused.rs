//! The fused structure-of-arrays RK4 kernel: fixed-step RK4 of many independent satellites under point
//! mass or point mass + J2 gravity, optionally with drag in a one-layer exponential atmosphere (the
//! force sets [`FastForces`] names), plus a constant per-satellite acceleration, with an optional
//! delta-v ledger, over the component-major layout `x[0..n], y[0..n], z[0..n], vx[0..n], vy[0..n], vz[0..n]`
//! (then, with the ledger, its four components likewise).
//!
//! # Fused
//!
//! The generic [`Rk4`](super::Rk4) makes one pass over the whole state per stage combination (five per
//! step) plus one per right-hand side. Here a block of [`Simd::lanes`] satellites is loaded into
//! `[f64; LANES]` arrays once per segment, stepped through every step of the segment in registers (four
//! gravity evaluations and the stage arithmetic per step), and stored once: one pass over memory per
//! segment. The lane loops are written so that LLVM vectorises them (SSE2 in the portable build; AVX2 or
//! AVX-512 copies of the same code chosen at run time by [`Simd::detect`]).
//!
//! # Bitwise identity
//!
//! Every satellite's numbers are computed by the same IEEE operations, in the same order, as the generic
//! [`Rk4`](super::Rk4) stepping one satellite (`y + h * (0.0 + a k)` for the stage arguments with zero
//! coefficients skipped, `y + h * ((((0.0 + b0 k1) + b1 k2) + b2 k3) + b3 k4)` for the new state, the
//! steps split as [`Rk4::integrate`](super::Rk4::integrate) splits them) with the right-hand side of
//! [`GravityModel::acceleration_m_s2`] (plus, with drag, [`crate::dynamics::drag_acceleration_m_s2`]
//! at the exponential density of the height above the sphere, through the atmosphere's own
//! vectorisable exponential) plus the held acceleration, summed in the order [`crate::dynamics::ForceSet`] sums
//! them. Rust does not contract `a * b + c`
//! into a fused multiply-add and no copy enables FMA, so the portable and wide copies give the same bits,
//! which the tests check against the generic stepper. Satellites do not interact, so the result of one
//! does not depend on its lane, block, chunk or thread: it is bitwise identical for any thread count.
//!
//! # Parallelism
//!
//! When the work (satellites × steps) reaches [`PARALLEL_MIN_SAT_STEPS`] and the rayon pool has more than
//! one thread, the satellites are split in halves at multiples of [`PARALLEL_CHUNK`] by `rayon::join`;
//! below it, or on one thread, the kernel runs on the calling thread with no fork-join at all.

use nalgebra::Vector3;

use super::rk4::{StepPlan, A, B};
use crate::dynamics::{
    speed_from_square_m_s, ExpTable, Exponential, FastForces, IndexedExpTable, PermutedExpTable,
    EARTH_ROTATION_RAD_S,
};
use crate::orbit::{EarthModel, GravityModel};

/// Satellites per parallel chunk: splits of the work fall on multiples of it.
pub const PARALLEL_CHUNK: usize = 512;

/// Least work (satellites × steps of the segment) run in parallel; less runs on the calling thread.
/// The measured crossover on the 2-core reference machine (`cargo bench --bench propagation --
/// fork_join`, one step of N satellites): the calling thread alone wins at 1 024 and 2 048 sat-steps
/// (9 and 18 µs against 11–28 µs forked: waking the other thread costs about 10 µs), forking wins from
/// 4 096 (26–30 against 36 µs) and by 1.7–1.9× from 8 192 on (see `BENCHMARKS.md`).
pub const PARALLEL_MIN_SAT_STEPS: usize = 4_096;

/// Which copy of the kernel runs: they give the same bits and differ only in speed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Simd {
    /// The portable build (baseline x86-64: SSE2, two `f64` per instruction), 4 lanes.
    Portable,
    /// AVX2 (four `f64` per instruction), 8 lanes; x86-64 only, when the CPU has it.
    Avx2,
    /// AVX-512F (eight `f64` per instruction), 16 lanes; x86-64 only, when the CPU has it. With drag
    /// it reads the exponential's table by register permutes instead of gathers.
    Avx512,
}

impl Simd {
    /// Every copy, in the order of [`Simd::NAMES`].
    pub const ALL: [Simd; 3] = [Simd::Portable, Simd::Avx2, Simd::Avx512];
    /// The names of the copies, as [`Simd::name`] gives them.
    pub const NAMES: [&'static str; 3] = ["portable", "avx2", "avx512"];

    /// The copy's name: `"portable"`, `"avx2"` or `"avx512"`.
    pub fn name(self) -> &'static str {
        match self {
            Simd::Portable => Self::NAMES[0],
            Simd::Avx2 => Self::NAMES[1],
            Simd::Avx512 => Self::NAMES[2],
        }
    }

    /// Whether this CPU runs the copy.
    pub fn is_available(self) -> bool {
        match self {
            Simd::Portable => true,
            #[cfg(target_arch = "x86_64")]
            Simd::Avx2 => std::arch::is_x86_feature_detected!("avx2"),
            #[cfg(target_arch = "x86_64")]
            Simd::Avx512 => std::arch::is_x86_feature_detected!("avx512f"),
            #[cfg(not(target_arch = "x86_64"))]
            Simd::Avx2 | Simd::Avx512 => false,
        }
    }

    /// The widest copy this CPU runs.
    pub fn detect() -> Simd {
        [Simd::Avx512, Simd::Avx2]
            .into_iter()
            .find(|s| s.is_available())
            .unwrap_or(Simd::Portable)
    }

    /// Satellites stepped together by the copy.
    pub fn lanes(self) -> usize {
        match self {
            Simd::Portable => PORTABLE_LANES,
            Simd::Avx2 => AVX2_LANES,
            Simd::Avx512 => AVX512_LANES,
        }
    }
}

/// Lanes of the portable copy (two SSE2 registers per quantity).
const PORTABLE_LANES: usize = 4;
/// Lanes of the AVX2 copy (two 256-bit registers per quantity).
const AVX2_LANES: usize = 8;
/// Lanes of the AVX-512 copy: two 512-bit registers per quantity, two independent dependency chains
/// through each step (the step is latency-bound: 16 lanes measured 1.45x 8 lanes for J2 and 1.2x with
/// drag at 10^5 satellites; 32 lanes spill registers and lose).
const AVX512_LANES: usize = 16;

/// Why the kernel refused to run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum FusedError {
    /// A slice has the wrong length for `n` satellites.
    #[error("{what} has length {got}, expected {expected}")]
    Length {
        /// Which slice.
        what: &'static str,
        /// Its length.
        got: usize,
        /// The length needed.
        expected: usize,
    },
    /// The step is not finite and positive, or an end of the interval is not finite.
    #[error("invalid step {max_step_s} s or interval [{t0_s}, {t1_s}] s (need a finite step > 0 and finite times)")]
    Interval {
        /// Start time (s).
        t0_s: f64,
        /// End time (s).
        t1_s: f64,
        /// Longest step (s).
        max_step_s: f64,
    },
    /// The kernel computes drag but the segment gave no per-satellite `C_d A / m`.
    #[error(
        "the kernel computes drag: drag_area_per_mass_m2_per_kg must be given for every satellite"
    )]
    MissingDragAreas,
    /// The requested copy does not run on this CPU.
    #[error("the {} kernel does not run on this CPU", .0.name())]
    Unavailable(Simd),
}

/// What each satellite holds constant over a segment. Every slice present has one entry per satellite.
#[derive(Clone, Copy, Debug, Default)]
pub struct SegmentInputs<'a> {
    /// Acceleration added to gravity, ECI \[m/s^2\] (the held command); `None`: none.
    pub control_eci_m_s2: Option<&'a [Vector3<f64>]>,
    /// The command the delta-v ledger integrates (Hill axes) \[m/s^2\]: present exactly when the state
    /// holds the four ledger components (∫|u_x|, ∫|u_y|, ∫|u_z|, ∫‖u‖ dt, in m/s).
    pub ledger_command_hill_m_s2: Option<&'a [Vector3<f64>]>,
    /// Which satellites move (the others are left as they are); `None`: all.
    pub active: Option<&'a [bool]>,
    /// Each satellite's drag term `C_d A / m` \[m^2/kg\] (as
    /// [`crate::dynamics::PhysicalProperties::drag_area_per_mass_m2_per_kg`] forms it): required by a
    /// kernel with drag, ignored by one without.
    pub drag_area_per_mass_m2_per_kg: Option<&'a [f64]>,
}

/// Fixed-step RK4 of independent satellites over structure-of-arrays state: each block of
/// [`Simd::lanes`] satellites stepped through the whole segment in registers, bitwise identical to
/// [`Rk4`](super::Rk4) on each satellite alone and for any thread count; in parallel over chunks of
/// [`PARALLEL_CHUNK`] satellites from [`PARALLEL_MIN_SAT_STEPS`] of work on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FusedRk4 {
    gravity: GravityModel,
    earth: EarthModel,
    drag: Option<DragConstants>,
    simd: Simd,
    parallel_min_sat_steps: usize,
}

impl FusedRk4 {
    /// A kernel for `gravity` with the constants `earth`, running the widest copy this CPU has.
    pub fn new(gravity: GravityModel, earth: EarthModel) -> Self {
        Self {
            gravity,
            earth,
            drag: None,
            simd: Simd::detect(),
            parallel_min_sat_steps: PARALLEL_MIN_SAT_STEPS,
        }
    }

    /// A kernel for the force set `forces` (gravity alone, or gravity and exponential drag), running
    /// the widest copy this CPU has.
    pub fn for_forces(forces: FastForces) -> Self {
        match forces {
            FastForces::Gravity(gravity, earth) => Self::new(gravity, earth),
            FastForces::GravityExponentialDrag {
                gravity,
                earth,
                atmosphere,
                corotation,
            } => Self {
                drag: Some(DragConstants {
                    atmosphere,
                    radius_m: earth.equatorial_radius_m,
                    corotation,
                }),
                ..Self::new(gravity, earth)
            },
        }
    }

    /// Whether the kernel computes drag (and so needs each satellite's `C_d A / m`).
    pub fn has_drag(&self) -> bool {
        self.drag.is_some()
    }

    /// The same kernel forking onto the rayon pool from `sat_steps` of work (satellites × steps of a
    /// segment) on, instead of [`PARALLEL_MIN_SAT_STEPS`]: for measuring the crossover on a machine
    /// (`benches/propagation.rs`, group `fork_join`). The answers never depend on it.
    pub fn with_parallel_min_sat_steps(self, sat_steps: usize) -> Self {
        Self {
            parallel_min_sat_steps: sat_steps,
            ..self
        }
    }

    /// The same kernel running the copy `simd` (same bits, other speed); refused when the CPU lacks it.
    pub fn with_simd(self, simd: Simd) -> Result<Self, FusedError> {
        if simd.is_available() {
            Ok(Self { simd, ..self })
        } else {
            Err(FusedError::Unavailable(simd))
        }
    }

    /// The copy that runs.
    pub fn simd(&self) -> Simd {
        self.simd
    }

    /// Advances the `n` satellites in `state` from `t0_s` to `t1_s` (s) in RK4 steps of `max_step_s` (s),
    /// split as [`Rk4::integrate`](super::Rk4::integrate) splits them; nothing when `t1_s <= t0_s`.
    ///
    /// `state` is component-major: positions x, y, z \[m\] then velocities \[m/s\], `n` values each, in
    /// the inertial frame of the gravity model (z the Earth's polar axis); followed by the four ledger
    /// components \[m/s\] exactly when `inputs.ledger_command_hill_m_s2` is present (length `10 n`, else
    /// `6 n`).
    pub fn advance(
        &self,
        state: &mut [f64],
        n: usize,
        inputs: &SegmentInputs<'_>,
        t0_s: f64,
        t1_s: f64,
        max_step_s: f64,
    ) -> Result<(), FusedError> {
        let components = if inputs.ledger_command_hill_m_s2.is_some() {
            10
        } else {
            6
        };
        let check = |what, got: usize, expected: usize| {
            if got == expected {
                Ok(())
            } else {
                Err(FusedError::Length {
                    what,
                    got,
                    expected,
                })
            }
        };
        check("state", state.len(), components * n)?;
        if let Some(c) = inputs.control_eci_m_s2 {
            check("control_eci_m_s2", c.len(), n)?;
        }
        if let Some(c) = inputs.ledger_command_hill_m_s2 {
            check("ledger_command_hill_m_s2", c.len(), n)?;
        }
        if let Some(a) = inputs.active {
            check("active", a.len(), n)?;
        }
        let drag_areas = match (self.drag.is_some(), inputs.drag_area_per_mass_m2_per_kg) {
            (true, None) if n > 0 => return Err(FusedError::MissingDragAreas),
            (true, Some(b)) => {
                check("drag_area_per_mass_m2_per_kg", b.len(), n)?;
                Some(b)
            }
            _ => None,
        };
        if !(max_step_s > 0.0 && max_step_s.is_finite() && t0_s.is_finite() && t1_s.is_finite()) {
            return Err(FusedError::Interval {
                t0_s,
                t1_s,
                max_step_s,
            });
        }
        let Some(plan) = StepPlan::new(t0_s, t1_s, max_step_s) else {
            return Ok(());
        };
        let (pv, ledger) = state.split_at_mut(6 * n);
        let mut pv = pv.chunks_exact_mut(n.max(1));
        let mut next = || pv.next().unwrap_or_default();
        let part = Part {
            pv: [next(), next(), next(), next(), next(), next()],
            ledger: inputs.ledger_command_hill_m_s2.map(|command| {
                let mut l = ledger.chunks_exact_mut(n.max(1));
                let mut next = || l.next().unwrap_or_default();
                ([next(), next(), next(), next()], command)
            }),
            control: inputs.control_eci_m_s2,
            active: inputs.active,
            drag_areas,
            offset: 0,
        };
        let parallel = n.saturating_mul(plan.steps) >= self.parallel_min_sat_steps
            && rayon::current_num_threads() > 1;
        let constants = Constants::new(&self.earth);
        let job = Job {
            constants,
            plan,
            j2: self.gravity == GravityModel::J2,
            drag: self.drag,
            simd: self.simd,
        };
        if parallel {
            run_parallel(&job, part);
        } else {
            job.run(part);
        }
        Ok(())
    }
}

/// The Earth constants as the gravity expression uses them.
#[derive(Clone, Copy, Debug)]
struct Constants {
    /// mu \[m^3/s^2\].
    mu: f64,
    /// `1.5 J2 R R` \[m^2\], evaluated in the order of [`GravityModel::acceleration_m_s2`].
    j2_r2: f64,
}

impl Constants {
    fn new(earth: &EarthModel) -> Self {
        Self {
            mu: earth.mu_m3_s2,
            j2_r2: 1.5 * earth.j2 * earth.equatorial_radius_m * earth.equatorial_radius_m,
        }
    }
}

/// The exponential atmosphere and the co-rotation as the drag expression uses them.
#[derive(Clone, Copy, Debug, PartialEq)]
struct DragConstants {
    atmosphere: Exponential,
    /// The sphere the height is measured above \[m\].
    radius_m: f64,
    corotation: bool,
}

impl DragConstants {
    /// Stands in for the atmosphere of a kernel without drag (whose lane arithmetic never reads it).
    const UNUSED: Self = Self {
        atmosphere: Exponential {
            reference_density_kg_per_m3: 0.0,
            reference_altitude_m: 0.0,
            scale_height_m: 1.0,
        },
        radius_m: 0.0,
        corotation: false,
    };
}

/// One segment's work, the same for every part of the swarm.
struct Job {
    constants: Constants,
    plan: StepPlan,
    j2: bool,
    drag: Option<DragConstants>,
    simd: Simd,
}

/// A contiguous range of satellites: their state components and held inputs.
struct Part<'a> {
    /// x, y, z, vx, vy, vz.
    pv: [&'a mut [f64]; 6],
    /// The ledger's four components and the command they integrate.
    ledger: Option<Ledger<'a>>,
    control: Option<&'a [Vector3<f64>]>,
    active: Option<&'a [bool]>,
    /// Each satellite's `C_d A / m` (kernels with drag).
    drag_areas: Option<&'a [f64]>,
    /// Index of the part's first satellite in the swarm (for the held inputs).
    offset: usize,
}

/// The ledger's four components of a part and the commands they integrate.
type Ledger<'a> = ([&'a mut [f64]; 4], &'a [Vector3<f64>]);

/// Splits every component of a part at `mid`.
fn split_components<const K: usize>(
    components: [&mut [f64]; K],
    mid: usize,
) -> ([&mut [f64]; K], [&mut [f64]; K]) {
    let mut halves = components.map(|c| c.split_at_mut(mid));
    let low = std::array::from_fn(|k| std::mem::take(&mut halves[k].0));
    let high = std::array::from_fn(|k| std::mem::take(&mut halves[k].1));
    (low, high)
}

impl<'a> Part<'a> {
    fn len(&self) -> usize {
        self.pv[0].len()
    }

    fn split_at(self, mid: usize) -> (Part<'a>, Part<'a>) {
        let (pv_low, pv_high) = split_components(self.pv, mid);
        let (ledger_low, ledger_high) = match self.ledger {
            Some((l, command)) => {
                let (low, high) = split_components(l, mid);
                (Some((low, command)), Some((high, command)))
            }
            None => (None, None),
        };
        (
            Part {
                pv: pv_low,
                ledger: ledger_low,
                offset: self.offset,
                ..self
            },
            Part {
                pv: pv_high,
                ledger: ledger_high,
                offset: self.offset + mid,
                ..self
            },
        )
    }
}

/// Runs `part` split in halves at multiples of [`PARALLEL_CHUNK`] on the rayon pool.
fn run_parallel(job: &Job, part: Part<'_>) {
    let chunks = part.len() / PARALLEL_CHUNK;
    if chunks < 2 {
        job.run(part);
        return;
    }
    let (low, high) = part.split_at(chunks / 2 * PARALLEL_CHUNK);
    rayon::join(|| run_parallel(job, low), || run_parallel(job, high));
}

impl Job {
    /// Runs `part` on this thread with the chosen copy of the kernel.
    #[allow(unsafe_code)]
    fn run(&self, part: Part<'_>) {
        #[cfg(target_arch = "x86_64")]
        match self.simd {
            Simd::Avx512 => {
                if let Some(table) = PermutedExpTable::new() {
                    // SAFETY: the CPU has AVX-512F (`table` exists), the only feature the function
                    // enables.
                    return unsafe { run_avx512(self, part, table) };
                }
            }
            Simd::Avx2 if std::arch::is_x86_feature_detected!("avx2") => {
                // SAFETY: the CPU has AVX2 (detected on the line above), the only feature the function
                // enables.
                return unsafe { run_avx2(self, part) };
            }
            _ => {}
        }
        run_lanes::<PORTABLE_LANES>(self, part, IndexedExpTable);
    }
}

/// The kernel compiled for AVX-512F.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn run_avx512(job: &Job, part: Part<'_>, table: PermutedExpTable) {
    run_lanes::<AVX512_LANES>(job, part, table);
}

/// The kernel compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn run_avx2(job: &Job, part: Part<'_>) {
    run_lanes::<AVX2_LANES>(job, part, IndexedExpTable);
}

/// `L` quantities of one kind, one per lane.
type Lanes<const L: usize> = [f64; L];
/// A 3-vector per lane, component-major.
type Vec3<const L: usize> = [Lanes<L>; 3];

#[inline(always)]
fn run_lanes<const L: usize>(job: &Job, part: Part<'_>, table: impl ExpTable) {
    let drag = match job.drag {
        None => NO_DRAG,
        Some(DragConstants {
            corotation: false, ..
        }) => DRAG_INERTIAL,
        Some(DragConstants {
            corotation: true, ..
        }) => DRAG_COROTATING,
    };
    match (job.j2, drag) {
        (true, NO_DRAG) => run_blocks::<L, true, NO_DRAG>(job, part, table),
        (false, NO_DRAG) => run_blocks::<L, false, NO_DRAG>(job, part, table),
        (true, DRAG_INERTIAL) => run_blocks::<L, true, DRAG_INERTIAL>(job, part, table),
        (false, DRAG_INERTIAL) => run_blocks::<L, false, DRAG_INERTIAL>(job, part, table),
        (true, _) => run_blocks::<L, true, DRAG_COROTATING>(job, part, table),
        (false, _) => run_blocks::<L, false, DRAG_COROTATING>(job, part, table),
    }
}

/// The kernel's drag modes (a const parameter of the lane arithmetic): none, in an inertial
/// atmosphere, in a co-rotating one.
const NO_DRAG: u8 = 0;
const DRAG_INERTIAL: u8 = 1;
const DRAG_COROTATING: u8 = 2;

/// The forces of one segment as the lane arithmetic reads them.
struct Forces<'c, const L: usize, T> {
    constants: &'c Constants,
    /// The atmosphere (a neutral one without drag: never read then).
    drag: DragConstants,
    /// How this copy reads the exponential's table.
    table: T,
    /// `-C_d A / (2 m)` per lane (zero without drag), as `drag_acceleration_m_s2` scales it.
    half_drag_areas: Lanes<L>,
}

/// Steps every satellite of `part`, `L` at a time, through the whole segment, then its ledger.
#[inline(always)]
fn run_blocks<const L: usize, const J2: bool, const DRAG: u8>(
    job: &Job,
    part: Part<'_>,
    table: impl ExpTable,
) {
    let Part {
        pv,
        ledger,
        control,
        active,
        drag_areas,
        offset,
    } = part;
    let n = pv[0].len();
    let moves = |i: usize| active.is_none_or(|a| a[offset + i]);
    let mut start = 0;
    while start < n {
        let len = L.min(n - start);
        let mut p: Vec3<L> = [[0.0; L]; 3];
        let mut v: Vec3<L> = [[0.0; L]; 3];
        let mut u: Vec3<L> = [[0.0; L]; 3];
        let mut forces = Forces {
            constants: &job.constants,
            drag: job.drag.unwrap_or(DragConstants::UNUSED),
            table,
            half_drag_areas: [0.0; L],
        };
        // The unused lanes of the last block repeat its last satellite (finite, never stored).
        for l in 0..L {
            let i = start + l.min(len - 1);
            for k in 0..3 {
                p[k][l] = pv[k][i];
                v[k][l] = pv[k + 3][i];
            }
            if let Some(c) = control {
                let c = c[offset + i];
                for k in 0..3 {
                    u[k][l] = c[k];
                }
            }
            if let Some(b) = drag_areas {
                forces.half_drag_areas[l] = -0.5 * b[offset + i];
            }
        }
        if control.is_some() {
            for s in 0..job.plan.steps {
                step::<L, J2, DRAG>(&forces, &mut p, &mut v, &u, job.plan.step_s(s));
            }
        } else {
            // No held acceleration: the same arithmetic (the same bits) with a zero the compiler
            // sees, which frees the registers the loaded one held (the step is short of registers;
            // BENCHMARKS.md, 2026-12-03).
            let zero: Vec3<L> = [[0.0; L]; 3];
            for s in 0..job.plan.steps {
                step::<L, J2, DRAG>(&forces, &mut p, &mut v, &zero, job.plan.step_s(s));
            }
        }
        for l in 0..len {
            if moves(start + l) {
                for k in 0..3 {
                    pv[k][start + l] = p[k][l];
                    pv[k + 3][start + l] = v[k][l];
                }
            }
        }
        start += len;
    }
    if let Some((mut ledger, command)) = ledger {
        for i in (0..n).filter(|&i| moves(i)) {
            let u = command[offset + i];
            let rates = [u.x.abs(), u.y.abs(), u.z.abs(), u.norm()];
            for (component, rate) in ledger.iter_mut().zip(rates) {
                // The RK4 combination of four equal stage derivatives, as the generic stepper forms it.
                let slope = (((0.0 + B[0] * rate) + B[1] * rate) + B[2] * rate) + B[3] * rate;
                let mut value = component[i];
                for s in 0..job.plan.steps {
                    value += job.plan.step_s(s) * slope;
                }
                component[i] = value;
            }
        }
    }
}

/// Gravity (plus drag) plus the held acceleration at `p`, `v`, per lane, as
/// [`GravityModel::acceleration_m_s2`] and [`crate::dynamics::drag_acceleration_m_s2`] form them and
/// [`crate::dynamics::ForceSet`] sums them: `(gravity + drag) + held`. One loop over the lanes with
/// every branch resolved at compile time (`DRAG`: [`NO_DRAG`], [`DRAG_INERTIAL`] or
/// [`DRAG_COROTATING`]), so it vectorises and keeps its intermediates in registers.
#[inline(always)]
fn acceleration<const L: usize, const J2: bool, const DRAG: u8>(
    f: &Forces<'_, L, impl ExpTable>,
    p: &Vec3<L>,
    v: &Vec3<L>,
    u: &Vec3<L>,
) -> Vec3<L> {
    let c = f.constants;
    let d = f.drag;
    let mut squared_radii_m2 = [0.0; L];
    let mut radii_m = [0.0; L];
    for l in 0..L {
        let (x, y, z) = (p[0][l], p[1][l], p[2][l]);
        squared_radii_m2[l] = x * x + y * y + z * z;
        radii_m[l] = squared_radii_m2[l].sqrt();
    }
    // With drag, the exponential densities of all lanes at once (the generic path's arithmetic, hence
    // the same bits), so that this copy reads the exponential's table its own way.
    let densities = if DRAG == NO_DRAG {
        [0.0; L]
    } else {
        d.atmosphere
            .densities_kg_per_m3(&radii_m.map(|r| r - d.radius_m), f.table)
    };
    let mut a = [[0.0; L]; 3];
    for l in 0..L {
        let (x, y, z) = (p[0][l], p[1][l], p[2][l]);
        let (r2, r) = (squared_radii_m2[l], radii_m[l]);
        let mu_over_r3 = c.mu / (r2 * r);
        let (horizontal, vertical) = if J2 {
            let k = c.j2_r2 / r2;
            let five_z2_over_r2 = 5.0 * z * z / r2;
            (
                -mu_over_r3 * (1.0 + k * (1.0 - five_z2_over_r2)),
                -mu_over_r3 * (1.0 + k * (3.0 - five_z2_over_r2)),
            )
        } else {
            (-mu_over_r3, -mu_over_r3)
        };
        if DRAG == NO_DRAG {
            a[0][l] = horizontal * x + u[0][l];
            a[1][l] = horizontal * y + u[1][l];
            a[2][l] = vertical * z + u[2][l];
        } else {
            // The drag acceleration as `drag_acceleration_m_s2` forms it.
            let (vx, vy, vz) = if DRAG == DRAG_COROTATING {
                (
                    v[0][l] + EARTH_ROTATION_RAD_S * y,
                    v[1][l] - EARTH_ROTATION_RAD_S * x,
                    v[2][l],
                )
            } else {
                (v[0][l], v[1][l], v[2][l])
            };
            let speed = speed_from_square_m_s(vx * vx + vy * vy + vz * vz);
            let k = densities[l] * f.half_drag_areas[l] * speed;
            a[0][l] = (horizontal * x + k * vx) + u[0][l];
            a[1][l] = (horizontal * y + k * vy) + u[1][l];
            a[2][l] = (vertical * z + k * vz) + u[2][l];
        }
    }
    a
}

/// `y + h * (0.0 + a k)`: a stage argument of the generic stepper (one non-zero coefficient).
#[inline(always)]
fn stage<const L: usize>(y: &Vec3<L>, h: f64, a: f64, k: &Vec3<L>) -> Vec3<L> {
    let mut out = [[0.0; L]; 3];
    for c in 0..3 {
        for l in 0..L {
            out[c][l] = y[c][l] + h * (0.0 + a * k[c][l]);
        }
    }
    out
}

/// `y + h * ((((0.0 + b0 k1) + b1 k2) + b2 k3) + b3 k4)`, in place: the new state of the generic stepper.
#[inline(always)]
fn combine<const L: usize>(y: &mut Vec3<L>, h: f64, k: [&Vec3<L>; 4]) {
    for c in 0..3 {
        for l in 0..L {
            let sum = (((0.0 + B[0] * k[0][c][l]) + B[1] * k[1][c][l]) + B[2] * k[2][c][l])
                + B[3] * k[3][c][l];
            y[c][l] += h * sum;
        }
    }
}

/// One RK4 step of `L` satellites; the position's derivative is the velocity.
#[inline(always)]
fn step<const L: usize, const J2: bool, const DRAG: u8>(
    f: &Forces<'_, L, impl ExpTable>,
    p: &mut Vec3<L>,
    v: &mut Vec3<L>,
    u: &Vec3<L>,
    h: f64,
) {
    let a1 = acceleration::<L, J2, DRAG>(f, p, v, u);
    let p2 = stage(p, h, A[1][0], v);
    let v2 = stage(v, h, A[1][0], &a1);
    let a2 = acceleration::<L, J2, DRAG>(f, &p2, &v2, u);
    let p3 = stage(p, h, A[2][1], &v2);
    let v3 = stage(v, h, A[2][1], &a2);
    let a3 = acceleration::<L, J2, DRAG>(f, &p3, &v3, u);
    let p4 = stage(p, h, A[3][2], &v3);
    let v4 = stage(v, h, A[3][2], &a3);
    let a4 = acceleration::<L, J2, DRAG>(f, &p4, &v4, u);
    let v1 = *v;
    combine(p, h, [&v1, &v2, &v3, &v4]);
    combine(v, h, [&a1, &a2, &a3, &a4]);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::Rk4;

    /// Deterministic numbers in [0, 1) (splitmix64).
    struct Numbers(u64);

    impl Numbers {
        fn next(&mut self) -> f64 {
            self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        }

        fn vector(&mut self, scale: f64) -> Vector3<f64> {
            Vector3::new(self.next() - 0.5, self.next() - 0.5, self.next() - 0.5) * scale
        }
    }

    /// A random swarm: per satellite `[x, y, z, vx, vy, vz, ledger x4]` (LEO-like, some exact zeros),
    /// commands, ledger commands and an activity mask.
    struct Case {
        blocks: Vec<[f64; 10]>,
        control: Vec<Vector3<f64>>,
        command: Vec<Vector3<f64>>,
        active: Vec<bool>,
    }

    fn case(n: usize, seed: u64) -> Case {
        let mut rng = Numbers(seed);
        let blocks = (0..n)
            .map(|i| {
                let mut p = rng.vector(2.0).normalize() * (6.7e6 + 1e6 * rng.next());
                let mut v = rng.vector(1.0).cross(&p).normalize() * (7.4e3 + 300.0 * rng.next());
                if i % 7 == 3 {
                    // An equatorial orbit: z and vz exactly zero (signed zeros in the stages).
                    p.z = 0.0;
                    v.z = 0.0;
                }
                let l = rng.vector(2.0);
                [
                    p.x,
                    p.y,
                    p.z,
                    v.x,
                    v.y,
                    v.z,
                    l.x.abs(),
                    l.y.abs(),
                    l.z.abs(),
                    l.norm(),
                ]
            })
            .collect();
        Case {
            blocks,
            control: (0..n).map(|_| rng.vector(1e-3)).collect(),
            command: (0..n).map(|_| rng.vector(2e-3)).collect(),
            active: (0..n).map(|i| i % 5 != 2).collect(),
        }
    }

    /// The engine's reference: every satellite alone through the generic RK4 (10 components with the
    /// ledger, 6 without), as `advance_sampled` and `propagate` form their right-hand sides.
    fn reference(
        c: &Case,
        gravity: GravityModel,
        inputs: (bool, bool, bool),
        (t0, t1, h): (f64, f64, f64),
    ) -> Vec<[f64; 10]> {
        let (control, ledger, mask) = inputs;
        let earth = EarthModel::WGS84_EGM96;
        let dim = if ledger { 10 } else { 6 };
        let mut rk = Rk4::new(dim);
        c.blocks
            .iter()
            .enumerate()
            .map(|(i, block)| {
                let mut y = *block;
                if mask && !c.active[i] {
                    return y;
                }
                let u = c.control[i];
                let w = c.command[i];
                let rates = [w.x.abs(), w.y.abs(), w.z.abs(), w.norm()];
                let rhs = |_t: f64, y: &[f64], dy: &mut [f64]| {
                    let g = gravity.acceleration_m_s2(&earth, &Vector3::new(y[0], y[1], y[2]));
                    let a = if control { g + u } else { g };
                    dy[0..3].copy_from_slice(&y[3..6]);
                    dy[3..6].copy_from_slice(a.as_slice());
                    if ledger {
                        dy[6..10].copy_from_slice(&rates);
                    }
                };
                rk.integrate(&rhs, t0, t1, &mut y[..dim], h);
                y
            })
            .collect()
    }

    /// The fused kernel on the same case, in the component-major layout.
    fn fused(
        c: &Case,
        kernel: &FusedRk4,
        (control, ledger, mask): (bool, bool, bool),
        (t0, t1, h): (f64, f64, f64),
    ) -> Vec<[f64; 10]> {
        let n = c.blocks.len();
        let dim = if ledger { 10 } else { 6 };
        let mut flat: Vec<f64> = (0..dim)
            .flat_map(|k| c.blocks.iter().map(move |b| b[k]))
            .collect();
        let inputs = SegmentInputs {
            control_eci_m_s2: control.then_some(&c.control[..]),
            ledger_command_hill_m_s2: ledger.then_some(&c.command[..]),
            active: mask.then_some(&c.active[..]),
            drag_area_per_mass_m2_per_kg: None,
        };
        kernel.advance(&mut flat, n, &inputs, t0, t1, h).unwrap();
        c.blocks
            .iter()
            .enumerate()
            .map(|(i, b)| {
                let mut out = *b;
                for (k, value) in out.iter_mut().take(dim).enumerate() {
                    *value = flat[k * n + i];
                }
                out
            })
            .collect()
    }

    fn assert_bitwise(got: &[[f64; 10]], want: &[[f64; 10]], what: &str) {
        for (i, (g, w)) in got.iter().zip(want).enumerate() {
            for k in 0..10 {
                assert_eq!(
                    g[k].to_bits(),
                    w[k].to_bits(),
                    "{what}: satellite {i} component {k}: {} != {}",
                    g[k],
                    w[k]
                );
            }
        }
    }

    /// Every copy, on 1, 2 and 4 threads, with the default fork-join threshold and with forking at any
    /// work, gives the generic stepper's bits.
    #[test]
    fn bitwise_identical_to_the_generic_rk4_for_every_copy_and_thread_count() {
        let intervals = [(0.3, 7.55, 1.0), (10.0, 10.3, 0.1), (0.0, 60.0, 5.0)];
        let mut tested = 0;
        for n in [1, 3, 13, 1100] {
            let c = case(n, n as u64);
            for gravity in [GravityModel::J2, GravityModel::TwoBody] {
                for inputs in [
                    (false, false, false),
                    (true, true, true),
                    (true, false, true),
                ] {
                    for interval in intervals {
                        let want = reference(&c, gravity, inputs, interval);
                        // The default fork-join threshold, and forking whatever the work.
                        let kernels =
                            Simd::ALL
                                .into_iter()
                                .filter(|s| s.is_available())
                                .flat_map(|simd| {
                                    let kernel = FusedRk4::new(gravity, EarthModel::WGS84_EGM96)
                                        .with_simd(simd)
                                        .unwrap();
                                    [kernel, kernel.with_parallel_min_sat_steps(0)]
                                });
                        for kernel in kernels {
                            let simd = kernel.simd();
                            for threads in [1, 2, 4] {
                                let pool = rayon::ThreadPoolBuilder::new()
                                    .num_threads(threads)
                                    .build()
                                    .unwrap();
                                let got = pool.install(|| fused(&c, &kernel, inputs, interval));
                                let what = format!(
                                    "n {n} {gravity} {inputs:?} {interval:?} {} {threads} threads",
                                    simd.name()
                                );
                                assert_bitwise(&got, &want, &what);
                                tested += 1;
                            }
                        }
                    }
                }
            }
        }
        assert!(tested >= 4 * 2 * 3 * 3 * 3);
    }

    /// With drag in a one-layer exponential atmosphere (co-rotating or not, satellites of different
    /// C_d A / m, some with none), every copy on 1 and 2 threads gives the bits of the generic RK4 whose
    /// right-hand side is the force set (gravity + drag) plus the held acceleration, as the engine's
    /// generic path forms it.
    #[test]
    fn with_exponential_drag_bitwise_identical_to_the_generic_rk4_on_the_force_set() {
        use crate::dynamics::{ForceSet, ForcesConfig, PhysicalProperties};
        let earth = EarthModel::WGS84_EGM96;
        let epoch = crate::time::parse_epoch_utc("2026-06-01T00:00:00Z").unwrap();
        let n = 45;
        let c = case(n, 9);
        let properties: Vec<PhysicalProperties> = (0..n)
            .map(|i| PhysicalProperties {
                mass_kg: 3.0 + i as f64,
                drag_area_m2: if i % 6 == 1 {
                    0.0
                } else {
                    0.01 * (1 + i % 4) as f64
                },
                drag_coefficient: 2.2,
                srp_area_m2: 0.0,
                reflectivity_coefficient: 0.0,
            })
            .collect();
        let areas: Vec<f64> = properties
            .iter()
            .map(PhysicalProperties::drag_area_per_mass_m2_per_kg)
            .collect();
        for (gravity, corotation) in [("j2", true), ("point-mass", false)] {
            let text = format!(
                "[gravity]\nmodel = \"{gravity}\"\n[drag]\natmosphere = \"exponential\"\n\
                 reference_density_kg_per_m3 = 3.725e-12\nreference_altitude_m = 400e3\n\
                 scale_height_m = 58515.0\ncorotation = {corotation}\n"
            );
            let config: ForcesConfig = toml::from_str(&text).unwrap();
            let set = ForceSet::from_config(&config, &earth, epoch).unwrap();
            let (t0, t1, h) = (5.0, 95.5, 2.0);
            let mut rk = Rk4::new(10);
            let want: Vec<[f64; 10]> = c
                .blocks
                .iter()
                .enumerate()
                .map(|(i, block)| {
                    let mut y = *block;
                    if !c.active[i] {
                        return y;
                    }
                    let (u, w, p) = (c.control[i], c.command[i], properties[i]);
                    let rates = [w.x.abs(), w.y.abs(), w.z.abs(), w.norm()];
                    let rhs = |t: f64, y: &[f64], dy: &mut [f64]| {
                        let r = Vector3::new(y[0], y[1], y[2]);
                        let v = Vector3::new(y[3], y[4], y[5]);
                        let a = set.acceleration_eci_m_s2(&set.instant(t), &r, &v, &p) + u;
                        dy[0..3].copy_from_slice(&y[3..6]);
                        dy[3..6].copy_from_slice(a.as_slice());
                        dy[6..10].copy_from_slice(&rates);
                    };
                    rk.integrate(&rhs, t0, t1, &mut y, h);
                    y
                })
                .collect();
            let fast = set
                .fast_forces()
                .expect("gravity + exponential drag is a fast set");
            for simd in Simd::ALL.into_iter().filter(|s| s.is_available()) {
                let kernel = FusedRk4::for_forces(fast).with_simd(simd).unwrap();
                assert!(kernel.has_drag());
                for threads in [1, 2] {
                    let pool = rayon::ThreadPoolBuilder::new()
                        .num_threads(threads)
                        .build()
                        .unwrap();
                    let mut flat: Vec<f64> = (0..10)
                        .flat_map(|k| c.blocks.iter().map(move |b| b[k]))
                        .collect();
                    let inputs = SegmentInputs {
                        control_eci_m_s2: Some(&c.control),
                        ledger_command_hill_m_s2: Some(&c.command),
                        active: Some(&c.active),
                        drag_area_per_mass_m2_per_kg: Some(&areas),
                    };
                    pool.install(|| kernel.advance(&mut flat, n, &inputs, t0, t1, h))
                        .unwrap();
                    let got: Vec<[f64; 10]> = (0..n)
                        .map(|i| std::array::from_fn(|k| flat[k * n + i]))
                        .collect();
                    let what = format!(
                        "{gravity} drag corotation {corotation} {} {threads}",
                        simd.name()
                    );
                    assert_bitwise(&got, &want, &what);
                }
            }
            // And drag really acts: without it the states differ.
            let plain = FusedRk4::new(
                if gravity == "j2" {
                    GravityModel::J2
                } else {
                    GravityModel::TwoBody
                },
                earth,
            );
            let mut flat: Vec<f64> = (0..10)
                .flat_map(|k| c.blocks.iter().map(move |b| b[k]))
                .collect();
            let inputs = SegmentInputs {
                control_eci_m_s2: Some(&c.control),
                ledger_command_hill_m_s2: Some(&c.command),
                active: Some(&c.active),
                drag_area_per_mass_m2_per_kg: None,
            };
            plain.advance(&mut flat, n, &inputs, t0, t1, h).unwrap();
            let moved = (0..n).filter(|&i| {
                c.active[i] && properties[i].drag_area_m2 > 0.0 && flat[3 * n + i] != want[i][3]
            });
            assert!(moved.count() > n / 2);
        }
        // A drag kernel without the areas is refused.
        let kernel = FusedRk4::for_forces(crate::dynamics::FastForces::GravityExponentialDrag {
            gravity: GravityModel::J2,
            earth,
            atmosphere: crate::dynamics::Exponential {
                reference_density_kg_per_m3: 3.725e-12,
                reference_altitude_m: 400e3,
                scale_height_m: 58515.0,
            },
            corotation: true,
        });
        let mut state = vec![7e6; 30];
        assert!(matches!(
            kernel.advance(&mut state, 5, &SegmentInputs::default(), 0.0, 1.0, 1.0),
            Err(FusedError::MissingDragAreas)
        ));
    }

    #[test]
    fn an_empty_interval_changes_nothing_and_bad_input_is_refused() {
        let c = case(5, 1);
        let kernel = FusedRk4::new(GravityModel::J2, EarthModel::WGS84_EGM96);
        let inputs = (true, true, true);
        assert_bitwise(
            &fused(&c, &kernel, inputs, (3.0, 3.0, 1.0)),
            &c.blocks,
            "empty interval",
        );
        let mut state = vec![7e6; 29];
        let none = SegmentInputs::default();
        assert!(matches!(
            kernel.advance(&mut state, 5, &none, 0.0, 1.0, 1.0),
            Err(FusedError::Length {
                what: "state",
                got: 29,
                expected: 30
            })
        ));
        let short = [true; 4];
        let masked = SegmentInputs {
            active: Some(&short),
            ..none
        };
        let mut state = vec![7e6; 30];
        assert!(matches!(
            kernel.advance(&mut state, 5, &masked, 0.0, 1.0, 1.0),
            Err(FusedError::Length { what: "active", .. })
        ));
        for (t0, t1, h) in [
            (0.0, 1.0, 0.0),
            (0.0, 1.0, f64::NAN),
            (0.0, f64::INFINITY, 1.0),
        ] {
            assert!(matches!(
                kernel.advance(&mut state, 5, &none, t0, t1, h),
                Err(FusedError::Interval { .. })
            ));
        }
        assert!(state.iter().all(|&x| x == 7e6));
        let mut empty: Vec<f64> = Vec::new();
        kernel
            .advance(&mut empty, 0, &none, 0.0, 10.0, 1.0)
            .unwrap();
    }

    #[test]
    fn detect_names_an_available_copy() {
        assert!(Simd::detect().is_available());
        assert!(Simd::Portable.is_available());
        for simd in Simd::ALL {
            assert_eq!(
                Simd::NAMES.iter().position(|&n| n == simd.name()),
                Some(simd as usize)
            );
            let kernel = FusedRk4::new(GravityModel::J2, EarthModel::WGS84_EGM96);
            match kernel.with_simd(simd) {
                Ok(k) => assert_eq!(k.simd(), simd),
                Err(e) => assert_eq!(e, FusedError::Unavailable(simd)),
            }
        }
    }
}
