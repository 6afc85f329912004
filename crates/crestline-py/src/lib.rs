//! Python bindings of crestline: the extension module `crestline._crestline`.
//! The package `crestline` (in `python/`) wraps these functions, checks their
//! arguments (shapes, dtypes, finite values, index ranges) with errors that name
//! the argument, and documents them; here the arrays arrive contiguous, float64
//! vertices and int64 faces with indices in range.

use std::path::Path;

use crestline::curvature::{estimate_curvature, CurvatureField, Estimator};
use crestline::lines::{FeatureLines, LineExtractor, Polyline, SurfaceWithValues};
use crestline::mesh::{Mesh, RepairReport, TriangleSoup};
use crestline::morse::{MorseSmale, Simplification};
use crestline::ridges::ExtremalityTracer;
use crestline::{Point, Vector};
use numpy::ndarray::{Array1, Array2, ArrayView2};
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

create_exception!(
    _crestline,
    Error,
    PyException,
    "An error of crestline: a file that cannot be read, a mesh that cannot be used, \
     a computation that failed. The message names the file or the problem."
);

/// A crestline error as a Python exception.
fn raised(error: crestline::Error) -> PyErr {
    Error::new_err(error.to_string())
}

/// The triangle soup of the arrays.
fn soup(vertices: ArrayView2<f64>, faces: ArrayView2<i64>) -> TriangleSoup {
    TriangleSoup {
        positions: vertices
            .rows()
            .into_iter()
            .map(|r| Point::new(r[0], r[1], r[2]))
            .collect(),
        triangles: faces
            .rows()
            .into_iter()
            .map(|r| [r[0] as u32, r[1] as u32, r[2] as u32])
            .collect(),
        vertex_scalars: Vec::new(),
    }
}

/// The mesh of the arrays, whose vertices must be the mesh's: repairs that weld,
/// drop or split vertices would renumber them, and every per-vertex result would
/// then belong to other rows than the caller's.
fn mesh_of(vertices: ArrayView2<f64>, faces: ArrayView2<i64>) -> PyResult<Mesh> {
    let (mesh, report) = Mesh::from_soup(soup(vertices, faces)).map_err(raised)?;
    let kept = mesh.positions().len() == vertices.nrows()
        && mesh
            .positions()
            .iter()
            .zip(vertices.rows())
            .all(|(p, r)| p.x == r[0] && p.y == r[1] && p.z == r[2]);
    if !kept {
        return Err(PyValueError::new_err(format!(
            "the mesh needs repairs that renumber its vertices ({}); read it with \
             crestline.read_mesh, which returns the repaired arrays",
            report.messages().join("; ")
        )));
    }
    Ok(mesh)
}

/// The estimator named `estimator` and the mesh of the arrays ([`mesh_of`]).
fn inputs(
    vertices: &PyReadonlyArray2<f64>,
    faces: &PyReadonlyArray2<i64>,
    estimator: &str,
) -> PyResult<(Estimator, Mesh)> {
    let estimator: Estimator = estimator.parse().map_err(raised)?;
    Ok((estimator, mesh_of(vertices.as_array(), faces.as_array())?))
}

/// `n × 3` float64 array of vectors or points.
fn rows<'py>(
    py: Python<'py>,
    items: impl ExactSizeIterator<Item = [f64; 3]>,
) -> Bound<'py, PyArray2<f64>> {
    let n = items.len();
    let flat: Vec<f64> = items.flatten().collect();
    Array2::from_shape_vec((n, 3), flat)
        .expect("three values per row")
        .into_pyarray(py)
}

/// The repair report as JSON (the package turns it into a dict).
fn report_json(report: &RepairReport) -> String {
    serde_json::to_string(report).unwrap_or_else(|_| "{}".to_string())
}

/// Vertices (n × 3 float64), faces (m × 3 int64) and the repairs as JSON.
type MeshArrays<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<i64>>, String);

/// Read a mesh file (OBJ, PLY, OFF, STL) and repair it.
#[pyfunction]
fn read_mesh<'py>(py: Python<'py>, path: &str) -> PyResult<MeshArrays<'py>> {
    let path = Path::new(path);
    let (mesh, report) = py
        .detach(|| crestline::io::read_mesh(path).and_then(Mesh::from_soup))
        .map_err(raised)?;
    let vertices = rows(py, mesh.positions().iter().map(|p| [p.x, p.y, p.z]));
    let faces: Vec<i64> = mesh
        .faces()
        .flat_map(|f| mesh.face_vertices(f).map(|v| i64::from(v.0)))
        .collect();
    let faces = Array2::from_shape_vec((mesh.face_count(), 3), faces)
        .expect("three corners per face")
        .into_pyarray(py);
    Ok((vertices, faces, report_json(&report)))
}

/// Principal curvatures and directions per vertex, as a dict of arrays.
#[pyfunction]
fn curvature<'py>(
    py: Python<'py>,
    vertices: PyReadonlyArray2<'py, f64>,
    faces: PyReadonlyArray2<'py, i64>,
    estimator: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let (estimator, mesh) = inputs(&vertices, &faces, estimator)?;
    let field = py
        .detach(|| estimate_curvature(&mesh, estimator.build().as_ref()))
        .map_err(raised)?;
    field_dict(py, &field)
}

/// The arrays of a curvature field.
fn field_dict<'py>(py: Python<'py>, field: &CurvatureField) -> PyResult<Bound<'py, PyDict>> {
    let vectors = |v: &[Vector]| rows(py, v.iter().map(|d| [d.x, d.y, d.z]));
    let dict = PyDict::new(py);
    dict.set_item("k_max", Array1::from(field.k_max.clone()).into_pyarray(py))?;
    dict.set_item("k_min", Array1::from(field.k_min.clone()).into_pyarray(py))?;
    dict.set_item("d_max", vectors(&field.d_max))?;
    dict.set_item("d_min", vectors(&field.d_min))?;
    dict.set_item("normal", vectors(&field.normal))?;
    dict.set_item(
        "unreliable",
        Array1::from(field.unreliable.clone()).into_pyarray(py),
    )?;
    Ok(dict)
}

/// Ridge and valley lines by extremality tracing, each a dict of kind, closed,
/// strength, points (k × 3) and per-point values.
#[pyfunction]
fn ridges<'py>(
    py: Python<'py>,
    vertices: PyReadonlyArray2<'py, f64>,
    faces: PyReadonlyArray2<'py, i64>,
    estimator: &str,
    smooth_steps: usize,
    smooth_time: f64,
    threshold: f64,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let (estimator, mesh) = inputs(&vertices, &faces, estimator)?;
    let tracer = ExtremalityTracer {
        estimator: estimator.build(),
        smooth_steps,
        smooth_time,
        threshold,
        ..ExtremalityTracer::default()
    };
    line_dicts(py, py.detach(|| tracer.extract(&mesh)).map_err(raised)?)
}

/// Feature lines as 1-cells of a simplified Morse-Smale complex (Sahner et al.
/// 2008) of the curvedness, or of `values` (one per vertex) when given, as dicts
/// like [`ridges`]'.
#[pyfunction]
#[pyo3(signature = (vertices, faces, estimator, keep_saddles, values=None))]
fn morse<'py>(
    py: Python<'py>,
    vertices: PyReadonlyArray2<'py, f64>,
    faces: PyReadonlyArray2<'py, i64>,
    estimator: &str,
    keep_saddles: usize,
    values: Option<PyReadonlyArray1<'py, f64>>,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let (estimator, mesh) = inputs(&vertices, &faces, estimator)?;
    let complex = MorseSmale {
        estimator: estimator.build(),
        simplification: Simplification::KeepSaddles(keep_saddles),
        ..MorseSmale::default()
    };
    let values: Option<Vec<f64>> = values.map(|v| v.as_array().to_vec());
    let lines = py.detach(|| match &values {
        Some(values) => complex.extract(&SurfaceWithValues {
            mesh: &mesh,
            values,
        }),
        None => complex.extract(&mesh),
    });
    line_dicts(py, lines.map_err(raised)?)
}

/// Every line as a dict ([`line_dict`]).
fn line_dicts(py: Python<'_>, lines: FeatureLines) -> PyResult<Vec<Bound<'_, PyDict>>> {
    lines.iter().map(|line| line_dict(py, line)).collect()
}

/// One line as a dict.
fn line_dict<'py>(py: Python<'py>, line: &Polyline) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    dict.set_item("kind", line.kind.name())?;
    dict.set_item("closed", line.closed)?;
    dict.set_item("strength", line.strength)?;
    dict.set_item(
        "points",
        rows(py, line.points.iter().map(|p| [p.x, p.y, p.z])),
    )?;
    let values = PyDict::new(py);
    for (name, v) in &line.values {
        values.set_item(name, Array1::from(v.clone()).into_pyarray(py))?;
    }
    dict.set_item("values", values)?;
    Ok(dict)
}

/// The extension module.
#[pymodule]
fn _crestline(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("Error", m.py().get_type::<Error>())?;
    m.add_function(wrap_pyfunction!(read_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(curvature, m)?)?;
    m.add_function(wrap_pyfunction!(ridges, m)?)?;
    m.add_function(wrap_pyfunction!(morse, m)?)?;
    Ok(())
}
