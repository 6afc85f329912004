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
//! `AnatomicalStructurePrimary` ([`STRUCTURES`]) and `GeometricType`.

mod encoding;
mod read;
mod write;

pub(in crate::io) use read::{parse_surface, parse_values};
pub use write::{
    write_gifti_labels, write_gifti_surface, write_gifti_values, GiftiLabel, Metadata,
};

use crate::{Error, Result};

/// The intent of a surface's coordinates.
const POINTSET: &str = "NIFTI_INTENT_POINTSET";

/// The intent of a surface's triangles.
const TRIANGLE: &str = "NIFTI_INTENT_TRIANGLE";

/// The structure names Connectome Workbench accepts as a file's
/// `AnatomicalStructurePrimary` (the GUI names of its `StructureEnum`, without
/// `All` and `Invalid`).
pub const STRUCTURES: &[&str] = &[
    "CortexLeft",
    "CortexRight",
    "Cerebellum",
    "AccumbensLeft",
    "AccumbensRight",
    "AllGreyMatter",
    "AllWhiteMatter",
    "AmygdalaLeft",
    "AmygdalaRight",
    "BrainStem",
    "CaudateLeft",
    "CaudateRight",
    "CerebellarWhiteMatterLeft",
    "CerebellarWhiteMatterRight",
    "CerebellumLeft",
    "CerebellumRight",
    "CerebralWhiteMatterLeft",
    "CerebralWhiteMatterRight",
    "Cortex",
    "DiencephalonVentralLeft",
    "DiencephalonVentralRight",
    "HippocampusLeft",
    "HippocampusRight",
    "Other",
    "OtherGreyMatter",
    "OtherWhiteMatter",
    "PallidumLeft",
    "PallidumRight",
    "PutamenLeft",
    "PutamenRight",
    "ThalamusLeft",
    "ThalamusRight",
];

/// The structure of [`STRUCTURES`] named `name`, in any letter case.
pub fn structure(name: &str) -> Result<&'static str> {
    STRUCTURES
        .iter()
        .find(|s| s.eq_ignore_ascii_case(name))
        .copied()
        .ok_or_else(|| Error::unknown_name("anatomical structure", name, STRUCTURES))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn structures_are_matched_in_any_case() {
        assert_eq!(structure("cortexleft").unwrap(), "CortexLeft");
        assert_eq!(structure("Other").unwrap(), "Other");
        let error = structure("LeftCortex").unwrap_err().to_string();
        assert!(error.contains("CortexRight"), "{error}");
    }
}
