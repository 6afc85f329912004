//! `--structure`: the anatomical structure a GIfTI surface output is of.

use crestline::io::Structure;

/// The anatomical structure of a `.surf.gii` output, an option of the commands
/// that write surfaces.
#[derive(clap::Args, Debug, Clone)]
pub struct StructureArg {
    /// The anatomical structure a .surf.gii output records for Connectome
    /// Workbench (AnatomicalStructurePrimary), one of Workbench's names in any
    /// letter case: CortexLeft, CortexRight, Cerebellum, ...
    #[arg(long, default_value_t = Structure::default())]
    pub structure: Structure,
}
