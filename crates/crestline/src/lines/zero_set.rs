//! Zero sets of functions on the vertices of a triangle mesh, traced as line
//! segments: one tracer for ridges and valleys (extremalities, whose sign depends on
//! a direction field), silhouettes (n · view) and any other piecewise linear field.
//!
//! The zero rule (Hildebrandt, Polthier, Wardetzky 2005, §4.1): a stored value of
//! exactly zero counts as the smallest positive number in its vertex's own frame,
//! so that both triangles of an edge agree on whether it is crossed. Edge (p, q) is
//! crossed iff e(p) and σ_pq e(q) differ in sign, at t = e(p) / (e(p) − σ_pq e(q)),
//! σ_pq the sign between a direction field's d(p) and d(q)
//! ([`super::DirectionField::sign`], per edge [`EdgeSigns`]) and 1 without one: the same point
//! seen from both triangles, so segments chain exactly by edge id.

use rayon::prelude::*;

use crate::mesh::{EdgeId, FaceId, Mesh};

use super::{EdgeSigns, SurfaceLocation};

/// A point of a traced line on a mesh: where a zero set crosses an edge, or the
/// barycenter of a face where three lines meet (a trisector of a singular face).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum LinePoint {
    /// The crossing on this edge.
    Edge(EdgeId),
    /// The barycenter of this face.
    Face(FaceId),
}

/// A piecewise linear function on the vertices of a mesh whose zero set is traced,
/// optionally signed relative to a per-vertex direction field.
#[derive(Clone, Debug)]
pub struct ZeroSet<'a> {
    /// Values per vertex, exact zeros replaced by the smallest positive number.
    values: Vec<f64>,
    /// The signs σ between the directions the values' signs refer to, if any.
    signs: Option<&'a EdgeSigns>,
}

impl<'a> ZeroSet<'a> {
    /// The zero set of `values` (one per vertex).
    pub fn new(values: Vec<f64>) -> ZeroSet<'static> {
        ZeroSet {
            values: without_zeros(values),
            signs: None,
        }
    }

    /// The zero set of `values` whose signs are relative to sign-ambiguous
    /// directions (e.g. extremalities along principal directions) whose edges'
    /// signs are `signs`.
    pub fn with_signs(values: Vec<f64>, signs: &'a EdgeSigns) -> ZeroSet<'a> {
        ZeroSet {
            values: without_zeros(values),
            signs: Some(signs),
        }
    }

    /// The value at vertex `v`, in its own frame (never exactly zero).
    pub fn value(&self, v: usize) -> f64 {
        self.values[v]
    }

    /// σ of edge `e`: 1 without directions.
    pub fn sign(&self, e: EdgeId) -> f64 {
        self.signs.map_or(1.0, |signs| signs.sign(e))
    }

    /// Where the zero set crosses edge `e`, as the parameter t ∈ (0, 1) from its
    /// first to its second vertex ([`Mesh::edge_vertices`]), or `None`.
    pub fn crossing(&self, mesh: &Mesh, e: EdgeId) -> Option<f64> {
        let [p, q] = mesh.edge_vertices(e).map(|v| v.idx());
        // The value at q carried into the frame of p: σ_pq e(q).
        let (a, b) = (self.values[p], self.sign(e) * self.values[q]);
        ((a > 0.0) != (b > 0.0)).then(|| a / (a - b))
    }

    /// The first two crossed edges of face `f`, if two are crossed. (A face where
    /// the signs are consistent has zero or two; a face singular for the direction
    /// field may have one or three, see Hildebrandt et al. §4.2.)
    pub fn face_segment(&self, mesh: &Mesh, f: FaceId) -> Option<[EdgeId; 2]> {
        let mut crossed = mesh
            .face_halfedges(f)
            .into_iter()
            .map(|h| mesh.edge(h))
            .filter(|&e| self.crossing(mesh, e).is_some());
        Some([crossed.next()?, crossed.next()?])
    }

    /// The segment of every face for which `keep` holds, in face order (computed in
    /// parallel); `None` where the face has no segment or `keep` refuses it.
    pub fn face_segments(
        &self,
        mesh: &Mesh,
        keep: impl Fn(FaceId, [EdgeId; 2]) -> bool + Sync,
    ) -> Vec<Option<[EdgeId; 2]>> {
        mesh.par_faces()
            .map(|f| self.face_segment(mesh, f).filter(|&s| keep(f, s)))
            .collect()
    }

    /// The segments of the zero set in every face, as pairs of edge crossings
    /// (chain them with [`super::chain::chain`]).
    pub fn segments(&self, mesh: &Mesh) -> Vec<[LinePoint; 2]> {
        self.face_segments(mesh, |_, _| true)
            .into_iter()
            .flatten()
            .map(|[a, b]| [LinePoint::Edge(a), LinePoint::Edge(b)])
            .collect()
    }

    /// Where a line point lies on the mesh: the crossing parameter on its edge, or
    /// the barycenter of its face.
    pub fn location(&self, mesh: &Mesh, point: LinePoint) -> SurfaceLocation {
        match point {
            LinePoint::Edge(e) => SurfaceLocation::Edge {
                edge: e.0,
                t: self.crossing(mesh, e).unwrap_or(0.5),
            },
            LinePoint::Face(f) => SurfaceLocation::Face {
                face: f.0,
                barycentric: [1.0 / 3.0; 3],
            },
        }
    }
}

/// `values` with every exact zero replaced by the smallest positive number.
fn without_zeros(mut values: Vec<f64>) -> Vec<f64> {
    for x in values.iter_mut().filter(|x| **x == 0.0) {
        *x = f64::MIN_POSITIVE;
    }
    values
}
