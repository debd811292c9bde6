//! Fuzzing the run-directory readers (issue 25): mutants of two real run directories (CSV and Parquet
//! tables) — a JSON value of `summary.json` or `scene.json` replaced by an extreme or wrong-typed one or
//! deleted, a CSV cell replaced, lines deleted, duplicated or swapped, a file cut short or a byte
//! flipped, a Parquet footer forged to claim up to 10¹⁵ rows or terabyte column chunks — are read by
//! every reader command (`characterize`, `plot`, `report`, `export oem`, `export czml`), each the
//! `satflock` binary in a child process. Each must succeed (exit 0) or refuse cleanly (exit 2): never a
//! panic (101), an abort (134) or a signal.
//!
//! Bounded for CI: 1000 mutants from a fixed seed, on two threads (about 30 s in release mode on two
//! cores; 240 mutants took 6.7 s, and seeds 2 and 3 with 3000 mutants each passed when this was
//! written); set `SATFLOCK_FUZZ_CASES=N` and `SATFLOCK_FUZZ_SEED=S` for a longer or different search. A
//! crash found becomes a named case in `regress_run_readers.rs`.

use std::path::{Path, PathBuf};

mod common;
use common::{copy_run, forge_parquet_footer, satflock, scratch_dir, small_run, stderr};

const DEFAULT_CASES: u64 = 1000;

/// SplitMix64: a fixed-seed generator (the same mutants on every machine).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A number in 0..n (n > 0).
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }

    fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

/// Extreme and wrong-typed CSV cells.
const CELLS: &[&str] = &[
    "NaN",
    "inf",
    "-inf",
    "-1",
    "0.5",
    "1e308",
    "-1e308",
    "1e15",
    "",
    "x",
    "18446744073709551616",
    "4",
    "0",
    "1e11",
    "99999999999",
];

/// Extreme and wrong-typed JSON values.
fn json_values() -> Vec<serde_json::Value> {
    use serde_json::json;
    vec![
        json!(null),
        json!(-1),
        json!(0),
        json!(0.5),
        json!(1e308),
        json!(-1e308),
        json!(1_000_000_000_000_000u64),
        json!(u64::MAX),
        json!(i64::MIN),
        json!("x"),
        json!(""),
        json!(true),
        json!([]),
        json!({}),
        json!([1e308, -1e308, 0]),
        json!("9999-99-99T99:99:99"),
    ]
}

/// Every JSON pointer to a value inside `v` (objects' keys and arrays' items, the root excluded).
fn pointers(v: &serde_json::Value, here: String, out: &mut Vec<String>) {
    let children: Vec<(String, &serde_json::Value)> = match v {
        serde_json::Value::Object(o) => o.iter().map(|(k, v)| (format!("{here}/{k}"), v)).collect(),
        serde_json::Value::Array(a) => a
            .iter()
            .enumerate()
            .map(|(k, v)| (format!("{here}/{k}"), v))
            .collect(),
        _ => Vec::new(),
    };
    for (p, child) in children {
        out.push(p.clone());
        pointers(child, p, out);
    }
}

/// Mutates a JSON file; returns what was done.
fn mutate_json(path: &Path, rng: &mut Rng) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    let mut doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    let mut all = Vec::new();
    pointers(&doc, String::new(), &mut all);
    match rng.below(4) {
        0 | 1 if !all.is_empty() => {
            let pointer = rng.pick(&all).clone();
            let value = rng.pick(&json_values()).clone();
            *doc.pointer_mut(&pointer).unwrap() = value.clone();
            std::fs::write(path, doc.to_string()).unwrap();
            format!("{pointer} = {value}")
        }
        2 if !all.is_empty() => {
            let pointer = rng.pick(&all).clone();
            let (parent, key) = pointer.rsplit_once('/').unwrap();
            match doc.pointer_mut(parent).unwrap() {
                serde_json::Value::Object(o) => {
                    o.remove(key);
                }
                serde_json::Value::Array(a) => {
                    a.remove(key.parse::<usize>().unwrap());
                }
                _ => unreachable!("a parent holds children"),
            }
            std::fs::write(path, doc.to_string()).unwrap();
            format!("{pointer} deleted")
        }
        _ => {
            let whole = *rng.pick(&["[]", "{}", "null", "", "1e999", "{\"n_satellites\": 4}"]);
            std::fs::write(path, whole).unwrap();
            format!("whole file = {whole:?}")
        }
    }
}

/// Mutates a CSV file; returns what was done.
fn mutate_csv(path: &Path, rng: &mut Rng) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let data = lines.len() - 1;
    let what = match rng.below(7) {
        0..=2 => {
            let line = 1 + rng.below(data);
            let mut cells: Vec<String> = lines[line].split(',').map(str::to_string).collect();
            let k = rng.below(cells.len());
            let value = *rng.pick(CELLS);
            cells[k] = value.to_string();
            lines[line] = cells.join(",");
            format!("line {} cell {k} = {value:?}", line + 1)
        }
        3 => {
            let line = 1 + rng.below(data);
            lines.remove(line);
            format!("line {} deleted", line + 1)
        }
        4 => {
            let line = 1 + rng.below(data);
            let copy = lines[line].clone();
            lines.insert(line, copy);
            format!("line {} duplicated", line + 1)
        }
        5 => {
            let (a, b) = (1 + rng.below(data), 1 + rng.below(data));
            lines.swap(a, b);
            format!("lines {} and {} swapped", a + 1, b + 1)
        }
        _ => {
            let keep = 1 + rng.below(lines.len());
            lines.truncate(keep);
            format!("first {keep} lines kept")
        }
    };
    std::fs::write(path, lines.join("\n") + "\n").unwrap();
    what
}

/// Mutates any file's bytes: one flipped, or the file cut short.
fn mutate_bytes(path: &Path, rng: &mut Rng) -> String {
    let mut bytes = std::fs::read(path).unwrap();
    if bytes.is_empty() {
        return "empty file left as is".into();
    }
    let what = if rng.below(2) == 0 {
        // Mostly near the end: a Parquet footer, a JSON document's closing keys.
        let k = bytes.len() - 1 - rng.below(bytes.len().min(300));
        bytes[k] ^= 1 << rng.below(8);
        format!("byte {k} flipped")
    } else {
        let keep = rng.below(bytes.len());
        bytes.truncate(keep);
        format!("cut to {keep} bytes")
    };
    std::fs::write(path, bytes).unwrap();
    what
}

/// Mutates a Parquet file; returns what was done.
fn mutate_parquet(path: &Path, rng: &mut Rng) -> String {
    if rng.below(3) == 0 {
        return mutate_bytes(path, rng);
    }
    let rows = *rng.pick(&[0, 1, 7, 1_000_000_000, 1_000_000_000_000_000]);
    let chunk = *rng.pick(&[None, Some(1), Some(1 << 40)]);
    std::fs::write(path, forge_parquet_footer(path, rows, chunk)).unwrap();
    format!("footer forged: {rows} rows, chunk bytes {chunk:?}")
}

/// One mutant: a copy of `base` with one file changed, read by every reader. Returns the failures.
fn one_case(base: &Path, ext: &str, case: &Path, rng: &mut Rng) -> Vec<String> {
    copy_run(base, case);
    let files = [
        "summary.json".to_string(),
        "scene.json".to_string(),
        format!("metrics.{ext}"),
        format!("trajectory.{ext}"),
    ];
    let file = rng.pick(&files).clone();
    let path = case.join(&file);
    let what = match (file.rsplit_once('.').unwrap().1, rng.below(5)) {
        (_, 0) => mutate_bytes(&path, rng),
        ("json", _) => mutate_json(&path, rng),
        ("csv", _) => mutate_csv(&path, rng),
        _ => mutate_parquet(&path, rng),
    };
    let out = case.join("exports");
    std::fs::create_dir_all(&out).unwrap();
    let trajectory = case.join(format!("trajectory.{ext}"));
    let commands: Vec<Vec<PathBuf>> = vec![
        vec!["characterize".into(), trajectory],
        vec!["plot".into(), case.into()],
        vec!["report".into(), case.into()],
        vec![
            "export".into(),
            "oem".into(),
            case.into(),
            "--out".into(),
            out.join("o.oem"),
        ],
        vec![
            "export".into(),
            "czml".into(),
            case.into(),
            "--out".into(),
            out.join("o.czml"),
        ],
    ];
    let mut failures = Vec::new();
    for args in commands {
        let o = satflock().args(&args).output().unwrap();
        let err = stderr(&o);
        if !matches!(o.status.code(), Some(0 | 2)) || err.contains("panicked") {
            failures.push(format!(
                "{file}: {what}; `satflock {}` ended with {:?}: {err}",
                args.iter()
                    .map(|a| a.display().to_string())
                    .collect::<Vec<_>>()
                    .join(" "),
                o.status
            ));
        }
    }
    failures
}

#[test]
fn fuzz_run_directory_readers_never_crash() {
    let number = |name: &str, default: u64| {
        std::env::var(name)
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(default)
    };
    let cases = number("SATFLOCK_FUZZ_CASES", DEFAULT_CASES);
    let seed = number("SATFLOCK_FUZZ_SEED", 1);
    let dir = scratch_dir("fuzz");
    let bases = [
        (small_run(&dir, "base-csv", "csv"), "csv"),
        (small_run(&dir, "base-parquet", "parquet"), "parquet"),
    ];
    let started = std::time::Instant::now();
    let failures: Vec<String> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..2u64)
            .map(|w| {
                let (dir, bases) = (&dir, &bases);
                scope.spawn(move || {
                    let mut failures = Vec::new();
                    for k in (w..cases).step_by(2) {
                        // Each case has its own stream: the same mutant whatever the thread count.
                        let mut rng = Rng(seed.wrapping_mul(0x1_0000_0001).wrapping_add(k));
                        rng.next();
                        let (base, ext) = &bases[rng.below(2)];
                        let case = dir.join(format!("case-{k}"));
                        failures.extend(one_case(base, ext, &case, &mut rng));
                        let _ = std::fs::remove_dir_all(&case);
                    }
                    failures
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().unwrap())
            .collect()
    });
    eprintln!(
        "{cases} mutants (seed {seed}) read by 5 commands each in {:.1} s",
        started.elapsed().as_secs_f64()
    );
    assert!(
        failures.is_empty(),
        "{} crashes:\n{}",
        failures.len(),
        failures.join("\n")
    );
    let _ = std::fs::remove_dir_all(&dir);
}
