//! The `satflock` command-line tool's library half: the full-length reproduction reports behind
//! `satflock validate` (and the long regression tests that share their code) and the figures of
//! `satflock plot`. The binary is `src/main.rs`; everything here uses only the public API of the
//! `satflock` library.

pub mod plot;
pub mod validate;
