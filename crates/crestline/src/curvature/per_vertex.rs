//! One curvature quantity per vertex of the input surface, in the files of
//! neuroimaging tools: GIfTI `.shape.gii` and FreeSurfer curv (`lh.mean.curv`).
//!
//! Both files hold exactly one value per vertex of the file the mesh was read
//! from, in its order ([`Mesh::to_input_order`]), whatever the repairs did; a
//! vertex the repairs dropped (unreferenced by any face) has NaN in GIfTI and 0
//! in a curv file (FreeSurfer's tools expect finite values).
//!
//! Signs: a `.shape.gii` keeps crestline's convention (positive where the
//! surface is convex seen from outside, see the module documentation) and says
//! so in its metadata; a curv file takes FreeSurfer's, that of `?h.curv`, whose
//! mean curvature is positive in sulci and negative on gyral crowns: the
//! curvatures with respect to the inward normal. The mean curvature changes sign,
//! `k_max` and `k_min` become `-k_min` and `-k_max`, the Gaussian curvature and
//! the curvedness stay as they are.

use std::path::Path;

use super::{CurvatureField, Quality};
use crate::io::{choose_format, write_vertex_values, FileFormat, Structure};
use crate::mesh::Mesh;
use crate::Result;

/// The metadata entry of a `.shape.gii` that states the sign convention.
pub const SIGN_CONVENTION_KEY: &str = "CurvatureSign";

/// The sign convention of crestline, as stated in a `.shape.gii`.
pub const SIGN_CONVENTION: &str =
    "positive where the surface is convex seen from outside (gyral crowns), outward normals";

/// The formats [`CurvatureField::write_values`] writes.
pub const PER_VERTEX_FORMATS: [FileFormat; 2] =
    [FileFormat::GiftiShape, FileFormat::FreeSurferCurv];

/// [`CurvatureField::write_values`].
pub(crate) fn write_curvature_values(
    path: &Path,
    mesh: &Mesh,
    field: &CurvatureField,
    quality: Quality,
    structure: Structure,
) -> Result<()> {
    let format = choose_format(path, "per-vertex curvature", &PER_VERTEX_FORMATS)?;
    let values = match format {
        FileFormat::FreeSurferCurv => mesh.to_input_order(&freesurfer_values(quality, field), 0.0),
        _ => mesh.to_input_order(&quality.values(field), f64::NAN),
    };
    let metadata = [
        ("Name", quality.name()),
        (SIGN_CONVENTION_KEY, SIGN_CONVENTION),
    ];
    write_vertex_values(path, &values, (&metadata, structure), mesh.face_count())
}

/// The quantity `quality` of `field` with FreeSurfer's sign: the curvatures with
/// respect to the inward normal.
pub fn freesurfer_values(quality: Quality, field: &CurvatureField) -> Vec<f64> {
    let negated = |values: &[f64]| values.iter().map(|x| -x).collect();
    match quality {
        Quality::Mean => negated(&field.mean()),
        Quality::KMax => negated(&field.k_min),
        Quality::KMin => negated(&field.k_max),
        Quality::Gauss | Quality::Curvedness => quality.values(field),
    }
}

impl CurvatureField {
    /// Write the quantity `quality` of `field` (on `mesh`) per input vertex, in the
    /// format of the extension of `path`: `.shape.gii` (crestline's sign, the
    /// quantity's name as the array's `Name`, `structure` as the file's) or `.curv`
    /// (FreeSurfer's sign). See
    /// the module documentation. Written atomically.
    pub fn write_values(
        &self,
        path: &Path,
        mesh: &Mesh,
        quality: Quality,
        structure: Structure,
    ) -> Result<()> {
        write_curvature_values(path, mesh, self, quality, structure)
    }
}
