//! Curvature and extremalities of iso-surfaces from image derivatives
//! (`differential::isosurface_curvature`), against closed forms and finite
//! differences on cubic polynomial fields, whose derivatives are exact.

use crestline::differential::{isosurface_curvature, IsoCurvature, ThirdOrder};
use crestline::{Point, Vector};
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

#[test]
fn spline_jets_give_the_ellipsoid_extremalities_between_samples() {
    use crestline::volume::{BSpline, Volume};
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
