//! Helpers shared by the command-line tests: the `satflock` binary under test, a fresh scratch folder
//! per test, and a command's standard error.
// Each test binary compiles this module and may use only part of it.
#![allow(dead_code)]

use std::path::PathBuf;
use std::process::{Command, Output};

/// The `satflock` binary built for these tests.
pub fn satflock() -> Command {
    Command::new(env!("CARGO_BIN_EXE_satflock"))
}

/// An empty folder in the system's temporary folder, unique to this test binary, process and `name`.
pub fn scratch_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "satflock-{}-{}-{name}",
        env!("CARGO_CRATE_NAME"),
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A finished command's standard error as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}
