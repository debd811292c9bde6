//! Helpers shared by the command-line tests: the `satflock` binary under test, a fresh scratch folder
//! per test, a command's standard error, and forged Parquet footers (the run-directory readers' tests).
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

/// The bytes of the Parquet file `path` with a forged footer: every row group claims `rows` rows (and
/// every column chunk as many values) and, with `chunk_bytes`, that many compressed bytes per column
/// chunk. The data pages are untouched: a reader that trusts the footer for an allocation aborts.
pub fn forge_parquet_footer(
    path: &std::path::Path,
    rows: i64,
    chunk_bytes: Option<i64>,
) -> Vec<u8> {
    use parquet::file::metadata::{ParquetMetaData, ParquetMetaDataReader, ParquetMetaDataWriter};
    let bytes = std::fs::read(path).unwrap();
    let file = std::fs::File::open(path).unwrap();
    let metadata = ParquetMetaDataReader::new()
        .parse_and_finish(&file)
        .unwrap();
    let n = bytes.len();
    let footer_len = u32::from_le_bytes(bytes[n - 8..n - 4].try_into().unwrap()) as usize;
    let data_end = n - 8 - footer_len;
    let row_groups = metadata
        .row_groups()
        .iter()
        .map(|rg| {
            let columns = rg
                .columns()
                .iter()
                .map(|c| {
                    let mut b = c.clone().into_builder().set_num_values(rows);
                    if let Some(size) = chunk_bytes {
                        b = b.set_total_compressed_size(size);
                    }
                    b.build().unwrap()
                })
                .collect();
            rg.clone()
                .into_builder()
                .set_num_rows(rows)
                .set_column_metadata(columns)
                .build()
                .unwrap()
        })
        .collect();
    let forged = ParquetMetaData::new(metadata.file_metadata().clone(), row_groups);
    let mut out = bytes[..data_end].to_vec();
    ParquetMetaDataWriter::new(&mut out, &forged)
        .finish()
        .unwrap();
    out
}

/// A small run directory `dir/NAME`: `free-drift` cut to 4 satellites over 200 s, with one threat and
/// one obstacle, its tables in `format` (`csv` or `parquet`), without plots.
pub fn small_run(dir: &std::path::Path, name: &str, format: &str) -> PathBuf {
    let builtin = satflock::scenario::builtin::find("free-drift").unwrap();
    let mut text = builtin.toml.to_string();
    for (from, to) in [
        ("count = 50", "count = 4"),
        ("duration_s = 5800.0", "duration_s = 200.0"),
    ] {
        assert!(text.contains(from), "free-drift has no `{from}`");
        text = text.replacen(from, to, 1);
    }
    text += r#"
[[threats]]
name = "threat-1"
danger_radius_m = 20.0
aim_point_hill_m = [0.0, 0.0, 0.0]
direction_hill = [0.0, 0.0, -1.0]
speed_mps = 1.0
arrival_time_s = 100.0

[[obstacles]]
name = "obstacle-1"
center_hill_m = [0.0, 500.0, 0.0]
radius_m = 50.0
detection_range_m = 100.0
"#;
    let scenario = dir.join(format!("{name}.toml"));
    std::fs::write(&scenario, text).unwrap();
    let out = dir.join(name);
    let o = satflock()
        .arg("run")
        .arg(&scenario)
        .arg("--out")
        .arg(&out)
        .args(["--quiet", "--no-plots", "--format", format])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    out
}

/// A copy of the run directory `from` as `to` (its files, not subfolders), replacing `to`.
pub fn copy_run(from: &std::path::Path, to: &std::path::Path) -> PathBuf {
    let _ = std::fs::remove_dir_all(to);
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        if entry.path().is_file() {
            std::fs::copy(entry.path(), to.join(entry.file_name())).unwrap();
        }
    }
    to.to_path_buf()
}
