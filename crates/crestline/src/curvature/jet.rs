//! Curvature from a local least-squares fit of a quartic height function (a 4-jet,
//! in the manner of Cazals and Pouget, "Estimating differential quantities using
//! polynomial fitting of osculating jets", 2003).

use nalgebra::{Matrix3, SMatrix, SVector};
use rayon::prelude::*;

use crate::mesh::{Mesh, VertexId};
use crate::{Result, Vector};

use super::{implicit_curvature, tangent_basis, CurvatureEstimator, CurvatureField};

/// Fits z = f(x, y), a polynomial of degree 4 (unweighted least squares), to the
/// vertices of a neighbourhood of rings around each vertex, in the frame of the
/// vertex's area-weighted normal, and takes the curvature of the fitted graph at the
/// vertex. The neighbourhood grows ring by ring until it holds `min_points` vertices
/// (or `max_rings` rings); where fewer than 15 points are found (or they do not
/// determine the quartic), a cubic (10 points) or a quadric (6 points) is fitted,
/// and with fewer than 6 the vertex is flagged unreliable.
///
/// Bounded work: gathering costs time linear in the size of the rings gathered
/// (each vertex is marked when found), and a fit uses at most `max_points` of
/// them (or `min_points`, if larger): the inner rings whole and, from the last
/// ring, points evenly spaced in its order, so a vertex of valence 10,000 costs a
/// pass over its ring and one small fit.
///
/// Error on a smooth surface sampled with spacing h is O(h²), independent of the
/// triangulation's regularity, unlike the discrete shape operator. Estimates are
/// computed in the unit frame ([`Mesh::in_unit_frame`]) and scaled back, and
/// non-finite or outlying ones are flagged and replaced
/// ([`super::robust::repair_outliers`]).
#[derive(Clone, Copy, Debug)]
pub struct JetFit {
    /// Smallest number of vertices to fit to (the vertex itself included).
    pub min_points: usize,
    /// Largest number of vertices one fit uses.
    pub max_points: usize,
    /// Largest number of rings to gather.
    pub max_rings: usize,
}

impl Default for JetFit {
    fn default() -> Self {
        JetFit {
            min_points: 18,
            max_points: 60,
            max_rings: 4,
        }
    }
}

impl CurvatureEstimator for JetFit {
    fn estimate(&self, mesh: &Mesh) -> Result<CurvatureField> {
        Ok(super::robust::estimate_robustly(mesh, |unit| {
            self.estimate_unit(unit)
        }))
    }
}

thread_local! {
    static GATHERER: std::cell::RefCell<Gatherer> = std::cell::RefCell::new(Gatherer::default());
    /// The fit points of one vertex in its local frame, reused from vertex to vertex.
    static LOCAL: std::cell::RefCell<Vec<Vector>> = const { std::cell::RefCell::new(Vec::new()) };
}

impl JetFit {
    /// The field of a mesh in the unit frame, before repairs.
    fn estimate_unit(&self, mesh: &Mesh) -> CurvatureField {
        let normals = area_weighted_normals(mesh);
        CurvatureField::from_fn(mesh.vertex_count(), |v| {
            GATHERER.with_borrow_mut(|gatherer| {
                let points = gatherer.gather(self, mesh, v);
                let (k, normal, fitted) = LOCAL
                    .with_borrow_mut(|local| fit_vertex(mesh, v, &normals[v.idx()], points, local));
                (k, normal, !fitted || mesh.is_boundary_vertex(v))
            })
        })
    }

    /// The vertices the fit at `v` uses, `v` first: the smallest ring neighbourhood
    /// with at least `min_points` vertices (or `max_rings` rings), its last ring
    /// thinned so that at most `max_points` (or `min_points`) remain.
    pub fn fit_points(&self, mesh: &Mesh, v: VertexId) -> Vec<VertexId> {
        GATHERER.with_borrow_mut(|gatherer| gatherer.gather(self, mesh, v).to_vec())
    }

    /// The most points one fit uses.
    fn point_cap(&self) -> usize {
        self.max_points.max(self.min_points)
    }
}

/// Gathers ring neighbourhoods with a per-vertex marker: a vertex is found when
/// its stamp equals the current generation, so a gather costs time linear in what
/// it visits and needs no clearing.
#[derive(Default)]
struct Gatherer {
    found: Vec<VertexId>,
    stamp: Vec<u32>,
    generation: u32,
}

impl Gatherer {
    /// The fit points of `v` (see [`JetFit::fit_points`]).
    fn gather(&mut self, jet: &JetFit, mesh: &Mesh, v: VertexId) -> &[VertexId] {
        self.start(mesh.vertex_count());
        self.visit(v);
        let mut ring_start = 0;
        for _ in 0..jet.max_rings {
            let ring_end = self.found.len();
            for i in ring_start..ring_end {
                for w in mesh.neighbors(self.found[i]) {
                    self.visit(w);
                }
            }
            ring_start = ring_end;
            if self.found.len() >= jet.min_points || self.found.len() == ring_end {
                break;
            }
        }
        thin_last_ring(&mut self.found, ring_start, jet.point_cap());
        &self.found
    }

    /// Forget the last gather: a new generation (stamps reset when it wraps).
    fn start(&mut self, vertex_count: usize) {
        self.found.clear();
        if self.stamp.len() != vertex_count || self.generation == u32::MAX {
            self.stamp.clear();
            self.stamp.resize(vertex_count, 0);
            self.generation = 0;
        }
        self.generation += 1;
    }

    /// Add `w` unless this gather found it already.
    fn visit(&mut self, w: VertexId) {
        let stamp = &mut self.stamp[w.idx()];
        if *stamp != self.generation {
            *stamp = self.generation;
            self.found.push(w);
        }
    }
}

/// Keep at most `cap` points: those before `last_ring` (fewer than the cap, since
/// gathering stopped at the first ring that reached `min_points`) and points of
/// the last ring at evenly spaced positions in its order, which keeps them spread
/// around the vertex.
fn thin_last_ring(found: &mut Vec<VertexId>, last_ring: usize, cap: usize) {
    if found.len() <= cap || last_ring >= cap {
        found.truncate(cap.max(last_ring));
        return;
    }
    let (room, ring) = (cap - last_ring, found.len() - last_ring);
    for i in 0..room {
        found[last_ring + i] = found[last_ring + i * ring / room];
    }
    found.truncate(cap);
}

/// Unit normals from the sum of the area vectors of the faces around each vertex.
fn area_weighted_normals(mesh: &Mesh) -> Vec<Vector> {
    mesh.par_vertices()
        .map(|v| mesh.area_weighted_normal(v))
        .collect()
}

/// Number of monomials of degree ≤ 4, ≤ 3 and ≤ 2 in (x, y): the columns of a fit.
const QUARTIC: usize = 15;
const CUBIC: usize = 10;
const QUADRIC: usize = 6;

/// Fit a height function over the tangent plane of `normal` at `v` and return the
/// curvature of its graph at the vertex, the graph's normal, and whether a fit
/// was possible. `local` is scratch space for the points in the local frame.
fn fit_vertex(
    mesh: &Mesh,
    v: VertexId,
    normal: &Vector,
    points: &[VertexId],
    local: &mut Vec<Vector>,
) -> (super::PrincipalCurvatures, Vector, bool) {
    let origin = mesh.position(v);
    let (t1, t2) = tangent_basis(normal);
    local.clear();
    local.extend(points.iter().map(|&w| {
        let d = mesh.position(w) - origin;
        Vector::new(d.dot(&t1), d.dot(&t2), d.dot(normal))
    }));
    // Scale to unit radius so the normal equations are well conditioned.
    let scale = local.iter().map(|p| p.xy().norm()).fold(0.0, f64::max);
    let derivatives = if scale > 0.0 {
        for p in local.iter_mut() {
            *p /= scale;
        }
        fit::<QUARTIC>(local)
            .or_else(|| fit::<CUBIC>(local))
            .or_else(|| fit::<QUADRIC>(local))
    } else {
        None
    };
    let Some([fx, fy, fxx, fxy, fyy]) = derivatives else {
        let flat = super::PrincipalCurvatures::from_tangent_operator(&Matrix3::zeros(), normal);
        return (flat, *normal, false);
    };
    // Back to unscaled units: first derivatives keep, second divide by the scale.
    let (fxx, fxy, fyy) = (fxx / scale, fxy / scale, fyy / scale);
    // The graph z = f(x, y) is the implicit surface F = z − f = 0, normal upwards.
    let gradient = Vector::new(-fx, -fy, 1.0);
    let hessian = -Matrix3::new(fxx, fxy, 0.0, fxy, fyy, 0.0, 0.0, 0.0, 0.0);
    let (k, n) = implicit_curvature(&gradient, &hessian);
    let to_world = |d: Vector| t1 * d.x + t2 * d.y + normal * d.z;
    let curvature = super::PrincipalCurvatures {
        d_max: to_world(k.d_max),
        d_min: to_world(k.d_min),
        ..k
    };
    (curvature, to_world(n), true)
}

/// Least-squares fit of z over the first `N` monomials 1, x, y, x², xy, y², x³,
/// x²y, xy², y³, x⁴, x³y, x²y², xy³, y⁴; returns (f_x, f_y, f_xx, f_xy, f_yy) at the origin, or `None` if
/// the points do not determine the fit.
fn fit<const N: usize>(points: &[Vector]) -> Option<[f64; 5]> {
    if points.len() < N {
        return None;
    }
    let mut normal_matrix = SMatrix::<f64, N, N>::zeros();
    let mut rhs = SVector::<f64, N>::zeros();
    for p in points {
        let (x, y) = (p.x, p.y);
        let (xx, xy, yy) = (x * x, x * y, y * y);
        let all = [
            1.0,
            x,
            y,
            xx,
            xy,
            yy,
            xx * x,
            xx * y,
            x * yy,
            yy * y,
            xx * xx,
            xx * xy,
            xx * yy,
            xy * yy,
            yy * yy,
        ];
        let row = SVector::<f64, N>::from_fn(|i, _| all[i]);
        // The lower triangle only: the Cholesky factorization reads no more.
        normal_matrix.syger(1.0, &row, &row, 1.0);
        rhs += row * p.z;
    }
    let c = normal_matrix.cholesky()?.solve(&rhs);
    // Reject near-singular systems (points on a curve, not spread over the plane).
    if !c.iter().all(|x| x.is_finite()) {
        return None;
    }
    Some([c[1], c[2], 2.0 * c[3], c[4], 2.0 * c[5]])
}
