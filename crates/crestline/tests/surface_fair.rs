//! Fairing on the surface: staircase lines become smooth, stay on the mesh and on
//! their crest.

use crestline::lines::surface_fair::fair_on_surface;
use crestline::lines::SurfaceLocation;
use crestline::mesh::generate::{sphere, Sampling};
use crestline::mesh::Mesh;
use crestline::Point;

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
