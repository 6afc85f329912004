//! Measuring an estimate against exact curvature.

use super::{CurvatureField, PrincipalCurvatures};

impl CurvatureField {
    /// Relative RMS error of this estimate over its reliable vertices against the
    /// `exact` curvatures (one per vertex, as the analytic test surfaces give them):
    /// √(Σ (k_max − k1)² + (k_min − k2)²) / √(Σ k1² + k2²), with k1 ≥ k2 the exact
    /// curvatures. Returns `None` if no vertex is reliable or the exact field is zero.
    pub fn relative_rms_error(&self, exact: &[PrincipalCurvatures]) -> Option<f64> {
        relative_rms_error(self, exact)
    }
}

/// [`CurvatureField::relative_rms_error`] of `field`.
fn relative_rms_error(field: &CurvatureField, exact: &[PrincipalCurvatures]) -> Option<f64> {
    let (mut error, mut norm) = (0.0, 0.0);
    for (i, truth) in exact
        .iter()
        .enumerate()
        .filter(|(i, _)| !field.unreliable[*i])
    {
        error += (field.k_max[i] - truth.k_max).powi(2) + (field.k_min[i] - truth.k_min).powi(2);
        norm += truth.k_max.powi(2) + truth.k_min.powi(2);
    }
    (norm > 0.0).then(|| (error / norm).sqrt())
}
