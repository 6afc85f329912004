//! Fairing of lines that must stay on the surface and on their crest: the
//! edge-path staircases of Morse-Smale 1-cells (Sahner et al. 2008, §3.6 smooths
//! them as space curves, which lifts them off the surface and off the crest).
//!
//! Each step moves every inner point halfway towards the midpoint of its
//! neighbours (the umbrella step of Laplacian fairing), then back onto the
//! surface: to the closest point of the faces around where it lies. A move is
//! taken only where the field interpolated there stays at or above the point's
//! floor, so the line cannot slide off the crest it follows.

use crate::mesh::{FaceId, Mesh, VertexId};
use crate::{Point, Vector};

use super::location::SurfaceLocation;

/// Fairs the line through `locations` on `mesh` with `iterations` steps (see the
/// module documentation), keeping every point where `field` (one value per
/// vertex) is at least `floor(i)` for point `i`. End points of open lines stay;
/// a closed line (first point not repeated) moves all its points.
pub fn fair_on_surface(
    mesh: &Mesh,
    locations: &mut [SurfaceLocation],
    closed: bool,
    iterations: usize,
    field: &[f64],
    floor: impl Fn(usize) -> f64,
) {
    let n = locations.len();
    if n < 3 {
        return;
    }
    let movable = |i: usize| closed || (i > 0 && i + 1 < n);
    for _ in 0..iterations {
        let points: Vec<Point> = locations.iter().map(|at| at.position(mesh)).collect();
        for i in (0..n).filter(|&i| movable(i)) {
            let (prev, next) = (points[(i + n - 1) % n], points[(i + 1) % n]);
            let target = points[i] + (nalgebra::center(&prev, &next) - points[i]) * 0.5;
            if let Some(moved) = closest_admissible(mesh, &locations[i], &target, field, floor(i)) {
                locations[i] = moved;
            }
        }
    }
}

/// The point of the faces around `at` closest to `target` among those where
/// `field` is at least `floor`; `None` if there is none.
fn closest_admissible(
    mesh: &Mesh,
    at: &SurfaceLocation,
    target: &Point,
    field: &[f64],
    floor: f64,
) -> Option<SurfaceLocation> {
    let mut best: Option<(f64, SurfaceLocation)> = None;
    for face in faces_around(mesh, at) {
        let corners = mesh.face_points(face);
        let barycentric = closest_on_triangle(target, &corners);
        let candidate = SurfaceLocation::Face {
            face: face.0,
            barycentric,
        };
        // NaN values are never admissible.
        let value = candidate.interpolate(mesh, field);
        if value.is_nan() || value < floor {
            continue;
        }
        let distance = (candidate.position(mesh) - target).norm_squared();
        if best.as_ref().is_none_or(|(d, _)| distance < *d) {
            best = Some((distance, candidate));
        }
    }
    best.map(|(_, location)| location)
}

/// The faces around the vertices `at` interpolates (its star, or the stars of its
/// edge's or face's corners), each once.
fn faces_around(mesh: &Mesh, at: &SurfaceLocation) -> Vec<FaceId> {
    let mut faces: Vec<FaceId> = at
        .weights(mesh)
        .iter()
        .flat_map(|&(v, _): &(VertexId, f64)| mesh.vertex_faces(v))
        .collect();
    faces.sort_unstable_by_key(|f| f.0);
    faces.dedup();
    faces
}

/// Barycentric coordinates of the point of the triangle `corners` closest to `p`
/// (Ericson, *Real-Time Collision Detection*, §5.1.5: Voronoi regions of the
/// corners, edges and interior).
fn closest_on_triangle(p: &Point, [a, b, c]: &[Point; 3]) -> [f64; 3] {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(&ap), ac.dot(&ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return [1.0, 0.0, 0.0];
    }
    let bp: Vector = p - b;
    let (d3, d4) = (ab.dot(&bp), ac.dot(&bp));
    if d3 >= 0.0 && d4 <= d3 {
        return [0.0, 1.0, 0.0];
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return [1.0 - v, v, 0.0];
    }
    let cp: Vector = p - c;
    let (d5, d6) = (ab.dot(&cp), ac.dot(&cp));
    if d6 >= 0.0 && d5 <= d6 {
        return [0.0, 0.0, 1.0];
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return [1.0 - w, 0.0, w];
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return [0.0, 1.0 - w, w];
    }
    let denominator = va + vb + vc;
    if denominator == 0.0 || denominator.is_nan() {
        // A degenerate triangle: its first corner.
        return [1.0, 0.0, 0.0];
    }
    let (v, w) = (vb / denominator, vc / denominator);
    [1.0 - v - w, v, w]
}
