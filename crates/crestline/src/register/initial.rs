//! Starting guesses for ICP from the moments of the point sets: the centroids
//! matched, and the principal axes of the moving set turned onto those of the fixed
//! set in each of the 24 ways that keep a frame right-handed (every axis
//! permutation with its sign choices), since the order of axes with close variances
//! and the sign of every axis are arbitrary.

use nalgebra::{Matrix3, Rotation3, SymmetricEigen};

use super::icp::centre_and_radius;
use super::transform::RigidTransform;
use crate::{Error, Point, Result};

/// The centroid of a point set and its principal axes.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    centre: Point,
    /// Columns: the principal axes, a right-handed orthonormal frame.
    axes: Rotation3<f64>,
}

/// The principal frame of `what` (`"fixed"` or `"moving"`) points: an error
/// ([`Error::Argument`]) if they all lie on one line, where a rotation about it
/// cannot be told.
pub fn principal_frame(points: &[Point], what: &str) -> Result<Frame> {
    let (centre, _) = centre_and_radius(points);
    let covariance: Matrix3<f64> = points
        .iter()
        .map(|p| (p - centre) * (p - centre).transpose())
        .sum();
    let eigen = SymmetricEigen::new(covariance);
    let mut order = [0, 1, 2];
    order.sort_by(|&a, &b| eigen.eigenvalues[b].total_cmp(&eigen.eigenvalues[a]));
    let (largest, middle) = (eigen.eigenvalues[order[0]], eigen.eigenvalues[order[1]]);
    if middle <= 1e-12 * largest {
        return Err(Error::Argument(format!(
            "the {what} points lie on a line (or coincide), so a rotation cannot be found"
        )));
    }
    let mut axes = Matrix3::from_columns(&order.map(|i| eigen.eigenvectors.column(i).into_owned()));
    if axes.determinant() < 0.0 {
        axes.set_column(2, &-axes.column(2));
    }
    Ok(Frame {
        centre,
        axes: Rotation3::from_matrix_unchecked(axes),
    })
}

/// The starting transforms taking `moving` onto `fixed`: centroids matched without
/// rotation, then the 24 principal-axis alignments.
pub fn hypotheses(fixed: &Frame, moving: &Frame) -> Vec<RigidTransform> {
    std::iter::once(Rotation3::identity())
        .chain(
            cube_rotations()
                .into_iter()
                .map(|turn| fixed.axes * turn * moving.axes.inverse()),
        )
        .map(|rotation| {
            RigidTransform::new(
                rotation,
                fixed.centre.coords - rotation * moving.centre.coords,
            )
        })
        .collect()
}

/// The 24 rotations that map the coordinate axes onto themselves: the signed
/// permutation matrices of determinant +1.
fn cube_rotations() -> Vec<Rotation3<f64>> {
    const PERMUTATIONS: [[usize; 3]; 6] = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ];
    let mut rotations = Vec::with_capacity(24);
    for permutation in PERMUTATIONS {
        for signs in 0..8 {
            let mut matrix = Matrix3::zeros();
            for (row, &column) in permutation.iter().enumerate() {
                matrix[(row, column)] = if (signs >> row) & 1 == 1 { -1.0 } else { 1.0 };
            }
            if matrix.determinant() > 0.0 {
                rotations.push(Rotation3::from_matrix_unchecked(matrix));
            }
        }
    }
    rotations
}
