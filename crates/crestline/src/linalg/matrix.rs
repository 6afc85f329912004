//! Assembly and storage of sparse symmetric matrices.

use std::sync::Arc;

use rayon::prelude::*;

use super::{Lanes, CHUNK};
use crate::{Error, Result};

/// Assembles a symmetric `n × n` sparse matrix from entries that may repeat;
/// repeated entries are summed.
///
/// [`add`](Self::add) writes an off-diagonal value to both `(i, j)` and `(j, i)`, so
/// the built matrix is symmetric by construction.
#[derive(Debug)]
#[cfg(test)]
pub struct SymmetricBuilder {
    n: usize,
    /// `(row, column, value)` entries, in the order added.
    triplets: Vec<(usize, usize, f64)>,
}

#[cfg(test)]
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
        let mut offsets = Vec::with_capacity(self.n + 1);
        let mut rows: Vec<u32> = Vec::with_capacity(entries.len());
        let mut values: Vec<f64> = Vec::with_capacity(entries.len());
        offsets.push(0);
        for j in 0..self.n {
            let column = &mut entries[col_ptr[j]..col_ptr[j + 1]];
            column.sort_unstable_by_key(|&(i, _)| i);
            let start = rows.len();
            for &(i, value) in column.iter() {
                match values.last_mut() {
                    Some(sum) if rows.len() > start && rows.last() == Some(&(i as u32)) => {
                        *sum += value;
                    }
                    _ => {
                        rows.push(i as u32);
                        values.push(value);
                    }
                }
            }
            offsets.push(rows.len());
        }
        SymmetricMatrix {
            n: self.n,
            col_ptr: offsets.into(),
            row_idx: rows.into(),
            values,
        }
    }
}

/// A square sparse matrix in compressed sparse column form (both triangles stored),
/// as [`SymmetricBuilder`] makes it and [`CholeskyFactor`](super::CholeskyFactor) reads it.
/// Matrices with one pattern (the two extremality fields' systems) share it.
/// Row indices are 32 bits wide, as the mesh's vertex ids: the iterative solver
/// streams them every sweep, and a third fewer bytes per entry are a third less
/// time where memory bandwidth decides.
///
/// The values are `f64`, or `f32` in the multigrid preconditioner's copies
/// ([`SymmetricMatrix::compact`]), which it streams every sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct SymmetricMatrix<T: Entry = f64> {
    n: usize,
    col_ptr: Arc<[usize]>,
    row_idx: Arc<[u32]>,
    values: Vec<T>,
}

/// The type of a stored matrix entry, read as `f64`.
pub trait Entry: Copy + Into<f64> + PartialEq + std::fmt::Debug + Send + Sync {}

impl Entry for f64 {}
impl Entry for f32 {}

impl SymmetricMatrix {
    /// The matrix with its values rounded to `f32` and its pattern shared: two
    /// thirds of the bytes per entry (a 4-byte row index and a 4-byte value), for
    /// a preconditioner, which needs the matrix only approximately.
    pub fn compact(&self) -> SymmetricMatrix<f32> {
        SymmetricMatrix {
            n: self.n,
            col_ptr: self.col_ptr.clone(),
            row_idx: self.row_idx.clone(),
            values: self.values.par_iter().map(|&v| v as f32).collect(),
        }
    }
}

impl<T: Entry> SymmetricMatrix<T> {
    /// A matrix from its compressed columns: `col_ptr` (n + 1 offsets), the row of
    /// every entry and its value. Errors if the arrays do not describe an `n × n`
    /// matrix with sorted, distinct rows in every column. Shared offsets and rows
    /// (`Arc`) are kept shared.
    pub fn from_csc(
        n: usize,
        col_ptr: impl Into<Arc<[usize]>>,
        row_idx: impl Into<Arc<[u32]>>,
        values: Vec<T>,
    ) -> Result<SymmetricMatrix<T>> {
        let (col_ptr, row_idx) = (col_ptr.into(), row_idx.into());
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
        if let Some(&i) = row_idx.iter().find(|&&i| i as usize >= n) {
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
            .map(|&i| i as usize)
            .zip(self.values[range].iter().map(|&v| v.into()))
    }

    /// Every stored entry as `(row, column, value)`, column by column.
    #[cfg(test)]
    pub fn entries(&self) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        (0..self.n).flat_map(move |j| self.column(j).map(move |(i, v)| (i, j, v)))
    }

    /// The compressed columns: offsets, rows and values (e.g. to hand the matrix to
    /// another solver).
    pub fn csc(&self) -> (&[usize], &[u32], &[T]) {
        (&self.col_ptr, &self.row_idx, &self.values)
    }

    /// The diagonal entries (zero where none is stored).
    pub fn diagonal(&self) -> Vec<f64> {
        (0..self.n)
            .into_par_iter()
            .map(|j| {
                self.column(j)
                    .find(|&(i, _)| i == j)
                    .map_or(0.0, |(_, v)| v)
            })
            .collect()
    }

    /// `y = A x`, in parallel over rows, and returns xᵀy (per lane: summed per
    /// chunk of rows and the chunks in order, so the same whatever the number of
    /// threads): the conjugate gradient method needs both, and taking the inner
    /// product while y is written spares it a pass over x and y. Both triangles
    /// are stored, so column `i` of the symmetric matrix is its row `i`.
    ///
    /// # Panics
    /// If `x` or `y` does not have length [`size`](Self::size).
    pub fn mul_vec<V: Lanes>(&self, x: &[V], y: &mut [V]) -> V {
        assert!(
            x.len() == self.n && y.len() == self.n,
            "product of a {n}×{n} matrix with vectors of length {} and {}",
            x.len(),
            y.len(),
            n = self.n
        );
        let parts: Vec<V> = y
            .par_chunks_mut(CHUNK)
            .enumerate()
            .map(|(c, rows)| {
                let mut sum = V::default();
                for (k, yi) in rows.iter_mut().enumerate() {
                    let i = c * CHUNK + k;
                    *yi = self.row_dot(i, x);
                    sum += x[i].times(*yi);
                }
                sum
            })
            .collect();
        parts.iter().fold(V::default(), |total, &part| total + part)
    }

    /// `r = b − A x`, in parallel over rows.
    ///
    /// # Panics
    /// If `x`, `b` or `r` does not have length [`size`](Self::size).
    pub fn residual<V: Lanes>(&self, x: &[V], b: &[V], r: &mut [V]) {
        assert!(
            x.len() == self.n && b.len() == self.n && r.len() == self.n,
            "residual of a {n}×{n} system with vectors of length {}, {} and {}",
            x.len(),
            b.len(),
            r.len(),
            n = self.n
        );
        r.par_chunks_mut(CHUNK).enumerate().for_each(|(c, rows)| {
            for (k, ri) in rows.iter_mut().enumerate() {
                let i = c * CHUNK + k;
                *ri = b[i] - self.row_dot(i, x);
            }
        });
    }

    /// Row `i` of the matrix times `x`.
    fn row_dot<V: Lanes>(&self, i: usize, x: &[V]) -> V {
        self.row_sum(i, |j| x[j])
    }

    /// Σ_j a_ij x_j over row `i` (column i: the matrix is symmetric), x_j read by
    /// `x_at`, in the order of the stored entries.
    #[inline(always)]
    pub(super) fn row_sum<V: Lanes>(&self, i: usize, x_at: impl Fn(usize) -> V) -> V {
        let range = self.col_ptr[i]..self.col_ptr[i + 1];
        self.row_idx[range.clone()]
            .iter()
            .zip(&self.values[range])
            .fold(V::default(), |sum, (&j, &v)| {
                sum + x_at(j as usize) * v.into()
            })
    }
}
