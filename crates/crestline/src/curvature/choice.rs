//! The estimators that come with the crate, by name.

use std::sync::Arc;

use super::{AutoEstimator, CurvatureEstimator, JetFit, ShapeOperator};

/// One of the crate's curvature estimators, named as on the command line.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Estimator {
    /// [`ShapeOperator`] (`shape-operator`): fast, best on regular meshes.
    #[default]
    ShapeOperator,
    /// [`JetFit`] (`jet-fit`): slower, accurate on irregular meshes.
    JetFit,
    /// [`AutoEstimator`] (`auto`): the jet fit on a clean mesh, the shape operator
    /// on a noisy one, told apart by the fit's residual. The default of line
    /// extraction.
    Auto,
}

crate::named::named!(Estimator, "estimator", {
    ShapeOperator => "shape-operator",
    JetFit => "jet-fit",
    Auto => "auto",
});

impl Estimator {
    /// The estimator with its default settings.
    pub fn build(self) -> Arc<dyn CurvatureEstimator + Send + Sync> {
        match self {
            Estimator::ShapeOperator => Arc::new(ShapeOperator),
            Estimator::JetFit => Arc::new(JetFit::default()),
            Estimator::Auto => Arc::new(AutoEstimator),
        }
    }
}
