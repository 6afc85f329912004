//! Sparse symmetric positive definite systems for the implicit smoothing steps of
//! the ridge pipeline (Hildebrandt et al. 2005, §5.1):
//!
//! - extremality smoothing `(M + t K) e' = M e`, one matrix for many steps and
//!   many right-hand sides: factor once with [`CholeskyFactor::new`], then solve
//!   repeatedly;
//! - surface smoothing `(M + t L) x' = M x`, where the matrix changes every step but
//!   keeps its sparsity pattern: [`CholeskyAnalysis`] keeps the fill-reducing
//!   ordering and symbolic analysis for the next factorization.
//!
//! Matrices are [`SymmetricMatrix`] values (compressed columns) factored by a supernodal sparse
//! Cholesky factorization `P A Pᵀ = L Lᵀ` (faer, approximate minimum degree ordering).
//!
//! Both matrices are M plus a small multiple of a Laplacian, diagonally dominant
//! and well conditioned, so on large meshes the Jacobi-preconditioned conjugate
//! gradient method, warm-started from the previous step,
//! needs few iterations and beats the factorization; [`SpdSolver`] chooses between
//! the two ([`Solver`]) and falls back to the factorization when the iteration
//! does not converge.

mod cg;
mod cholesky;
mod matrix;

#[cfg(test)]
mod tests;

#[cfg(test)]
use cg::conjugate_gradient;
pub use cg::CgSettings;
use cg::{jacobi, Cg};
pub use cholesky::{CholeskyAnalysis, CholeskyFactor};
#[cfg(test)]
use matrix::SymmetricBuilder;
pub use matrix::SymmetricMatrix;

use crate::Result;

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
    /// [`Solver::Iterative`] from 50,000 unknowns on when the matrix is diagonally
    /// dominant enough for fast convergence (a dominance ratio of at most 100; both
    /// measured, see `linalg/mod.rs`), [`Solver::Direct`] otherwise.
    #[default]
    Auto,
    /// Sparse Cholesky factorization (faer, approximate minimum degree ordering).
    Direct,
    /// Jacobi-preconditioned conjugate gradient,
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

/// Solves a sequence of symmetric positive definite systems `A x = b` that share
/// a sparsity pattern (the implicit smoothing steps of §5.1) with the method
/// [`Solver`] picks: a [`CholeskyFactor`] refactored per matrix, or the
/// conjugate gradient method warm-started from the caller's `x`, which falls
/// back to the factorization (built on first need) when it does not converge.
#[derive(Clone, Debug)]
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
    /// An analysis made before the first factorization ([`analyze`](Self::analyze)).
    analysis: Option<CholeskyAnalysis>,
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
            analysis: None,
            factor_current: false,
        }
    }

    /// Prepares for matrices with the pattern of `matrix` (and values like its
    /// own, which [`Solver::Auto`] looks at): when they will be factored, the
    /// ordering and symbolic analysis are made now, once for every copy of this
    /// solver (e.g. one per extremality field, solved in parallel).
    ///
    /// An [`Error::Argument`](crate::Error::Argument) if the matrix has a non-finite entry.
    pub fn analyze(&mut self, matrix: &SymmetricMatrix) -> Result<()> {
        if self.solver.resolve(matrix) != Solver::Iterative && self.analysis.is_none() {
            self.analysis = Some(CholeskyAnalysis::new(matrix)?);
        }
        Ok(())
    }

    /// The matrix of the next solves. The direct method factors it now (reusing
    /// the symbolic analysis of a previous matrix with the same pattern).
    ///
    /// An [`Error::Argument`](crate::Error::Argument) if it is not positive definite as far as the method
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

    /// The factorization of the current matrix, computed if not yet done (reusing
    /// the analysis of the previous factorization or of [`analyze`](Self::analyze)).
    fn factor(&mut self) -> Result<&CholeskyFactor> {
        let matrix = self.matrix.as_ref().expect("no matrix to factor");
        if !self.factor_current {
            let analysis = self.factor.as_ref().map(CholeskyFactor::analysis);
            let factor = match analysis.or(self.analysis.as_ref()) {
                Some(analysis) => analysis.factor(matrix)?,
                None => CholeskyFactor::new(matrix)?,
            };
            self.factor = Some(factor);
            self.factor_current = true;
        }
        Ok(self.factor.as_ref().expect("factored above"))
    }
}
