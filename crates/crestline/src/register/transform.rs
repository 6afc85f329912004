//! Rigid motions of 3D space: `x ↦ R·x + t` with `R` a proper rotation.

use nalgebra::{Matrix3, Matrix4, Rotation3};

use crate::{Error, Point, Result, Vector};

/// The rigid motion `x ↦ rotation · x + translation`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidTransform {
    /// The rotation `R` (orthogonal, determinant +1).
    pub rotation: Rotation3<f64>,
    /// The translation `t`, applied after the rotation.
    pub translation: Vector,
}

impl Default for RigidTransform {
    fn default() -> Self {
        RigidTransform::identity()
    }
}

impl RigidTransform {
    /// The motion `x ↦ rotation · x + translation`.
    pub fn new(rotation: Rotation3<f64>, translation: Vector) -> RigidTransform {
        RigidTransform {
            rotation,
            translation,
        }
    }

    /// The motion of a homogeneous 4×4 matrix `[[R, t], [0, 1]]`: an
    /// [`Error::Argument`] unless its last row is `0 0 0 1` and `R` is a proper
    /// rotation (orthonormal to 1e-6, determinant +1).
    pub fn from_matrix4(matrix: &Matrix4<f64>) -> Result<RigidTransform> {
        let rotation: Matrix3<f64> = matrix.fixed_view::<3, 3>(0, 0).into_owned();
        let translation: Vector = matrix.fixed_view::<3, 1>(0, 3).into_owned();
        let last_row = matrix.row(3).iter().copied().eq([0.0, 0.0, 0.0, 1.0]);
        let orthonormal = (rotation.transpose() * rotation - Matrix3::identity()).amax() <= 1e-6;
        if !matrix.iter().all(|x| x.is_finite()) || !last_row {
            return Err(Error::Argument(format!(
                "not a finite homogeneous matrix with last row 0 0 0 1: {matrix}"
            )));
        }
        if !orthonormal || rotation.determinant() <= 0.0 {
            return Err(Error::Argument(format!(
                "the 3 × 3 part is not a rotation (orthonormal, determinant +1): {rotation}"
            )));
        }
        Ok(RigidTransform::new(
            Rotation3::from_matrix(&rotation),
            translation,
        ))
    }

    /// The motion that moves nothing.
    pub fn identity() -> RigidTransform {
        RigidTransform::new(Rotation3::identity(), Vector::zeros())
    }

    /// The image of `point`.
    pub fn apply(&self, point: &Point) -> Point {
        self.rotation * point + self.translation
    }

    /// The motion that undoes this one: `x ↦ Rᵀ·(x − t)`.
    pub fn inverse(&self) -> RigidTransform {
        let rotation = self.rotation.inverse();
        RigidTransform::new(rotation, -(rotation * self.translation))
    }

    /// `self ∘ first`: the motion that applies `first`, then `self`.
    pub fn after(&self, first: &RigidTransform) -> RigidTransform {
        RigidTransform::new(
            self.rotation * first.rotation,
            self.rotation * first.translation + self.translation,
        )
    }

    /// The homogeneous 4×4 matrix `[[R, t], [0, 1]]` (acting on column vectors).
    pub fn to_matrix4(&self) -> Matrix4<f64> {
        let mut matrix = Matrix4::identity();
        matrix
            .fixed_view_mut::<3, 3>(0, 0)
            .copy_from(self.rotation.matrix());
        matrix
            .fixed_view_mut::<3, 1>(0, 3)
            .copy_from(&self.translation);
        matrix
    }

    /// The angle of the rotation, in degrees (in `[0, 180]`).
    pub fn angle_degrees(&self) -> f64 {
        rotation_angle(&self.rotation).to_degrees()
    }

    /// The same motion in coordinates whose first two axes are flipped:
    /// `F·T·F` with `F = diag(−1, −1, 1)`, which turns a motion in RAS coordinates
    /// into the same motion in LPS coordinates and back.
    pub fn flip_xy(&self) -> RigidTransform {
        let flip =
            Rotation3::from_matrix_unchecked(Matrix3::from_diagonal(&Vector::new(-1.0, -1.0, 1.0)));
        RigidTransform::new(flip * self.rotation * flip, flip * self.translation)
    }
}

/// The angle of `rotation` in radians, in `[0, π]`: `atan2(‖v‖, trace − 1)` with
/// `v` the axial vector of `R − Rᵀ` (`2 sin θ` long), which stays accurate for small
/// angles and defined when round-off puts the trace slightly above 3.
pub fn rotation_angle(rotation: &Rotation3<f64>) -> f64 {
    let r = rotation.matrix();
    let axial = Vector::new(
        r[(2, 1)] - r[(1, 2)],
        r[(0, 2)] - r[(2, 0)],
        r[(1, 0)] - r[(0, 1)],
    );
    axial.norm().atan2(r.trace() - 1.0)
}
