//! The front door as a newcomer meets it: the README and docs explain the binary before they name
//! a bare `satflock`, the tour reads shipped files and runs what it writes, and `satflock scenarios`
//! gives every built-in its own description.

use std::path::Path;

mod common;
use common::{satflock, stderr};

fn readme() -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../README.md")).unwrap()
}

/// Every `cargo run --release -- ...` command line of the README's shell blocks.
fn commands(text: &str) -> Vec<Vec<String>> {
    let mut in_sh = false;
    let mut out = Vec::new();
    for line in text.lines() {
        match line.trim() {
            "```sh" => in_sh = true,
            "```" => in_sh = false,
            l if in_sh => {
                if let Some(rest) = l.strip_prefix("cargo run --release -- ") {
                    let command = rest
                        .split('#')
                        .next()
                        .unwrap()
                        .trim()
                        .trim_end_matches('\\');
                    out.push(command.split_whitespace().map(str::to_string).collect());
                }
            }
            _ => {}
        }
    }
    out
}

#[test]
fn regress_the_readme_says_how_to_get_satflock_before_using_it_bare() {
    let text = readme();
    let install = text
        .find("cargo install --path cli")
        .expect("the README says how to install the binary");
    let first_bare = text
        .find("`satflock ")
        .expect("the README names commands as `satflock …`");
    assert!(
        install < first_bare,
        "explained at {install}, used at {first_bare}"
    );
}

#[test]
fn regress_the_tour_reads_shipped_files_and_runs_what_it_writes() {
    let text = readme();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let commands = commands(&text);
    assert!(commands.len() > 5);
    // Input files (not outputs under out/) exist in the repository.
    for command in &commands {
        for arg in command.iter().skip(1) {
            let is_file = [".toml", ".csv"].iter().any(|e| arg.ends_with(e));
            if is_file && !arg.starts_with("out/") && arg != "mine.toml" {
                assert!(
                    root.join(arg).is_file(),
                    "{command:?}: {arg} is not shipped"
                );
            }
        }
    }
    // Step 3 runs the file it tells the reader to create.
    let step3 = &text[text.find("**3. Write a scenario.**").unwrap()..];
    let step3 = &step3[..step3.find("**4.").unwrap()];
    assert!(step3.contains("> mine.toml"));
    assert!(step3.contains("-- run mine.toml"), "{step3}");
    // Step 5's positions characterise as written.
    let o = satflock()
        .current_dir(&root)
        .args(["characterize", "examples/positions.csv"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(json["n"], 6);
}

#[test]
fn regress_every_docs_page_that_types_satflock_says_how_to_get_it() {
    let docs = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs");
    for entry in std::fs::read_dir(&docs).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "md") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        // After the page's title (a title may name a command).
        let text = text.split_once('\n').map_or("", |(_, rest)| rest);
        let Some(first) = text.find("`satflock ").or_else(|| text.find("\nsatflock ")) else {
            continue;
        };
        let install = text.find("cargo install --path cli");
        assert!(
            install.is_some_and(|i| i < first),
            "{}: types `satflock` before saying how to get it",
            path.display()
        );
    }
}

#[test]
fn regress_every_builtin_has_its_own_line_in_satflock_scenarios() {
    let o = satflock().arg("scenarios").output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8(o.stdout).unwrap();
    let mut seen = std::collections::BTreeMap::new();
    for line in text.lines().filter(|l| !l.trim().is_empty()) {
        let Some((name, description)) = line.split_once(' ') else {
            continue;
        };
        let description = description.trim();
        if let Some(other) = seen.insert(description.to_string(), name.to_string()) {
            panic!("{name} and {other} share the description `{description}`");
        }
    }
    assert!(seen.len() > 30, "{text}");
}
