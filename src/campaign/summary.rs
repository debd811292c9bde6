//! Statistics of a campaign: per parameter point, the median and the 5 % and 95 % percentiles of each
//! headline outcome over the point's completed runs, and its failure count; written as `summary.md`.
//!
//! Percentiles: [`crate::output::spread`] (linear interpolation between order statistics, as in
//! `satflock compare`).

use super::file::Campaign;
use super::manifest::{RunRecord, Status};
use crate::output::outcomes::RunTable;
use crate::output::spread::Spread;

/// Name of the summary in the output directory.
pub const FILE_NAME: &str = "summary.md";

/// The headline outcomes summarised when the campaign file names none, in this order (those the runs
/// have), followed by every outcome of the law (`law.*`).
pub const DEFAULT_OUTCOMES: &[&str] = &[
    "delta_v_mps.mean",
    "delta_v_mps.max",
    "min_separation_m",
    "collisions",
    "final.five_elements.d_max_m",
    "final.five_elements.uniformity_l",
    "environment.closest_threat_approach.minimum.distance_m",
    "environment.threat_incursions",
    "environment.min_obstacle_clearance.minimum.clearance_m",
    "environment.obstacle_incursions",
];

/// Every scalar outcome a run's `summary.json` can have (by [`crate::output::outcomes::scalar_outcomes`]),
/// besides the law's own `law.*` and the components of [`VECTOR_OUTCOMES`]: what a campaign file's
/// `outcomes` may name.
pub const KNOWN_OUTCOMES: &[&str] = &[
    "collisions",
    "delta_v_mps.max",
    "delta_v_mps.mean",
    "duration_s",
    "environment.closest_threat_approach.minimum.distance_m",
    "environment.closest_threat_approach.minimum.time_s",
    "environment.closest_threat_approach.object",
    "environment.closest_threat_approach.satellite",
    "environment.min_obstacle_clearance.minimum.clearance_m",
    "environment.min_obstacle_clearance.minimum.time_s",
    "environment.min_obstacle_clearance.object",
    "environment.min_obstacle_clearance.satellite",
    "environment.obstacle_incursions",
    "environment.threat_incursions",
    "final.five_elements.d_max_m",
    "final.five_elements.d_min_m",
    "final.five_elements.diameter_m",
    "final.five_elements.n",
    "final.five_elements.uniformity_l",
    "min_separation_m",
    "n_satellites",
    "satellite_steps_per_s",
    "simulated_s",
    "tai_minus_utc_s",
    "tt_minus_utc_s",
    "wall_time_s",
];

/// Outcomes that are short arrays: `NAME.K` is component K (from 0; per-satellite arrays only for
/// swarms of at most [`crate::output::outcomes::MAX_VECTOR_LEN`] satellites).
pub const VECTOR_OUTCOMES: &[&str] = &[
    "delta_v_mps.mean_per_axis_hill",
    "delta_v_mps.per_satellite",
    "environment.min_obstacle_clearance_per_satellite_m",
    "environment.min_threat_distance_per_satellite_m",
    "final.five_elements.r_o_m",
    "final.five_elements.v_o_mps",
];

/// Whether `name` is an outcome a run can have: one of [`KNOWN_OUTCOMES`], a component `K` of one of
/// [`VECTOR_OUTCOMES`], or a law's own result `law.NAME` (each law has its own).
pub fn is_known_outcome(name: &str) -> bool {
    if KNOWN_OUTCOMES.contains(&name) {
        return true;
    }
    if let Some(rest) = name.strip_prefix("law.") {
        return !rest.is_empty();
    }
    name.rsplit_once('.').is_some_and(|(vector, k)| {
        VECTOR_OUTCOMES.contains(&vector)
            && k.parse::<usize>()
                .is_ok_and(|k| k < crate::output::outcomes::MAX_VECTOR_LEN)
    })
}

/// The outcomes to summarise: the campaign file's `outcomes`, or [`DEFAULT_OUTCOMES`] that the table
/// has followed by its `law.*` columns.
pub fn headline_outcomes(campaign: &Campaign, table: &RunTable) -> Vec<String> {
    if let Some(named) = &campaign.outcomes {
        return named.clone();
    }
    let has = |name: &str| table.numbers(name).is_some();
    DEFAULT_OUTCOMES
        .iter()
        .filter(|n| has(n))
        .map(|n| n.to_string())
        .chain(
            table
                .numbers
                .iter()
                .filter(|(n, _)| n.starts_with("law."))
                .map(|(n, _)| n.clone()),
        )
        .collect()
}

/// A number in at most 6 significant digits, no trailing zeros (scientific below 10⁻³ and from 10⁶).
fn short(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && !(1e-3..1e6).contains(&a) {
        let text = format!("{v:.5e}");
        let (mantissa, exponent) = text.split_once('e').unwrap_or((&text, "0"));
        let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
        return format!("{mantissa}e{exponent}");
    }
    let decimals = if a == 0.0 {
        0
    } else {
        (5 - a.log10().floor() as i32).clamp(0, 8) as usize
    };
    let text = format!("{v:.decimals$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

/// The text of `summary.md` for `records` (the last record of every finished run) and their `table`;
/// `dropped` lists the manifest lines `--resume` did not keep.
pub fn markdown(
    campaign: &Campaign,
    records: &[RunRecord],
    table: &RunTable,
    dropped: &[String],
) -> String {
    let count = |status: Status| records.iter().filter(|r| r.status == status).count();
    let mut out = format!("# Campaign `{}`\n\n", campaign.file);
    if !campaign.description.trim().is_empty() {
        out.push_str(&format!("{}\n\n", campaign.description.trim()));
    }
    let seeds: Vec<String> = campaign.seeds.iter().map(u64::to_string).collect();
    out.push_str(&format!(
        "Scenario `{}`; {} runs: {} parameter point(s) × {} seed(s) ({}). Finished: {} of {} — {} \
         completed, {} failed, {} refused, {} interrupted.\n\n",
        campaign.scenario.source,
        campaign.run_count(),
        campaign.points.len(),
        campaign.seeds.len(),
        seeds.join(", "),
        records.len(),
        campaign.run_count(),
        count(Status::Completed),
        count(Status::Failed),
        count(Status::Refused),
        count(Status::Interrupted),
    ));
    if let Some(s) = campaign.sampling {
        out.push_str(&format!(
            "Ranges sampled by {} with {} samples (sampling seed {}), shared by every point of the \
             value lists' grid.\n\n",
            match s.method {
                super::sampling::Method::LatinHypercube => "Latin hypercube",
                super::sampling::Method::Random => "independent uniform draws",
            },
            s.samples,
            s.seed
        ));
    }
    out.push_str(
        "Statistics over each point's completed runs: the median and the 5 % and 95 % percentiles \
         (linear interpolation between order statistics, numpy's default); `n` is the number of \
         completed runs that have the outcome. Every run's values are in `campaign.parquet`.\n\n",
    );
    out.push_str(&format!(
        "Campaign file SHA-256 `{}`; satflock {}.\n\n",
        campaign.sha256,
        env!("CARGO_PKG_VERSION")
    ));

    if !dropped.is_empty() {
        out.push_str(&format!(
            "## Manifest lines dropped by `--resume`\n\n{} line(s) did not read as a run record or \
             did not match their run's directory or the campaign; a run that no kept line records as \
             completed was run again.\n\n",
            dropped.len()
        ));
        for line in dropped {
            out.push_str(&format!("- {line}\n"));
        }
        out.push('\n');
    }

    let keys: Vec<String> = campaign
        .parameters
        .iter()
        .map(|p| format!("`{}`", p.key))
        .collect();
    let header = |extra: &str| {
        let mut h = String::from("| point |");
        let mut rule = String::from("| ---: |");
        for k in &keys {
            h.push_str(&format!(" {k} |"));
            rule.push_str(" ---: |");
        }
        for e in extra.split(',') {
            h.push_str(&format!(" {e} |"));
            rule.push_str(" ---: |");
        }
        format!("{h}\n{rule}\n")
    };
    let point_cells = |point: usize| {
        let mut row = format!("| {point} |");
        for value in &campaign.points[point] {
            let text = match super::table::number(value) {
                Some(v) => short(v),
                None => value.to_string(),
            };
            row.push_str(&format!(" {text} |"));
        }
        row
    };

    out.push_str("## Runs per point\n\n");
    out.push_str(&header("runs,completed,failed,refused,interrupted,not run"));
    for point in 0..campaign.points.len() {
        let of_point: Vec<&RunRecord> = records.iter().filter(|r| r.point == point).collect();
        let by = |s: Status| of_point.iter().filter(|r| r.status == s).count();
        out.push_str(&format!(
            "{} {} | {} | {} | {} | {} | {} |\n",
            point_cells(point),
            campaign.seeds.len(),
            by(Status::Completed),
            by(Status::Failed),
            by(Status::Refused),
            by(Status::Interrupted),
            campaign.seeds.len() - of_point.len(),
        ));
    }

    let status = table.text("status").unwrap_or_default();
    let points = table.numbers("point").unwrap_or_default();
    for outcome in headline_outcomes(campaign, table) {
        out.push_str(&format!("\n## `{outcome}`\n\n"));
        let Some(values) = table.numbers(&outcome) else {
            out.push_str("No run has this outcome.\n");
            continue;
        };
        out.push_str(&header("n,median,5 %,95 %"));
        for point in 0..campaign.points.len() {
            let completed: Vec<f64> = (0..values.len())
                .filter(|&r| points[r] == point as f64 && status[r] == "completed")
                .map(|r| values[r])
                .collect();
            let spread = Some(Spread::of(&completed)).filter(|s| s.count > 0);
            out.push_str(&match spread {
                Some(s) => format!(
                    "{} {} | {} | {} | {} |\n",
                    point_cells(point),
                    s.count,
                    short(s.median),
                    short(s.p05),
                    short(s.p95)
                ),
                None => format!("{} 0 | | | |\n", point_cells(point)),
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_outcomes_are_the_summary_names_the_law_names_and_vector_components() {
        for name in DEFAULT_OUTCOMES {
            assert!(is_known_outcome(name), "{name}");
        }
        for name in [
            "law.group_count",
            "final.five_elements.r_o_m.2",
            "delta_v_mps.per_satellite.5",
        ] {
            assert!(is_known_outcome(name), "{name}");
        }
        for name in [
            "delta_v_mps.meen",
            "law.",
            "final.five_elements.r_o_m",
            "final.five_elements.r_o_m.6",
            "delta_v_mps.mean.0",
            "seed",
        ] {
            assert!(!is_known_outcome(name), "{name}");
        }
    }

    #[test]
    fn short_numbers() {
        assert_eq!(short(0.004), "0.004");
        assert_eq!(short(2.0), "2");
        assert_eq!(short(123.456789), "123.457");
        assert_eq!(short(2.5e-5), "2.5e-5");
        assert_eq!(short(1e6), "1e6");
        assert_eq!(short(-1.234567e7), "-1.23457e7");
        assert_eq!(short(0.0), "0");
    }
}
