//! Numerics that degrade instead of aborting, and bounded work: presmoothing on
//! meshes with boundary and obtuse triangles, curvature outliers flagged
//! unreliable, meshes at extreme coordinate scales, range checks of f32 output,
//! and the cost of jet-fit neighbourhoods and of drawing scrambled meshes.

use std::time::Instant;

use crate::common::mesh_of;
use crate::curvature::{
    estimate_curvature, repair_outliers, CurvatureEstimator, JetFit, ShapeOperator,
};
use crate::draw::{draw, Camera, DrawOptions, Projection, View};
use crate::lines::{FeatureLines, LineExtractor, LineKind, Polyline};
use crate::mesh::generate::{height_field, sphere, Paraboloid, Sampling};
use crate::mesh::{Mesh, TriangleSoup, VertexId};
use crate::progress::Observer;
use crate::progress::Silent;
use crate::ridges::presmooth_surface;
use crate::ridges::ExtremalityTracer;
use crate::Point;

fn all_finite(mesh: &Mesh) -> bool {
    mesh.positions()
        .iter()
        .all(|p| p.iter().all(|c| c.is_finite()))
}

#[test]
fn presmoothing_an_open_height_field_is_finite() {
    let paraboloid = Paraboloid { a: 0.5, b: -0.3 };
    let mesh = height_field(&paraboloid, 1.0, 900, Sampling::jittered(3))
        .unwrap()
        .mesh;
    assert!(mesh.vertices().any(|v| mesh.is_boundary_vertex(v)));
    for steps in [1, 3, 20] {
        let smoothed = presmooth_surface(&mesh, steps).unwrap();
        assert!(all_finite(&smoothed), "{steps} steps");
    }
}

#[test]
fn presmoothing_a_very_obtuse_triangle_is_finite() {
    // A lone sliver: its angle at the apex is nearly π, the cotan weight of the
    // opposite edge very negative.
    let lone = mesh_of(
        vec![
            Point::new(0.0, 0.0, 0.0),
            Point::new(1.0, 0.0, 0.0),
            Point::new(0.5, 1e-3, 0.0),
        ],
        vec![[0, 1, 2]],
    );
    let smoothed = presmooth_surface(&lone, 3).unwrap();
    assert!(all_finite(&smoothed));
    // The same sliver inside a closed surface: one vertex of a sphere moved almost
    // onto the edge between two of its neighbours.
    let ball = sphere(1.0, 500, Sampling::Regular).unwrap().mesh;
    let v = VertexId(100);
    let ring: Vec<VertexId> = ball.neighbors(v).collect();
    let (a, b) = (ball.position(ring[0]), ball.position(ring[1]));
    let mut positions = ball.positions().to_vec();
    positions[v.idx()] = nalgebra::center(&a, &b) + (positions[v.idx()] - a) * 1e-3;
    let sliver = mesh_of(positions, ball.triangles());
    let smoothed = presmooth_surface(&sliver, 3).unwrap();
    assert!(all_finite(&smoothed));
}

#[test]
fn presmoothing_fifty_steps_of_the_bunny_is_finite() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../meshes/bunny_small.obj");
    let soup = crate::io::read_mesh(std::path::Path::new(path)).unwrap();
    let (mesh, _) = Mesh::from_soup(soup).unwrap();
    let smoothed = presmooth_surface(&mesh, 50).unwrap();
    assert!(all_finite(&smoothed));
}

/// Counts told to an observer.
#[derive(Default)]
struct Counts(Vec<(String, usize)>);

impl Observer for Counts {
    fn count(&mut self, key: &str, value: usize) {
        self.0.push((key.to_string(), value));
    }
}

impl Counts {
    fn get(&self, key: &str) -> Option<usize> {
        self.0.iter().find(|(k, _)| k == key).map(|&(_, v)| v)
    }
}

#[test]
fn a_spike_is_flagged_unreliable_and_ridges_still_run() {
    let ball = sphere(1.0, 2_000, Sampling::jittered(5)).unwrap().mesh;
    let spike = VertexId(321);
    let mut positions = ball.positions().to_vec();
    positions[spike.idx()] *= 1e4;
    let mesh = mesh_of(positions, ball.triangles());
    for estimator in [
        &ShapeOperator as &dyn CurvatureEstimator,
        &JetFit::default(),
    ] {
        let field = estimate_curvature(&mesh, estimator).unwrap();
        assert!(field.unreliable[spike.idx()]);
        let flagged = field.unreliable.iter().filter(|&&u| u).count();
        assert!(flagged < 60, "{flagged} flagged");
    }
    let mut counts = Counts::default();
    let lines = ExtremalityTracer::default()
        .trace(&mesh, &mut counts)
        .unwrap();
    assert!(counts.get("unreliable_vertices").unwrap() >= 1);
    assert!(lines
        .lines
        .iter()
        .all(|l| l.points.iter().all(|p| p.iter().all(|c| c.is_finite()))));
    // No line point lies on an edge at the spike.
    for line in &lines.lines {
        for p in &line.points {
            assert!((p - mesh.position(spike)).norm() > 0.5, "{p}");
        }
    }
}

#[test]
fn a_non_finite_estimate_is_flagged_not_fatal() {
    // A vertex whose link is a bow-tie with parallel diagonals: the area vectors of
    // its four (sound) triangles sum to zero, so it has no normal.
    let mesh = mesh_of(
        vec![
            Point::new(1.0, 0.5, 1.0),
            Point::new(0.0, 0.0, 0.0),
            Point::new(0.0, 1.0, 0.0),
            Point::new(2.0, 0.0, 0.0),
            Point::new(3.0, 1.0, 0.0),
        ],
        vec![[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 1]],
    );
    assert_eq!(mesh.face_count(), 4);
    let centre = VertexId(0);
    assert!(!mesh.is_boundary_vertex(centre));
    for estimator in [
        &ShapeOperator as &dyn CurvatureEstimator,
        &JetFit::default(),
    ] {
        let field = estimate_curvature(&mesh, estimator).unwrap();
        assert!(field.unreliable[centre.idx()]);
        assert!(field
            .k_max
            .iter()
            .chain(&field.k_min)
            .all(|k| k.is_finite()));
    }
    let mut counts = Counts::default();
    ExtremalityTracer::default()
        .trace(&mesh, &mut counts)
        .unwrap();
    assert_eq!(counts.get("unreliable_vertices"), Some(1));
}

#[test]
fn repairs_replace_a_value_by_the_median_of_its_ring() {
    let mesh = sphere(1.0, 500, Sampling::Regular).unwrap().mesh;
    let mut field = ShapeOperator.estimate(&mesh).unwrap();
    assert_eq!(repair_outliers(&mesh, &mut field), 0);
    let ring: Vec<f64> = mesh
        .neighbors(VertexId(3))
        .map(|w| field.k_max[w.idx()])
        .collect();
    field.k_max[3] = f64::NAN;
    field.k_min[9] = 1e9;
    assert_eq!(repair_outliers(&mesh, &mut field), 2);
    assert!(field.unreliable[3] && field.unreliable[9]);
    let (low, high) = ring
        .iter()
        .fold((f64::MAX, f64::MIN), |(l, h), &k| (l.min(k), h.max(k)));
    assert!((low..=high).contains(&field.k_max[3]), "{}", field.k_max[3]);
    assert!(field.k_min[9] < 1.5, "{}", field.k_min[9]);
    field.check(&mesh).unwrap();
}

/// A sphere of radius `radius` (mesh positions scaled from the unit sphere).
fn scaled_sphere(radius: f64) -> (Mesh, usize) {
    let unit = sphere(1.0, 1_000, Sampling::jittered(11)).unwrap().mesh;
    let positions = unit.positions().iter().map(|p| p * radius).collect();
    let faces = unit.face_count();
    let soup = TriangleSoup {
        positions,
        triangles: unit.triangles(),
        vertex_scalars: Vec::new(),
        space: None,
        volume_geometry: None,
    };
    let (mesh, report) = Mesh::from_soup(soup).unwrap();
    assert!(report.is_clean(), "{radius}: {report}");
    (mesh, faces)
}

#[test]
fn spheres_at_extreme_scales_keep_their_faces_and_curvature() {
    let (unit, _) = scaled_sphere(1.0);
    let estimators = [
        &ShapeOperator as &dyn CurvatureEstimator,
        &JetFit::default(),
    ];
    let reference: Vec<_> = estimators
        .iter()
        .map(|e| estimate_curvature(&unit, *e).unwrap())
        .collect();
    for radius in [1e154, 1e-160, 1e300, 1e-300, 1e307] {
        let (mesh, faces) = scaled_sphere(radius);
        assert_eq!(mesh.face_count(), faces, "{radius:e}");
        let diagonal = mesh.bounding_box().diagonal();
        let expected = unit.bounding_box().diagonal() * radius;
        assert!(
            (diagonal / expected - 1.0).abs() < 1e-12,
            "{radius:e}: {diagonal:e}"
        );
        let h = mesh.mean_edge_length() / unit.mean_edge_length() / radius;
        assert!((h - 1.0).abs() < 1e-12, "{radius:e}: {h}");
        for (estimator, truth) in estimators.iter().zip(&reference) {
            let field = estimate_curvature(&mesh, *estimator).unwrap();
            assert_eq!(field.unreliable, truth.unreliable, "{radius:e}");
            for (k, unit_k) in field.k_max.iter().zip(&truth.k_max) {
                assert!(
                    (k * radius / unit_k - 1.0).abs() < 1e-6,
                    "{radius:e}: k {k:e}"
                );
            }
            // The mean curvature times the radius is 1 on average.
            let mean = field.mean().iter().sum::<f64>() / field.len() as f64 * radius;
            assert!((mean - 1.0).abs() < 0.02, "{radius:e}: mean H·r {mean}");
        }
    }
}

#[test]
fn spheres_at_extreme_scales_give_no_spurious_lines() {
    for radius in [1e154, 1e-160] {
        let (mesh, _) = scaled_sphere(radius);
        let lines = ExtremalityTracer::default()
            .extract(&mesh, &mut Silent)
            .unwrap();
        let reference = ExtremalityTracer::default()
            .extract(&scaled_sphere(1.0).0, &mut Silent)
            .unwrap();
        assert_eq!(lines.len(), reference.len(), "{radius}");
    }
}

#[test]
fn a_curvature_ply_holds_values_beyond_f32_exactly_and_refuses_non_finite_ones() {
    // On a sphere of radius 1e-30 the Gaussian curvature is about 1e60, beyond
    // f32: written in double precision, it reads back exactly.
    let (mesh, _) = scaled_sphere(1e-30);
    let field = estimate_curvature(&mesh, &ShapeOperator).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("tiny.ply");
    field.write_ply(&path, &mesh).unwrap();
    let soup = crate::io::read_mesh(&path).unwrap();
    let gauss = soup
        .vertex_scalars
        .iter()
        .find(|p| p.name == "gauss")
        .unwrap();
    let expected: Vec<f64> = field
        .k_max
        .iter()
        .zip(&field.k_min)
        .map(|(a, b)| a * b)
        .collect();
    assert!(gauss.values[0] > 1e59, "{}", gauss.values[0]);
    assert_eq!(gauss.values, expected);
    // A non-finite value is an error naming the file and the property, and no
    // file is left.
    let mut broken = field.clone();
    broken.k_min[3] = f64::INFINITY;
    let path = dir.path().join("broken.ply");
    let message = broken.write_ply(&path, &mesh).unwrap_err().to_string();
    assert!(
        message.contains("broken.ply") && message.contains("k_min"),
        "{message}"
    );
    assert!(!path.exists());
}

/// A fan of `valence` triangles around a centre vertex on the paraboloid cap
/// z = −r²/2, its rim at radii 1 and 0.6 in turn (so that the points of a fit do
/// not all lie on one circle).
fn fan(valence: usize) -> Mesh {
    let mut positions = vec![Point::new(0.0, 0.0, 0.0)];
    for i in 0..valence {
        let a = std::f64::consts::TAU * i as f64 / valence as f64;
        let r = if i % 2 == 0 { 1.0 } else { 0.6 };
        positions.push(Point::new(r * a.cos(), r * a.sin(), -0.5 * r * r));
    }
    let triangles = (0..valence as u32)
        .map(|i| [0, 1 + i, 1 + (i + 1) % valence as u32])
        .collect();
    mesh_of(positions, triangles)
}

#[test]
fn jet_fit_on_a_fan_of_valence_ten_thousand_is_bounded() {
    let mesh = fan(10_000);
    let start = Instant::now();
    let field = JetFit::default().estimate(&mesh).unwrap();
    let seconds = start.elapsed().as_secs_f64();
    eprintln!("jet fit, valence 10000: {seconds:.3} s");
    assert!(field.k_max.iter().all(|k| k.is_finite()));
    assert!(field.k_min.iter().all(|k| k.is_finite()));
    let jet = JetFit::default();
    let used = jet.fit_points(&mesh, VertexId(0)).len();
    assert_eq!(used, jet.max_points);
    let rim = jet.fit_points(&mesh, VertexId(1)).len();
    assert!(rim <= jet.max_points, "{rim}");
    // The centre of the cap z = −r²/2 has curvature 1 both ways.
    assert!((field.k_max[0] - 1.0).abs() < 0.05, "{}", field.k_max[0]);
}

#[test]
fn drawing_a_scrambled_mesh_returns() {
    let ball = sphere(1.0, 20_000, Sampling::jittered(2)).unwrap().mesh;
    let n = ball.vertex_count() as u64;
    // Connect far-apart vertices: every triangle spans much of the canvas.
    let scramble = |v: u32| ((u64::from(v) * 7919 + 13) % n) as u32;
    let triangles = ball
        .triangles()
        .into_iter()
        .map(|t| [t[0], scramble(t[1]), scramble(scramble(t[2]))])
        .collect();
    let soup = TriangleSoup {
        positions: ball.positions().to_vec(),
        triangles,
        vertex_scalars: Vec::new(),
        space: None,
        volume_geometry: None,
    };
    let (mesh, _) = Mesh::from_soup(soup).unwrap();
    let mut lines = FeatureLines::new(String::new());
    lines.push(Polyline::new(
        LineKind::Ridge,
        false,
        5.0,
        vec![Point::new(-1.0, 0.0, 1.0), Point::new(1.0, 0.0, 1.0)],
    ));
    let camera = Camera::framing(
        mesh.positions(),
        View::Orbit {
            azimuth: 0.3,
            elevation: 0.2,
        },
        Projection::Orthographic,
        800,
        800,
    )
    .unwrap();
    let start = Instant::now();
    let drawing = draw(&mesh, &lines, &camera, &with_silhouettes()).unwrap();
    eprintln!(
        "draw, scrambled sphere of {} faces: {:.3} s",
        mesh.face_count(),
        start.elapsed().as_secs_f64()
    );
    assert!(drawing.group(LineKind::Ridge).is_some());
}

/// The default drawing settings with the silhouettes drawn.
fn with_silhouettes() -> DrawOptions {
    DrawOptions {
        silhouettes: true,
        ..DrawOptions::default()
    }
}
