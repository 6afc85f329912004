//! The multigrid's smoother: hybrid Gauss–Seidel sweeps, forward before the
//! coarse correction and backward after it, over pieces of the unknowns swept in
//! parallel, with small groups of stiffly coupled unknowns relaxed together
//! ([`StiffBlocks`]).

use rayon::prelude::*;

use super::super::stiff_blocks::{Relax, StiffBlocks, MAX_BLOCK};
use super::super::{Lanes, SymmetricMatrix};

/// What the hybrid Gauss–Seidel sweep ([`Smoother::sweep`]) of one level reads:
/// its matrix in `f32` (see [`super::Level`]), the reciprocal divisors of
/// [`sweep_inverse`] and the stiffly coupled unknowns it relaxes together.
#[derive(Clone, Debug)]
pub(super) struct Smoother {
    pub(super) matrix: SymmetricMatrix<f32>,
    pub(super) inverse: Vec<f64>,
    pub(super) blocks: Option<StiffBlocks>,
    /// The unknowns that rows of another piece of the sweep read, increasing.
    pub(super) interface: Vec<u32>,
}

/// The pieces of rows that a Gauss–Seidel sweep relaxes in parallel: a fixed
/// number, so the result does not depend on the number of threads.
pub(super) const SWEEP_PIECES: usize = 8;

/// Rows per piece of a sweep over `n` rows.
pub(super) fn sweep_piece(n: usize) -> usize {
    n.div_ceil(SWEEP_PIECES).max(1)
}

/// The unknowns of `a` that a row in another piece of the hybrid sweep couples
/// to ([`sweep_piece`]), increasing: the only values the sweep must keep from
/// before it. Along the Morton curve the pieces are compact patches of the
/// surface, so this is their rims (1.5% of the dragon ×4's unknowns on the
/// fine level, 6.5% on the next), and copying it instead of the whole vector
/// before every sweep spares a pass over x (the ×4's smoothing 7.8 → 7.4 s).
pub(super) fn interface(a: &SymmetricMatrix) -> Vec<u32> {
    let piece = sweep_piece(a.size());
    (0..a.size())
        .into_par_iter()
        .filter(|&i| a.column(i).any(|(j, _)| j / piece != i / piece))
        .map(|i| i as u32)
        .collect()
}

/// The reciprocal divisors of the hybrid sweep ([`gauss_seidel`]; multiplying
/// keeps a division off the sweep's chain of dependent rows): 1 / d_i, d_i = a_ii
/// plus Σ |a_ij| over
/// the columns j in other pieces than row i's, which makes the sweep convergent
/// whatever the coupling between pieces (the ℓ1 smoother of Baker, Falgout,
/// Kolev and Yang, *Multigrid smoothers for ultraparallel computing*, SISC 33,
/// 2011, §5).
pub(super) fn sweep_inverse(a: &SymmetricMatrix) -> Vec<f64> {
    let piece = sweep_piece(a.size());
    (0..a.size())
        .into_par_iter()
        .map(|i| {
            let d: f64 = a
                .column(i)
                .map(|(j, v)| match j {
                    j if j == i => v,
                    j if j / piece != i / piece => v.abs(),
                    _ => 0.0,
                })
                .sum();
            1.0 / d
        })
        .collect()
}

impl Smoother {
    /// The smoother of `a`: its `f32` copy, divisors and stiff blocks.
    pub(super) fn new(a: &SymmetricMatrix) -> Smoother {
        Smoother {
            matrix: a.compact(),
            inverse: sweep_inverse(a),
            blocks: StiffBlocks::new(a, sweep_piece(a.size())),
            interface: interface(a),
        }
    }

    /// The size of its matrix.
    pub(super) fn size(&self) -> usize {
        self.matrix.size()
    }

    /// One hybrid Gauss–Seidel sweep on A x = b, forward or `backward`: Gauss–Seidel
    /// within each of [`SWEEP_PIECES`] pieces of rows, relaxed in parallel, and
    /// Jacobi between them (the other pieces' values from before the sweep), with
    /// the divisors of [`sweep_inverse`] and the blocks of stiffly coupled unknowns
    /// relaxed together (at their first member, with the inverse of their diagonal
    /// block); `before` (of x's length) receives the values of x at the
    /// [`interface`] as they were before the sweep. The backward sweep is the
    /// forward one's adjoint, so a V-cycle with one of each stays symmetric.
    ///
    /// The rows of both directions run in one loop, into which the common case,
    /// an unknown relaxed alone, is compiled: a closure per row, called from a
    /// loop per direction, was a call with its frame per row (the dragon ×4's fine
    /// level: 55–62 → 52–55 ms per two sweeps; the ×16's smoothing stage
    /// 42.9–47.1 → 40.2–41.5 s; the same lines to the bit).
    pub(super) fn sweep<V: Lanes>(&self, b: &[V], x: &mut [V], before: &mut [V], backward: bool) {
        // Only the interface is read from `before`: the rest may hold anything.
        for &j in &self.interface {
            before[j as usize] = x[j as usize];
        }
        let before = &*before;
        let rows = sweep_piece(b.len());
        x.par_chunks_mut(rows).enumerate().for_each(|(k, own)| {
            let mut piece = Piece {
                start: k * rows,
                own,
                before,
            };
            let (start, end) = (piece.start, piece.start + piece.own.len());
            for step in 0..end - start {
                let i = if backward {
                    end - 1 - step
                } else {
                    start + step
                };
                match self
                    .blocks
                    .as_ref()
                    .map_or(Relax::Single, |blocks| blocks.at(i))
                {
                    Relax::Single => {
                        let r = self.residual(b, &piece, i);
                        piece.own[i - start] += r * self.inverse[i];
                    }
                    Relax::Block { members, inverse } => {
                        self.relax_block(b, &mut piece, members, inverse);
                    }
                    Relax::Follower => {}
                }
            }
        });
    }

    /// Relaxes the unknowns `members` of `piece` together: the inverse of their
    /// diagonal block (row by row) times their residuals.
    #[inline]
    pub(super) fn relax_block<V: Lanes>(
        &self,
        b: &[V],
        piece: &mut Piece<'_, V>,
        members: &[u32],
        inverse: &[f64],
    ) {
        let mut r = [V::default(); MAX_BLOCK];
        for (r, &m) in r.iter_mut().zip(members) {
            *r = self.residual(b, piece, m as usize);
        }
        let k = members.len();
        for (row, &m) in inverse.chunks_exact(k).zip(members) {
            piece.own[m as usize - piece.start] += row
                .iter()
                .zip(&r)
                .fold(V::default(), |sum, (&a, &r)| sum + r * a);
        }
    }

    /// b_i − (A x)_i, with x_j from `piece` as relaxed so far. Column i is row i:
    /// the matrix is symmetric. The sum includes a_ii x_i.
    #[inline(always)]
    pub(super) fn residual<V: Lanes>(&self, b: &[V], piece: &Piece<'_, V>, i: usize) -> V {
        b[i] - self.matrix.row_sum(i, |j| piece.x(j))
    }
}

/// The rows of x one task of a sweep relaxes, from row `start` on, and the values
/// of the other pieces' rows from before the sweep.
pub(super) struct Piece<'a, V> {
    pub(super) start: usize,
    pub(super) own: &'a mut [V],
    pub(super) before: &'a [V],
}

impl<V: Lanes> Piece<'_, V> {
    /// x_j as the sweep has it: relaxed so far in this piece, from before the
    /// sweep in the others.
    #[inline(always)]
    pub(super) fn x(&self, j: usize) -> V {
        match j.checked_sub(self.start) {
            Some(k) if k < self.own.len() => self.own[k],
            _ => self.before[j],
        }
    }
}
