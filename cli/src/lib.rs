//! The `satflock` command-line tool's library half: the full-length reproduction reports behind
//! `satflock validate` (and the long regression tests that share their code), the figures of
//! `satflock plot`, the offline HTML report of a run directory (`satflock report`) and `satflock
//! compare` (laws side by side on one case). The binary is
//! `src/main.rs`; everything here uses only the public API of the `satflock` library.

pub mod bench_cases;
pub mod compare;
pub mod plot;
pub mod report;
pub mod validate;
