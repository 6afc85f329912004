//! The two solvers of the implicit smoothing systems (M + t K) x' = M x
//! (Hildebrandt et al. 2005, §5.1): sparse Cholesky factorization and the
//! conjugate gradient method give the same lines, the iteration meets its
//! tolerance, and it falls back to the factorization when it cannot.

use crestline::linalg::{
    conjugate_gradient, CgSettings, CholeskyFactor, Solver, SpdSolver, SymmetricBuilder,
    SymmetricMatrix,
};
use crestline::lines::{FeatureLines, LineExtractor};
use crestline::mesh::generate::{self, Sampling};
use crestline::mesh::{EdgeId, Mesh};
use crestline::progress::Silent;
use crestline::ridges::ExtremalityTracer;

fn lines(mesh: &Mesh, solver: Solver, presmooth_steps: usize) -> FeatureLines {
    ExtremalityTracer {
        solver,
        presmooth_steps,
        ..ExtremalityTracer::default()
    }
    .extract(mesh, &mut Silent)
    .unwrap()
}

/// Same number of lines, of points per line, and every point within 10⁻⁶ of the
/// bounding box diagonal.
fn assert_same_lines(mesh: &Mesh, presmooth_steps: usize, what: &str) {
    let direct = lines(mesh, Solver::Direct, presmooth_steps);
    let iterative = lines(mesh, Solver::Iterative, presmooth_steps);
    assert!(!direct.is_empty(), "{what}: no lines");
    assert_eq!(direct.len(), iterative.len(), "{what}: line counts");
    let slack = 1e-6 * mesh.bounding_box().diagonal();
    for (a, b) in direct.iter().zip(iterative.iter()) {
        assert_eq!(a.points.len(), b.points.len(), "{what}: points of a line");
        for (p, q) in a.points.iter().zip(&b.points) {
            assert!((p - q).norm() <= slack, "{what}: {p} and {q} differ");
        }
    }
}

fn bunny() -> Mesh {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../meshes/bunny.obj");
    Mesh::from_soup(crestline::io::read_mesh(&path).unwrap())
        .unwrap()
        .0
}

#[test]
fn both_solvers_give_the_same_lines() {
    let ellipsoid = generate::ellipsoid([1.0, 0.7, 0.45], 30_000, Sampling::jittered(1))
        .unwrap()
        .mesh;
    let torus = generate::torus(1.0, 0.35, 20_000, Sampling::jittered(6))
        .unwrap()
        .mesh;
    assert_same_lines(&ellipsoid, 0, "ellipsoid");
    assert_same_lines(&torus, 0, "torus");
    assert_same_lines(&bunny(), 0, "bunny");
}

#[test]
fn both_solvers_give_the_same_lines_after_presmoothing() {
    assert_same_lines(&bunny(), 2, "presmoothed bunny");
}

/// M + t K of a sphere with the cotan Laplacian, t = 2 h̄² (the default τ), and
/// the right-hand side M e for a smooth e.
fn sphere_system() -> (SymmetricMatrix, Vec<f64>) {
    let mesh = generate::sphere(1.0, 30_000, Sampling::jittered(3))
        .unwrap()
        .mesh;
    let h = mesh.mean_edge_length();
    let time = 2.0 * h * h;
    let mass = mesh.vertex_areas();
    let mut system = SymmetricBuilder::new(mesh.vertex_count());
    for (v, &m) in mass.iter().enumerate() {
        system.add_diagonal(v, m);
    }
    for (e, w) in mesh.clamped_cotan_weights().into_iter().enumerate() {
        let [p, q] = mesh.edge_vertices(EdgeId(e as u32)).map(|v| v.idx());
        system.add_edge(p, q, time * w);
    }
    let rhs = mesh
        .positions()
        .iter()
        .zip(&mass)
        .map(|(p, m)| m * (3.0 * p.x + p.y * p.z).sin())
        .collect();
    (system.build(), rhs)
}

fn relative_residual(matrix: &SymmetricMatrix, rhs: &[f64], x: &[f64]) -> f64 {
    let mut ax = vec![0.0; x.len()];
    matrix.mul_vec(x, &mut ax);
    let norm = |v: &mut dyn Iterator<Item = f64>| v.map(|x| x * x).sum::<f64>().sqrt();
    norm(&mut rhs.iter().zip(&ax).map(|(b, y)| b - y)) / norm(&mut rhs.iter().copied())
}

#[test]
fn conjugate_gradient_meets_its_tolerance_on_a_sphere() {
    let (matrix, rhs) = sphere_system();
    assert!(matrix.dominance_ratio() < 100.0);
    let settings = CgSettings::default();
    let mut x = rhs.clone();
    let report = conjugate_gradient(&matrix, &rhs, &mut x, settings).unwrap();
    eprintln!("{report:?}");
    assert!(report.converged);
    assert!(report.iterations > 1 && report.iterations < settings.max_iterations);
    assert!(report.relative_residual <= settings.tolerance);
    assert!(relative_residual(&matrix, &rhs, &x) <= settings.tolerance);
    let exact = CholeskyFactor::new(&matrix).unwrap().solve(&rhs);
    let scale = exact.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for (a, b) in x.iter().zip(&exact) {
        assert!((a - b).abs() <= 1e-8 * scale);
    }
}

#[test]
fn conjugate_gradient_capped_at_one_iteration_falls_back_to_the_factorization() {
    let (matrix, rhs) = sphere_system();
    let capped = CgSettings {
        max_iterations: 1,
        ..CgSettings::default()
    };
    let mut x = rhs.clone();
    let report = conjugate_gradient(&matrix, &rhs, &mut x, capped).unwrap();
    assert!(!report.converged && report.iterations == 1);

    let exact = CholeskyFactor::new(&matrix).unwrap().solve(&rhs);
    let mut solver = SpdSolver::new(Solver::Iterative, capped);
    solver.set_matrix(matrix.clone()).unwrap();
    for _ in 0..2 {
        let mut x = rhs.clone();
        solver.solve(&rhs, &mut x).unwrap();
        assert!(relative_residual(&matrix, &rhs, &x) < 1e-12);
        let scale = exact.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (a, b) in x.iter().zip(&exact) {
            assert!((a - b).abs() <= 1e-12 * scale);
        }
    }
}

#[test]
fn auto_takes_the_iteration_only_for_large_well_shaped_systems() {
    let (matrix, _) = sphere_system();
    assert_eq!(
        Solver::Auto.resolve(&matrix),
        Solver::Direct,
        "30k unknowns"
    );
    assert_eq!(Solver::Iterative.resolve(&matrix), Solver::Iterative);
    assert_eq!(Solver::Direct.resolve(&matrix), Solver::Direct);
    let mut sliver = SymmetricBuilder::new(2);
    sliver.add_diagonal(0, 1e-6);
    sliver.add_diagonal(1, 1.0);
    sliver.add_edge(0, 1, 1.0);
    assert!(sliver.build().dominance_ratio() > 1e5);
}

#[test]
fn solver_names_round_trip() {
    for &name in Solver::NAMES {
        assert_eq!(name.parse::<Solver>().unwrap().name(), name);
    }
    assert!("cholesky".parse::<Solver>().is_err());
    assert_eq!(Solver::default(), Solver::Auto);
}
