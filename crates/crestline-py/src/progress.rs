//! Progress of long computations reported to a Python callable.

use crestline::progress::Observer;
use pyo3::prelude::*;

/// Calls `callback(stage, seconds)` when a stage starts (`seconds` is `None`) and
/// when it ends. An exception raised by the callback is printed by Python and
/// otherwise ignored: progress must not break the computation.
pub struct Callback(pub Option<Py<PyAny>>);

impl Callback {
    fn call(&self, stage: &str, seconds: Option<f64>) {
        if let Some(callback) = &self.0 {
            Python::attach(|py| {
                if let Err(error) = callback.call1(py, (stage, seconds)) {
                    error.print(py);
                }
            });
        }
    }
}

impl Observer for Callback {
    fn stage_started(&mut self, name: &str) {
        self.call(name, None);
    }

    fn stage_finished(&mut self, name: &str, seconds: f64) {
        self.call(name, Some(seconds));
    }
}
