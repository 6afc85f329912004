//! A smoothed-aggregation algebraic multigrid preconditioner (Vaněk, Mandel and
//! Brezina, *Algebraic multigrid by smoothed aggregation for second and fourth
//! order elliptic problems*, Computing 56, 1996) for the smoothing systems
//! M + t K of §5.1.
//!
//! A scanned mesh's slivers join neighbouring vertices with cotan weights up to
//! 10⁴ times the typical one (on the Stanford dragon 0.5% of the angles have a
//! cotangent above 100), so the Jacobi-preconditioned conjugate gradient method
//! needs over a thousand iterations there, and an incomplete Cholesky
//! factorization still 150. Aggregation puts strongly coupled vertices into one
//! coarse unknown, so those couplings are resolved on a coarser level: the
//! dragon's extremality systems take about 18 iterations to a relative residual
//! of 10⁻⁸.
//! Every level's cost and memory are linear in its size, and the levels shrink
//! about fourfold each.
//!
//! The finest level's prolongator is smoothed, the coarser ones are plain
//! aggregations; one V-cycle is [`SWEEPS`] forward Gauss–Seidel sweeps, the
//! coarse correction and as many backward sweeps, a symmetric positive definite
//! preconditioner; the coarsest level is factored. Small groups of stiffly
//! coupled unknowns are relaxed together ([`StiffBlocks`]), and the operators are
//! stored in `f32` ([`Level`]).
//!
//! The matrices are not M-matrices: the sign-aware Laplacian (§5.1) has
//! off-diagonal entries −t w σ_pq of either sign. Its near-kernel is not the
//! constant vector but one whose signs follow σ, so each aggregate's tentative
//! basis vector takes its signs from the off-diagonal entries it was grown along.

mod aggregation;
mod smoother;
mod sparse;

use rayon::prelude::*;

use super::{CholeskyFactor, Lanes, SymmetricMatrix, CHUNK};
use crate::{Error, Result};
use aggregation::coarsen;
use smoother::Smoother;
use sparse::Rows;

/// Coarsening stops when a level keeps more than this share of its unknowns.
const MIN_REDUCTION: f64 = 0.8;

/// Gauss–Seidel sweeps before and after the coarse correction on every level.
/// Two halve the iterations one needs (the Stanford dragon's six extremality
/// solves: 106 iterations against 167, smoothing 5.6 s against 6.4 s); three cut
/// them to 87 but cost more than they save (6.9 s).
const SWEEPS: usize = 2;

/// Levels with at most this many unknowns are solved by a sparse Cholesky
/// factorization.
const COARSEST_SIZE: usize = 4000;

/// One level below a finer matrix: the prolongator from it and the coarse matrix,
/// stored in `f32` ([`SymmetricMatrix::compact`]): the V-cycle is a
/// preconditioner, and rounding its operators to single precision (relative
/// changes of 6 · 10⁻⁸, symmetric as the matrices) leaves its effect on the
/// conjugate gradient method as it was while a third fewer bytes stream through
/// every sweep, residual, restriction and prolongation.
#[derive(Clone, Debug)]
struct Level {
    /// P, fine rows × coarse columns.
    prolongator: Rows<f32>,
    /// Pᵀ, stored so that the restriction gathers a row per coarse unknown in
    /// parallel rather than scattering the fine ones into per-thread copies.
    restrictor: Rows<f32>,
    /// Pᵀ A P and its smoother.
    coarse: Smoother,
}

/// The vectors one V-cycle works in, per level ([`Multigrid::buffers`]): made
/// once per solve rather than allocated (and their pages zeroed by the system)
/// at every cycle.
pub struct CycleBuffers<V> {
    levels: Vec<LevelBuffers<V>>,
}

/// A level's vectors: the sweeps' copy of x and the residual between them (fine
/// size), and the coarse right-hand side and solution.
struct LevelBuffers<V> {
    scratch: Vec<V>,
    coarse_b: Vec<V>,
    coarse_x: Vec<V>,
}

/// The multigrid hierarchy of a matrix.
#[derive(Clone, Debug)]
pub struct Multigrid {
    /// The fine matrix's smoother.
    fine: Smoother,
    levels: Vec<Level>,
    /// The factorization of the coarsest matrix, if there is a level below the
    /// fine one.
    coarsest: Option<CholeskyFactor>,
}

impl Multigrid {
    /// The hierarchy of `matrix` (symmetric positive definite, with a positive
    /// diagonal).
    pub fn new(matrix: &SymmetricMatrix) -> Result<Multigrid> {
        positive_diagonal(matrix)?;
        let mut levels: Vec<Level> = Vec::new();
        // The coarsest level so far, in f64: the next one is computed from it.
        let mut coarsest: Option<SymmetricMatrix> = None;
        loop {
            let current = coarsest.as_ref().unwrap_or(matrix);
            let n = current.size();
            if n <= COARSEST_SIZE {
                break;
            }
            let Some((prolongator, restrictor, coarse)) = coarsen(current, levels.len()) else {
                break;
            };
            if coarse.size() as f64 > MIN_REDUCTION * n as f64 {
                break;
            }
            levels.push(Level {
                restrictor: restrictor.compact(),
                prolongator: prolongator.compact(),
                coarse: Smoother::new(&coarse),
            });
            coarsest = Some(coarse);
        }
        Ok(Multigrid {
            fine: Smoother::new(matrix),
            levels,
            coarsest: coarsest.as_ref().map(CholeskyFactor::new).transpose()?,
        })
    }

    /// The number of levels, the fine one included.
    #[cfg(test)]
    pub fn depth(&self) -> usize {
        self.levels.len() + 1
    }

    /// z ≈ A⁻¹ r by one V-cycle with [`SWEEPS`] forward Gauss–Seidel sweeps before
    /// and as many backward ones after the coarse correction, so the
    /// preconditioner is symmetric positive definite (as the conjugate gradient
    /// method needs).
    ///
    /// `buffers` are [`buffers`](Self::buffers) of this hierarchy.
    pub fn apply<V: Lanes>(&self, r: &[V], z: &mut [V], buffers: &mut CycleBuffers<V>) {
        self.cycle(0, &self.fine, r, z, &mut buffers.levels);
    }

    /// The vectors [`apply`](Self::apply) works in, for vectors of `V`.
    pub fn buffers<V: Lanes>(&self) -> CycleBuffers<V> {
        let mut fine_size = self.fine.size();
        let levels = self
            .levels
            .iter()
            .map(|level| {
                let coarse_size = level.coarse.size();
                let buffers = LevelBuffers {
                    scratch: vec![V::default(); fine_size],
                    coarse_b: vec![V::default(); coarse_size],
                    coarse_x: vec![V::default(); coarse_size],
                };
                fine_size = coarse_size;
                buffers
            })
            .collect();
        CycleBuffers { levels }
    }

    /// One V-cycle from level `l`, whose smoother is `smoother`, with the buffers
    /// of level `l` and below.
    fn cycle<V: Lanes>(
        &self,
        l: usize,
        smoother: &Smoother,
        b: &[V],
        x: &mut [V],
        buffers: &mut [LevelBuffers<V>],
    ) {
        x.fill(V::default());
        let (Some(level), [own, below @ ..]) = (self.levels.get(l), buffers) else {
            // Below the last level lies the coarsest, factored; without levels the
            // fine matrix is only smoothed.
            match &self.coarsest {
                Some(factor) if l > 0 => factor.solve_lanes(b, x),
                _ => {
                    let mut before = vec![V::default(); b.len()];
                    smoother.sweep(b, x, &mut before, false);
                    smoother.sweep(b, x, &mut before, true);
                }
            }
            return;
        };
        let scratch = &mut own.scratch;
        for _ in 0..SWEEPS {
            smoother.sweep(b, x, scratch, false);
        }
        smoother.matrix.residual(x, b, scratch);
        own.coarse_b.fill(V::default());
        add_product(&level.restrictor, scratch, &mut own.coarse_b);
        self.cycle(
            l + 1,
            &level.coarse,
            &own.coarse_b,
            &mut own.coarse_x,
            below,
        );
        add_product(&level.prolongator, &own.coarse_x, x);
        for _ in 0..SWEEPS {
            smoother.sweep(b, x, scratch, true);
        }
    }
}

/// The diagonal of `matrix`, checked positive and finite.
fn positive_diagonal(matrix: &SymmetricMatrix) -> Result<()> {
    let diagonal = matrix.diagonal();
    match diagonal.iter().position(|d| !(d.is_finite() && *d > 0.0)) {
        Some(i) => Err(Error::Argument(format!(
            "diagonal entry {i} of the matrix is {}; a positive definite matrix has \
             positive diagonal entries",
            diagonal[i]
        ))),
        None => Ok(()),
    }
}

/// y += R x, in parallel over rows.
fn add_product<V: Lanes>(rows: &Rows<f32>, x: &[V], y: &mut [V]) {
    y.par_chunks_mut(CHUNK).enumerate().for_each(|(c, out)| {
        for (k, y) in out.iter_mut().enumerate() {
            *y += rows
                .row(c * CHUNK + k)
                .fold(V::default(), |sum, (j, v)| sum + x[j] * v);
        }
    });
}

#[cfg(test)]
mod tests {
    use nalgebra::DMatrix;

    use super::aggregation::coarsen;
    use super::sparse::{from_upper_rows, Rows};
    use crate::linalg::tests::{dense, random_sign, smoothing_system, stiff_edges};

    fn dense_rows(rows: &Rows, columns: usize) -> DMatrix<f64> {
        let mut m = DMatrix::zeros(rows.len(), columns);
        for i in 0..rows.len() {
            for (j, v) in rows.row(i) {
                m[(i, j)] += v;
            }
        }
        m
    }

    #[test]
    fn the_coarse_matrix_is_the_galerkin_product_of_the_prolongator() {
        // M + t K of a jittered sphere, a third of the edges' signs flipped and one
        // in seven 100 times stiffer: the prolongator is smoothed on the fine level
        // and plain below, and both kinds of sign appear in it.
        let (a, _) = smoothing_system(400, 2, stiff_edges(7, 100.0, random_sign), |_| 0.0);
        for depth in [0, 1] {
            let (p, pt, coarse) = coarsen(&a, depth).expect("strong couplings");
            let n = coarse.size();
            assert!(n > 10 && n < a.size() / 2, "{n} aggregates");
            let p = dense_rows(&p, n);
            assert_eq!(dense_rows(&pt, a.size()), p.transpose());
            let expected = p.transpose() * dense(&a) * &p;
            let error = (dense(&coarse) - &expected).abs().max();
            assert!(error <= 1e-12 * expected.abs().max(), "{error}");
            assert_eq!(
                dense(&coarse),
                dense(&coarse).transpose(),
                "exactly symmetric"
            );
        }
    }

    /// Upper rows of 40 unknowns (mirrored in parts of five columns) with
    /// scattered entries, long-range ones, a row with none and one with only its
    /// diagonal: every entry lands in both triangles, once.
    #[test]
    fn an_upper_triangle_is_mirrored_into_the_whole_matrix() {
        let n = 40;
        let mut expected = DMatrix::zeros(n, n);
        let (mut ptr, mut cols, mut values) = (vec![0], Vec::new(), Vec::new());
        for r in 0..n {
            for c in r..n {
                let kept = match r {
                    5 => false,
                    6 => c == r,
                    _ => c == r || (r * 7 + c * 3) % 5 == 0 || c == n - 1,
                };
                if kept {
                    let value = (100 * r + c) as f64;
                    cols.push(c as u32);
                    values.push(value);
                    expected[(r, c)] = value;
                    expected[(c, r)] = value;
                }
            }
            ptr.push(cols.len());
        }
        let matrix = from_upper_rows(n, &ptr, &cols, &values);
        assert_eq!(dense(&matrix), expected);
    }
}
