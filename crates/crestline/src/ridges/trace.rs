//! Tracing the zero sets of the extremalities: regular triangles with the feature
//! conditions (Hildebrandt, Polthier, Wardetzky 2005, §4.1, eqs. 5 and 6), then the
//! singular triangles from their regular neighbours (§4.2).

use rayon::prelude::*;

use crate::curvature::CurvatureField;
use crate::mesh::{EdgeId, FaceId, Mesh};
use crate::Vector;

use super::extremality::{direction_sign, face_gradient, Principal};

/// A point of a traced line: where a zero set crosses an edge, or the barycenter
/// of a singular triangle where three lines meet (a trisector).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum LinePoint {
    Edge(EdgeId),
    Face(FaceId),
}

/// One field's extremality, prepared for tracing.
pub struct Extremality<'a> {
    pub which: Principal,
    /// e per vertex, in each vertex's own direction sign, with exact zeros replaced
    /// by the smallest positive number (so both triangles of an edge agree on
    /// whether it is crossed).
    pub values: Vec<f64>,
    pub directions: &'a [Vector],
    pub regular: &'a [bool],
    /// Whether to apply the feature conditions (eqs. 5, 6); without them every
    /// zero crossing (maxima and minima of either magnitude) is traced.
    pub feature_conditions: bool,
}

impl<'a> Extremality<'a> {
    /// Wrap smoothed extremality values for tracing.
    pub fn new(
        which: Principal,
        mut values: Vec<f64>,
        field: &'a CurvatureField,
        regular: &'a [bool],
        feature_conditions: bool,
    ) -> Self {
        for x in values.iter_mut().filter(|x| **x == 0.0) {
            *x = f64::MIN_POSITIVE;
        }
        Extremality {
            which,
            values,
            directions: which.directions(field),
            regular,
            feature_conditions,
        }
    }

    /// Where the zero set crosses edge `e`, as the parameter t ∈ (0, 1) from its
    /// first to its second vertex ([`Mesh::edge_vertices`]), or `None`. The edge is
    /// crossed iff e(p) σ_pq e(q) < 0, at t = e(p) / (e(p) − σ_pq e(q)): the same
    /// point seen from both triangles of the edge.
    pub fn crossing(&self, mesh: &Mesh, e: EdgeId) -> Option<f64> {
        let [p, q] = mesh.edge_vertices(e).map(|v| v.idx());
        let (ep, eq) = (
            self.values[p],
            direction_sign(self.directions, p, q) * self.values[q],
        );
        (ep * eq < 0.0).then(|| ep / (ep - eq))
    }
}

/// The feature-line segments of one field: one per regular triangle whose zero set
/// passes the feature conditions, plus those bridging singular triangles.
pub fn trace(mesh: &Mesh, field: &CurvatureField, ext: &Extremality<'_>) -> Vec<[LinePoint; 2]> {
    let regular_segments: Vec<Option<[EdgeId; 2]>> = mesh
        .par_faces()
        .map(|f| {
            if ext.regular[f.idx()] {
                regular_segment(mesh, field, ext, f)
            } else {
                None
            }
        })
        .collect();
    let singular: Vec<[LinePoint; 2]> = mesh
        .par_faces()
        .filter(|f| !ext.regular[f.idx()])
        .flat_map_iter(|f| singular_segments(mesh, f, &regular_segments))
        .collect();
    regular_segments
        .into_iter()
        .flatten()
        .map(|[a, b]| [LinePoint::Edge(a), LinePoint::Edge(b)])
        .chain(singular)
        .collect()
}

/// The segment of the zero set in regular face `f`, if it crosses two edges and
/// satisfies the feature condition of its field, with directions and values signed
/// consistently within the face: ridges ⟨∇e_max, Σ d_max⟩ < 0 and
/// |Σ k_max| > |Σ k_min| (eqs. 5, 6); valleys ⟨∇e_min, Σ d_min⟩ > 0 and
/// |Σ k_min| > |Σ k_max|.
fn regular_segment(
    mesh: &Mesh,
    field: &CurvatureField,
    ext: &Extremality<'_>,
    f: FaceId,
) -> Option<[EdgeId; 2]> {
    let mut crossed = mesh
        .face_halfedges(f)
        .into_iter()
        .map(|h| mesh.edge(h))
        .filter(|&e| ext.crossing(mesh, e).is_some());
    let (first, second) = (crossed.next()?, crossed.next()?);
    if !ext.feature_conditions {
        return Some([first, second]);
    }
    let corners = mesh.face_vertices(f).map(|v| v.idx());
    let d = ext.directions;
    let signs = corners.map(|c| direction_sign(d, corners[0], c));
    let oriented_values = [0, 1, 2].map(|i| signs[i] * ext.values[corners[i]]);
    let direction_sum: Vector = (0..3).map(|i| d[corners[i]] * signs[i]).sum();
    let slope = face_gradient(mesh, f, oriented_values).dot(&direction_sum);
    let k_max: f64 = corners.iter().map(|&c| field.k_max[c]).sum();
    let k_min: f64 = corners.iter().map(|&c| field.k_min[c]).sum();
    let is_feature = match ext.which {
        Principal::Max => slope < 0.0 && k_max.abs() > k_min.abs(),
        Principal::Min => slope > 0.0 && k_min.abs() > k_max.abs(),
    };
    is_feature.then_some([first, second])
}

/// Bridge singular face `f` (§4.2): its edges where a neighbouring regular face's
/// segment ends are marked; two marks are connected, three meet at the barycenter,
/// one is a line end and adds nothing.
fn singular_segments(
    mesh: &Mesh,
    f: FaceId,
    regular_segments: &[Option<[EdgeId; 2]>],
) -> Vec<[LinePoint; 2]> {
    let marked: Vec<EdgeId> = mesh
        .face_halfedges(f)
        .into_iter()
        .filter_map(|h| {
            let e = mesh.edge(h);
            let neighbour = mesh.face(mesh.twin(h));
            let segment = neighbour
                .is_valid()
                .then(|| regular_segments[neighbour.idx()])
                .flatten()?;
            segment.contains(&e).then_some(e)
        })
        .collect();
    match marked.as_slice() {
        [a, b] => vec![[LinePoint::Edge(*a), LinePoint::Edge(*b)]],
        [a, b, c] => [a, b, c]
            .into_iter()
            .map(|e| [LinePoint::Face(f), LinePoint::Edge(*e)])
            .collect(),
        _ => Vec::new(),
    }
}
