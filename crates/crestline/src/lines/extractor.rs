//! The extractor trait every feature-line method implements, and the inputs it
//! can take.

use crate::curvature::CurvatureField;
use crate::mesh::Mesh;
use crate::progress::Observer;
use crate::Result;

use super::FeatureLines;

/// A method that finds feature lines on an input: a [`Mesh`] by default, a
/// surface that carries what the method needs ([`SurfaceWithCurvature`],
/// [`SurfaceWithValues`]), or a [`crate::volume::Volume`]. The crate's three
/// methods implement it — extremality tracing ([`crate::ridges::ExtremalityTracer`]),
/// Morse-Smale lines ([`crate::morse::MorseSmale`]) and Marching Lines
/// ([`crate::crest_lines::LineTracing`]); implement it to plug a custom method
/// into every consumer of lines (filters, writers, drawings).
pub trait LineExtractor<Input: ?Sized = Mesh> {
    /// Find the feature lines of `input`, telling `observer` of the stages and
    /// stopping with [`crate::Error::Cancelled`] when it asks
    /// (`crate::progress::checkpoint`); [`crate::progress::Silent`] when no one
    /// listens.
    fn extract(&self, input: &Input, observer: &mut dyn Observer) -> Result<FeatureLines>;
}

/// A mesh with principal curvatures computed elsewhere (e.g. from the derivatives
/// of an image, or by a custom estimator), for extractors that need curvature.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceWithCurvature<'a> {
    /// The surface.
    pub mesh: &'a Mesh,
    /// Its curvature, one entry per vertex.
    pub curvature: &'a CurvatureField,
}

/// A mesh with one scalar per vertex (an indicator of features), for extractors
/// that work on a scalar field.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceWithValues<'a> {
    /// The surface.
    pub mesh: &'a Mesh,
    /// One value per vertex.
    pub values: &'a [f64],
}
