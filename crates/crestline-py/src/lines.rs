//! Feature lines as dicts of numpy arrays (the package makes `Line` objects of
//! them), and lines given back by the package as the library's polylines.

use std::path::PathBuf;

use crestline::lines::{write_point_labels, FeatureLines, LineKind, Polyline};
use crestline::mesh::{Mesh, VertexId};
use numpy::ndarray::Array1;
use numpy::{IntoPyArray, PyReadonlyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{index_rows, points, rows};
use crate::built_mesh::BuiltMesh;
use crate::errors::raised;

/// Every line as a dict ([`line_dict`]).
pub fn line_dicts<'py>(
    py: Python<'py>,
    lines: &[Polyline],
    mesh: Option<&Mesh>,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    lines.iter().map(|line| line_dict(py, line, mesh)).collect()
}

/// One line as a dict: kind, closed, strength, points (k × 3), values (per-point
/// arrays) and, for lines traced on `mesh`, where each point lies on it: three
/// vertex indices and three weights per point (`location_vertices`,
/// `location_weights`), unused slots with weight 0.
fn line_dict<'py>(
    py: Python<'py>,
    line: &Polyline,
    mesh: Option<&Mesh>,
) -> PyResult<Bound<'py, PyDict>> {
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
    if let Some(mesh) = mesh.filter(|_| line.locations.len() == line.points.len()) {
        let (vertices, weights): (Vec<[u32; 3]>, Vec<[f64; 3]>) = line
            .locations
            .iter()
            .map(|location| {
                let pairs = location.weights(mesh);
                let (mut ids, mut ws) = ([pairs[0].0 .0; 3], [0.0; 3]);
                for (slot, (v, w)) in pairs.into_iter().enumerate() {
                    ids[slot] = v.0;
                    ws[slot] = w;
                }
                (ids, ws)
            })
            .unzip();
        dict.set_item("location_vertices", index_rows(py, vertices.into_iter()))?;
        dict.set_item("location_weights", rows(py, weights.into_iter()))?;
    }
    Ok(dict)
}

/// A line given as its kind's name, closed flag, strength, points (k × 3) and
/// named per-point values.
pub type LineParts<'py> = (
    String,
    bool,
    f64,
    PyReadonlyArray2<'py, f64>,
    Vec<(String, Vec<f64>)>,
);

/// The library's lines of lines given by the package.
pub fn feature_lines(lines: Vec<LineParts<'_>>) -> PyResult<FeatureLines> {
    let lines = lines
        .into_iter()
        .map(|(kind, closed, strength, line_points, values)| {
            let kind = LineKind::ALL
                .into_iter()
                .find(|k| k.name() == kind)
                .ok_or_else(|| PyValueError::new_err(format!("lines: unknown kind {kind:?}")))?;
            let mut line = Polyline::new(kind, closed, strength, points(line_points.as_array()));
            line.values = values.into_iter().collect();
            Ok(line)
        })
        .collect::<PyResult<Vec<Polyline>>>()?;
    Ok(FeatureLines {
        source: "arrays".to_string(),
        lines,
        space: None,
    })
}

/// Every kind of line in the order of its code ([`LineKind::ALL`]): its name, the
/// name of its family ([`LineKind::family`]) and the family's colour as `#rrggbb`
/// ([`LineKind::color_hex`]).
#[pyfunction]
pub fn line_kinds() -> Vec<(&'static str, &'static str, String)> {
    LineKind::ALL
        .iter()
        .map(|kind| (kind.name(), kind.family(), kind.color_hex()))
        .collect()
}

/// Write lines to `path` in the format of its extension (.json, .obj, .ply,
/// .vtk, .mrk.json: 3D Slicer markups), atomically.
#[pyfunction]
#[pyo3(signature = (path, lines, space=None))]
pub fn write_lines(
    py: Python<'_>,
    path: PathBuf,
    lines: Vec<LineParts<'_>>,
    space: Option<&str>,
) -> PyResult<()> {
    let mut lines = feature_lines(lines)?;
    lines.space = crate::volume::frame(space)?;
    py.detach(|| lines.write(&path)).map_err(raised)
}

/// A line's kind and where its points lie: the three mesh vertices each point
/// interpolates (k × 3) and their weights (k × 3).
pub type LocatedLine<'py> = (
    String,
    PyReadonlyArray2<'py, i64>,
    PyReadonlyArray2<'py, f64>,
);

/// Write the labels of the vertices of the mesh that ridge and valley `lines` pass near, as a
/// `.label.gii` (of Workbench's `structure`) or `.label`
/// ([`crestline::lines::write_labels`]), atomically.
#[pyfunction]
pub fn write_line_labels(
    py: Python<'_>,
    path: PathBuf,
    mesh: Bound<'_, BuiltMesh>,
    lines: Vec<LocatedLine<'_>>,
    structure: &str,
) -> PyResult<()> {
    let structure = structure.parse().map_err(raised)?;
    let mesh = &mesh.get().surface().mesh;
    let n = mesh.vertex_count();
    let mut points = Vec::new();
    for (i, (kind, ids, weights)) in lines.iter().enumerate() {
        let label = LineKind::ALL
            .into_iter()
            .find(|k| k.name() == kind)
            .filter(|kind| matches!(kind, LineKind::Ridge | LineKind::Valley))
            .ok_or_else(|| {
                PyValueError::new_err(format!(
                    "lines[{i}]: vertex labels hold ridge and valley lines, not {kind:?} lines"
                ))
            })?;
        let (ids, weights) = (ids.as_array(), weights.as_array());
        if ids.dim() != weights.dim() || ids.ncols() != 3 {
            return Err(PyValueError::new_err(format!(
                "lines[{i}]: location vertices {:?} and weights {:?} must both be k x 3",
                ids.dim(),
                weights.dim()
            )));
        }
        for (row, w) in ids.rows().into_iter().zip(weights.rows()) {
            let corners = row
                .iter()
                .zip(w.iter())
                .map(|(&v, &w)| match u32::try_from(v) {
                    Ok(v) if (v as usize) < n => Ok((VertexId(v), w)),
                    _ => Err(PyValueError::new_err(format!(
                        "lines[{i}]: location vertex {v} is not one of the {n} vertices"
                    ))),
                })
                .collect::<PyResult<Vec<_>>>()?;
            points.push((label, corners));
        }
    }
    py.detach(|| write_point_labels(&path, mesh, points, structure))
        .map_err(raised)
}
