//! Anatomical structures as Connectome Workbench names them.
//!
//! Workbench tags every surface file with the structure it belongs to, and refuses
//! names it does not know. Its list (`StructureEnum` in Workbench's source) gives
//! each structure two spellings: the GIfTI one, written as a surface's
//! `AnatomicalStructurePrimary` metadata (`CortexLeft`), and the enum one, written
//! as the `Structure` attribute of a border file (`CORTEX_LEFT`). [`Structure`]
//! is one of them and parses either spelling.

use std::fmt;
use std::str::FromStr;

use crate::{Error, Result};

/// Every structure Workbench knows, as (GIfTI name, border-file name).
const STRUCTURES: [(&str, &str); 36] = [
    ("CortexLeft", "CORTEX_LEFT"),
    ("CortexRight", "CORTEX_RIGHT"),
    ("Cortex", "CORTEX"),
    ("Cerebellum", "CEREBELLUM"),
    ("CerebellumLeft", "CEREBELLUM_LEFT"),
    ("CerebellumRight", "CEREBELLUM_RIGHT"),
    ("AccumbensLeft", "ACCUMBENS_LEFT"),
    ("AccumbensRight", "ACCUMBENS_RIGHT"),
    ("All", "ALL"),
    ("AllGreyMatter", "ALL_GREY_MATTER"),
    ("AllWhiteMatter", "ALL_WHITE_MATTER"),
    ("AmygdalaLeft", "AMYGDALA_LEFT"),
    ("AmygdalaRight", "AMYGDALA_RIGHT"),
    ("BrainStem", "BRAIN_STEM"),
    ("CaudateLeft", "CAUDATE_LEFT"),
    ("CaudateRight", "CAUDATE_RIGHT"),
    ("CerebellarWhiteMatterLeft", "CEREBELLAR_WHITE_MATTER_LEFT"),
    (
        "CerebellarWhiteMatterRight",
        "CEREBELLAR_WHITE_MATTER_RIGHT",
    ),
    ("CerebralWhiteMatterLeft", "CEREBRAL_WHITE_MATTER_LEFT"),
    ("CerebralWhiteMatterRight", "CEREBRAL_WHITE_MATTER_RIGHT"),
    ("DiencephalonVentralLeft", "DIENCEPHALON_VENTRAL_LEFT"),
    ("DiencephalonVentralRight", "DIENCEPHALON_VENTRAL_RIGHT"),
    ("HippocampusLeft", "HIPPOCAMPUS_LEFT"),
    ("HippocampusRight", "HIPPOCAMPUS_RIGHT"),
    ("HippocampusDentateLeft", "HIPPOCAMPUS_DENTATE_LEFT"),
    ("HippocampusDentateRight", "HIPPOCAMPUS_DENTATE_RIGHT"),
    ("Invalid", "INVALID"),
    ("Other", "OTHER"),
    ("OtherGreyMatter", "OTHER_GREY_MATTER"),
    ("OtherWhiteMatter", "OTHER_WHITE_MATTER"),
    ("PallidumLeft", "PALLIDUM_LEFT"),
    ("PallidumRight", "PALLIDUM_RIGHT"),
    ("PutamenLeft", "PUTAMEN_LEFT"),
    ("PutamenRight", "PUTAMEN_RIGHT"),
    ("ThalamusLeft", "THALAMUS_LEFT"),
    ("ThalamusRight", "THALAMUS_RIGHT"),
];

/// An anatomical structure Connectome Workbench knows: the one a surface or a
/// border file belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Structure(usize);

impl Structure {
    /// `Other`: a structure Workbench accepts for any surface, the default.
    pub const OTHER: Structure = Structure(27);

    /// Every GIfTI name, in Workbench's order.
    pub const NAMES: [&'static str; STRUCTURES.len()] = {
        let mut names = [""; STRUCTURES.len()];
        let mut i = 0;
        while i < STRUCTURES.len() {
            names[i] = STRUCTURES[i].0;
            i += 1;
        }
        names
    };

    /// The name in GIfTI metadata (`AnatomicalStructurePrimary`), e.g. `CortexLeft`.
    pub fn gifti_name(self) -> &'static str {
        STRUCTURES[self.0].0
    }

    /// The GIfTI metadata entry that names the structure,
    /// `AnatomicalStructurePrimary` (Workbench reads it from the point set's
    /// metadata in a surface file and from the file's metadata in the others).
    pub fn gifti_metadata(self) -> [(&'static str, &'static str); 1] {
        [("AnatomicalStructurePrimary", self.gifti_name())]
    }

    /// The name in a border file's `Structure` attribute, e.g. `CORTEX_LEFT`.
    pub fn border_name(self) -> &'static str {
        STRUCTURES[self.0].1
    }
}

impl Default for Structure {
    fn default() -> Self {
        Structure::OTHER
    }
}

impl fmt::Display for Structure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.gifti_name())
    }
}

impl FromStr for Structure {
    type Err = Error;

    /// Either spelling (`CortexLeft` or `CORTEX_LEFT`), in any letter case.
    fn from_str(name: &str) -> Result<Structure> {
        STRUCTURES
            .iter()
            .position(|(gifti, border)| {
                gifti.eq_ignore_ascii_case(name) || border.eq_ignore_ascii_case(name)
            })
            .map(Structure)
            .ok_or_else(|| Error::unknown_name("anatomical structure", name, &Structure::NAMES))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_spellings_parse_to_the_same_structure() {
        for &name in Structure::NAMES.iter() {
            let structure: Structure = name.parse().unwrap();
            assert_eq!(structure.gifti_name(), name);
            assert_eq!(
                structure.border_name().parse::<Structure>().unwrap(),
                structure
            );
            // The border name is the GIfTI name in capitals, words split by '_'.
            assert_eq!(
                structure.border_name().replace('_', ""),
                name.to_ascii_uppercase()
            );
        }
        assert_eq!(Structure::default().gifti_name(), "Other");
        assert_eq!(
            "cortex_left".parse::<Structure>().unwrap().gifti_name(),
            "CortexLeft"
        );
        let error = "LeftCortex".parse::<Structure>().unwrap_err().to_string();
        assert!(error.contains("CortexLeft"), "{error}");
    }
}
