//! Analytic test surfaces with their exact principal curvatures: sphere, ellipsoid,
//! torus and height fields z = f(x, y), each on a regular or a jittered
//! (irregular) triangulation. Every vertex lies exactly on the surface (up to
//! rounding), and [`AnalyticMesh::exact`] holds the exact curvature at each vertex,
//! so estimators can be measured against the truth.
//!
//! Exact curvatures come from an implicit description F(p) = 0 with outward normal
//! ∇F/|∇F|: the shape operator is W = P H P / |∇F| with H the Hessian of F and
//! P = I − n nᵀ, restricted to the tangent plane.

use std::collections::HashMap;

use nalgebra::{Matrix3, Point2};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use spade::{DelaunayTriangulation, Triangulation};

use super::{Mesh, TriangleSoup};
use crate::differential::{implicit_curvature, tangent_basis, PrincipalCurvatures};
use crate::{Point, Result, Vector};

/// How the vertices of a generated surface are placed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Sampling {
    /// A regular pattern (geodesic sphere, parameter grid).
    Regular,
    /// The regular pattern with every vertex moved at random along the surface by
    /// up to `amount` (a fraction of the local spacing, below 0.5), reproducibly
    /// from `seed`.
    Jittered {
        /// The largest move, as a fraction of the local spacing (below 0.5).
        amount: f64,
        /// The seed of the random moves.
        seed: u64,
    },
}

impl Sampling {
    /// A jitter of 0.25 spacings: irregular, yet no triangle folds over.
    pub fn jittered(seed: u64) -> Sampling {
        Sampling::Jittered { amount: 0.25, seed }
    }

    fn rng(self) -> Option<(f64, StdRng)> {
        match self {
            Sampling::Regular => None,
            Sampling::Jittered { amount, seed } => Some((amount, StdRng::seed_from_u64(seed))),
        }
    }
}

/// A generated mesh and the exact principal curvatures at its vertices.
#[derive(Clone, Debug)]
pub struct AnalyticMesh {
    /// The triangulated surface.
    pub mesh: Mesh,
    /// Exact curvature per vertex, indexed like the mesh's vertices.
    pub exact: Vec<PrincipalCurvatures>,
}

/// A surface given implicitly as F(p) = 0 with outward normal ∇F/|∇F|.
pub trait ImplicitSurface {
    /// ∇F at `p`.
    fn gradient(&self, p: &Point) -> Vector;
    /// The Hessian of F at `p`.
    fn hessian(&self, p: &Point) -> Matrix3<f64>;

    /// Exact principal curvatures at a point `p` on the surface.
    fn curvature(&self, p: &Point) -> PrincipalCurvatures {
        implicit_curvature(&self.gradient(p), &self.hessian(p)).0
    }
}

/// The ellipsoid x²/a² + y²/b² + z²/c² = 1 (a sphere when all axes are equal).
#[derive(Clone, Copy, Debug)]
pub struct Ellipsoid {
    /// The semi-axes along x, y and z.
    pub axes: [f64; 3],
}

impl ImplicitSurface for Ellipsoid {
    fn gradient(&self, p: &Point) -> Vector {
        Vector::from_fn(|i, _| 2.0 * p[i] / (self.axes[i] * self.axes[i]))
    }

    fn hessian(&self, _p: &Point) -> Matrix3<f64> {
        Matrix3::from_diagonal(&Vector::from_fn(|i, _| 2.0 / (self.axes[i] * self.axes[i])))
    }
}

/// The torus (√(x² + y²) − R)² + z² = r² around the z axis.
#[derive(Clone, Copy, Debug)]
pub struct Torus {
    /// Distance from the centre to the centre of the tube.
    pub major: f64,
    /// Radius of the tube.
    pub minor: f64,
}

impl ImplicitSurface for Torus {
    fn gradient(&self, p: &Point) -> Vector {
        let rho = p.x.hypot(p.y);
        let q = rho - self.major;
        Vector::new(2.0 * q * p.x / rho, 2.0 * q * p.y / rho, 2.0 * p.z)
    }

    fn hessian(&self, p: &Point) -> Matrix3<f64> {
        // F = q² + z² with q = ρ − R: ∂²F = 2 ∇q ∇qᵀ + 2 q ∂²q, ∂²ρ = (I − r̂ r̂ᵀ)/ρ in xy.
        let rho = p.x.hypot(p.y);
        let q = rho - self.major;
        let (ux, uy) = (p.x / rho, p.y / rho);
        let xx = 2.0 * (ux * ux + q * uy * uy / rho);
        let xy = 2.0 * (ux * uy - q * ux * uy / rho);
        let yy = 2.0 * (uy * uy + q * ux * ux / rho);
        Matrix3::new(xx, xy, 0.0, xy, yy, 0.0, 0.0, 0.0, 2.0)
    }
}

/// A height function z = f(x, y) with its derivatives.
pub trait HeightFunction {
    /// f(x, y).
    fn value(&self, x: f64, y: f64) -> f64;
    /// (f_x, f_y).
    fn gradient(&self, x: f64, y: f64) -> [f64; 2];
    /// (f_xx, f_xy, f_yy).
    fn hessian(&self, x: f64, y: f64) -> [f64; 3];
}

/// The graph z = f(x, y) as the implicit surface F = z − f(x, y) (normal upwards).
struct Graph<'a, F: ?Sized>(&'a F);

impl<F: HeightFunction + ?Sized> ImplicitSurface for Graph<'_, F> {
    fn gradient(&self, p: &Point) -> Vector {
        let [fx, fy] = self.0.gradient(p.x, p.y);
        Vector::new(-fx, -fy, 1.0)
    }

    fn hessian(&self, p: &Point) -> Matrix3<f64> {
        let [fxx, fxy, fyy] = self.0.hessian(p.x, p.y);
        -Matrix3::new(fxx, fxy, 0.0, fxy, fyy, 0.0, 0.0, 0.0, 0.0)
    }
}

/// The paraboloid z = (a x² + b y²) / 2: curvatures a and b at the origin (sign
/// convention: a cap opening downwards, a, b < 0, is convex with the upward
/// normal, so its curvatures are −a, −b > 0).
#[derive(Clone, Copy, Debug)]
pub struct Paraboloid {
    /// Coefficient of x².
    pub a: f64,
    /// Coefficient of y².
    pub b: f64,
}

impl HeightFunction for Paraboloid {
    fn value(&self, x: f64, y: f64) -> f64 {
        0.5 * (self.a * x * x + self.b * y * y)
    }

    fn gradient(&self, x: f64, y: f64) -> [f64; 2] {
        [self.a * x, self.b * y]
    }

    fn hessian(&self, _x: f64, _y: f64) -> [f64; 3] {
        [self.a, 0.0, self.b]
    }
}

/// A sphere of `radius` with about `vertices` vertices (a geodesic icosphere).
pub fn sphere(radius: f64, vertices: usize, sampling: Sampling) -> Result<AnalyticMesh> {
    ellipsoid([radius; 3], vertices, sampling)
}

/// The ellipsoid with semi-axes `axes` along x, y, z, with about `vertices` vertices:
/// a geodesic icosphere (jittered on the unit sphere if asked) scaled to the axes.
pub fn ellipsoid(axes: [f64; 3], vertices: usize, sampling: Sampling) -> Result<AnalyticMesh> {
    let (mut unit, triangles, spacing) = icosphere(vertices);
    if let Some((amount, mut rng)) = sampling.rng() {
        for p in &mut unit {
            let (t1, t2) = tangent_basis(&p.coords);
            let offset =
                t1 * rng.random_range(-amount..amount) + t2 * rng.random_range(-amount..amount);
            *p = Point::from((p.coords + offset * spacing).normalize());
        }
    }
    let positions = unit
        .iter()
        .map(|p| Point::new(axes[0] * p.x, axes[1] * p.y, axes[2] * p.z))
        .collect();
    analytic(positions, triangles, &Ellipsoid { axes })
}

/// The torus with radii `major` (R) and `minor` (r) around the z axis, with about
/// `vertices` vertices on a (u, v) parameter grid of near-square cells.
pub fn torus(major: f64, minor: f64, vertices: usize, sampling: Sampling) -> Result<AnalyticMesh> {
    let ratio = major / minor;
    let nv = ((vertices as f64 / ratio).sqrt().round() as usize).max(3);
    let nu = (vertices / nv).max(3);
    let mut params = grid_params(nu, nv, sampling);
    for (u, v) in &mut params {
        *u *= std::f64::consts::TAU;
        *v *= std::f64::consts::TAU;
    }
    let positions = params
        .iter()
        .map(|&(u, v)| {
            let rho = major + minor * v.cos();
            Point::new(rho * u.cos(), rho * u.sin(), minor * v.sin())
        })
        .collect();
    let mut triangles = Vec::with_capacity(2 * nu * nv);
    for i in 0..nu {
        for j in 0..nv {
            let index = |a: usize, b: usize| ((a % nu) * nv + b % nv) as u32;
            let (p00, p10, p11, p01) = (
                index(i, j),
                index(i + 1, j),
                index(i + 1, j + 1),
                index(i, j + 1),
            );
            triangles.push([p00, p10, p11]);
            triangles.push([p00, p11, p01]);
        }
    }
    analytic(positions, triangles, &Torus { major, minor })
}

/// Grid parameters (u, v) in [0, 1)² on an `nu` × `nv` periodic grid, jittered by
/// up to the sampling's amount of one cell.
fn grid_params(nu: usize, nv: usize, sampling: Sampling) -> Vec<(f64, f64)> {
    let mut jitter = sampling.rng();
    let mut offset = || match jitter.as_mut() {
        Some((amount, rng)) => (
            rng.random_range(-*amount..*amount),
            rng.random_range(-*amount..*amount),
        ),
        None => (0.0, 0.0),
    };
    let mut params = Vec::with_capacity(nu * nv);
    for i in 0..nu {
        for j in 0..nv {
            let (du, dv) = offset();
            params.push(((i as f64 + du) / nu as f64, (j as f64 + dv) / nv as f64));
        }
    }
    params
}

/// The graph of `f` over the square [−half_width, half_width]², with about `vertices`
/// vertices, triangulated by Delaunay (spade). `Regular` samples a square grid;
/// `Jittered` moves interior grid points at random (boundary points stay on the
/// square's sides, so the domain stays a square).
pub fn height_field<F: HeightFunction + ?Sized>(
    f: &F,
    half_width: f64,
    vertices: usize,
    sampling: Sampling,
) -> Result<AnalyticMesh> {
    let n = ((vertices as f64).sqrt().round() as usize).max(2);
    let spacing = 2.0 * half_width / (n - 1) as f64;
    let mut jitter = sampling.rng();
    let mut sites = Vec::with_capacity(n * n);
    for i in 0..n {
        for j in 0..n {
            let (mut x, mut y) = (
                -half_width + i as f64 * spacing,
                -half_width + j as f64 * spacing,
            );
            if let Some((amount, rng)) = jitter.as_mut() {
                if i > 0 && i + 1 < n {
                    x += rng.random_range(-*amount..*amount) * spacing;
                }
                if j > 0 && j + 1 < n {
                    y += rng.random_range(-*amount..*amount) * spacing;
                }
            }
            sites.push(Point2::new(x, y));
        }
    }
    let (planar, triangles) = delaunay(sites)?;
    let positions = planar
        .iter()
        .map(|p| Point::new(p.x, p.y, f.value(p.x, p.y)))
        .collect();
    analytic(positions, triangles, &Graph(f))
}

/// Planar points and the triangles on them.
type PlanarTriangulation = (Vec<Point2<f64>>, Vec<[u32; 3]>);

/// Delaunay triangulation of planar sites; triangles counter-clockwise.
fn delaunay(sites: Vec<Point2<f64>>) -> Result<PlanarTriangulation> {
    let points: Vec<spade::Point2<f64>> =
        sites.iter().map(|p| spade::Point2::new(p.x, p.y)).collect();
    let triangulation: DelaunayTriangulation<spade::Point2<f64>> =
        DelaunayTriangulation::bulk_load(points)
            .map_err(|e| crate::Error::Argument(format!("cannot triangulate the sites: {e}")))?;
    let planar = triangulation
        .vertices()
        .map(|v| Point2::new(v.position().x, v.position().y))
        .collect();
    let triangles = triangulation
        .inner_faces()
        .map(|face| face.vertices().map(|v| v.index() as u32))
        .collect();
    Ok((planar, triangles))
}

/// Build the mesh and attach the exact curvature of `surface` at every vertex.
fn analytic(
    positions: Vec<Point>,
    triangles: Vec<[u32; 3]>,
    surface: &dyn ImplicitSurface,
) -> Result<AnalyticMesh> {
    let (mesh, _) = Mesh::from_soup(TriangleSoup {
        positions,
        triangles,
        ..TriangleSoup::default()
    })?;
    let exact = mesh
        .positions()
        .iter()
        .map(|p| surface.curvature(p))
        .collect();
    Ok(AnalyticMesh { mesh, exact })
}

/// A geodesic sphere: every face of an icosahedron split into k² triangles, points
/// projected to the unit sphere; k is chosen so that 10k² + 2 is about `vertices`.
/// Returns the points, the triangles and the mean angular spacing of the points.
fn icosphere(vertices: usize) -> (Vec<Point>, Vec<[u32; 3]>, f64) {
    let k = (((vertices.max(12) - 2) as f64 / 10.0).sqrt().round() as usize).max(1);
    let (corners, faces) = icosahedron();
    let mut index: HashMap<Vec<(usize, usize)>, u32> = HashMap::new();
    let mut points = Vec::new();
    // A point is identified by its integer barycentric weights on the icosahedron's
    // corners, so points on shared edges are created once.
    let mut point = |weights: [(usize, usize); 3]| -> u32 {
        let mut key: Vec<(usize, usize)> = weights.into_iter().filter(|&(_, w)| w > 0).collect();
        key.sort_unstable();
        *index.entry(key.clone()).or_insert_with(|| {
            let sum: Vector = key.iter().map(|&(c, w)| corners[c] * w as f64).sum();
            points.push(Point::from(sum.normalize()));
            (points.len() - 1) as u32
        })
    };
    let mut triangles = Vec::with_capacity(20 * k * k);
    for [a, b, c] in faces {
        let at = |i: usize, j: usize| [(a, k - i - j), (b, i), (c, j)];
        for i in 0..k {
            for j in 0..k - i {
                let (p, q, r) = (point(at(i, j)), point(at(i + 1, j)), point(at(i, j + 1)));
                triangles.push([p, q, r]);
                if i + j + 1 < k {
                    triangles.push([q, point(at(i + 1, j + 1)), r]);
                }
            }
        }
    }
    let spacing = 1.1071487177940904 / k as f64; // icosahedron edge angle / k
    (points, triangles, spacing)
}

/// The 12 unit corners and 20 counter-clockwise faces of a regular icosahedron.
fn icosahedron() -> (Vec<Vector>, Vec<[usize; 3]>) {
    let phi = (1.0 + 5f64.sqrt()) / 2.0;
    let corners = [
        (-1.0, phi, 0.0),
        (1.0, phi, 0.0),
        (-1.0, -phi, 0.0),
        (1.0, -phi, 0.0),
        (0.0, -1.0, phi),
        (0.0, 1.0, phi),
        (0.0, -1.0, -phi),
        (0.0, 1.0, -phi),
        (phi, 0.0, -1.0),
        (phi, 0.0, 1.0),
        (-phi, 0.0, -1.0),
        (-phi, 0.0, 1.0),
    ]
    .map(|(x, y, z)| Vector::new(x, y, z).normalize())
    .to_vec();
    let faces = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    (corners, faces)
}

/// A copy of `mesh` with every vertex moved along its angle-weighted normal by
/// Gaussian noise of standard deviation `sigma` mean edge lengths, reproducibly
/// from `seed`: the noisy scans of robustness tests.
pub fn with_normal_noise(mesh: &Mesh, sigma: f64, seed: u64) -> Result<Mesh> {
    let h = mesh.mean_edge_length();
    let mut rng = StdRng::seed_from_u64(seed);
    let positions = mesh
        .positions()
        .iter()
        .zip(mesh.vertex_normals())
        .map(|(p, n)| {
            // Box-Muller: a standard normal sample from two uniform ones.
            let (u, v): (f64, f64) = (rng.random_range(f64::EPSILON..1.0), rng.random());
            p + n * (sigma * h * (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos())
        })
        .collect();
    let soup = TriangleSoup {
        positions,
        triangles: mesh.triangles(),
        ..TriangleSoup::default()
    };
    Ok(Mesh::from_soup(soup)?.0)
}
