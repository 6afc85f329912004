//! The analytic test surfaces: topology, vertices on the surface, and exact
//! curvatures against closed forms.

use crestline::mesh::generate::{self, AnalyticMesh, Paraboloid, Sampling};

const SAMPLINGS: [Sampling; 2] = [
    Sampling::Regular,
    Sampling::Jittered {
        amount: 0.25,
        seed: 7,
    },
];

fn assert_close(a: f64, b: f64, tol: f64, what: &str) {
    assert!((a - b).abs() <= tol, "{what}: {a} vs {b}");
}

/// A valid halfedge structure with finite, non-degenerate faces.
fn assert_valid(surface: &AnalyticMesh) {
    let mesh = &surface.mesh;
    mesh.check_connectivity().unwrap();
    assert!(mesh.faces().all(|f| mesh.face_area(f) > 0.0));
}

#[test]
fn sphere_is_closed_genus_zero_with_curvature_one_over_radius() {
    for sampling in SAMPLINGS {
        let s = generate::sphere(2.0, 5000, sampling).unwrap();
        let mesh = &s.mesh;
        assert!(
            (4500..=5500).contains(&mesh.vertex_count()),
            "{}",
            mesh.vertex_count()
        );
        assert_eq!(mesh.euler_characteristic(), 2);
        let components = mesh.components();
        assert_eq!(components.len(), 1);
        assert_eq!((components[0].genus, components[0].boundary_loops), (0, 0));
        assert_valid(&s);
        for (p, k) in mesh.positions().iter().zip(&s.exact) {
            assert_close(p.coords.norm(), 2.0, 1e-12, "on the sphere");
            assert_close(k.k_max, 0.5, 1e-12, "k_max");
            assert_close(k.k_min, 0.5, 1e-12, "k_min");
        }
        // Outward orientation: face normals agree with the radial direction.
        for f in mesh.faces() {
            let [a, _, _] = mesh.face_points(f);
            assert!(mesh.face_normal(f).dot(&a.coords) > 0.0);
        }
    }
}

#[test]
fn jitter_makes_the_sphere_irregular() {
    let regular = generate::sphere(1.0, 5000, Sampling::Regular).unwrap().mesh;
    let jittered = generate::sphere(1.0, 5000, Sampling::jittered(1))
        .unwrap()
        .mesh;
    let spread = |m: &crestline::mesh::Mesh| {
        let lengths = m.edge_lengths();
        let mean = lengths.iter().sum::<f64>() / lengths.len() as f64;
        (lengths.iter().map(|l| (l - mean).powi(2)).sum::<f64>() / lengths.len() as f64).sqrt()
            / mean
    };
    assert!(spread(&jittered) > 2.0 * spread(&regular));
    assert!(spread(&jittered) > 0.15);
}

#[test]
fn ellipsoid_curvature_matches_closed_form_at_the_axis_tips() {
    let (a, b, c) = (1.0, 0.7, 0.45);
    for sampling in SAMPLINGS {
        let s = generate::ellipsoid([a, b, c], 20_000, sampling).unwrap();
        assert_eq!(s.mesh.euler_characteristic(), 2);
        assert_valid(&s);
        for (p, k) in s.mesh.positions().iter().zip(&s.exact) {
            let level = (p.x / a).powi(2) + (p.y / b).powi(2) + (p.z / c).powi(2);
            assert_close(level, 1.0, 1e-12, "on the ellipsoid");
            assert!(k.k_max >= k.k_min && k.k_min > 0.0);
            // Gaussian curvature of an ellipsoid: 1 / (a b c)² / (x²/a⁴ + y²/b⁴ + z²/c⁴)².
            let s4 = p.x * p.x / a.powi(4) + p.y * p.y / b.powi(4) + p.z * p.z / c.powi(4);
            assert_close(
                k.gauss(),
                1.0 / ((a * b * c).powi(2) * s4 * s4),
                1e-9,
                "Gauss",
            );
            assert_close(k.d_max.norm(), 1.0, 1e-12, "unit d_max");
            assert_close(k.d_max.dot(&k.d_min), 0.0, 1e-12, "orthogonal directions");
        }
    }
    // At the tip (a, 0, 0) the curvatures are a/b² and a/c², with d_max along z.
    let tip = generate::Ellipsoid { axes: [a, b, c] };
    let k = crestline::mesh::generate::ImplicitSurface::curvature(
        &tip,
        &crestline::Point::new(a, 0.0, 0.0),
    );
    assert_close(k.k_max, a / (c * c), 1e-12, "k_max at tip");
    assert_close(k.k_min, a / (b * b), 1e-12, "k_min at tip");
    assert_close(k.d_max.z.abs(), 1.0, 1e-12, "d_max at tip");
}

#[test]
fn torus_is_genus_one_with_closed_form_curvature() {
    let (big, small) = (1.0, 0.35);
    for sampling in SAMPLINGS {
        let s = generate::torus(big, small, 20_000, sampling).unwrap();
        let mesh = &s.mesh;
        assert_eq!(mesh.euler_characteristic(), 0);
        let components = mesh.components();
        assert_eq!((components.len(), components[0].genus), (1, 1));
        for (p, k) in mesh.positions().iter().zip(&s.exact) {
            let rho = p.x.hypot(p.y);
            assert_close((rho - big).hypot(p.z), small, 1e-12, "on the torus");
            // Meridian curvature 1/r; parallel curvature cos v / (R + r cos v).
            let cos_v = (rho - big) / small;
            let parallel = cos_v / rho;
            let meridian = 1.0 / small;
            assert_close(k.k_max, meridian.max(parallel), 1e-9, "k_max");
            assert_close(k.k_min, meridian.min(parallel), 1e-9, "k_min");
        }
        // Outward: the normal points away from the tube's core circle.
        for f in mesh.faces() {
            let [p, _, _] = mesh.face_points(f);
            let rho = p.x.hypot(p.y);
            let core = crestline::Point::new(p.x / rho * big, p.y / rho * big, 0.0);
            assert!(mesh.face_normal(f).dot(&(p - core)) > 0.0);
        }
    }
}

#[test]
fn height_field_is_a_disk_with_upward_normals_and_exact_curvature() {
    let f = Paraboloid { a: -2.0, b: -0.5 };
    for sampling in SAMPLINGS {
        let s = generate::height_field(&f, 0.5, 4000, sampling).unwrap();
        let mesh = &s.mesh;
        let components = mesh.components();
        assert_eq!(components.len(), 1);
        assert_eq!(
            (
                components[0].euler_characteristic,
                components[0].boundary_loops
            ),
            (1, 1)
        );
        assert!(mesh.faces().all(|face| mesh.face_normal(face).z > 0.0));
        let origin = mesh
            .vertices()
            .min_by(|&u, &v| {
                let (p, q) = (mesh.position(u), mesh.position(v));
                p.coords.xy().norm().total_cmp(&q.coords.xy().norm())
            })
            .unwrap();
        let k = s.exact[origin.idx()];
        let p = mesh.position(origin);
        // Near the apex of a downward cap with upward normal: curvatures 2 and 0.5.
        assert!(p.coords.xy().norm() < 0.02);
        assert_close(k.k_max, 2.0, 0.05, "k_max near apex");
        assert_close(k.k_min, 0.5, 0.05, "k_min near apex");
    }
}
