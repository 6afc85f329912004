//! Landmark transfer as Python sees it: a template's labelled landmarks carried
//! onto a subject through their lines ([`jobs::transfer`]), the lines of an image
//! ([`TransferOptions::image_lines`]) or a mesh ([`TransferOptions::mesh_tracing`]) it
//! registers, and the labelled landmark files
//! ([`crestline::transfer::read_labelled`], [`write_labelled`]) and the lines
//! files a cohort computes the template's lines into.

use std::path::PathBuf;

use crestline::jobs::{self, Surface};
use crestline::mesh::Mesh;
use crestline::transfer::{read_labelled, write_labelled, LabelledPoint, TransferOptions};
use numpy::ndarray::{Array1, Array2};
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray3};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{points, rows};
use crate::built_mesh::BuiltMesh;
use crate::errors::raised;
use crate::jobs::job_options;
use crate::lines::{feature_lines, line_dicts, LineParts};
use crate::progress::Callback;
use crate::volume::{frame, lines_of_image};

/// The functions of this module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(transfer_landmarks, m)?)?;
    m.add_function(wrap_pyfunction!(transfer_image_lines, m)?)?;
    m.add_function(wrap_pyfunction!(transfer_mesh_lines, m)?)?;
    m.add_function(wrap_pyfunction!(transfer_mesh_file_lines, m)?)?;
    m.add_function(wrap_pyfunction!(read_lines_file, m)?)?;
    m.add_function(wrap_pyfunction!(read_labelled_points, m)?)?;
    m.add_function(wrap_pyfunction!(write_labelled_points, m)?)?;
    Ok(())
}

/// The landmarks `labels` at `positions` (RAS) of the template whose lines are
/// `template` (in the frame `template_space`) carried onto the subject whose
/// lines are `subject` ([`jobs::transfer`], the JSON `options` of
/// [`TransferOptions`]): a dict of positions (n × 3, RAS), confidence, coverage,
/// flagged, rms and the rigid stage's 4 × 4 matrix.
#[pyfunction]
#[pyo3(signature = (template, template_space, subject, subject_space, labels, positions, options, progress=None))]
#[allow(clippy::too_many_arguments)] // the arguments of one call, as the package passes them
fn transfer_landmarks<'py>(
    py: Python<'py>,
    template: Vec<LineParts<'py>>,
    template_space: Option<&str>,
    subject: Vec<LineParts<'py>>,
    subject_space: Option<&str>,
    labels: Vec<String>,
    positions: PyReadonlyArray2<'py, f64>,
    options: &str,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let lines = |parts, space| -> PyResult<_> {
        let mut lines = feature_lines(parts)?;
        lines.space = frame(space)?;
        Ok(lines)
    };
    let (template, subject) = (
        lines(template, template_space)?,
        lines(subject, subject_space)?,
    );
    let landmarks: Vec<LabelledPoint> = labels
        .into_iter()
        .zip(points(positions.as_array()))
        .map(|(label, position)| LabelledPoint { label, position })
        .collect();
    let options: TransferOptions = job_options("transfer", options)?;
    let mut observer = Callback::new(progress);
    let found =
        py.detach(|| jobs::transfer(&template, &subject, &landmarks, &options, &mut observer));
    let found = observer.outcome(found)?;
    let matrix = found.rigid.transform.to_matrix4();
    let dict = PyDict::new(py);
    let moved = found.positions.iter().map(|p| [p.x, p.y, p.z]);
    dict.set_item("positions", rows(py, moved))?;
    dict.set_item(
        "confidence",
        Array1::from(found.confidence).into_pyarray(py),
    )?;
    dict.set_item("coverage", Array1::from(found.coverage).into_pyarray(py))?;
    dict.set_item("flagged", found.flagged)?;
    dict.set_item("rms", found.rms)?;
    let matrix = Array2::from_shape_fn((4, 4), |(r, c)| matrix[(r, c)]);
    dict.set_item("rigid", matrix.into_pyarray(py))?;
    Ok(dict)
}

/// The lines of the image that [`jobs::transfer`] registers, its landmarks on the
/// isosurface `level` ([`TransferOptions::image_lines`], the JSON `options` of
/// [`TransferOptions`]), as line dicts.
#[pyfunction]
#[pyo3(signature = (samples, affine, level, options, progress=None))]
fn transfer_image_lines<'py>(
    py: Python<'py>,
    samples: PyReadonlyArray3<'py, f32>,
    affine: PyReadonlyArray2<'py, f64>,
    level: f64,
    options: &str,
    progress: Option<Py<PyAny>>,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    lines_of_image(
        py,
        (samples, affine),
        ("transfer", options),
        progress,
        |v, o: &TransferOptions, b| o.image_lines(v, level, b),
    )
}

/// The lines of the mesh that [`jobs::transfer`] registers
/// ([`TransferOptions::mesh_tracing`], the JSON `options` of [`TransferOptions`]),
/// as line dicts.
#[pyfunction]
#[pyo3(signature = (mesh, options, progress=None))]
fn transfer_mesh_lines<'py>(
    py: Python<'py>,
    mesh: Bound<'py, BuiltMesh>,
    options: &str,
    progress: Option<Py<PyAny>>,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let options: TransferOptions = job_options("transfer", options)?;
    let surface = mesh.get().surface();
    let mut observer = Callback::new(progress);
    let lines = py.detach(|| jobs::ridges(surface, &options.mesh_tracing(), &mut observer));
    line_dicts(py, &observer.outcome(lines)?.lines, Some(&surface.mesh))
}

/// The lines [`transfer_mesh_lines`] gives, of the mesh file `path`, read and repaired as the
/// command-line tool reads it, with the frame the file states (or `None`).
#[pyfunction]
#[pyo3(signature = (path, options, progress=None))]
fn transfer_mesh_file_lines<'py>(
    py: Python<'py>,
    path: PathBuf,
    options: &str,
    progress: Option<Py<PyAny>>,
) -> PyResult<(Vec<Bound<'py, PyDict>>, Option<&'static str>)> {
    let options: TransferOptions = job_options("transfer", options)?;
    let mut observer = Callback::new(progress);
    let traced = py.detach(|| -> crestline::Result<_> {
        let soup = crestline::io::read_mesh(&path)?;
        let (mesh, _) = Mesh::from_soup(soup).map_err(|e| e.in_file(&path))?;
        let surface = Surface::of_mesh(mesh);
        let lines = jobs::ridges(&surface, &options.mesh_tracing(), &mut observer)
            .map_err(|e| e.in_file(&path))?;
        Ok((lines, surface))
    });
    let (lines, surface) = observer.outcome(traced)?;
    let dicts = line_dicts(py, &lines.lines, Some(&surface.mesh))?;
    Ok((dicts, lines.space.map(|s| s.name())))
}

/// The lines of a lines file (`.json`, as `crestline crest-lines` and `crestline
/// ridges` write it; [`crestline::lines::read_json`]) as line dicts, with the frame
/// the file states.
#[pyfunction]
fn read_lines_file(
    py: Python<'_>,
    path: PathBuf,
) -> PyResult<(Vec<Bound<'_, PyDict>>, Option<&'static str>)> {
    let lines = py
        .detach(|| crestline::lines::FeatureLines::read_json(&path))
        .map_err(raised)?;
    let dicts = line_dicts(py, &lines.lines, None)?;
    Ok((dicts, lines.space.map(|s| s.name())))
}

/// The labels and positions (n × 3, RAS) of a landmarks file (.mrk.json, .json,
/// .csv; [`read_labelled`]).
#[pyfunction]
fn read_labelled_points(
    py: Python<'_>,
    path: PathBuf,
) -> PyResult<(Vec<String>, Bound<'_, PyArray2<f64>>)> {
    let found = py.detach(|| read_labelled(&path)).map_err(raised)?;
    let positions = rows(
        py,
        found.iter().map(|l| l.position).map(|p| [p.x, p.y, p.z]),
    );
    Ok((found.into_iter().map(|l| l.label).collect(), positions))
}

/// Write labelled landmarks (positions n × 3 in RAS) with their confidence and
/// flags to `path` ([`write_labelled`]), positions in `space` where the format
/// allows.
#[pyfunction]
fn write_labelled_points(
    py: Python<'_>,
    path: PathBuf,
    labels: Vec<String>,
    positions: PyReadonlyArray2<'_, f64>,
    confidence: PyReadonlyArray1<'_, f64>,
    flagged: Vec<bool>,
    space: &str,
) -> PyResult<()> {
    let space = frame(Some(space))?.unwrap_or(crestline::Space::Ras);
    let points: Vec<LabelledPoint> = labels
        .into_iter()
        .zip(points(positions.as_array()))
        .map(|(label, position)| LabelledPoint { label, position })
        .collect();
    let confidence = confidence.as_array().to_vec();
    py.detach(|| write_labelled(&path, &points, &confidence, &flagged, space))
        .map_err(raised)
}
