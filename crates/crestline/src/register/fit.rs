//! The rigid motion that best maps paired points onto each other in the weighted
//! least-squares sense (Kabsch 1976; Umeyama 1991, whose sign correction keeps the
//! result a rotation when the best orthogonal map would be a reflection).

use nalgebra::{Matrix3, Rotation3};

use super::transform::RigidTransform;
use crate::{Error, Point, Result, Vector};

/// The proper rigid motion `T` minimizing `Σ wᵢ ‖T(sourceᵢ) − targetᵢ‖²`, with
/// `weights` all 1 when `None`.
///
/// Centred on the weighted centroids, the rotation is `V·diag(1, 1, d)·Uᵀ` where
/// `U·Σ·Vᵀ` is the SVD of the cross-covariance `Σ wᵢ (sᵢ − s̄)(tᵢ − t̄)ᵀ` and
/// `d = sign det(V·Uᵀ)` flips the axis of the smallest singular value when the
/// unconstrained optimum is a reflection (Umeyama 1991).
///
/// Errors ([`Error::Argument`]) if the slices differ in length, are empty, a
/// weight is negative or not finite, or the weights sum to zero.
pub fn best_rigid_fit(
    source: &[Point],
    target: &[Point],
    weights: Option<&[f64]>,
) -> Result<RigidTransform> {
    let weight_of = |i: usize| weights.map_or(1.0, |w| w[i]);
    check_pairs(source, target, weights)?;
    let total: f64 = (0..source.len()).map(weight_of).sum();
    if !(total > 0.0 && total.is_finite()) {
        return Err(Error::Argument(format!(
            "the weights of a rigid fit sum to {total}, not a positive number"
        )));
    }
    let centroid = |points: &[Point]| -> Vector {
        (0..points.len())
            .map(|i| points[i].coords * weight_of(i))
            .sum::<Vector>()
            / total
    };
    let (source_centre, target_centre) = (centroid(source), centroid(target));
    let covariance: Matrix3<f64> = (0..source.len())
        .map(|i| {
            (source[i].coords - source_centre)
                * (target[i].coords - target_centre).transpose()
                * weight_of(i)
        })
        .sum();
    let rotation = proper_rotation(&covariance);
    Ok(RigidTransform::new(
        rotation,
        target_centre - rotation * source_centre,
    ))
}

/// The rotation `V·diag(1, 1, d)·Uᵀ` from the SVD `U·Σ·Vᵀ` of `covariance`, the
/// sign `d` applied to the singular vectors of the smallest singular value.
fn proper_rotation(covariance: &Matrix3<f64>) -> Rotation3<f64> {
    let svd = covariance.svd(true, true);
    let (Some(u), Some(v_t)) = (svd.u, svd.v_t) else {
        unreachable!("the SVD was asked for both singular vector matrices")
    };
    let v = v_t.transpose();
    let mut correction = Matrix3::identity();
    if (v * u.transpose()).determinant() < 0.0 {
        correction[(svd.singular_values.imin(), svd.singular_values.imin())] = -1.0;
    }
    Rotation3::from_matrix_unchecked(v * correction * u.transpose())
}

/// Equal, non-zero lengths and finite, non-negative weights.
fn check_pairs(source: &[Point], target: &[Point], weights: Option<&[f64]>) -> Result<()> {
    if source.len() != target.len() || source.is_empty() {
        return Err(Error::Argument(format!(
            "a rigid fit needs as many source as target points, at least one ({} and {})",
            source.len(),
            target.len()
        )));
    }
    if let Some(weights) = weights {
        if weights.len() != source.len() {
            return Err(Error::Argument(format!(
                "{} weights for {} point pairs",
                weights.len(),
                source.len()
            )));
        }
        if let Some(bad) = weights.iter().find(|w| !(w.is_finite() && **w >= 0.0)) {
            return Err(Error::Argument(format!(
                "a rigid-fit weight is {bad}, not finite and non-negative"
            )));
        }
    }
    Ok(())
}
