//! The Takahashi–Sakai Θ2 split (`satflock validate takahashi-split`): how often the Θ2 deployment
//! (`ts-plane-2`) splits during its first 4 h, over seeds 1–20, with the paper's grouping (Algorithm 1)
//! and with the connectivity-preserving grouping, an extension beyond the paper (method page
//! `docs/methods/j2-distance.md` §9.6).
//!
//! **Split**, as measured here: a run splits if, at some grouping update within the 4 h, the grouping
//! graph over the live satellites has more than one connected component, i.e. `summary.json`'s
//! `law.grouping.max_components` > 1 (equivalently `law.grouping.always_connected` = false;
//! `law.grouping.first_disconnected_s` is the first such update, and the `ts_components` column of
//! `metrics.csv` samples the same count at the recording times). `ts-plane-2` removes no satellite and
//! cuts no link, so this is the swarm's interaction graph coming apart.
//!
//! The 40 runs (20 seeds × 2 groupings) go through one call of [`satflock::campaign::pool::run_bounded`]; the
//! campaign files `campaigns/ts-plane-2-split.toml` and `campaigns/ts-plane-2-split-preserving.toml`
//! describe the same runs for `satflock campaign`.

use satflock::guidance::LawConfig;

use super::data::{Outcome, PaperData};
use super::takahashi::{scenario, traced_run};
use super::{Check, Report, Table, ValidateError, Verdict};

/// Seeds of the showcase: 1 to this number.
pub const SEEDS: u64 = 20;

/// Simulated time of every run \[s\] (the first 4 h of `ts-plane-2`; its grouping schedule keeps the
/// scenario's 120 h end, so the grouping runs every 5 min as in the full run).
pub const DURATION_S: f64 = 4.0 * 3600.0;

/// Interval of the samples of C₁…C₆ behind [`SplitRun::peak_max_c4_m`] \[s\].
pub const SAMPLE_S: f64 = 900.0;

/// One run of `ts-plane-2` for the showcase: what its law results say at the end.
#[derive(Clone, Debug, PartialEq)]
pub struct SplitRun {
    /// Seed of the run.
    pub seed: u64,
    /// Whether the connectivity-preserving grouping was on.
    pub preserve_connectivity: bool,
    /// Largest number of connected components of the grouping graph over the updates.
    pub max_components: u64,
    /// Components at the last update.
    pub final_components: u64,
    /// Time of the first update whose grouping graph was not connected \[s\] (`None`: never split).
    pub first_split_s: Option<f64>,
    /// Updates at which the preserving grouping added edges.
    pub repairs: u64,
    /// Edges it added, summed over the updates.
    pub repair_edges: u64,
    /// max|C₁| relative to the reference satellite at the end \[m\].
    pub max_c1_m: f64,
    /// max|C₄| relative to the reference satellite at the end \[m\].
    pub max_c4_m: f64,
    /// Largest max|C₄| relative to the reference satellite over samples every [`SAMPLE_S`] \[m\]: how
    /// far the swarm came apart on the way.
    pub peak_max_c4_m: f64,
}

impl SplitRun {
    /// Whether the run split (see the module docs).
    pub fn split(&self) -> bool {
        self.max_components > 1
    }
}

/// Runs `ts-plane-2` with `seed` for `duration_s` \[s\], with or without the connectivity-preserving
/// grouping (the parameter absent, i.e. the paper's grouping, when `preserve_connectivity` is false).
pub fn split_run(
    seed: u64,
    preserve_connectivity: bool,
    duration_s: f64,
) -> Result<SplitRun, String> {
    let mut s = scenario("ts-plane-2", None, Some(duration_s))?;
    s.file.seed = seed;
    // The samples of C are taken at recordings.
    s.file.record_interval_s = SAMPLE_S;
    if preserve_connectivity {
        match &mut s.file.law {
            LawConfig::J2Distance(p) => p.preserve_connectivity = true,
            other => return Err(format!("ts-plane-2 runs {other:?}, not j2-distance")),
        }
    }
    let run = traced_run(&s, SAMPLE_S, f64::INFINITY)?;
    let g = &run.law["grouping"];
    let count = |key: &str| {
        g[key]
            .as_u64()
            .ok_or_else(|| format!("seed {seed}: no law.grouping.{key} in the results"))
    };
    let number = |key: &str| run.law[key].as_f64().unwrap_or(f64::NAN);
    Ok(SplitRun {
        seed,
        preserve_connectivity,
        max_components: count("max_components")?,
        final_components: count("components")?,
        first_split_s: g["first_disconnected_s"].as_f64(),
        repairs: count("connectivity_repairs")?,
        repair_edges: count("connectivity_repair_edges")?,
        max_c1_m: number("max_abs_c1_m"),
        max_c4_m: number("max_abs_c4_m"),
        peak_max_c4_m: run
            .parameters
            .iter()
            .flatten()
            .map(|c| c.c4_m.abs())
            .fold(0.0, f64::max),
    })
}

fn failed(message: impl ToString) -> ValidateError {
    ValidateError::Failed {
        target: "takahashi-split".into(),
        message: message.to_string(),
    }
}

fn verdict(pass: bool) -> Verdict {
    if pass {
        Verdict::Reproduced
    } else {
        Verdict::Differs
    }
}

/// Median of a non-empty list (mean of the middle two for an even count).
fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    if v.len() % 2 == 1 {
        v[m]
    } else {
        0.5 * (v[m - 1] + v[m])
    }
}

/// The runs of `runs` that split.
fn split<'a>(runs: &[&'a SplitRun]) -> Vec<&'a SplitRun> {
    runs.iter().copied().filter(|r| r.split()).collect()
}

fn seed_list(runs: &[&SplitRun]) -> String {
    if runs.is_empty() {
        return "none".into();
    }
    runs.iter()
        .map(|r| r.seed.to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

/// The data file (`validation/takahashi-split.toml`).
pub fn data() -> Result<PaperData, ValidateError> {
    PaperData::of("takahashi-split").ok_or_else(|| failed("no validation/takahashi-split.toml"))?
}

/// The runs, by grouping.
struct Groups<'a> {
    /// The paper's grouping (Algorithm 1).
    paper: Vec<&'a SplitRun>,
    /// The connectivity-preserving grouping (extension).
    kept: Vec<&'a SplitRun>,
}

/// First split times of the runs that split, as "lo–hi h".
fn hours(rs: &[&SplitRun]) -> String {
    let t: Vec<f64> = rs
        .iter()
        .filter_map(|r| r.first_split_s)
        .map(|s| s / 3600.0)
        .collect();
    match (
        t.iter().copied().reduce(f64::min),
        t.iter().copied().reduce(f64::max),
    ) {
        (Some(lo), Some(hi)) => format!("{lo:.2}–{hi:.2} h"),
        _ => "—".into(),
    }
}

fn fraction(k: usize, n: usize) -> String {
    format!("{k}/{n} = {:.2}", k as f64 / n as f64)
}

fn c4(rs: &[&SplitRun]) -> Vec<f64> {
    rs.iter().map(|r| r.max_c4_m).collect()
}

fn largest(v: Vec<f64>) -> f64 {
    v.into_iter().fold(f64::NEG_INFINITY, f64::max)
}

fn s1(o: &Outcome, g: &Groups) -> Result<Check, ValidateError> {
    let up_to = o.value("compare_up_to_seed")?;
    let expected: Vec<u64> = o
        .values
        .iter()
        .filter(|(k, _)| k.starts_with("split_seed_"))
        .map(|(_, v)| *v as u64)
        .collect();
    let paper_split = split(&g.paper);
    let first: Vec<&SplitRun> = paper_split
        .iter()
        .copied()
        .filter(|r| r.seed as f64 <= up_to)
        .collect();
    Ok(o.check(
        format!(
            "seeds 1–{up_to:.0}: {}; all seeds: {} split (seeds {}), first split at {}",
            seed_list(&first),
            fraction(paper_split.len(), g.paper.len()),
            seed_list(&paper_split),
            hours(&paper_split)
        ),
        verdict(first.iter().map(|r| r.seed).eq(expected)),
    ))
}

fn s2(o: &Outcome, g: &Groups) -> Result<Check, ValidateError> {
    let kept_split = split(&g.kept);
    Ok(o.check(
        format!(
            "{} split (seeds {}); repairs in {} runs, {} updates and {} edges in total",
            fraction(kept_split.len(), g.kept.len()),
            seed_list(&kept_split),
            g.kept.iter().filter(|r| r.repairs > 0).count(),
            g.kept.iter().map(|r| r.repairs).sum::<u64>(),
            g.kept.iter().map(|r| r.repair_edges).sum::<u64>()
        ),
        verdict(kept_split.len() as f64 <= o.value("max_split_runs")?),
    ))
}

fn s3(o: &Outcome, g: &Groups) -> Result<Check, ValidateError> {
    let max_c4_kept = largest(c4(&g.kept));
    Ok(o.check(
        format!(
            "largest {max_c4_kept:.2} m (median {:.2} m); paper's grouping: largest {:.2} m, median {:.2} m",
            median(c4(&g.kept)),
            largest(c4(&g.paper)),
            median(c4(&g.paper))
        ),
        verdict(max_c4_kept < o.value("max_c4_m")?),
    ))
}

/// The summary table: one row per grouping.
fn summary(g: &Groups) -> Table {
    let summary_row = |label: &str, rs: &[&SplitRun], parameter: &str| -> Vec<String> {
        let s = split(rs);
        vec![
            label.into(),
            parameter.into(),
            fraction(s.len(), rs.len()),
            seed_list(&s),
            hours(&s),
            rs.iter()
                .filter(|r| r.final_components > 1)
                .count()
                .to_string(),
            format!(
                "{} / {} / {}",
                rs.iter().filter(|r| r.repairs > 0).count(),
                rs.iter().map(|r| r.repairs).sum::<u64>(),
                rs.iter().map(|r| r.repair_edges).sum::<u64>()
            ),
            format!(
                "{:.3} / {:.3}",
                median(rs.iter().map(|r| r.max_c1_m).collect()),
                largest(rs.iter().map(|r| r.max_c1_m).collect())
            ),
            format!("{:.2} / {:.2}", median(c4(rs)), largest(c4(rs))),
            format!(
                "{:.2} / {:.2}",
                median(rs.iter().map(|r| r.peak_max_c4_m).collect()),
                largest(rs.iter().map(|r| r.peak_max_c4_m).collect())
            ),
        ]
    };
    Table {
        title: format!(
            "Θ2 split fraction, ts-plane-2, seeds 1–{SEEDS}, first {:.0} h (split: grouping graph not connected at some update)",
            DURATION_S / 3600.0
        ),
        header: [
            "grouping",
            "[law] parameter",
            "split fraction",
            "seeds that split",
            "first split",
            "runs still split at the end",
            "runs with repairs / repair updates / edges added",
            "max|C1| at end, median / max [m]",
            "max|C4| at end, median / max [m]",
        ]
        .map(String::from)
        .into_iter()
        .chain([format!(
            "peak max|C4| ({:.0} min samples), median / max [m]",
            SAMPLE_S / 60.0
        )])
        .collect(),
        rows: vec![
            summary_row(
                "paper (Algorithm 1)",
                &g.paper,
                "preserve_connectivity absent (false)",
            ),
            summary_row(
                "connectivity-preserving (extension)",
                &g.kept,
                "preserve_connectivity = true",
            ),
        ],
    }
}

/// The per-seed table.
fn per_seed(g: &Groups) -> Table {
    Table {
        title: "By seed".into(),
        header: [
            "seed",
            "paper: first split",
            "paper: max|C4| at end / peak [m]",
            "preserving: repair updates (edges)",
            "preserving: components max / end",
            "preserving: max|C4| at end / peak [m]",
        ]
        .map(String::from)
        .to_vec(),
        rows: g
            .paper
            .iter()
            .zip(&g.kept)
            .map(|(p, k)| {
                vec![
                    p.seed.to_string(),
                    p.first_split_s
                        .map_or("—".into(), |s| format!("{:.2} h", s / 3600.0)),
                    format!("{:.2} / {:.2}", p.max_c4_m, p.peak_max_c4_m),
                    format!("{} ({})", k.repairs, k.repair_edges),
                    format!("{} / {}", k.max_components, k.final_components),
                    format!("{:.2} / {:.2}", k.max_c4_m, k.peak_max_c4_m),
                ]
            })
            .collect(),
    }
}

/// The report: 40 runs of 100 satellites under truth J2, 4 h each (about 2 s of CPU per run on
/// one thread; the wall time is in the saved measurement).
pub fn report() -> Result<Report, ValidateError> {
    let data = data()?;
    let jobs: Vec<(u64, bool)> = [false, true]
        .into_iter()
        .flat_map(|preserve| (1..=SEEDS).map(move |seed| (seed, preserve)))
        .collect();
    let runs: Vec<SplitRun> = satflock::campaign::pool::run_bounded(
        jobs,
        rayon::current_num_threads(),
        |(seed, preserve)| split_run(seed, preserve, DURATION_S),
    )
    .map_err(failed)?
    .into_iter()
    .collect::<Result<_, _>>()
    .map_err(failed)?;
    let (paper, kept): (Vec<&SplitRun>, Vec<&SplitRun>) =
        runs.iter().partition(|r| !r.preserve_connectivity);
    let g = Groups { paper, kept };
    let checks = vec![
        s1(data.outcome("S1")?, &g)?,
        s2(data.outcome("S2")?, &g)?,
        s3(data.outcome("S3")?, &g)?,
    ];
    let satellites = scenario("ts-plane-2", None, None)
        .and_then(|s| s.prepare().map_err(|e| e.to_string()))
        .map_err(failed)?
        .satellites
        .len();
    Ok(data.report(checks, vec![summary(&g), per_seed(&g)], vec![format!(
            "Runs: ts-plane-2 ({satellites} satellites, truth J2, defaults of docs/methods/j2-distance.md §10), duration_s = {DURATION_S}, seeds 1–{SEEDS}, each grouping; {} runs through satflock::campaign::pool::run_bounded, each on one thread. A run splits if its grouping graph over the live satellites has more than one connected component at some grouping update (summary.json: law.grouping.max_components > 1). The same runs as a campaign: campaigns/ts-plane-2-split.toml and campaigns/ts-plane-2-split-preserving.toml.",
            runs.len()
        )]))
}
