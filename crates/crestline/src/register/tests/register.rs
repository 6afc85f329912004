//! Rigid registration of crest-line point sets: known motions recovered from
//! synthetic space curves (also with a missing chunk and outliers), from the ridge
//! lines of a real mesh and its moved copy, and from the crest lines of the MNI152
//! template and a moved, resampled copy; the transform files; bad input.

use crate::common;

use std::f64::consts::TAU;
use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::lines::{LineExtractor, Polyline};
use crate::mesh::Mesh;
use crate::progress::Silent;
use crate::register::{
    best_rigid_fit, register, rotation_angle, PointSet, Registration, RegistrationOptions,
    RigidTransform,
};
use crate::ridges::ExtremalityTracer;
use crate::volume::Volume;
use crate::{Point, Vector};
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use nalgebra::{Rotation3, Unit};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

/// `angle` degrees about the skew `axis`, then `translation`.
fn motion(axis: [f64; 3], angle: f64, translation: Vector) -> RigidTransform {
    let axis = Unit::new_normalize(Vector::from(axis));
    RigidTransform::new(
        Rotation3::from_axis_angle(&axis, angle.to_radians()),
        translation,
    )
}

/// Rotation error (degrees) and translation error of `found` against `truth`.
fn errors(found: &RigidTransform, truth: &RigidTransform) -> (f64, f64) {
    let angle = rotation_angle(&(found.rotation * truth.rotation.inverse())).to_degrees();
    (angle, (found.translation - truth.translation).norm())
}

fn diagonal(points: &[Point]) -> f64 {
    let (low, high) = bounds(points);
    (high - low).norm()
}

fn bounds(points: &[Point]) -> (Point, Point) {
    let low = points
        .iter()
        .fold(Point::from([f64::MAX; 3]), |a, p| a.inf(p));
    let high = points
        .iter()
        .fold(Point::from([f64::MIN; 3]), |a, p| a.sup(p));
    (low, high)
}

fn line_set(points: Vec<Point>) -> PointSet {
    PointSet {
        line_points: points,
        key_points: Vec::new(),
    }
}

fn moved(points: &[Point], transform: &RigidTransform) -> Vec<Point> {
    points.iter().map(|p| transform.apply(p)).collect()
}

/// Register `moving` onto `fixed`, print the figures under `name` and check that
/// `truth` is recovered within `max_degrees` and `max_distance`.
fn recover(
    name: &str,
    fixed: &PointSet,
    moving: &PointSet,
    truth: &RigidTransform,
    (max_degrees, max_distance): (f64, f64),
) -> Registration {
    let start = Instant::now();
    let found = register(fixed, moving, &RegistrationOptions::default()).unwrap();
    let (angle, shift) = errors(&found.transform, truth);
    eprintln!(
        "{name}: rotation error {angle:.4}°, translation error {shift:.4} (limits {max_degrees}°, \
         {max_distance:.4}), rms {:.4}, matched {:.1}%, {} iterations, {:.2} s",
        found.rms,
        100.0 * found.matched_share,
        found.iterations,
        start.elapsed().as_secs_f64()
    );
    assert!(angle < max_degrees, "{name}: rotation off by {angle}°");
    assert!(shift < max_distance, "{name}: translation off by {shift}");
    found
}

// ---------------------------------------------------------------- synthetic curves

/// Three space curves with no symmetry between them: a (2, 3) torus knot, a helix
/// beside it and a tilted elliptic arc, 3 300 points in order along each curve,
/// sampled from `phase` (a share of the sampling step, 0 to 1) on.
fn sampled_curves(phase: f64) -> Vec<Point> {
    let knot = (0..1800).map(|i| {
        let t = TAU * (i as f64 + phase) / 1800.0;
        let radius = 1.0 + 0.4 * (3.0 * t).cos();
        Point::new(
            radius * (2.0 * t).cos(),
            radius * (2.0 * t).sin(),
            0.4 * (3.0 * t).sin(),
        )
    });
    let helix = (0..800).map(|i| {
        let t = 2.0 * TAU * (i as f64 + phase) / 800.0;
        Point::new(1.9 + 0.3 * t.cos(), 0.2 + 0.3 * t.sin(), -0.6 + 0.1 * t)
    });
    let arc = (0..700).map(|i| {
        let t = 0.5 * TAU * (i as f64 + phase) / 700.0;
        Point::new(
            -0.5 + 1.2 * t.cos(),
            -1.7 + 0.5 * t.sin(),
            0.3 * t.cos() + 0.8,
        )
    });
    knot.chain(helix).chain(arc).collect()
}

fn curves() -> Vec<Point> {
    sampled_curves(0.0)
}

/// 40° about a skew axis and a third of the curves' diagonal.
fn curve_motion(diagonal: f64) -> RigidTransform {
    let direction = Vector::new(0.6, -0.35, 0.72).normalize();
    motion([1.0, 2.0, -0.5], 40.0, direction * diagonal / 3.0)
}

/// `points` without a contiguous fifth from 40% on, plus 10% (of the original
/// count) points uniform in their bounding box.
fn damaged(points: &[Point]) -> Vec<Point> {
    let n = points.len();
    let mut kept: Vec<Point> = points[..2 * n / 5]
        .iter()
        .chain(&points[3 * n / 5..])
        .copied()
        .collect();
    let (low, high) = bounds(points);
    let mut rng = StdRng::seed_from_u64(17);
    kept.extend((0..n / 10).map(|_| {
        Point::from(std::array::from_fn::<f64, 3, _>(|a| {
            rng.random_range(low[a]..high[a])
        }))
    }));
    kept
}

#[test]
fn a_large_motion_of_space_curves_is_recovered() {
    let fixed = curves();
    let size = diagonal(&fixed);
    let truth = curve_motion(size);
    let moving = moved(&fixed, &truth.inverse());
    let limits = (0.5, 0.01 * size);
    let found = recover(
        "curves",
        &line_set(fixed.clone()),
        &line_set(moving),
        &truth,
        limits,
    );
    assert!(found.rms < 1e-6 * size, "rms {}", found.rms);
    assert!(
        found.matched_share > 0.999,
        "matched {}",
        found.matched_share
    );
}

#[test]
fn a_half_turn_is_found_from_the_principal_axes() {
    let fixed = sampled_curves(0.0);
    let size = diagonal(&fixed);
    let truth = motion([-0.3, 0.8, 1.0], 150.0, Vector::new(0.2, 0.1, -0.3) * size);
    let moving = moved(&sampled_curves(0.5), &truth.inverse());
    recover(
        "curves, 150°",
        &line_set(fixed),
        &line_set(moving),
        &truth,
        (0.5, 0.01 * size),
    );
}

#[test]
fn a_motion_is_recovered_with_a_missing_chunk_and_outliers() {
    let fixed = curves();
    let size = diagonal(&fixed);
    let truth = curve_motion(size);
    // Sampled between the fixed points, so that no point has an exact counterpart.
    let moving = damaged(&moved(&sampled_curves(0.5), &truth.inverse()));
    let limits = (0.5, 0.01 * size);
    let (fixed, moving) = (line_set(fixed), line_set(moving));
    let found = recover(
        "curves, 20% cut, 10% outliers",
        &fixed,
        &moving,
        &truth,
        limits,
    );
    // 80% of the original points remain among 90%: about 89% have a counterpart.
    assert!(
        (0.75..0.95).contains(&found.matched_share),
        "matched {}",
        found.matched_share
    );
    // Deterministic: the same input gives the same transform, bit for bit.
    let again = register(&fixed, &moving, &RegistrationOptions::default()).unwrap();
    assert_eq!(again, found);
    let back = recover(
        "curves back, 20% cut, 10% outliers",
        &moving,
        &fixed,
        &truth.inverse(),
        limits,
    );
    let (angle, shift) = errors(
        &back.transform.after(&found.transform),
        &RigidTransform::identity(),
    );
    eprintln!("there and back: {angle:.4}°, {shift:.5}");
    assert!(angle < 0.5 && shift < 0.01 * size);
}

#[test]
fn key_points_in_the_coarse_stage_keep_the_motion_found() {
    let fixed = curves();
    let size = diagonal(&fixed);
    let truth = curve_motion(size);
    let keys: Vec<Point> = fixed.iter().step_by(97).copied().collect();
    let fixed_set = PointSet {
        line_points: fixed.clone(),
        key_points: keys.clone(),
    };
    let moving_set = PointSet {
        line_points: damaged(&moved(&sampled_curves(0.5), &truth.inverse())),
        key_points: moved(&keys, &truth.inverse()),
    };
    recover(
        "curves with key points",
        &fixed_set,
        &moving_set,
        &truth,
        (0.5, 0.01 * size),
    );
    // Key points that all coincide cannot fix a rotation and are not used.
    let fixed_set = PointSet {
        key_points: vec![keys[0]; 4],
        ..fixed_set
    };
    let moving_set = PointSet {
        key_points: vec![truth.inverse().apply(&keys[0]); 4],
        ..moving_set
    };
    recover(
        "curves with coincident key points",
        &fixed_set,
        &moving_set,
        &truth,
        (0.5, 0.01 * size),
    );
}

// ---------------------------------------------------------------- a real mesh

fn all_points(lines: &[Polyline]) -> Vec<Point> {
    lines
        .iter()
        .flat_map(|l| l.points.iter().copied())
        .collect()
}

/// Distance from each of `points` to the closest of `to`.
fn closest_distances(points: &[Point], to: &[Point]) -> Vec<f64> {
    let coordinates: Vec<[f64; 3]> = to.iter().map(|p| [p.x, p.y, p.z]).collect();
    let tree: ImmutableKdTree<f64, 3> = ImmutableKdTree::new_from_slice(&coordinates);
    points
        .iter()
        .map(|p| {
            tree.nearest_one::<SquaredEuclidean>(&[p.x, p.y, p.z])
                .distance
                .sqrt()
        })
        .collect()
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

#[test]
fn ridge_lines_of_a_moved_mesh_register_onto_the_original() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../meshes/bunny.obj");
    let mesh = Mesh::from_soup(crate::io::read_mesh(&path).unwrap())
        .unwrap()
        .0;
    let size = mesh.bounding_box().diagonal();
    let truth = motion(
        [-0.4, 1.0, 0.7],
        35.0,
        Vector::new(0.2, 0.25, -0.1).normalize() * size / 3.0,
    );
    let moved_mesh = common::transformed(&mesh, |p| truth.inverse().apply(p));
    let tracer = ExtremalityTracer::default();
    let fixed = all_points(&tracer.extract(&mesh, &mut Silent).unwrap().lines);
    let moving = all_points(&tracer.extract(&moved_mesh, &mut Silent).unwrap().lines);
    let gaps = closest_distances(&moved(&moving, &truth), &fixed);
    let median_gap = median(gaps);
    eprintln!(
        "bunny: {} and {} line points; median distance between corresponding points under \
         the true motion {median_gap:.3e} ({:.3e} of the diagonal)",
        fixed.len(),
        moving.len(),
        median_gap / size
    );
    assert!(median_gap < 1e-3 * size);
    let limits = (0.5, 0.01 * size);
    let fixed = line_set(fixed);
    recover("bunny", &fixed, &line_set(moving.clone()), &truth, limits);
    recover(
        "bunny, 20% cut, 10% outliers",
        &fixed,
        &line_set(damaged(&moving)),
        &truth,
        limits,
    );
}

// ---------------------------------------------------------------- the MNI template

fn crest_points(volume: &Volume) -> Vec<Point> {
    all_points(&crate::crest_lines::crest_lines(volume, 60.0, 1.0).unwrap())
}

#[test]
fn crest_lines_of_a_moved_mni_template_register_onto_the_original() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../volumes/mni152_t1_1mm.nii.gz");
    let volume = crate::io::read_volume(&path).unwrap();
    let truth = motion(
        [0.3, -0.5, 0.8],
        10.0,
        Vector::new(5.0, -4.0, 5.0).normalize() * 8.0,
    );
    let start = Instant::now();
    let copy = common::resampled(&volume, &truth, |p| volume.interpolate(p));
    let resampling = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let fixed = crest_points(&volume);
    let moving = crest_points(&copy);
    eprintln!(
        "MNI152: resampled in {resampling:.2} s; {} and {} crest-line points in {:.2} s",
        fixed.len(),
        moving.len(),
        start.elapsed().as_secs_f64()
    );
    let found = recover(
        "MNI152",
        &line_set(fixed),
        &line_set(moving),
        &truth,
        (1.0, 1.0),
    );
    assert!(found.matched_share > 0.5, "matched {}", found.matched_share);
}

// ---------------------------------------------------------------- pieces

#[test]
fn rigid_transforms_compose_invert_and_give_their_matrix() {
    let a = motion([1.0, -2.0, 0.5], 70.0, Vector::new(3.0, -1.0, 2.0));
    let b = motion([0.0, 1.0, 1.0], -25.0, Vector::new(-0.5, 4.0, 1.0));
    let p = Point::new(0.3, -1.2, 2.5);
    assert!((a.after(&b).apply(&p) - a.apply(&b.apply(&p))).norm() < 1e-12);
    assert!((a.inverse().apply(&a.apply(&p)) - p).norm() < 1e-12);
    let homogeneous = a.to_matrix4() * p.to_homogeneous();
    assert!((Point::from_homogeneous(homogeneous).unwrap() - a.apply(&p)).norm() < 1e-12);
    assert_eq!(
        a.to_matrix4().row(3).transpose(),
        nalgebra::Vector4::new(0.0, 0.0, 0.0, 1.0)
    );
    assert!((a.angle_degrees() - 70.0).abs() < 1e-9);
    let flipped = a.flip_xy();
    let flip = |p: &Point| Point::new(-p.x, -p.y, p.z);
    assert!((flipped.apply(&flip(&p)) - flip(&a.apply(&p))).norm() < 1e-12);
}

#[test]
fn the_weighted_fit_is_exact_and_never_a_reflection() {
    let truth = motion([2.0, 1.0, -1.0], 123.0, Vector::new(1.0, 2.0, 3.0));
    let source = curves()[..50].to_vec();
    let mut target = moved(&source, &truth);
    // Points given no weight do not count, however far off they are.
    let mut weights = vec![1.0; source.len()];
    for i in (0..source.len()).step_by(7) {
        target[i] += Vector::new(5.0, -3.0, 8.0);
        weights[i] = 0.0;
    }
    let fit = best_rigid_fit(&source, &target, Some(&weights)).unwrap();
    let (angle, shift) = errors(&fit, &truth);
    assert!(angle < 1e-9 && shift < 1e-9, "{angle} {shift}");
    // A mirror image is fitted by a proper rotation.
    let mirrored: Vec<Point> = source.iter().map(|p| Point::new(-p.x, p.y, p.z)).collect();
    let fit = best_rigid_fit(&source, &mirrored, None).unwrap();
    assert!((fit.rotation.matrix().determinant() - 1.0).abs() < 1e-9);
    let err = best_rigid_fit(&source, &target, Some(&[1.0])).unwrap_err();
    assert!(err.to_string().contains("1 weights for 50"), "{err}");
}

fn example_registration() -> Registration {
    Registration {
        transform: motion([0.2, -1.0, 0.4], 12.0, Vector::new(4.0, -7.5, 2.25)),
        rms: 0.4,
        matched: 900,
        matched_share: 0.9,
        iterations: 31,
    }
}

#[test]
fn the_json_transform_reads_back() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.json");
    let registration = example_registration();
    registration.write(&path).unwrap();
    let value: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(value["coordinate_system"], "RAS");
    let matrix = registration.transform.to_matrix4();
    for row in 0..4 {
        for column in 0..4 {
            let read = value["matrix"][row][column].as_f64().unwrap();
            assert!((read - matrix[(row, column)]).abs() < 1e-15, "{read}");
        }
    }
    for axis in 0..3 {
        let read = value["translation"][axis].as_f64().unwrap();
        assert!((read - registration.transform.translation[axis]).abs() < 1e-14);
    }
    let degrees = value["rotation_degrees"].as_f64().unwrap();
    assert!((degrees - 12.0).abs() < 1e-9, "{degrees}");
    assert_eq!(value["rms"].as_f64(), Some(0.4));
    assert_eq!(value["matched_share"].as_f64(), Some(0.9));
}

#[test]
fn the_itk_transform_maps_fixed_lps_points_to_moving_lps_points() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.tfm");
    let registration = example_registration();
    registration.write(&path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(
        lines[..3],
        [
            "#Insight Transform File V1.0",
            "#Transform 0",
            "Transform: AffineTransform_double_3_3"
        ]
    );
    assert_eq!(lines[4], "FixedParameters: 0 0 0");
    let parameters: Vec<f64> = lines[3]
        .strip_prefix("Parameters: ")
        .unwrap()
        .split(' ')
        .map(|x| x.parse().unwrap())
        .collect();
    assert_eq!(parameters.len(), 12);
    // A point of the fixed scan, in RAS, and where the same anatomy is in the moving scan.
    let fixed_ras = Point::new(10.0, -20.0, 30.0);
    let moving_ras = registration.transform.inverse().apply(&fixed_ras);
    let lps = |p: &Point| Point::new(-p.x, -p.y, p.z);
    let x = lps(&fixed_ras);
    let mapped: Vec<f64> = (0..3)
        .map(|row| {
            (0..3).map(|c| parameters[3 * row + c] * x[c]).sum::<f64>() + parameters[9 + row]
        })
        .collect();
    let expected = lps(&moving_ras);
    for axis in 0..3 {
        assert!(
            (mapped[axis] - expected[axis]).abs() < 1e-9,
            "{mapped:?} vs {expected}"
        );
    }
}

#[test]
fn an_unknown_transform_extension_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.mat");
    let err = example_registration().write(&path).unwrap_err();
    assert!(err.to_string().contains(".json, .tfm"), "{err}");
    assert!(!path.exists());
}

#[test]
fn bad_input_is_an_error_naming_the_problem() {
    let good = line_set(curves());
    let options = RegistrationOptions::default();
    let expect =
        |fixed: &PointSet, moving: &PointSet, options: &RegistrationOptions, words: &str| {
            let err = register(fixed, moving, options).unwrap_err();
            assert!(matches!(err, crate::Error::Argument(_)), "{err:?}");
            assert!(
                err.to_string().contains(words),
                "'{err}' should mention '{words}'"
            );
        };
    expect(
        &line_set(Vec::new()),
        &good,
        &options,
        "fixed set has 0 line points",
    );
    expect(
        &good,
        &line_set(curves()[..2].to_vec()),
        &options,
        "moving set has 2 line points",
    );
    let mut nan = curves();
    nan[5].y = f64::NAN;
    expect(
        &good,
        &line_set(nan),
        &options,
        "moving line point 5 has a non-finite",
    );
    let key_nan = PointSet {
        line_points: curves(),
        key_points: vec![Point::new(f64::INFINITY, 0.0, 0.0)],
    };
    expect(
        &key_nan,
        &good,
        &options,
        "fixed key point 0 has a non-finite",
    );
    let line: Vec<Point> = (0..10)
        .map(|i| Point::new(i as f64, 2.0 * i as f64, 1.0))
        .collect();
    expect(
        &line_set(line),
        &good,
        &options,
        "fixed points lie on a line",
    );
    for (bad, words) in [
        (
            RegistrationOptions {
                min_overlap: 0.0,
                ..options
            },
            "`min_overlap` is 0",
        ),
        (
            RegistrationOptions {
                min_overlap: f64::NAN,
                ..options
            },
            "`min_overlap` is NaN",
        ),
        (
            RegistrationOptions {
                max_iterations: 0,
                ..options
            },
            "`max_iterations` is 0",
        ),
        (
            RegistrationOptions {
                coarse_points: 2,
                ..options
            },
            "`coarse_points` is 2",
        ),
        (
            RegistrationOptions {
                tolerance: -1.0,
                ..options
            },
            "`tolerance` is -1",
        ),
    ] {
        expect(&good, &good, &bad, words);
    }
}
