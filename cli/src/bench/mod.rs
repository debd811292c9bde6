//! `satflock bench`: performance measurements that print one JSON line per case, so that any harness can
//! set other tools' timings beside them. Each case is a subcommand (`satflock bench propagate`).

use anyhow::Result;
use clap::Subcommand;

mod propagate;

/// The cases of `satflock bench`.
#[derive(Subcommand)]
pub enum BenchCommand {
    /// Propagate N independent satellites (point mass + J2 or point mass, RK4, the fused kernel) and
    /// print one JSON line: peer, n, steps, wall_s, sat_steps_per_s, threads, simd,
    /// final_state_first_sat.
    #[command(allow_negative_numbers = true)]
    Propagate(propagate::PropagateBenchArgs),
}

/// Runs one `satflock bench` case.
pub fn bench_command(command: &BenchCommand) -> Result<()> {
    match command {
        BenchCommand::Propagate(args) => propagate::run(args),
    }
}
