//! The curvature field smoothed over the feature scale: the shape operator of
//! every vertex, S = k_max d_max d_maxᵀ + k_min d_min d_minᵀ (a symmetric 3 × 3
//! tensor of the ambient space), diffused by implicit heat steps
//! (M + tK) S' = M S with the mesh's cotan Laplacian and lumped masses, then
//! restricted to each vertex's tangent plane and diagonalised again.
//!
//! Unlike smoothing the surface itself (step 1 of Hildebrandt et al.'s Table 1,
//! [`super::presmooth_surface`]), this leaves the geometry in place: a part
//! thinner than the scale (a horn, a tail) keeps its shape, where mean curvature
//! flow shrinks it to a needle whose curvature is unbounded. The heat operator
//! with the mass matrix converges as the mesh is refined, so a time in world units
//! is the same filter on every sampling of a surface.

use nalgebra::Matrix3;
use rayon::prelude::*;

use super::smoothing::ExtremalitySmoother;
use crate::curvature::CurvatureField;
use crate::linalg::Solver;
use crate::lines::EdgeSigns;
use crate::mesh::Mesh;
use crate::progress::Observer;
use crate::{Result, Vector};

/// The six independent entries (xx, yy, zz, xy, xz, yz) of a symmetric tensor.
const ENTRIES: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)];

/// `field` of `mesh` after `steps` implicit heat steps of time `tau` h̄² of its
/// shape operators, solved as `solver` says. The normals and the flags of
/// unreliable vertices stay; extremalities an estimator gave are dropped (they
/// belong to the unsmoothed curvature), so they are differentiated again from
/// the smoothed field.
pub(crate) fn smooth_curvature(
    mesh: &Mesh,
    field: &CurvatureField,
    steps: usize,
    tau: f64,
    solver: Solver,
    observer: &mut dyn Observer,
) -> Result<CurvatureField> {
    let mut entries = tensor_entries(field);
    let smoother = ExtremalitySmoother::new(mesh, tau, None, solver)?.analyzed(None)?;
    let mut slices: Vec<&mut [f64]> = entries.iter_mut().map(|e| &mut e[..]).collect();
    smoother.smooth(&EdgeSigns::positive(mesh), &mut slices, steps, observer)?;
    Ok(principal_field(field, &entries))
}

/// The entries ([`ENTRIES`]) of every vertex's shape operator.
fn tensor_entries(field: &CurvatureField) -> Vec<Vec<f64>> {
    let tensors: Vec<Matrix3<f64>> = (0..field.k_max.len())
        .into_par_iter()
        .map(|v| {
            let (dmax, dmin) = (field.d_max[v], field.d_min[v]);
            dmax * dmax.transpose() * field.k_max[v] + dmin * dmin.transpose() * field.k_min[v]
        })
        .collect();
    ENTRIES
        .iter()
        .map(|&(i, j)| tensors.iter().map(|t| t[(i, j)]).collect())
        .collect()
}

/// The principal curvatures and directions of the smoothed tensors `entries` in
/// the tangent planes of `field`'s normals.
fn principal_field(field: &CurvatureField, entries: &[Vec<f64>]) -> CurvatureField {
    let principal: Vec<(f64, f64, Vector, Vector)> = (0..field.k_max.len())
        .into_par_iter()
        .map(|v| {
            let mut s = Matrix3::zeros();
            for (k, &(i, j)) in ENTRIES.iter().enumerate() {
                s[(i, j)] = entries[k][v];
                s[(j, i)] = entries[k][v];
            }
            in_tangent_plane(&s, field.normal[v], field.d_max[v])
        })
        .collect();
    CurvatureField {
        k_max: principal.iter().map(|p| p.0).collect(),
        k_min: principal.iter().map(|p| p.1).collect(),
        d_max: principal.iter().map(|p| p.2).collect(),
        d_min: principal.iter().map(|p| p.3).collect(),
        normal: field.normal.clone(),
        unreliable: field.unreliable.clone(),
        extremality: None,
        fit_residual: None,
    }
}

/// The eigenvalues (larger first) and unit eigenvectors of `s` restricted to the
/// plane normal to `n`, in the basis (`u`, n × `u`) of that plane (`u` a tangent
/// direction, e.g. the unsmoothed d_max); the minimal direction is n × d_max, so
/// that (d_max, d_min, n) is right-handed.
fn in_tangent_plane(s: &Matrix3<f64>, n: Vector, u: Vector) -> (f64, f64, Vector, Vector) {
    let u = (u - n * n.dot(&u)).normalize();
    let w = n.cross(&u);
    let (a, b, c) = ((s * u).dot(&u), (s * u).dot(&w), (s * w).dot(&w));
    // The symmetric 2 × 2 [[a, b], [b, c]]: eigenvalues m ± r, the larger's
    // eigenvector at angle θ with tan 2θ = 2b / (a − c).
    let (m, r) = (0.5 * (a + c), (0.25 * (a - c) * (a - c) + b * b).sqrt());
    let theta = 0.5 * (2.0 * b).atan2(a - c);
    let dmax = u * theta.cos() + w * theta.sin();
    (m + r, m - r, dmax, n.cross(&dmax))
}
