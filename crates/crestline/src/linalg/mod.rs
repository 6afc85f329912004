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
//! Cholesky factorization `P A Pᵀ = L Lᵀ` (faer; approximate minimum degree ordering of
//! matched pairs of unknowns, `linalg/ordering.rs`).
//!
//! The factorization's fill grows faster than the mesh (about 40 entries per
//! vertex on the Stanford dragon, 60 on the dragon refined ×4), so on large
//! meshes the conjugate gradient method preconditioned by smoothed-aggregation
//! multigrid ([`Multigrid`]), warm-started from the previous step, takes its
//! place: its memory is linear in the mesh. [`SpdSolver`] chooses between the two
//! ([`Solver`]) and falls back to the factorization when the iteration does not
//! converge.

mod cg;
mod cholesky;
mod lanes;
mod matrix;
mod multigrid;
mod ordering;
mod stiff_blocks;

#[cfg(test)]
mod tests;

#[cfg(test)]
use cg::conjugate_gradient;
use cg::Cg;
pub use cg::CgSettings;
pub use cholesky::{CholeskyAnalysis, CholeskyFactor};
pub use lanes::{Lanes, Pair};
#[cfg(test)]
use matrix::SymmetricBuilder;
pub use matrix::{Entry, SymmetricMatrix};
pub use multigrid::{CycleBuffers, Multigrid};

use crate::progress::{checkpoint, Observer};
use crate::Result;

/// Rows per parallel task of the vector operations: large enough to amortise the
/// scheduling, small enough to balance two to dozens of cores on meshes of 10⁵
/// vertices and more.
const CHUNK: usize = 8192;

/// Systems with fewer unknowns than this are solved with the sparse Cholesky
/// factorization under [`Solver::Auto`], larger ones by the multigrid-preconditioned
/// conjugate gradient method. On two cores the factorization is still the faster at the
/// dragon ×4 (1.7M vertices; ridges' smoothing stage, both fields, 3 steps): 3.5 s plus
/// 2.5 s of its ordering that the curvature does not hide, against 7.6 s iterated
/// (whole `ridges` 8.6 s against 10.3 s): the nine to eleven V-cycles of a solve, bound
/// by the latency of their sweeps' dependent rows more than by the bytes they read
/// (`linalg/lanes.rs`), take longer than a solve with the factor. But the factor's fill
/// grows faster than the mesh: on the dragon ×16 (7M vertices) the factored ridges need
/// 10.4 GB and 103 s (smoothing 74 s, ordering 19 s), the iterated ones 5.1 GB and
/// 47–50 s (smoothing 35–38 s), and the dragon ×64 would not fit in 24 GiB factored.
pub const ITERATIVE_MIN_SIZE: usize = 2_000_000;

/// How the sparse symmetric positive definite systems of the implicit smoothing
/// steps (§5.1) are solved.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Solver {
    /// [`Solver::Direct`] below 2,000,000 unknowns, [`Solver::Iterative`] from
    /// there on, where the factorization's memory grows too large (measured, see
    /// `ITERATIVE_MIN_SIZE` in `linalg/mod.rs`).
    #[default]
    Auto,
    /// Sparse Cholesky factorization (faer; approximate minimum degree ordering of
    /// matched pairs of unknowns).
    Direct,
    /// The conjugate gradient method preconditioned by a smoothed-aggregation
    /// multigrid V-cycle (`linalg/multigrid.rs`), warm-started, falling back to
    /// [`Solver::Direct`] if it does not converge.
    Iterative,
}

crate::named::named!(Solver, "solver", {
    Auto => "auto",
    Direct => "direct",
    Iterative => "iterative",
});

impl Solver {
    /// [`Solver::Direct`] or [`Solver::Iterative`] for systems of `unknowns`.
    pub fn resolve(self, unknowns: usize) -> Solver {
        match self {
            Solver::Auto if unknowns >= ITERATIVE_MIN_SIZE => Solver::Iterative,
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
    multigrid: Option<Multigrid>,
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
            multigrid: None,
            factor: None,
            analysis: None,
            factor_current: false,
        }
    }

    /// The method asked for.
    pub fn solver(&self) -> Solver {
        self.solver
    }

    /// Prepares for matrices with the pattern of `matrix` (and values like its
    /// own, which [`Solver::Auto`] looks at): when they will be factored, the
    /// ordering and symbolic analysis are made now, once for every copy of this
    /// solver (e.g. one per extremality field, solved in parallel).
    ///
    /// An [`Error::Argument`](crate::Error::Argument) if the matrix has a non-finite entry.
    pub fn analyze(&mut self, matrix: &SymmetricMatrix) -> Result<()> {
        if self.solver.resolve(matrix.size()) != Solver::Iterative && self.analysis.is_none() {
            self.analysis = Some(CholeskyAnalysis::new(matrix)?);
        }
        Ok(())
    }

    /// Prepares for matrices with the pattern `analysis` was made for (by another
    /// solver, e.g. of the surface's smoothing on the same mesh), so that the
    /// first factorization does not order and analyse it again. A matrix of
    /// another pattern is analysed anew.
    pub fn reuse_analysis(&mut self, analysis: CholeskyAnalysis) {
        self.analysis = Some(analysis);
    }

    /// The ordering and symbolic analysis of its last factorization, or the one
    /// made or given beforehand, if any.
    pub fn analysis(&self) -> Option<&CholeskyAnalysis> {
        self.factor
            .as_ref()
            .map(CholeskyFactor::analysis)
            .or(self.analysis.as_ref())
    }

    /// The matrix of the next solves. The direct method factors it now (reusing
    /// the symbolic analysis of a previous matrix with the same pattern).
    ///
    /// An [`Error::Argument`](crate::Error::Argument) if it is not positive definite as far as the method
    /// can tell (a non-positive pivot or diagonal entry, a non-finite entry).
    pub fn set_matrix(&mut self, matrix: SymmetricMatrix) -> Result<()> {
        self.method = self.solver.resolve(matrix.size());
        self.factor_current = false;
        if self.method == Solver::Iterative {
            self.multigrid = Some(Multigrid::new(&matrix)?);
        }
        self.matrix = Some(matrix);
        if self.method == Solver::Direct {
            self.factor()?;
        }
        Ok(())
    }

    /// Overwrites `x` with the solution of `A x = b`, for one vector or several
    /// interleaved ([`Lanes`]: the iteration then serves all of them with each
    /// pass over the matrix and its hierarchy); the iterative method starts from
    /// the `x` given. If it does not converge within the cap, the system is
    /// solved by the factorization instead, and so are the next ones with the
    /// same matrix. Asks `observer` whether to go on before the solve and, when
    /// iterating, before every iteration ([`Error::Cancelled`](crate::Error::Cancelled)
    /// if not).
    ///
    /// # Panics
    /// Without a matrix ([`set_matrix`](Self::set_matrix)), or if `b` or `x` does
    /// not have its size.
    pub fn solve<V: Lanes>(
        &mut self,
        b: &[V],
        x: &mut [V],
        observer: &mut dyn Observer,
    ) -> Result<()> {
        checkpoint(observer)?;
        let matrix = self.matrix.as_ref().expect("no matrix to solve with");
        if self.method == Solver::Iterative {
            let multigrid = self.multigrid.as_ref().expect("made with the matrix");
            let report = Cg::new(matrix, multigrid, b).run(x, self.settings, observer)?;
            if report.converged {
                return Ok(());
            }
            self.method = Solver::Direct;
        }
        self.factor()?.solve_lanes(b, x);
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
