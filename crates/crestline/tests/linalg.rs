//! Sparse Cholesky solves of `crestline::linalg` against dense solves and residuals.

use crestline::linalg::{CholeskyFactor, SymmetricBuilder, SymmetricMatrix};
use crestline::mesh::generate::{self, Sampling};
use crestline::mesh::Mesh;
use crestline::Error;
use nalgebra::{DMatrix, DVector};

/// The 1D Poisson matrix tridiag(−1, 2, −1) plus `shift` times the identity.
fn poisson_1d(n: usize, shift: f64) -> SymmetricMatrix {
    let mut builder = SymmetricBuilder::new(n);
    for i in 0..n {
        builder.add_diagonal(i, 2.0 + shift);
        if i + 1 < n {
            builder.add(i, i + 1, -1.0);
        }
    }
    builder.build()
}

/// `M + t K` of §5.1: lumped masses plus `t` times the cotan Laplacian with
/// weights clamped at 0.
fn mass_plus_stiffness(mesh: &Mesh, t: f64) -> SymmetricMatrix {
    let mut builder = SymmetricBuilder::new(mesh.vertex_count());
    for (v, mass) in mesh.vertex_areas().into_iter().enumerate() {
        builder.add_diagonal(v, mass);
    }
    for (e, w) in mesh.edges().zip(mesh.cotan_weights()) {
        let [p, q] = mesh.edge_vertices(e);
        builder.add_edge(p.idx(), q.idx(), t * w.max(0.0));
    }
    builder.build()
}

fn dense(matrix: &SymmetricMatrix) -> DMatrix<f64> {
    let mut a = DMatrix::zeros(matrix.size(), matrix.size());
    for (i, j, value) in matrix.entries() {
        a[(i, j)] += value;
    }
    a
}

fn relative_residual(matrix: &SymmetricMatrix, x: &[f64], b: &[f64]) -> f64 {
    let mut ax = vec![0.0; matrix.size()];
    for (i, j, value) in matrix.entries() {
        ax[i] += value * x[j];
    }
    let r: f64 = ax.iter().zip(b).map(|(p, q)| (p - q).powi(2)).sum();
    let bn: f64 = b.iter().map(|q| q * q).sum();
    (r / bn).sqrt()
}

fn max_abs_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (p - q).abs())
        .fold(0.0, f64::max)
}

fn rhs(n: usize, phase: f64) -> Vec<f64> {
    (0..n).map(|i| (i as f64 * 0.37 + phase).sin()).collect()
}

#[test]
fn poisson_matches_dense_solve() {
    let n = 40;
    let matrix = poisson_1d(n, 1.0);
    let b = rhs(n, 0.0);
    let x = CholeskyFactor::new(&matrix).unwrap().solve(&b);
    let expected = dense(&matrix)
        .cholesky()
        .unwrap()
        .solve(&DVector::from_vec(b));
    assert!(max_abs_difference(&x, expected.as_slice()) < 1e-12);
}

#[test]
fn sphere_smoothing_system_has_small_residual() {
    let mesh = generate::sphere(1.0, 2000, Sampling::jittered(3))
        .unwrap()
        .mesh;
    let h = mesh.mean_edge_length();
    let matrix = mass_plus_stiffness(&mesh, 2.0 * h * h);
    let factor = CholeskyFactor::new(&matrix).unwrap();
    let b: Vec<f64> = mesh.positions().iter().map(|p| p.x * p.y + p.z).collect();
    let x = factor.solve(&b);
    assert!(relative_residual(&matrix, &x, &b) < 1e-10);
}

#[test]
fn negative_identity_is_an_error() {
    let mut builder = SymmetricBuilder::new(5);
    for i in 0..5 {
        builder.add_diagonal(i, -1.0);
    }
    let err = CholeskyFactor::new(&builder.build()).unwrap_err();
    assert!(matches!(err, Error::Argument(_)), "{err}");
    assert!(err.to_string().contains("not positive definite"), "{err}");
}

#[test]
fn indefinite_matrix_is_an_error() {
    let mut builder = SymmetricBuilder::new(2);
    builder.add_diagonal(0, 1.0);
    builder.add_diagonal(1, 1.0);
    builder.add(0, 1, 2.0);
    assert!(CholeskyFactor::new(&builder.build()).is_err());
}

#[test]
fn non_square_and_nan_matrices_are_errors() {
    // Two columns of three rows cannot be a square matrix.
    let rectangular = SymmetricMatrix::from_csc(3, vec![0, 1, 2], vec![0, 1], vec![1.0, 1.0]);
    assert!(rectangular.is_err());
    let mut builder = SymmetricBuilder::new(2);
    builder.add_diagonal(0, 1.0);
    builder.add_diagonal(1, f64::NAN);
    let err = CholeskyFactor::new(&builder.build()).unwrap_err();
    assert!(err.to_string().contains("not finite"), "{err}");
}

#[test]
fn refactor_with_new_values_gives_the_new_solution() {
    let n = 30;
    let b = rhs(n, 1.0);
    let mut factor = CholeskyFactor::new(&poisson_1d(n, 1.0)).unwrap();
    let updated = poisson_1d(n, 0.25);
    factor.refactor(&updated).unwrap();
    let expected = CholeskyFactor::new(&updated).unwrap().solve(&b);
    assert!(max_abs_difference(&factor.solve(&b), &expected) < 1e-13);
    assert!(relative_residual(&updated, &factor.solve(&b), &b) < 1e-12);
}

#[test]
fn refactor_with_a_new_pattern_and_failed_refactor() {
    let n = 20;
    let b = rhs(n, 2.0);
    let mut factor = CholeskyFactor::new(&poisson_1d(n, 1.0)).unwrap();
    let mut builder = SymmetricBuilder::new(n);
    for i in 0..n {
        builder.add_diagonal(i, 3.0);
    }
    builder.add(0, n - 1, 1.0);
    let other = builder.build();
    factor.refactor(&other).unwrap();
    assert!(relative_residual(&other, &factor.solve(&b), &b) < 1e-12);

    let before = factor.solve(&b);
    assert!(factor.refactor(&poisson_1d(n, -3.0)).is_err());
    assert_eq!(
        factor.solve(&b),
        before,
        "a failed refactor keeps the factor"
    );
}

#[test]
fn multi_rhs_equals_single_solves() {
    let mesh = generate::torus(1.0, 0.35, 3000, Sampling::jittered(5))
        .unwrap()
        .mesh;
    let h = mesh.mean_edge_length();
    let factor = CholeskyFactor::new(&mass_plus_stiffness(&mesh, 2.0 * h * h)).unwrap();
    let positions = mesh.positions();
    let mut columns: Vec<Vec<f64>> = (0..3)
        .map(|k| positions.iter().map(|p| p[k]).collect())
        .collect();
    let singles: Vec<Vec<f64>> = columns.iter().map(|c| factor.solve(c)).collect();
    factor.solve_columns(&mut columns);
    for (multi, single) in columns.iter().zip(&singles) {
        assert!(max_abs_difference(multi, single) < 1e-13);
    }
}

#[test]
fn the_builder_sums_repeated_entries_into_sorted_columns() {
    let mut builder = SymmetricBuilder::new(3);
    builder.add(2, 0, 1.5);
    builder.add_diagonal(1, 4.0);
    builder.add_edge(0, 1, 2.0);
    builder.add(0, 2, 0.5);
    let matrix = builder.build();
    let entries: Vec<(usize, usize, f64)> = matrix.entries().collect();
    assert_eq!(
        entries,
        [
            (0, 0, 2.0),
            (1, 0, -2.0),
            (2, 0, 2.0),
            (0, 1, -2.0),
            (1, 1, 6.0),
            (0, 2, 2.0),
        ]
    );
    let (col_ptr, rows, values) = matrix.csc();
    let copy = SymmetricMatrix::from_csc(3, col_ptr.to_vec(), rows.to_vec(), values.to_vec());
    assert_eq!(copy.unwrap(), matrix);
    let unsorted = SymmetricMatrix::from_csc(2, vec![0, 2, 2], vec![1, 0], vec![1.0, 1.0]);
    assert!(unsorted.unwrap_err().to_string().contains("unsorted"));
}
