//! `--structure`: the anatomical structure a GIfTI surface or a border file output
//! is of.

use crestline::io::Structure;

/// The anatomical structure of a `.surf.gii` or `.border` output, an option of
/// the commands that write them.
#[derive(clap::Args, Debug, Clone)]
pub struct StructureArg {
    /// The anatomical structure a .surf.gii or .border output records for
    /// Connectome Workbench (AnatomicalStructurePrimary, or the border's
    /// Structure), one of Workbench's names in any letter case: CortexLeft,
    /// CortexRight, Cerebellum, ...
    #[arg(long, default_value_t = Structure::default())]
    pub structure: Structure,
}
