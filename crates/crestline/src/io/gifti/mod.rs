//! GIfTI, the XML format of surfaces and per-vertex data of nibabel, nilearn,
//! Connectome Workbench and FreeSurfer's `mris_convert` (GIfTI 1.0 spec,
//! <https://www.nitrc.org/projects/gifti/>).
//!
//! A file is a list of `DataArray`s, each with an intent, a data type, its
//! dimensions, an encoding and a byte order. A surface (`.surf.gii`) holds a
//! `NIFTI_INTENT_POINTSET` array of coordinates (RAS millimetres) and a
//! `NIFTI_INTENT_TRIANGLE` array of vertex indices; per-vertex values
//! (`.shape.gii`, `.func.gii`) and labels (`.label.gii`, with a `LabelTable`)
//! hold one array per map. The readers take the encodings `ASCII`,
//! `Base64Binary` and `GZipBase64Binary` (data in an external file is refused),
//! the data types float32, int32 and uint8, both byte orders and both index
//! orders; the writers write gzipped base64, little-endian and row-major.
//!
//! Connectome Workbench places a surface by the metadata
//! `AnatomicalStructurePrimary` ([`crate::io::Structure`]) and `GeometricType`.

mod encoding;
mod read;
mod write;

pub(in crate::io) use read::{parse_surface, parse_values};
pub use write::{
    write_gifti_labels, write_gifti_surface, write_gifti_values, GiftiLabel, Metadata,
};

/// The intent of a surface's coordinates.
const POINTSET: &str = "NIFTI_INTENT_POINTSET";

/// The intent of a surface's triangles.
const TRIANGLE: &str = "NIFTI_INTENT_TRIANGLE";
