//! Curvature from a local least-squares fit of a quartic height function (a 4-jet,
//! in the manner of Cazals and Pouget, "Estimating differential quantities using
//! polynomial fitting of osculating jets", 2003).

use nalgebra::{Matrix3, SMatrix, SVector};
use rayon::prelude::*;

use crate::mesh::{Mesh, VertexId};
use crate::{Result, Vector};

use crate::differential::{isosurface_curvature, ThirdOrder};

use super::{tangent_basis, CurvatureEstimator, CurvatureField};

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
/// triangulation's regularity, unlike the discrete shape operator.
///
/// The fit also gives the extremalities e_max = ∇k_max · d_max and e_min =
/// ∇k_min · d_min from its third-order terms ([`CurvatureField::extremality`];
/// Hildebrandt, Polthier and Wardetzky 2005, eq. 4, in the smooth setting), O(h)
/// accurate where differentiating the curvature across the mesh is not, and the
/// fit's residual ([`CurvatureField::fit_residual`]), which tells clean data from
/// noise. Estimates are
/// computed in the unit frame ([`Mesh::in_unit_frame`]) and scaled back, and
/// non-finite or outlying ones are flagged and replaced
/// (`super::robust::repair_outliers`).
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
    /// The field of a mesh in the unit frame, before repairs, with the
    /// extremalities of the fitted height functions ([`fit_vertex`]). Where a fit
    /// has no third-order terms (a quadric, from fewer than 10 points) the
    /// extremality is taken from the vertex's neighbours ([`super::robust::fill_extremality`]).
    fn estimate_unit(&self, mesh: &Mesh) -> CurvatureField {
        let normals = area_weighted_normals(mesh);
        let fits: Vec<VertexFit> = mesh
            .par_vertices()
            .map(|v| self.fit_at(mesh, v, &normals[v.idx()]))
            .collect();
        let mut field = CurvatureField::from_fn(mesh.vertex_count(), |v| {
            let fit = &fits[v.idx()];
            let unreliable = !fit.fitted || mesh.is_boundary_vertex(v);
            (fit.curvature, fit.normal, unreliable)
        });
        let known: Vec<bool> = fits.iter().map(|f| f.extremality.is_some()).collect();
        let extremality = [0, 1].map(|i| {
            fits.iter()
                .map(|f| f.extremality.map_or(0.0, |e| e[i]))
                .collect::<Vec<f64>>()
        });
        field.extremality = Some(extremality);
        field.fit_residual = Some(fits.iter().map(|f| f.residual).collect());
        super::robust::fill_extremality(mesh, &mut field, &known);
        field
    }

    /// The median fit residual ([`CurvatureField::fit_residual`]) over at most
    /// `count` vertices of `mesh` spread evenly through its numbering: a cheap
    /// reading of whether the mesh is clean (near 0) or noisy, from a few fits.
    /// `None` if no vertex could be fitted. The residual is relative to the fit's
    /// radius, so the mesh's scale does not matter.
    pub fn median_residual(&self, mesh: &Mesh, count: usize) -> Option<f64> {
        let n = mesh.vertex_count();
        let step = n.div_ceil(count.max(1)).max(1);
        let mut residuals: Vec<f64> = (0..n)
            .into_par_iter()
            .step_by(step)
            .filter_map(|v| {
                let v = VertexId(v as u32);
                let fit = self.fit_at(mesh, v, &mesh.area_weighted_normal(v));
                fit.fitted.then_some(fit.residual)
            })
            .filter(|r| r.is_finite())
            .collect();
        residuals.sort_by(f64::total_cmp);
        residuals.get(residuals.len() / 2).copied()
    }

    /// The fit at `v` in the frame of `normal` ([`fit_vertex`]) to the points
    /// [`JetFit::fit_points`] gathers, with this thread's buffers.
    fn fit_at(&self, mesh: &Mesh, v: VertexId, normal: &Vector) -> VertexFit {
        GATHERER.with_borrow_mut(|gatherer| {
            let points = gatherer.gather(self, mesh, v);
            LOCAL.with_borrow_mut(|local| fit_vertex(mesh, v, normal, points, local))
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

/// What one vertex's fit gives.
struct VertexFit {
    /// Principal curvatures and directions of the fitted graph.
    curvature: super::PrincipalCurvatures,
    /// The fitted graph's unit normal.
    normal: Vector,
    /// Whether a fit was possible.
    fitted: bool,
    /// `[e_max, e_min]` of the fitted graph, if the fit had third-order terms.
    extremality: Option<[f64; 2]>,
    /// The fit's residual relative to the radius of its points
    /// ([`CurvatureField::fit_residual`]).
    residual: f64,
}

/// Fit a height function over the tangent plane of `normal` at `v` and return the
/// curvature of its graph at the vertex, the graph's normal, whether a fit was
/// possible and, if the fit has third-order terms, the extremalities. `local` is
/// scratch space for the points in the local frame.
///
/// The graph z = f(x, y) is the level set f(x, y) − z = 0 of a function whose
/// derivatives are those of the fit, so curvature and extremalities follow from
/// [`isosurface_curvature`]: in the Monge frame (x along d_max, y along d_min,
/// where f_x = f_y = 0) with the outward normal along +z, k = −f_xx and e_max =
/// ∂k_max/∂x = −f_xxx, e_min = −f_yyy. In the notation of the Monge form
/// ½(k1 x² + k2 y²) + (1/6)(b0 x³ + 3 b1 x² y + 3 b2 x y² + b3 y³) of the height
/// along the inward normal (so that a convex surface has k1, k2 > 0, as here),
/// e_max = b0 and e_min = b3. Away from the Monge frame (the fit is made in the
/// frame of the area-weighted normal) the closed form also accounts for the tilt
/// of the fitted normal. This is the
/// smooth counterpart of the extremality of Hildebrandt, Polthier and Wardetzky
/// (2005), eq. 4, read off the fitted jet as in Cazals and Pouget (2005).
fn fit_vertex(
    mesh: &Mesh,
    v: VertexId,
    normal: &Vector,
    points: &[VertexId],
    local: &mut Vec<Vector>,
) -> VertexFit {
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
    let flat = |normal: &Vector| VertexFit {
        curvature: super::PrincipalCurvatures::from_tangent_operator(&Matrix3::zeros(), normal),
        normal: *normal,
        fitted: false,
        extremality: None,
        residual: 0.0,
    };
    let Some(Jet {
        derivatives: d,
        third_order,
        residual,
    }) = derivatives
    else {
        return flat(normal);
    };
    // Back to unscaled units: first derivatives keep, the k-th divide by scale^(k−1).
    let [fx, fy, fxx, fxy, fyy, fxxx, fxxy, fxyy, fyyy] = [
        d[0],
        d[1],
        d[2] / scale,
        d[3] / scale,
        d[4] / scale,
        d[5] / (scale * scale),
        d[6] / (scale * scale),
        d[7] / (scale * scale),
        d[8] / (scale * scale),
    ];
    // The level set f(x, y) − z = 0 of the fitted graph, "inside" below it: its
    // outward normal points up, along the vertex normal.
    let gradient = Vector::new(fx, fy, -1.0);
    let hessian = Matrix3::new(fxx, fxy, 0.0, fxy, fyy, 0.0, 0.0, 0.0, 0.0);
    let third = ThirdOrder::from_components([fxxx, fxxy, 0.0, fxyy, 0.0, 0.0, fyyy, 0.0, 0.0, 0.0]);
    let Some(iso) = isosurface_curvature(&gradient, &hessian, &third) else {
        return flat(normal);
    };
    let to_world = |d: Vector| t1 * d.x + t2 * d.y + normal * d.z;
    let k = iso.principal;
    VertexFit {
        curvature: super::PrincipalCurvatures {
            d_max: to_world(k.d_max),
            d_min: to_world(k.d_min),
            ..k
        },
        normal: to_world(iso.normal),
        fitted: true,
        extremality: third_order.then_some([iso.e_max, iso.e_min]),
        // Both the residual and the coordinates were divided by the scale.
        residual,
    }
}

/// The monomials 1, x, y, x², xy, y², x³, x²y, xy², y³, x⁴, x³y, x²y², xy³, y⁴.
fn monomials(x: f64, y: f64) -> [f64; QUARTIC] {
    let (xx, xy, yy) = (x * x, x * y, y * y);
    [
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
    ]
}

/// A fitted height function at the origin.
struct Jet {
    /// (f_x, f_y, f_xx, f_xy, f_yy, f_xxx, f_xxy, f_xyy, f_yyy).
    derivatives: [f64; 9],
    /// Whether the fit has third-order terms (a quadric's third derivatives are 0).
    third_order: bool,
    /// The root mean square distance (in z) of the points from the fitted graph,
    /// over the degrees of freedom left (points − coefficients; 0 if none).
    residual: f64,
}

/// Least-squares fit of z over the first `N` [`monomials`]; `None` if the points
/// do not determine the fit.
fn fit<const N: usize>(points: &[Vector]) -> Option<Jet> {
    if points.len() < N {
        return None;
    }
    let mut normal_matrix = SMatrix::<f64, N, N>::zeros();
    let mut rhs = SVector::<f64, N>::zeros();
    for p in points {
        let all = monomials(p.x, p.y);
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
    let squares: f64 = points
        .iter()
        .map(|p| {
            let all = monomials(p.x, p.y);
            let z: f64 = (0..N).map(|i| c[i] * all[i]).sum();
            (p.z - z).powi(2)
        })
        .sum();
    let freedom = points.len() - N;
    let residual = if freedom > 0 {
        (squares / freedom as f64).sqrt()
    } else {
        0.0
    };
    let third = |i: usize, factor: f64| if i < N { factor * c[i] } else { 0.0 };
    Some(Jet {
        derivatives: [
            c[1],
            c[2],
            2.0 * c[3],
            c[4],
            2.0 * c[5],
            third(6, 6.0),
            third(7, 2.0),
            third(8, 2.0),
            third(9, 6.0),
        ],
        third_order: N >= CUBIC,
        residual,
    })
}
