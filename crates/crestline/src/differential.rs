//! Differential geometry of a single point, shared by meshes, curvature estimators
//! and (implicit) surfaces of images: principal curvatures from a shape operator,
//! tangent bases, and the curvature of an implicit surface from its gradient and
//! Hessian.
//!
//! Sign convention, used everywhere in crestline: with outward normals a sphere has
//! both principal curvatures positive, and `k_max ≥ k_min` algebraically.

use nalgebra::Matrix3;

use crate::Vector;

/// Principal curvatures and unit principal directions at one point. `(d_max, d_min,
/// normal)` is a right-handed orthonormal frame; directions are defined up to sign.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrincipalCurvatures {
    /// The larger principal curvature (algebraically).
    pub k_max: f64,
    /// The smaller principal curvature (algebraically).
    pub k_min: f64,
    /// Unit direction of `k_max`.
    pub d_max: Vector,
    /// Unit direction of `k_min`.
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
        let (op_t1, op_t2) = (op * t1, op * t2);
        let a = t1.dot(&op_t1);
        let b = 0.5 * (t1.dot(&op_t2) + t2.dot(&op_t1));
        let c = t2.dot(&op_t2);
        let (k_max, k_min, [u, w]) = symmetric_2x2_eigen(a, b, c);
        let d_max = t1 * u + t2 * w;
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

/// Eigenvalues `λ1 ≥ λ2` of `[[a, b], [b, c]]` and a unit eigenvector of `λ1`
/// (`[1, 0]` when the matrix is a multiple of the identity).
pub fn symmetric_2x2_eigen(a: f64, b: f64, c: f64) -> (f64, f64, [f64; 2]) {
    let mean = 0.5 * (a + c);
    let half_gap = 0.5 * (a - c);
    let radius = (half_gap * half_gap + b * b).sqrt();
    // (A − λ2 I) has the λ1-eigenvector in its columns: take the longer one.
    let (column_1, column_2) = ([half_gap + radius, b], [b, radius - half_gap]);
    let norm = |v: [f64; 2]| (v[0] * v[0] + v[1] * v[1]).sqrt();
    let longer = if norm(column_1) >= norm(column_2) {
        column_1
    } else {
        column_2
    };
    let length = norm(longer);
    let direction = if length > 0.0 {
        [longer[0] / length, longer[1] / length]
    } else {
        [1.0, 0.0]
    };
    (mean + radius, mean - radius, direction)
}

/// Principal curvatures of the implicit surface F = 0 at a point where ∇F =
/// `gradient` and the Hessian of F is `hessian`, with outward normal n = ∇F/|∇F|:
/// the shape operator is W = P H P / |∇F| with P = I − n nᵀ, restricted to the
/// tangent plane. Returns the curvatures and n.
pub fn implicit_curvature(
    gradient: &Vector,
    hessian: &Matrix3<f64>,
) -> (PrincipalCurvatures, Vector) {
    let norm = gradient.norm();
    let n = gradient / norm;
    let projector = Matrix3::identity() - n * n.transpose();
    let shape = projector * hessian * projector / norm;
    (PrincipalCurvatures::from_tangent_operator(&shape, &n), n)
}

/// The third partial derivatives of a scalar field at a point: `t[i][j][k]` =
/// ∂³f/∂x_i∂x_j∂x_k, symmetric in its three indices.
pub type ThirdDerivatives = [[[f64; 3]; 3]; 3];

/// The curvature of the iso-surface of an image through one point, and how it
/// changes along the principal directions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IsoCurvature {
    /// Principal curvatures and directions, signed so that a bright convex object
    /// (inside f ≥ I) has positive curvature.
    pub principal: PrincipalCurvatures,
    /// The unit normal n = −∇f/|∇f|, pointing out of the object (toward darker
    /// values).
    pub normal: Vector,
    /// The extremality e_max = ∇k_max · d_max: zero on ridges and on the other
    /// extremal curves of k_max. Its sign follows the arbitrary sign of `d_max`.
    pub e_max: f64,
    /// The extremality e_min = ∇k_min · d_min.
    pub e_min: f64,
}

/// Curvature and extremalities of the iso-surface f = f(p) through a point p, from
/// the gradient, Hessian and third derivatives of the image f at p (Thirion and
/// Gourdon 1993, part 1, with the conventions of DESIGN.md): n = −g/|g|,
/// P = I − n nᵀ, shape operator W = −P H P / |g|, restricted to the tangent plane
/// ([`PrincipalCurvatures::from_tangent_operator`], symmetric in x, y and z).
///
/// The extremality along a principal direction t with curvature k is, by
/// Hellmann–Feynman (∂k = tᵀ (∂W) t where the curvatures differ), with ∂_j n =
/// −P H e_j / |g| and ∂_j |g| = −nᵀ H e_j:
///
/// `e = ∇k · t = (−f_ttt + 3 k nᵀ H t) / |g|`
///
/// with f_ttt = Σ f_ijk t_i t_j t_k. `None` where the gradient vanishes or a value
/// is not finite. At umbilics (k_max = k_min) the directions, and so the
/// extremalities, are arbitrary.
pub fn isosurface_curvature(
    gradient: &Vector,
    hessian: &Matrix3<f64>,
    third: &ThirdDerivatives,
) -> Option<IsoCurvature> {
    let norm = gradient.norm();
    let finite = hessian.iter().all(|h| h.is_finite())
        && third.iter().flatten().flatten().all(|t| t.is_finite());
    if !(norm > 0.0 && norm.is_finite() && finite) {
        return None;
    }
    // The object is where f is large: the implicit surface F = −f with outward
    // normal ∇F/|∇F| = −g/|g|.
    let (principal, normal) = implicit_curvature(&-gradient, &-hessian);
    let extremality = |k: f64, t: &Vector| {
        let f_ttt = directional_third(third, t);
        (-f_ttt + 3.0 * k * normal.dot(&(hessian * t))) / norm
    };
    Some(IsoCurvature {
        e_max: extremality(principal.k_max, &principal.d_max),
        e_min: extremality(principal.k_min, &principal.d_min),
        principal,
        normal,
    })
}

/// The third directional derivative Σ_ijk t_ijk v_i v_j v_k.
pub fn directional_third(third: &ThirdDerivatives, v: &Vector) -> f64 {
    let mut sum = 0.0;
    for (i, plane) in third.iter().enumerate() {
        for (j, row) in plane.iter().enumerate() {
            for (k, t) in row.iter().enumerate() {
                sum += t * v[i] * v[j] * v[k];
            }
        }
    }
    sum
}
