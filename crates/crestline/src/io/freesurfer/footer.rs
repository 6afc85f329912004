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
//! They are read into, and written from, a [`VolumeGeometry`].

use crate::space::VolumeGeometry;
use crate::{Error, Result};

/// The tag words FreeSurfer writes before the volume geometry.
#[cfg(test)]
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

/// The footer of `geometry` as FreeSurfer and nibabel write it, tag included.
#[cfg(test)]
pub(crate) fn footer_bytes(geometry: &VolumeGeometry) -> Vec<u8> {
    let mut bytes: Vec<u8> = TAG.iter().flat_map(|w| w.to_be_bytes()).collect();
    let triple = |v: [f64; 3]| format!("{} {} {}", v[0], v[1], v[2]);
    let [nx, ny, nz] = geometry.volume;
    let values = [
        geometry.valid.clone(),
        geometry.filename.clone(),
        format!("{nx} {ny} {nz}"),
        triple(geometry.voxel_size),
        triple(geometry.x_ras),
        triple(geometry.y_ras),
        triple(geometry.z_ras),
        triple(geometry.c_ras),
    ];
    for (key, value) in KEYS.iter().zip(values) {
        bytes.extend_from_slice(format!("{key:<6} = {value}\n").as_bytes());
    }
    bytes
}

/// The geometry in the bytes after a surface's faces: `None` when they are
/// empty or hold another tag (ignored, as FreeSurfer and nibabel do); an error
/// when the tag is there but its lines are malformed.
pub(crate) fn read_footer(bytes: &[u8]) -> Result<Option<VolumeGeometry>> {
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

/// The three numbers of a footer line.
fn numbers<T: std::str::FromStr>(key: &str, value: &str) -> Result<[T; 3]> {
    let parsed: Vec<T> = value
        .split_whitespace()
        .map(str::parse)
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| footer_error(format!("'{key}' is not three numbers")))?;
    <[T; 3]>::try_from(parsed).map_err(|_| footer_error(format!("'{key}' is not three numbers")))
}

/// An error in the footer, saying so.
fn footer_error(message: String) -> Error {
    Error::Parse(format!("volume geometry footer: {message}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn conformed(c_ras: [f64; 3]) -> VolumeGeometry {
        VolumeGeometry::conformed("orig.mgz", c_ras)
    }

    #[test]
    fn footers_read_back_and_bad_ones_are_refused() {
        let geometry = conformed([0.5, -1.25, 3.0]);
        let bytes = footer_bytes(&geometry);
        assert_eq!(read_footer(&bytes).unwrap(), Some(geometry));
        assert_eq!(read_footer(&[]).unwrap(), None);
        assert_eq!(read_footer(&[0, 0, 0, 7]).unwrap(), None);
        let mut broken = bytes.clone();
        let at = broken.windows(4).position(|w| w == b"xras").unwrap();
        broken[at] = b'q';
        let error = read_footer(&broken).unwrap_err();
        assert!(error.to_string().contains("'xras = ...'"), "{error}");
    }
}
