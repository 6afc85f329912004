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
        Self::from_tangent_form([a, b, c], (t1, t2), normal)
    }

    /// The eigenpairs of the symmetric operator `[[a, b], [b, c]]` = `form` in the
    /// orthonormal tangent basis `(t1, t2)` (`tangent_basis` of `normal`).
    pub fn from_tangent_form(
        [a, b, c]: [f64; 3],
        (t1, t2): (Vector, Vector),
        normal: &Vector,
    ) -> Self {
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

/// The (symmetric) tensor of third partial derivatives `T[i][j][k] = ∂³f/∂xᵢ∂xⱼ∂xₖ`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThirdOrder(pub [[[f64; 3]; 3]; 3]);

impl ThirdOrder {
    /// The tensor from its 10 distinct components, in the order
    /// `xxx, xxy, xxz, xyy, xyz, xzz, yyy, yyz, yzz, zzz` (that of
    /// `crate::volume::Partial::ALL`).
    pub fn from_components(c: [f64; 10]) -> ThirdOrder {
        let mut t = [[[0.0; 3]; 3]; 3];
        for (i, plane) in t.iter_mut().enumerate() {
            for (j, row) in plane.iter_mut().enumerate() {
                for (k, value) in row.iter_mut().enumerate() {
                    *value = c[component_index(i, j, k)];
                }
            }
        }
        ThirdOrder(t)
    }

    /// The component `∂³f/∂xᵢ∂xⱼ∂xₖ`.
    pub fn get(&self, i: usize, j: usize, k: usize) -> f64 {
        self.0[i][j][k]
    }

    /// The derivative of the Hessian along `v`: `Σₖ T[i][j][k] vₖ`.
    pub fn contract(&self, v: &Vector) -> Matrix3<f64> {
        Matrix3::from_fn(|i, j| (0..3).map(|k| self.0[i][j][k] * v[k]).sum())
    }

    /// The third directional derivative along `v`: `Σ T[i][j][k] vᵢ vⱼ vₖ`.
    pub fn directional(&self, v: &Vector) -> f64 {
        v.dot(&(self.contract(v) * v))
    }

    /// The tensor in coordinates `x` where the present ones are `u = J x` (see the
    /// module documentation).
    pub fn pulled_back(&self, jacobian: &Matrix3<f64>) -> ThirdOrder {
        let mut out = [[[0.0; 3]; 3]; 3];
        for (i, plane) in out.iter_mut().enumerate() {
            for (j, row) in plane.iter_mut().enumerate() {
                for (k, value) in row.iter_mut().enumerate() {
                    *value = self.weighted_sum(jacobian, [i, j, k]);
                }
            }
        }
        ThirdOrder(out)
    }

    /// `Σ J[a][i] J[b][j] J[c][k] T[a][b][c]` for `(i, j, k) = at`.
    fn weighted_sum(&self, jacobian: &Matrix3<f64>, [i, j, k]: [usize; 3]) -> f64 {
        let mut sum = 0.0;
        for (a, plane) in self.0.iter().enumerate() {
            for (b, row) in plane.iter().enumerate() {
                let ab = jacobian[(a, i)] * jacobian[(b, j)];
                for (c, value) in row.iter().enumerate() {
                    sum += ab * jacobian[(c, k)] * value;
                }
            }
        }
        sum
    }
}

/// The position of component `(i, j, k)` among the 10 distinct ones
/// (`xxx, xxy, xxz, xyy, xyz, xzz, yyy, yyz, yzz, zzz`).
fn component_index(i: usize, j: usize, k: usize) -> usize {
    let mut sorted = [i, j, k];
    sorted.sort_unstable();
    let [a, b, c] = sorted;
    // Sorted triples in lexicographic order: those starting with 0 come first (6 of
    // them), then those starting with 1 (3), then (2, 2, 2).
    match a {
        0 => [[0, 1, 2], [0, 3, 4], [0, 0, 5]][b][c],
        1 => [6, 7, 8][b + c - 2],
        _ => 9,
    }
}

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
/// Gourdon 1993, part 1, with the conventions of docs/design/images.md): n = −g/|g|,
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
    third: &ThirdOrder,
) -> Option<IsoCurvature> {
    let norm = gradient.norm();
    let finite = hessian.iter().all(|h| h.is_finite())
        && third.0.iter().flatten().flatten().all(|t| t.is_finite());
    if !(norm > 0.0 && norm.is_finite() && finite) {
        return None;
    }
    // The object is where f is large: the implicit surface F = −f with outward
    // normal ∇F/|∇F| = −g/|g|.
    let (principal, normal) = implicit_curvature(&-gradient, &-hessian);
    let extremality = |k: f64, t: &Vector| {
        let f_ttt = third.directional(t);
        (-f_ttt + 3.0 * k * normal.dot(&(hessian * t))) / norm
    };
    Some(IsoCurvature {
        e_max: extremality(principal.k_max, &principal.d_max),
        e_min: extremality(principal.k_min, &principal.d_min),
        principal,
        normal,
    })
}
