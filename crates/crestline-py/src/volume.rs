//! The image half: reading 3D images, isosurfaces, crest lines by Marching Lines,
//! crease surfaces, landmarks and rigid registration of crest lines.
//!
//! Images cross the boundary as a C-contiguous float32 array of shape
//! `(nz, ny, nx)` (x fastest, as [`Volume`] stores them; the package transposes
//! to and from nibabel's `[i, j, k]` indexing) and a 4 × 4 voxel-to-world affine.

use std::path::PathBuf;

use crestline::io::VolumeReadOptions;
use crestline::jobs;
use crestline::lines::FeatureLines;
use crestline::mesh::TriangleSoup;
use crestline::register::{PointSet, RegistrationOptions, RigidTransform};
use crestline::volume::Volume;
use nalgebra::Matrix4;
use numpy::ndarray::{Array1, Array2, Array3};
use numpy::{IntoPyArray, PyArray2, PyArray3, PyReadonlyArray2, PyReadonlyArray3};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{points, rows};
use crate::errors::raised;
use crate::jobs::job_options;
use crate::lines::{feature_lines, line_dicts, LineParts};
use crate::progress::Callback;

/// The functions of this module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(read_volume, m)?)?;
    m.add_function(wrap_pyfunction!(read_dicom, m)?)?;
    m.add_function(wrap_pyfunction!(isosurface, m)?)?;
    m.add_function(wrap_pyfunction!(crest_lines, m)?)?;
    m.add_function(wrap_pyfunction!(crease_surface, m)?)?;
    m.add_function(wrap_pyfunction!(image_landmarks, m)?)?;
    m.add_function(wrap_pyfunction!(lines_landmarks, m)?)?;
    m.add_function(wrap_pyfunction!(write_landmarks, m)?)?;
    m.add_function(wrap_pyfunction!(voxel_size, m)?)?;
    m.add_function(wrap_pyfunction!(register_lines, m)?)?;
    m.add_function(wrap_pyfunction!(write_transform, m)?)?;
    Ok(())
}

/// The samples `(nz, ny, nx)` and the 4 × 4 voxel-to-world affine of an image.
type ImageArrays<'py> = (
    Bound<'py, PyArray3<f32>>,
    Bound<'py, PyArray2<f64>>,
    Option<&'static str>,
);

/// Read a 3D image (NIfTI, NRRD, MetaImage, a DICOM folder, DICOMDIR or file),
/// of DICOM input the series `series` if given.
#[pyfunction]
#[pyo3(signature = (path, series=None))]
fn read_volume<'py>(
    py: Python<'py>,
    path: PathBuf,
    series: Option<String>,
) -> PyResult<ImageArrays<'py>> {
    let options = VolumeReadOptions { series };
    let volume = py.detach(|| options.read(&path)).map_err(raised)?;
    Ok(image_arrays(py, &volume))
}

/// Read a DICOM series from a list of files, the series `series` if given.
#[pyfunction]
#[pyo3(signature = (files, series=None))]
fn read_dicom<'py>(
    py: Python<'py>,
    files: Vec<PathBuf>,
    series: Option<String>,
) -> PyResult<ImageArrays<'py>> {
    let options = VolumeReadOptions { series };
    let volume = py.detach(|| options.read_dicom(&files)).map_err(raised)?;
    Ok(image_arrays(py, &volume))
}

/// The arrays of `volume` for Python.
fn image_arrays<'py>(py: Python<'py>, volume: &Volume) -> ImageArrays<'py> {
    let [nx, ny, nz] = volume.dims();
    let samples = Array3::from_shape_vec((nz, ny, nx), volume.samples().to_vec())
        .expect("x fastest, one sample per voxel");
    let placed = volume.affine();
    let affine = Array2::from_shape_fn((4, 4), |(r, c)| placed[(r, c)]);
    let space = volume.space().map(crestline::Space::name);
    (samples.into_pyarray(py), affine.into_pyarray(py), space)
}

/// The volume of the samples `(nz, ny, nx)` and the affine, checked by
/// [`Volume::new`].
pub(crate) fn volume_of(
    samples: &PyReadonlyArray3<f32>,
    affine: &PyReadonlyArray2<f64>,
) -> PyResult<Volume> {
    let samples = samples.as_array();
    let affine = affine.as_array();
    let (nz, ny, nx) = samples.dim();
    let placed = Matrix4::from_fn(|row, column| affine[(row, column)]);
    let flat = samples.iter().copied().collect();
    Volume::from_affine([nx, ny, nz], &placed, flat).map_err(raised)
}

/// Vertices (n × 3 float64) and faces (m × 3 int64).
type SurfaceArrays<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<i64>>);

/// The isosurface `f = level` (inside is `f ≥ level`) of the image smoothed as
/// the JSON `options` of [`jobs::IsoOptions`] say, as vertices and faces
/// ([`jobs::isosurface`]).
#[pyfunction]
#[pyo3(signature = (samples, affine, level, options, progress=None))]
fn isosurface<'py>(
    py: Python<'py>,
    samples: PyReadonlyArray3<'py, f32>,
    affine: PyReadonlyArray2<'py, f64>,
    level: f64,
    options: &str,
    progress: Option<Py<PyAny>>,
) -> PyResult<SurfaceArrays<'py>> {
    let volume = volume_of(&samples, &affine)?;
    let options: jobs::IsoOptions = job_options("iso", options)?;
    let mut observer = Callback::new(progress);
    let surface = py.detach(|| jobs::isosurface(&volume, level, &options, None, &mut observer));
    let mesh = observer.outcome(surface)?.mesh;
    let vertices = rows(py, mesh.positions().iter().map(|p| [p.x, p.y, p.z]));
    Ok((vertices, crate::arrays::faces(py, &mesh)))
}

/// The vertices and faces of a triangle soup.
fn soup_arrays<'py>(py: Python<'py>, soup: &TriangleSoup) -> SurfaceArrays<'py> {
    let vertices = rows(py, soup.positions.iter().map(|p| [p.x, p.y, p.z]));
    let faces = crate::arrays::index_rows(py, soup.triangles.iter().copied());
    (vertices, faces)
}

/// Lines of the isosurface `level` of the image by Marching Lines (Thirion &
/// Gourdon 1993) as the JSON `options` of [`jobs::CrestLinesOptions`] say
/// ([`jobs::crest_lines`]).
#[pyfunction]
#[pyo3(signature = (samples, affine, level, options, progress=None))]
fn crest_lines<'py>(
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
        ("crest_lines", options),
        progress,
        |v, o, b| jobs::crest_lines(v, level, o, b),
    )
}

/// The line dicts of the lines `trace` finds in the image of `samples` and
/// `affine` (`image`) with the JSON `options` of the job `job` (`given`),
/// `progress` told of its stages.
pub(crate) fn lines_of_image<'py, O>(
    py: Python<'py>,
    (samples, affine): (PyReadonlyArray3<'py, f32>, PyReadonlyArray2<'py, f64>),
    (job, given): (&str, &str),
    progress: Option<Py<PyAny>>,
    trace: impl FnOnce(&Volume, &O, &mut Callback) -> crestline::Result<FeatureLines> + Send,
) -> PyResult<Vec<Bound<'py, PyDict>>>
where
    O: serde::de::DeserializeOwned + serde::Serialize + Default + Sync,
{
    let volume = volume_of(&samples, &affine)?;
    let options: O = job_options(job, given)?;
    let mut observer = Callback::new(progress);
    let lines = py.detach(|| trace(&volume, &options, &mut observer));
    line_dicts(py, &observer.outcome(lines)?.lines, None)
}

/// The ridge (or valley) surface of the image (Schultz, Theisel & Seidel 2010)
/// as the JSON `options` of [`jobs::CreaseOptions`] say ([`jobs::crease`]):
/// vertices, faces and the per-vertex values `strength` (−λ3) and `degenerate`.
#[pyfunction]
#[pyo3(signature = (samples, affine, options, progress=None))]
fn crease_surface<'py>(
    py: Python<'py>,
    samples: PyReadonlyArray3<'py, f32>,
    affine: PyReadonlyArray2<'py, f64>,
    options: &str,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let volume = volume_of(&samples, &affine)?;
    let options: jobs::CreaseOptions = job_options("crease", options)?;
    let mut observer = Callback::new(progress);
    let soup = py.detach(|| jobs::crease(&volume, &options, &mut observer));
    let soup = observer.outcome(soup)?;
    let (vertices, faces) = soup_arrays(py, &soup);
    let dict = PyDict::new(py);
    dict.set_item("vertices", vertices)?;
    dict.set_item("faces", faces)?;
    for scalar in &soup.vertex_scalars {
        dict.set_item(
            scalar.name.as_str(),
            Array1::from(scalar.values.clone()).into_pyarray(py),
        )?;
    }
    Ok(dict)
}

/// The landmarks of the crest lines of the image's isosurface `level`
/// ([`jobs::landmarks`] from [`jobs::LinesFrom::Image`]), as the JSON the library
/// writes; `crest` and `options` are the JSON options of the tracing and of the
/// landmarks.
#[pyfunction]
#[pyo3(signature = (samples, affine, level, crest, options, progress=None))]
fn image_landmarks(
    py: Python<'_>,
    samples: PyReadonlyArray3<'_, f32>,
    affine: PyReadonlyArray2<'_, f64>,
    level: f64,
    crest: &str,
    options: &str,
    progress: Option<Py<PyAny>>,
) -> PyResult<String> {
    let volume = volume_of(&samples, &affine)?;
    let crest: jobs::CrestLinesOptions = job_options("crest_lines", crest)?;
    let options: jobs::LandmarksOptions = job_options("landmarks", options)?;
    let mut observer = Callback::new(progress);
    let found = py.detach(|| {
        let input = jobs::LinesFrom::Image {
            volume: &volume,
            level,
            options: &crest,
        };
        jobs::landmarks(input, &options, &mut observer)
    });
    landmarks_json(&observer.outcome(found)?)
}

/// The landmarks of `lines`, whose relative lengths are in `unit`s, both the
/// sampling's and the feature scale's ([`jobs::LinesFrom::Lines`]), as the
/// JSON the library writes.
#[pyfunction]
fn lines_landmarks(lines: Vec<LineParts<'_>>, unit: f64, options: &str) -> PyResult<String> {
    let lines = feature_lines(lines)?;
    let options: jobs::LandmarksOptions = job_options("landmarks", options)?;
    let mut observer = Callback::new(None);
    let input = jobs::LinesFrom::Lines {
        lines: &lines,
        unit,
    };
    let found = jobs::landmarks(input, &options, &mut observer);
    landmarks_json(&observer.outcome(found)?)
}

/// Write landmarks given as the JSON the library serializes them to, in the
/// format of the file's extension (`.mrk.json`, `.json`, `.csv`), their
/// positions in the frame they `declared`, else the one `given`, else LPS
/// ([`crestline::Space::resolve`]).
#[pyfunction]
#[pyo3(signature = (path, landmarks, declared, given))]
fn write_landmarks(
    path: PathBuf,
    landmarks: &str,
    declared: Option<&str>,
    given: Option<&str>,
) -> PyResult<()> {
    let invalid = |e: serde_json::Error| raised(crestline::Error::Argument(e.to_string()));
    let found: crestline::landmarks::Landmarks =
        serde_json::from_str(landmarks).map_err(invalid)?;
    let space = crestline::Space::resolve(frame(declared)?, frame(given)?)
        .map_err(raised)?
        .unwrap_or(crestline::Space::Lps);
    found.write(&path, space).map_err(raised)
}

/// Write the moving → fixed motion `matrix` (4 × 4), in the frame `space`, as
/// the tool's `register` writes its result (`.json` in RAS, `.tfm` for ITK and
/// 3D Slicer), atomically.
#[pyfunction]
fn write_transform(path: PathBuf, matrix: PyReadonlyArray2<'_, f64>, space: &str) -> PyResult<()> {
    let matrix = matrix.as_array();
    if matrix.dim() != (4, 4) {
        let message = format!("matrix: expected 4 × 4, got {:?}", matrix.dim());
        return Err(raised(crestline::Error::Argument(message)));
    }
    let motion =
        RigidTransform::from_matrix4(&Matrix4::from_fn(|r, c| matrix[(r, c)])).map_err(raised)?;
    let in_ras = match frame(Some(space))? {
        Some(crestline::Space::Lps) => motion.flip_xy(),
        _ => motion,
    };
    in_ras.write(&path).map_err(raised)
}

/// The frame `name` names (`RAS` or `LPS`, any case), if any.
pub fn frame(name: Option<&str>) -> PyResult<Option<crestline::Space>> {
    name.map(str::parse).transpose().map_err(raised)
}

/// One voxel of an image placed by `affine`: its largest spacing, the unit of
/// the relative lengths of the image jobs.
#[pyfunction]
fn voxel_size(affine: PyReadonlyArray2<'_, f64>) -> f64 {
    let affine = affine.as_array();
    let placed = Matrix4::from_fn(|row, column| affine[(row, column)]);
    crestline::volume::split_affine(&placed)
        .0
        .into_iter()
        .fold(0.0, f64::max)
}

/// Landmarks as the JSON the library writes.
pub fn landmarks_json(found: &crestline::landmarks::Landmarks) -> PyResult<String> {
    serde_json::to_string(found).map_err(|e| raised(crestline::Error::Argument(e.to_string())))
}

/// The rigid motion taking the `moving` points onto the `fixed` ones by trimmed
/// ICP ([`jobs::register`] with the JSON `options` of
/// [`crestline::register::RegistrationOptions`]), as its 4 × 4 matrix and
/// figures (rms, matched, matched_share, iterations).
#[pyfunction]
#[pyo3(signature = (fixed, moving, fixed_keys, moving_keys, options, progress=None))]
fn register_lines<'py>(
    py: Python<'py>,
    fixed: PyReadonlyArray2<'py, f64>,
    moving: PyReadonlyArray2<'py, f64>,
    fixed_keys: PyReadonlyArray2<'py, f64>,
    moving_keys: PyReadonlyArray2<'py, f64>,
    options: &str,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let set = |lines: &PyReadonlyArray2<f64>, keys: &PyReadonlyArray2<f64>| PointSet {
        line_points: points(lines.as_array()),
        key_points: points(keys.as_array()),
    };
    let (fixed, moving) = (set(&fixed, &fixed_keys), set(&moving, &moving_keys));
    let options: RegistrationOptions = job_options("register", options)?;
    let mut observer = Callback::new(progress);
    let found = py.detach(|| jobs::register(&fixed, &moving, &options, &mut observer));
    let found = observer.outcome(found)?;
    let matrix = found.transform.to_matrix4();
    let matrix = Array2::from_shape_fn((4, 4), |(r, c)| matrix[(r, c)]);
    let dict = PyDict::new(py);
    dict.set_item("matrix", matrix.into_pyarray(py))?;
    dict.set_item("rms", found.rms)?;
    dict.set_item("matched", found.matched)?;
    dict.set_item("matched_share", found.matched_share)?;
    dict.set_item("iterations", found.iterations)?;
    Ok(dict)
}
