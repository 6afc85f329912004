//! Progress, warnings and cancellation of long computations, told to an
//! [`Observer`].
//!
//! Every algorithm that runs in stages (the jobs of [`crate::jobs`], ridges,
//! Morse-Smale lines, Marching Lines, crease surfaces) takes a `&mut dyn Observer`
//! and reports each stage as it starts and ends (and, in its long stages, how many of
//! their parts are done), the figures it measures on the way (line counts, the share
//! of singular triangles, ...) and warnings about its input. Between stages, and
//! inside its own long loops, it asks the observer whether to go on
//! ([`Observer::keep_going`], through `checkpoint`); an observer that says no stops
//! the computation with [`crate::Error::Cancelled`]. A command-line tool turns these
//! into a spinner and a JSON report, a Python binding into a callback that can also
//! stop the run (Ctrl-C, or a callback that raises); [`Silent`] ignores them and
//! never stops.

use std::time::Instant;

/// Told what a computation is doing, and asked whether it should go on. Every
/// method has a default, so an observer implements only what it needs.
pub trait Observer {
    /// Stage `name` starts.
    fn stage_started(&mut self, name: &str) {
        let _ = name;
    }

    /// Stage `name` ended after `seconds` of wall-clock time.
    fn stage_finished(&mut self, name: &str, seconds: f64) {
        let _ = (name, seconds);
    }

    /// The running stage has done `done` of its `total` parts (e.g. the implicit
    /// smoothing steps of the extremalities), told as each part ends and once
    /// before the first.
    fn progress(&mut self, done: usize, total: usize) {
        let _ = (done, total);
    }

    /// A count measured by the run, e.g. `("lines", 12)`.
    fn count(&mut self, key: &str, value: usize) {
        let _ = (key, value);
    }

    /// A real-valued figure measured by the run, e.g. `("total_length", 3.2)`.
    fn measure(&mut self, key: &str, value: f64) {
        let _ = (key, value);
    }

    /// Something about the input the run repaired or could not use, that its user
    /// should know (e.g. non-finite samples set to the background). The run goes
    /// on. An option the message suggests changing is named between backticks as
    /// its options struct spells it (`` `min_length` ``), for each caller to show
    /// in its own spelling (`--min-length` on a command line).
    fn warning(&mut self, message: &str) {
        let _ = message;
    }

    /// Whether the computation should go on; asked between stages and inside long
    /// loops, on the thread that started the computation. `false` stops it with
    /// [`crate::Error::Cancelled`] at the next `checkpoint`.
    fn keep_going(&mut self) -> bool {
        true
    }
}

/// An observer that ignores everything and never stops a computation.
#[derive(Clone, Copy, Debug, Default)]
pub struct Silent;

impl Observer for Silent {}

/// Ask `observer` whether to go on: [`crate::Error::Cancelled`] if it says no.
pub(crate) fn checkpoint(observer: &mut dyn Observer) -> crate::Result<()> {
    if observer.keep_going() {
        Ok(())
    } else {
        Err(crate::Error::Cancelled)
    }
}

/// Run `work` as stage `name`: tell `observer` when it starts and how long it took.
pub(crate) fn stage<T>(observer: &mut dyn Observer, name: &str, work: impl FnOnce() -> T) -> T {
    observer.stage_started(name);
    let start = Instant::now();
    let result = work();
    observer.stage_finished(name, start.elapsed().as_secs_f64());
    result
}

/// [`stage`] for work that can fail, between two [`checkpoint`]s: its error says
/// which stage failed ([`crate::Error::in_stage`]), and a cancellation asked for
/// before or during the stage stops the computation.
pub(crate) fn try_stage<T>(
    observer: &mut dyn Observer,
    name: &str,
    work: impl FnOnce() -> crate::Result<T>,
) -> crate::Result<T> {
    try_stage_with(observer, name, |_| work())
}

/// [`try_stage`] for work that reports stages of its own to the same observer
/// (its stages nest in this one).
pub(crate) fn try_stage_with<T>(
    observer: &mut dyn Observer,
    name: &str,
    work: impl FnOnce(&mut dyn Observer) -> crate::Result<T>,
) -> crate::Result<T> {
    checkpoint(observer)?;
    observer.stage_started(name);
    let start = Instant::now();
    let result = work(observer);
    observer.stage_finished(name, start.elapsed().as_secs_f64());
    let result = result.map_err(|e| e.in_stage(name))?;
    checkpoint(observer)?;
    Ok(result)
}

/// An observer that keeps the time of every stage, in the order they ended.
#[derive(Clone, Debug, Default)]
pub struct Timings {
    /// `(stage, seconds)` per finished stage.
    pub stages: Vec<(String, f64)>,
}

impl Timings {
    /// The seconds of every stage named `name`, added up.
    pub fn seconds(&self, name: &str) -> f64 {
        self.stages
            .iter()
            .filter(|(stage, _)| stage == name)
            .map(|(_, seconds)| seconds)
            .sum()
    }
}

impl Observer for Timings {
    fn stage_finished(&mut self, name: &str, seconds: f64) {
        self.stages.push((name.to_string(), seconds));
    }
}
