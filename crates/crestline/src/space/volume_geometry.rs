//! The image a FreeSurfer surface was made from, which places the surface's
//! tkr-RAS coordinates in the scanner's RAS (FreeSurfer's `VOL_GEOM`, the footer
//! of a surface file; see `crate::io::freesurfer`).
//!
//! The image's voxel-to-scanner matrix has the columns `xras`, `yras`, `zras`
//! scaled by the voxel size and puts the centre voxel `volume / 2` at `cras`; its
//! tkr-RAS matrix (FreeSurfer's `tkregister` frame, that of the surface's
//! vertices) has the columns `-x`, `-z`, `y` of the same sizes and the centre at
//! the origin. A vertex `p` is at `vox2ras · tkr_vox2ras⁻¹ · p` in the scanner's
//! RAS, which for the usual conformed images is `p + cras`.

use nalgebra::{Matrix3, Matrix4, Vector3};

use crate::Point;

/// The image a FreeSurfer surface was made from, as the surface file's footer
/// gives it (see the module documentation); written back unchanged with the
/// surface.
#[derive(Clone, Debug, PartialEq)]
pub struct VolumeGeometry {
    /// The text after `valid =` (`1  # volume info valid` for a valid geometry).
    pub valid: String,
    /// The image file's name.
    pub filename: String,
    /// The image's size in voxels.
    pub volume: [i64; 3],
    /// The voxel size in millimetres.
    pub voxel_size: [f64; 3],
    /// The RAS directions of the image's axes.
    pub x_ras: [f64; 3],
    /// See `x_ras`.
    pub y_ras: [f64; 3],
    /// See `x_ras`.
    pub z_ras: [f64; 3],
    /// The scanner RAS position of the image's centre.
    pub c_ras: [f64; 3],
}

impl VolumeGeometry {
    /// The geometry of a FreeSurfer conformed image (`mri_convert --conform`, the
    /// `orig.mgz` of a subject: 256³ voxels of 1 mm, LIA axes) named `filename`,
    /// its centre at `c_ras` in the scanner's RAS.
    pub fn conformed(filename: &str, c_ras: [f64; 3]) -> VolumeGeometry {
        VolumeGeometry {
            valid: "1  # volume info valid".into(),
            filename: filename.into(),
            volume: [256, 256, 256],
            voxel_size: [1.0, 1.0, 1.0],
            x_ras: [-1.0, 0.0, 0.0],
            y_ras: [0.0, 0.0, -1.0],
            z_ras: [0.0, 1.0, 0.0],
            c_ras,
        }
    }

    /// Whether the footer declares itself valid (`valid = 1`).
    pub fn is_valid(&self) -> bool {
        self.valid.split_whitespace().next() == Some("1")
    }

    /// The voxel-to-scanner-RAS matrix of the image.
    pub fn vox2ras(&self) -> Matrix4<f64> {
        let directions = Matrix3::from_columns(&[
            Vector3::from(self.x_ras),
            Vector3::from(self.y_ras),
            Vector3::from(self.z_ras),
        ]);
        centred(directions, Vector3::from(self.c_ras), self)
    }

    /// The voxel-to-tkr-RAS matrix of the image (FreeSurfer's
    /// `MRIxfmCRS2XYZtkreg`).
    pub fn tkr_vox2ras(&self) -> Matrix4<f64> {
        let directions = Matrix3::new(-1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, -1.0, 0.0);
        centred(directions, Vector3::zeros(), self)
    }

    /// The map from tkr-RAS to scanner RAS, `vox2ras · tkr_vox2ras⁻¹`; `None` when
    /// the geometry is not valid or its matrix singular.
    pub fn tkr_to_scanner(&self) -> Option<Matrix4<f64>> {
        if !self.is_valid() {
            return None;
        }
        let map = self.vox2ras() * self.tkr_vox2ras().try_inverse()?;
        map.iter().all(|x| x.is_finite()).then_some(map)
    }
}

/// `positions` in RAS taken back to tkr-RAS through `geometry` when it is valid
/// (the coordinates FreeSurfer's surface and label files hold), else as they are.
pub(crate) fn to_tkr(positions: &[Point], geometry: Option<&VolumeGeometry>) -> Vec<Point> {
    let to_tkr = geometry
        .and_then(VolumeGeometry::tkr_to_scanner)
        .and_then(|map| map.try_inverse());
    positions
        .iter()
        .map(|p| to_tkr.map_or(*p, |map| map.transform_point(p)))
        .collect()
}

/// The voxel-to-RAS matrix with axis `directions` scaled by the voxel sizes and
/// the centre voxel (`volume / 2`) at `centre`.
fn centred(
    directions: Matrix3<f64>,
    centre: Vector3<f64>,
    geometry: &VolumeGeometry,
) -> Matrix4<f64> {
    let linear = directions * Matrix3::from_diagonal(&Vector3::from(geometry.voxel_size));
    let half = Vector3::from(geometry.volume.map(|n| n as f64 / 2.0));
    let origin = centre - linear * half;
    let mut matrix = linear.to_homogeneous();
    matrix.fixed_view_mut::<3, 1>(0, 3).copy_from(&origin);
    matrix
}

#[cfg(test)]
mod tests {
    use super::*;

    fn conformed(c_ras: [f64; 3]) -> VolumeGeometry {
        VolumeGeometry::conformed("orig.mgz", c_ras)
    }

    #[test]
    fn a_conformed_image_moves_tkr_points_by_c_ras() {
        let map = conformed([5.5, -18.0, 2.25]).tkr_to_scanner().unwrap();
        let moved = map.transform_point(&Point::new(10.0, 20.0, 30.0));
        assert!((moved - Point::new(15.5, 2.0, 32.25)).norm() < 1e-12);
    }

    #[test]
    fn an_oblique_anisotropic_image_maps_its_voxels_consistently() {
        // The voxel (i, j, k) lies at tkr_vox2ras · (i, j, k) in tkr-RAS and at
        // vox2ras · (i, j, k) in scanner RAS.
        let geometry = VolumeGeometry {
            volume: [100, 120, 80],
            voxel_size: [0.9, 1.1, 1.3],
            x_ras: [0.6, 0.8, 0.0],
            y_ras: [-0.8, 0.6, 0.0],
            z_ras: [0.0, 0.0, 1.0],
            ..conformed([1.0, 2.0, 3.0])
        };
        let voxel = Point::new(7.0, 50.0, 33.0);
        let tkr = geometry.tkr_vox2ras().transform_point(&voxel);
        let scanner = geometry.vox2ras().transform_point(&voxel);
        let map = geometry.tkr_to_scanner().unwrap();
        assert!((map.transform_point(&tkr) - scanner).norm() < 1e-9);
    }

    #[test]
    fn an_invalid_geometry_places_nothing() {
        let invalid = VolumeGeometry {
            valid: "0".into(),
            ..conformed([0.0; 3])
        };
        assert!(invalid.tkr_to_scanner().is_none());
    }
}
