//! `satflock campaign CAMPAIGN.toml --out DIR`: a campaign (`satflock::campaign`, `docs/campaigns.md`)
//! with a progress bar over runs, then its figure.
//!
//! Exit codes: 0 when the campaign ran, even if some runs failed or were refused (stderr says how
//! many; `--fail-on-run-failure` makes that exit 1); 2 for a bad campaign file (naming the file, the
//! key and the allowed range; nothing is run or written), an output directory that cannot hold it or a
//! manifest that does not match; 1 when an output cannot be written; 130 / 143 when SIGINT / SIGTERM
//! stopped it (the running runs are recorded as `interrupted`; `--resume` continues).

use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

use anyhow::{bail, Result};
use indicatif::{ProgressBar, ProgressStyle};

use crate::plot::{draw_campaign, PlotParameter};
use satflock::campaign::{
    run_campaign, table, Campaign, CampaignError, RunEvent, RunnerOptions, Status,
};

use crate::{install_signal_handlers, usage, Interrupted, MAX_THREADS};

/// The arguments of `satflock campaign`.
#[derive(clap::Args)]
pub(crate) struct CampaignArgs {
    /// The campaign file (TOML; see docs/campaigns.md).
    campaign: PathBuf,
    /// Output directory: a new path or an empty directory (with --resume: the campaign's directory).
    #[arg(long)]
    out: PathBuf,
    /// Runs at once, 1 to 1024, each on one thread (default: the machine's cores). Results do not
    /// depend on it.
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..=MAX_THREADS))]
    jobs: Option<u16>,
    /// Continue the campaign in --out: keep the runs its manifest.jsonl records as completed, run the
    /// others (missing, failed, refused or interrupted). Refused if the campaign file changed.
    #[arg(long)]
    resume: bool,
    /// Keep every run's full outputs (tables, scene.json) under OUT/runs/NNNNN/ (default: only
    /// summary.json and scenario.toml).
    #[arg(long)]
    keep_runs: bool,
    /// No progress bar and no closing report (warnings and errors still go to stderr).
    #[arg(long)]
    quiet: bool,
    /// Exit with code 1 if any run did not complete (by default failed runs are recorded and the
    /// campaign exits 0).
    #[arg(long)]
    fail_on_run_failure: bool,
}

/// Counts shown on the progress bar.
#[derive(Default)]
struct Counts {
    done: AtomicUsize,
    failed: AtomicUsize,
    running: AtomicUsize,
}

impl Counts {
    fn message(&self) -> String {
        format!(
            "{} done, {} failed, {} running",
            self.done.load(Ordering::Relaxed),
            self.failed.load(Ordering::Relaxed),
            self.running.load(Ordering::Relaxed)
        )
    }
}

/// Runs `satflock campaign`.
pub(crate) fn campaign_command(args: &CampaignArgs) -> Result<()> {
    // Every key is validated before anything is created on disk.
    let campaign = Campaign::load(&args.campaign).map_err(|e| usage(e.to_string()))?;
    let (cancel, which) = install_signal_handlers()?;
    let bar = if args.quiet {
        ProgressBar::hidden()
    } else {
        let bar = ProgressBar::new(0);
        bar.set_style(
            ProgressStyle::with_template(
                "{spinner} [{bar:30}] {pos}/{len} runs: {msg}, {elapsed} elapsed, ETA {eta}",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        bar.enable_steady_tick(std::time::Duration::from_millis(250));
        bar
    };
    let counts = Counts::default();
    let events = |event: RunEvent| {
        match event {
            RunEvent::Planned { to_run, .. } => bar.set_length(to_run as u64),
            RunEvent::Started(_) => {
                counts.running.fetch_add(1, Ordering::Relaxed);
            }
            RunEvent::Finished(_, status) => {
                counts.running.fetch_sub(1, Ordering::Relaxed);
                counts.done.fetch_add(1, Ordering::Relaxed);
                if status != Status::Completed {
                    counts.failed.fetch_add(1, Ordering::Relaxed);
                }
                bar.inc(1);
            }
        }
        bar.set_message(counts.message());
    };
    let options = RunnerOptions {
        jobs: args.jobs.map(usize::from),
        resume: args.resume,
        keep_runs: args.keep_runs,
        cancel: Some(cancel),
    };
    let outcome = run_campaign(&campaign, &args.out, &options, &events);
    bar.finish_and_clear();
    let report = outcome.map_err(|e: CampaignError| {
        if e.is_input() {
            usage(e.to_string())
        } else {
            anyhow::Error::from(e)
        }
    })?;

    for line in &report.dropped {
        eprintln!("warning: --resume dropped {line}");
    }
    if !report.dropped.is_empty() {
        eprintln!(
            "warning: --resume dropped {} manifest line(s) (listed in {}); runs that no kept line \
             records as completed were run again",
            report.dropped.len(),
            args.out.join("summary.md").display()
        );
    }
    if !report.records.is_empty() {
        let parameters: Vec<PlotParameter> = campaign
            .parameters
            .iter()
            .enumerate()
            .filter(|(k, _)| table::is_numeric(&campaign, *k))
            .map(|(_, p)| PlotParameter {
                key: p.key.to_string(),
                column: format!("{}{}", table::PARAMETER_PREFIX, p.key),
                log: p.is_log(),
            })
            .collect();
        match draw_campaign(
            &args.out,
            &campaign.file,
            &report.table,
            &parameters,
            &report.outcomes,
        ) {
            Ok(plots) if !args.quiet => eprintln!("{}", plots.describe(&args.out)),
            Ok(_) => {}
            Err(e) => eprintln!("warning: plots not drawn: {e}"),
        }
    }
    let not_completed = report.records.len() - report.count(Status::Completed);
    if !args.quiet {
        eprintln!(
            "campaign {}: {} runs ({} point(s) × {} seed(s)); ran {} now, {} already complete; {} \
             completed, {} failed, {} refused, {} interrupted; outputs in {}",
            campaign.file,
            campaign.run_count(),
            campaign.points.len(),
            campaign.seeds.len(),
            report.ran,
            report.already_complete,
            report.count(Status::Completed),
            report.count(Status::Failed),
            report.count(Status::Refused),
            report.count(Status::Interrupted),
            args.out.display()
        );
    }
    if report.interrupted {
        return Err(Interrupted {
            signal: which.load(Ordering::Relaxed) as i32,
            message: format!(
                "campaign interrupted: {} of {} runs finished; `satflock campaign {} --out {} \
                 --resume` runs the rest",
                report.records.len(),
                campaign.run_count(),
                args.campaign.display(),
                args.out.display()
            ),
        }
        .into());
    }
    if not_completed > 0 {
        eprintln!(
            "warning: {not_completed} of {} runs did not complete (status and error in {}; \
             `--resume` runs them again)",
            campaign.run_count(),
            args.out.join("manifest.jsonl").display()
        );
        if args.fail_on_run_failure {
            bail!("{not_completed} run(s) did not complete (--fail-on-run-failure)");
        }
    }
    Ok(())
}
