//! A `satflock` binary of your own: the whole command line (`run`, `compare`, `campaign`, `plot`,
//! `report` …) with one more law, the "centring" law of `examples/custom_law.rs`, registered under the
//! name `centring`. Scenario files, controller files (`examples/custom_law.toml`) and
//! `set-law-parameters` / `switch-law` events may then name it as they name a built-in law, and
//! `compare` shows the headline outcomes it declares.
//!
//! ```text
//! cargo run --release --example custom_law_cli -- compare hold --law examples/custom_law.toml \
//!     --law builtin:hold --seeds 1..3 --out out/centring-vs-hold
//! ```

use std::process::ExitCode;

use satflock::guidance::LawRegistry;

// The law, shared with `examples/custom_law.rs`.
#[path = "custom_law/centring.rs"]
mod centring;

fn main() -> ExitCode {
    let mut registry = LawRegistry::builtin();
    registry
        .register(centring::NAME, centring::Centring::new)
        .expect("`centring` is not a built-in law's name");
    satflock_cli::main_with(registry)
}
