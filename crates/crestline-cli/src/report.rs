//! Machine-readable run reports (`--report r.json`): stage timings and counts.

use std::collections::BTreeMap;
use std::fmt;
use std::io::Write;
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use serde::Serialize;
use serde_json::Value;

use crestline::io::write_atomically;
use crestline::progress::Observer;
use crestline::Result;

/// One timed stage of a run.
#[derive(Clone, Debug, Serialize)]
pub struct Stage {
    pub name: String,
    pub seconds: f64,
}

/// What a command did, as written by `--report`:
/// `{"command": ..., "input": ..., "stages": [{"name": ..., "seconds": ...}], "counts": {...},
/// "warnings": [...]}` (warnings only when there are some),
/// plus any further top-level sections a command adds with [`Report::section`].
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    pub command: String,
    pub input: String,
    pub stages: Vec<Stage>,
    pub counts: BTreeMap<String, Value>,
    /// The warnings about the input, as printed.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    #[serde(flatten)]
    pub sections: BTreeMap<String, Value>,
    /// Told the name of each stage as it starts (e.g. to show progress).
    #[serde(skip)]
    pub observer: StageObserver,
    /// The stage running, for its progress.
    #[serde(skip)]
    running: String,
}

/// A function of a stage name.
type StageCallback = Arc<dyn Fn(&str) + Send + Sync>;

/// A callback told the name of each stage of a [`Report`] as it starts.
#[derive(Clone, Default)]
pub struct StageObserver(Option<StageCallback>);

impl StageObserver {
    /// An observer calling `notify` with each stage name.
    pub fn new(notify: impl Fn(&str) + Send + Sync + 'static) -> StageObserver {
        StageObserver(Some(Arc::new(notify)))
    }

    fn notify(&self, stage: &str) {
        if let Some(notify) = &self.0 {
            notify(stage);
        }
    }
}

impl fmt::Debug for StageObserver {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(if self.0.is_some() {
            "StageObserver(..)"
        } else {
            "StageObserver(none)"
        })
    }
}

impl Report {
    /// An empty report for `command` run on `input`.
    pub fn new(command: &str, input: &Path) -> Report {
        Report {
            command: command.to_string(),
            input: input.display().to_string(),
            stages: Vec::new(),
            counts: BTreeMap::new(),
            warnings: Vec::new(),
            sections: BTreeMap::new(),
            observer: StageObserver::default(),
            running: String::new(),
        }
    }

    /// Run `work`, recording its wall-clock time as stage `name`.
    pub fn stage<T>(&mut self, name: &str, work: impl FnOnce() -> T) -> T {
        self.stage_started(name);
        let start = Instant::now();
        let result = work();
        self.stage_finished(name, start.elapsed().as_secs_f64());
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

    /// Write the report as pretty JSON (atomically).
    pub fn write(&self, path: &Path) -> Result<()> {
        write_atomically(path, |w| {
            serde_json::to_writer_pretty(&mut *w, self)?;
            writeln!(w)
        })
    }
}

/// The library's algorithms report into the run report: stages as they start (shown
/// by the spinner) and end (timed), counts and figures under `counts`.
impl Observer for Report {
    fn stage_started(&mut self, name: &str) {
        self.running = name.to_string();
        self.observer.notify(name);
    }

    /// Shown as `<stage> <done>/<total>`.
    fn progress(&mut self, done: usize, total: usize) {
        self.observer
            .notify(&format!("{} {done}/{total}", self.running));
    }

    fn stage_finished(&mut self, name: &str, seconds: f64) {
        self.stages.push(Stage {
            name: name.to_string(),
            seconds,
        });
    }

    fn count(&mut self, key: &str, value: usize) {
        Report::count(self, key, value);
    }

    fn measure(&mut self, key: &str, value: f64) {
        Report::count(self, key, value);
    }

    /// Until SIGINT or SIGTERM ([`crate::signals`]).
    fn keep_going(&mut self) -> bool {
        crate::signals::received().is_none()
    }

    /// Printed on stderr as `warning: <input>: <message>` with the options it
    /// names as flags, and kept in the report.
    fn warning(&mut self, message: &str) {
        let message = crate::as_flags(message);
        crate::warn(std::path::Path::new(&self.input), &message);
        self.warnings.push(message);
    }
}
