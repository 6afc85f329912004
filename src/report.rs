//! Machine-readable run reports (`--report r.json`): stage timings and counts.

use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

use serde::Serialize;
use serde_json::Value;

use std::io::Write;

use crate::io::atomic::write_atomically;
use crate::Result;

/// One timed stage of a run.
#[derive(Clone, Debug, Serialize)]
pub struct Stage {
    pub name: String,
    pub seconds: f64,
}

/// What a command did, as written by `--report`:
/// `{"command": ..., "input": ..., "stages": [{"name": ..., "seconds": ...}], "counts": {...}}`,
/// plus any further top-level sections a command adds with [`Report::section`].
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    pub command: String,
    pub input: String,
    pub stages: Vec<Stage>,
    pub counts: BTreeMap<String, Value>,
    #[serde(flatten)]
    pub sections: BTreeMap<String, Value>,
}

impl Report {
    /// An empty report for `command` run on `input`.
    pub fn new(command: &str, input: &Path) -> Report {
        Report {
            command: command.to_string(),
            input: input.display().to_string(),
            stages: Vec::new(),
            counts: BTreeMap::new(),
            sections: BTreeMap::new(),
        }
    }

    /// Run `work`, recording its wall-clock time as stage `name`.
    pub fn stage<T>(&mut self, name: &str, work: impl FnOnce() -> T) -> T {
        let start = Instant::now();
        let result = work();
        self.stages.push(Stage {
            name: name.to_string(),
            seconds: start.elapsed().as_secs_f64(),
        });
        result
    }

    /// Record a count (or any value) under `counts`.
    pub fn count(&mut self, key: &str, value: impl Into<Value>) {
        self.counts.insert(key.to_string(), value.into());
    }

    /// Add a top-level section, e.g. `"repairs": {...}`.
    pub fn section(&mut self, key: &str, value: impl Serialize) {
        let value = serde_json::to_value(value).unwrap_or(Value::Null);
        self.sections.insert(key.to_string(), value);
    }

    /// Total seconds over all stages.
    pub fn total_seconds(&self) -> f64 {
        self.stages.iter().map(|s| s.seconds).sum()
    }

    /// Write the report as pretty JSON (atomically).
    pub fn write(&self, path: &Path) -> Result<()> {
        write_atomically(path, |w| {
            serde_json::to_writer_pretty(&mut *w, self)?;
            writeln!(w)
        })
    }
}
