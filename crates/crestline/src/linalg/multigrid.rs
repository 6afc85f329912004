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

use std::ops::Range;

use rayon::prelude::*;

use super::stiff_blocks::{Relax, StiffBlocks, MAX_BLOCK};
use super::{CholeskyFactor, Entry, Lanes, SymmetricMatrix, CHUNK};
use crate::slices::split_into;
use crate::{Error, Result};

/// Strength threshold θ: a_ij is a strong coupling when a_ij² ≥ θ² a_ii a_jj
/// (Vaněk et al. §4 use θ = 0.08 · ½^level; a fixed θ keeps coarse levels sparse).
const STRENGTH: f64 = 0.08;

/// Levels with at most this many unknowns are solved by a sparse Cholesky
/// factorization.
const COARSEST_SIZE: usize = 4000;

/// Coarsening stops when a level keeps more than this share of its unknowns.
const MIN_REDUCTION: f64 = 0.8;

/// Gauss–Seidel sweeps before and after the coarse correction on every level.
/// Two halve the iterations one needs (the Stanford dragon's six extremality
/// solves: 106 iterations against 167, smoothing 5.6 s against 6.4 s); three cut
/// them to 87 but cost more than they save (6.9 s).
const SWEEPS: usize = 2;

/// A row-compressed sparse matrix, for the prolongators: `f64` values while the
/// hierarchy is made, `f32` in the V-cycle ([`Rows::compact`]).
#[derive(Clone, Debug, Default)]
struct Rows<T = f64> {
    ptr: Vec<usize>,
    /// Column indices, 32 bits wide: meshes index vertices with 32 bits.
    cols: Vec<u32>,
    values: Vec<T>,
}

impl Rows {
    /// The same rows with their values rounded to `f32`.
    fn compact(self) -> Rows<f32> {
        Rows {
            ptr: self.ptr,
            cols: self.cols,
            values: self.values.iter().map(|&v| v as f32).collect(),
        }
    }
}

impl<T: Entry> Rows<T> {
    fn row(&self, i: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let range = self.ptr[i]..self.ptr[i + 1];
        self.cols[range.clone()]
            .iter()
            .map(|&c| c as usize)
            .zip(self.values[range].iter().map(|&v| v.into()))
    }

    fn len(&self) -> usize {
        self.ptr.len() - 1
    }
}

impl Rows {
    /// The transpose, with `columns` rows.
    fn transpose(&self, columns: usize) -> Rows {
        let mut ptr = vec![0; columns + 1];
        for &c in &self.cols {
            ptr[c as usize + 1] += 1;
        }
        for c in 0..columns {
            ptr[c + 1] += ptr[c];
        }
        let mut next = ptr.clone();
        let mut cols = vec![0; self.cols.len()];
        let mut values = vec![0.0; self.cols.len()];
        for i in 0..self.len() {
            for (c, v) in self.row(i) {
                cols[next[c]] = i as u32;
                values[next[c]] = v;
                next[c] += 1;
            }
        }
        Rows { ptr, cols, values }
    }
}

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

/// What the hybrid Gauss–Seidel sweep ([`Smoother::sweep`]) of one level reads:
/// its matrix in `f32` (see [`Level`]), the reciprocal divisors of
/// [`sweep_inverse`] and the stiffly coupled unknowns it relaxes together.
#[derive(Clone, Debug)]
struct Smoother {
    matrix: SymmetricMatrix<f32>,
    inverse: Vec<f64>,
    blocks: Option<StiffBlocks>,
    /// The unknowns that rows of another piece of the sweep read, increasing.
    interface: Vec<u32>,
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

/// The pieces of rows that a Gauss–Seidel sweep relaxes in parallel: a fixed
/// number, so the result does not depend on the number of threads.
const SWEEP_PIECES: usize = 8;

/// Rows per piece of a sweep over `n` rows.
fn sweep_piece(n: usize) -> usize {
    n.div_ceil(SWEEP_PIECES).max(1)
}

/// The unknowns of `a` that a row in another piece of the hybrid sweep couples
/// to ([`sweep_piece`]), increasing: the only values the sweep must keep from
/// before it. Along the Morton curve the pieces are compact patches of the
/// surface, so this is their rims (1.5% of the dragon ×4's unknowns on the
/// fine level, 6.5% on the next), and copying it instead of the whole vector
/// before every sweep spares a pass over x (the ×4's smoothing 7.8 → 7.4 s).
fn interface(a: &SymmetricMatrix) -> Vec<u32> {
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
fn sweep_inverse(a: &SymmetricMatrix) -> Vec<f64> {
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
    fn new(a: &SymmetricMatrix) -> Smoother {
        Smoother {
            matrix: a.compact(),
            inverse: sweep_inverse(a),
            blocks: StiffBlocks::new(a, sweep_piece(a.size())),
            interface: interface(a),
        }
    }

    /// The size of its matrix.
    fn size(&self) -> usize {
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
    fn sweep<V: Lanes>(&self, b: &[V], x: &mut [V], before: &mut [V], backward: bool) {
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
    fn relax_block<V: Lanes>(
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
    fn residual<V: Lanes>(&self, b: &[V], piece: &Piece<'_, V>, i: usize) -> V {
        b[i] - self.matrix.row_sum(i, |j| piece.x(j))
    }
}

/// The rows of x one task of a sweep relaxes, from row `start` on, and the values
/// of the other pieces' rows from before the sweep.
struct Piece<'a, V> {
    start: usize,
    own: &'a mut [V],
    before: &'a [V],
}

impl<V: Lanes> Piece<'_, V> {
    /// x_j as the sweep has it: relaxed so far in this piece, from before the
    /// sweep in the others.
    #[inline(always)]
    fn x(&self, j: usize) -> V {
        match j.checked_sub(self.start) {
            Some(k) if k < self.own.len() => self.own[k],
            _ => self.before[j],
        }
    }
}

/// The next level of `a`: its prolongator P, Pᵀ and the Galerkin matrix, or
/// `None` if nothing is strongly coupled.
fn coarsen(a: &SymmetricMatrix, depth: usize) -> Option<(Rows, Rows, SymmetricMatrix)> {
    let diagonal = &a.diagonal();
    let (aggregate, sign, count) = aggregate(a, diagonal);
    if count == 0 {
        return None;
    }
    // Smoothing the coarser levels' prolongators too left the iteration counts as
    // they were (dragon and dragon ×4) and made their matrices five times denser.
    let omega = if depth == 0 {
        smoothing_weight(a, diagonal)
    } else {
        0.0
    };
    let prolongator = prolongator(a, diagonal, &aggregate, &sign, omega);
    let restrictor = prolongator.transpose(count);
    let coarse = galerkin(a, &prolongator, &restrictor, count);
    Some((prolongator, restrictor, coarse))
}

/// Marks a vertex that belongs to no aggregate.
const NONE: usize = usize::MAX;

/// Whether a_ij (i ≠ j) is a strong coupling.
fn strong(a_ij: f64, a_ii: f64, a_jj: f64) -> bool {
    a_ij * a_ij >= STRENGTH * STRENGTH * a_ii * a_jj
}

/// Greedy aggregation (Vaněk et al. §4): first every unknown whose strong
/// neighbours are all free starts an aggregate with them; then every unknown
/// left joins the aggregate of its strongest neighbour among the first pass's.
/// Unknowns with no strong coupling stay out (their rows are nearly diagonal, and
/// the smoother solves them). Returns each unknown's aggregate (or [`NONE`]), its
/// sign in the aggregate's basis vector, and the number of aggregates.
fn aggregate(a: &SymmetricMatrix, diagonal: &[f64]) -> (Vec<usize>, Vec<f64>, usize) {
    let n = a.size();
    let mut aggregate = vec![NONE; n];
    let mut sign = vec![1.0; n];
    let mut count = 0;
    let strong_neighbours = |i: usize| {
        a.column(i)
            .filter(move |&(j, v)| j != i && strong(v, diagonal[i], diagonal[j]))
    };
    for i in 0..n {
        if aggregate[i] != NONE {
            continue;
        }
        let isolated = strong_neighbours(i).next().is_none();
        if isolated || strong_neighbours(i).any(|(j, _)| aggregate[j] != NONE) {
            continue;
        }
        aggregate[i] = count;
        for (j, v) in strong_neighbours(i) {
            aggregate[j] = count;
            // Along a coupling a_ij = −t w σ the near-kernel has x_j = σ x_i.
            sign[j] = -v.signum();
        }
        count += 1;
    }
    let first = aggregate.clone();
    for i in 0..n {
        if aggregate[i] != NONE {
            continue;
        }
        let strongest = strong_neighbours(i)
            .filter(|&(j, _)| first[j] != NONE)
            .max_by(|x, y| x.1.abs().total_cmp(&y.1.abs()));
        if let Some((j, v)) = strongest {
            aggregate[i] = first[j];
            sign[i] = -v.signum() * sign[j];
        }
    }
    (aggregate, sign, count)
}

/// The prolongator smoothing's weight ω = 4 / (3 ρ), ρ ≥ ρ(D⁻¹ A) by Gershgorin
/// (Vaněk et al. §3); 0 (no smoothing) if ρ is not finite.
fn smoothing_weight(a: &SymmetricMatrix, diagonal: &[f64]) -> f64 {
    let rho = (0..a.size())
        .into_par_iter()
        .map(|i| a.column(i).map(|(_, v)| v.abs()).sum::<f64>() / diagonal[i])
        .reduce(|| 0.0, f64::max);
    let omega = 4.0 / (3.0 * rho);
    if omega.is_finite() {
        omega
    } else {
        0.0
    }
}

/// P = (I − ω D⁻¹ A) P₀ with the tentative prolongator P₀ (row i: `sign[i]` in
/// column `aggregate[i]`); P₀ itself for ω = 0.
fn prolongator(
    a: &SymmetricMatrix,
    diagonal: &[f64],
    aggregate: &[usize],
    sign: &[f64],
    omega: f64,
) -> Rows {
    let (ptr, cols, values) = compressed_rows(
        a.size(),
        || (),
        |(), i, row| {
            if aggregate[i] != NONE {
                row.push((aggregate[i] as u32, sign[i]));
            }
            if omega != 0.0 {
                let scale = omega / diagonal[i];
                for (j, v) in a.column(i).filter(|&(j, _)| aggregate[j] != NONE) {
                    row.push((aggregate[j] as u32, -scale * v * sign[j]));
                }
            }
            row.sort_unstable_by_key(|&(c, _)| c);
            row.dedup_by(|next, kept| {
                let same = next.0 == kept.0;
                if same {
                    kept.1 += next.1;
                }
                same
            });
        },
    );
    Rows { ptr, cols, values }
}

/// Rows that `fill` writes into an empty buffer one at a time (`fill(scratch,
/// row, buffer)`, with per-thread scratch made by `scratch`), computed in parallel
/// over pieces of rows and stored compressed: offsets, columns and values. Holds
/// no more than the result twice while it works, rather than a vector per row.
fn compressed_rows<C: Copy + Default + Send + Sync, S>(
    n: usize,
    scratch: impl Fn() -> S + Sync,
    fill: impl Fn(&mut S, usize, &mut Vec<(C, f64)>) + Sync,
) -> (Vec<usize>, Vec<C>, Vec<f64>) {
    const PIECE: usize = 16_384;
    let pieces: Vec<(Vec<usize>, Vec<C>, Vec<f64>)> = (0..n.div_ceil(PIECE))
        .into_par_iter()
        .map_init(
            || (scratch(), Vec::new()),
            |(scratch, row), piece| {
                let rows = piece * PIECE..((piece + 1) * PIECE).min(n);
                let (mut lengths, mut cols, mut values) =
                    (Vec::with_capacity(rows.len()), Vec::new(), Vec::new());
                for i in rows {
                    row.clear();
                    fill(scratch, i, row);
                    lengths.push(row.len());
                    cols.extend(row.iter().map(|&(c, _)| c));
                    values.extend(row.iter().map(|&(_, v)| v));
                }
                (lengths, cols, values)
            },
        )
        .collect();
    // Every piece copied into place, in parallel: on the dragon ×16's fine level
    // (24 million entries), one after the other took 0.95 s.
    let mut ptr = vec![0; n + 1];
    let stored = pieces.iter().map(|p| p.1.len()).sum();
    let (mut cols, mut values) = (vec![C::default(); stored], vec![0.0; stored]);
    let offsets: Vec<usize> = pieces
        .iter()
        .scan(0, |offset, piece| {
            let start = *offset;
            *offset += piece.1.len();
            Some(start)
        })
        .collect();
    let row_places = split_into(&mut ptr[1..], pieces.iter().map(|p| p.0.len()));
    let col_places = split_into(&mut cols, pieces.iter().map(|p| p.1.len()));
    let value_places = split_into(&mut values, pieces.iter().map(|p| p.1.len()));
    pieces
        .into_par_iter()
        .zip(offsets)
        .zip(row_places)
        .zip(col_places.into_par_iter().zip(value_places))
        .for_each(|(((piece, offset), ptr), (cols, values))| {
            let (lengths, piece_cols, piece_values) = piece;
            let mut end = offset;
            for (slot, length) in ptr.iter_mut().zip(lengths) {
                end += length;
                *slot = end;
            }
            cols.copy_from_slice(&piece_cols);
            values.copy_from_slice(&piece_values);
        });
    (ptr, cols, values)
}

/// The Galerkin coarse matrix Pᵀ A P, its upper triangle row by row, mirrored
/// into the lower one, so that it is exactly symmetric. Row I is (Pᵀ A P)_I = Σ_k
/// y_k P_k with the fine vector y = Σ_i P_iI A_i (the rows i of A over column I
/// of P): summing y first and multiplying each of its entries by a row of P once
/// costs fewer products than Σ_i Σ_k P_iI a_ik P_k, where a fine k reached from
/// several i multiplies its row of P once per path; and of each row of P only the
/// columns J ≥ I are needed. On the dragon ×16's first level: 2.0 s, against
/// 3.1–4.1 s for both triangles averaged with their transpose (docs/design/numerics.md).
fn galerkin(a: &SymmetricMatrix, p: &Rows, pt: &Rows, count: usize) -> SymmetricMatrix {
    let scratch = || (Accumulator::new(a.size()), Accumulator::new(count));
    let (ptr, cols, values) = compressed_rows(
        count,
        scratch,
        |(fine, coarse): &mut (Accumulator, Accumulator), big_i, row| {
            for (i, p_i) in pt.row(big_i) {
                for (k, a_ik) in a.column(i) {
                    fine.add(k, p_i * a_ik);
                }
            }
            fine.drain(|k, y_k| {
                for (big_j, p_k) in p.row(k).filter(|&(big_j, _)| big_j >= big_i) {
                    coarse.add(big_j, y_k * p_k);
                }
            });
            coarse.sort();
            coarse.drain(|big_j, value| row.push((big_j as u32, value)));
        },
    );
    from_upper_rows(count, &ptr, &cols, &values)
}

/// A sparse vector summed entry by entry in a dense one of its whole length,
/// which remembers the entries it touched: adding and reading back cost as
/// many steps as entries touched, not as the length.
struct Accumulator {
    sum: Vec<f64>,
    seen: Vec<bool>,
    touched: Vec<usize>,
}

impl Accumulator {
    /// A zero vector of length `n`.
    fn new(n: usize) -> Accumulator {
        Accumulator {
            sum: vec![0.0; n],
            seen: vec![false; n],
            touched: Vec::new(),
        }
    }

    /// Entry `j` += `value`.
    fn add(&mut self, j: usize, value: f64) {
        if !self.seen[j] {
            self.seen[j] = true;
            self.touched.push(j);
        }
        self.sum[j] += value;
    }

    /// Orders the touched entries by index, for [`drain`](Self::drain).
    fn sort(&mut self) {
        self.touched.sort_unstable();
    }

    /// Gives every touched entry (index and sum) to `f`, in the order first
    /// touched or [`sort`](Self::sort)ed, and leaves the vector zero.
    fn drain(&mut self, mut f: impl FnMut(usize, f64)) {
        for &j in &self.touched {
            f(j, self.sum[j]);
            self.sum[j] = 0.0;
            self.seen[j] = false;
        }
        self.touched.clear();
    }
}

/// Parts of the columns that [`from_upper_rows`] fills in parallel: a fixed
/// number, so that the work does not depend on the number of threads.
const MIRROR_PARTS: usize = 8;

/// The symmetric `n × n` matrix whose upper triangle is given by rows (`ptr`,
/// `cols`, `values`): row r holds the entries (r, c) with c ≥ r, increasing.
/// Column c of the result holds the entries (r, c) of the rows r < c, mirrored,
/// then row c's own. Parts of the columns are filled in parallel, each from the
/// rows that reach into it (on the dragon ×16's first coarse level, 25 million
/// entries, one pass over them all took 0.9–1.5 s).
fn from_upper_rows(n: usize, ptr: &[usize], cols: &[u32], values: &[f64]) -> SymmetricMatrix {
    let part = n.div_ceil(MIRROR_PARTS).max(1);
    let parts: Vec<Range<usize>> = (0..n.div_ceil(part))
        .map(|k| k * part..((k + 1) * part).min(n))
        .collect();
    // The slots of the entries (r, c), r < c, with c among `columns`, by row: rows
    // whose last (largest) column lies before the part are skipped.
    let mirrored = |columns: &Range<usize>| {
        let columns = columns.clone();
        (0..columns.end)
            .filter(move |&r| ptr[r] < ptr[r + 1] && cols[ptr[r + 1] - 1] as usize >= columns.start)
            .flat_map(move |r| (ptr[r]..ptr[r + 1]).map(move |s| (r, s)))
            .filter(move |&(r, s)| cols[s] as usize != r && columns.contains(&(cols[s] as usize)))
    };
    let lengths: Vec<usize> = parts
        .par_iter()
        .flat_map_iter(|columns| {
            let mut lengths: Vec<usize> = columns.clone().map(|c| ptr[c + 1] - ptr[c]).collect();
            for (_, s) in mirrored(columns) {
                lengths[cols[s] as usize - columns.start] += 1;
            }
            lengths
        })
        .collect();
    let mut col_ptr = Vec::with_capacity(n + 1);
    col_ptr.push(0);
    for (c, length) in lengths.into_iter().enumerate() {
        col_ptr.push(col_ptr[c] + length);
    }
    let mut row_idx = vec![0u32; col_ptr[n]];
    let mut entries = vec![0.0; col_ptr[n]];
    let lengths = parts.iter().map(|c| col_ptr[c.end] - col_ptr[c.start]);
    let row_places = split_into(&mut row_idx, lengths.clone());
    let entry_places = split_into(&mut entries, lengths);
    parts
        .into_par_iter()
        .zip(row_places)
        .zip(entry_places)
        .for_each(|((columns, rows), entries)| {
            let base = col_ptr[columns.start];
            // Every column's next free slot: its mirrored entries by increasing row,
            // then its own row.
            let mut next: Vec<usize> = columns.clone().map(|c| col_ptr[c] - base).collect();
            for (r, s) in mirrored(&columns) {
                let slot = &mut next[cols[s] as usize - columns.start];
                rows[*slot] = r as u32;
                entries[*slot] = values[s];
                *slot += 1;
            }
            for (c, &own) in columns.zip(&next) {
                let range = ptr[c]..ptr[c + 1];
                rows[own..own + range.len()].copy_from_slice(&cols[range.clone()]);
                entries[own..own + range.len()].copy_from_slice(&values[range]);
            }
        });
    SymmetricMatrix::from_csc(n, col_ptr, row_idx, entries)
        .expect("an upper triangle mirrored has sorted columns")
}

/// The coarse level against dense products.
#[cfg(test)]
mod tests {
    use nalgebra::DMatrix;

    use super::{coarsen, from_upper_rows, Rows};
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
