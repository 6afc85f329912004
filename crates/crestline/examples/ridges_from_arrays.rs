//! Ridges of a surface given as plain arrays, with curvature from a formula.
//!
//! A caller who already knows the curvature of a surface (from the derivatives of
//! an image, from an analytic description, from another program) builds the mesh
//! from arrays of positions and triangles, fills a [`CurvatureField`] with a
//! function of its own, and hands both to the tracer through the public entry point
//! [`LineExtractor<SurfaceWithCurvature>`]: no estimator runs.
//!
//! Here the surface is an ellipsoid x²/a² + y²/b² + z²/c² = 1 on a latitude-longitude
//! grid, and the curvature comes from its implicit equation
//! ([`implicit_curvature`], Thirion & Gourdon's formula for isosurfaces). Its one
//! ridge is the ellipse through the two longer axes (z = 0).
//!
//! `cargo run --release --example ridges_from_arrays`

use crestline::curvature::implicit_curvature;
use crestline::curvature::CurvatureField;
use crestline::lines::{LineExtractor, SurfaceWithCurvature};
use crestline::mesh::{Mesh, TriangleSoup};
use crestline::progress::Silent;
use crestline::ridges::ExtremalityTracer;
use crestline::{Point, Vector};
use nalgebra::Matrix3;

const AXES: [f64; 3] = [1.0, 0.7, 0.45];

/// Positions and triangles of an ellipsoid: `rings` latitudes between the poles,
/// `sectors` longitudes, a vertex at each pole.
fn ellipsoid_arrays(rings: u32, sectors: u32) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let [a, b, c] = AXES;
    let mut positions = vec![[0.0, 0.0, c]];
    for i in 1..=rings {
        let theta = std::f64::consts::PI * f64::from(i) / f64::from(rings + 1);
        for j in 0..sectors {
            let phi = std::f64::consts::TAU * f64::from(j) / f64::from(sectors);
            let (s, z) = theta.sin_cos();
            positions.push([a * s * phi.cos(), b * s * phi.sin(), c * z]);
        }
    }
    positions.push([0.0, 0.0, -c]);
    let south = positions.len() as u32 - 1;
    let at = |ring: u32, j: u32| 1 + (ring - 1) * sectors + j % sectors;
    let mut triangles = Vec::new();
    for j in 0..sectors {
        triangles.push([0, at(1, j), at(1, j + 1)]);
        triangles.push([south, at(rings, j + 1), at(rings, j)]);
        for ring in 1..rings {
            let (p, q) = (at(ring, j), at(ring, j + 1));
            let (r, s) = (at(ring + 1, j), at(ring + 1, j + 1));
            triangles.push([p, r, s]);
            triangles.push([p, s, q]);
        }
    }
    (positions, triangles)
}

/// The exact curvature of the ellipsoid at `p`, from F = Σ x_i² / a_i² − 1.
fn ellipsoid_curvature(p: &Point) -> (crestline::curvature::PrincipalCurvatures, Vector) {
    let inverse_squares = Vector::from(AXES.map(|a| 1.0 / (a * a)));
    let gradient = 2.0 * p.coords.component_mul(&inverse_squares);
    let hessian = Matrix3::from_diagonal(&(2.0 * inverse_squares));
    implicit_curvature(&gradient, &hessian)
}

fn main() -> crestline::Result<()> {
    let (positions, triangles) = ellipsoid_arrays(120, 240);
    let soup = TriangleSoup {
        positions: positions.iter().map(|&p| Point::from(p)).collect(),
        triangles,
        vertex_scalars: Vec::new(),
        space: None,
        volume_geometry: None,
    };
    let (mesh, _repairs) = Mesh::from_soup(soup)?;
    let curvature = CurvatureField::from_fn(mesh.vertex_count(), |v| {
        let (k, normal) = ellipsoid_curvature(&mesh.position(v));
        (k, normal, false)
    });
    let surface = SurfaceWithCurvature {
        mesh: &mesh,
        curvature: &curvature,
    };
    let lines = ExtremalityTracer::default().extract(&surface, &mut Silent)?;
    let points: Vec<&Point> = lines.iter().flat_map(|l| l.points.iter()).collect();
    let off_plane = points.iter().map(|p| p.z.abs()).fold(0.0, f64::max);
    println!(
        "ellipsoid from arrays: {} vertices, {} lines ({} points), largest |z| on them {:.2e}",
        mesh.vertex_count(),
        lines.len(),
        points.len(),
        off_plane
    );
    for line in &lines {
        println!(
            "  {} closed={} strength {:.1}, k_max along it {:.3}..{:.3}",
            line.kind,
            line.closed,
            line.strength,
            line.values["k_max"]
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min),
            line.values["k_max"].iter().copied().fold(0.0, f64::max),
        );
    }
    assert_eq!(lines.len(), 1, "one ridge: the ellipse in z = 0");
    assert!(off_plane < 0.01, "the ridge lies in z = 0");
    Ok(())
}
