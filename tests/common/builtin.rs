//! A built-in scenario edited by text replacements, for the integration tests that run a variant of a
//! built-in (included with `#[path = "common/builtin.rs"] mod builtin_variant;`, so a test file
//! compiles only this, not the fuzz helpers of `common/mod.rs`).

use std::path::Path;

use satflock::scenario::{builtin, Scenario};

/// The built-in scenario `name` with each `(from, to)` replacement applied to its TOML text (each
/// `from` must occur: a built-in that changed fails here, not silently in the test).
pub fn builtin_with(name: &str, replacements: &[(&str, &str)]) -> Scenario {
    let b = builtin::find(name).expect("a built-in scenario");
    let mut text = b.toml.to_string();
    for (from, to) in replacements {
        assert!(text.contains(from), "{name}: `{from}` not found");
        text = text.replace(from, to);
    }
    Scenario::from_toml(&text, name, Path::new(".")).expect("a valid scenario")
}
