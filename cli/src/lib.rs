//! The `satflock` command-line tool as a library: the whole command line ([`main_with`]: `run`,
//! `compare`, `campaign`, `plot`, `report` … with the laws of a [`LawRegistry`]), the full-length
//! reproduction reports behind `satflock validate` (and the long regression tests that share their
//! code), the figures of `satflock plot`, the offline HTML report of a run directory (`satflock report`)
//! and `satflock compare` (laws side by side on one case). Everything here uses only the public API of
//! the `satflock` library.
//!
//! The `satflock` binary is `src/main.rs`: [`main_with`] with the built-in laws. A program that
//! registers laws of its own is a full `satflock` binary whose scenario and controller files may name
//! them (`examples/custom_law_cli.rs`, `docs/writing-a-law.md`):
//!
//! ```no_run
//! use satflock::guidance::LawRegistry;
//!
//! fn main() -> std::process::ExitCode {
//!     let registry = LawRegistry::builtin();
//!     // registry.register("my-law", MyLaw::new).unwrap();
//!     satflock_cli::main_with(registry)
//! }
//! ```

mod app;
pub mod bench_cases;
pub mod compare;
pub mod plot;
pub mod report;
pub mod validate;

mod bench;
mod budget;
mod campaign;
mod characterize;
mod export;

use std::ffi::OsString;
use std::process::ExitCode;

pub use satflock::guidance::LawRegistry;

use app::{install_signal_handlers, print_out, usage, GravityArg, Interrupted, MAX_THREADS};

/// The `satflock` command line on the process's arguments, with the laws of `registry` (installed as
/// the process's registry first, [`LawRegistry::install`], so every scenario, controller file and law
/// event read by any command may name them). Returns the exit code: 0 success, 1 a run that failed, 2
/// bad arguments or input (a message naming the file, the key and the allowed range), 130 / 143 a run
/// interrupted by SIGINT / SIGTERM.
pub fn main_with(registry: LawRegistry) -> ExitCode {
    app::main_with_args(registry, std::env::args_os())
}

/// [`main_with`] on the given arguments (the program name first), e.g. from a test. Bad command-line
/// syntax (and `--help`, `--version`) prints clap's message and ends the process, as the binary does.
pub fn main_with_args<I, T>(registry: LawRegistry, args: I) -> ExitCode
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    app::main_with_args(registry, args)
}
