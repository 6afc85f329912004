//! Geometric quantities of a mesh: normals, areas, lengths, angles, cotan weights,
//! lumped mass, bounding box. Per-element functions compute one value; the plural
//! forms compute all of them in parallel.
//!
//! Range: lengths ([`Mesh::edge_length`], [`BoundingBox::diagonal`]) are computed
//! without overflow or underflow of their squares ([`robust_norm`]), so they are
//! right for coordinates anywhere in f64's range. Products of lengths (areas,
//! cross products, cotangents) are not: algorithms that need them at any scale
//! work on a copy of the mesh scaled by a power of two into the unit frame
//! ([`Mesh::in_unit_frame`]; exact, since scaling by a power of two only changes
//! exponents) and scale their results back.

use std::borrow::Cow;

use rayon::prelude::*;

use super::{EdgeId, FaceId, HalfedgeId, Mesh, VertexId};
use crate::{Point, Vector};

/// Axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct BoundingBox {
    /// The smallest coordinates.
    pub min: Point,
    /// The largest coordinates.
    pub max: Point,
}

impl BoundingBox {
    /// Length of the box diagonal: the mesh's reference length for relative tolerances.
    /// Finite for any finite box whose diagonal is below `f64::MAX` (the half
    /// extents are subtracted, so `max − min` cannot overflow).
    pub fn diagonal(&self) -> f64 {
        2.0 * robust_norm(&(self.max * 0.5 - self.min * 0.5))
    }

    /// Centre of the box.
    pub fn center(&self) -> Point {
        nalgebra::center(&self.min, &self.max)
    }
}

/// Signed angle from unit normal `n1` to unit normal `n2` about the unit `axis`
/// (φ = atan2(⟨n1 × n2, axis⟩, ⟨n1, n2⟩)): the signed dihedral angle of an edge
/// whose direction is `axis` as the boundary of the face with normal `n1` runs.
#[inline]
pub fn signed_angle(n1: &Vector, n2: &Vector, axis: &Vector) -> f64 {
    n1.cross(n2).dot(axis).atan2(n1.dot(n2))
}

/// Euclidean norm of `v` without overflow or underflow of the squares: the plain
/// √(Σ v_i²) when Σ v_i² is a normal float, else computed from `v` divided by its
/// largest absolute component.
pub fn robust_norm(v: &Vector) -> f64 {
    let squared = v.norm_squared();
    if squared.is_finite() && squared >= f64::MIN_POSITIVE {
        return squared.sqrt();
    }
    let largest = v.amax();
    if largest == 0.0 || !largest.is_finite() {
        return largest;
    }
    largest * (v / largest).norm()
}

/// The largest cotan weight used by [`Mesh::clamped_cotan_weight`]: ½ cot θ of an
/// angle θ ≈ 5·10⁻⁵ rad. Bounds the stiffness of sliver triangles (a degenerate one
/// would give ∞ or NaN).
pub const MAX_COTAN_WEIGHT: f64 = 1e4;

/// The power of two 2^k that brings the largest absolute coordinate of `points`
/// into [½, 1) (1 for no points or all at the origin). Multiplying by it is exact.
pub fn unit_scale(points: &[Point]) -> f64 {
    let largest = points.iter().map(|p| p.coords.amax()).fold(0.0, f64::max);
    if largest == 0.0 || !largest.is_finite() {
        return 1.0;
    }
    // largest ∈ [2^e, 2^(e+1)): the factor is 2^-(e+1), within f64's normal range.
    let exponent = largest.log2().floor() as i64 + 1;
    power_of_two(-exponent)
}

/// 2^n for n clamped to the exponents of normal floats, built from its bits.
fn power_of_two(n: i64) -> f64 {
    let n = n.clamp(-1022, 1023);
    f64::from_bits(((n + 1023) as u64) << 52)
}

/// Cotangent of the angle between `u` and `v`.
#[inline]
fn cot(u: &Vector, v: &Vector) -> f64 {
    u.dot(v) / u.cross(v).norm()
}

impl Mesh {
    /// The vector from the source to the target of `h`.
    #[inline]
    pub fn halfedge_vector(&self, h: HalfedgeId) -> Vector {
        self.position(self.target(h)) - self.position(self.source(h))
    }

    /// Twice the area times the unit normal of `f` (counter-clockwise corners).
    #[inline]
    pub fn face_area_vector(&self, f: FaceId) -> Vector {
        let [a, b, c] = self.face_points(f);
        (b - a).cross(&(c - a))
    }

    /// Unit normal of `f`.
    #[inline]
    pub fn face_normal(&self, f: FaceId) -> Vector {
        self.face_area_vector(f).normalize()
    }

    /// Area of `f`.
    #[inline]
    pub fn face_area(&self, f: FaceId) -> f64 {
        0.5 * self.face_area_vector(f).norm()
    }

    /// Unit normals of all faces.
    pub fn face_normals(&self) -> Vec<Vector> {
        self.par_faces().map(|f| self.face_normal(f)).collect()
    }

    /// Areas of all faces.
    pub fn face_areas(&self) -> Vec<f64> {
        self.par_faces().map(|f| self.face_area(f)).collect()
    }

    /// Length of `e` (right at any scale, computed without overflow or underflow).
    #[inline]
    pub fn edge_length(&self, e: EdgeId) -> f64 {
        robust_norm(&self.halfedge_vector(self.edge_halfedge(e, 0)))
    }

    /// Lengths of all edges.
    pub fn edge_lengths(&self) -> Vec<f64> {
        (0..self.edge_count() as u32)
            .into_par_iter()
            .map(|e| self.edge_length(EdgeId(e)))
            .collect()
    }

    /// Mean edge length h̄: the length unit of every mesh-relative parameter.
    /// (Where the plain sum of the lengths overflows, near f64::MAX, each length is
    /// divided by the count before summing.)
    pub fn mean_edge_length(&self) -> f64 {
        let lengths = self.edge_lengths();
        let n = lengths.len() as f64;
        let mean = lengths.iter().sum::<f64>() / n;
        if mean.is_finite() {
            return mean;
        }
        lengths.iter().map(|l| l / n).sum()
    }

    /// Interior angle of the face of `h` at the corner opposite `h`.
    #[inline]
    pub fn opposite_angle(&self, h: HalfedgeId) -> f64 {
        let (u, v) = self.opposite_legs(h);
        u.angle(&v)
    }

    /// The two edge vectors from the corner opposite `h` to the ends of `h`.
    #[inline]
    fn opposite_legs(&self, h: HalfedgeId) -> (Vector, Vector) {
        let opposite = self.position(self.target(self.next(h)));
        (
            self.position(self.source(h)) - opposite,
            self.position(self.target(h)) - opposite,
        )
    }

    /// Area-weighted normal of `v`: the normalised sum of the area vectors of the
    /// faces around it (the vertex normal N_p of Hildebrandt et al. §3).
    pub fn area_weighted_normal(&self, v: VertexId) -> Vector {
        self.vertex_faces(v)
            .map(|f| self.face_area_vector(f))
            .sum::<Vector>()
            .normalize()
    }

    /// Angle-weighted vertex normals (Thürmer–Wüthrich): each face contributes its
    /// normal times its interior angle at the vertex.
    pub fn vertex_normals(&self) -> Vec<Vector> {
        let face_normals = self.face_normals();
        self.par_vertices()
            .map(|v| {
                let sum: Vector = self
                    .outgoing(v)
                    .filter(|&h| !self.is_boundary_halfedge(h))
                    .map(|h| {
                        // Angle at v between h and the incoming halfedge prev(h).
                        let angle = self.opposite_angle(self.next(h));
                        face_normals[self.face(h).idx()] * angle
                    })
                    .sum();
                sum.normalize()
            })
            .collect()
    }

    /// Signed dihedral angle φ_e of an interior edge (Hildebrandt et al. §3): the
    /// angle between the two face normals, positive where the surface is convex
    /// across `e`, zero on flat and boundary edges.
    /// φ = atan2(⟨N1 × N2, ê⟩, ⟨N1, N2⟩) with ê the unit vector of halfedge `2e`
    /// and N1 the normal of its face.
    pub fn dihedral_angle(&self, e: EdgeId) -> f64 {
        if self.is_boundary_edge(e) {
            return 0.0;
        }
        let h = self.edge_halfedge(e, 0);
        let n1 = self.face_normal(self.face(h));
        let n2 = self.face_normal(self.face(self.twin(h)));
        signed_angle(&n1, &n2, &self.halfedge_vector(h).normalize())
    }

    /// Cotan weight w_e = ½ (cot α + cot β) of the angles opposite `e` (one term on a
    /// boundary edge). Negative where α + β > π; callers decide whether to clamp.
    pub fn cotan_weight(&self, e: EdgeId) -> f64 {
        [self.edge_halfedge(e, 0), self.edge_halfedge(e, 1)]
            .into_iter()
            .filter(|&h| !self.is_boundary_halfedge(h))
            .map(|h| {
                let (u, v) = self.opposite_legs(h);
                0.5 * cot(&u, &v)
            })
            .sum()
    }

    /// Cotan weights of all edges.
    pub fn cotan_weights(&self) -> Vec<f64> {
        (0..self.edge_count() as u32)
            .into_par_iter()
            .map(|e| self.cotan_weight(EdgeId(e)))
            .collect()
    }

    /// [`Mesh::cotan_weight`] clamped to [0, `MAX_COTAN_WEIGHT`] (NaN, from a
    /// degenerate triangle, gives 0): with these weights the cotan Laplacian is
    /// positive semi-definite on any mesh, with or without boundary, however
    /// obtuse its triangles (Hildebrandt et al. §5.1).
    pub fn clamped_cotan_weight(&self, e: EdgeId) -> f64 {
        let w = self.cotan_weight(e);
        if w.is_nan() {
            return 0.0;
        }
        w.clamp(0.0, MAX_COTAN_WEIGHT)
    }

    /// Clamped cotan weights of all edges ([`Mesh::clamped_cotan_weight`]).
    pub fn clamped_cotan_weights(&self) -> Vec<f64> {
        (0..self.edge_count() as u32)
            .into_par_iter()
            .map(|e| self.clamped_cotan_weight(EdgeId(e)))
            .collect()
    }

    /// A copy of the mesh with every position multiplied by `factor` (same
    /// connectivity and vertex properties).
    pub fn scaled(&self, factor: f64) -> Mesh {
        let mut copy = self.clone();
        copy.scale(factor);
        copy
    }

    /// Multiply every position by `factor`.
    pub fn scale(&mut self, factor: f64) {
        for p in &mut self.positions {
            *p *= factor;
        }
    }

    /// The mesh in a frame where areas, angles and curvatures neither overflow nor
    /// underflow, and the factor its coordinates were multiplied by: the mesh itself
    /// (factor 1) when its largest absolute coordinate lies within 2^±100, else a
    /// copy scaled by a power of two into the unit frame (largest coordinate in
    /// [½, 1), `unit_scale`). Scaling by a power of two is exact, so results on
    /// either are the same up to the factor: lengths of the input are those of the
    /// frame divided by the factor, curvatures multiplied by it.
    pub fn in_unit_frame(&self) -> (Cow<'_, Mesh>, f64) {
        let factor = unit_scale(&self.positions);
        if (power_of_two(-100)..=power_of_two(100)).contains(&factor) {
            return (Cow::Borrowed(self), 1.0);
        }
        (Cow::Owned(self.scaled(factor)), factor)
    }

    /// Lumped (barycentric) mass of every vertex: area(star(v)) / 3.
    pub fn vertex_areas(&self) -> Vec<f64> {
        let mut mass = vec![0.0; self.vertex_count()];
        for (f, area) in self.face_areas().into_iter().enumerate() {
            for v in self.face_vertices(FaceId(f as u32)) {
                mass[v.idx()] += area / 3.0;
            }
        }
        mass
    }

    /// Axis-aligned bounding box of the vertices.
    pub fn bounding_box(&self) -> BoundingBox {
        let first = self.positions()[0];
        let (min, max) = self
            .positions()
            .iter()
            .fold((first, first), |(lo, hi), p| (lo.inf(p), hi.sup(p)));
        BoundingBox { min, max }
    }

    /// Parallel iterator over faces.
    pub fn par_faces(&self) -> impl IndexedParallelIterator<Item = FaceId> + '_ {
        (0..self.face_count() as u32).into_par_iter().map(FaceId)
    }

    /// Parallel iterator over vertices.
    pub fn par_vertices(&self) -> impl IndexedParallelIterator<Item = VertexId> + '_ {
        (0..self.vertex_count() as u32)
            .into_par_iter()
            .map(VertexId)
    }
}
