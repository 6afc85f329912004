//! The edge-based discrete shape operator (Hildebrandt, Polthier, Wardetzky 2005, §3;
//! after Cohen-Steiner and Morvan 2003 and Hildebrandt and Polthier 2004).

use rayon::prelude::*;

use crate::differential::tangent_basis;
use crate::mesh::{EdgeId, Mesh};
use crate::{Result, Vector};

use super::{CurvatureEstimator, CurvatureField, PrincipalCurvatures};

/// The discrete shape operator: for each interior edge e with face normals N1, N2,
/// S(e) = H_e (ê × N_e)(ê × N_e)ᵀ with H_e = 2|e| sin(φ_e / 2) (φ_e the signed
/// dihedral angle, positive on convex edges) and N_e = normalize(N1 + N2); at each
/// vertex S(p) = ½ Σ_{e∋p} ⟨N_p, N_e⟩ S(e), with N_p the area-weighted normal. The
/// eigenpairs of S(p) in the tangent plane of N_p, rescaled by 3 / area(star(p)),
/// are the principal curvatures and directions. Boundary edges contribute nothing
/// and boundary vertices are flagged unreliable.
///
/// Cost: one parallel pass over the faces (their area vectors and unit normals)
/// and one over the vertices, each edge evaluated from both of its ends (cheaper
/// than storing per-edge operators).
///
/// Robustness: the operator is computed in the unit frame ([`Mesh::in_unit_frame`])
/// and the curvatures scaled back, so any coordinate scale works; non-finite and
/// outlying estimates (e.g. at a vertex whose star has collapsed) are flagged
/// unreliable and replaced (`super::robust::repair_outliers`).
#[derive(Clone, Copy, Debug, Default)]
pub struct ShapeOperator;

/// The per-edge part of the operator: S(e) = `mean_curvature` · v vᵀ.
#[derive(Clone, Copy)]
struct EdgeOperator {
    mean_curvature: f64,
    /// ê × N_e: the tangent direction across the edge.
    across: Vector,
    normal: Vector,
}

impl CurvatureEstimator for ShapeOperator {
    fn estimate(&self, mesh: &Mesh) -> Result<CurvatureField> {
        Ok(super::robust::estimate_robustly(mesh, estimate_unit))
    }
}

/// The field of a mesh in the unit frame, before repairs.
fn estimate_unit(mesh: &Mesh) -> CurvatureField {
    // The faces' area vectors are recomputed where summed rather than stored:
    // cheaper than writing and reading a vector per face on large meshes.
    let normals: Vec<Vector> = mesh
        .par_faces()
        .map(|f| mesh.face_area_vector(f).normalize())
        .collect();
    CurvatureField::from_fn(mesh.vertex_count(), |v| {
        let mut area_vector = Vector::zeros();
        for h in mesh.outgoing(v) {
            let f = mesh.face(h);
            if f.is_valid() {
                area_vector += mesh.face_area_vector(f);
            }
        }
        let normal = area_vector.normalize();
        let star_area = 0.5 * area_vector.norm();
        // S(p) in the tangent plane of N_p, accumulated as its three entries.
        let basis = tangent_basis(&normal);
        let mut form = [0.0; 3];
        for h in mesh.outgoing(v) {
            // Each edge is evaluated from both of its ends: cheaper than storing it.
            let e = edge_operator(mesh, mesh.edge(h), &normals);
            let weight = normal.dot(&e.normal) * e.mean_curvature;
            let (p, q) = (e.across.dot(&basis.0), e.across.dot(&basis.1));
            form[0] += weight * p * p;
            form[1] += weight * p * q;
            form[2] += weight * q * q;
        }
        // ½ Σ ..., rescaled by the lumped mass area(star) / 3.
        let scale = 0.5 * 3.0 / star_area;
        let k = PrincipalCurvatures::from_tangent_form(form.map(|x| x * scale), basis, &normal);
        (k, normal, mesh.is_boundary_vertex(v))
    })
}

/// S(e) of edge `e` from the unit normals of the faces.
fn edge_operator(mesh: &Mesh, e: EdgeId, normals: &[Vector]) -> EdgeOperator {
    let h = mesh.edge_halfedge(e, 0);
    let edge = mesh.halfedge_vector(h);
    if mesh.is_boundary_edge(e) {
        return EdgeOperator {
            mean_curvature: 0.0,
            across: Vector::zeros(),
            normal: Vector::zeros(),
        };
    }
    let n1 = normals[mesh.face(h).idx()];
    let n2 = normals[mesh.face(mesh.twin(h)).idx()];
    let length = edge.norm();
    let e_hat = edge / length;
    // 2|e| sin(φ/2) without trigonometry: sin φ = ⟨N1 × N2, ê⟩ (signed) and
    // 2 cos(φ/2) = |N1 + N2| = √(2 (1 + cos φ)), so sin(φ/2) = sin φ / |N1 + N2|.
    let sum = n1 + n2;
    let sum_length = sum.norm();
    // Folded faces (N1 = −N2) have no edge normal; such an edge contributes nothing.
    if sum_length < 1e-12 {
        return EdgeOperator {
            mean_curvature: 0.0,
            across: Vector::zeros(),
            normal: Vector::zeros(),
        };
    }
    let normal = sum / sum_length;
    let sin_phi = n1.cross(&n2).dot(&e_hat);
    EdgeOperator {
        mean_curvature: 2.0 * length * sin_phi / sum_length,
        across: e_hat.cross(&normal),
        normal,
    }
}
