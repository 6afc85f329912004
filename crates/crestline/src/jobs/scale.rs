//! The feature scale: one length in world units from which the jobs' defaults that
//! would otherwise count samples (the image's σ, the shortest line, the landmarks'
//! radius and persistence) are derived, so that a second scan of the same object at
//! another resolution, or moved off the grid, gives the same features.
//!
//! Its default comes from the object, not from its sampling: a share of the size of
//! what the image's isosurface encloses (the cube root of its volume), or of a
//! mesh's size (the square root of its area). Measured on the MNI template at level
//! 60 (`tools/image_rescans.py`): with σ of one voxel, as before, 43–47% of the
//! extremal points of a moved copy had one of the copy within 1 mm; with σ of 2 mm
//! and the other lengths in millimetres 90–93%, with 3 mm 95–98%.

use crate::mesh::Mesh;
use crate::volume::Volume;

/// The feature scale of an image as a share of the size of the object its
/// isosurface encloses: 2.5 mm for the MNI template at level 60 (enclosing 1.9
/// litres), between the 2 mm that meets the re-scan targets with little margin
/// and the 3 mm that keeps a third fewer landmarks.
pub const IMAGE_SCALE_SHARE: f64 = 0.02;

/// The feature scale of a mesh as a share of the square root of its area: 1.5
/// mean edge lengths of the bundled bunny (28k vertices). Measured with
/// `tools/sampling_invariance.py` (the figures are in `docs/design/scale.md`):
/// at this scale (`RidgesOptions::scale`) the bunny remeshed at 0.5× to 2× its
/// edge length or decimated to a half or a quarter of its faces keeps its
/// ridges and valleys; 1.5% and 2% kept fewer lines, less stable.
pub const MESH_SCALE_SHARE: f64 = 0.01;

/// The share of a mesh's feature scale for which its surface is smoothed
/// before its curvature is estimated ([`super::RidgesOptions::scale`]): a time
/// of (share · scale)²; the curvature tensor field is smoothed for the scale.
pub const SCALE_PRESMOOTH_SHARE: f64 = 0.7;

/// The implicit smoothing steps of a mesh's surface, of its curvature tensor
/// field and of its extremalities at a feature scale
/// ([`super::RidgesOptions::scale`]), unless given.
pub const SCALE_SMOOTH_STEPS: usize = 3;

/// [`Volume::feature_scale`].
pub(crate) fn image_scale(volume: &Volume, level: f64, voxel: f64) -> f64 {
    let inside = volume
        .samples()
        .iter()
        .filter(|&&s| f64::from(s) >= level)
        .count();
    let voxel_volume: f64 = volume.spacing().iter().product();
    let size = (inside as f64 * voxel_volume).cbrt();
    (IMAGE_SCALE_SHARE * size).max(voxel)
}

/// The default feature scale of `mesh`: [`MESH_SCALE_SHARE`] times the square
/// root of its area, at least its mean edge length.
pub fn mesh_scale(mesh: &Mesh) -> f64 {
    let area: f64 = mesh.vertex_areas().iter().sum();
    (MESH_SCALE_SHARE * area.sqrt()).max(mesh.mean_edge_length())
}

/// The scale `given` (world units), checked to be positive and finite, or
/// `default()` when none is.
pub fn chosen_scale(given: Option<f64>, default: impl FnOnce() -> f64) -> crate::Result<f64> {
    match given {
        None => Ok(default()),
        Some(scale) if scale.is_finite() && scale > 0.0 => Ok(scale),
        Some(scale) => Err(crate::Error::Argument(format!(
            "`scale` is {scale}; it must be a positive, finite length"
        ))),
    }
}

impl Volume {
    /// The default feature scale of the isosurface `level` of `volume` (inside is
    /// `f ≥ level`): `IMAGE_SCALE_SHARE` times the cube root of the enclosed volume
    /// (the samples at or above the level, times a voxel's volume), at least one
    /// voxel (`voxel`, the largest spacing): below that the grid cannot tell.
    pub fn feature_scale(&self, level: f64, voxel: f64) -> f64 {
        image_scale(self, level, voxel)
    }
}
