//! `satflock bench propagate`: N independent satellites under point mass + J2 (or point mass) with RK4
//! through the library's fused structure-of-arrays kernel ([`satflock::integrate::FusedRk4`]), timed on
//! the propagation alone (not the reading, generation or writing of states). With `--forces FILE.toml`
//! the force set of that file: on the fused kernel when it covers the set (gravity and exponential
//! drag), else on the generic path (each satellite alone through the generic RK4 on the force set,
//! satellites in parallel), which the JSON line names as `path`.
//!
//! Initial states come from a CSV with header `sat,x,y,z,vx,vy,vz` (m, m/s, EME2000), or are generated
//! deterministically: satellite `i` gets the orbit drawn from the splitmix64 stream seeded with `i`
//! (semi-major axis R + 400 to R + 1 200 km, eccentricity 0 to 0.01, inclination 0 to 180°, node,
//! argument of perigee and true anomaly 0 to 360°, each uniform; R the WGS 84 equatorial radius).

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result};
use clap::ValueEnum;
use rayon::prelude::*;
use satflock::dynamics::{ForceSet, ForcesConfig, PhysicalProperties};
use satflock::integrate::{FusedRk4, Rk4, SegmentInputs, Simd};
use satflock::orbit::{EarthModel, GravityModel, KeplerianElements};

use crate::{usage, GravityArg, MAX_THREADS};

/// Most satellites (`--n`): 48 bytes each in memory.
const MAX_SATELLITES: u64 = 100_000_000;
/// Most steps (`--duration-s` / `--step-s`).
const MAX_STEPS: f64 = 1e9;
/// The CSV header of initial and final states.
const HEADER: [&str; 7] = ["sat", "x", "y", "z", "vx", "vy", "vz"];

/// Which copy of the kernel runs (all give the same bits).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SimdArg {
    /// The widest this CPU has.
    Auto,
    /// Baseline x86-64 (SSE2).
    Portable,
    /// AVX2.
    Avx2,
    /// AVX-512F.
    Avx512,
}

/// Options of `satflock bench propagate`.
#[derive(clap::Args)]
pub struct PropagateBenchArgs {
    /// Number of satellites, 1 to 100 000 000 (with --initial-states: the first N rows; default all).
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..=MAX_SATELLITES))]
    n: Option<u64>,
    /// Propagation time [s], finite and > 0.
    #[arg(long)]
    duration_s: f64,
    /// RK4 step [s], finite and > 0, at most 1e9 steps over the duration.
    #[arg(long, default_value_t = 1.0)]
    step_s: f64,
    /// Initial states: CSV with header sat,x,y,z,vx,vy,vz (m, m/s, EME2000). Default: generated.
    #[arg(long)]
    initial_states: Option<PathBuf>,
    /// Worker threads, 1 to 1024 (default: all cores). Results do not depend on it.
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..=MAX_THREADS))]
    threads: Option<u16>,
    /// Gravity model (default j2), without --forces.
    #[arg(long, value_enum)]
    gravity: Option<GravityArg>,
    /// Copy of the kernel (same bits; `auto` is the widest the CPU has).
    #[arg(long, value_enum, default_value = "auto")]
    simd: SimdArg,
    /// Also write every final state to this CSV (header sat,x,y,z,vx,vy,vz).
    #[arg(long)]
    write_final: Option<PathBuf>,
    /// A force file (as `satflock propagate --forces`) instead of --gravity; every satellite has its
    /// [satellite] properties. Its epoch of t = 0 is the default scenario epoch.
    #[arg(long, conflicts_with = "gravity")]
    forces: Option<PathBuf>,
}

/// Runs the benchmark and prints its JSON line.
pub fn run(args: &PropagateBenchArgs) -> Result<()> {
    for (option, value) in [("--duration-s", args.duration_s), ("--step-s", args.step_s)] {
        if !(value.is_finite() && value > 0.0) {
            return Err(usage(format!(
                "{option} {value} is out of range (allowed: finite, > 0)"
            )));
        }
    }
    if args.duration_s / args.step_s > MAX_STEPS {
        return Err(usage(format!(
            "--step-s {} gives more than 1e9 steps over --duration-s {} (allowed: at most 1e9 steps)",
            args.step_s, args.duration_s
        )));
    }
    let gravity = match args.gravity.unwrap_or(GravityArg::J2) {
        GravityArg::J2 => GravityModel::J2,
        GravityArg::TwoBody => GravityModel::TwoBody,
    };
    let earth = EarthModel::WGS84_EGM96;
    let (forces, properties) = match &args.forces {
        Some(path) => {
            let config = ForcesConfig::from_file(path).map_err(|e| usage(e.to_string()))?;
            let invalid =
                |e: satflock::dynamics::ForceConfigError| usage(format!("{}: {e}", path.display()));
            let epoch = satflock::time::parse_epoch_utc(satflock::time::DEFAULT_EPOCH_UTC)
                .map_err(usage)?;
            let set = ForceSet::from_config(&config, &earth, epoch).map_err(invalid)?;
            (set, config.satellite_properties().map_err(invalid)?)
        }
        None => (
            ForceSet::gravity(gravity, earth),
            PhysicalProperties::point_mass(1.0),
        ),
    };
    let fast = forces.fast_forces();
    let mut kernel = match fast {
        Some(f) => FusedRk4::for_forces(f),
        None => FusedRk4::new(gravity, earth),
    };
    let simd = match args.simd {
        SimdArg::Auto => None,
        SimdArg::Portable => Some(Simd::Portable),
        SimdArg::Avx2 => Some(Simd::Avx2),
        SimdArg::Avx512 => Some(Simd::Avx512),
    };
    if let Some(simd) = simd {
        kernel = kernel.with_simd(simd).map_err(|e| {
            usage(format!(
                "--simd {}: {e} (allowed here: {})",
                simd.name(),
                Simd::ALL
                    .iter()
                    .filter(|s| s.is_available())
                    .map(|s| s.name())
                    .collect::<Vec<_>>()
                    .join(", ")
            ))
        })?;
    }
    let (ids, states) = match &args.initial_states {
        Some(path) => read_states(path, args.n)?,
        None => {
            let n = args
                .n
                .ok_or_else(|| usage("give --n (1 to 100000000) or --initial-states FILE.csv"))?
                as usize;
            ((0..n as u64).collect(), generated_states(n, &earth))
        }
    };
    let n = ids.len();
    // Component-major: x[0..n], y[0..n], ..., vz[0..n].
    let mut flat: Vec<f64> = (0..6)
        .flat_map(|k| states.iter().map(move |s| s[k]))
        .collect();
    drop(states);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.map_or(0, usize::from))
        .build()
        .context("cannot start the thread pool")?;
    let threads = pool.current_num_threads();
    let areas = vec![properties.drag_area_per_mass_m2_per_kg(); n];
    let inputs = SegmentInputs {
        drag_area_per_mass_m2_per_kg: kernel.has_drag().then_some(&areas[..]),
        ..SegmentInputs::default()
    };
    let start = Instant::now();
    if fast.is_some() {
        pool.install(|| kernel.advance(&mut flat, n, &inputs, 0.0, args.duration_s, args.step_s))?;
    } else {
        pool.install(|| generic(&forces, &properties, &mut flat, n, args));
    }
    let wall_s = start.elapsed().as_secs_f64();
    let steps = Rk4::step_count(0.0, args.duration_s, args.step_s);
    let first: Vec<f64> = (0..6).map(|k| flat[k * n]).collect();
    if let Some(path) = &args.write_final {
        write_states(path, &ids, &flat, n)?;
    }
    let line = serde_json::json!({
        "peer": "satflock",
        "n": n,
        "steps": steps,
        "wall_s": wall_s,
        "sat_steps_per_s": (n * steps) as f64 / wall_s,
        "threads": threads,
        "simd": kernel.simd().name(),
        "gravity": gravity.name(),
        "forces": forces.summary().models,
        "path": if fast.is_some() { "fused" } else { "generic" },
        "step_s": args.step_s,
        "duration_s": args.duration_s,
        "final_state_first_sat": first,
    });
    println!("{line}");
    Ok(())
}

/// Every satellite alone through the generic RK4 on `forces` (the engine's generic sampled path without
/// commands), in parallel over chunks of satellites, on the component-major state `flat`.
fn generic(
    forces: &ForceSet,
    properties: &PhysicalProperties,
    flat: &mut [f64],
    n: usize,
    args: &PropagateBenchArgs,
) {
    const CHUNK: usize = 256;
    let mut blocks: Vec<[f64; 6]> = (0..n)
        .map(|i| std::array::from_fn(|k| flat[k * n + i]))
        .collect();
    blocks.par_chunks_mut(CHUNK).for_each(|chunk| {
        let mut rk = Rk4::new(6);
        for y in chunk {
            let rhs = |t: f64, y: &[f64], dy: &mut [f64]| {
                let r = satflock::orbit::Vector3::new(y[0], y[1], y[2]);
                let v = satflock::orbit::Vector3::new(y[3], y[4], y[5]);
                let a = forces.acceleration_eci_m_s2(&forces.instant(t), &r, &v, properties);
                dy[0..3].copy_from_slice(&y[3..6]);
                dy[3..6].copy_from_slice(a.as_slice());
            };
            rk.integrate(&rhs, 0.0, args.duration_s, y, args.step_s);
        }
    });
    for (i, y) in blocks.iter().enumerate() {
        for (k, value) in y.iter().enumerate() {
            flat[k * n + i] = *value;
        }
    }
}

/// Deterministic numbers in [0, 1) from the splitmix64 stream seeded with `seed`.
fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The generated swarm (see the module documentation).
fn generated_states(n: usize, earth: &EarthModel) -> Vec<[f64; 6]> {
    use std::f64::consts::{PI, TAU};
    (0..n as u64)
        .map(|i| {
            let mut next = uniform(i);
            let s = KeplerianElements {
                semi_major_axis_m: earth.equatorial_radius_m + 400e3 + 800e3 * next(),
                eccentricity: 0.01 * next(),
                inclination_rad: PI * next(),
                raan_rad: TAU * next(),
                arg_perigee_rad: TAU * next(),
                true_anomaly_rad: TAU * next(),
            }
            .to_cartesian(earth.mu_m3_s2)
            .expect("elliptic elements in range always convert");
            let (p, v) = (s.position_m, s.velocity_mps);
            [p.x, p.y, p.z, v.x, v.y, v.z]
        })
        .collect()
}

/// Reads `sat,x,y,z,vx,vy,vz` rows (the first `n`, or all).
fn read_states(path: &Path, n: Option<u64>) -> Result<(Vec<u64>, Vec<[f64; 6]>)> {
    let shown = format!("--initial-states {}", path.display());
    let bad = |e: &dyn std::fmt::Display| usage(format!("{shown}: {e}"));
    let mut reader = satflock::input_file::open(path, satflock::input_file::MAX_TABLE_BYTES)
        .map(csv::Reader::from_reader)
        .map_err(|e| bad(&e))?;
    let header = reader.headers().map_err(|e| bad(&e))?;
    if header.iter().map(str::trim).ne(HEADER) {
        return Err(bad(&format!(
            "the header must be {} (got {})",
            HEADER.join(","),
            header.iter().collect::<Vec<_>>().join(",")
        )));
    }
    let mut ids = Vec::new();
    let mut states = Vec::new();
    for (row, record) in reader.records().enumerate() {
        if n.is_some_and(|n| ids.len() as u64 >= n) {
            break;
        }
        let record = record.map_err(|e| bad(&e))?;
        let line = row + 2;
        let id: u64 = record[0].trim().parse().map_err(|_| {
            bad(&format!(
                "line {line}: sat {:?} is not an integer >= 0",
                &record[0]
            ))
        })?;
        let mut state = [0.0; 6];
        for (k, value) in state.iter_mut().enumerate() {
            *value = record[k + 1]
                .trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    bad(&format!(
                        "line {line}: {} {:?} is not a finite number",
                        HEADER[k + 1],
                        &record[k + 1]
                    ))
                })?;
        }
        if state[..3].iter().all(|&c| c == 0.0) {
            return Err(bad(&format!("line {line}: the position is at the origin")));
        }
        ids.push(id);
        states.push(state);
    }
    match n {
        Some(n) if (ids.len() as u64) < n => Err(bad(&format!(
            "--n {n} is out of range (allowed: 1 to the file's {} rows)",
            ids.len()
        ))),
        _ if ids.is_empty() => Err(bad(&"no rows (allowed: at least one satellite)")),
        _ => Ok((ids, states)),
    }
}

/// Writes every satellite's final state (component-major `flat`) with the input's ids.
fn write_states(path: &Path, ids: &[u64], flat: &[f64], n: usize) -> Result<()> {
    let shown = format!("--write-final {}", path.display());
    let mut writer = csv::Writer::from_path(path).with_context(|| shown.clone())?;
    writer.write_record(HEADER).with_context(|| shown.clone())?;
    for (i, id) in ids.iter().enumerate() {
        let mut row = vec![id.to_string()];
        row.extend((0..6).map(|k| flat[k * n + i].to_string()));
        writer.write_record(&row).with_context(|| shown.clone())?;
    }
    writer.flush().with_context(|| shown.clone())?;
    Ok(())
}
