//! Progress and stage timings of long computations, told to an [`Observer`].
//!
//! Every algorithm that runs in stages (ridges, Morse-Smale lines) takes a
//! `&mut dyn Observer` and reports each stage as it starts and ends, and the figures
//! it measures on the way (line counts, the share of singular triangles, ...). A
//! command-line tool turns these into a spinner and a JSON report, a Python binding
//! into a callback; [`Silent`] ignores them.

use std::time::Instant;

/// Told what a computation is doing. Every method has an empty default, so an
/// observer implements only what it needs.
pub trait Observer {
    /// Stage `name` starts.
    fn stage_started(&mut self, name: &str) {
        let _ = name;
    }

    /// Stage `name` ended after `seconds` of wall-clock time.
    fn stage_finished(&mut self, name: &str, seconds: f64) {
        let _ = (name, seconds);
    }

    /// A count measured by the run, e.g. `("lines", 12)`.
    fn count(&mut self, key: &str, value: usize) {
        let _ = (key, value);
    }

    /// A real-valued figure measured by the run, e.g. `("total_length", 3.2)`.
    fn measure(&mut self, key: &str, value: f64) {
        let _ = (key, value);
    }
}

/// An observer that ignores everything.
#[derive(Clone, Copy, Debug, Default)]
pub struct Silent;

impl Observer for Silent {}

/// Run `work` as stage `name`: tell `observer` when it starts and how long it took.
pub fn stage<T>(observer: &mut dyn Observer, name: &str, work: impl FnOnce() -> T) -> T {
    observer.stage_started(name);
    let start = Instant::now();
    let result = work();
    observer.stage_finished(name, start.elapsed().as_secs_f64());
    result
}

/// [`stage`] for work that can fail: its error says which stage failed
/// ([`crate::Error::in_stage`]).
pub fn try_stage<T>(
    observer: &mut dyn Observer,
    name: &str,
    work: impl FnOnce() -> crate::Result<T>,
) -> crate::Result<T> {
    stage(observer, name, work).map_err(|e| e.in_stage(name))
}
