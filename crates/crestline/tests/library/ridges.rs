//! Ridge and valley lines by extremality tracing, on an ellipsoid whose ridges are
//! known exactly (its principal ellipses), under rigid motion, scaling, arbitrary
//! direction signs and noise, and on real meshes.

use crate::common;

use common::transformed;
use crestline::curvature::{CurvatureEstimator, CurvatureField, Estimator, JetFit, ShapeOperator};
use crestline::jobs;
use crestline::lines::{
    FeatureLines, LineExtractor, LineKind, SurfaceLocation, SurfaceWithCurvature,
};
use crestline::mesh::generate::{self, Sampling};
use crestline::mesh::{Mesh, TriangleSoup};
use crestline::progress::Silent;
use crestline::ridges::ExtremalityTracer;
use crestline::{Point, Vector};
use nalgebra::{Isometry3, Translation3, UnitQuaternion};
use rand::rngs::StdRng;
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use std::sync::Arc;

const AXES: [f64; 3] = [1.0, 0.7, 0.45];

fn ellipsoid() -> Mesh {
    generate::ellipsoid(AXES, 30_000, Sampling::jittered(1))
        .unwrap()
        .mesh
}

fn motion() -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(5.0, -2.0, 9.0),
        UnitQuaternion::from_euler_angles(0.7, 0.4, -1.2),
    )
}

/// Distance of `p` (in the ellipsoid's own frame) to the nearest principal plane.
fn plane_distance(p: &Point) -> f64 {
    p.x.abs().min(p.y.abs()).min(p.z.abs())
}

fn all_points(lines: &FeatureLines) -> Vec<Point> {
    lines
        .iter()
        .flat_map(|l| l.points.iter().copied())
        .collect()
}

fn mean_plane_distance(points: &[Point]) -> f64 {
    points.iter().map(plane_distance).sum::<f64>() / points.len() as f64
}

/// `a` and `b` are the same lines, point for point to 1e-12, and not none.
fn assert_same_lines(a: &FeatureLines, b: &FeatureLines) {
    assert!(!a.is_empty());
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(b.iter()) {
        assert_eq!(x.points.len(), y.points.len());
        assert!(x
            .points
            .iter()
            .zip(&y.points)
            .all(|(p, q)| (p - q).norm() < 1e-12));
    }
}

fn diagonal() -> f64 {
    2.0 * Vector::from(AXES).norm()
}

/// Share of the principal ellipse in the plane `axis` = 0 that lies within
/// `radius` of a line point, sampled away from the umbilics (which lie in y = 0).
fn coverage(points: &[Point], axis: usize, radius: f64) -> f64 {
    let [a, b, c] = AXES;
    let umbilic = Point::new(
        a * ((a * a - b * b) / (a * a - c * c)).sqrt(),
        0.0,
        c * ((b * b - c * c) / (a * a - c * c)).sqrt(),
    );
    let (u, v) = match axis {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    };
    let samples: Vec<Point> = (0..720)
        .map(|i| {
            let angle = std::f64::consts::TAU * i as f64 / 720.0;
            let mut p = Point::origin();
            p[u] = AXES[u] * angle.cos();
            p[v] = AXES[v] * angle.sin();
            p
        })
        .filter(|p| {
            let mirrored = Point::new(p.x.abs(), p.y.abs(), p.z.abs());
            (mirrored - umbilic).norm() > 0.15
        })
        .collect();
    let covered = samples
        .iter()
        .filter(|s| points.iter().any(|p| (p - *s).norm() < radius))
        .count();
    covered as f64 / samples.len() as f64
}

#[test]
fn default_ridge_of_a_rotated_ellipsoid_is_its_sharpest_principal_ellipse() {
    let motion = motion();
    let mesh = transformed(&ellipsoid(), |p| motion * p);
    let lines = ExtremalityTracer::default()
        .extract(&mesh, &mut Silent)
        .unwrap();
    // Back to the ellipsoid's frame.
    let points: Vec<Point> = all_points(&lines)
        .iter()
        .map(|p| motion.inverse_transform_point(p))
        .collect();
    let mean = mean_plane_distance(&points) / diagonal();
    eprintln!(
        "default: {} lines, mean plane distance {:.4}% of the diagonal",
        lines.len(),
        100.0 * mean
    );
    assert!(mean < 0.005, "{mean}");
    // On a convex surface only maxima of k_max qualify (eqs. 5, 6): the ellipse
    // through the two longer axes, as one closed ridge; nothing else is strong.
    assert_eq!(
        lines.len(),
        1,
        "{:?}",
        lines.iter().map(|l| l.strength).collect::<Vec<_>>()
    );
    let ridge = &lines.lines[0];
    assert!(ridge.closed && ridge.kind == LineKind::Ridge);
    assert!(ridge.strength > 15.0, "{}", ridge.strength);
    let h = mesh.mean_edge_length();
    assert!(coverage(&points, 2, 2.0 * h) > 0.98);
}

#[test]
fn all_extremal_lines_of_an_ellipsoid_cover_its_three_principal_ellipses() {
    let tracer = ExtremalityTracer {
        all_extrema: true,
        threshold: 0.5,
        ..Default::default()
    };
    let mesh = ellipsoid();
    let lines = tracer.extract(&mesh, &mut Silent).unwrap();
    let points = all_points(&lines);
    let mean = mean_plane_distance(&points) / diagonal();
    let h = mesh.mean_edge_length();
    let covered = [0, 1, 2].map(|axis| coverage(&points, axis, 2.0 * h));
    eprintln!(
        "all extrema: {} lines, mean plane distance {:.4}%, coverage {covered:.3?}",
        lines.len(),
        100.0 * mean
    );
    assert!(mean < 0.005, "{mean}");
    assert!(covered.iter().all(|&c| c > 0.9), "{covered:?}");
}

#[test]
fn scaling_by_1000_gives_the_same_lines() {
    let mesh = ellipsoid();
    let big = transformed(&mesh, |p| p * 1000.0);
    let tracer = ExtremalityTracer {
        all_extrema: true,
        threshold: 0.5,
        ..Default::default()
    };
    let small_lines = tracer.extract(&mesh, &mut Silent).unwrap();
    let big_lines = tracer.extract(&big, &mut Silent).unwrap();
    assert_eq!(small_lines.len(), big_lines.len());
    for (s, b) in small_lines.iter().zip(big_lines.iter()) {
        assert_eq!(s.points.len(), b.points.len());
        assert!((s.strength - b.strength).abs() < 1e-9 * s.strength.max(1.0));
        for (p, q) in s.points.iter().zip(&b.points) {
            assert!((p - q / 1000.0).norm() < 1e-9, "{p} vs {q}");
        }
    }
}

/// The shape operator with the direction signs flipped at a random half of the
/// vertices: a legitimate, equally valid output.
struct RandomSigns;

impl CurvatureEstimator for RandomSigns {
    fn estimate(&self, mesh: &Mesh) -> crestline::Result<CurvatureField> {
        let mut field = ShapeOperator.estimate(mesh)?;
        let mut rng = StdRng::seed_from_u64(99);
        for v in 0..field.len() {
            if rng.random_bool(0.5) {
                field.d_max[v] = -field.d_max[v];
            }
            if rng.random_bool(0.5) {
                field.d_min[v] = -field.d_min[v];
            }
        }
        Ok(field)
    }
}

#[test]
fn lines_do_not_depend_on_direction_signs() {
    let mesh = generate::torus(1.0, 0.35, 20_000, Sampling::jittered(6))
        .unwrap()
        .mesh;
    let reference = ShapeOperator.estimate(&mesh).unwrap();
    let flipped = RandomSigns.estimate(&mesh).unwrap();
    let flips = (0..reference.len())
        .filter(|&v| reference.d_max[v] != flipped.d_max[v])
        .count();
    assert!(flips > reference.len() / 3);
    let tracer = |estimator: Arc<dyn CurvatureEstimator + Send + Sync>| ExtremalityTracer {
        estimator,
        threshold: 0.0,
        ..Default::default()
    };
    let lines_a = tracer(Arc::new(ShapeOperator))
        .extract(&mesh, &mut Silent)
        .unwrap();
    let lines_b = tracer(Arc::new(RandomSigns))
        .extract(&mesh, &mut Silent)
        .unwrap();
    assert_same_lines(&lines_a, &lines_b);
}

#[test]
fn smoothing_recovers_the_ridge_of_a_noisy_ellipsoid() {
    let mesh = ellipsoid();
    let h = mesh.mean_edge_length();
    let noisy = generate::with_normal_noise(&mesh, 0.2, 5).unwrap();
    let unsmoothed = ExtremalityTracer {
        smooth_steps: 0,
        ..Default::default()
    }
    .extract(&noisy, &mut Silent)
    .unwrap();
    let smoothed = ExtremalityTracer {
        presmooth_steps: 3,
        smooth_steps: 5,
        ..Default::default()
    }
    .extract(&noisy, &mut Silent)
    .unwrap();
    let points = all_points(&smoothed);
    let mean = mean_plane_distance(&points) / diagonal();
    let covered = coverage(&points, 2, 2.0 * h);
    let unsmoothed_mean = mean_plane_distance(&all_points(&unsmoothed)) / diagonal();
    eprintln!(
        "noise 0.2 h: unsmoothed {} lines, mean distance {:.3}%; presmooth 3 + 5 steps: {} lines, mean distance {:.3}%, coverage {:.3}",
        unsmoothed.len(),
        100.0 * unsmoothed_mean,
        smoothed.len(),
        100.0 * mean,
        covered
    );
    assert!(mean < 0.005, "{mean}");
    assert!(covered > 0.9, "{covered}");
    // Without smoothing the noise scatters lines all over the surface.
    assert!(
        unsmoothed.len() > 100 && unsmoothed_mean > 0.02,
        "{unsmoothed_mean}"
    );
}

/// `mesh` with its vertices and its faces listed in random orders (each face keeps
/// its corners' cyclic order).
fn shuffled(mesh: &Mesh, seed: u64) -> Mesh {
    let mut rng = StdRng::seed_from_u64(seed);
    let soup = mesh.to_soup();
    let mut order: Vec<usize> = (0..soup.positions.len()).collect();
    order.shuffle(&mut rng);
    let mut rank = vec![0; order.len()];
    for (k, &v) in order.iter().enumerate() {
        rank[v] = k as u32;
    }
    let mut triangles: Vec<[u32; 3]> = soup
        .triangles
        .iter()
        .map(|t| t.map(|v| rank[v as usize]))
        .collect();
    triangles.shuffle(&mut rng);
    let soup = TriangleSoup {
        positions: order.iter().map(|&v| soup.positions[v]).collect(),
        triangles,
        ..TriangleSoup::default()
    };
    Mesh::from_soup(soup).unwrap().0
}

#[test]
fn ridges_of_a_real_mesh_do_not_depend_on_its_vertex_and_face_numbering() {
    // The same surface numbered another way gives the same lines, perhaps listed
    // in another order or direction: as many, with as many points each, and every
    // point within 1e-12 of the diagonal of a point of the other lines. (Morse
    // lines do depend on the numbering: it breaks ties between equal values.) The
    // bunny gets spikes, so that curvature outliers are repaired from their rings.
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../meshes/bunny.obj");
    let mut soup = crestline::io::read_mesh(&path).unwrap();
    let centre = soup
        .positions
        .iter()
        .fold(Vector::zeros(), |s, p| s + p.coords)
        / soup.positions.len() as f64;
    for v in (0..soup.positions.len()).step_by(997) {
        let p = soup.positions[v];
        soup.positions[v] = p + (p.coords - centre) * 0.3;
    }
    let mesh = Mesh::from_soup(soup).unwrap().0;
    let repaired = ShapeOperator.estimate(&mesh).unwrap().unreliable;
    assert!(repaired.iter().filter(|&&u| u).count() > 10);
    let renumbered = shuffled(&mesh, 17);
    assert!((0..100).any(|v| mesh.positions()[v] != renumbered.positions()[v]));
    let a = ExtremalityTracer::default()
        .extract(&mesh, &mut Silent)
        .unwrap();
    let b = ExtremalityTracer::default()
        .extract(&renumbered, &mut Silent)
        .unwrap();
    assert!(a.len() > 20);
    assert_eq!(a.len(), b.len());
    let sizes = |lines: &FeatureLines| {
        let mut sizes: Vec<usize> = lines.iter().map(|l| l.points.len()).collect();
        sizes.sort_unstable();
        sizes
    };
    assert_eq!(sizes(&a), sizes(&b));
    let tolerance = 1e-12 * mesh.bounding_box().diagonal();
    let (points_a, points_b) = (all_points(&a), all_points(&b));
    for (from, to) in [(&points_a, &points_b), (&points_b, &points_a)] {
        for p in from {
            let nearest = to
                .iter()
                .map(|q| (p - q).norm())
                .fold(f64::INFINITY, f64::min);
            assert!(nearest < tolerance, "{p} is {nearest} from the other lines");
        }
    }
}

#[test]
fn real_meshes_give_lines() {
    for name in [
        "bunny.obj",
        "cow.obj",
        "fsaverage5_pial_left.obj",
        "airplane.obj",
    ] {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../meshes")
            .join(name);
        let soup = crestline::io::read_mesh(&path).unwrap();
        let mesh = Mesh::from_soup(soup).unwrap().0;
        let lines = ExtremalityTracer::default()
            .extract(&mesh, &mut Silent)
            .unwrap();
        let ridges = lines.of_kind(LineKind::Ridge).count();
        let valleys = lines.of_kind(LineKind::Valley).count();
        eprintln!(
            "{name}: {ridges} ridges, {valleys} valleys, length {:.3}",
            lines.total_length()
        );
        assert!(ridges > 0 && valleys > 0, "{name}");
        let bbox = mesh.bounding_box();
        let slack = 1e-9 * bbox.diagonal();
        for p in all_points(&lines) {
            assert!((0..3).all(|i| p[i] >= bbox.min[i] - slack && p[i] <= bbox.max[i] + slack));
        }
    }
}

/// The exact curvature of the analytic ellipsoid as a field, as a caller with
/// curvature from elsewhere (an image, a formula) would build it.
fn exact_field(surface: &generate::AnalyticMesh) -> CurvatureField {
    CurvatureField::from_fn(surface.mesh.vertex_count(), |v| {
        let k = surface.exact[v.idx()];
        (k, k.d_max.cross(&k.d_min), false)
    })
}

#[test]
fn given_exact_curvature_traces_the_sharpest_principal_ellipse() {
    let surface = generate::ellipsoid(AXES, 30_000, Sampling::jittered(1)).unwrap();
    let field = exact_field(&surface);
    let mesh = &surface.mesh;
    let input = SurfaceWithCurvature {
        mesh,
        curvature: &field,
    };
    let lines = ExtremalityTracer::default()
        .extract(&input, &mut Silent)
        .unwrap();
    let points = all_points(&lines);
    let mean = mean_plane_distance(&points) / diagonal();
    eprintln!(
        "exact curvature: {} lines, mean plane distance {:.4}% of the diagonal",
        lines.len(),
        100.0 * mean
    );
    assert_eq!(lines.len(), 1);
    assert!(lines.lines[0].closed && lines.lines[0].kind == LineKind::Ridge);
    assert!(mean < 0.0002, "{mean}");
    assert!(coverage(&points, 2, 2.0 * mesh.mean_edge_length()) > 0.98);
    // The estimator is not consulted: the same call with a failing one works.
    let refuses = ExtremalityTracer {
        estimator: Arc::new(Refuses),
        ..Default::default()
    };
    assert_eq!(refuses.extract(&input, &mut Silent).unwrap(), lines);
}

/// An estimator that always fails, to show which entry points use the estimator.
struct Refuses;

impl CurvatureEstimator for Refuses {
    fn estimate(&self, _: &Mesh) -> crestline::Result<CurvatureField> {
        Err(crestline::Error::Argument("not to be called".into()))
    }
}

#[test]
fn given_curvature_must_fit_the_mesh_and_excludes_presmoothing() {
    let surface = generate::ellipsoid(AXES, 2_000, Sampling::Regular).unwrap();
    let mut field = exact_field(&surface);
    let presmoothing = ExtremalityTracer {
        presmooth_steps: 2,
        ..Default::default()
    };
    let err = presmoothing
        .trace_with_curvature(&surface.mesh, &field, &mut Silent)
        .unwrap_err();
    assert!(err.to_string().contains("presmooth"), "{err}");
    field.k_max.pop();
    let err = ExtremalityTracer::default()
        .trace_with_curvature(&surface.mesh, &field, &mut Silent)
        .unwrap_err();
    assert!(err.to_string().contains("vertices"), "{err}");
}

#[test]
fn line_points_keep_their_place_on_the_surface_and_the_curvature_there() {
    let surface = generate::ellipsoid(AXES, 8_000, Sampling::jittered(3)).unwrap();
    let mesh = &surface.mesh;
    let field = ShapeOperator.estimate(mesh).unwrap();
    for presmooth_steps in [0, 2] {
        let tracer = ExtremalityTracer {
            all_extrema: true,
            threshold: 0.5,
            presmooth_steps,
            ..Default::default()
        };
        let lines = tracer.extract(mesh, &mut Silent).unwrap();
        assert!(lines.len() >= 3);
        for line in &lines {
            assert_eq!(line.locations.len(), line.points.len());
            for (at, p) in line.locations.iter().zip(&line.points) {
                assert!((at.position(mesh) - p).norm() < 1e-12, "{at:?} vs {p}");
                assert!(!matches!(at, SurfaceLocation::Vertex { .. }));
            }
            // Without presmoothing the values are the field's, interpolated.
            if presmooth_steps == 0 {
                for (at, k) in line.locations.iter().zip(&line.values["k_max"]) {
                    assert!((at.interpolate(mesh, &field.k_max) - k).abs() < 1e-12);
                }
            }
            assert_eq!(line.values["k_min"].len(), line.points.len());
        }
    }
    // Faired points leave the surface: no locations then.
    let faired = ExtremalityTracer {
        fair: Some(Default::default()),
        ..Default::default()
    };
    let lines = faired.extract(mesh, &mut Silent).unwrap();
    assert!(!lines.is_empty() && lines.iter().all(|l| l.locations.is_empty()));
}

/// The ellipsoid rotated, moved and scaled by 1000, and how to map its points back.
fn big_rotated_ellipsoid() -> (Mesh, impl Fn(&Point) -> Point) {
    let motion = motion();
    let mesh = transformed(&ellipsoid(), |p| motion * (p * 1000.0));
    (mesh, move |p: &Point| {
        motion.inverse_transform_point(p) / 1000.0
    })
}

/// The mean distance of `lines` (on the big ellipsoid `mesh`, mapped `back`)
/// from the principal plane as a share of the diagonal, and their coverage of the
/// ridge ellipse, printed under `label`.
fn ridge_accuracy(
    label: &str,
    lines: &FeatureLines,
    mesh: &Mesh,
    back: impl Fn(&Point) -> Point,
) -> (f64, f64) {
    let points: Vec<Point> = all_points(lines).iter().map(back).collect();
    let mean = mean_plane_distance(&points) / diagonal();
    let h = mesh.mean_edge_length() / 1000.0;
    let covered = coverage(&points, 2, 2.0 * h);
    eprintln!(
        "{label}: {} lines, mean plane distance {:.5}% of the diagonal, coverage {:.4}",
        lines.len(),
        100.0 * mean,
        covered
    );
    (mean, covered)
}

fn jet_tracer() -> ExtremalityTracer {
    ExtremalityTracer::with_estimator(Estimator::JetFit)
}

/// With extremalities from the fitted jet the ridge of a clean irregular
/// ellipsoid lies on its principal plane to a few millionths of the diagonal.
#[test]
fn jet_extremalities_put_the_ridge_on_the_principal_plane() {
    let (mesh, back) = big_rotated_ellipsoid();
    let lines = jet_tracer().extract(&mesh, &mut Silent).unwrap();
    let (mean, covered) = ridge_accuracy("jet path", &lines, &mesh, &back);
    assert!(mean < 0.00002, "{mean}");
    assert!(covered >= 0.98, "{covered}");
    assert_eq!(lines.len(), 1);
    assert!(lines.lines[0].closed && lines.lines[0].kind == LineKind::Ridge);
}

/// The jet path keeps the robustness to noise of the discrete path: with normal
/// noise of 0.2 mean edge lengths, 3 presmoothing and 5 extremality smoothing steps
/// recover the ridge.
#[test]
fn jet_extremalities_recover_the_ridge_of_a_noisy_ellipsoid() {
    let (mesh, back) = big_rotated_ellipsoid();
    let noisy = generate::with_normal_noise(&mesh, 0.2, 5).unwrap();
    let tracer = ExtremalityTracer {
        presmooth_steps: 3,
        smooth_steps: 5,
        ..jet_tracer()
    };
    let lines = tracer.extract(&noisy, &mut Silent).unwrap();
    let (mean, covered) = ridge_accuracy("jet path, noise 0.2 h", &lines, &mesh, &back);
    assert!(mean < 0.002, "{mean}");
    assert!(covered >= 0.95, "{covered}");
}

/// The jet fit with the directions, and with them the fitted extremalities,
/// flipped at a random half of the vertices.
struct RandomJetSigns;

impl CurvatureEstimator for RandomJetSigns {
    fn estimate(&self, mesh: &Mesh) -> crestline::Result<CurvatureField> {
        let mut field = JetFit::default().estimate(mesh)?;
        let mut rng = StdRng::seed_from_u64(98);
        for v in 0..field.len() {
            for max in [true, false] {
                if rng.random_bool(0.5) {
                    field.flip_direction(crestline::mesh::VertexId(v as u32), max);
                }
            }
        }
        Ok(field)
    }
}

#[test]
fn jet_path_lines_do_not_depend_on_direction_signs() {
    let mesh = generate::torus(1.0, 0.35, 20_000, Sampling::jittered(6))
        .unwrap()
        .mesh;
    let tracer = |estimator: Arc<dyn CurvatureEstimator + Send + Sync>| ExtremalityTracer {
        estimator,
        threshold: 0.0,
        ..jet_tracer()
    };
    let lines_a = tracer(Arc::new(JetFit::default()))
        .extract(&mesh, &mut Silent)
        .unwrap();
    let lines_b = tracer(Arc::new(RandomJetSigns))
        .extract(&mesh, &mut Silent)
        .unwrap();
    assert_same_lines(&lines_a, &lines_b);
}

/// The jet path, fitted extremalities and residual weights included, gives the
/// same lines on a mesh scaled by 1000.
#[test]
fn jet_path_scaling_by_1000_gives_the_same_lines() {
    let mesh = ellipsoid();
    let big = transformed(&mesh, |p| p * 1000.0);
    let tracer = ExtremalityTracer {
        all_extrema: true,
        threshold: 0.5,
        ..jet_tracer()
    };
    let small_lines = tracer.extract(&mesh, &mut Silent).unwrap();
    let big_lines = tracer.extract(&big, &mut Silent).unwrap();
    assert!(!small_lines.is_empty());
    assert_eq!(small_lines.len(), big_lines.len());
    for (s, b) in small_lines.iter().zip(big_lines.iter()) {
        assert_eq!(s.points.len(), b.points.len());
        assert!((s.strength - b.strength).abs() < 1e-9 * s.strength.max(1.0));
        for (p, q) in s.points.iter().zip(&b.points) {
            assert!((p - q / 1000.0).norm() < 1e-9, "{p} vs {q}");
        }
    }
}

/// The default of line extraction (`auto`, through the options `ridges` uses)
/// takes the jet fit on the clean ellipsoid, with its precision, and the shape
/// operator, with the same lines, on the noisy one and on a scan.
#[test]
fn the_default_estimator_takes_the_jet_fit_only_on_clean_meshes() {
    use crestline::curvature::AutoEstimator;
    use crestline::jobs::{ridges, RidgesOptions, Surface};

    let (mesh, back) = big_rotated_ellipsoid();
    assert!(AutoEstimator::is_clean(&mesh));
    let defaults = RidgesOptions::default();
    let lines = ridges(&Surface::of_mesh(mesh.clone()), &defaults, &mut Silent).unwrap();
    let (mean, covered) = ridge_accuracy("default, clean", &lines, &mesh, &back);
    assert!(mean < 0.00002, "{mean}");
    assert!(covered >= 0.98, "{covered}");

    // Noise of a twentieth of the mean edge, presmoothed: the shape operator's
    // lines, point for point.
    let noisy = generate::with_normal_noise(&mesh, 0.05, 3).unwrap();
    let noisy_options = |estimator| RidgesOptions {
        estimator,
        presmooth: 3,
        smooth_steps: Some(5),
        ..RidgesOptions::default()
    };
    let surface = Surface::of_mesh(noisy);
    let by_default = ridges(&surface, &noisy_options(Estimator::Auto), &mut Silent).unwrap();
    let by_shape = ridges(
        &surface,
        &noisy_options(Estimator::ShapeOperator),
        &mut Silent,
    )
    .unwrap();
    assert_same_lines(&by_default, &by_shape);
    let (mean, _) = ridge_accuracy("default, noise 0.05 h", &by_default, &mesh, &back);
    assert!(mean < 0.001, "{mean}");

    let bunny = crestline::io::read_mesh(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../meshes/bunny.obj"
    )))
    .unwrap();
    assert!(!AutoEstimator::is_clean(&Mesh::from_soup(bunny).unwrap().0));
}

/// At the mesh's feature scale (`RidgesOptions::scale`: the surface smoothed
/// lightly, then its curvature tensor field and its extremalities, all for times
/// in world units) the ridge of the irregular ellipsoid is its sharpest principal
/// ellipse, one closed line on the principal plane.
#[test]
fn ridges_at_the_feature_scale_keep_the_ridge_of_an_ellipsoid() {
    let (mesh, back) = big_rotated_ellipsoid();
    let options = jobs::RidgesOptions {
        scale: Some(jobs::mesh_info(&mesh, &mut Silent).feature_scale),
        ..Default::default()
    };
    let surface = jobs::Surface::of_mesh(mesh.clone());
    let lines = jobs::ridges(&surface, &options, &mut Silent).unwrap();
    let (mean, covered) = ridge_accuracy("at the feature scale", &lines, &mesh, &back);
    assert!(mean < 0.0005, "{mean}");
    assert!(covered >= 0.98, "{covered}");
    assert_eq!(lines.len(), 1);
    assert!(lines.lines[0].closed && lines.lines[0].kind == LineKind::Ridge);
}
