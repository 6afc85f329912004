//! The library's jobs as Python sees them: their defaults and the names of every
//! choice, read from the library, and options given as JSON objects.

use crestline::crest_lines::LineFamily;
use crestline::curvature::Estimator;
use crestline::jobs::{self, CurvatureSource, LinesChoice};
use crestline::morse::{Cells, Criterion, Indicator};
use crestline::ridges::Kinds;
use crestline::ridges::Solver;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::raised;

/// The functions of this module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(defaults, m)?)?;
    m.add_function(wrap_pyfunction!(names, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}

/// Every job's defaults as JSON ([`jobs::defaults`]).
#[pyfunction]
fn defaults() -> String {
    jobs::defaults().to_string()
}

/// The names of every choice, by what they choose.
#[pyfunction]
fn names(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let dict = PyDict::new(py);
    dict.set_item("estimator", Estimator::NAMES)?;
    dict.set_item("kind", Kinds::NAMES)?;
    dict.set_item("solver", Solver::NAMES)?;
    dict.set_item("curvature", CurvatureSource::NAMES)?;
    dict.set_item("family", LineFamily::NAMES)?;
    dict.set_item("criterion", Criterion::NAMES)?;
    dict.set_item("cells", Cells::NAMES)?;
    dict.set_item("indicator", Indicator::NAMES)?;
    dict.set_item("lines", LinesChoice::NAMES)?;
    dict.set_item("space", crestline::Space::NAMES)?;
    Ok(dict)
}

/// The options of `job` from a JSON object of the options given; the others
/// keep the library's defaults.
pub fn job_options<T>(job: &str, json: &str) -> PyResult<T>
where
    T: serde::de::DeserializeOwned + serde::Serialize + Default,
{
    let given: serde_json::Value = serde_json::from_str(json).map_err(|e| {
        raised(crestline::Error::Argument(format!(
            "the options of {job}: {e}"
        )))
    })?;
    jobs::options_from_json(job, &given).map_err(raised)
}
