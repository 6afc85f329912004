//! Curvature and extremalities of iso-surfaces from image derivatives
//! (`differential::isosurface_curvature`), against closed forms and finite
//! differences on cubic polynomial fields, whose derivatives are exact.

use crate::curvature::{isosurface_curvature, IsoCurvature, ThirdOrder};
use crate::{Point, Vector};
use nalgebra::Matrix3;

/// f(x) = c + bᵀx + ½ xᵀAx + ⅙ T(x, x, x), with its exact derivatives.
struct Cubic {
    b: Vector,
    a: Matrix3<f64>,
    t: ThirdOrder,
}

impl Cubic {
    fn gradient(&self, p: &Point) -> Vector {
        let x = p.coords;
        let mut g = self.b + self.a * x;
        for (i, gi) in g.iter_mut().enumerate() {
            *gi += 0.5 * quadratic(&self.t.0[i], &x);
        }
        g
    }

    fn hessian(&self, p: &Point) -> Matrix3<f64> {
        let x = p.coords;
        Matrix3::from_fn(|i, j| {
            self.a[(i, j)] + (0..3).map(|k| self.t.0[i][j][k] * x[k]).sum::<f64>()
        })
    }

    fn curvature(&self, p: &Point) -> IsoCurvature {
        isosurface_curvature(&self.gradient(p), &self.hessian(p), &self.t).expect("regular point")
    }
}

/// xᵀ M x for a 3×3 slice of the tensor.
fn quadratic(m: &[[f64; 3]; 3], x: &Vector) -> f64 {
    (0..3)
        .flat_map(|j| (0..3).map(move |k| (j, k)))
        .map(|(j, k)| m[j][k] * x[j] * x[k])
        .sum()
}

/// A bright ellipsoid: f = −(x²/a² + y²/b² + z²/c²), inside f ≥ I.
fn ellipsoid(a: f64, b: f64, c: f64) -> Cubic {
    Cubic {
        b: Vector::zeros(),
        a: Matrix3::from_diagonal(&Vector::new(-2.0 / (a * a), -2.0 / (b * b), -2.0 / (c * c))),
        t: ThirdOrder([[[0.0; 3]; 3]; 3]),
    }
}

#[test]
fn bright_sphere_has_positive_curvature_one_over_radius() {
    let sphere = ellipsoid(1.0, 1.0, 1.0);
    for p in [Point::new(2.0, 0.0, 0.0), Point::new(0.3, -1.1, 0.7)] {
        let c = sphere.curvature(&p);
        let r = p.coords.norm();
        assert!((c.principal.k_max - 1.0 / r).abs() < 1e-12, "{c:?}");
        assert!((c.principal.k_min - 1.0 / r).abs() < 1e-12, "{c:?}");
        assert!(
            (c.normal - p.coords / r).norm() < 1e-12,
            "normal points out: {c:?}"
        );
    }
}

#[test]
fn ellipsoid_curvature_matches_the_closed_form_at_the_axis_ends() {
    let (a, b, c) = (3.0, 2.0, 1.0);
    let field = ellipsoid(a, b, c);
    // At (a, 0, 0) on the surface the normal curvatures are a/b² (along y) and a/c²
    // (along z).
    let k = field.curvature(&Point::new(a, 0.0, 0.0));
    assert!((k.principal.k_max - a / (c * c)).abs() < 1e-12, "{k:?}");
    assert!((k.principal.k_min - a / (b * b)).abs() < 1e-12, "{k:?}");
    assert!(k.principal.d_max.z.abs() > 1.0 - 1e-12, "{k:?}");
    assert!(k.principal.d_min.y.abs() > 1.0 - 1e-12, "{k:?}");
    // Both directions at an axis end are extremal by symmetry.
    assert!(k.e_max.abs() < 1e-12 && k.e_min.abs() < 1e-12, "{k:?}");
}

/// e = ∇k · d, by central differences of k along d.
fn finite_difference_extremality(field: &Cubic, p: &Point, use_max: bool) -> f64 {
    let c = field.curvature(p);
    let d = if use_max {
        c.principal.d_max
    } else {
        c.principal.d_min
    };
    let h = 1e-5;
    let k_at = |q: Point| {
        let c = field.curvature(&q);
        if use_max {
            c.principal.k_max
        } else {
            c.principal.k_min
        }
    };
    (k_at(p + d * h) - k_at(p - d * h)) / (2.0 * h)
}

#[test]
fn extremalities_match_finite_differences_of_curvature_on_cubic_fields() {
    let mut fields = vec![ellipsoid(3.0, 2.0, 1.0)];
    let mut cubic = ellipsoid(2.5, 1.5, 1.0);
    cubic.b = Vector::new(0.1, -0.2, 0.05);
    cubic.t = ThirdOrder::from_components([0.3, -0.1, 0.2, 0.05, 0.4, -0.25, 0.15, 0.1, -0.3, 0.2]);
    fields.push(cubic);
    let points = [
        Point::new(1.1, 0.7, 0.4),
        Point::new(-0.9, 0.3, 0.6),
        Point::new(0.4, -1.0, -0.3),
    ];
    let mut checked = 0;
    for field in &fields {
        for p in &points {
            let c = field.curvature(p);
            if (c.principal.k_max - c.principal.k_min).abs() < 0.05 {
                continue; // near an umbilic the directions are ill-conditioned
            }
            for use_max in [true, false] {
                let exact = if use_max { c.e_max } else { c.e_min };
                let numeric = finite_difference_extremality(field, p, use_max);
                assert!(
                    (exact - numeric).abs() < 1e-5 * (1.0 + numeric.abs()),
                    "at {p:?}: closed form {exact}, finite differences {numeric}"
                );
                assert!(
                    numeric.abs() > 1e-3,
                    "a test point on an extremal curve is no test"
                );
                checked += 1;
            }
        }
    }
    assert!(checked >= 8, "{checked} extremalities checked");
}

#[test]
fn extremality_sign_follows_the_direction_sign_and_scale_is_consistent() {
    let mut field = ellipsoid(2.5, 1.5, 1.0);
    field.t = ThirdOrder::from_components([0.3, -0.1, 0.2, 0.05, 0.4, -0.25, 0.15, 0.1, -0.3, 0.2]);
    let p = Point::new(1.1, 0.7, 0.4);
    let c = field.curvature(&p);
    // Brightness scale and offset do not change the geometry.
    let scaled = Cubic {
        b: field.b * 7.0,
        a: field.a * 7.0,
        t: ThirdOrder(field.t.0.map(|m| m.map(|r| r.map(|v| v * 7.0)))),
    };
    let s = scaled.curvature(&p);
    assert!((s.principal.k_max - c.principal.k_max).abs() < 1e-12);
    assert!((s.e_max * s.principal.d_max.dot(&c.principal.d_max).signum() - c.e_max).abs() < 1e-10);
}

#[test]
fn vanishing_or_non_finite_gradient_gives_none() {
    let zero = ThirdOrder([[[0.0; 3]; 3]; 3]);
    assert!(isosurface_curvature(&Vector::zeros(), &Matrix3::identity(), &zero).is_none());
    let nan = Vector::new(f64::NAN, 1.0, 0.0);
    assert!(isosurface_curvature(&nan, &Matrix3::identity(), &zero).is_none());
}

// ---------------------------------------------------------------------------
// Isosurface meshes with image-based curvature (`curvature::image_isosurface`).

mod sampled {
    use crate::curvature::{estimate_curvature, image_isosurface, CurvatureField};
    use crate::mesh::Mesh;
    use crate::volume::Volume;
    use crate::{Point, Vector};
    use nalgebra::Matrix3;

    /// `f` sampled on an `n³` grid with `spacing`, centred on the world origin, axes
    /// along `direction`.
    pub fn field(
        n: usize,
        spacing: [f64; 3],
        direction: Matrix3<f64>,
        f: impl Fn(&Point) -> f64,
    ) -> Volume {
        let centre = (n - 1) as f64 / 2.0;
        let offset = -(direction * Vector::from_fn(|i, _| centre * spacing[i]));
        let origin = [offset.x, offset.y, offset.z];
        let mut samples = Vec::with_capacity(n * n * n);
        let probe = Volume::new([1, 1, 1], spacing, origin, direction, vec![0.0]).unwrap();
        for k in 0..n {
            for j in 0..n {
                for i in 0..n {
                    let p = probe.index_to_world([i as f64, j as f64, k as f64]);
                    samples.push(f(&p) as f32);
                }
            }
        }
        Volume::new([n; 3], spacing, origin, direction, samples).unwrap()
    }

    /// The isosurface and its image-based curvature field.
    pub fn surface(volume: &Volume, level: f64, sigma: f64) -> (Mesh, CurvatureField) {
        let (iso, curvature) = image_isosurface(volume, level, sigma).unwrap();
        let mesh = iso.to_mesh().unwrap();
        let field = estimate_curvature(&mesh, &curvature).unwrap();
        assert!(
            field.unreliable.iter().all(|u| !u),
            "every vertex has a gradient"
        );
        (mesh, field)
    }

    /// Mean and largest of |measured − expected| / scale over the vertices.
    pub fn errors(values: impl Iterator<Item = (f64, f64)>, scale: f64) -> (f64, f64) {
        let (mut sum, mut max, mut n) = (0.0, 0.0f64, 0);
        for (measured, expected) in values {
            let e = (measured - expected).abs() / scale;
            sum += e;
            max = max.max(e);
            n += 1;
        }
        (sum / n as f64, max)
    }
}

#[test]
fn sphere_field_curvature_is_one_over_the_radius_at_every_vertex() {
    let radius = 20.0;
    let flips = Matrix3::new(-1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0);
    for (spacing, direction, sigma) in [
        ([1.0; 3], Matrix3::identity(), 1.5),
        ([1.0; 3], Matrix3::identity(), 0.0),
        ([0.8, 1.0, 1.3], flips, 1.5),
    ] {
        // Room for the Gaussian's 5σ (and the spline's support) beyond the sphere
        // along every axis.
        let finest = spacing.iter().fold(f64::INFINITY, |a, &b| a.min(b));
        let n = 2 + (2.0 * (radius + 5.0 * sigma + 3.0) / finest) as usize;
        let volume = sampled::field(n, spacing, direction, |p| radius - p.coords.norm());
        let (mesh, field) = sampled::surface(&volume, 0.0, sigma);
        assert_eq!(mesh.euler_characteristic(), 2);
        // The curvature of the sphere through each vertex, 1/|p|.
        let expected = |v: usize| 1.0 / mesh.positions()[v].coords.norm();
        let k = 1.0 / radius;
        let (mean, max) = sampled::errors(
            (0..mesh.vertex_count())
                .flat_map(|v| [(field.k_max[v], expected(v)), (field.k_min[v], expected(v))]),
            k,
        );
        eprintln!(
            "sphere, spacing {spacing:?}, σ {sigma}: relative error mean {mean:.2e}, max {max:.2e}"
        );
        assert!(mean < 0.005 && max < 0.03, "mean {mean}, max {max}");
        for (v, n) in field.normal.iter().enumerate() {
            let radial = mesh.positions()[v].coords.normalize();
            assert!(n.dot(&radial) > 0.999, "normal {n:?} at {v}");
        }
    }
}

#[test]
fn curvature_kept_at_some_points_equals_the_whole_grids_there_and_is_none_elsewhere() {
    use crate::curvature::DerivativeOrder::Third;
    use crate::curvature::ImageCurvature;
    let flips = Matrix3::new(-1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0);
    let volume = sampled::field(41, [0.8, 1.0, 1.3], flips, |p| {
        12.0 - (p.coords.component_mul(&Vector::new(1.0, 1.3, 0.8))).norm()
    });
    let (iso, _) = crate::curvature::image_isosurface(&volume, 0.0, 1.5).unwrap();
    let mesh = iso.to_mesh().unwrap();
    let whole = ImageCurvature::new(&volume, 1.5).unwrap();
    let some = ImageCurvature::at_points(&volume, 1.5, mesh.positions(), Third).unwrap();
    assert!(some.smoothed().is_none() && whole.smoothed().is_some());
    assert!(some.surface_volume(&volume).is_err());
    for p in mesh.positions() {
        let (a, b) = (whole.derivatives_at(p), some.derivatives_at(p));
        assert!(a.is_some() && a == b, "at {p:?}: {a:?} vs {b:?}");
    }
    // The centre is far from every vertex: no derivatives are kept around it.
    let centre = volume.index_to_world([20.0; 3]);
    assert!(whole.derivatives_at(&centre).is_some());
    assert!(some.derivatives_at(&centre).is_none());
    // The spline keeps its samples whole.
    let spline = ImageCurvature::at_points(&volume, 0.0, &[centre], Third).unwrap();
    assert!(spline.derivatives_at(&centre).is_some());
    assert!(ImageCurvature::at_points(&volume, -1.0, &[centre], Third).is_err());
}

#[test]
fn torus_field_curvatures_match_the_closed_form() {
    let (big, small) = (18.0, 7.0);
    let tube_distance = |p: &Point| {
        let ring = (p.x * p.x + p.y * p.y).sqrt() - big;
        (ring * ring + p.z * p.z).sqrt()
    };
    let volume = sampled::field(64, [1.0; 3], Matrix3::identity(), |p| {
        small - tube_distance(p)
    });
    let (mesh, field) = sampled::surface(&volume, 0.0, 1.0);
    assert_eq!(mesh.euler_characteristic(), 0);
    // Around the tube 1/r; around the axis cos φ / (R + r cos φ), with r and φ of
    // the torus through the vertex.
    let (mean, max) = sampled::errors(
        mesh.positions().iter().enumerate().flat_map(|(v, p)| {
            let rho = (p.x * p.x + p.y * p.y).sqrt();
            let r = tube_distance(p);
            let cos = (rho - big) / r;
            let around_axis = cos / (big + r * cos);
            let tube = 1.0 / r;
            [
                (field.k_max[v], tube.max(around_axis)),
                (field.k_min[v], tube.min(around_axis)),
            ]
        }),
        1.0 / small,
    );
    eprintln!("torus: error mean {mean:.2e}, max {max:.2e} of 1/r");
    assert!(mean < 0.005 && max < 0.03, "mean {mean}, max {max}");
}

/// The principal directions of the ellipsoid x²/a² + y²/b² + z²/c² = 1 at its point
/// p: the normals of the two other confocal quadrics through p (parameters λ ≠ 0
/// solving Σ pᵢ² / (aᵢ² + λ) = 1).
fn confocal_directions(axes: [f64; 3], p: &Point) -> [Vector; 2] {
    let [a2, b2, c2] = axes.map(|a| a * a);
    let [x2, y2, z2] = [p.x * p.x, p.y * p.y, p.z * p.z];
    // Σ pᵢ² Π_{j≠i}(aⱼ² + λ) = Π(aᵢ² + λ), a cubic in λ with root 0; divide it out.
    // Π(aᵢ² + λ) = λ³ + s1 λ² + s2 λ + s3.
    let s1 = a2 + b2 + c2;
    let s2 = a2 * b2 + b2 * c2 + c2 * a2;
    let t1 = x2 + y2 + z2;
    let t2 = x2 * (b2 + c2) + y2 * (a2 + c2) + z2 * (a2 + b2);
    // λ² + (s1 − t1) λ + (s2 − t2) = 0.
    let (bq, cq) = (s1 - t1, s2 - t2);
    let root = (bq * bq - 4.0 * cq).max(0.0).sqrt();
    [(-bq + root) / 2.0, (-bq - root) / 2.0].map(|l| {
        let squares = [a2, b2, c2];
        // On a symmetry plane pᵢ = 0 a root is −aᵢ²: that quadric degenerates to
        // the plane, whose normal is the axis.
        match (0..3).find(|&i| (squares[i] + l).abs() < 1e-9 * squares[i]) {
            Some(i) => Vector::ith(i, 1.0),
            None => Vector::new(p.x / (a2 + l), p.y / (b2 + l), p.z / (c2 + l)).normalize(),
        }
    })
}

#[test]
fn ellipsoid_field_principal_directions_follow_its_curvature_lines() {
    let axes = [24.0, 17.0, 11.0];
    let q = |p: &Point| (p.x / axes[0]).powi(2) + (p.y / axes[1]).powi(2) + (p.z / axes[2]).powi(2);
    let volume = sampled::field(60, [1.0; 3], Matrix3::identity(), |p| -q(p));
    let (mesh, field) = sampled::surface(&volume, -1.0, 1.0);
    let mut worst = 0.0f64;
    let mut checked = 0;
    for (v, p) in mesh.positions().iter().enumerate() {
        // The quadric through the vertex is homothetic to the one sampled.
        let scale = q(p).sqrt();
        let [u, w] = confocal_directions(axes.map(|a| a * scale), p);
        // Skip near-umbilics, where directions are undetermined.
        if field.k_max[v] - field.k_min[v] < 0.1 * field.k_max[v].abs() {
            continue;
        }
        let d = field.d_max[v];
        let misfit = 1.0 - d.dot(&u).abs().max(d.dot(&w).abs());
        worst = worst.max(misfit);
        checked += 1;
    }
    eprintln!("ellipsoid: {checked} vertices, worst 1 − |cos| {worst:.2e}");
    assert!(
        checked > mesh.vertex_count() / 2,
        "{checked} of {}",
        mesh.vertex_count()
    );
    assert!(
        worst < 1e-6,
        "principal direction off a curvature line by 1 − |cos| = {worst}"
    );
}

#[test]
fn spline_jets_give_the_ellipsoid_extremalities_between_samples() {
    use crate::volume::{BSpline, Volume};
    // f = −(x²/a² + y²/b² + z²/c²) sampled on a grid: the cubic B-spline
    // reproduces the quadratic, so curvature and extremalities between samples
    // are those of the field.
    let field = ellipsoid(9.0, 6.0, 4.0);
    let n = 25;
    let origin = -12.0;
    let samples = (0..n * n * n)
        .map(|i| {
            let p = Point::new(
                origin + (i % n) as f64,
                origin + ((i / n) % n) as f64,
                origin + (i / (n * n)) as f64,
            );
            (0.5 * p.coords.dot(&(field.a * p.coords))) as f32
        })
        .collect();
    let volume = Volume::new([n; 3], [1.0; 3], [origin; 3], Matrix3::identity(), samples).unwrap();
    let spline = BSpline::new(&volume);
    for p in [Point::new(3.3, 2.1, 1.7), Point::new(-5.2, 1.4, -0.6)] {
        let exact = field.curvature(&p);
        let sampled = spline
            .jet_at_world(&p)
            .unwrap()
            .isosurface_curvature()
            .unwrap();
        let k = exact.principal.k_max;
        assert!(
            (sampled.principal.k_max - k).abs() < 1e-3 * k,
            "{sampled:?} vs {exact:?}"
        );
        let sign = sampled.principal.d_max.dot(&exact.principal.d_max).signum();
        assert!(
            (sign * sampled.e_max - exact.e_max).abs() < 1e-2 * exact.e_max.abs().max(1e-3),
            "e_max {} vs {}",
            sampled.e_max,
            exact.e_max
        );
    }
}

// ---------------------------------------------------------------------------
// Ridges of an image's isosurface (`ridges <volume> --level …`) with the
// extremalities of the image's third derivatives.

mod image_ridges {
    use std::sync::Arc;

    use crate::curvature::{DerivativeOrder, WithoutExtremality};
    use crate::jobs::{isosurface, IsoOptions, RidgesOptions, Surface};
    use crate::lines::LineKind;
    use crate::progress::Silent;
    use crate::ridges::Kinds;
    use crate::volume::Volume;
    use crate::{Point, Vector};
    use nalgebra::{Matrix3, Rotation3, Unit};

    const AXES: [f64; 3] = [24.0, 17.0, 11.0];

    /// The ellipsoid's axes turned off the grid's and its centre off the grid.
    fn frame() -> (Rotation3<f64>, Point) {
        let axis = Unit::new_normalize(Vector::new(0.3, -0.5, 0.8));
        (
            Rotation3::from_axis_angle(&axis, 0.6),
            Point::new(32.3, 31.7, 30.45),
        )
    }

    fn ellipsoid() -> Volume {
        let dims = [65, 64, 62];
        let (turn, centre) = frame();
        let mut samples = Vec::new();
        for k in 0..dims[2] {
            for j in 0..dims[1] {
                for i in 0..dims[0] {
                    let p = turn.inverse() * (Point::new(i as f64, j as f64, k as f64) - centre);
                    let r = (0..3).map(|a| (p[a] / AXES[a]).powi(2)).sum::<f64>();
                    samples.push(-r as f32);
                }
            }
        }
        Volume::new(dims, [1.0; 3], [0.0; 3], Matrix3::identity(), samples).unwrap()
    }

    /// The ridge points' mean distance (voxels) from the plane of the two longer
    /// axes, where the true ridge lies, and how many ridge lines there are.
    fn ridge_offset(surface: &Surface, smooth_steps: Option<usize>) -> (f64, usize) {
        let options = RidgesOptions {
            kind: Kinds::Ridges,
            smooth_steps,
            ..RidgesOptions::default()
        };
        let lines = options
            .tracer(surface)
            .trace(&surface.mesh, &mut Silent)
            .unwrap();
        let (turn, centre) = frame();
        let ridges: Vec<_> = lines.iter().filter(|l| l.kind == LineKind::Ridge).collect();
        let offsets: Vec<f64> = ridges
            .iter()
            .flat_map(|l| &l.points)
            .map(|p| (turn.inverse() * (p - centre)).z.abs())
            .collect();
        assert!(offsets.len() > 100, "{} ridge points", offsets.len());
        (
            offsets.iter().sum::<f64>() / offsets.len() as f64,
            ridges.len(),
        )
    }

    #[test]
    fn the_images_extremalities_put_the_ridge_closer_than_discrete_differences() {
        let third = Some(DerivativeOrder::Third);
        let surface = isosurface(
            &ellipsoid(),
            -1.0,
            &IsoOptions::default(),
            third,
            &mut Silent,
        )
        .unwrap();
        assert!(surface.has_image_extremalities());
        let image = surface.curvature.clone().expect("the image's curvature");
        // The same surface and curvature as a mesh with given curvature: the
        // discrete extremalities, with their default smoothing.
        let discrete = Surface {
            mesh: surface.mesh.clone(),
            curvature: Some(Arc::new(WithoutExtremality(image))),
            image: None,
        };
        let (by_image, lines) = ridge_offset(&surface, None);
        let (unsmoothed, _) = ridge_offset(&surface, Some(0));
        let (by_differences, _) = ridge_offset(&discrete, None);
        println!(
            "ridge from the true plane: {by_image:.4} voxel with the image's extremalities \
             ({unsmoothed:.4} unsmoothed), {by_differences:.4} with discrete differences"
        );
        // Measured: 0.022, 0.0021 and 0.093 voxel.
        assert_eq!(lines, 1, "the ridge is one closed line");
        assert!(
            by_image * 3.0 <= by_differences,
            "{by_image} against {by_differences}"
        );
        assert!(unsmoothed <= 0.01, "{unsmoothed} voxel unsmoothed");
    }

    /// A job that needs the curvature alone gets the same curvature from the first
    /// and second derivatives, without extremalities; one that needs neither gets
    /// the surface alone.
    #[test]
    fn the_isosurface_computes_only_the_derivatives_its_job_needs() {
        let volume = ellipsoid();
        let options = IsoOptions::default();
        let full = isosurface(
            &volume,
            -1.0,
            &options,
            Some(DerivativeOrder::Third),
            &mut Silent,
        )
        .unwrap();
        let second = isosurface(
            &volume,
            -1.0,
            &options,
            Some(DerivativeOrder::Second),
            &mut Silent,
        )
        .unwrap();
        assert!(!second.has_image_extremalities());
        let estimate = |s: &Surface| s.curvature.as_ref().unwrap().estimate(&s.mesh).unwrap();
        let (a, b) = (estimate(&full), estimate(&second));
        assert!(a.extremality.is_some() && b.extremality.is_none());
        assert_eq!((a.k_max, a.d_max, a.normal), (b.k_max, b.d_max, b.normal));
        let bare = isosurface(&volume, -1.0, &options, None, &mut Silent).unwrap();
        assert!(bare.curvature.is_none() && !bare.has_image_extremalities());
        assert_eq!(bare.mesh.positions(), full.mesh.positions());
    }
}

/// The extremalities come with a Gaussian's smooth third derivatives, not with the
/// cubic B-spline's (σ = 0), which jump across every grid plane.
#[test]
fn only_a_gaussian_gives_the_images_extremalities() {
    use crate::curvature::{CurvatureEstimator, ImageCurvature};

    let volume = sampled::field(24, [1.0; 3], Matrix3::identity(), |p| {
        -p.coords.norm_squared()
    });
    let (iso, _) = crate::curvature::image_isosurface(&volume, -64.0, 1.0).unwrap();
    let mesh = iso.to_mesh().unwrap();
    let gaussian = ImageCurvature::new(&volume, 1.0)
        .unwrap()
        .estimate(&mesh)
        .unwrap();
    let spline = ImageCurvature::new(&volume, 0.0)
        .unwrap()
        .estimate(&mesh)
        .unwrap();
    let [e_max, e_min] = gaussian.extremality.expect("a Gaussian's extremalities");
    // A sphere: every direction is principal and the curvature is constant.
    let largest = e_max
        .iter()
        .chain(&e_min)
        .fold(0.0f64, |m, e| m.max(e.abs()));
    assert!(
        largest < 1e-3,
        "extremality {largest} on a sphere of radius 8"
    );
    assert!(spline.extremality.is_none());
}
