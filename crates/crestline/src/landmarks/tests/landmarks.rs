//! Anatomical landmarks from crest lines: on an ellipsoid, whose ridge is the
//! principal ellipse of its two longest axes, the extremal points are the four
//! vertices of that ellipse and the curvature maxima its two sharpest ends, from
//! a mesh and from an image alike; landmarks move with the surface; the 3D
//! Slicer, JSON and CSV files hold what they should.

use crate::common;

use crate::crest_lines::crest_lines;
use crate::landmarks::{
    landmarks, read_landmarks, LandmarkFormat, LandmarkKind, LandmarkOptions, Landmarks,
    PointLandmark, Space,
};
use crate::lines::{FeatureLines, LineExtractor, LineKind};
use crate::mesh::generate::{self, Sampling};
use crate::progress::Silent;
use crate::ridges::ExtremalityTracer;
use crate::volume::Volume;
use crate::Point;
use common::transformed;
use nalgebra::{Isometry3, Matrix3, Translation3, UnitQuaternion};

const AXES: [f64; 3] = [1.0, 0.7, 0.45];

/// The landmarks of the ridges of the ellipsoid with `AXES` (a jittered mesh).
fn ellipsoid_landmarks(motion: &Isometry3<f64>) -> Landmarks {
    let mesh = generate::ellipsoid(AXES, 30_000, Sampling::jittered(3))
        .unwrap()
        .mesh;
    let mesh = transformed(&mesh, |p| motion * p);
    let lines = ExtremalityTracer::default()
        .extract(&mesh, &mut Silent)
        .unwrap();
    let h = mesh.mean_edge_length();
    // Curvature maxima at the scale of the ellipsoid (the ridge is 5.4 long);
    // the estimated curvature's noise makes maxima at the scale of a few edges.
    let options = LandmarkOptions {
        radius: 0.5,
        persistence: 2.0 * h,
    };
    landmarks(&lines, &options).unwrap()
}

fn of_kind(found: &Landmarks, kind: LandmarkKind) -> Vec<&PointLandmark> {
    found.points.iter().filter(|p| p.kind == kind).collect()
}

/// The distance from `p` to the nearest of `targets`.
fn nearest(p: &Point, targets: &[Point]) -> f64 {
    targets
        .iter()
        .map(|t| (p - t).norm())
        .fold(f64::INFINITY, f64::min)
}

/// Each target has a point within `tolerance`, and every point is within
/// `tolerance` of a target.
fn assert_at(points: &[Point], targets: &[Point], tolerance: f64, what: &str) {
    for p in points {
        let d = nearest(p, targets);
        assert!(
            d < tolerance,
            "{what}: a point {d} from every expected one, at {p:?}"
        );
    }
    for t in targets {
        let d = nearest(t, points);
        assert!(d < tolerance, "{what}: nothing within {d} of {t:?}");
    }
}

/// The vertices of the ellipse of axes `a`, `b` in the plane z = 0.
fn vertices(a: f64, b: f64) -> [Point; 4] {
    [
        Point::new(a, 0.0, 0.0),
        Point::new(-a, 0.0, 0.0),
        Point::new(0.0, b, 0.0),
        Point::new(0.0, -b, 0.0),
    ]
}

#[test]
fn the_extremal_points_of_an_ellipsoid_are_the_vertices_of_its_ridge() {
    let found = ellipsoid_landmarks(&Isometry3::identity());
    let positions =
        |kind| -> Vec<Point> { of_kind(&found, kind).iter().map(|p| p.position).collect() };
    let extremal = positions(LandmarkKind::Extremal);
    let maxima = positions(LandmarkKind::CurvatureMaximum);
    println!(
        "ellipsoid mesh: {} extremal points, {} curvature maxima, {} lines",
        extremal.len(),
        maxima.len(),
        found.lines.len()
    );
    // Along the ridge ellipse (z = 0) the other curvature is extremal at its four
    // vertices; k_max is largest at the ends of the longest axis.
    assert_at(
        &extremal,
        &vertices(AXES[0], AXES[1]),
        0.03,
        "extremal points",
    );
    assert_at(
        &maxima,
        &vertices(AXES[0], AXES[1])[..2],
        0.03,
        "curvature maxima",
    );
    assert!(found
        .lines
        .iter()
        .all(|l| l.kind == LineKind::Ridge && l.convex));
    // The ridge's curvature there: k_max = a / c² at (±a, 0, 0).
    let sharpest = AXES[0] / (AXES[2] * AXES[2]);
    for p in of_kind(&found, LandmarkKind::CurvatureMaximum) {
        assert!(
            (p.curvature - sharpest).abs() < 0.1 * sharpest,
            "k_max {} at a maximum, exactly {sharpest}",
            p.curvature
        );
    }
}

#[test]
fn landmarks_move_with_the_surface() {
    let motion = Isometry3::from_parts(
        Translation3::new(5.0, -2.0, 9.0),
        UnitQuaternion::from_euler_angles(0.7, 0.4, -1.2),
    );
    let still = ellipsoid_landmarks(&Isometry3::identity());
    let moved = ellipsoid_landmarks(&motion);
    assert_eq!(still.points.len(), moved.points.len());
    for kind in [LandmarkKind::Extremal, LandmarkKind::CurvatureMaximum] {
        let targets: Vec<Point> = of_kind(&moved, kind).iter().map(|p| p.position).collect();
        let mut distances: Vec<f64> = of_kind(&still, kind)
            .iter()
            .map(|p| nearest(&(motion * p.position), &targets))
            .collect();
        distances.sort_by(f64::total_cmp);
        let median = distances[distances.len() / 2];
        println!("{kind:?}: median distance after the motion {median:.2e}");
        assert!(median < 1e-6, "{kind:?}: median distance {median}");
    }
}

#[test]
fn crest_lines_of_an_image_give_the_same_landmarks() {
    // The ellipsoid as a bright object in an image, axes 16, 11, 7 voxels.
    let (a, b, c) = (16.0, 11.0, 7.0);
    let dims = [48usize, 38, 30];
    let origin = dims.map(|n| -(n as f64 - 1.0) / 2.0);
    let grid = Volume::new(
        dims,
        [1.0; 3],
        origin,
        Matrix3::identity(),
        vec![0.0; 48 * 38 * 30],
    )
    .unwrap();
    let samples = (0..grid.len())
        .map(|at| {
            let index = [at % 48, (at / 48) % 38, at / (48 * 38)].map(|x| x as f64);
            let p = grid.index_to_world(index);
            -((p.x / a).powi(2) + (p.y / b).powi(2) + (p.z / c).powi(2)) as f32
        })
        .collect();
    let volume = grid.with_samples(samples).unwrap();
    let mut lines = FeatureLines::new("ellipsoid".to_string());
    lines.lines = crest_lines(&volume, -1.0, 1.5).unwrap();
    let options = LandmarkOptions {
        radius: 5.0,
        persistence: 2.0,
    };
    let found = landmarks(&lines, &options).unwrap();
    let extremal: Vec<Point> = of_kind(&found, LandmarkKind::Extremal)
        .iter()
        .map(|p| p.position)
        .collect();
    println!("ellipsoid image: {} extremal points", extremal.len());
    // Smoothing by σ = 1.5 moves the isosurface inwards by a fraction of a voxel.
    assert_at(&extremal, &vertices(a, b), 1.0, "extremal points");
}

/// A small set of landmarks: one ridge with two points.
fn sample_landmarks() -> Landmarks {
    let found = ellipsoid_landmarks(&Isometry3::identity());
    assert!(!found.points.is_empty() && !found.lines.is_empty());
    found
}

#[test]
fn slicer_markups_hold_the_schema_fields_and_read_back_as_points_and_curves() {
    let found = sample_landmarks();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("ellipsoid.mrk.json");
    assert_eq!(
        LandmarkFormat::from_path(&path).unwrap(),
        LandmarkFormat::Slicer
    );
    found.write(&path, Space::Ras).unwrap();
    let document: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
    // The schema's required fields and the types and values it allows.
    assert!(document["@schema"]
        .as_str()
        .unwrap()
        .contains("markups-schema-v1.0.3.json"));
    let markups = document["markups"].as_array().unwrap();
    assert_eq!(markups.len(), 1 + found.lines.len());
    for markup in markups {
        let kind = markup["type"].as_str().unwrap();
        assert!(["Fiducial", "Curve", "ClosedCurve"].contains(&kind));
        assert_eq!(markup["coordinateSystem"], "LPS");
        assert_eq!(markup["coordinateUnits"], "mm");
        for point in markup["controlPoints"].as_array().unwrap() {
            assert!(point["id"].is_string() && point["label"].is_string());
            assert_eq!(point["position"].as_array().unwrap().len(), 3);
            assert_eq!(point["positionStatus"], "defined");
        }
    }
    // Read back: the fiducials are the point landmarks, the curves the lines, in
    // LPS (x and y negated from RAS).
    let position = |v: &serde_json::Value| -> Point {
        let p: Vec<f64> = v["position"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        Point::new(-p[0], -p[1], p[2])
    };
    let fiducials = markups[0]["controlPoints"].as_array().unwrap();
    assert_eq!(markups[0]["type"], "Fiducial");
    assert_eq!(fiducials.len(), found.points.len());
    for (read, point) in fiducials.iter().zip(&found.points) {
        assert!((position(read) - point.position).norm() < 1e-12);
        assert_eq!(read["label"], format!("{}-{}", point.kind.name(), point.id));
    }
    for (markup, line) in markups[1..].iter().zip(&found.lines) {
        let points = markup["controlPoints"].as_array().unwrap();
        assert_eq!(points.len(), line.points.len());
        assert!(points
            .iter()
            .zip(&line.points)
            .all(|(r, p)| (position(r) - p).norm() < 1e-12));
    }
}

#[test]
fn json_round_trips_and_csv_has_one_row_per_point() {
    let found = sample_landmarks();
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("landmarks.json");
    found.write(&json, Space::Lps).unwrap();
    let (read, space) = read_landmarks(&json).unwrap();
    assert_eq!(space, Space::Lps);
    assert_eq!(read.space, Some(Space::Lps), "the frame the file declares");
    assert_eq!(
        read,
        Landmarks {
            space: Some(Space::Lps),
            ..found.clone()
        }
    );
    let csv = dir.path().join("landmarks.csv");
    found.write(&csv, Space::Lps).unwrap();
    let text = std::fs::read_to_string(&csv).unwrap();
    let rows: Vec<&str> = text.lines().collect();
    assert_eq!(rows[0], "id,kind,x,y,z,curvature,line,space");
    assert_eq!(rows.len(), 1 + found.points.len());
    let first: Vec<&str> = rows[1].split(',').collect();
    assert_eq!(first.len(), 8);
    assert_eq!(first[7], "LPS");
    assert_eq!(first[1], found.points[0].kind.name());
    assert_eq!(first[2].parse::<f64>().unwrap(), found.points[0].position.x);
}

#[test]
fn bad_options_and_files_are_errors() {
    let lines = FeatureLines::new(String::new());
    for (radius, persistence) in [(0.0, 1.0), (1.0, f64::NAN), (-1.0, 1.0)] {
        let error = landmarks(
            &lines,
            &LandmarkOptions {
                radius,
                persistence,
            },
        )
        .unwrap_err();
        assert!(error.to_string().contains("finite and positive"), "{error}");
    }
    assert!(LandmarkFormat::from_path(std::path::Path::new("points.txt")).is_err());
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("lines.json");
    std::fs::write(&path, "{\"format\": \"crestline-lines/1\", \"lines\": []}").unwrap();
    let error = read_landmarks(&path).unwrap_err().to_string();
    assert!(error.contains("lines.json"), "{error}");
}
