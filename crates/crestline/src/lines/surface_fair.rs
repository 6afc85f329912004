//! Fairing of lines that must stay on the surface and on their crest: the
//! edge-path staircases of Morse-Smale 1-cells (Sahner et al. 2008, §3.6 smooths
//! them as space curves, which lifts them off the surface and off the crest).
//!
//! Each step moves every inner point halfway towards the midpoint of its
//! neighbours (the umbrella step of Laplacian fairing), then back onto the
//! surface: to the closest point of the faces around where it lies. A move is
//! taken only where the field interpolated there stays at or above the point's
//! floor, so the line cannot slide off the crest it follows.

use rayon::prelude::*;

use crate::mesh::{EdgeId, FaceId, Mesh, VertexId};
use crate::{Point, Vector};

use super::location::SurfaceLocation;

/// Fairs the line through `locations` on `mesh` with `iterations` steps (see the
/// module documentation), keeping every point where `field` (one value per
/// vertex) is at least `floor(i)` for point `i`. End points of open lines stay;
/// a closed line (first point not repeated) moves all its points. Stops early
/// once no point moves more than a thousandth of the mean point spacing.
pub fn fair_on_surface(
    mesh: &Mesh,
    locations: &mut [SurfaceLocation],
    closed: bool,
    iterations: usize,
    field: &[f64],
    floor: impl Fn(usize) -> f64 + Sync,
) {
    let n = locations.len();
    if n < 3 {
        return;
    }
    let movable = |i: usize| closed || (i > 0 && i + 1 < n);
    let mut points: Vec<Point> = locations.iter().map(|at| at.position(mesh)).collect();
    // Settled: no point moves more than this (a thousandth of the mean spacing).
    let spacing = points.windows(2).map(|w| (w[1] - w[0]).norm()).sum::<f64>() / n as f64;
    let settled = 1e-3 * spacing;
    let mut previous = points.clone();
    let mut stars: Vec<Star> = (0..n).map(|_| Star::default()).collect();
    for _ in 0..iterations {
        // Every point moves from the previous positions, so the points of a long
        // line are moved in parallel.
        let largest_move = locations
            .par_iter_mut()
            .zip(points.par_iter_mut())
            .zip(stars.par_iter_mut())
            .enumerate()
            .with_min_len(256)
            .filter(|(i, _)| movable(*i))
            .map(|(i, ((at, point), star))| {
                let (prev, next) = (previous[(i + n - 1) % n], previous[(i + 1) % n]);
                let target = previous[i] + (nalgebra::center(&prev, &next) - previous[i]) * 0.5;
                let Some((moved, position)) =
                    closest_admissible(mesh, at, star, &target, field, floor(i))
                else {
                    return 0.0;
                };
                *at = moved;
                *point = position;
                (*point - previous[i]).norm()
            })
            .reduce(|| 0.0, f64::max);
        previous.copy_from_slice(&points);
        if largest_move <= settled {
            break;
        }
    }
}

/// The faces around a vertex, in the order [`Mesh::vertex_faces`] gives them,
/// with their corners' positions and a field's values there: kept for a point
/// from one fairing step to the next while the vertex it moves around stays,
/// rather than walked and read anew (the Morse lines stage,
/// 3 interleaved runs: dragon 0.25–0.27 → 0.21–0.23 s, dragon ×4 0.55–0.62 →
/// 0.47–0.54 s; the lines the same to the byte).
#[derive(Default)]
struct Star {
    centre: Option<VertexId>,
    faces: Vec<Corners>,
}

impl Star {
    /// The star of `centre` with `field` at the corners, from the mesh unless it
    /// is the one kept (a star is kept for one field).
    fn of(&mut self, mesh: &Mesh, centre: VertexId, field: &[f64]) -> &[Corners] {
        if self.centre != Some(centre) {
            self.centre = Some(centre);
            self.faces.clear();
            self.faces.extend(
                mesh.vertex_faces(centre)
                    .map(|face| Corners::new(mesh, face, field)),
            );
        }
        &self.faces
    }
}

/// A face with the positions of its corners and a field's values there.
struct Corners {
    face: FaceId,
    points: [Point; 3],
    values: [f64; 3],
}

impl Corners {
    fn new(mesh: &Mesh, face: FaceId, field: &[f64]) -> Corners {
        let corners = mesh.face_vertices(face);
        Corners {
            face,
            points: corners.map(|v| mesh.position(v)),
            values: corners.map(|v| field[v.idx()]),
        }
    }
}

/// The point of the faces around `at` closest to `target` among those where
/// `field` is at least `floor`, and its position; `None` if there is none.
/// `star` keeps the faces around `at`'s nearest vertex.
fn closest_admissible(
    mesh: &Mesh,
    at: &SurfaceLocation,
    star: &mut Star,
    target: &Point,
    field: &[f64],
    floor: f64,
) -> Option<(SurfaceLocation, Point)> {
    let mut best: Option<(f64, SurfaceLocation, Point)> = None;
    let (centre, mut own_face) = nearest_vertex(mesh, at);
    for corners in star.of(mesh, centre, field) {
        // The face `at` lies in is one of the star's, looked at once.
        if own_face == Some(corners.face) {
            own_face = None;
        }
        closer_admissible(corners, target, floor, &mut best);
    }
    if let Some(face) = own_face {
        closer_admissible(&Corners::new(mesh, face, field), target, floor, &mut best);
    }
    best.map(|(_, location, position)| (location, position))
}

/// The point of the face of `corners` closest to `target` as `best` (with its
/// squared distance and location) if the field is at least `floor` there and it
/// is closer than `best`.
fn closer_admissible(
    corners: &Corners,
    target: &Point,
    floor: f64,
    best: &mut Option<(f64, SurfaceLocation, Point)>,
) {
    let Corners {
        face,
        points,
        values,
    } = corners;
    // No point of a face whose corners all lie below the floor is admissible.
    if values.iter().all(|&value| value < floor) {
        return;
    }
    let barycentric = closest_on_triangle(target, points);
    // NaN values are never admissible.
    let value: f64 = (0..3).map(|k| barycentric[k] * values[k]).sum();
    if value.is_nan() || value < floor {
        return;
    }
    let position: Vector = (0..3).map(|k| points[k].coords * barycentric[k]).sum();
    let distance = (position - target.coords).norm_squared();
    if best.as_ref().is_none_or(|(d, ..)| distance < *d) {
        let location = SurfaceLocation::Face {
            face: face.0,
            barycentric,
        };
        *best = Some((distance, location, Point::from(position)));
    }
}

/// The vertex with the largest weight at `at`, and the face `at` lies in (if it
/// lies inside one): a point moves over the star of that vertex, which holds the
/// faces across the edges it is nearest to.
fn nearest_vertex(mesh: &Mesh, at: &SurfaceLocation) -> (VertexId, Option<FaceId>) {
    match *at {
        SurfaceLocation::Vertex { vertex } => (VertexId(vertex), None),
        SurfaceLocation::Edge { edge, t } => {
            let [a, b] = mesh.edge_vertices(EdgeId(edge));
            (if t <= 0.5 { a } else { b }, None)
        }
        SurfaceLocation::Face { face, barycentric } => {
            let corners = mesh.face_vertices(FaceId(face));
            let k = (0..3)
                .max_by(|&i, &j| barycentric[i].total_cmp(&barycentric[j]))
                .unwrap_or(0);
            (corners[k], Some(FaceId(face)))
        }
    }
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

/// Fairing on the surface: staircase lines become smooth, stay on the mesh and on
/// their crest.
#[cfg(test)]
mod tests {
    use super::fair_on_surface;
    use crate::lines::SurfaceLocation;
    use crate::mesh::generate::{sphere, Sampling};
    use crate::mesh::Mesh;
    use crate::Point;

    /// The total turning angle of a polyline (radians).
    fn turning(points: &[Point]) -> f64 {
        points
            .windows(3)
            .map(|w| (w[1] - w[0]).angle(&(w[2] - w[1])))
            .sum()
    }

    /// A staircase along the equator y = 0 of a unit sphere: the vertices within
    /// two mean edge lengths of it on the quarter x, z > 0, by longitude.
    fn staircase(mesh: &Mesh) -> Vec<SurfaceLocation> {
        let h = mesh.mean_edge_length();
        let mut near: Vec<(f64, u32)> = mesh
            .vertices()
            .map(|v| (v, mesh.position(v)))
            .filter(|(_, p)| p.y.abs() < 2.0 * h && p.x > 0.0 && p.z > 0.0)
            .map(|(v, p)| (p.z.atan2(p.x), v.0))
            .collect();
        near.sort_by(|a, b| a.0.total_cmp(&b.0));
        near.into_iter()
            .map(|(_, vertex)| SurfaceLocation::Vertex { vertex })
            .collect()
    }

    #[test]
    fn a_staircase_along_a_crest_is_smoothed_on_the_surface_and_on_the_crest() {
        let mesh = sphere(1.0, 5000, Sampling::Regular).unwrap().mesh;
        let h = mesh.mean_edge_length();
        // The crest: the equator, where -|y| is largest.
        let field: Vec<f64> = mesh.positions().iter().map(|p| -p.y.abs()).collect();
        let mut line = staircase(&mesh);
        let before: Vec<Point> = line.iter().map(|at| at.position(&mesh)).collect();
        let floors: Vec<f64> = line
            .iter()
            .map(|at| at.interpolate(&mesh, &field))
            .collect();
        fair_on_surface(&mesh, &mut line, false, 10, &field, |i| floors[i]);
        let after: Vec<Point> = line.iter().map(|at| at.position(&mesh)).collect();
        assert_eq!(after[0], before[0]);
        assert_eq!(after.last(), before.last());
        assert!(
            turning(&after) < 0.5 * turning(&before),
            "turning {} -> {}",
            turning(&before),
            turning(&after)
        );
        for (i, (at, p)) in line.iter().zip(&after).enumerate() {
            // On the crest: never farther from it than the staircase was.
            assert!(at.interpolate(&mesh, &field) >= floors[i], "point {i}");
            // On the surface: within the chordal error of a face (h²/8 for the unit
            // sphere) of the sphere itself.
            assert!((p.coords.norm() - 1.0).abs() <= h * h / 4.0, "{p}");
        }
    }
}
