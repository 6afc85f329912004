//! The estimator of line extraction chosen per mesh: the jet fit where the mesh is
//! clean, the discrete shape operator where it is noisy.
//!
//! On a clean mesh the jet fit's extremalities (from its third-order terms) put a
//! ridge 20 to 70 times closer to the true one than the shape operator's discrete
//! extremalities; on a noisy mesh the fitted extremalities are noisier than the
//! smoothed discrete ones and the shape operator is closer (examples
//! `jet_extremality` and `default_fidelity`). The jet fit's residual tells the two
//! apart, from a sample of fits ([`JetFit::median_residual`]).

use super::{CurvatureEstimator, CurvatureField, JetFit, ShapeOperator};
use crate::mesh::Mesh;
use crate::Result;

/// The median fit residual below which a mesh is clean and gets the jet fit; also
/// the residual at which fitted extremalities start to be smoothed
/// ([`crate::ridges::FULL_SMOOTHING_RESIDUAL`]). Measured medians: about 4·10⁻⁸ on
/// a clean irregular ellipsoid, 2.5·10⁻⁴ with normal noise of 0.2 mean edge
/// lengths after 3 presmoothing steps (0.08 without them), 1.6·10⁻³ to 3.6·10⁻²
/// on the bundled meshes and the dragon scan.
pub const CLEAN_FIT_RESIDUAL: f64 = 1e-5;

/// How many vertices' fits decide ([`JetFit::median_residual`]).
const SAMPLED_FITS: usize = 2000;

/// [`JetFit`] on a mesh whose median fit residual is below
/// `CLEAN_FIT_RESIDUAL`, [`ShapeOperator`] otherwise.
#[derive(Clone, Copy, Debug, Default)]
pub struct AutoEstimator;

impl AutoEstimator {
    /// Whether `mesh` is clean enough for the jet fit.
    pub fn is_clean(mesh: &Mesh) -> bool {
        JetFit::default()
            .median_residual(mesh, SAMPLED_FITS)
            .is_some_and(|r| r < CLEAN_FIT_RESIDUAL)
    }
}

impl CurvatureEstimator for AutoEstimator {
    fn estimate(&self, mesh: &Mesh) -> Result<CurvatureField> {
        if AutoEstimator::is_clean(mesh) {
            JetFit::default().estimate(mesh)
        } else {
            ShapeOperator.estimate(mesh)
        }
    }
}
