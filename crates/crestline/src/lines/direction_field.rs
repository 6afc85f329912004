//! Sign-ambiguous direction fields on a surface (principal directions), and the
//! signs σ_pq that relate the direction at one vertex to its neighbour's.
//!
//! Hildebrandt, Polthier and Wardetzky (2005, §4.1) set σ_pq = sign⟨d(p), d(q)⟩.
//! The two directions lie in different tangent planes, and where the surface
//! bends sharply between p and q (the creases where ridges run) that inner
//! product can have the wrong sign: across a fold of 120°, the two directions
//! across the fold meet at 120° although each is the other turned with the
//! surface. Here d(q) is first carried into the tangent plane of p by the
//! smallest rotation taking n(q) to n(p) (the discrete Levi-Civita transport of
//! the edge), so σ_pq tells whether the directions agree as the surface sees
//! them. The transport commutes with n × ·, so for principal directions
//! (d_min = ±n × d_max) the two fields' signs are equal up to a per-vertex sign
//! ([`gauge_between`]): their smoothing systems are one matrix.

use rayon::prelude::*;

use crate::mesh::{EdgeId, Mesh};
use crate::Vector;

/// A direction per vertex, defined up to sign, tangent to the surface whose unit
/// normal at that vertex is `normals`.
#[derive(Clone, Copy, Debug)]
pub struct DirectionField<'a> {
    /// The directions (any sign).
    pub directions: &'a [Vector],
    /// The surface normals the directions are tangent to.
    pub normals: &'a [Vector],
}

impl<'a> DirectionField<'a> {
    /// The field of `directions` tangent to the surface of `normals` (one each per
    /// vertex).
    pub fn new(directions: &'a [Vector], normals: &'a [Vector]) -> DirectionField<'a> {
        debug_assert_eq!(directions.len(), normals.len());
        DirectionField {
            directions,
            normals,
        }
    }

    /// The direction at vertex `v`.
    pub fn at(&self, v: usize) -> Vector {
        self.directions[v]
    }

    /// σ_pq = sign⟨d(p), R_pq d(q)⟩ (+1 for orthogonal directions), R_pq the
    /// smallest rotation taking n(q) to n(p): the sign that carries a value given
    /// relative to d(q) into the frame of d(p). Symmetric in p and q. Where a
    /// normal is zero, d(q) is compared as it is.
    pub fn sign(&self, p: usize, q: usize) -> f64 {
        sign_of(self.alignment(p, q))
    }

    /// ⟨d(p), R_pq d(q)⟩, whose sign is [`sign`](Self::sign)'s.
    fn alignment(&self, p: usize, q: usize) -> f64 {
        // One evaluation order for both (p, q) and (q, p), so that rounding
        // cannot make the sign asymmetric.
        let (p, q) = (p.min(q), p.max(q));
        let transported = transport(self.normals[q], self.normals[p], self.directions[q]);
        self.directions[p].dot(&transported)
    }
}

/// The sign σ_pq ([`DirectionField::sign`]) of every edge of a mesh for one
/// direction field, transported once: the smoothing matrix, the zero set's
/// crossings and the faces' regularity and feature tests all read it (they
/// transported each of the Stanford dragon's edges about eleven times).
#[derive(Clone, Debug)]
pub struct EdgeSigns(Vec<i8>);

/// What [`EdgeSigns`] stores of an edge whose alignment is a tie ([`TIE`]), times
/// its sign; other edges store their sign.
const TIED: i8 = 2;

impl EdgeSigns {
    /// σ of every edge of `mesh` for the directions `d`, in parallel.
    pub fn new(mesh: &Mesh, d: DirectionField) -> EdgeSigns {
        let signs = (0..mesh.edge_count() as u32)
            .into_par_iter()
            .map(|e| {
                let [p, q] = mesh.edge_vertices(EdgeId(e)).map(|v| v.idx());
                let alignment = d.alignment(p, q);
                let sign = sign_of(alignment) as i8;
                if alignment.abs() <= TIE {
                    sign * TIED
                } else {
                    sign
                }
            })
            .collect();
        EdgeSigns(signs)
    }

    /// σ = +1 on every edge of `mesh`: the signs of a field with no sign
    /// ambiguity (a scalar or tensor field's entries).
    pub fn positive(mesh: &Mesh) -> EdgeSigns {
        EdgeSigns(vec![1; mesh.edge_count()])
    }

    /// σ of edge `e` (±1).
    pub fn sign(&self, e: EdgeId) -> f64 {
        f64::from(self.0[e.idx()].signum())
    }

    /// Whether the directions' alignment on edge `e` is a tie ([`TIE`]): its
    /// sign is rounding.
    fn is_tie(&self, e: EdgeId) -> bool {
        self.0[e.idx()].abs() == TIED
    }
}

/// Alignments ([`DirectionField::sign`]) of unit directions this close to zero
/// are ties, their sign is rounding: principal directions at two vertices of the
/// dragon ×4 met at 10⁻¹⁷ on 2 of its 5.2M edges.
const TIE: f64 = 1e-9;

/// `v` turned by the smallest rotation taking the direction of `from` to that of
/// `to` (Rodrigues' formula with axis `from × to`); where the two are opposite,
/// by a half turn about an axis normal to `from` chosen from `from` alone, so
/// that every field is carried alike (one edge of the dragon ×16 joins opposite
/// normals); `v` itself where one of them is zero.
fn transport(from: Vector, to: Vector, v: Vector) -> Vector {
    let (Some(from), Some(to)) = (from.try_normalize(0.0), to.try_normalize(0.0)) else {
        return v;
    };
    let cos = from.dot(&to);
    if cos.is_nan() {
        return v;
    }
    if cos <= -1.0 + OPPOSITE {
        let axis = half_turn_axis(from);
        return axis * (2.0 * axis.dot(&v)) - v;
    }
    let axis = from.cross(&to);
    v * cos + axis.cross(&v) + axis * (axis.dot(&v) / (1.0 + cos))
}

/// Unit normals whose inner product is within this of −1 are opposite: Rodrigues'
/// formula divides by 1 + cos.
const OPPOSITE: f64 = 1e-6;

/// A unit axis normal to the unit vector `n`: n × e, e the coordinate axis least
/// aligned with n.
fn half_turn_axis(n: Vector) -> Vector {
    let k = n.iamin();
    n.cross(&Vector::ith(k, 1.0)).normalize()
}

/// +1 for `x` ≥ 0, else −1.
fn sign_of(x: f64) -> f64 {
    if x >= 0.0 {
        1.0
    } else {
        -1.0
    }
}

/// The per-vertex signs g (±1) with σ^b_pq = g_p g_q σ^a_pq on every edge of
/// `mesh` but ties ([`TIE`]), taking b's direction at p as g_p n(p) × a's, if
/// such signs exist: always for principal directions with one normal field
/// (d_min = ±n × d_max, and the transport commutes with n × ·). A value v
/// relative to b is then g_p v relative to n × a, and the smoothing system of a
/// serves b ([`crate::ridges`]). `None` otherwise. Each field comes with its
/// edges' signs.
pub fn gauge_between(
    mesh: &Mesh,
    (a, a_signs): (DirectionField, &EdgeSigns),
    (b, b_signs): (DirectionField, &EdgeSigns),
) -> Option<Vec<f64>> {
    let gauge: Vec<f64> = (0..a.directions.len())
        .into_par_iter()
        .map(|p| sign_of(b.at(p).dot(&a.normals[p].cross(&a.at(p)))))
        .collect();
    let agree = (0..mesh.edge_count() as u32).into_par_iter().all(|e| {
        let e = EdgeId(e);
        let [p, q] = mesh.edge_vertices(e).map(|v| v.idx());
        a_signs.is_tie(e)
            || b_signs.is_tie(e)
            || a_signs.sign(e) * b_signs.sign(e) == gauge[p] * gauge[q]
    });
    agree.then_some(gauge)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two vertices on either side of a fold: the plane z = 0 (normal +z) and a
    /// plane turned by `fold` about the x axis, each with the direction across the
    /// fold (perpendicular to the x axis) pointing away from it.
    fn across_fold(fold: f64) -> ([Vector; 2], [Vector; 2]) {
        let (s, c) = fold.sin_cos();
        let normals = [Vector::z(), Vector::new(0.0, -s, c)];
        // Away from the fold on the first side is −y; on the turned side it is
        // the turned +y, i.e. (0, c, s).
        let directions = [-Vector::y(), Vector::new(0.0, c, s)];
        (directions, normals)
    }

    #[test]
    fn directions_across_a_sharp_fold_agree_once_transported() {
        // Seen from the surface, −y on one side and (0, c, s) on the other point
        // opposite ways across the fold, whatever the fold's angle: σ = −1. The
        // plain inner product −c says so only while the fold is under 90°.
        for degrees in [10.0_f64, 60.0, 89.0, 100.0, 120.0, 160.0] {
            let (d, n) = across_fold(degrees.to_radians());
            let field = DirectionField::new(&d, &n);
            assert_eq!(field.sign(0, 1), -1.0, "fold of {degrees}°");
            assert_eq!(field.sign(1, 0), -1.0, "fold of {degrees}°");
            let plain = d[0].dot(&d[1]).signum();
            assert_eq!(plain < 0.0, degrees < 90.0, "fold of {degrees}°");
        }
    }

    #[test]
    fn directions_along_a_fold_on_a_plane_and_across_opposite_normals() {
        // Along the fold's axis the rotation leaves a direction unchanged.
        let (_, n) = across_fold(2.0);
        let d = [Vector::x(), -Vector::x()];
        assert_eq!(DirectionField::new(&d, &n).sign(0, 1), -1.0);
        // On a plane, transport is the identity.
        let n = [Vector::z(), Vector::z() * 3.0];
        let d = [Vector::new(1.0, 0.2, 0.0), Vector::new(0.3, 1.0, 0.0)];
        assert_eq!(DirectionField::new(&d, &n).sign(0, 1), 1.0);
        // Unusable normals: compared as they are.
        let n = [Vector::zeros(), Vector::z()];
        assert_eq!(DirectionField::new(&d, &n).sign(1, 0), 1.0);
        // Opposite normals: a half turn, the same for every field, so that a
        // direction and its normal's cross product with it keep one sign.
        let n = [Vector::new(0.3, 0.1, 1.0), -Vector::new(0.3, 0.1, 1.0)];
        for angle in [0.0_f64, 0.7, 1.9, 3.0] {
            let t = Vector::new(angle.cos(), angle.sin(), 0.0);
            let d = [n[0].cross(&t), n[1].cross(&Vector::new(0.2, 1.0, 0.4))];
            let turned = [n[0].cross(&d[0]), n[1].cross(&d[1])];
            assert_eq!(
                DirectionField::new(&d, &n).sign(0, 1),
                DirectionField::new(&turned, &n).sign(0, 1),
                "angle {angle}"
            );
        }
    }

    /// The unit square of two triangles in the plane z = 0
    /// ([`unit_square`](crate::lines::test_meshes::unit_square)), and the mesh
    /// edge joining vertices `a` and `b`.
    fn square() -> (Mesh, impl Fn(u32, u32) -> EdgeId) {
        let mesh = crate::lines::test_meshes::unit_square();
        let ends: Vec<[u32; 2]> = (0..mesh.edge_count() as u32)
            .map(|e| mesh.edge_vertices(EdgeId(e)).map(|v| v.0))
            .collect();
        let edge = move |a: u32, b: u32| {
            let e = ends
                .iter()
                .position(|&[p, q]| (p, q) == (a, b) || (p, q) == (b, a));
            EdgeId(e.expect("an edge of the square") as u32)
        };
        (mesh, edge)
    }

    #[test]
    fn edge_signs_mark_ties_and_the_gauge_ignores_them() {
        let (mesh, edge) = square();
        let normals = [Vector::z(); 4];
        // Vertex 2's direction is orthogonal to the others': its three edges tie.
        let a = [Vector::x(), -Vector::x(), Vector::y(), Vector::x()];
        let signs = EdgeSigns::new(&mesh, DirectionField::new(&a, &normals));
        assert_eq!(signs.sign(edge(0, 1)), -1.0);
        assert_eq!(signs.sign(edge(0, 3)), 1.0);
        assert!(!signs.is_tie(edge(0, 1)) && !signs.is_tie(edge(0, 3)));
        for other in [0, 1, 3] {
            assert!(signs.is_tie(edge(2, other)), "edge 2–{other}");
            assert_eq!(signs.sign(edge(2, other)).abs(), 1.0);
        }
        // b = g n × a with g = (1, −1, ·, 1), except at vertex 2, whose
        // direction is a's own (g_2 = +1, a tie itself): on edge 1–2 σ^b = +1
        // contradicts g_1 g_2 σ^a = −1, but a ties there, so the edge is ignored.
        let b = [Vector::y(), Vector::y(), Vector::y(), Vector::y()];
        let b_signs = EdgeSigns::new(&mesh, DirectionField::new(&b, &normals));
        assert_eq!(b_signs.sign(edge(0, 1)), 1.0);
        let gauge = gauge_between(
            &mesh,
            (DirectionField::new(&a, &normals), &signs),
            (DirectionField::new(&b, &normals), &b_signs),
        )
        .expect("the edges that disagree are ties");
        assert_eq!([gauge[0], gauge[1], gauge[3]], [1.0, -1.0, 1.0]);
    }
}
