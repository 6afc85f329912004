//! Sparse symmetric positive definite systems for the implicit smoothing steps of
//! the ridge pipeline (Hildebrandt et al. 2005, §5.1):
//!
//! - extremality smoothing `(M + t K) e' = M e`, one matrix for many steps and
//!   many right-hand sides: factor once with [`CholeskyFactor::new`], then solve
//!   repeatedly;
//! - surface smoothing `(M + t L) x' = M x`, where the matrix changes every step but
//!   keeps its sparsity pattern: [`CholeskyFactor::refactor`] reuses the fill-reducing
//!   ordering and symbolic analysis, and [`CholeskyFactor::solve_columns`] solves for
//!   the three coordinates at once.
//!
//! Matrices are assembled with [`SymmetricBuilder`] into a [`SymmetricMatrix`]
//! (compressed columns, bucketed in linear time) and factored by a supernodal sparse
//! Cholesky factorization `P A Pᵀ = L Lᵀ` (faer, approximate minimum degree ordering).
//!
//! Both matrices are M plus a small multiple of a Laplacian, diagonally dominant
//! and well conditioned, so on large meshes the Jacobi-preconditioned conjugate
//! gradient method ([`conjugate_gradient`]), warm-started from the previous step,
//! needs few iterations and beats the factorization; [`SpdSolver`] chooses between
//! the two ([`Solver`]) and falls back to the factorization when the iteration
//! does not converge.

use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Mat, MatMut, Side};
use rayon::prelude::*;

use crate::{Error, Result};

/// Assembles a symmetric `n × n` sparse matrix from entries that may repeat;
/// repeated entries are summed.
///
/// [`add`](Self::add) writes an off-diagonal value to both `(i, j)` and `(j, i)`, so
/// the built matrix is symmetric by construction.
#[derive(Debug)]
pub struct SymmetricBuilder {
    n: usize,
    /// `(row, column, value)` entries, in the order added.
    triplets: Vec<(usize, usize, f64)>,
}

impl SymmetricBuilder {
    /// An empty `n × n` matrix.
    pub fn new(n: usize) -> SymmetricBuilder {
        SymmetricBuilder::with_capacity(n, 0)
    }

    /// An empty `n × n` matrix with room for `entries` stored entries (an
    /// off-diagonal [`add`](Self::add) stores two, [`add_edge`](Self::add_edge) four).
    pub fn with_capacity(n: usize, entries: usize) -> SymmetricBuilder {
        SymmetricBuilder {
            n,
            triplets: Vec::with_capacity(entries),
        }
    }

    /// The matrix size `n`.
    pub fn size(&self) -> usize {
        self.n
    }

    /// Adds `value` to entry `(i, j)` and, when `i ≠ j`, to `(j, i)`.
    ///
    /// # Panics
    /// If `i` or `j` is not below [`size`](Self::size).
    pub fn add(&mut self, i: usize, j: usize, value: f64) {
        assert!(
            i < self.n && j < self.n,
            "entry ({i}, {j}) of a {n}×{n} matrix",
            n = self.n
        );
        self.triplets.push((i, j, value));
        if i != j {
            self.triplets.push((j, i, value));
        }
    }

    /// Adds `value` to the diagonal entry `(i, i)`, e.g. a lumped vertex mass.
    ///
    /// # Panics
    /// If `i` is not below [`size`](Self::size).
    pub fn add_diagonal(&mut self, i: usize, value: f64) {
        self.add(i, i, value);
    }

    /// Adds the stiffness of one edge `(i, j)` with weight `w`: `w` to both diagonal
    /// entries and `−w` to both off-diagonal ones. Summed over the edges with cotan
    /// weights this is the Laplacian `K` (`K_pp = Σ w`, `K_pq = −w`) of §5.1.
    ///
    /// # Panics
    /// If `i` or `j` is not below [`size`](Self::size), or `i == j`.
    pub fn add_edge(&mut self, i: usize, j: usize, w: f64) {
        assert_ne!(i, j, "an edge needs two distinct vertices");
        self.add_diagonal(i, w);
        self.add_diagonal(j, w);
        self.add(i, j, -w);
    }

    /// The assembled matrix in compressed sparse column form, repeated entries
    /// summed: entries are bucketed by column (linear time), then each column is
    /// sorted by row.
    pub fn build(&self) -> SymmetricMatrix {
        let mut col_ptr = vec![0usize; self.n + 1];
        for &(_, j, _) in &self.triplets {
            col_ptr[j + 1] += 1;
        }
        for j in 0..self.n {
            col_ptr[j + 1] += col_ptr[j];
        }
        let mut next = col_ptr.clone();
        let mut entries = vec![(0usize, 0.0f64); self.triplets.len()];
        for &(i, j, value) in &self.triplets {
            entries[next[j]] = (i, value);
            next[j] += 1;
        }
        let mut matrix = SymmetricMatrix {
            n: self.n,
            col_ptr: Vec::with_capacity(self.n + 1),
            row_idx: Vec::with_capacity(entries.len()),
            values: Vec::with_capacity(entries.len()),
        };
        matrix.col_ptr.push(0);
        for j in 0..self.n {
            let column = &mut entries[col_ptr[j]..col_ptr[j + 1]];
            column.sort_unstable_by_key(|&(i, _)| i);
            let start = matrix.row_idx.len();
            for &(i, value) in column.iter() {
                match matrix.values.last_mut() {
                    Some(sum)
                        if matrix.row_idx.len() > start && matrix.row_idx.last() == Some(&i) =>
                    {
                        *sum += value;
                    }
                    _ => {
                        matrix.row_idx.push(i);
                        matrix.values.push(value);
                    }
                }
            }
            matrix.col_ptr.push(matrix.row_idx.len());
        }
        matrix
    }
}

/// A square sparse matrix in compressed sparse column form (both triangles stored),
/// as [`SymmetricBuilder`] makes it and [`CholeskyFactor`] reads it.
#[derive(Clone, Debug, PartialEq)]
pub struct SymmetricMatrix {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    values: Vec<f64>,
}

impl SymmetricMatrix {
    /// A matrix from its compressed columns: `col_ptr` (n + 1 offsets), the row of
    /// every entry and its value. Errors if the arrays do not describe an `n × n`
    /// matrix with sorted, distinct rows in every column.
    pub fn from_csc(
        n: usize,
        col_ptr: Vec<usize>,
        row_idx: Vec<usize>,
        values: Vec<f64>,
    ) -> Result<SymmetricMatrix> {
        let bad = |what: String| Err(Error::Argument(what));
        if col_ptr.len() != n + 1 {
            return bad(format!(
                "{} column offsets for a square matrix of {n} columns (it is not square)",
                col_ptr.len()
            ));
        }
        if col_ptr[0] != 0 || col_ptr.windows(2).any(|w| w[0] > w[1]) {
            return bad("column offsets must start at 0 and not decrease".into());
        }
        if row_idx.len() != values.len() || col_ptr[n] != row_idx.len() {
            return bad("column offsets, rows and values disagree in length".into());
        }
        if let Some(&i) = row_idx.iter().find(|&&i| i >= n) {
            return bad(format!("row {i} in a {n}×{n} matrix"));
        }
        let matrix = SymmetricMatrix {
            n,
            col_ptr,
            row_idx,
            values,
        };
        let increasing = |j: usize| {
            let rows = &matrix.row_idx[matrix.col_ptr[j]..matrix.col_ptr[j + 1]];
            rows.windows(2).all(|w| w[0] < w[1])
        };
        match (0..n).find(|&j| !increasing(j)) {
            Some(j) => bad(format!(
                "column {j} of the matrix has unsorted or repeated row indices"
            )),
            None => Ok(matrix),
        }
    }

    /// The size `n` of the `n × n` matrix.
    pub fn size(&self) -> usize {
        self.n
    }

    /// The entries `(row, value)` of column `j`, by increasing row.
    pub fn column(&self, j: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let range = self.col_ptr[j]..self.col_ptr[j + 1];
        self.row_idx[range.clone()]
            .iter()
            .copied()
            .zip(self.values[range].iter().copied())
    }

    /// Every stored entry as `(row, column, value)`, column by column.
    pub fn entries(&self) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        (0..self.n).flat_map(move |j| self.column(j).map(move |(i, v)| (i, j, v)))
    }

    /// The compressed columns: offsets, rows and values (e.g. to hand the matrix to
    /// another solver).
    pub fn csc(&self) -> (&[usize], &[usize], &[f64]) {
        (&self.col_ptr, &self.row_idx, &self.values)
    }

    /// The diagonal entries (zero where none is stored).
    pub fn diagonal(&self) -> Vec<f64> {
        (0..self.n)
            .map(|j| {
                self.column(j)
                    .find(|&(i, _)| i == j)
                    .map_or(0.0, |(_, v)| v)
            })
            .collect()
    }

    /// max_i a_ii / (a_ii − Σ_{j≠i} |a_ij|): how far the matrix is from losing
    /// strict diagonal dominance; infinite if it is not strictly diagonally
    /// dominant with a positive diagonal. For M + t K (§5.1) the excess
    /// a_ii − Σ |a_ij| is the lumped mass m_i, so the ratio is the largest
    /// (m_i + t K_ii) / m_i. With E the diagonal of excesses and D the diagonal,
    /// E ≤ A ≤ 2 D, so the ratio r bounds the condition number of the
    /// Jacobi-preconditioned matrix D⁻¹A by 2 r.
    pub fn dominance_ratio(&self) -> f64 {
        (0..self.n)
            .map(|i| {
                let (diagonal, off) =
                    self.column(i).fold(
                        (0.0, 0.0),
                        |(d, o), (j, v)| {
                            if j == i {
                                (v, o)
                            } else {
                                (d, o + v.abs())
                            }
                        },
                    );
                let excess = diagonal - off;
                if excess > 0.0 && diagonal.is_finite() {
                    diagonal / excess
                } else {
                    f64::INFINITY
                }
            })
            .fold(0.0, f64::max)
    }

    /// `y = A x`, in parallel over rows. Both triangles are stored, so column `i`
    /// of the symmetric matrix is its row `i`.
    ///
    /// # Panics
    /// If `x` or `y` does not have length [`size`](Self::size).
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        assert!(
            x.len() == self.n && y.len() == self.n,
            "product of a {n}×{n} matrix with vectors of length {} and {}",
            x.len(),
            y.len(),
            n = self.n
        );
        y.par_chunks_mut(CHUNK).enumerate().for_each(|(c, rows)| {
            for (k, yi) in rows.iter_mut().enumerate() {
                *yi = self.row_dot(c * CHUNK + k, x);
            }
        });
    }

    /// Row `i` of the matrix times `x`.
    fn row_dot(&self, i: usize, x: &[f64]) -> f64 {
        let range = self.col_ptr[i]..self.col_ptr[i + 1];
        self.row_idx[range.clone()]
            .iter()
            .zip(&self.values[range])
            .map(|(&j, v)| v * x[j])
            .sum()
    }
}

/// The lower triangle of a square sparse matrix in compressed column form, the
/// layout the factorization reads.
#[derive(Clone, Debug, PartialEq)]
struct LowerTriangle {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    values: Vec<f64>,
}

impl LowerTriangle {
    /// Extracts the entries `(i, j)` with `i ≥ j` of `matrix`, checking that they
    /// are finite.
    fn new(matrix: &SymmetricMatrix) -> Result<LowerTriangle> {
        let n = matrix.size();
        let stored = matrix.row_idx.len();
        let mut lower = LowerTriangle {
            n,
            col_ptr: Vec::with_capacity(n + 1),
            row_idx: Vec::with_capacity(stored / 2 + n),
            values: Vec::with_capacity(stored / 2 + n),
        };
        lower.col_ptr.push(0);
        for j in 0..n {
            lower.push_column(j, matrix.column(j))?;
        }
        Ok(lower)
    }

    /// Appends the lower part (rows `≥ j`) of column `j`.
    fn push_column(&mut self, j: usize, entries: impl Iterator<Item = (usize, f64)>) -> Result<()> {
        for (i, value) in entries {
            if !value.is_finite() {
                return Err(Error::Argument(format!(
                    "matrix entry ({i}, {j}) is not finite ({value})"
                )));
            }
            if i >= j {
                self.row_idx.push(i);
                self.values.push(value);
            }
        }
        self.col_ptr.push(self.row_idx.len());
        Ok(())
    }

    /// Whether `other` has the same size and nonzero pattern.
    fn same_pattern(&self, other: &LowerTriangle) -> bool {
        self.n == other.n && self.col_ptr == other.col_ptr && self.row_idx == other.row_idx
    }

    /// A faer view of the pattern alone.
    fn symbolic(&self) -> SymbolicSparseColMatRef<'_, usize> {
        SymbolicSparseColMatRef::new_checked(self.n, self.n, &self.col_ptr, None, &self.row_idx)
    }

    /// A faer view of pattern and values.
    fn view(&self) -> SparseColMatRef<'_, usize, f64> {
        SparseColMatRef::new(self.symbolic(), &self.values)
    }
}

/// A sparse Cholesky factorization `P A Pᵀ = L Lᵀ` of a symmetric positive definite
/// matrix `A`, with a fill-reducing permutation `P`: factor once, solve many times.
///
/// Only the lower triangle of `A` is read; the upper one is assumed to mirror it
/// (which [`SymmetricBuilder`] guarantees).
#[derive(Clone, Debug)]
pub struct CholeskyFactor {
    /// Pattern of the factored matrix, to tell whether the symbolic analysis can be
    /// reused by [`refactor`](Self::refactor).
    pattern: LowerTriangle,
    symbolic: SymbolicLlt<usize>,
    numeric: Llt<usize, f64>,
}

impl CholeskyFactor {
    /// Factors `matrix`: ordering and symbolic analysis, then the numeric
    /// factorization. This is the "factor once" step of the implicit curvature
    /// smoothing `(M + t K) e' = M e` (§5.1).
    ///
    /// An [`Error::Argument`] if the matrix is not square, has a non-finite entry or
    /// is not positive definite (e.g. a zero lumped mass from a degenerate vertex).
    pub fn new(matrix: &SymmetricMatrix) -> Result<CholeskyFactor> {
        let pattern = LowerTriangle::new(matrix)?;
        let symbolic = analyze(&pattern)?;
        let numeric = factor_numeric(&symbolic, &pattern)?;
        Ok(CholeskyFactor {
            pattern,
            symbolic,
            numeric,
        })
    }

    /// Factors a new `matrix` in place of the current one. When its nonzero pattern
    /// is the same (the per-step surface smoothing `(M + t L) x' = M x` of §5.1, with
    /// `L` rebuilt on the smoothed surface), the ordering and symbolic analysis are
    /// reused and only the numeric factorization runs; otherwise everything is redone.
    ///
    /// Errors as [`new`](Self::new); on error the previous factorization is kept.
    pub fn refactor(&mut self, matrix: &SymmetricMatrix) -> Result<()> {
        let pattern = LowerTriangle::new(matrix)?;
        let symbolic = if pattern.same_pattern(&self.pattern) {
            self.symbolic.clone()
        } else {
            analyze(&pattern)?
        };
        self.numeric = factor_numeric(&symbolic, &pattern)?;
        self.symbolic = symbolic;
        self.pattern = pattern;
        Ok(())
    }

    /// The size `n` of the factored `n × n` matrix.
    pub fn size(&self) -> usize {
        self.pattern.n
    }

    /// Overwrites `x` (the right-hand side `b`) with the solution of `A x = b`.
    ///
    /// # Panics
    /// If `x.len()` is not [`size`](Self::size).
    pub fn solve_in_place(&self, x: &mut [f64]) {
        self.check_len(x.len());
        self.numeric
            .solve_in_place(faer::ColMut::from_slice_mut(x).as_mat_mut());
    }

    /// The solution of `A x = rhs`.
    ///
    /// # Panics
    /// If `rhs.len()` is not [`size`](Self::size).
    pub fn solve(&self, rhs: &[f64]) -> Vec<f64> {
        let mut x = rhs.to_vec();
        self.solve_in_place(&mut x);
        x
    }

    /// Solves `A X = B` for several right-hand sides at once (e.g. the x, y and z
    /// coordinates of the surface smoothing step), overwriting each column of `B`
    /// with the matching column of `X`. One pass over the factor serves all columns,
    /// which is faster than separate [`solve`](Self::solve) calls.
    ///
    /// # Panics
    /// If a column's length is not [`size`](Self::size).
    pub fn solve_columns(&self, columns: &mut [Vec<f64>]) {
        let n = self.size();
        for column in columns.iter() {
            self.check_len(column.len());
        }
        let mut rhs = Mat::from_fn(n, columns.len(), |i, j| columns[j][i]);
        self.solve_matrix(rhs.as_mut());
        for (j, column) in columns.iter_mut().enumerate() {
            column.copy_from_slice(rhs.col_as_slice(j));
        }
    }

    /// Solves `A X = B` in place for the columns of a faer matrix `B`, without the
    /// copies [`solve_columns`](Self::solve_columns) makes.
    ///
    /// # Panics
    /// If `rhs` does not have [`size`](Self::size) rows.
    pub fn solve_matrix(&self, rhs: MatMut<'_, f64>) {
        self.check_len(rhs.nrows());
        self.numeric.solve_in_place(rhs);
    }

    /// Panics with a clear message if a right-hand side has the wrong length.
    fn check_len(&self, len: usize) {
        assert_eq!(
            len,
            self.size(),
            "right-hand side of length {len} for a {n}×{n} system",
            n = self.size()
        );
    }
}

/// Fill-reducing ordering and symbolic factorization of the pattern.
fn analyze(pattern: &LowerTriangle) -> Result<SymbolicLlt<usize>> {
    SymbolicLlt::try_new(pattern.symbolic(), Side::Lower).map_err(|err| {
        Error::Argument(format!(
            "symbolic Cholesky analysis of a {n}×{n} matrix failed: {err}",
            n = pattern.n
        ))
    })
}

/// Numeric Cholesky factorization of `matrix`, whose pattern `symbolic` describes.
fn factor_numeric(
    symbolic: &SymbolicLlt<usize>,
    matrix: &LowerTriangle,
) -> Result<Llt<usize, f64>> {
    Llt::try_new_with_symbolic(symbolic.clone(), matrix.view(), Side::Lower).map_err(
        |err| match err {
            faer::sparse::linalg::LltError::Numeric(_) => Error::Argument(format!(
                "the {n}×{n} matrix is not positive definite (Cholesky factorization met a \
                 non-positive pivot)",
                n = matrix.n
            )),
            faer::sparse::linalg::LltError::Generic(err) => Error::Argument(format!(
                "Cholesky factorization of a {n}×{n} matrix failed: {err}",
                n = matrix.n
            )),
        },
    )
}

/// Rows per parallel task of the vector operations: large enough to amortise the
/// scheduling, small enough to balance two to dozens of cores on meshes of 10⁵
/// vertices and more.
const CHUNK: usize = 8192;

/// Systems with fewer unknowns than this are solved with the sparse Cholesky
/// factorization under [`Solver::Auto`]. Measured on the extremality smoothing
/// (both fields, 3 steps; `examples/bench_smoothing.rs`, 2 cores), the conjugate
/// gradient method wins on well-shaped meshes from about 30k vertices on
/// (jittered torus: 0.07 s against 0.09 s at 30k, 0.19 against 0.28 at 50k,
/// 1.6 against 2.3 at 400k), while on the 28k-vertex Stanford bunny, whose
/// factorization is cheaper, the two are even within the noise (0.08 to 0.17 s
/// against 0.09 to 0.12 s over several runs); 50k leaves a margin.
pub const ITERATIVE_MIN_SIZE: usize = 50_000;

/// The largest [`SymmetricMatrix::dominance_ratio`] for which [`Solver::Auto`]
/// takes the conjugate gradient method. The ratio bounds the condition number
/// of the Jacobi-preconditioned matrix by twice itself, so at 100 the iteration
/// needs at most ½ √200 ln(2 / 10⁻¹⁰) ≈ 170 iterations (in practice about 70 on a
/// jittered torus, whose ratio is about 66). Scanned meshes with slivers have
/// ratios of 10³ to 10⁸ (Stanford dragon at full resolution: 7 · 10⁷) and
/// converge slowly (about 100 iterations at 23k vertices, 190 at 100k, over
/// 1000 at 437k), where the factorization is two to five times faster.
pub const MAX_DOMINANCE_RATIO: f64 = 100.0;

/// How the sparse symmetric positive definite systems of the implicit smoothing
/// steps (§5.1) are solved.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Solver {
    /// [`Solver::Iterative`] from [`ITERATIVE_MIN_SIZE`] unknowns on when the
    /// matrix is diagonally dominant enough for fast convergence
    /// ([`MAX_DOMINANCE_RATIO`]), [`Solver::Direct`] otherwise.
    #[default]
    Auto,
    /// Sparse Cholesky factorization ([`CholeskyFactor`]).
    Direct,
    /// Jacobi-preconditioned conjugate gradient ([`conjugate_gradient`]),
    /// warm-started, falling back to [`Solver::Direct`] if it does not converge.
    Iterative,
}

crate::named::named!(Solver, "solver", {
    Auto => "auto",
    Direct => "direct",
    Iterative => "iterative",
});

impl Solver {
    /// [`Solver::Direct`] or [`Solver::Iterative`] for `matrix`.
    pub fn resolve(self, matrix: &SymmetricMatrix) -> Solver {
        match self {
            Solver::Auto
                if matrix.size() >= ITERATIVE_MIN_SIZE
                    && matrix.dominance_ratio() <= MAX_DOMINANCE_RATIO =>
            {
                Solver::Iterative
            }
            Solver::Auto => Solver::Direct,
            chosen => chosen,
        }
    }
}

/// When the conjugate gradient iteration stops.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CgSettings {
    /// Converged when ‖b − A x‖ ≤ `tolerance` · ‖b‖ (Euclidean norms).
    pub tolerance: f64,
    /// Give up (not converged) after this many iterations.
    pub max_iterations: usize,
}

impl CgSettings {
    /// Default relative residual: the smoothed extremalities then agree with the
    /// factorization's to about 10⁻¹⁰ of their magnitude, far below what moves a
    /// traced zero crossing visibly.
    pub const DEFAULT_TOLERANCE: f64 = 1e-10;
    /// Default iteration cap; the smoothing systems converge in well under a
    /// hundred iterations.
    pub const DEFAULT_MAX_ITERATIONS: usize = 1000;
}

impl Default for CgSettings {
    fn default() -> Self {
        CgSettings {
            tolerance: Self::DEFAULT_TOLERANCE,
            max_iterations: Self::DEFAULT_MAX_ITERATIONS,
        }
    }
}

/// The outcome of [`conjugate_gradient`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CgReport {
    /// Iterations run.
    pub iterations: usize,
    /// The true relative residual ‖b − A x‖ / ‖b‖ of the returned `x` (recomputed,
    /// not the recurrence's estimate).
    pub relative_residual: f64,
    /// Whether it is below [`CgSettings::tolerance`].
    pub converged: bool,
}

/// Solves `A x = b` for a symmetric positive definite `matrix` by the conjugate
/// gradient method with the Jacobi preconditioner diag(A)⁻¹ (Saad, *Iterative
/// Methods for Sparse Linear Systems*, Algorithm 9.1), starting from the given
/// `x` (a warm start: the previous smoothing step's solution) and overwriting it.
/// Matrix-vector products and vector updates run in parallel; sums are reduced
/// in a fixed order, so the result does not depend on the number of threads.
///
/// When the recurrence's residual meets the tolerance, the true residual is
/// recomputed; if rounding has let them drift apart the iteration restarts from
/// the true residual.
///
/// An [`Error::Argument`] if a diagonal entry is not positive and finite.
///
/// # Panics
/// If `b` or `x` does not have the matrix's size.
pub fn conjugate_gradient(
    matrix: &SymmetricMatrix,
    b: &[f64],
    x: &mut [f64],
    settings: CgSettings,
) -> Result<CgReport> {
    let inverse_diagonal = jacobi(matrix)?;
    Ok(Cg::new(matrix, &inverse_diagonal, b).run(x, settings))
}

/// The Jacobi preconditioner diag(A)⁻¹, checking the diagonal is positive.
fn jacobi(matrix: &SymmetricMatrix) -> Result<Vec<f64>> {
    let diagonal = matrix.diagonal();
    match diagonal.iter().position(|d| !(d.is_finite() && *d > 0.0)) {
        Some(i) => Err(Error::Argument(format!(
            "diagonal entry {i} of the matrix is {}; a positive definite matrix has \
             positive diagonal entries",
            diagonal[i]
        ))),
        None => Ok(diagonal.iter().map(|d| 1.0 / d).collect()),
    }
}

/// The state of one preconditioned conjugate gradient solve.
struct Cg<'a> {
    matrix: &'a SymmetricMatrix,
    inverse_diagonal: &'a [f64],
    b: &'a [f64],
    /// Residual b − A x.
    r: Vec<f64>,
    /// Search direction.
    p: Vec<f64>,
    /// A p, then scratch.
    q: Vec<f64>,
}

impl<'a> Cg<'a> {
    fn new(matrix: &'a SymmetricMatrix, inverse_diagonal: &'a [f64], b: &'a [f64]) -> Self {
        let n = matrix.size();
        assert_eq!(
            b.len(),
            n,
            "right-hand side of length {} for a {n}×{n} system",
            b.len()
        );
        Cg {
            matrix,
            inverse_diagonal,
            b,
            r: vec![0.0; n],
            p: vec![0.0; n],
            q: vec![0.0; n],
        }
    }

    /// Iterates from `x` until the tolerance or the cap.
    fn run(&mut self, x: &mut [f64], settings: CgSettings) -> CgReport {
        assert_eq!(x.len(), self.b.len(), "initial guess of the wrong length");
        let b_norm = dot(self.b, self.b).sqrt();
        if b_norm == 0.0 {
            x.fill(0.0);
            return CgReport {
                iterations: 0,
                relative_residual: 0.0,
                converged: true,
            };
        }
        let target = settings.tolerance * b_norm;
        let mut iterations = 0;
        loop {
            let residual = self.restart(x);
            if residual <= target || iterations >= settings.max_iterations {
                return CgReport {
                    iterations,
                    relative_residual: residual / b_norm,
                    converged: residual <= target,
                };
            }
            iterations += self.iterate(x, target, settings.max_iterations - iterations);
        }
    }

    /// Sets r = b − A x and p = D⁻¹ r; returns ‖r‖.
    fn restart(&mut self, x: &[f64]) -> f64 {
        self.matrix.mul_vec(x, &mut self.q);
        let sums: Vec<f64> = self
            .r
            .par_chunks_mut(CHUNK)
            .zip(self.p.par_chunks_mut(CHUNK))
            .zip(self.q.par_chunks(CHUNK).zip(self.b.par_chunks(CHUNK)))
            .zip(self.inverse_diagonal.par_chunks(CHUNK))
            .map(|(((r, p), (ax, b)), d)| {
                let mut rr = 0.0;
                for k in 0..r.len() {
                    r[k] = b[k] - ax[k];
                    p[k] = d[k] * r[k];
                    rr += r[k] * r[k];
                }
                rr
            })
            .collect();
        sums.iter().sum::<f64>().sqrt()
    }

    /// At most `budget` iterations from the state [`restart`](Self::restart) left,
    /// until the recurrence's residual is at most `target`; returns how many ran.
    fn iterate(&mut self, x: &mut [f64], target: f64, budget: usize) -> usize {
        let mut rz = dot(&self.r, &self.p);
        for iteration in 1..=budget {
            self.matrix.mul_vec(&self.p, &mut self.q);
            let alpha = rz / dot(&self.p, &self.q);
            let (next_rz, rr) = self.step(x, alpha);
            if rr.sqrt() <= target {
                return iteration;
            }
            let beta = next_rz / rz;
            rz = next_rz;
            self.update_direction(beta);
        }
        budget
    }

    /// x += α p, r −= α q, and z = D⁻¹ r kept in q; returns (rᵀz, rᵀr).
    fn step(&mut self, x: &mut [f64], alpha: f64) -> (f64, f64) {
        let d = self.inverse_diagonal;
        let sums: Vec<(f64, f64)> = x
            .par_chunks_mut(CHUNK)
            .zip(self.r.par_chunks_mut(CHUNK))
            .zip(self.p.par_chunks(CHUNK).zip(self.q.par_chunks_mut(CHUNK)))
            .zip(d.par_chunks(CHUNK))
            .map(|(((x, r), (p, q)), d)| {
                let (mut rz, mut rr) = (0.0, 0.0);
                for k in 0..x.len() {
                    x[k] += alpha * p[k];
                    r[k] -= alpha * q[k];
                    q[k] = d[k] * r[k];
                    rz += r[k] * q[k];
                    rr += r[k] * r[k];
                }
                (rz, rr)
            })
            .collect();
        sums.iter()
            .fold((0.0, 0.0), |(a, b), (c, d)| (a + c, b + d))
    }

    /// p = z + β p, with z = D⁻¹ r held in q.
    fn update_direction(&mut self, beta: f64) {
        self.p
            .par_chunks_mut(CHUNK)
            .zip(self.q.par_chunks(CHUNK))
            .for_each(|(p, z)| {
                for (p, z) in p.iter_mut().zip(z) {
                    *p = z + beta * *p;
                }
            });
    }
}

/// The dot product `aᵀb`, summed per chunk in parallel and the chunks in order.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let sums: Vec<f64> = a
        .par_chunks(CHUNK)
        .zip(b.par_chunks(CHUNK))
        .map(|(a, b)| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>())
        .collect();
    sums.iter().sum()
}

/// Solves a sequence of symmetric positive definite systems `A x = b` that share
/// a sparsity pattern (the implicit smoothing steps of §5.1) with the method
/// [`Solver`] picks: a [`CholeskyFactor`] refactored per matrix, or the
/// [`conjugate_gradient`] method warm-started from the caller's `x`, which falls
/// back to the factorization (built on first need) when it does not converge.
#[derive(Debug)]
pub struct SpdSolver {
    /// The method asked for.
    solver: Solver,
    /// The method for the current matrix: `solver` resolved, and switched to
    /// [`Solver::Direct`] once the iteration has failed on it.
    method: Solver,
    settings: CgSettings,
    matrix: Option<SymmetricMatrix>,
    inverse_diagonal: Vec<f64>,
    factor: Option<CholeskyFactor>,
    /// Whether `factor` belongs to `matrix`.
    factor_current: bool,
}

impl SpdSolver {
    /// A solver for the method `solver` ([`Solver::Auto`] is resolved for every
    /// matrix) and the iteration's stopping rule `settings`.
    pub fn new(solver: Solver, settings: CgSettings) -> SpdSolver {
        SpdSolver {
            solver,
            method: Solver::Direct,
            settings,
            matrix: None,
            inverse_diagonal: Vec::new(),
            factor: None,
            factor_current: false,
        }
    }

    /// The matrix of the next solves. The direct method factors it now (reusing
    /// the symbolic analysis of a previous matrix with the same pattern).
    ///
    /// An [`Error::Argument`] if it is not positive definite as far as the method
    /// can tell (a non-positive pivot or diagonal entry, a non-finite entry).
    pub fn set_matrix(&mut self, matrix: SymmetricMatrix) -> Result<()> {
        self.method = self.solver.resolve(&matrix);
        self.factor_current = false;
        if self.method == Solver::Iterative {
            self.inverse_diagonal = jacobi(&matrix)?;
        }
        self.matrix = Some(matrix);
        if self.method == Solver::Direct {
            self.factor()?;
        }
        Ok(())
    }

    /// Overwrites `x` with the solution of `A x = b`; the iterative method starts
    /// from the `x` given. If it does not converge within the cap, the system is
    /// solved by the factorization instead, and so are the next ones with the
    /// same matrix.
    ///
    /// # Panics
    /// Without a matrix ([`set_matrix`](Self::set_matrix)), or if `b` or `x` does
    /// not have its size.
    pub fn solve(&mut self, b: &[f64], x: &mut [f64]) -> Result<()> {
        let matrix = self.matrix.as_ref().expect("no matrix to solve with");
        if self.method == Solver::Iterative {
            let report = Cg::new(matrix, &self.inverse_diagonal, b).run(x, self.settings);
            if report.converged {
                return Ok(());
            }
            self.method = Solver::Direct;
        }
        x.copy_from_slice(b);
        self.factor()?.solve_in_place(x);
        Ok(())
    }

    /// The factorization of the current matrix, computed if not yet done.
    fn factor(&mut self) -> Result<&CholeskyFactor> {
        let matrix = self.matrix.as_ref().expect("no matrix to factor");
        if !self.factor_current {
            match &mut self.factor {
                Some(f) => f.refactor(matrix)?,
                None => self.factor = Some(CholeskyFactor::new(matrix)?),
            }
            self.factor_current = true;
        }
        Ok(self.factor.as_ref().expect("factored above"))
    }
}
