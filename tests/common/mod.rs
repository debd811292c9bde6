//! Helpers shared by the library's integration tests. (`builtin.rs`, a built-in scenario edited by
//! text replacements, is included on its own by the tests that use it.)

pub mod toml_fuzz;
