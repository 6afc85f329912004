//! Saving a registration: as JSON, or as an ITK transform file that 3D Slicer and
//! ITK-based tools load.
//!
//! Coordinates: the points registered are taken to be in RAS (the world
//! coordinates of the NIfTI reader, and of meshes in a scanner frame), and the
//! transform [`Registration::transform`] `T` maps moving-set points onto fixed-set
//! points. The JSON file states exactly that transform. ITK transform files differ
//! on both counts: ITK works in LPS coordinates, and a registration there stores
//! the transform from the fixed space to the moving space (the map a resampler
//! needs to pull moving-image values onto the fixed grid). So the `.tfm` file
//! holds `(F·T·F)⁻¹ = F·T⁻¹·F` with `F = diag(−1, −1, 1)` the RAS ↔ LPS flip, and
//! its `FixedParameters` (the centre of rotation) are `0 0 0`.

use std::io::Write;
use std::path::Path;

use serde::Serialize;

use super::transform::RigidTransform;
use super::Registration;
use crate::atomic::write_atomically;
use crate::io::{choose_format, FileFormat, FormatChoice};
use crate::{Error, Result};

/// The value of the `format` key of the JSON files [`write_transform`] writes.
pub const FORMAT: &str = "crestline-transform/1";

/// The JSON document: `{"format", "coordinate_system": "RAS", "maps": ..., "matrix":
/// 4 rows of 4, "rotation_degrees", "translation", "rms", "matched_share",
/// "matched", "iterations"}`.
#[derive(Serialize)]
struct Document {
    format: &'static str,
    coordinate_system: &'static str,
    maps: &'static str,
    matrix: [[f64; 4]; 4],
    rotation_degrees: f64,
    translation: [f64; 3],
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    fit: Option<Fit>,
}

/// The figures of a registration's fit.
#[derive(Serialize)]
struct Fit {
    rms: f64,
    matched_share: f64,
    matched: usize,
    iterations: usize,
}

/// The file formats of [`Registration::write`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TransformFormat {
    /// `.json`: the moving → fixed transform in RAS, with the fit's figures.
    Json,
    /// `.tfm`: ITK's text transform, fixed → moving in LPS.
    Itk,
}

impl TransformFormat {
    /// Every format, in the order listed in error messages.
    pub const ALL: [TransformFormat; 2] = [TransformFormat::Json, TransformFormat::Itk];

    /// The format given by the extension of `path` (case-insensitive,
    /// [`choose_format`]); another extension is an [`Error::File`] listing the
    /// supported ones.
    pub fn from_path(path: &Path) -> Result<TransformFormat> {
        choose_format(path, "a transform", &Self::ALL)
    }
}

impl FormatChoice for TransformFormat {
    fn file_format(self) -> FileFormat {
        match self {
            TransformFormat::Json => FileFormat::Json,
            TransformFormat::Itk => FileFormat::ItkTransform,
        }
    }
}

/// [`Registration::write`].
pub(crate) fn write_transform(path: &Path, registration: &Registration) -> Result<()> {
    let fit = Fit {
        rms: registration.rms,
        matched_share: registration.matched_share,
        matched: registration.matched,
        iterations: registration.iterations,
    };
    write(path, &registration.transform, Some(fit))
}

/// [`RigidTransform::write`].
pub(crate) fn write_rigid_transform(path: &Path, transform: &RigidTransform) -> Result<()> {
    write(path, transform, None)
}

/// Write `transform`, with the `fit` it came from if any.
fn write(path: &Path, transform: &RigidTransform, fit: Option<Fit>) -> Result<()> {
    let format = TransformFormat::from_path(path)?;
    if !transform.to_matrix4().iter().all(|x| x.is_finite()) {
        return Err(Error::Argument(format!(
            "the transform to write has a non-finite entry: {:?}",
            transform.to_matrix4()
        )));
    }
    let text = match format {
        TransformFormat::Json => json_text(transform, fit)?,
        TransformFormat::Itk => itk_text(transform),
    };
    write_atomically(path, |w| w.write_all(text.as_bytes()))
}

/// The JSON document of `transform` and its `fit`, one line.
fn json_text(transform: &RigidTransform, fit: Option<Fit>) -> Result<String> {
    let matrix = transform.to_matrix4();
    let document = Document {
        format: FORMAT,
        coordinate_system: "RAS",
        maps: "moving to fixed",
        matrix: std::array::from_fn(|row| std::array::from_fn(|column| matrix[(row, column)])),
        rotation_degrees: transform.angle_degrees(),
        translation: transform.translation.into(),
        fit,
    };
    let text = serde_json::to_string(&document)
        .map_err(|e| Error::Argument(format!("the transform cannot be written as JSON: {e}")))?;
    Ok(text + "\n")
}

/// The ITK transform file of the RAS moving → fixed `transform`: the LPS
/// fixed → moving affine transform, matrix entries row by row, then the
/// translation.
pub fn itk_text(transform: &RigidTransform) -> String {
    let itk = transform.flip_xy().inverse();
    let matrix = itk.rotation.matrix();
    let parameters: Vec<String> = (0..3)
        .flat_map(|row| (0..3).map(move |column| matrix[(row, column)]))
        .chain(itk.translation.iter().copied())
        .map(|x| x.to_string())
        .collect();
    format!(
        "#Insight Transform File V1.0\n#Transform 0\nTransform: AffineTransform_double_3_3\n\
         Parameters: {}\nFixedParameters: 0 0 0\n",
        parameters.join(" ")
    )
}

impl RigidTransform {
    /// Write a moving → fixed motion in RAS (of a registration made elsewhere, say)
    /// as [`Registration::write`] does, without the fit's figures.
    pub fn write(&self, path: &Path) -> Result<()> {
        write_rigid_transform(path, self)
    }
}

impl Registration {
    /// Write `registration` to `path`, in the format of its extension
    /// ([`TransformFormat::from_path`]; see [`crate::register`] for the
    /// conventions of each). Written under a temporary name and renamed on success.
    ///
    /// Errors: [`Error::File`] for another extension or a failed write,
    /// [`Error::Argument`] for a transform with a non-finite entry.
    pub fn write(&self, path: &Path) -> Result<()> {
        write_transform(path, self)
    }
}
