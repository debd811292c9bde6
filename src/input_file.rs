//! The one way satflock reads a file it is given: a scenario, a controller (`--law`), a campaign file,
//! a force file (`--forces`), a positions CSV and every file of a run directory (`summary.json`,
//! `scene.json`, `scenario.toml`, the metrics and trajectory tables, the plots the report embeds).
//!
//! The file must be a regular file (a device such as `/dev/zero`, a FIFO or a directory is refused
//! before anything is read: it would be read forever, or block) and at most a stated number of bytes
//! ([`MAX_DOCUMENT_BYTES`] for TOML and JSON documents, [`MAX_TABLE_BYTES`] for tables and images).
//! The limit is checked on the opened file and again while reading (a file that grows after the check
//! is cut at the limit and refused), so nothing reads more than the limit whatever the file claims.
//!
//! A Parquet file is read through [`ParquetFile`]: every offset and length its footer states is checked
//! against the file's real length before anything is read, so no footer makes the reader allocate more
//! than the file holds.
//!
//! Errors are [`std::io::Error`]s (kind `InvalidInput`) whose message says what is allowed; every
//! caller names the file beside it, as it does for a file that does not exist.

use std::fs::File;
use std::io::{Error, ErrorKind, Read};
use std::path::Path;

use parquet::errors::ParquetError;
use parquet::file::reader::{ChunkReader, Length};

/// Largest TOML or JSON document read \[bytes\] (256 MiB): scenario, controller, campaign and force
/// files, `summary.json`, `scene.json`, `scenario.toml` of a run. A force file has its own smaller
/// limit ([`crate::dynamics::MAX_FORCES_FILE_BYTES`]).
pub const MAX_DOCUMENT_BYTES: u64 = 256 << 20;

/// Largest table, image or log read \[bytes\] (4 GiB): `metrics.*`, `trajectory.*`, a positions CSV, the
/// plots embedded in a report, a campaign's `manifest.jsonl`.
pub const MAX_TABLE_BYTES: u64 = 4 << 30;

/// A byte count for people: `256 MiB (268435456 bytes)`, `4 GiB (…)`, or `N bytes`.
fn size_text(bytes: u64) -> String {
    match bytes {
        b if b >= 1 << 30 && b % (1 << 30) == 0 => format!("{} GiB ({b} bytes)", b >> 30),
        b if b >= 1 << 20 && b % (1 << 20) == 0 => format!("{} MiB ({b} bytes)", b >> 20),
        b => format!("{b} bytes"),
    }
}

fn too_large(bytes: u64, limit: u64) -> Error {
    Error::new(
        ErrorKind::InvalidInput,
        format!(
            "is {bytes} bytes, too large (allowed: at most {} for this file)",
            size_text(limit)
        ),
    )
}

/// Opens `path` for reading if it is a regular file of at most `limit` bytes.
pub fn open(path: &Path, limit: u64) -> std::io::Result<File> {
    let file = File::open(path)?;
    let metadata = file.metadata()?;
    if !metadata.is_file() {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            "is not a regular file (allowed: a regular file; a device, FIFO or directory is refused)",
        ));
    }
    if metadata.len() > limit {
        return Err(too_large(metadata.len(), limit));
    }
    Ok(file)
}

/// A Parquet file opened by [`open_parquet`]: what the `parquet` readers read, with every footer offset
/// and length checked against the file's length first.
#[derive(Debug)]
pub struct ParquetFile {
    file: File,
    len: u64,
}

impl ParquetFile {
    fn check(&self, start: u64, length: u64) -> parquet::errors::Result<()> {
        match start.checked_add(length) {
            Some(end) if end <= self.len => Ok(()),
            _ => Err(ParquetError::EOF(format!(
                "the footer points at {length} bytes from offset {start}, beyond the file's {} bytes",
                self.len
            ))),
        }
    }
}

impl Length for ParquetFile {
    fn len(&self) -> u64 {
        self.len
    }
}

impl ChunkReader for ParquetFile {
    type T = <File as ChunkReader>::T;

    fn get_read(&self, start: u64) -> parquet::errors::Result<Self::T> {
        self.check(start, 0)?;
        self.file.get_read(start)
    }

    fn get_bytes(&self, start: u64, length: usize) -> parquet::errors::Result<bytes::Bytes> {
        self.check(start, length as u64)?;
        self.file.get_bytes(start, length)
    }
}

/// Opens the Parquet file `path`, a regular file of at most `limit` bytes.
pub fn open_parquet(path: &Path, limit: u64) -> std::io::Result<ParquetFile> {
    let file = open(path, limit)?;
    let len = file.metadata()?.len();
    Ok(ParquetFile { file, len })
}

/// The bytes of `path`, a regular file of at most `limit` bytes.
pub fn read(path: &Path, limit: u64) -> std::io::Result<Vec<u8>> {
    let file = open(path, limit)?;
    let expected = file.metadata()?.len();
    let mut bytes = Vec::with_capacity(usize::try_from(expected).unwrap_or(0));
    file.take(limit.saturating_add(1)).read_to_end(&mut bytes)?;
    let read = bytes.len() as u64;
    if read > limit {
        return Err(too_large(read, limit));
    }
    Ok(bytes)
}

/// The text of `path`, a regular UTF-8 file of at most `limit` bytes.
pub fn read_to_string(path: &Path, limit: u64) -> std::io::Result<String> {
    String::from_utf8(read(path, limit)?).map_err(|e| {
        Error::new(
            ErrorKind::InvalidData,
            format!(
                "is not UTF-8 text (byte {} is not valid UTF-8)",
                e.utf8_error().valid_up_to()
            ),
        )
    })
}

/// The text of a TOML or JSON document: [`read_to_string`] with [`MAX_DOCUMENT_BYTES`].
pub fn read_document(path: &Path) -> std::io::Result<String> {
    read_to_string(path, MAX_DOCUMENT_BYTES)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> std::path::PathBuf {
        let dir =
            std::env::temp_dir().join(format!("satflock-input-file-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn reads_a_regular_file_within_its_limit() {
        let dir = scratch("ok");
        let path = dir.join("a.toml");
        std::fs::write(&path, "abc").unwrap();
        assert_eq!(read_document(&path).unwrap(), "abc");
        assert_eq!(read(&path, 3).unwrap(), b"abc");
        let e = read(&path, 2).unwrap_err();
        assert_eq!(e.kind(), ErrorKind::InvalidInput);
        assert_eq!(
            e.to_string(),
            "is 3 bytes, too large (allowed: at most 2 bytes for this file)"
        );
        std::fs::write(&path, [0xff, 0xfe]).unwrap();
        assert!(read_document(&path)
            .unwrap_err()
            .to_string()
            .contains("not UTF-8"));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_parquet_footer_cannot_point_beyond_the_file() {
        let dir = scratch("parquet");
        let path = dir.join("t.parquet");
        std::fs::write(&path, [0u8; 100]).unwrap();
        let file = open_parquet(&path, MAX_TABLE_BYTES).unwrap();
        assert_eq!(file.len(), 100);
        assert_eq!(file.get_bytes(90, 10).unwrap().len(), 10);
        for (start, length) in [(90, 11), (101, 0), (u64::MAX, 1)] {
            let e = file.check(start, length).unwrap_err();
            assert!(e.to_string().contains("beyond the file's 100 bytes"), "{e}");
        }
        assert!(file.get_bytes(0, usize::MAX).is_err());
        assert!(file.get_read(101).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn refuses_devices_and_directories_before_reading() {
        for path in ["/dev/zero", "/dev/null"] {
            if Path::new(path).exists() {
                let e = read_document(Path::new(path)).unwrap_err();
                assert!(e.to_string().contains("not a regular file"), "{path}: {e}");
            }
        }
        let dir = scratch("dir");
        assert!(read_document(&dir).is_err());
        assert!(open(&dir, MAX_TABLE_BYTES).is_err());
        assert!(open_parquet(&dir, MAX_TABLE_BYTES).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(size_text(MAX_DOCUMENT_BYTES), "256 MiB (268435456 bytes)");
        assert_eq!(size_text(MAX_TABLE_BYTES), "4 GiB (4294967296 bytes)");
    }
}
