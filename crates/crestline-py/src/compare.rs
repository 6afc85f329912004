//! `crestline.compare`: the agreement of two lines or landmarks files
//! ([`crestline::compare`]).

use std::path::PathBuf;

use crestline::compare::{Features, Tolerance};
use crestline::register::RigidTransform;
use nalgebra::Matrix4;
use numpy::PyReadonlyArray2;
use pyo3::prelude::*;

use crate::errors::raised;

/// Register the module's functions.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(compare_files, m)?)?;
    Ok(())
}

/// The motion given as a transform file or as a 4 × 4 matrix (moving → fixed,
/// RAS), if either is.
fn motion(
    file: Option<PathBuf>,
    matrix: Option<PyReadonlyArray2<'_, f64>>,
) -> PyResult<Option<RigidTransform>> {
    if let Some(path) = file {
        return RigidTransform::read(&path).map(Some).map_err(raised);
    }
    let Some(matrix) = matrix else {
        return Ok(None);
    };
    let matrix = matrix.as_array();
    if matrix.dim() != (4, 4) {
        let message = format!("transform: expected 4 × 4, got {:?}", matrix.dim());
        return Err(raised(crestline::Error::Argument(message)));
    }
    let matrix = Matrix4::from_fn(|r, c| matrix[(r, c)]);
    RigidTransform::from_matrix4(&matrix)
        .map(Some)
        .map_err(raised)
}

/// The comparison of the files `a` and `b` (B first moved by the transform file
/// or matrix), within `tolerance` (a length, or a share of A's diagonal as
/// `"0.5%"`; default the library's), as JSON.
#[pyfunction]
#[pyo3(signature = (a, b, transform_file=None, transform_matrix=None, tolerance=None))]
fn compare_files(
    a: PathBuf,
    b: PathBuf,
    transform_file: Option<PathBuf>,
    transform_matrix: Option<PyReadonlyArray2<'_, f64>>,
    tolerance: Option<&str>,
) -> PyResult<String> {
    let tolerance = tolerance
        .map(str::parse::<Tolerance>)
        .transpose()
        .map_err(raised)?
        .unwrap_or_default();
    let first = Features::read(&a).map_err(raised)?;
    let mut second = Features::read(&b).map_err(raised)?;
    if let Some(motion) = motion(transform_file, transform_matrix)? {
        second = second.moved(&motion);
    }
    let (first, second) = Features::in_one_frame(first, second);
    let length = tolerance.resolve(&first).map_err(raised)?;
    let found = first.compare(&second, length);
    serde_json::to_string(&found).map_err(|e| raised(crestline::Error::Argument(e.to_string())))
}
