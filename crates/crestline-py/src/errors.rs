//! crestline's errors as the exceptions of `crestline._errors`: `FileError` (with
//! `.path`), `MeshError`, `ArgumentError` and `StageError` (with `.stage`), all
//! subclasses of `crestline.Error`.

use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

/// A crestline error as the Python exception of its kind, carrying the library's
/// message.
pub fn raised(error: crestline::Error) -> PyErr {
    // Options the message names are between backticks: Python spells them as is.
    let message = error.to_string().replace('`', "");
    let (class, attribute) = match &error {
        crestline::Error::File { path, .. } => {
            ("FileError", Some(("path", path.display().to_string())))
        }
        crestline::Error::Parse(_) => ("FileError", None),
        crestline::Error::Mesh(_) => ("MeshError", None),
        crestline::Error::Argument(_) => ("ArgumentError", None),
        crestline::Error::Stage { stage, .. } => ("StageError", Some(("stage", stage.clone()))),
        // A computation stopped from Python raises what stopped it (see
        // `progress::Callback::outcome`); one stopped otherwise is a Ctrl-C.
        crestline::Error::Cancelled => {
            return pyo3::exceptions::PyKeyboardInterrupt::new_err(message);
        }
    };
    Python::attach(|py| {
        let exception = || -> PyResult<Bound<'_, PyAny>> {
            let exception = py
                .import("crestline._errors")?
                .getattr(class)?
                .call1((message.as_str(),))?;
            if let Some((name, value)) = &attribute {
                exception.setattr(*name, value)?;
            }
            Ok(exception)
        };
        match exception() {
            Ok(exception) => PyErr::from_value(exception),
            Err(_) => PyRuntimeError::new_err(message.clone()),
        }
    })
}
