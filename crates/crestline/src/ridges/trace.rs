//! Tracing the zero sets of the extremalities: regular triangles with the feature
//! conditions (Hildebrandt, Polthier, Wardetzky 2005, §4.1, eqs. 5 and 6), then the
//! singular triangles from their regular neighbours (§4.2). The zero rule and the
//! crossings are those of [`ZeroSet`], shared with every other traced line.

use rayon::prelude::*;

use crate::curvature::CurvatureField;
use crate::lines::zero_set::{LinePoint, ZeroSet};
use crate::lines::{DirectionField, EdgeSigns};
use crate::mesh::{EdgeId, FaceId, Mesh};
use crate::Vector;

use super::extremality::{face_gradient, Principal};

/// One field's extremality, prepared for tracing.
pub struct Extremality<'a> {
    /// The field (ridges: `Max`, valleys: `Min`).
    pub which: Principal,
    /// e per vertex, signed relative to the field's principal directions.
    pub zero_set: ZeroSet<'a>,
    /// The field's principal directions.
    pub directions: DirectionField<'a>,
    /// Their signs σ on every edge.
    pub signs: &'a EdgeSigns,
    /// Whether each face is regular for the directions (Definition 1).
    pub regular: &'a [bool],
    /// Whether to apply the feature conditions (eqs. 5, 6); without them every
    /// zero crossing (maxima and minima of either magnitude) is traced.
    pub feature_conditions: bool,
}

impl<'a> Extremality<'a> {
    /// Wrap smoothed extremality values for tracing; `signs` are those of the
    /// field's directions.
    pub fn new(
        which: Principal,
        values: Vec<f64>,
        field: &'a CurvatureField,
        signs: &'a EdgeSigns,
        regular: &'a [bool],
        feature_conditions: bool,
    ) -> Self {
        Extremality {
            which,
            zero_set: ZeroSet::with_signs(values, signs),
            directions: which.direction_field(field),
            signs,
            regular,
            feature_conditions,
        }
    }
}

/// The feature-line segments of one field: one per regular triangle whose zero set
/// passes the feature conditions, plus those bridging singular triangles.
pub fn trace(mesh: &Mesh, field: &CurvatureField, ext: &Extremality<'_>) -> Vec<[LinePoint; 2]> {
    let regular_segments = ext.zero_set.face_segments(mesh, |f, _| {
        ext.regular[f.idx()] && (!ext.feature_conditions || is_feature(mesh, field, ext, f))
    });
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

/// Whether the zero set in regular face `f` satisfies the feature condition of its
/// field, with directions and values signed consistently within the face: ridges
/// ⟨∇e_max, Σ d_max⟩ < 0 and |Σ k_max| > |Σ k_min| (eqs. 5, 6); valleys
/// ⟨∇e_min, Σ d_min⟩ > 0 and |Σ k_min| > |Σ k_max|.
fn is_feature(mesh: &Mesh, field: &CurvatureField, ext: &Extremality<'_>, f: FaceId) -> bool {
    let corners = mesh.face_vertices(f).map(|v| v.idx());
    let d = ext.directions;
    // σ from the first corner to each: halfedge 0 joins corners 0 and 1,
    // halfedge 2 corners 2 and 0.
    let [h0, _, h2] = mesh.face_halfedges(f);
    let signs = [
        1.0,
        ext.signs.sign(mesh.edge(h0)),
        ext.signs.sign(mesh.edge(h2)),
    ];
    // The values seen from the first corner.
    let oriented_values = [0, 1, 2].map(|i| signs[i] * ext.zero_set.value(corners[i]));
    let direction_sum: Vector = (0..3).map(|i| d.at(corners[i]) * signs[i]).sum();
    let slope = face_gradient(mesh, f, oriented_values).dot(&direction_sum);
    let k_max: f64 = corners.iter().map(|&c| field.k_max[c]).sum();
    let k_min: f64 = corners.iter().map(|&c| field.k_min[c]).sum();
    match ext.which {
        Principal::Max => slope < 0.0 && k_max.abs() > k_min.abs(),
        Principal::Min => slope > 0.0 && k_min.abs() > k_max.abs(),
    }
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
