//! Progress of long computations reported to a Python callable, and their
//! cancellation from Python: Ctrl-C (KeyboardInterrupt) or a callback that raises.

use crestline::progress::Observer;
use pyo3::prelude::*;

/// Calls `callback(stage, seconds)` when a stage starts (`seconds` is `None`) and
/// when it ends, and asks Python for pending signals whenever the computation
/// asks whether to go on. An exception — the callback's, or the KeyboardInterrupt
/// of a Ctrl-C — stops the computation at its next checkpoint and is raised by
/// [`Callback::outcome`].
pub struct Callback {
    callback: Option<Py<PyAny>>,
    raised: Option<PyErr>,
}

impl Callback {
    /// An observer calling `callback`, if any.
    pub fn new(callback: Option<Py<PyAny>>) -> Callback {
        Callback {
            callback,
            raised: None,
        }
    }

    fn call(&mut self, stage: &str, seconds: Option<f64>) {
        if self.raised.is_some() {
            return;
        }
        if let Some(callback) = &self.callback {
            let result = Python::attach(|py| callback.call1(py, (stage, seconds)).map(drop));
            self.raised = result.err();
        }
    }

    /// The computation's result as Python sees it: the exception that stopped it
    /// (or was raised by the callback after its last checkpoint) if there is one,
    /// else the library's error or value.
    pub fn outcome<T>(self, result: crestline::Result<T>) -> PyResult<T> {
        match self.raised {
            Some(error) => Err(error),
            None => result.map_err(crate::errors::raised),
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

    /// Shown as a Python `UserWarning` (through the `warnings` module, so that
    /// filters apply), the options it names spelled as the keyword arguments.
    fn warning(&mut self, message: &str) {
        let shown = Python::attach(|py| {
            let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
            let message = std::ffi::CString::new(message.replace(['\0', '`'], ""))
                .expect("no NUL left in the message");
            PyErr::warn(py, &category, &message, 1)
        });
        if let Err(error) = shown {
            self.raised.get_or_insert(error);
        }
    }

    fn keep_going(&mut self) -> bool {
        if self.raised.is_none() {
            self.raised = Python::attach(|py| py.check_signals()).err();
        }
        self.raised.is_none()
    }
}
