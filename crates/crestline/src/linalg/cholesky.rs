//! Sparse Cholesky factorization (faer, supernodal, approximate minimum degree on
//! matched pairs: [`super::ordering`]).

use std::sync::Arc;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, Par, Side};
use rayon::prelude::*;

use super::lanes::{lane, set_lane};
use super::ordering::paired_amd;
use super::{Lanes, SymmetricMatrix};
use crate::{Error, Result};

/// The lower triangle of a square sparse matrix in compressed column form, the
/// layout the factorization reads.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct LowerTriangle {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    values: Vec<f64>,
}

impl LowerTriangle {
    /// Extracts the entries `(i, j)` with `i ≥ j` of `matrix`, checking that they
    /// are finite.
    pub(super) fn new(matrix: &SymmetricMatrix) -> Result<LowerTriangle> {
        let n = matrix.size();
        let stored = matrix.csc().1.len();
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
    pub(super) fn symbolic(&self) -> SymbolicSparseColMatRef<'_, usize> {
        SymbolicSparseColMatRef::new_checked(self.n, self.n, &self.col_ptr, None, &self.row_idx)
    }

    /// A faer view of pattern and values.
    fn view(&self) -> SparseColMatRef<'_, usize, f64> {
        SparseColMatRef::new(self.symbolic(), &self.values)
    }
}

/// The fill-reducing ordering ([`paired_amd`]) and symbolic analysis of
/// a sparsity pattern: the costly part of a sparse Cholesky factorization, shared
/// by the factorizations of every matrix with that pattern (the systems of both
/// extremality fields and of every surface smoothing step, §5.1).
#[derive(Clone, Debug)]
pub struct CholeskyAnalysis {
    /// The analysed matrix's lower triangle, to tell whether another matrix has
    /// the same pattern.
    pattern: LowerTriangle,
    symbolic: Arc<SymbolicCholesky<usize>>,
}

impl CholeskyAnalysis {
    /// Orders and analyses the pattern of `matrix`.
    ///
    /// An [`Error::Argument`] if the matrix has a non-finite entry.
    pub fn new(matrix: &SymmetricMatrix) -> Result<CholeskyAnalysis> {
        let pattern = LowerTriangle::new(matrix)?;
        let symbolic = analyze(&pattern, matrix)?;
        Ok(CholeskyAnalysis { pattern, symbolic })
    }

    /// Factors `matrix`, reusing this analysis when its nonzero pattern is the
    /// same and analysing it anew otherwise.
    ///
    /// An [`Error::Argument`] if the matrix has a non-finite entry or is not
    /// positive definite.
    pub fn factor(&self, matrix: &SymmetricMatrix) -> Result<CholeskyFactor> {
        let pattern = LowerTriangle::new(matrix)?;
        let symbolic = if pattern.same_pattern(&self.pattern) {
            self.symbolic.clone()
        } else {
            analyze(&pattern, matrix)?
        };
        let numeric = factor_numeric(&symbolic, &pattern)?;
        Ok(CholeskyFactor {
            analysis: CholeskyAnalysis { pattern, symbolic },
            numeric,
        })
    }
}

/// A sparse Cholesky factorization `P A Pᵀ = L Lᵀ` of a symmetric positive definite
/// matrix `A`, with a fill-reducing permutation `P`: factor once, solve many times.
///
/// Only the lower triangle of `A` is read; the upper one is assumed to mirror it
/// (which [`SymmetricBuilder`](super::SymmetricBuilder) guarantees).
#[derive(Clone, Debug)]
pub struct CholeskyFactor {
    /// Ordering and symbolic analysis, reused by [`refactor`](Self::refactor).
    analysis: CholeskyAnalysis,
    /// The values of L, laid out as the analysis says.
    numeric: Vec<f64>,
}

impl CholeskyFactor {
    /// Factors `matrix`: ordering and symbolic analysis, then the numeric
    /// factorization. This is the "factor once" step of the implicit curvature
    /// smoothing `(M + t K) e' = M e` (§5.1).
    ///
    /// An [`Error::Argument`] if the matrix is not square, has a non-finite entry or
    /// is not positive definite (e.g. a zero lumped mass from a degenerate vertex).
    pub fn new(matrix: &SymmetricMatrix) -> Result<CholeskyFactor> {
        CholeskyAnalysis::new(matrix)?.factor(matrix)
    }

    /// The ordering and symbolic analysis this factorization was made with.
    pub fn analysis(&self) -> &CholeskyAnalysis {
        &self.analysis
    }

    /// The size `n` of the factored `n × n` matrix.
    pub fn size(&self) -> usize {
        self.analysis.pattern.n
    }

    /// Overwrites `x` (the right-hand side `b`) with the solution of `A x = b`.
    ///
    /// # Panics
    /// If `x.len()` is not [`size`](Self::size).
    pub fn solve_in_place(&self, x: &mut [f64]) {
        self.check_len(x.len());
        let symbolic = &self.analysis.symbolic;
        let mut scratch = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        LltRef::new(symbolic, &self.numeric).solve_in_place_with_conj(
            Conj::No,
            faer::ColMut::from_slice_mut(x).as_mat_mut(),
            Par::Seq,
            MemStack::new(&mut scratch),
        );
    }

    /// `x` = A⁻¹ `b` for every vector of the interleaved `b` ([`Lanes`]), the
    /// vectors solved in parallel.
    ///
    /// # Panics
    /// If `b` or `x` does not have length [`size`](Self::size).
    pub fn solve_lanes<V: Lanes>(&self, b: &[V], x: &mut [V]) {
        assert_eq!(
            b.len(),
            x.len(),
            "right-hand side and solution differ in length"
        );
        let columns: Vec<Vec<f64>> = (0..V::COUNT)
            .into_par_iter()
            .map(|k| {
                let mut column = lane(b, k);
                self.solve_in_place(&mut column);
                column
            })
            .collect();
        for (k, column) in columns.iter().enumerate() {
            set_lane(x, k, column);
        }
    }

    /// The solution of `A x = rhs`.
    ///
    /// # Panics
    /// If `rhs.len()` is not [`size`](Self::size).
    #[cfg(test)]
    pub fn solve(&self, rhs: &[f64]) -> Vec<f64> {
        let mut x = rhs.to_vec();
        self.solve_in_place(&mut x);
        x
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

/// Fill-reducing ordering ([`paired_amd`] of `matrix`) and symbolic
/// factorization of `pattern`, its lower triangle.
fn analyze(
    pattern: &LowerTriangle,
    matrix: &SymmetricMatrix,
) -> Result<Arc<SymbolicCholesky<usize>>> {
    let n = pattern.n;
    let (order, rank) = paired_amd(matrix)?;
    factorize_symbolic_cholesky(
        pattern.symbolic(),
        Side::Lower,
        SymmetricOrdering::Custom(PermRef::new_checked(&order, &rank, n)),
        Default::default(),
    )
    .map(Arc::new)
    .map_err(|err| {
        Error::Argument(format!(
            "symbolic Cholesky analysis of a {n}×{n} matrix failed: {err}"
        ))
    })
}

/// Numeric Cholesky factorization of `matrix`, whose pattern `symbolic` describes:
/// the values of L. Sequential: on two cores faer's parallel factorization
/// took 0.60 s on the Stanford dragon's extremality system and 3.4 s on the
/// dragon ×4's (median of 4), the sequential one 0.37 and 2.4 s.
fn factor_numeric(symbolic: &SymbolicCholesky<usize>, matrix: &LowerTriangle) -> Result<Vec<f64>> {
    let failed = |err: String| {
        Error::Argument(format!(
            "Cholesky factorization of a {n}×{n} matrix failed: {err}",
            n = matrix.n
        ))
    };
    let mut values = Vec::new();
    values
        .try_reserve_exact(symbolic.len_val())
        .map_err(|err| failed(err.to_string()))?;
    values.resize(symbolic.len_val(), 0.0);
    let scratch = symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default());
    let mut scratch = MemBuffer::try_new(scratch).map_err(|err| failed(format!("{err:?}")))?;
    symbolic
        .factorize_numeric_llt(
            &mut values,
            matrix.view(),
            Side::Lower,
            Default::default(),
            Par::Seq,
            MemStack::new(&mut scratch),
            Default::default(),
        )
        .map_err(|_| {
            Error::Argument(format!(
                "the {n}×{n} matrix is not positive definite (Cholesky factorization met a \
                 non-positive pivot)",
                n = matrix.n
            ))
        })?;
    Ok(values)
}
