//! The image half: reading 3D images, isosurfaces, crest lines by Marching Lines,
//! crease surfaces, landmarks and rigid registration of crest lines.
//!
//! Images cross the boundary as a C-contiguous float32 array of shape
//! `(nz, ny, nx)` (x fastest, as [`Volume`] stores them; the package transposes
//! to and from nibabel's `[i, j, k]` indexing) and a 4 × 4 voxel-to-world affine.

use std::path::Path;

use crestline::crest_lines::{trace, LineFamily, LineTracing};
use crestline::landmarks::{landmarks as find_landmarks, LandmarkOptions};
use crestline::lines::{FeatureLines, MinLength, MinStrength};
use crestline::mesh::TriangleSoup;
use crestline::progress::{try_stage, Observer};
use crestline::register::{register as align, PointSet, RegistrationOptions};
use crestline::volume::crease::{crease_surface_with, CreaseField, DEFAULT_STRENGTH_FRACTION};
use crestline::volume::{isosurface as iso, Derivatives, Sweep, Volume};
use nalgebra::Matrix4;
use numpy::ndarray::{Array1, Array2, Array3};
use numpy::{IntoPyArray, PyArray2, PyArray3, PyReadonlyArray2, PyReadonlyArray3};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{points, rows};
use crate::errors::raised;
use crate::lines::{feature_lines, line_dicts, LineParts};
use crate::progress::Callback;

/// The functions of this module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(read_volume, m)?)?;
    m.add_function(wrap_pyfunction!(isosurface, m)?)?;
    m.add_function(wrap_pyfunction!(crest_lines, m)?)?;
    m.add_function(wrap_pyfunction!(crease_surface, m)?)?;
    m.add_function(wrap_pyfunction!(landmarks, m)?)?;
    m.add_function(wrap_pyfunction!(register_lines, m)?)?;
    Ok(())
}

/// The samples `(nz, ny, nx)` and the 4 × 4 voxel-to-world affine of an image.
type ImageArrays<'py> = (Bound<'py, PyArray3<f32>>, Bound<'py, PyArray2<f64>>);

/// Read a 3D image (NIfTI, NRRD, MetaImage).
#[pyfunction]
fn read_volume<'py>(py: Python<'py>, path: &str) -> PyResult<ImageArrays<'py>> {
    let path = Path::new(path);
    let volume = py
        .detach(|| crestline::io::read_volume(path))
        .map_err(raised)?;
    let [nx, ny, nz] = volume.dims();
    let samples = Array3::from_shape_vec((nz, ny, nx), volume.samples().to_vec())
        .expect("x fastest, one sample per voxel");
    let placed = volume.affine();
    let affine = Array2::from_shape_fn((4, 4), |(r, c)| placed[(r, c)]);
    Ok((samples.into_pyarray(py), affine.into_pyarray(py)))
}

/// The volume of the samples `(nz, ny, nx)` and the affine, checked by
/// [`Volume::new`].
fn volume_of(samples: &PyReadonlyArray3<f32>, affine: &PyReadonlyArray2<f64>) -> PyResult<Volume> {
    let samples = samples.as_array();
    let affine = affine.as_array();
    let (nz, ny, nx) = samples.dim();
    let placed = Matrix4::from_fn(|row, column| affine[(row, column)]);
    let flat = samples.iter().copied().collect();
    Volume::from_affine([nx, ny, nz], &placed, flat).map_err(raised)
}

/// Vertices (n × 3 float64) and faces (m × 3 int64).
type SurfaceArrays<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<i64>>);

/// The isosurface `f = level` (inside is `f ≥ level`) by marching cubes, as
/// vertices and faces.
#[pyfunction]
fn isosurface<'py>(
    py: Python<'py>,
    samples: PyReadonlyArray3<'py, f32>,
    affine: PyReadonlyArray2<'py, f64>,
    level: f64,
) -> PyResult<SurfaceArrays<'py>> {
    let volume = volume_of(&samples, &affine)?;
    let soup = py
        .detach(|| iso(&volume, level).map(|surface| surface.into_soup()))
        .map_err(raised)?;
    Ok(soup_arrays(py, &soup))
}

/// The vertices and faces of a triangle soup.
fn soup_arrays<'py>(py: Python<'py>, soup: &TriangleSoup) -> SurfaceArrays<'py> {
    let vertices = rows(py, soup.positions.iter().map(|p| [p.x, p.y, p.z]));
    let faces = crate::arrays::index_rows(py, soup.triangles.iter().copied());
    (vertices, faces)
}

/// Lines of the isosurface `level` of the image smoothed by `sigma` (world
/// units) by Marching Lines (Thirion & Gourdon 1993): crest lines, or the
/// iso-Gaussian curves `K = gauss` (parabolic lines for 0) when `gauss` is given;
/// from `seeds` random cells when given; lines shorter than `min_length` or
/// weaker than `min_strength` dropped.
#[pyfunction]
#[pyo3(signature = (samples, affine, level, sigma, min_length, min_strength, gauss=None, seeds=None, rng_seed=0))]
#[allow(clippy::too_many_arguments)]
fn crest_lines<'py>(
    py: Python<'py>,
    samples: PyReadonlyArray3<'py, f32>,
    affine: PyReadonlyArray2<'py, f64>,
    level: f64,
    sigma: f64,
    min_length: f64,
    min_strength: f64,
    gauss: Option<f64>,
    seeds: Option<usize>,
    rng_seed: u64,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let volume = volume_of(&samples, &affine)?;
    let tracing = LineTracing {
        family: gauss.map_or(LineFamily::Crest, LineFamily::Gauss),
        sweep: seeds.map_or(Sweep::Every, |count| Sweep::Seeds { count, rng_seed }),
        ..LineTracing::new(level, sigma)
    };
    let lines = py
        .detach(|| -> crestline::Result<FeatureLines> {
            let mut lines = FeatureLines::new("arrays");
            lines.lines = trace(&volume, &tracing)?;
            lines.filter(&MinLength(min_length));
            lines.filter(&MinStrength(min_strength));
            Ok(lines)
        })
        .map_err(raised)?;
    line_dicts(py, &lines.lines, None)
}

/// The ridge (or valley) surface of the image (Schultz, Theisel & Seidel 2010):
/// vertices, faces and the per-vertex values `strength` (−λ3) and `degenerate`
/// (1 on the degenerate lines where the surface ends). `sigma` 0 differentiates
/// the cubic B-spline of the samples, else a Gaussian of that width; `strength`
/// is the least −λ3 as a fraction of the strongest in the image. `progress` is
/// told of each stage.
#[pyfunction]
#[pyo3(signature = (samples, affine, valley, sigma, strength, min_component, progress=None))]
#[allow(clippy::too_many_arguments)]
fn crease_surface<'py>(
    py: Python<'py>,
    samples: PyReadonlyArray3<'py, f32>,
    affine: PyReadonlyArray2<'py, f64>,
    valley: bool,
    sigma: f64,
    strength: f64,
    min_component: usize,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let volume = volume_of(&samples, &affine)?;
    let mut observer = Callback(progress);
    let soup = py
        .detach(|| -> crestline::Result<TriangleSoup> {
            let derivatives = try_stage(&mut observer, "reconstruction", || {
                if sigma == 0.0 {
                    Derivatives::cubic_spline(&volume, 2)
                } else {
                    Derivatives::new(&volume, sigma, 2)
                }
            })?;
            let field = try_stage(&mut observer, "eigenframes", || {
                CreaseField::new(&volume, &derivatives, !valley)
            })?;
            drop(derivatives);
            let mut options = field.default_options();
            options.strength *= strength / DEFAULT_STRENGTH_FRACTION;
            Ok(crease_surface_with(
                &field,
                &options,
                min_component,
                |stage, took| observer.stage_finished(stage.name(), took.as_secs_f64()),
            ))
        })
        .map_err(raised)?;
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

/// Landmarks of ridge and valley lines (extremal points, curvature maxima, ends,
/// and a descriptor per line) as the JSON the library writes.
#[pyfunction]
fn landmarks(lines: Vec<LineParts<'_>>, radius: f64, persistence: f64) -> PyResult<String> {
    let lines = feature_lines(lines)?;
    let options = LandmarkOptions {
        radius,
        persistence,
    };
    let found = find_landmarks(&lines, &options).map_err(raised)?;
    serde_json::to_string(&found).map_err(|e| raised(crestline::Error::Argument(e.to_string())))
}

/// The rigid motion taking the `moving` points onto the `fixed` ones by trimmed
/// ICP, as its 4 × 4 matrix and figures (rms, matched, matched_share,
/// iterations).
#[pyfunction]
#[pyo3(signature = (fixed, moving, fixed_keys, moving_keys, min_overlap))]
fn register_lines<'py>(
    py: Python<'py>,
    fixed: PyReadonlyArray2<'py, f64>,
    moving: PyReadonlyArray2<'py, f64>,
    fixed_keys: PyReadonlyArray2<'py, f64>,
    moving_keys: PyReadonlyArray2<'py, f64>,
    min_overlap: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let set = |lines: &PyReadonlyArray2<f64>, keys: &PyReadonlyArray2<f64>| PointSet {
        line_points: points(lines.as_array()),
        key_points: points(keys.as_array()),
    };
    let (fixed, moving) = (set(&fixed, &fixed_keys), set(&moving, &moving_keys));
    let options = RegistrationOptions {
        min_overlap,
        ..RegistrationOptions::default()
    };
    let found = py
        .detach(|| align(&fixed, &moving, &options))
        .map_err(raised)?;
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
