//! `satflock bench`: performance measurements that print one JSON line per case, so that any harness can
//! set other tools' timings beside them. Without a subcommand, the fixed suite (`suite.rs`: propagation
//! and the guided step of each law at N = 1e3 … 1e6, five elements, peak memory, each case in a child
//! process); `satflock bench propagate` (`propagate.rs`): N independent satellites through the fused
//! RK4 kernel, from given or generated initial states.

use anyhow::Result;
use clap::Subcommand;

mod propagate;
pub mod suite;

/// The options of `satflock bench`.
#[derive(clap::Args)]
pub struct BenchArgs {
    #[command(subcommand)]
    action: Option<BenchCommand>,
    /// Small N only (1000 satellites per case).
    #[arg(long)]
    quick: bool,
    /// Only this case (propagation, hold-repel, bifurcating, equilibrium-shaping, pigeon,
    /// five-elements).
    #[arg(long)]
    case: Option<String>,
    /// Largest N measured, 1000 to 1000000 (default 1000000, or 1000 with --quick).
    #[arg(long)]
    max_n: Option<usize>,
}

/// The subcommands of `satflock bench`.
#[derive(Subcommand)]
pub enum BenchCommand {
    /// Propagate N independent satellites (point mass + J2 or point mass, RK4, the fused kernel) and
    /// print one JSON line: peer, n, steps, wall_s, sat_steps_per_s, threads, simd,
    /// final_state_first_sat.
    #[command(allow_negative_numbers = true)]
    Propagate(propagate::PropagateBenchArgs),
    /// One suite case at N satellites in this process (what the suite runs in its child processes).
    #[command(hide = true)]
    Case {
        /// The case's name.
        name: String,
        /// Number of satellites.
        n: usize,
        /// Timed steps (default: the suite's, fewer at larger N); more for profiling.
        #[arg(long)]
        steps: Option<usize>,
        /// Control ticks between re-sorts of the satellites' storage by grid cell (0: never; default:
        /// the engine's).
        #[arg(long)]
        resort_every: Option<u64>,
    },
}

/// Runs `satflock bench`: the suite, one of its cases, or `propagate`.
pub fn bench_command(args: &BenchArgs) -> Result<()> {
    match &args.action {
        Some(BenchCommand::Propagate(propagate)) => propagate::run(propagate),
        Some(BenchCommand::Case {
            name,
            n,
            steps,
            resort_every,
        }) => suite::run_case(name, *n, *steps, *resort_every),
        None => suite::run_suite(args.quick, args.case.as_deref(), args.max_n),
    }
}
