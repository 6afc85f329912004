//! The extractor trait every feature-line method implements.

use crate::mesh::Mesh;
use crate::Result;

use super::FeatureLines;

/// A method that finds feature lines on a mesh (e.g. extremality tracing or the
/// Morse-Smale complex). Implement it to plug a custom method into every consumer
/// of lines (writers, drawings).
pub trait LineExtractor {
    /// Find the feature lines of `mesh`.
    fn extract(&self, mesh: &Mesh) -> Result<FeatureLines>;
}
