//! Blocks of unknowns joined by stiff couplings, which the multigrid smoother
//! relaxes together (block Gauss–Seidel).
//!
//! A scan's slivers join nearly coincident vertices with cotan weights up to 10⁴
//! times the typical one (on the Stanford dragon ×4, a quarter of the unknowns
//! of the extremality systems have a coupling of at least half their diagonal).
//! Relaxed one at a time, two such vertices hardly move apart or together: the
//! error along the stiff edge is left for the coarse levels, whose prolongators
//! represent it poorly. Solving each small group of stiffly coupled unknowns
//! exactly in the sweep removes that error where it arises.

use nalgebra::DMatrix;
use rayon::prelude::*;

use super::SymmetricMatrix;

/// A coupling a_ij is stiff when |a_ij| ≥ `STIFF` · √(a_ii a_jj): on a mesh of
/// equilateral triangles with the extremality systems' time step (τ = 2) the
/// ratio is about 0.15; 0.5 is reached at about seven times the typical weight.
const STIFF: f64 = 0.5;

/// The most unknowns in one block: the blocks are solved with dense inverses.
pub(super) const MAX_BLOCK: usize = 8;

/// An unknown relaxed alone.
const SINGLE: u32 = u32::MAX;
/// A block's member after its first, relaxed with the block.
const FOLLOWER: u32 = u32::MAX - 1;

/// Groups of unknowns of a matrix joined by stiff couplings, each within one
/// piece of rows of the hybrid sweep, with the inverses of their diagonal blocks.
#[derive(Clone, Debug)]
pub(super) struct StiffBlocks {
    /// Of every unknown: the block it is the first member of, [`FOLLOWER`] or
    /// [`SINGLE`].
    role: Vec<u32>,
    /// Offsets of every block's members in `members` (and one past the last).
    start: Vec<usize>,
    /// The members of each block, increasing.
    members: Vec<u32>,
    /// Offsets of every block's inverse in `inverses`.
    inverse_start: Vec<usize>,
    /// The inverse of every block's diagonal block (with the ℓ1 terms of the
    /// couplings to other pieces on its diagonal), row by row.
    inverses: Vec<f64>,
}

/// What a sweep does at one unknown ([`StiffBlocks::at`]).
pub(super) enum Relax<'a> {
    /// Relax it alone.
    Single,
    /// Relax its block, of which it is the first member.
    Block {
        members: &'a [u32],
        /// The inverse of the block's diagonal block, row by row.
        inverse: &'a [f64],
    },
    /// Nothing: it is relaxed with its block.
    Follower,
}

impl StiffBlocks {
    /// The blocks of `a` for a sweep in pieces of `piece` rows, each block inside
    /// one piece; `None` if nothing is stiffly coupled.
    pub(super) fn new(a: &SymmetricMatrix, piece: usize) -> Option<StiffBlocks> {
        let diagonal = a.diagonal();
        let groups: Vec<Vec<u32>> = (0..a.size().div_ceil(piece))
            .into_par_iter()
            .flat_map_iter(|k| {
                let rows = k * piece..((k + 1) * piece).min(a.size());
                stiff_groups(a, &diagonal, rows)
            })
            .collect();
        let inverses: Vec<Option<Vec<f64>>> = groups
            .par_iter()
            .map(|group| block_inverse(a, group, piece))
            .collect();
        let mut blocks = StiffBlocks {
            role: vec![SINGLE; a.size()],
            start: vec![0],
            members: Vec::new(),
            inverse_start: vec![0],
            inverses: Vec::new(),
        };
        for (group, inverse) in groups.into_iter().zip(inverses) {
            // A block that is not positive definite in floating point stays
            // relaxed one unknown at a time.
            let Some(inverse) = inverse else { continue };
            blocks.role[group[0] as usize] = blocks.start.len() as u32 - 1;
            for &m in &group[1..] {
                blocks.role[m as usize] = FOLLOWER;
            }
            blocks.members.extend(group);
            blocks.start.push(blocks.members.len());
            blocks.inverses.extend(inverse);
            blocks.inverse_start.push(blocks.inverses.len());
        }
        (blocks.start.len() > 1).then_some(blocks)
    }

    /// What the sweep does at unknown `i`.
    #[inline]
    pub(super) fn at(&self, i: usize) -> Relax<'_> {
        match self.role[i] {
            SINGLE => Relax::Single,
            FOLLOWER => Relax::Follower,
            b => {
                let b = b as usize;
                Relax::Block {
                    members: &self.members[self.start[b]..self.start[b + 1]],
                    inverse: &self.inverses[self.inverse_start[b]..self.inverse_start[b + 1]],
                }
            }
        }
    }
}

/// The groups of two to [`MAX_BLOCK`] unknowns among `rows` (one piece) that
/// stiff couplings within them join (union–find over the couplings in row
/// order), members increasing, groups by their first member.
fn stiff_groups(
    a: &SymmetricMatrix,
    diagonal: &[f64],
    rows: std::ops::Range<usize>,
) -> Vec<Vec<u32>> {
    let offset = rows.start;
    let mut parent: Vec<usize> = (0..rows.len()).collect();
    let mut size = vec![1usize; rows.len()];
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for i in rows.clone() {
        for (j, v) in a.column(i) {
            let inside = j > i && j < rows.end;
            if !inside || v * v < STIFF * STIFF * diagonal[i] * diagonal[j] {
                continue;
            }
            let (ri, rj) = (root(&mut parent, i - offset), root(&mut parent, j - offset));
            if ri != rj && size[ri] + size[rj] <= MAX_BLOCK {
                let (big, small) = if size[ri] >= size[rj] {
                    (ri, rj)
                } else {
                    (rj, ri)
                };
                parent[small] = big;
                size[big] += size[small];
            }
        }
    }
    let mut group_of = vec![usize::MAX; rows.len()];
    let mut groups: Vec<Vec<u32>> = Vec::new();
    for local in 0..rows.len() {
        let r = root(&mut parent, local);
        if size[r] < 2 {
            continue;
        }
        if group_of[r] == usize::MAX {
            group_of[r] = groups.len();
            groups.push(Vec::with_capacity(size[r]));
        }
        groups[group_of[r]].push((local + offset) as u32);
    }
    groups
}

/// The inverse (row by row) of the diagonal block of `a` on `members`, with the
/// ℓ1 terms Σ |a_ij| over columns j in other pieces (of `piece` rows) added to
/// its diagonal as the point sweep adds them; `None` if its Cholesky
/// factorization fails.
fn block_inverse(a: &SymmetricMatrix, members: &[u32], piece: usize) -> Option<Vec<f64>> {
    let k = members.len();
    let mut block = DMatrix::<f64>::zeros(k, k);
    for (r, &m) in members.iter().enumerate() {
        let m = m as usize;
        for (j, v) in a.column(m) {
            match members.iter().position(|&x| x as usize == j) {
                Some(c) => block[(r, c)] += v,
                None if j / piece != m / piece => block[(r, r)] += v.abs(),
                None => {}
            }
        }
    }
    // Symmetric: its columns are its rows.
    Some(block.cholesky()?.inverse().iter().copied().collect())
}
