//! `--structure`: the anatomical structure a GIfTI surface output is of.

use crestline::io::gifti::structure;
use crestline::io::DEFAULT_STRUCTURE;

/// The anatomical structure of a `.surf.gii` output, an option of the commands
/// that write surfaces.
#[derive(clap::Args, Debug, Clone)]
pub struct StructureArg {
    /// The anatomical structure a .surf.gii output records for Connectome
    /// Workbench (AnatomicalStructurePrimary), one of Workbench's names in any
    /// letter case: CortexLeft, CortexRight, Cerebellum, ...
    #[arg(long, default_value = DEFAULT_STRUCTURE, value_parser = workbench_name)]
    pub structure: String,
}

/// Workbench's spelling of the structure `name`, or the list of names.
fn workbench_name(name: &str) -> Result<String, String> {
    structure(name)
        .map(str::to_string)
        .map_err(|e| e.to_string())
}
