//! TOML mutants for the fuzz tests (`fuzz_scenarios`, `fuzz_campaigns`): structured mutations of a
//! document (a value replaced by an extreme or wrong-typed one, a key deleted, an unknown key added),
//! byte flips, the proptest strategy over them, a runner with a fixed seed, and the panic-catching
//! check that turns a panic or a broken promise into a failure with the mutant printed.
//!
//! Bounded for CI by default; `SATFLOCK_FUZZ_CASES=N` and `SATFLOCK_FUZZ_SEED=S` search longer or
//! elsewhere.

use std::panic::{catch_unwind, AssertUnwindSafe};

use proptest::prelude::*;
use proptest::sample::Index;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

/// One change to a document.
#[derive(Clone, Debug)]
pub enum Mutation {
    /// Replace the value at a leaf (chosen by index) by `values()[k]`.
    Replace(Index, usize),
    /// Delete the key at a leaf or table (chosen by index).
    Delete(Index),
    /// Add an unknown key to a table (chosen by index).
    AddUnknown(Index),
}

/// Extreme and wrong-typed values.
fn values() -> Vec<toml::Value> {
    use toml::Value::*;
    vec![
        Integer(0),
        Integer(-1),
        Float(1e300),
        Float(-1e300),
        Float(f64::NAN),
        Float(f64::INFINITY),
        Float(1e-308),
        Float(0.0),
        Integer(i64::MAX),
        Integer(1_000_000_000),
        String("x".into()),
        Boolean(true),
        Array(vec![]),
    ]
}

/// A path to a value inside a document: table keys and array indices.
#[derive(Clone, Debug)]
enum Step {
    Key(String),
    At(usize),
}

fn collect(
    value: &toml::Value,
    path: &mut Vec<Step>,
    leaves: &mut Vec<Vec<Step>>,
    tables: &mut Vec<Vec<Step>>,
) {
    match value {
        toml::Value::Table(t) => {
            tables.push(path.clone());
            for (k, v) in t {
                path.push(Step::Key(k.clone()));
                leaves.push(path.clone());
                collect(v, path, leaves, tables);
                path.pop();
            }
        }
        toml::Value::Array(a) => {
            for (i, v) in a.iter().enumerate() {
                path.push(Step::At(i));
                leaves.push(path.clone());
                collect(v, path, leaves, tables);
                path.pop();
            }
        }
        _ => {}
    }
}

fn get_mut<'a>(mut v: &'a mut toml::Value, path: &[Step]) -> &'a mut toml::Value {
    for s in path {
        v = match s {
            Step::Key(k) => v.get_mut(k.as_str()).expect("key exists"),
            Step::At(i) => v.get_mut(*i).expect("index exists"),
        };
    }
    v
}

/// Applies the structured mutations to the document of `text`.
pub fn mutate(text: &str, mutations: &[Mutation]) -> String {
    let mut doc = toml::Value::Table(text.parse::<toml::Table>().expect("the original parses"));
    for m in mutations {
        let (mut leaves, mut tables) = (Vec::new(), Vec::new());
        collect(&doc, &mut Vec::new(), &mut leaves, &mut tables);
        match m {
            Mutation::Replace(ix, k) => {
                // Prefer numbers: the pick walks forward from the index to the next numeric leaf.
                let start = ix.index(leaves.len());
                let pick = (0..leaves.len())
                    .map(|d| &leaves[(start + d) % leaves.len()])
                    .find(|p| {
                        matches!(
                            get_mut(&mut doc, p),
                            toml::Value::Integer(_) | toml::Value::Float(_)
                        )
                    })
                    .unwrap_or(&leaves[start])
                    .clone();
                let vals = values();
                *get_mut(&mut doc, &pick) = vals[k % vals.len()].clone();
            }
            Mutation::Delete(ix) => {
                let path = &leaves[ix.index(leaves.len())];
                let (last, parent) = path.split_last().expect("non-empty path");
                match (get_mut(&mut doc, parent), last) {
                    (toml::Value::Table(t), Step::Key(k)) => {
                        t.remove(k);
                    }
                    (toml::Value::Array(a), Step::At(i)) => {
                        a.remove(*i);
                    }
                    _ => unreachable!("paths follow the document"),
                }
            }
            Mutation::AddUnknown(ix) => {
                let path = &tables[ix.index(tables.len())];
                if let toml::Value::Table(t) = get_mut(&mut doc, path) {
                    t.insert("fuzz_unknown_key".into(), toml::Value::Integer(1));
                }
            }
        }
    }
    toml::to_string(&doc).expect("a document serializes")
}

/// Flips bytes of the text (positions by index, xor by a nonzero byte).
pub fn flip(text: &str, flips: &[(Index, u8)]) -> String {
    let mut bytes = text.as_bytes().to_vec();
    if bytes.is_empty() {
        return String::new();
    }
    for (ix, x) in flips {
        let i = ix.index(bytes.len());
        bytes[i] ^= x.max(&1);
    }
    String::from_utf8_lossy(&bytes).into_owned()
}

/// Runs `exercise` on `text` under `catch_unwind`; a panic or broken promise fails with the mutant printed.
pub fn check(
    label: &str,
    text: &str,
    exercise: impl Fn(&str) -> Result<(), String>,
) -> Result<(), String> {
    match catch_unwind(AssertUnwindSafe(|| exercise(text))) {
        Ok(Ok(())) => Ok(()),
        Ok(Err(e)) => Err(format!("{label}: {e}\n--- mutant ---\n{text}\n---")),
        Err(p) => {
            let msg = p
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            Err(format!(
                "{label}: PANIC: {msg}\n--- mutant ---\n{text}\n---"
            ))
        }
    }
}

/// One mutation, replacements three times as likely as deletions or unknown keys.
pub fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        3 => (any::<Index>(), 0..64usize).prop_map(|(i, k)| Mutation::Replace(i, k)),
        1 => any::<Index>().prop_map(Mutation::Delete),
        1 => any::<Index>().prop_map(Mutation::AddUnknown),
    ]
}

/// Cases per run: `SATFLOCK_FUZZ_CASES`, else `default`.
pub fn cases(default: u32) -> u32 {
    std::env::var("SATFLOCK_FUZZ_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

/// A runner of `default` cases (or `SATFLOCK_FUZZ_CASES`) from the seed `SATFLOCK_FUZZ_SEED`, else 2026:
/// CI runs the same mutants every time; a crash found by a longer search becomes a named regression.
pub fn runner(default: u32) -> TestRunner {
    let seed: u64 = std::env::var("SATFLOCK_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(2026);
    let mut seed_bytes = [0u8; 32];
    seed_bytes[..8].copy_from_slice(&seed.to_le_bytes());
    TestRunner::new_with_rng(
        Config {
            cases: cases(default),
            failure_persistence: None,
            ..Config::default()
        },
        TestRng::from_seed(RngAlgorithm::ChaCha, &seed_bytes),
    )
}

/// Runs `body` with the panic hook silenced (it would print every caught panic), restoring it after.
pub fn quietly<T>(body: impl FnOnce() -> T) -> T {
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let out = body();
    std::panic::set_hook(hook);
    out
}
