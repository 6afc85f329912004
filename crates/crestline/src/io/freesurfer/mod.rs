//! FreeSurfer's files: binary triangle surfaces (`lh.pial`, `lh.white`, ...),
//! per-vertex "curv" files (`lh.curv`, `lh.sulc`, `lh.thickness`) and ASCII
//! labels (`lh.cortex.label`).
//!
//! The layouts are those FreeSurfer's `utils/mrisurf` and `utils/label.c` read
//! and write, and nibabel's `nibabel/freesurfer/io.py` (FreeSurfer wiki,
//! "FileFormats" and "SurfaceFormats"). Binary numbers are big-endian.
//!
//! - A triangle surface ([`write_surface`], read by [`crate::io::read_mesh`])
//!   starts with the magic bytes `FF FF FE`, a "created by" line and an empty
//!   line, then the vertex and face counts (i32), the vertices (three f32 each,
//!   x y z) and the faces (three i32 each), and may end with the volume geometry
//!   of the image the surface was made from ([`VolumeGeometry`]).
//! - A curv file ([`read_curv`], [`write_curv`], the "new" format) starts with
//!   `FF FF FF`, then the vertex count, the face count and the values per vertex
//!   (i32, always 1 here), then one f32 per vertex.
//! - An ASCII label ([`write_label`]) is a `#!ascii label` comment line, the
//!   number of vertices, and one `vertex x y z value` line per labelled vertex.

pub(crate) mod curv;
mod footer;
pub(crate) mod label;
pub(crate) mod surface;

#[cfg(test)]
pub(crate) use curv::write_curv;
pub use label::{write_label, LabelledVertex};
#[cfg(test)]
pub(crate) use surface::write_surface;

pub(crate) use crate::space::VolumeGeometry;

/// The magic bytes of a triangle surface file.
pub(crate) const SURFACE_MAGIC: [u8; 3] = [0xFF, 0xFF, 0xFE];

/// The magic bytes of a new-format curv file (also those of FreeSurfer's old quad
/// surfaces, which crestline does not read).
pub(crate) const CURV_MAGIC: [u8; 3] = [0xFF, 0xFF, 0xFF];

/// The next big-endian i32 of `bytes` at `*pos`, advancing; `None` past the end.
fn be_i32(bytes: &[u8], pos: &mut usize) -> Option<i32> {
    let word = bytes.get(*pos..*pos + 4)?;
    *pos += 4;
    Some(i32::from_be_bytes([word[0], word[1], word[2], word[3]]))
}

/// A count read from a header: a negative one is an error naming `what`.
fn count(value: i32, what: &str) -> crate::Result<usize> {
    usize::try_from(value)
        .map_err(|_| crate::Error::Parse(format!("negative {what} count {value} in the header")))
}
