//! Principal curvatures and directions.
//!
//! Sign convention, used everywhere in crestline: with outward normals (faces
//! counter-clockwise seen from outside) a sphere has both principal curvatures
//! positive. `k_max ≥ k_min` algebraically.

use nalgebra::Matrix3;

use crate::Vector;

/// Principal curvatures and unit principal directions at one point. `(d_max, d_min,
/// normal)` is a right-handed orthonormal frame; directions are defined up to sign.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrincipalCurvatures {
    pub k_max: f64,
    pub k_min: f64,
    pub d_max: Vector,
    pub d_min: Vector,
}

impl PrincipalCurvatures {
    /// Mean curvature H = (k_max + k_min) / 2.
    pub fn mean(&self) -> f64 {
        0.5 * (self.k_max + self.k_min)
    }

    /// Gaussian curvature K = k_max k_min.
    pub fn gauss(&self) -> f64 {
        self.k_max * self.k_min
    }

    /// Eigenpairs of a symmetric shape operator `op` restricted to the tangent plane
    /// of the unit `normal`: the 2×2 matrix ⟨t_i, op t_j⟩ in an orthonormal tangent
    /// basis is diagonalised in closed form. Using the tangent plane (rather than
    /// picking two of the 3×3 eigenvectors) stays well defined on flat and umbilic
    /// points.
    pub fn from_tangent_operator(op: &Matrix3<f64>, normal: &Vector) -> Self {
        let (t1, t2) = tangent_basis(normal);
        let a = t1.dot(&(op * t1));
        let b = 0.5 * (t1.dot(&(op * t2)) + t2.dot(&(op * t1)));
        let c = t2.dot(&(op * t2));
        let (k_max, k_min, angle) = symmetric_2x2_eigen(a, b, c);
        let d_max = t1 * angle.cos() + t2 * angle.sin();
        PrincipalCurvatures {
            k_max,
            k_min,
            d_max,
            d_min: normal.cross(&d_max),
        }
    }
}

/// An orthonormal basis `(t1, t2)` of the plane orthogonal to the unit vector `n`,
/// with `(t1, t2, n)` right-handed.
pub fn tangent_basis(n: &Vector) -> (Vector, Vector) {
    // Cross with the coordinate axis least aligned with n: never near-parallel.
    let axis = if n.x.abs() <= n.y.abs() && n.x.abs() <= n.z.abs() {
        Vector::x()
    } else if n.y.abs() <= n.z.abs() {
        Vector::y()
    } else {
        Vector::z()
    };
    let t1 = n.cross(&axis).normalize();
    (t1, n.cross(&t1))
}

/// Eigenvalues `λ1 ≥ λ2` of `[[a, b], [b, c]]` and the angle θ of the eigenvector
/// (cos θ, sin θ) of `λ1`.
pub fn symmetric_2x2_eigen(a: f64, b: f64, c: f64) -> (f64, f64, f64) {
    let mean = 0.5 * (a + c);
    let radius = (0.5 * (a - c)).hypot(b);
    (mean + radius, mean - radius, 0.5 * (2.0 * b).atan2(a - c))
}
