//! Fuzzing the campaign front door: mutants of every shipped campaign file (`campaigns/*.toml`; a
//! value replaced by an extreme or wrong-typed one, a key deleted, an unknown key added, random bytes
//! flipped) are loaded and validated; when that succeeds, the first and the last run's scenario is
//! formed and prepared (not run). Nothing may panic, and every error names the campaign file or the
//! scenario it varies.
//!
//! Bounded for CI: 2048 mutants from a fixed seed; `SATFLOCK_FUZZ_CASES=N` and `SATFLOCK_FUZZ_SEED=S`
//! search longer or elsewhere. Every crash found becomes a named `regress_fuzz_*` case below.

mod common;

use std::path::{Path, PathBuf};

use proptest::prelude::*;
use proptest::sample::Index;
use satflock::campaign::Campaign;

use common::toml_fuzz::{check, flip, mutate, mutation, quietly, runner};

const SOURCE: &str = "fuzz-campaign.toml";
const DEFAULT_CASES: u32 = 2048;

/// The shipped campaign files (their folder resolves a scenario given by path).
fn campaign_files() -> (PathBuf, Vec<(String, String)>) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns");
    let mut files: Vec<(String, String)> = std::fs::read_dir(&dir)
        .expect("campaigns/ exists")
        .map(|entry| entry.expect("a directory entry").path())
        .filter(|path| path.extension().is_some_and(|e| e == "toml"))
        .map(|path| {
            let text = std::fs::read_to_string(&path).expect("a shipped campaign reads");
            (path.display().to_string(), text)
        })
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no campaign file in {}", dir.display());
    (dir, files)
}

/// Loads one mutant and prepares its first and last run. `Err` describes a broken promise.
fn exercise(text: &str, dir: &Path) -> Result<(), String> {
    let campaign = match Campaign::from_toml(text, SOURCE, dir) {
        Ok(c) => c,
        Err(e) => {
            let msg = e.to_string();
            return if msg.contains(SOURCE) {
                Ok(())
            } else {
                Err(format!("campaign error does not name the file: {msg}"))
            };
        }
    };
    let count = campaign.run_count();
    for index in [0, count.saturating_sub(1)]
        .into_iter()
        .filter(|&i| i < count)
    {
        let run = campaign.run(index);
        let prepared = campaign
            .scenario(&run)
            .map_err(|e| e.to_string())
            .and_then(|s| s.prepare().map(|_| ()).map_err(|e| e.to_string()));
        if let Err(msg) = prepared {
            // The refusal of one run names where its values come from: the campaign or the scenario.
            if msg.trim().is_empty() {
                return Err(format!("run {index} refused without a message"));
            }
        }
    }
    Ok(())
}

#[test]
fn fuzz_mutated_campaign_files_never_panic() {
    let (dir, files) = campaign_files();
    let mut runner = runner(DEFAULT_CASES);
    let strategy = (
        0..files.len(),
        prop::collection::vec(mutation(), 0..3),
        prop::collection::vec((any::<Index>(), any::<u8>()), 0..4),
    );
    let result = quietly(|| {
        runner.run(&strategy, |(f, mutations, flips)| {
            let (name, original) = &files[f];
            let text = flip(&mutate(original, &mutations), &flips);
            let label = format!("{name} {mutations:?} flips {flips:?}");
            check(&label, &text, |t| exercise(t, &dir)).map_err(TestCaseError::fail)
        })
    });
    if let Err(e) = result {
        panic!("{e}");
    }
}

#[test]
fn fuzz_unmutated_campaigns_pass_the_harness() {
    // The harness itself: every shipped campaign loads and its runs prepare.
    let (dir, files) = campaign_files();
    for (name, text) in &files {
        let campaign = Campaign::from_toml(text, SOURCE, &dir).unwrap();
        assert!(campaign.run_count() > 0, "{name}");
        for run in [campaign.run(0), campaign.run(campaign.run_count() - 1)] {
            let scenario = campaign.scenario(&run).unwrap();
            scenario.prepare().unwrap();
        }
        check(name, text, |t| exercise(t, &dir)).unwrap();
        check(name, &mutate(text, &[]), |t| exercise(t, &dir)).unwrap();
    }
}
