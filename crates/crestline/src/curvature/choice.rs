//! The estimators that come with the crate, by name.

use std::sync::Arc;

use super::{CurvatureEstimator, JetFit, ShapeOperator};

/// One of the crate's curvature estimators, named as on the command line.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Estimator {
    /// [`ShapeOperator`] (`shape-operator`): fast, best on regular meshes.
    #[default]
    ShapeOperator,
    /// [`JetFit`] (`jet-fit`): slower, accurate on irregular meshes.
    JetFit,
}

crate::named::named!(Estimator, "estimator", {
    ShapeOperator => "shape-operator",
    JetFit => "jet-fit",
});

impl Estimator {
    /// The estimator with its default settings.
    pub fn build(self) -> Arc<dyn CurvatureEstimator + Send + Sync> {
        match self {
            Estimator::ShapeOperator => Arc::new(ShapeOperator),
            Estimator::JetFit => Arc::new(JetFit::default()),
        }
    }
}
