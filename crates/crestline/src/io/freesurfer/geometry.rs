//! The volume geometry footer of a FreeSurfer surface: the image the surface was
//! made from, which places its tkr-RAS coordinates in the scanner's RAS.
//!
//! After the faces, FreeSurfer writes the tag `TAG_OLD_SURF_GEOM` (20, as the
//! big-endian i32 words `2 0 20` or `20` alone, as nibabel's
//! `_read_volume_info` accepts them) followed by eight text lines:
//!
//! ```text
//! valid = 1  # volume info valid
//! filename = ../mri/filled-pretess255.mgz
//! volume = 256 256 256
//! voxelsize = 1 1 1
//! xras   = -1 0 0
//! yras   = 0 0 -1
//! zras   = 0 1 0
//! cras   = 5.3 18.0 0.1
//! ```
//!
//! The image's voxel-to-scanner matrix has the columns `xras`, `yras`, `zras`
//! scaled by the voxel size and puts the centre voxel `volume / 2` at `cras`; its
//! tkr-RAS matrix (FreeSurfer's `tkregister` frame, that of the surface's
//! vertices) has the columns `-x`, `-z`, `y` of the same sizes and the centre at
//! the origin. A vertex `p` is at `vox2ras · tkr_vox2ras⁻¹ · p` in the scanner's
//! RAS, which for the usual conformed images is `p + cras`.

use nalgebra::{Matrix3, Matrix4, Vector3};

use crate::{Error, Point, Result};

/// The tag words FreeSurfer writes before the volume geometry.
const TAG: [i32; 3] = [2, 0, 20];

/// The keys of the footer's lines, in their order.
const KEYS: [&str; 8] = [
    "valid",
    "filename",
    "volume",
    "voxelsize",
    "xras",
    "yras",
    "zras",
    "cras",
];

/// The image a FreeSurfer surface was made from, as its footer gives it (see the
/// module documentation); written back unchanged with the surface.
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

    /// The footer as FreeSurfer and nibabel write it, tag included.
    pub(crate) fn to_bytes(&self) -> Vec<u8> {
        let mut bytes: Vec<u8> = TAG.iter().flat_map(|w| w.to_be_bytes()).collect();
        let triple = |v: [f64; 3]| format!("{} {} {}", v[0], v[1], v[2]);
        let [nx, ny, nz] = self.volume;
        let values = [
            self.valid.clone(),
            self.filename.clone(),
            format!("{nx} {ny} {nz}"),
            triple(self.voxel_size),
            triple(self.x_ras),
            triple(self.y_ras),
            triple(self.z_ras),
            triple(self.c_ras),
        ];
        for (key, value) in KEYS.iter().zip(values) {
            bytes.extend_from_slice(format!("{key:<6} = {value}\n").as_bytes());
        }
        bytes
    }

    /// The geometry in the bytes after a surface's faces: `None` when they are
    /// empty or hold another tag (ignored, as FreeSurfer and nibabel do); an error
    /// when the tag is there but its lines are malformed.
    pub(crate) fn from_footer(bytes: &[u8]) -> Result<Option<VolumeGeometry>> {
        let mut pos = 0;
        match super::be_i32(bytes, &mut pos) {
            Some(20) => {}
            Some(2) if matches!(super::be_i32(bytes, &mut pos), Some(0 | 1)) => {
                if super::be_i32(bytes, &mut pos) != Some(20) {
                    return Ok(None);
                }
            }
            _ => return Ok(None),
        }
        let text = String::from_utf8_lossy(&bytes[pos..]);
        let mut lines = text.lines();
        let mut values = Vec::with_capacity(KEYS.len());
        for key in KEYS {
            let line = lines.next().unwrap_or("");
            let value = line
                .split_once('=')
                .filter(|(k, _)| k.trim() == key)
                .map(|(_, v)| v.trim())
                .ok_or_else(|| footer_error(format!("expected a '{key} = ...' line")))?;
            values.push(value);
        }
        Ok(Some(VolumeGeometry {
            valid: values[0].to_string(),
            filename: values[1].to_string(),
            volume: numbers(KEYS[2], values[2])?,
            voxel_size: numbers(KEYS[3], values[3])?,
            x_ras: numbers(KEYS[4], values[4])?,
            y_ras: numbers(KEYS[5], values[5])?,
            z_ras: numbers(KEYS[6], values[6])?,
            c_ras: numbers(KEYS[7], values[7])?,
        }))
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

/// The three numbers of a footer line.
fn numbers<T: std::str::FromStr>(key: &str, value: &str) -> Result<[T; 3]> {
    let parsed: Vec<T> = value
        .split_whitespace()
        .map(str::parse)
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| footer_error(format!("'{key}' is not three numbers")))?;
    <[T; 3]>::try_from(parsed).map_err(|_| footer_error(format!("'{key}' is not three numbers")))
}

fn footer_error(message: String) -> Error {
    Error::Parse(format!("volume geometry footer: {message}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn conformed(c_ras: [f64; 3]) -> VolumeGeometry {
        VolumeGeometry {
            valid: "1  # volume info valid".into(),
            filename: "orig.mgz".into(),
            volume: [256, 256, 256],
            voxel_size: [1.0, 1.0, 1.0],
            x_ras: [-1.0, 0.0, 0.0],
            y_ras: [0.0, 0.0, -1.0],
            z_ras: [0.0, 1.0, 0.0],
            c_ras,
        }
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
    fn footers_read_back_and_bad_ones_are_refused() {
        let geometry = conformed([0.5, -1.25, 3.0]);
        let bytes = geometry.to_bytes();
        assert_eq!(VolumeGeometry::from_footer(&bytes).unwrap(), Some(geometry));
        assert_eq!(VolumeGeometry::from_footer(&[]).unwrap(), None);
        assert_eq!(VolumeGeometry::from_footer(&[0, 0, 0, 7]).unwrap(), None);
        let mut broken = bytes.clone();
        let at = broken.windows(4).position(|w| w == b"xras").unwrap();
        broken[at] = b'q';
        let error = VolumeGeometry::from_footer(&broken).unwrap_err();
        assert!(error.to_string().contains("'xras = ...'"), "{error}");
        let invalid = VolumeGeometry {
            valid: "0".into(),
            ..conformed([0.0; 3])
        };
        assert!(invalid.tkr_to_scanner().is_none());
    }
}
