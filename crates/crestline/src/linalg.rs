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
//! Matrices are assembled with [`SymmetricBuilder`] into a [`sprs::CsMat`] and factored
//! by a supernodal sparse Cholesky factorization `P A Pᵀ = L Lᵀ` (faer, approximate
//! minimum degree ordering).

use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Mat, MatMut, Side};
use sprs::{CsMat, TriMat};

use crate::{Error, Result};

/// Assembles a symmetric `n × n` sparse matrix from entries that may repeat;
/// repeated entries are summed.
///
/// [`add`](Self::add) writes an off-diagonal value to both `(i, j)` and `(j, i)`, so
/// the built matrix is symmetric by construction.
#[derive(Debug)]
pub struct SymmetricBuilder {
    triplets: TriMat<f64>,
}

impl SymmetricBuilder {
    /// An empty `n × n` matrix.
    pub fn new(n: usize) -> SymmetricBuilder {
        SymmetricBuilder {
            triplets: TriMat::new((n, n)),
        }
    }

    /// An empty `n × n` matrix with room for `entries` stored entries (an
    /// off-diagonal [`add`](Self::add) stores two, [`add_edge`](Self::add_edge) four).
    pub fn with_capacity(n: usize, entries: usize) -> SymmetricBuilder {
        SymmetricBuilder {
            triplets: TriMat::with_capacity((n, n), entries),
        }
    }

    /// The matrix size `n`.
    pub fn size(&self) -> usize {
        self.triplets.rows()
    }

    /// Adds `value` to entry `(i, j)` and, when `i ≠ j`, to `(j, i)`.
    ///
    /// # Panics
    /// If `i` or `j` is not below [`size`](Self::size).
    pub fn add(&mut self, i: usize, j: usize, value: f64) {
        self.triplets.add_triplet(i, j, value);
        if i != j {
            self.triplets.add_triplet(j, i, value);
        }
    }

    /// Adds `value` to the diagonal entry `(i, i)`, e.g. a lumped vertex mass.
    ///
    /// # Panics
    /// If `i` is not below [`size`](Self::size).
    pub fn add_diagonal(&mut self, i: usize, value: f64) {
        self.triplets.add_triplet(i, i, value);
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

    /// The assembled matrix in compressed sparse column form, repeated entries summed.
    pub fn build(&self) -> CsMat<f64> {
        self.triplets.to_csc()
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
    /// Extracts the entries `(i, j)` with `i ≥ j` of `matrix`, checking that it is
    /// square, finite and has strictly increasing indices in every column.
    ///
    /// For a symmetric matrix the compressed row form holds the same arrays as the
    /// compressed column form, so either storage is accepted.
    fn from_sprs(matrix: &CsMat<f64>) -> Result<LowerTriangle> {
        let n = matrix.cols();
        if matrix.rows() != n {
            return Err(Error::Argument(format!(
                "a {}×{} matrix is not square",
                matrix.rows(),
                n
            )));
        }
        let mut lower = LowerTriangle {
            n,
            col_ptr: Vec::with_capacity(n + 1),
            row_idx: Vec::with_capacity(matrix.nnz() / 2 + n),
            values: Vec::with_capacity(matrix.nnz() / 2 + n),
        };
        lower.col_ptr.push(0);
        for (j, column) in matrix.outer_iterator().enumerate() {
            lower.push_column(j, column.iter())?;
        }
        Ok(lower)
    }

    /// Appends the lower part (rows `≥ j`) of column `j`.
    fn push_column<'a>(
        &mut self,
        j: usize,
        entries: impl Iterator<Item = (usize, &'a f64)>,
    ) -> Result<()> {
        let mut previous = None;
        for (i, &value) in entries {
            if previous.is_some_and(|p| p >= i) {
                return Err(Error::Argument(format!(
                    "column {j} of the matrix has unsorted or repeated row indices"
                )));
            }
            previous = Some(i);
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
    pub fn new(matrix: &CsMat<f64>) -> Result<CholeskyFactor> {
        let pattern = LowerTriangle::from_sprs(matrix)?;
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
    pub fn refactor(&mut self, matrix: &CsMat<f64>) -> Result<()> {
        let pattern = LowerTriangle::from_sprs(matrix)?;
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
