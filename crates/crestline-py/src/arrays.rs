//! Between numpy arrays and the library's meshes, points and vectors.

use crestline::mesh::{Mesh, RepairReport, TriangleSoup};
use crestline::Point;
use numpy::ndarray::{Array2, ArrayView2};
use numpy::{IntoPyArray, PyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::errors::raised;

/// The triangle soup of the arrays.
pub fn soup(vertices: ArrayView2<f64>, faces: ArrayView2<i64>) -> TriangleSoup {
    TriangleSoup {
        positions: points(vertices),
        triangles: match faces.as_slice() {
            Some(flat) => flat
                .chunks_exact(3)
                .map(|r| [r[0] as u32, r[1] as u32, r[2] as u32])
                .collect(),
            None => faces
                .rows()
                .into_iter()
                .map(|r| [r[0] as u32, r[1] as u32, r[2] as u32])
                .collect(),
        },
        vertex_scalars: Vec::new(),
        space: None,
        volume_geometry: None,
    }
}

/// The rows of an `n × 3` array as points (read straight from memory when the
/// array is contiguous, as the package passes it).
pub fn points(rows: ArrayView2<f64>) -> Vec<Point> {
    match rows.as_slice() {
        Some(flat) => flat
            .chunks_exact(3)
            .map(|r| Point::new(r[0], r[1], r[2]))
            .collect(),
        None => rows
            .rows()
            .into_iter()
            .map(|r| Point::new(r[0], r[1], r[2]))
            .collect(),
    }
}

/// The mesh of the arrays, whose vertices must be the mesh's: repairs that weld,
/// drop or split vertices would renumber them, and every per-vertex result would
/// then belong to other rows than the caller's.
pub fn mesh_of(vertices: ArrayView2<f64>, faces: ArrayView2<i64>) -> PyResult<Mesh> {
    let (mesh, report) = Mesh::from_soup(soup(vertices, faces)).map_err(raised)?;
    let kept = mesh.positions().len() == vertices.nrows()
        && mesh
            .positions()
            .iter()
            .zip(vertices.rows())
            .all(|(p, r)| p.x == r[0] && p.y == r[1] && p.z == r[2]);
    if !kept {
        return Err(PyValueError::new_err(format!(
            "the mesh needs repairs that renumber its vertices ({}); \
             crestline.repair_mesh returns the repaired arrays",
            report.messages().join("; ")
        )));
    }
    Ok(mesh)
}

/// `n × 3` float64 array of vectors or points.
pub fn rows<'py>(
    py: Python<'py>,
    items: impl ExactSizeIterator<Item = [f64; 3]>,
) -> Bound<'py, PyArray2<f64>> {
    let n = items.len();
    let mut flat = Vec::with_capacity(3 * n);
    items.for_each(|row| flat.extend_from_slice(&row));
    Array2::from_shape_vec((n, 3), flat)
        .expect("three values per row")
        .into_pyarray(py)
}

/// `n × 3` int64 array of vertex indices.
pub fn index_rows<'py>(
    py: Python<'py>,
    items: impl ExactSizeIterator<Item = [u32; 3]>,
) -> Bound<'py, PyArray2<i64>> {
    let n = items.len();
    let flat: Vec<i64> = items.flatten().map(i64::from).collect();
    Array2::from_shape_vec((n, 3), flat)
        .expect("three indices per row")
        .into_pyarray(py)
}

/// The faces of a mesh as an `m × 3` int64 array.
pub fn faces<'py>(py: Python<'py>, mesh: &Mesh) -> Bound<'py, PyArray2<i64>> {
    index_rows(
        py,
        mesh.faces()
            .map(|f| mesh.face_vertices(f).map(|v| v.0))
            .collect::<Vec<_>>()
            .into_iter(),
    )
}

/// The repair report as JSON (the package turns it into a dict).
pub fn report_json(report: &RepairReport) -> String {
    serde_json::to_string(report).unwrap_or_else(|_| "{}".to_string())
}

/// Write a triangle mesh with per-vertex values to `path` in the format of its
/// extension (.ply with the values as properties, .obj, .vtk), atomically.
#[pyfunction]
pub fn write_mesh(
    py: Python<'_>,
    path: std::path::PathBuf,
    vertices: numpy::PyReadonlyArray2<'_, f64>,
    faces: numpy::PyReadonlyArray2<'_, i64>,
    values: Vec<(String, Vec<f64>)>,
    space: Option<&str>,
) -> PyResult<()> {
    let mut soup = soup(vertices.as_array(), faces.as_array());
    soup.space = crate::volume::frame(space)?;
    soup.vertex_scalars = values
        .into_iter()
        .map(|(name, values)| crestline::mesh::ScalarProperty { name, values })
        .collect();
    py.detach(|| crestline::io::write_soup(&path, &soup))
        .map_err(raised)
}

/// Read one value per vertex from a FreeSurfer curv, GIfTI or text file
/// ([`crestline::io::read_vertex_values`]).
#[pyfunction]
pub fn read_vertex_values(py: Python<'_>, path: std::path::PathBuf) -> PyResult<Vec<f64>> {
    py.detach(|| crestline::io::read_vertex_values(&path))
        .map_err(raised)
}

/// Write one value per vertex as a GIfTI `.shape.gii`/`.func.gii` (the array
/// named `name`, the file of Workbench's `structure`) or a FreeSurfer `.curv`,
/// atomically
/// ([`crestline::io::write_vertex_values`]).
#[pyfunction]
pub fn write_vertex_values(
    py: Python<'_>,
    path: std::path::PathBuf,
    values: Vec<f64>,
    name: Option<&str>,
    structure: &str,
) -> PyResult<()> {
    let metadata: Vec<(&str, &str)> = name.map(|name| ("Name", name)).into_iter().collect();
    let structure = structure.parse().map_err(raised)?;
    py.detach(|| crestline::io::write_vertex_values(&path, &values, (&metadata, structure), 0))
        .map_err(raised)
}
