//! Extremality coefficients and regular triangles (Hildebrandt, Polthier,
//! Wardetzky 2005, §3, eq. 4 and Definition 1).

use rayon::prelude::*;

use crate::curvature::CurvatureField;
use crate::lines::{DirectionField, EdgeSigns};
use crate::mesh::{FaceId, Mesh};
use crate::Vector;

/// Which principal curvature a quantity belongs to: ridges come from `Max`,
/// valleys from `Min`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Principal {
    /// k_max, d_max: ridges.
    Max,
    /// k_min, d_min: valleys.
    Min,
}

impl Principal {
    /// The curvature values of this field.
    pub fn curvature(self, field: &CurvatureField) -> &[f64] {
        match self {
            Principal::Max => &field.k_max,
            Principal::Min => &field.k_min,
        }
    }

    /// The name of this field's extremality as a per-point value of a line.
    pub fn extremality_name(self) -> &'static str {
        match self {
            Principal::Max => "e_max",
            Principal::Min => "e_min",
        }
    }

    /// The extremalities of this field that the estimator gave
    /// ([`CurvatureField::extremality`]), if it did.
    pub fn given(self, field: &CurvatureField) -> Option<&[f64]> {
        let slot = match self {
            Principal::Max => 0,
            Principal::Min => 1,
        };
        field.extremality.as_ref().map(|e| &e[slot][..])
    }

    /// The (sign-ambiguous) directions of this field.
    pub fn directions(self, field: &CurvatureField) -> &[Vector] {
        match self {
            Principal::Max => &field.d_max,
            Principal::Min => &field.d_min,
        }
    }

    /// This field's directions with the normals they are tangent to.
    pub fn direction_field(self, field: &CurvatureField) -> DirectionField<'_> {
        DirectionField::new(self.directions(field), &field.normal)
    }
}

/// Gradient of the piecewise linear function with corner values `values` on face
/// `f`: ∇f = Σ_i f_i (N × e_i) / (2A), e_i the edge opposite corner i, counter-clockwise.
pub fn face_gradient(mesh: &Mesh, f: FaceId, values: [f64; 3]) -> Vector {
    let [a, b, c] = mesh.face_points(f);
    let area_vector = (b - a).cross(&(c - a));
    let twice_area = area_vector.norm();
    let n = area_vector / twice_area;
    let opposite = [c - b, a - c, b - a];
    let sum: Vector = (0..3).map(|i| n.cross(&opposite[i]) * values[i]).sum();
    sum / twice_area
}

/// The extremality e_i(p) = Σ_{T∋p} area(T) ⟨∇k_i(T), d_i(p)⟩ / area(star p) at every
/// vertex (eq. 4), for the arbitrary but fixed sign of d_i(p) stored in `field`.
/// A collapsed triangle (zero area: no gradient) contributes nothing, and a vertex
/// whose star has collapsed gets e = 0 (no information), never NaN.
pub fn extremality(mesh: &Mesh, field: &CurvatureField, which: Principal) -> Vec<f64> {
    let k = which.curvature(field);
    let d = which.directions(field);
    // Per face: area × ∇k (the area cancels the 1/(2A) of the gradient up to ½).
    let weighted_gradients: Vec<Vector> = mesh
        .par_faces()
        .map(|f| {
            let values = mesh.face_vertices(f).map(|v| k[v.idx()]);
            let weighted = face_gradient(mesh, f, values) * mesh.face_area(f);
            if weighted.iter().all(|x| x.is_finite()) {
                weighted
            } else {
                Vector::zeros()
            }
        })
        .collect();
    let areas = mesh.face_areas();
    mesh.par_vertices()
        .map(|v| {
            let (mut sum, mut star) = (Vector::zeros(), 0.0);
            for f in mesh.vertex_faces(v) {
                sum += weighted_gradients[f.idx()];
                star += areas[f.idx()];
            }
            let e = sum.dot(&d[v.idx()]) / star;
            if e.is_finite() {
                e
            } else {
                0.0
            }
        })
        .collect()
}

/// Whether face `f` is regular for the direction field whose edge signs are
/// `signs` (Definition 1): the directions at its corners can be signed so that
/// all pairs agree ([`DirectionField::sign`]), i.e. σ12 σ23 σ31 = +1.
pub fn is_regular(mesh: &Mesh, signs: &EdgeSigns, f: FaceId) -> bool {
    let product: f64 = mesh
        .face_halfedges(f)
        .iter()
        .map(|&h| signs.sign(mesh.edge(h)))
        .product();
    product > 0.0
}

/// Regularity of every face for the direction field whose edge signs are
/// `signs`.
pub fn regular_faces(mesh: &Mesh, signs: &EdgeSigns) -> Vec<bool> {
    mesh.par_faces()
        .map(|f| is_regular(mesh, signs, f))
        .collect()
}
