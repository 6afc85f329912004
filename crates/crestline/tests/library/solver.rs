//! The two solvers of the implicit smoothing systems (M + t K) x' = M x
//! (Hildebrandt et al. 2005, §5.1), sparse Cholesky factorization and the
//! conjugate gradient method, give the same lines. (The solvers themselves are
//! tested in the crate's `linalg` module.)

use crestline::lines::{FeatureLines, LineExtractor};
use crestline::mesh::generate::{self, Sampling};
use crestline::mesh::Mesh;
use crestline::progress::Silent;
use crestline::ridges::{ExtremalityTracer, Solver};

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
