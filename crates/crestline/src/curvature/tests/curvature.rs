//! Curvature estimators against exact curvature of analytic surfaces, and the
//! invariances every estimator must have.

use crate::common;

use crate::curvature::Quality;
use crate::curvature::{
    estimate_curvature, CurvatureEstimator, CurvatureField, JetFit, ShapeOperator,
};
use crate::curvature::{isosurface_curvature, IsoCurvature, ThirdOrder};
use crate::jobs;
use crate::mesh::generate::{self, AnalyticMesh, Paraboloid, Sampling};
use crate::mesh::Mesh;
use crate::ridges::{extremality, Principal};
use crate::Vector;
use common::transformed;
use nalgebra::{Isometry3, Translation3, UnitQuaternion};

const VERTICES: usize = 20_000;

fn samplings() -> [(&'static str, Sampling); 2] {
    [
        ("regular", Sampling::Regular),
        ("jittered", Sampling::jittered(11)),
    ]
}

fn ellipsoid(sampling: Sampling) -> AnalyticMesh {
    generate::ellipsoid([1.0, 0.7, 0.45], VERTICES, sampling).unwrap()
}

fn torus(sampling: Sampling) -> AnalyticMesh {
    generate::torus(1.0, 0.35, VERTICES, sampling).unwrap()
}

fn error_of(surface: &AnalyticMesh, estimator: &dyn CurvatureEstimator) -> f64 {
    let field = estimate_curvature(&surface.mesh, estimator).unwrap();
    field.relative_rms_error(&surface.exact).unwrap()
}

#[test]
fn jet_fit_is_accurate_on_regular_and_irregular_meshes() {
    for (name, sampling) in samplings() {
        let on_ellipsoid = error_of(&ellipsoid(sampling), &JetFit::default());
        let on_torus = error_of(&torus(sampling), &JetFit::default());
        eprintln!(
            "jet fit, {name}: ellipsoid {:.4}%, torus {:.4}%",
            100.0 * on_ellipsoid,
            100.0 * on_torus
        );
        // Targets 0.5% and 1%; measured below 0.03% on both samplings.
        assert!(on_ellipsoid < 0.001, "{name} ellipsoid: {on_ellipsoid}");
        assert!(on_torus < 0.001, "{name} torus: {on_torus}");
    }
}

#[test]
fn shape_operator_is_accurate_on_regular_meshes_and_bounded_on_irregular_ones() {
    for (name, sampling) in samplings() {
        let on_ellipsoid = error_of(&ellipsoid(sampling), &ShapeOperator);
        let on_torus = error_of(&torus(sampling), &ShapeOperator);
        eprintln!(
            "shape operator, {name}: ellipsoid {:.3}%, torus {:.3}%",
            100.0 * on_ellipsoid,
            100.0 * on_torus
        );
        // Measured: 0.35% / 0.07% regular, 7% / 11% jittered (the operator is only
        // accurate on regular meshes; a factor-2 scale error would give 50%+).
        let bound = if sampling == Sampling::Regular {
            0.01
        } else {
            0.15
        };
        assert!(on_ellipsoid < bound, "{name} ellipsoid: {on_ellipsoid}");
        assert!(on_torus < bound, "{name} torus: {on_torus}");
    }
}

#[test]
fn sphere_has_positive_curvature_and_outward_normals() {
    let sphere = generate::sphere(2.0, 5000, Sampling::jittered(2)).unwrap();
    // Exact: 0.5. The shape operator is off by up to a factor of two at single
    // vertices of an irregular mesh (its error converges only on average).
    let estimators: [(&dyn CurvatureEstimator, f64, f64); 2] = [
        (&ShapeOperator, 0.2, 1.1),
        (&JetFit::default(), 0.4995, 0.5005),
    ];
    for (estimator, low, high) in estimators {
        let field = estimate_curvature(&sphere.mesh, estimator).unwrap();
        for (i, p) in sphere.mesh.positions().iter().enumerate() {
            assert!(
                field.k_min[i] > low && field.k_max[i] < high,
                "k at {i}: {} {}",
                field.k_min[i],
                field.k_max[i]
            );
            assert!(field.normal[i].dot(&p.coords.normalize()) > 0.99);
            let frame = [field.d_max[i], field.d_min[i], field.normal[i]];
            assert!(
                (frame[0].cross(&frame[1]).dot(&frame[2]) - 1.0).abs() < 1e-9,
                "right-handed frame"
            );
        }
    }
}

#[test]
fn principal_directions_follow_the_exact_ones() {
    let surface = ellipsoid(Sampling::jittered(5));
    let field = estimate_curvature(&surface.mesh, &JetFit::default()).unwrap();
    let mut alignments = Vec::new();
    for (i, exact) in surface.exact.iter().enumerate() {
        // Away from the four umbilics, where the directions are undefined.
        if exact.k_max - exact.k_min > 0.2 * exact.k_max {
            alignments.push(field.d_max[i].dot(&exact.d_max).abs());
        }
    }
    let mean = alignments.iter().sum::<f64>() / alignments.len() as f64;
    let worst = alignments.iter().cloned().fold(1.0, f64::min);
    assert!(alignments.len() > VERTICES / 2);
    assert!(mean > 0.9999 && worst > 0.99, "mean {mean}, worst {worst}");
}

fn assert_scaled(a: &CurvatureField, b: &CurvatureField, factor: f64) {
    let reference = a.k_max.iter().fold(0.0f64, |m, k| m.max(k.abs()));
    for i in 0..a.len() {
        assert!(
            (b.k_max[i] * factor - a.k_max[i]).abs() <= 1e-9 * reference,
            "k_max at {i}"
        );
        assert!(
            (b.k_min[i] * factor - a.k_min[i]).abs() <= 1e-9 * reference,
            "k_min at {i}"
        );
    }
}

#[test]
fn scaling_the_mesh_by_1000_scales_curvature_by_a_thousandth() {
    let surface = torus(Sampling::jittered(3));
    let big = transformed(&surface.mesh, |p| p * 1000.0);
    for estimator in [
        &ShapeOperator as &dyn CurvatureEstimator,
        &JetFit::default(),
    ] {
        let original = estimate_curvature(&surface.mesh, estimator).unwrap();
        let scaled = estimate_curvature(&big, estimator).unwrap();
        assert_scaled(&original, &scaled, 1000.0);
    }
}

#[test]
fn rigid_motion_leaves_curvature_unchanged_and_rotates_directions() {
    let surface = ellipsoid(Sampling::jittered(4));
    let motion = Isometry3::from_parts(
        Translation3::new(3.0, -7.0, 11.0),
        UnitQuaternion::from_euler_angles(0.3, -1.1, 2.0),
    );
    let moved = transformed(&surface.mesh, |p| motion * p);
    for estimator in [
        &ShapeOperator as &dyn CurvatureEstimator,
        &JetFit::default(),
    ] {
        let original = estimate_curvature(&surface.mesh, estimator).unwrap();
        let after = estimate_curvature(&moved, estimator).unwrap();
        assert_scaled(&original, &after, 1.0);
        for i in 0..original.len() {
            let rotated: Vector = motion.rotation * original.normal[i];
            assert!(rotated.dot(&after.normal[i]) > 1.0 - 1e-9, "normal at {i}");
            if original.k_max[i] - original.k_min[i] > 0.1 {
                let d: Vector = motion.rotation * original.d_max[i];
                assert!(d.dot(&after.d_max[i]).abs() > 1.0 - 1e-6, "d_max at {i}");
            }
        }
    }
}

#[test]
fn boundary_vertices_are_flagged_and_interior_is_accurate_on_a_height_field() {
    let f = Paraboloid { a: -1.5, b: 0.5 };
    let surface = generate::height_field(&f, 0.5, 10_000, Sampling::jittered(8)).unwrap();
    let mesh = &surface.mesh;
    for estimator in [
        &ShapeOperator as &dyn CurvatureEstimator,
        &JetFit::default(),
    ] {
        let field = estimate_curvature(mesh, estimator).unwrap();
        for v in mesh.vertices() {
            assert_eq!(field.unreliable[v.idx()], mesh.is_boundary_vertex(v));
        }
    }
    // A saddle with the upward normal: curvatures +1.5 and −0.5 at the apex.
    let field = estimate_curvature(mesh, &JetFit::default()).unwrap();
    let error = field.relative_rms_error(&surface.exact).unwrap();
    assert!(error < 0.001, "{error}");
    assert!(surface.exact.iter().all(|k| k.k_max > 0.0 && k.k_min < 0.0));
}

/// An estimator that breaks the contract: one value short, or a NaN.
struct Broken {
    nan: bool,
}

impl CurvatureEstimator for Broken {
    fn estimate(&self, mesh: &Mesh) -> crate::Result<CurvatureField> {
        let mut field = ShapeOperator.estimate(mesh)?;
        if self.nan {
            field.k_max[3] = f64::NAN;
        } else {
            field.d_min.pop();
        }
        Ok(field)
    }
}

#[test]
fn a_custom_estimator_is_held_to_the_same_contract() {
    let mesh = generate::sphere(1.0, 500, Sampling::Regular).unwrap().mesh;
    let short = estimate_curvature(&mesh, &Broken { nan: false }).unwrap_err();
    assert!(
        short.to_string().contains("values for a mesh with"),
        "{short}"
    );
    let nan = estimate_curvature(&mesh, &Broken { nan: true }).unwrap_err();
    assert!(nan.to_string().contains("vertex 3"), "{nan}");
}

/// The exact extremalities `[e_max, e_min]` of the ellipsoid x²/a² + y²/b² + z²/c² = 1
/// at a point on it, along the exact principal directions: the closed form of the
/// curvature of a level set (`isosurface_curvature`) for the quadric, whose third
/// derivatives vanish.
fn exact_ellipsoid_extremality(axes: [f64; 3], p: &crate::Point) -> IsoCurvature {
    // The object is inside, where −Σ x_i²/a_i² is large.
    let gradient = Vector::from_fn(|i, _| -2.0 * p[i] / (axes[i] * axes[i]));
    let hessian = nalgebra::Matrix3::from_fn(|i, j| {
        if i == j {
            -2.0 / (axes[i] * axes[i])
        } else {
            0.0
        }
    });
    isosurface_curvature(&gradient, &hessian, &ThirdOrder([[[0.0; 3]; 3]; 3])).unwrap()
}

/// The jet fit's extremalities (read off its third-order terms) against the closed
/// form on an ellipsoid, with the signs of the jet's own directions, away from the
/// umbilics: root mean square error below 2% of the root mean square of the exact
/// values; and against the discrete extremality of eq. 4, which they must match in
/// sign.
#[test]
fn jet_fit_extremalities_match_the_closed_form_on_an_ellipsoid() {
    let axes = [1.0, 0.7, 0.45];
    for (name, sampling) in samplings() {
        let surface = generate::ellipsoid(axes, 30_000, sampling).unwrap();
        let mesh = &surface.mesh;
        let field = estimate_curvature(mesh, &JetFit::default()).unwrap();
        let fitted = field
            .extremality
            .as_ref()
            .expect("the jet fit gives extremalities");
        let discrete = [Principal::Max, Principal::Min].map(|w| extremality(mesh, &field, w));
        for (slot, which) in [(0, Principal::Max), (1, Principal::Min)] {
            let directions = which.directions(&field);
            let (mut error, mut norm, mut agree, mut counted) = (0.0, 0.0, 0, 0);
            let mut discrete_error = 0.0;
            for v in 0..mesh.vertex_count() {
                let exact = exact_ellipsoid_extremality(axes, &mesh.positions()[v]);
                let k = exact.principal;
                // Away from the umbilics, where directions (and e) are undefined.
                if k.k_max - k.k_min < 0.1 * k.k_max {
                    continue;
                }
                let (d, e) = match which {
                    Principal::Max => (k.d_max, exact.e_max),
                    Principal::Min => (k.d_min, exact.e_min),
                };
                let e = e * directions[v].dot(&d).signum();
                error += (fitted[slot][v] - e).powi(2);
                discrete_error += (discrete[slot][v] - e).powi(2);
                norm += e * e;
                // Where |e| is large enough for its sign to be meaningful.
                if e.abs() > 0.2 {
                    counted += 1;
                    agree += usize::from(fitted[slot][v] * discrete[slot][v] > 0.0);
                }
            }
            let relative = (error / norm).sqrt();
            let discrete_relative = (discrete_error / norm).sqrt();
            let agreement = agree as f64 / counted as f64;
            eprintln!(
                "{name} {which:?}: rms error of the fitted e {relative:.4}, of the discrete e \
                 {discrete_relative:.4} (relative to rms |e| {:.3}); signs agree at {:.2}% of {counted} vertices",
                (norm / mesh.vertex_count() as f64).sqrt(),
                100.0 * agreement
            );
            assert!(relative < 0.02, "{name} {which:?}: {relative}");
            // On the irregular mesh the fit beats differentiating the curvature.
            if name == "jittered" {
                assert!(relative < 0.5 * discrete_relative, "{name} {which:?}");
            }
            assert!(agreement > 0.97, "{name} {which:?}: {agreement}");
        }
    }
}

/// Extremalities scale by 1/length² with the mesh, and flipping a direction with
/// [`CurvatureField::flip_direction`] flips its extremality.
#[test]
fn jet_fit_extremalities_scale_with_the_mesh_and_flip_with_the_direction() {
    let surface = torus(Sampling::jittered(3));
    let small = estimate_curvature(&surface.mesh, &JetFit::default()).unwrap();
    let big_mesh = transformed(&surface.mesh, |p| p * 1000.0);
    let big = estimate_curvature(&big_mesh, &JetFit::default()).unwrap();
    let (e_small, e_big) = (
        small.extremality.as_ref().unwrap(),
        big.extremality.as_ref().unwrap(),
    );
    let scale = e_small[0].iter().fold(0.0f64, |m, e| m.max(e.abs()));
    for slot in 0..2 {
        for v in 0..small.len() {
            let same_sign = small.d_max[v].dot(&big.d_max[v]).signum();
            let same_sign = if slot == 0 {
                same_sign
            } else {
                small.d_min[v].dot(&big.d_min[v]).signum()
            };
            let diff = e_small[slot][v] - same_sign * e_big[slot][v] * 1e6;
            assert!(diff.abs() < 1e-6 * scale, "{slot} {v}: {diff}");
        }
    }
    let mut flipped = small.clone();
    flipped.flip_direction(crate::mesh::VertexId(7), true);
    flipped.flip_direction(crate::mesh::VertexId(9), false);
    let e = flipped.extremality.as_ref().unwrap();
    assert_eq!(flipped.d_max[7], -small.d_max[7]);
    assert_eq!(e[0][7], -e_small[0][7]);
    assert_eq!(e[1][9], -e_small[1][9]);
    assert_eq!(e[0][9], e_small[0][9]);
}

/// A field with extremalities of the wrong length or not finite breaks the
/// contract, and the shape operator gives none.
#[test]
fn extremalities_are_checked_with_the_field() {
    let mesh = torus(Sampling::Regular).mesh;
    assert!(ShapeOperator.estimate(&mesh).unwrap().extremality.is_none());
    let mut field = JetFit::default().estimate(&mesh).unwrap();
    field.check(&mesh).unwrap();
    field.extremality.as_mut().unwrap()[1][3] = f64::NAN;
    assert!(field.check(&mesh).is_err());
    field.extremality.as_mut().unwrap()[1].pop();
    assert!(field.check(&mesh).is_err());
}

/// The vertex property `name` of the PLY file at `path`.
fn ply_property(path: &std::path::Path, name: &str) -> Vec<f64> {
    let soup = crate::io::read_mesh(path).unwrap();
    soup.vertex_scalars
        .into_iter()
        .find(|p| p.name == name)
        .unwrap_or_else(|| panic!("{} has no vertex property {name}", path.display()))
        .values
}

#[test]
fn the_curvature_ply_carries_the_chosen_quantity_as_quality() {
    // On a sphere of radius r: k_max = k_min = mean = curvedness = 1/r, gauss = 1/r².
    let radius = 2.0;
    let sphere = generate::sphere(radius, 3000, Sampling::Regular).unwrap();
    let field = estimate_curvature(&sphere.mesh, &JetFit::default()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    for &name in Quality::NAMES {
        let quality: Quality = name.parse().unwrap();
        let exact = match quality {
            Quality::Gauss => 1.0 / (radius * radius),
            _ => 1.0 / radius,
        };
        let path = dir.path().join(format!("{name}.ply"));
        field
            .write_ply_with_quality(&path, &sphere.mesh, quality)
            .unwrap();
        let written = ply_property(&path, "quality");
        assert_eq!(written, quality.values(&field), "{name}");
        for (v, q) in written.iter().enumerate() {
            assert!(
                (q / exact - 1.0).abs() < 2e-3,
                "{name} at {v}: {q}, not {exact}"
            );
        }
        // The quantities that have a property of their own are that property again.
        if name != "curvedness" {
            assert_eq!(written, ply_property(&path, name), "{name}");
        }
    }
}

#[test]
fn the_quality_is_the_mean_curvature_by_default() {
    assert_eq!(Quality::default(), Quality::Mean);
    assert_eq!(
        jobs::CurvatureOptions::default().quality,
        Quality::default()
    );
    assert_eq!(
        jobs::defaults()["curvature"]["quality"],
        Quality::default().name()
    );
    let chosen: jobs::CurvatureOptions =
        jobs::options_from_json("curvature", &serde_json::json!({"quality": "gauss"})).unwrap();
    assert_eq!(chosen.quality, Quality::Gauss);
    let message = "k1".parse::<Quality>().unwrap_err().to_string();
    assert!(
        message.contains("k_max, k_min, mean, gauss, curvedness"),
        "{message}"
    );
    // The writer without a choice writes the default.
    let sphere = generate::sphere(1.5, 500, Sampling::Regular).unwrap();
    let field = estimate_curvature(&sphere.mesh, &ShapeOperator).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("default.ply");
    field.write_ply(&path, &sphere.mesh).unwrap();
    assert_eq!(ply_property(&path, "quality"), field.mean());
}
