//! `--structure`: the anatomical structure a GIfTI surface output is of.

use crestline::io::gifti::STRUCTURES;
use crestline::io::DEFAULT_STRUCTURE;

/// The anatomical structure of a `.surf.gii` output, an option of the commands
/// that write surfaces.
#[derive(clap::Args, Debug, Clone)]
pub struct StructureArg {
    /// The anatomical structure a .surf.gii output records for Connectome
    /// Workbench (AnatomicalStructurePrimary), one of Workbench's names:
    /// CortexLeft, CortexRight, Cerebellum, ...
    #[arg(long, default_value = DEFAULT_STRUCTURE, hide_possible_values = true,
          value_parser = clap::builder::PossibleValuesParser::new(STRUCTURES))]
    pub structure: String,
}
