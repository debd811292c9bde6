//! `events.jsonl`: one JSON object per event firing, in firing order (`event`: the index in the
//! scenario's `[[events]]`, `time_s`, `tick`, `trigger`: `time_s` or the condition's key, `value`:
//! the condition's value in its unit or null, `action`). Each line goes to the system in one write,
//! so a run stopped at any point leaves whole lines.

use std::fs::File;
use std::io::Write;
use std::path::Path;

use crate::swarm::Firing;

/// The file name in a run directory.
pub const RUN_FILE: &str = "events.jsonl";

/// The open `events.jsonl` of a run.
#[derive(Debug)]
pub struct EventLog {
    file: File,
}

impl EventLog {
    /// Creates (or truncates) `dir/events.jsonl`.
    pub fn create(dir: &Path) -> std::io::Result<Self> {
        Ok(Self {
            file: File::create(dir.join(RUN_FILE))?,
        })
    }

    /// Appends one firing as a line.
    pub fn write(&mut self, firing: &Firing) -> std::io::Result<()> {
        let mut line = serde_json::to_string(firing).map_err(std::io::Error::other)?;
        line.push('\n');
        self.file.write_all(line.as_bytes())
    }

    /// Flushes the file to the system and closes it.
    pub fn finish(self) -> std::io::Result<()> {
        self.file.sync_data()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_firing_is_one_json_line() {
        let dir = std::env::temp_dir().join(format!("satflock-events-log-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut log = EventLog::create(&dir).unwrap();
        let firing = Firing {
            event: 2,
            time_s: 40.0,
            tick: 4,
            trigger: "min_separation_below_m",
            value: Some(4.5),
            action: "stop-run",
        };
        log.write(&firing).unwrap();
        log.write(&Firing {
            value: None,
            trigger: "time_s",
            ..firing
        })
        .unwrap();
        log.finish().unwrap();
        let text = std::fs::read_to_string(dir.join(RUN_FILE)).unwrap();
        let lines: Vec<serde_json::Value> = text
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        assert_eq!(lines.len(), 2);
        assert_eq!(lines[0]["event"], 2);
        assert_eq!(lines[0]["value"], 4.5);
        assert_eq!(lines[0]["action"], "stop-run");
        assert!(lines[1]["value"].is_null());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
