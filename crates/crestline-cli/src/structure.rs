//! `--structure`: the anatomical structure a GIfTI or border file output is of.

use crestline::io::Structure;

/// The anatomical structure of a GIfTI (`.surf.gii`, `.shape.gii`,
/// `.label.gii`) or `.border` output, an option of the commands that write them.
#[derive(clap::Args, Debug, Clone)]
pub struct StructureArg {
    /// The anatomical structure a GIfTI (.surf.gii, .shape.gii, .label.gii) or
    /// .border output records for Connectome Workbench (AnatomicalStructurePrimary,
    /// or the border's Structure), one of Workbench's names in any letter case:
    /// CortexLeft, CortexRight, Cerebellum, ...
    #[arg(long, default_value_t = Structure::default())]
    pub structure: Structure,
}
