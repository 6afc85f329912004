//! The multigrid's sparse assembly: row-compressed prolongators, rows computed in
//! parallel and stored compressed, the Galerkin product Pᵀ A P and the mirroring of
//! an upper triangle into a whole symmetric matrix.

use std::ops::Range;

use rayon::prelude::*;

use super::super::{Entry, SymmetricMatrix};
use crate::slices::split_into;

/// A row-compressed sparse matrix, for the prolongators: `f64` values while the
/// hierarchy is made, `f32` in the V-cycle ([`Rows::compact`]).
#[derive(Clone, Debug, Default)]
pub(super) struct Rows<T = f64> {
    pub(super) ptr: Vec<usize>,
    /// Column indices, 32 bits wide: meshes index vertices with 32 bits.
    pub(super) cols: Vec<u32>,
    pub(super) values: Vec<T>,
}

impl Rows {
    /// The same rows with their values rounded to `f32`.
    pub(super) fn compact(self) -> Rows<f32> {
        Rows {
            ptr: self.ptr,
            cols: self.cols,
            values: self.values.iter().map(|&v| v as f32).collect(),
        }
    }
}

impl<T: Entry> Rows<T> {
    pub(super) fn row(&self, i: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let range = self.ptr[i]..self.ptr[i + 1];
        self.cols[range.clone()]
            .iter()
            .map(|&c| c as usize)
            .zip(self.values[range].iter().map(|&v| v.into()))
    }

    pub(super) fn len(&self) -> usize {
        self.ptr.len() - 1
    }
}

impl Rows {
    /// The transpose, with `columns` rows.
    pub(super) fn transpose(&self, columns: usize) -> Rows {
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

/// Rows that `fill` writes into an empty buffer one at a time (`fill(scratch,
/// row, buffer)`, with per-thread scratch made by `scratch`), computed in parallel
/// over pieces of rows and stored compressed: offsets, columns and values. Holds
/// no more than the result twice while it works, rather than a vector per row.
pub(super) fn compressed_rows<C: Copy + Default + Send + Sync, S>(
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
pub(super) fn galerkin(a: &SymmetricMatrix, p: &Rows, pt: &Rows, count: usize) -> SymmetricMatrix {
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
pub(super) struct Accumulator {
    pub(super) sum: Vec<f64>,
    pub(super) seen: Vec<bool>,
    pub(super) touched: Vec<usize>,
}

impl Accumulator {
    /// A zero vector of length `n`.
    pub(super) fn new(n: usize) -> Accumulator {
        Accumulator {
            sum: vec![0.0; n],
            seen: vec![false; n],
            touched: Vec::new(),
        }
    }

    /// Entry `j` += `value`.
    pub(super) fn add(&mut self, j: usize, value: f64) {
        if !self.seen[j] {
            self.seen[j] = true;
            self.touched.push(j);
        }
        self.sum[j] += value;
    }

    /// Orders the touched entries by index, for [`drain`](Self::drain).
    pub(super) fn sort(&mut self) {
        self.touched.sort_unstable();
    }

    /// Gives every touched entry (index and sum) to `f`, in the order first
    /// touched or [`sort`](Self::sort)ed, and leaves the vector zero.
    pub(super) fn drain(&mut self, mut f: impl FnMut(usize, f64)) {
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
pub(super) const MIRROR_PARTS: usize = 8;

/// The symmetric `n × n` matrix whose upper triangle is given by rows (`ptr`,
/// `cols`, `values`): row r holds the entries (r, c) with c ≥ r, increasing.
/// Column c of the result holds the entries (r, c) of the rows r < c, mirrored,
/// then row c's own. Parts of the columns are filled in parallel, each from the
/// rows that reach into it (on the dragon ×16's first coarse level, 25 million
/// entries, one pass over them all took 0.9–1.5 s).
pub(super) fn from_upper_rows(
    n: usize,
    ptr: &[usize],
    cols: &[u32],
    values: &[f64],
) -> SymmetricMatrix {
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
