//! Crest lines are features of the shape, not of the grid: one bumpy ellipsoid
//! sampled at three voxel sizes, and moved off the grid by a fraction of a voxel,
//! has the same crest lines at the default (feature) scale; a moved rescan of the
//! MNI template keeps its landmarks.

use std::path::Path;

use crate::common;
use crate::compare::{compare, Features};
use crate::jobs::{
    crest_lines, image_units, landmarks, ridges, CrestLinesOptions, LandmarksOptions, LinesFrom,
    RidgesOptions, Surface,
};
use crate::mesh::generate::{self, Sampling};
use crate::mesh::Mesh;
use crate::progress::Silent;
use crate::register::RigidTransform;
use crate::volume::Volume;
use crate::{Point, Vector};
use nalgebra::{Matrix3, Rotation3};

/// The implicit bumpy ellipsoid: inside where the value is at least -1.
fn bumpy(p: Point) -> f64 {
    let ellipsoid = (p.x / 60.0).powi(2) + (p.y / 45.0).powi(2) + (p.z / 30.0).powi(2);
    let bumps = 0.04 * (p.x / 7.0).sin() * (p.y / 6.0).sin() * (p.z / 5.0).sin();
    let ripples = 0.004 * (p.x / 2.1 + p.y / 2.9).sin() * (p.z / 2.5).sin();
    -ellipsoid + bumps + ripples
}

/// `bumpy` moved by `shift`, sampled every `spacing` over the box ±(66, 51, 36).
fn sampled(spacing: f64, shift: Vector) -> Volume {
    let half = [66.0, 51.0, 36.0];
    let dims = half.map(|h| (2.0 * h / spacing).ceil() as usize + 1);
    let origin = half.map(|h| -h);
    let count = dims.iter().product();
    let grid = Volume::new(
        dims,
        [spacing; 3],
        origin,
        Matrix3::identity(),
        vec![0.0; count],
    );
    let grid = grid.unwrap();
    let [nx, ny, _] = dims;
    let samples = (0..count)
        .map(|at| {
            let index = [at % nx, (at / nx) % ny, at / (nx * ny)];
            bumpy(grid.index_to_world(index.map(|i| i as f64)) - shift) as f32
        })
        .collect();
    grid.with_samples(samples).unwrap()
}

/// The default crest lines of `volume`, and its feature scale.
fn default_lines(volume: &Volume) -> (Features, f64) {
    let scale = image_units(volume, -1.0, None, &mut Silent).unwrap().scale;
    let lines = crest_lines(volume, -1.0, &CrestLinesOptions::default(), &mut Silent).unwrap();
    (Features::of_lines(&lines), scale)
}

/// The smallest share of crest-line length, either way and of either kind, of
/// `a` within `tolerance` of `b`'s.
fn worst_share(a: &Features, b: &Features, tolerance: f64) -> f64 {
    let found = compare(a, b, tolerance);
    assert!(!found.lines.is_empty());
    for row in &found.lines {
        println!(
            "{}: {:.4} {:.4}, lines {} -> {}",
            row.kind, row.a_in_b, row.b_in_a, row.a_count, row.b_count
        );
    }
    found
        .lines
        .iter()
        .map(|r| r.a_in_b.min(r.b_in_a))
        .fold(1.0, f64::min)
}

#[test]
fn the_scale_and_the_crest_lines_do_not_depend_on_the_voxel_size() {
    let (reference, scale) = default_lines(&sampled(1.0, Vector::zeros()));
    assert!(scale > 1.25, "the scale {scale} fell to the voxel floor");
    for spacing in [0.8, 1.25] {
        let (lines, other) = default_lines(&sampled(spacing, Vector::zeros()));
        assert!(
            (other / scale - 1.0).abs() < 0.02,
            "scale {other} against {scale}"
        );
        let share = worst_share(&reference, &lines, 0.5);
        assert!(share > 0.95, "voxel {spacing}: {share}");
    }
}

#[test]
fn crest_lines_moved_off_the_grid_move_with_the_shape() {
    let (reference, _) = default_lines(&sampled(1.0, Vector::zeros()));
    let shift = Vector::new(0.43, 0.29, 0.17);
    let (moved, _) = default_lines(&sampled(1.0, shift));
    let back = RigidTransform::new(Rotation3::identity(), -shift);
    let share = worst_share(&reference, &moved.moved(&back), 0.5);
    assert!(share > 0.95, "{share}");
}

/// The landmarks of the MNI template at level 60 with every default, as features.
fn mni_landmarks(volume: &Volume) -> Features {
    let input = LinesFrom::Image {
        volume,
        level: 60.0,
        options: &CrestLinesOptions::default(),
    };
    let found = landmarks(input, &LandmarksOptions::default(), &mut Silent).unwrap();
    Features::of_landmarks(&found)
}

/// The count of `kind` in `features`: landmarks, or lines.
fn count(features: &Features, kind: &str) -> usize {
    features
        .points
        .get(kind)
        .map(Vec::len)
        .or_else(|| features.line_counts.get(kind).copied())
        .unwrap_or(0)
}

#[test]
fn a_moved_rescan_of_the_mni_template_keeps_its_extremal_points() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../volumes/mni152_t1_1mm.nii.gz");
    let volume = crate::io::read_volume(&path).unwrap();
    // A second scan: the head moved by 6° and (2.5, -1.5, 3) mm, sampled on the
    // same grid by trilinear interpolation of the first one's samples (SimpleITK's
    // B-spline, in tools/image_rescans.py, gives the same shares within a percent
    // at seven times the cost).
    let motion = RigidTransform::new(
        Rotation3::from_euler_angles(0.06, -0.05, 0.08),
        Vector::new(2.5, -1.5, 3.0),
    );
    let copy = common::resampled(&volume, &motion, |p| volume.interpolate(p));
    let original = mni_landmarks(&volume);
    // The copy's anatomy at x lies at motion(x) in the original.
    let rescan = mni_landmarks(&copy).moved(&motion);
    let found = compare(&original, &rescan, 1.0);
    let row = |rows: &[crate::compare::Agreement], kind: &str| {
        rows.iter().find(|r| r.kind == kind).unwrap().clone()
    };
    let extremal = row(&found.landmarks, "extremal");
    println!("{extremal:?}");
    assert!(
        extremal.a_in_b >= 0.9 && extremal.b_in_a >= 0.9,
        "{extremal:?}"
    );
    for kind in ["ridge", "valley"] {
        let lines = row(&found.lines, kind);
        println!("{lines:?}");
        assert!(lines.a_in_b >= 0.97 && lines.b_in_a >= 0.97, "{lines:?}");
    }
    for kind in ["extremal", "curvature_maximum", "end", "ridge", "valley"] {
        let (a, b) = (count(&original, kind), count(&rescan, kind));
        assert!(
            a > 100 && (b as f64 / a as f64 - 1.0).abs() < 0.2,
            "{kind}: {a} -> {b}"
        );
    }
}

/// The rounded cube |x|⁴ + |y|⁴ + |z|⁴ = 1 triangulated with about `vertices`
/// vertices (an icosphere jittered by `seed`, pushed out along its rays): the
/// same surface at every resolution, with a ridge along each of its 12 edges.
fn rounded_cube(vertices: usize, seed: u64) -> Mesh {
    let sphere = generate::sphere(1.0, vertices, Sampling::jittered(seed)).unwrap();
    common::transformed(&sphere.mesh, |p| {
        let quartic = p.x.powi(4) + p.y.powi(4) + p.z.powi(4);
        p / quartic.powf(0.25)
    })
}

/// The ridges and valleys of `mesh` at the feature scale `scale` (none: the
/// sampling's defaults), as features.
fn mesh_lines(mesh: Mesh, scale: Option<f64>) -> Features {
    let options = RidgesOptions {
        scale,
        ..RidgesOptions::default()
    };
    Features::of_lines(&ridges(&Surface::of_mesh(mesh), &options, &mut Silent).unwrap())
}

#[test]
fn at_a_feature_scale_a_finer_and_a_coarser_sampling_trace_the_same_lines() {
    // About four mean edge lengths of the finest mesh, one of the coarsest.
    let scale = Some(0.05);
    let reference = mesh_lines(rounded_cube(20_000, 1), scale);
    let length = |f: &Features| {
        f.segments["ridge"]
            .iter()
            .map(|[p, q]| (q - p).norm())
            .sum::<f64>()
    };
    // Ridges along the twelve edges, about 18 long in all.
    assert!(
        (17.0..19.5).contains(&length(&reference)),
        "{}",
        length(&reference)
    );
    for vertices in [5_000, 80_000] {
        let other = mesh_lines(rounded_cube(vertices, 2), scale);
        assert!(
            worst_share(&reference, &other, 0.02) > 0.9,
            "{vertices} vertices"
        );
        assert!((length(&other) / length(&reference) - 1.0).abs() < 0.05);
    }
}
