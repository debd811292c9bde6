//! `docs/validation.md` shows each paper's reproduction as `satflock validate TARGET --from
//! validation/measured/TARGET.json` prints it: the saved measurement rendered with today's data file
//! (`validation/TARGET.toml`). This test renders every saved measurement and compares it with the
//! section between the target's markers, so a data file, a measurement and the document cannot drift
//! apart. After rerunning a reproduction (`satflock validate TARGET --json >
//! validation/measured/TARGET.json`), `SATFLOCK_UPDATE_DOCS=1 cargo test --release --test
//! validation_docs` rewrites the sections.

use std::path::PathBuf;

use satflock_cli::validate::{doc_markers, render_saved};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The targets whose reproduction is data (`validation/TARGET.toml`), with a saved measurement.
fn targets() -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(root().join("validation"))
        .expect("validation/")
        .filter_map(|e| {
            let name = e.ok()?.file_name().into_string().ok()?;
            name.strip_suffix(".toml").map(str::to_string)
        })
        .collect();
    names.sort();
    names
}

#[test]
fn docs_validation_tables_are_what_validate_from_prints() {
    let docs_path = root().join("docs/validation.md");
    let mut docs = std::fs::read_to_string(&docs_path).expect("docs/validation.md");
    let update = std::env::var_os("SATFLOCK_UPDATE_DOCS").is_some();
    let targets = targets();
    assert!(!targets.is_empty(), "no data file in validation/");
    let mut stale = Vec::new();
    for target in &targets {
        let saved = root().join(format!("validation/measured/{target}.json"));
        let json = std::fs::read_to_string(&saved).unwrap_or_else(|e| {
            panic!(
                "{}: {e} (run `satflock validate {target} --json`)",
                saved.display()
            )
        });
        let rendered = render_saved(target, &json)
            .unwrap_or_else(|e| panic!("{target}: {e}"))
            .to_markdown();
        let (begin, end) = doc_markers(target);
        let start = docs
            .find(&begin)
            .unwrap_or_else(|| panic!("docs/validation.md has no marker {begin}"))
            + begin.len();
        let stop = start
            + docs[start..]
                .find(&end)
                .unwrap_or_else(|| panic!("docs/validation.md has no marker {end}"));
        let expected = format!("\n{rendered}");
        if docs[start..stop] != expected {
            if update {
                docs.replace_range(start..stop, &expected);
            } else {
                stale.push(target.clone());
            }
        }
    }
    if update {
        std::fs::write(&docs_path, &docs).expect("write docs/validation.md");
    }
    assert!(
        stale.is_empty(),
        "docs/validation.md differs from `satflock validate TARGET --from validation/measured/TARGET.json` for {stale:?}; \
         SATFLOCK_UPDATE_DOCS=1 cargo test --release --test validation_docs rewrites it"
    );
}

/// Every data file's outcomes are exactly the saved measurement's checks (none unmeasured, none
/// stray), which `render_saved` enforces; and the saved measurement says when and how long it ran.
#[test]
fn every_saved_measurement_is_stamped() {
    for target in targets() {
        let json =
            std::fs::read_to_string(root().join(format!("validation/measured/{target}.json")))
                .expect("saved measurement");
        let report = render_saved(&target, &json).unwrap_or_else(|e| panic!("{target}: {e}"));
        let measured = report
            .measured
            .unwrap_or_else(|| panic!("{target}: the saved measurement has no `measured` stamp"));
        assert_eq!(measured.command, format!("satflock validate {target}"));
        assert!(measured.wall_s > 0.0 && measured.threads >= 1, "{target}");
    }
}
