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

use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Mat, MatMut, Side};

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
