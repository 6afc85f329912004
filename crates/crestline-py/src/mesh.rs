//! The mesh half: reading meshes, curvature, ridges and Morse-Smale lines.

use std::path::PathBuf;
use std::sync::Arc;

use crestline::curvature::{CurvatureField, Estimator, GivenCurvature};
use crestline::jobs::{self, Surface};
use crestline::mesh::{Mesh, RepairReport};
use crestline::Vector;
use numpy::ndarray::Array1;
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{faces, points, report_json, rows, soup};
use crate::built_mesh::BuiltMesh;
use crate::errors::raised;
use crate::jobs::job_options;
use crate::lines::line_dicts;
use crate::progress::Callback;
use crate::volume::landmarks_json;

/// The functions of this module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(read_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(repair_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(curvature, m)?)?;
    m.add_function(wrap_pyfunction!(ridges, m)?)?;
    m.add_function(wrap_pyfunction!(mesh_landmarks, m)?)?;
    m.add_function(wrap_pyfunction!(morse, m)?)?;
    m.add_class::<BuiltMesh>()?;
    Ok(())
}

/// Vertices (n × 3 float64), faces (m × 3 int64) and the repairs as JSON.
type MeshArrays<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<i64>>, String);

/// Read a mesh file (OBJ, PLY, OFF, STL) and repair it.
#[pyfunction]
fn read_mesh<'py>(py: Python<'py>, path: PathBuf) -> PyResult<MeshArrays<'py>> {
    let path = path.as_path();
    let repaired = py
        .detach(|| crestline::io::read_mesh(path).and_then(Mesh::from_soup))
        .map_err(raised)?;
    Ok(mesh_arrays(py, repaired))
}

/// Repair the mesh of the arrays as [`read_mesh`] repairs a file's
/// ([`Mesh::from_soup`]).
#[pyfunction]
fn repair_mesh<'py>(
    py: Python<'py>,
    vertices: PyReadonlyArray2<'py, f64>,
    faces: PyReadonlyArray2<'py, i64>,
) -> PyResult<MeshArrays<'py>> {
    let (vertices, faces) = (vertices.as_array(), faces.as_array());
    let repaired = py
        .detach(|| Mesh::from_soup(soup(vertices, faces)))
        .map_err(raised)?;
    Ok(mesh_arrays(py, repaired))
}

/// The arrays of a repaired mesh, with its repairs.
fn mesh_arrays<'py>(py: Python<'py>, (mesh, report): (Mesh, RepairReport)) -> MeshArrays<'py> {
    let vertices = rows(py, mesh.positions().iter().map(|p| [p.x, p.y, p.z]));
    (vertices, faces(py, &mesh), report_json(&report))
}

/// Principal curvatures and directions per vertex ([`jobs::curvature`] with the
/// JSON `options` of [`jobs::CurvatureOptions`]), as a dict of arrays.
#[pyfunction]
fn curvature<'py>(
    py: Python<'py>,
    mesh: Bound<'py, BuiltMesh>,
    options: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let options: jobs::CurvatureOptions = job_options("curvature", options)?;
    let surface = mesh.get().surface();
    let mut observer = Callback::new(None);
    let field = py.detach(|| jobs::curvature(surface, &options, &mut observer));
    field_dict(py, observer.outcome(field)?)
}

/// The arrays of a curvature field (its per-vertex values moved, not copied).
fn field_dict(py: Python<'_>, field: CurvatureField) -> PyResult<Bound<'_, PyDict>> {
    let vectors = |v: &[Vector]| rows(py, v.iter().map(|d| [d.x, d.y, d.z]));
    let dict = PyDict::new(py);
    dict.set_item("d_max", vectors(&field.d_max))?;
    dict.set_item("d_min", vectors(&field.d_min))?;
    dict.set_item("normal", vectors(&field.normal))?;
    dict.set_item("k_max", Array1::from(field.k_max).into_pyarray(py))?;
    dict.set_item("k_min", Array1::from(field.k_min).into_pyarray(py))?;
    dict.set_item(
        "unreliable",
        Array1::from(field.unreliable).into_pyarray(py),
    )?;
    if let Some([e_max, e_min]) = field.extremality {
        dict.set_item("e_max", Array1::from(e_max).into_pyarray(py))?;
        dict.set_item("e_min", Array1::from(e_min).into_pyarray(py))?;
    }
    if let Some(residual) = field.fit_residual {
        dict.set_item("fit_residual", Array1::from(residual).into_pyarray(py))?;
    }
    Ok(dict)
}

/// The array `name` of a curvature dict checked by the package, if present.
fn entry<'py, T: FromPyObjectOwned<'py>>(
    field: &Bound<'py, PyDict>,
    name: &str,
) -> PyResult<Option<T>> {
    field
        .get_item(name)?
        .map(|v| v.extract().map_err(Into::into))
        .transpose()
}

/// The array `name` of a curvature dict, which must be there.
fn required<'py, T: FromPyObjectOwned<'py>>(field: &Bound<'py, PyDict>, name: &str) -> PyResult<T> {
    entry(field, name)?
        .ok_or_else(|| PyValueError::new_err(format!("estimator result: no {name:?}")))
}

/// The curvature field of a dict of arrays checked by the package (one row per
/// vertex): `k_max`, `k_min`, `d_max`, `d_min`, `normal`, `unreliable`, and the
/// fitted `e_max`, `e_min` and `fit_residual` when present.
fn field_of(field: &Bound<'_, PyDict>) -> PyResult<CurvatureField> {
    let vectors = |name: &str| -> PyResult<Vec<Vector>> {
        let array: PyReadonlyArray2<f64> = required(field, name)?;
        Ok(points(array.as_array())
            .into_iter()
            .map(|p| p.coords)
            .collect())
    };
    let values = |name: &str| -> PyResult<Option<Vec<f64>>> {
        Ok(entry::<PyReadonlyArray1<f64>>(field, name)?.map(|a| a.as_array().to_vec()))
    };
    let curvature = |name: &str| -> PyResult<Vec<f64>> {
        Ok(required::<PyReadonlyArray1<f64>>(field, name)?
            .as_array()
            .to_vec())
    };
    let unreliable: PyReadonlyArray1<bool> = required(field, "unreliable")?;
    Ok(CurvatureField {
        k_max: curvature("k_max")?,
        k_min: curvature("k_min")?,
        d_max: vectors("d_max")?,
        d_min: vectors("d_min")?,
        normal: vectors("normal")?,
        unreliable: unreliable.as_array().to_vec(),
        extremality: match (values("e_max")?, values("e_min")?) {
            (Some(e_max), Some(e_min)) => Some([e_max, e_min]),
            _ => None,
        },
        fit_residual: values("fit_residual")?,
    })
}

/// The ridges options of the JSON `options` ([`jobs::RidgesOptions`]) with the
/// per-vertex smoothing `weights`.
fn ridges_options(
    options: &str,
    weights: Option<PyReadonlyArray1<f64>>,
) -> PyResult<jobs::RidgesOptions> {
    let mut options: jobs::RidgesOptions = job_options("ridges", options)?;
    options.smoothing_weights = weights.map(|w| w.as_array().to_vec());
    Ok(options)
}

/// Ridge and valley lines by extremality tracing ([`jobs::ridges`]) as the JSON
/// `options` of [`jobs::RidgesOptions`] say, each a dict of kind, closed,
/// strength, points (k × 3), per-point values and surface locations. With
/// `field`, the curvature is that one (from a callable estimator) instead of the
/// estimator's, and the smoothing defaults are those of its extremalities (the
/// jet fit's when it has fitted ones).
#[pyfunction]
#[pyo3(signature = (mesh, options, weights=None, field=None, progress=None))]
fn ridges<'py>(
    py: Python<'py>,
    mesh: Bound<'py, BuiltMesh>,
    options: &str,
    weights: Option<PyReadonlyArray1<'py, f64>>,
    field: Option<Bound<'py, PyDict>>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let surface = mesh.get().surface();
    let mut options = ridges_options(options, weights)?;
    let field = field.as_ref().map(field_of).transpose()?;
    if let Some(field) = &field {
        options.estimator = if field.extremality.is_some() {
            Estimator::JetFit
        } else {
            Estimator::ShapeOperator
        };
    }
    let mut observer = Callback::new(progress);
    let lines = py.detach(|| match &field {
        Some(field) => {
            options
                .tracer(surface)
                .trace_with_curvature(&surface.mesh, field, &mut observer)
        }
        None => jobs::ridges(surface, &options, &mut observer),
    });
    line_dicts(py, &observer.outcome(lines)?.lines, Some(&surface.mesh))
}

/// The landmarks of the ridges and valleys of the mesh ([`jobs::landmarks`]
/// from [`jobs::LinesFrom::Surface`]), as the JSON the library writes; `ridges`
/// and `options` are the JSON options of the tracing and of the landmarks.
#[pyfunction]
#[pyo3(signature = (mesh, ridges, options, weights=None, progress=None))]
fn mesh_landmarks<'py>(
    py: Python<'py>,
    mesh: Bound<'py, BuiltMesh>,
    ridges: &str,
    options: &str,
    weights: Option<PyReadonlyArray1<'py, f64>>,
    progress: Option<Py<PyAny>>,
) -> PyResult<String> {
    let surface = mesh.get().surface();
    let ridges = ridges_options(ridges, weights)?;
    let options: jobs::LandmarksOptions = job_options("landmarks", options)?;
    let mut observer = Callback::new(progress);
    let found = py.detach(|| {
        let input = jobs::LinesFrom::Surface {
            surface,
            options: &ridges,
        };
        jobs::landmarks(input, &options, &mut observer)
    });
    landmarks_json(&observer.outcome(found)?)
}

/// Feature lines from the Morse-Smale complex ([`jobs::morse`]) as the JSON
/// `options` of [`jobs::MorseOptions`] say, of the per-vertex `values` when given
/// instead of the indicator, the curvature of `field` when given (from a callable
/// estimator) instead of the estimator's; as dicts like [`ridges`]'.
#[pyfunction]
#[pyo3(signature = (mesh, options, values=None, field=None, progress=None))]
fn morse<'py>(
    py: Python<'py>,
    mesh: Bound<'py, BuiltMesh>,
    options: &str,
    values: Option<PyReadonlyArray1<'py, f64>>,
    field: Option<Bound<'py, PyDict>>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let options: jobs::MorseOptions = job_options("morse", options)?;
    let built = mesh.get().surface();
    // A given field needs a surface of its own (rare: a callable estimator's).
    let with_field = field
        .as_ref()
        .map(field_of)
        .transpose()?
        .map(|field| Surface {
            curvature: Some(Arc::new(GivenCurvature(field))),
            ..Surface::of_mesh(built.mesh.clone())
        });
    let surface = with_field.as_ref().unwrap_or(built);
    let values: Option<Vec<f64>> = values.map(|v| v.as_array().to_vec());
    let mut observer = Callback::new(progress);
    let found = py.detach(|| jobs::morse(surface, values, &options, &mut observer));
    let (lines, _) = observer.outcome(found)?;
    line_dicts(py, &lines.lines, Some(&surface.mesh))
}
