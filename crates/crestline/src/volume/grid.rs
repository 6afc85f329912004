//! The index arithmetic of a volume's grid, in one place.
//!
//! - Sample `(i, j, k)` of a grid of `nx × ny × nz` samples is stored x fastest, at
//!   linear index `i + nx·(j + ny·k)` ([`Grid::index`], [`Grid::position_of`]).
//! - A cell is named by its lowest corner; its corner `c` is offset by
//!   `(c & 1, (c >> 1) & 1, (c >> 2) & 1)` from it ([`corner_offset`]).
//! - A grid edge is keyed `3 · point + axis` by the linear index of its first sample
//!   and the axis it runs along, a face alike by its lowest corner and the axis
//!   normal to it ([`edge_key`], [`Grid::key`]): all cells around an edge or a face
//!   name it the same.

use std::ops::Range;

/// A grid of `dims` samples, x fastest in memory.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Grid {
    /// The number of samples along x, y and z.
    pub dims: [usize; 3],
}

impl Grid {
    /// The linear index of sample `(i, j, k)`: `i + nx·(j + ny·k)`.
    #[inline]
    pub fn index(&self, [i, j, k]: [usize; 3]) -> usize {
        i + self.dims[0] * (j + self.dims[1] * k)
    }

    /// The sample `(i, j, k)` at linear index `n`: the inverse of [`Grid::index`].
    #[inline]
    pub fn position_of(&self, n: usize) -> [usize; 3] {
        let [nx, ny, _] = self.dims;
        [n % nx, (n / nx) % ny, n / (nx * ny)]
    }

    /// Whether `index` is a sample of the grid.
    #[inline]
    pub fn contains(&self, index: [usize; 3]) -> bool {
        (0..3).all(|a| index[a] < self.dims[a])
    }

    /// The linear index of sample `index`, or `None` outside the grid.
    #[inline]
    pub fn checked_index(&self, index: [usize; 3]) -> Option<usize> {
        self.contains(index).then(|| self.index(index))
    }

    /// The number of samples.
    pub fn sample_count(&self) -> usize {
        self.dims.iter().product()
    }

    /// The number of samples of one z plane, `nx·ny`.
    #[inline]
    pub fn plane_len(&self) -> usize {
        self.dims[0] * self.dims[1]
    }

    /// The difference of linear index between neighbours along `axis`.
    #[inline]
    pub fn step(&self, axis: usize) -> usize {
        [1, self.dims[0], self.plane_len()][axis]
    }

    /// The linear indices of the 8 corners of `cell` (its lowest corner), corner `c`
    /// being [`cell_corner`]`(cell, c)`.
    #[inline]
    pub fn corners(&self, cell: [usize; 3]) -> [usize; 8] {
        let at = self.index(cell);
        let (y, z) = (self.step(1), self.step(2));
        [
            at,
            at + 1,
            at + y,
            at + 1 + y,
            at + z,
            at + 1 + z,
            at + y + z,
            at + 1 + y + z,
        ]
    }

    /// The linear index of corner `c` of a cell minus that of its lowest corner, for
    /// each of the 8 corners.
    pub fn corner_steps(&self) -> [usize; 8] {
        self.corners([0; 3])
    }

    /// The number of cell layers along z, `nz − 1`.
    pub fn cell_layers(&self) -> usize {
        self.dims[2] - 1
    }

    /// The cells (lowest corners) of the z layers `layers`, x fastest, then y, then
    /// z.
    pub fn cells(&self, layers: Range<usize>) -> Cells {
        let [nx, ny, _] = self.dims;
        let width = [nx - 1, ny - 1];
        let end = if width.contains(&0) {
            layers.start
        } else {
            layers.end
        };
        Cells {
            next: [0, 0, layers.start],
            width,
            end,
        }
    }

    /// The cell (lowest corner) holding the fractional index `u`, the nearest one
    /// where `u` lies outside the cells (an axis of one sample has cell 0).
    #[inline]
    pub fn cell_holding(&self, u: [f64; 3]) -> [usize; 3] {
        let last = self.dims.map(|n| n.saturating_sub(2));
        std::array::from_fn(|a| (u[a].floor().max(0.0) as usize).min(last[a]))
    }

    /// Whether the cell with lowest corner `cell` lies in the grid.
    pub fn has_cell(&self, cell: [usize; 3]) -> bool {
        self.contains(cell.map(|x| x + 1))
    }

    /// The key `3 · index(point) + axis` of the edge from sample `point` along
    /// `axis`, or of the face with lowest corner `point` normal to `axis`.
    #[inline]
    pub fn key(&self, point: [usize; 3], axis: usize) -> u64 {
        edge_key(self.index(point), axis)
    }

    /// The point and axis of a key: the inverse of [`Grid::key`].
    #[inline]
    pub fn unkey(&self, key: u64) -> ([usize; 3], usize) {
        let (point, axis) = edge_of_key(key);
        (self.position_of(point), axis)
    }

    /// The four corners of the face with lowest corner `low` normal to `axis`, in
    /// cyclic order.
    pub fn face_corners(&self, low: [usize; 3], axis: usize) -> [[usize; 3]; 4] {
        let (u, v) = in_face_axes(axis);
        [(0, 0), (1, 0), (1, 1), (0, 1)].map(|(du, dv)| {
            let mut c = low;
            c[u] += du;
            c[v] += dv;
            c
        })
    }

    /// Whether the face with lowest corner `low` normal to `axis` lies in the grid.
    pub fn has_face(&self, low: [usize; 3], axis: usize) -> bool {
        self.contains(self.face_corners(low, axis)[2])
    }

    /// The four edges around a face in cyclic order, each with whether the cycle
    /// runs along it forwards (from its first sample).
    pub fn face_edges(&self, low: [usize; 3], axis: usize) -> [(u64, bool); 4] {
        let corners = self.face_corners(low, axis);
        std::array::from_fn(|k| {
            let (a, b) = (corners[k], corners[(k + 1) % 4]);
            let forward = a <= b;
            let first = if forward { a } else { b };
            let along = (0..3).find(|&x| a[x] != b[x]).unwrap_or(0);
            (self.key(first, along), forward)
        })
    }

    /// The keys of the (up to four) faces of the grid around edge `key`.
    pub fn edge_faces(&self, key: u64) -> Vec<u64> {
        let (point, along) = self.unkey(key);
        let mut faces = Vec::with_capacity(4);
        for normal in (0..3).filter(|&a| a != along) {
            let across = 3 - along - normal;
            let mut below = point;
            if point[across] > 0 {
                below[across] -= 1;
                faces.push(self.key(below, normal));
            }
            if self.has_face(point, normal) {
                faces.push(self.key(point, normal));
            }
        }
        faces
    }

    /// The (up to four) cells of the grid around edge `key`, as lowest corners.
    pub fn edge_cells(&self, key: u64) -> impl Iterator<Item = [usize; 3]> + '_ {
        let (point, axis) = self.unkey(key);
        let (u, v) = in_face_axes(axis);
        [(0, 0), (1, 0), (0, 1), (1, 1)]
            .into_iter()
            .filter_map(move |(du, dv)| {
                let mut cell = point;
                cell[u] = point[u].checked_sub(du)?;
                cell[v] = point[v].checked_sub(dv)?;
                Some(cell)
            })
            .filter(|&cell| self.has_cell(cell))
    }

    /// The (up to two) cells of the grid on either side of face `key`, as lowest
    /// corners.
    pub fn face_cells(&self, key: u64) -> impl Iterator<Item = [usize; 3]> + '_ {
        let (low, axis) = self.unkey(key);
        [0, 1]
            .into_iter()
            .filter_map(move |below| {
                let mut cell = low;
                cell[axis] = low[axis].checked_sub(below)?;
                Some(cell)
            })
            .filter(|&cell| self.has_cell(cell))
    }
}

/// The cells of some z layers of a grid, x fastest ([`Grid::cells`]).
pub(crate) struct Cells {
    /// The next cell.
    next: [usize; 3],
    /// The number of cells along x and y.
    width: [usize; 2],
    /// The layer after the last.
    end: usize,
}

impl Iterator for Cells {
    type Item = [usize; 3];

    #[inline]
    fn next(&mut self) -> Option<[usize; 3]> {
        let cell = self.next;
        if cell[2] >= self.end {
            return None;
        }
        self.next[0] += 1;
        if self.next[0] == self.width[0] {
            self.next[0] = 0;
            self.next[1] += 1;
            if self.next[1] == self.width[1] {
                self.next[1] = 0;
                self.next[2] += 1;
            }
        }
        Some(cell)
    }
}

/// The offset of corner `c` of a cell from its lowest corner, along x, y and z.
#[inline]
pub(crate) fn corner_offset(c: usize) -> [usize; 3] {
    [c & 1, (c >> 1) & 1, (c >> 2) & 1]
}

/// Corner `c` of the cell with lowest corner `cell`.
#[inline]
pub(crate) fn cell_corner([i, j, k]: [usize; 3], c: usize) -> [usize; 3] {
    let [di, dj, dk] = corner_offset(c);
    [i + di, j + dj, k + dk]
}

/// The key `3 · point + axis` of the grid edge from the sample of linear index
/// `point` along `axis` (or of the face with that lowest corner normal to `axis`).
#[inline]
pub(crate) fn edge_key(point: usize, axis: usize) -> u64 {
    3 * point as u64 + axis as u64
}

/// The linear index of the first sample and the axis of edge `key`: the inverse of
/// [`edge_key`].
#[inline]
pub(crate) fn edge_of_key(key: u64) -> (usize, usize) {
    ((key / 3) as usize, (key % 3) as usize)
}

/// The two index axes spanning a face normal to `axis`, in cyclic order (so that
/// `(u, v, axis)` is right-handed).
#[inline]
pub(crate) fn in_face_axes(axis: usize) -> (usize, usize) {
    ((axis + 1) % 3, (axis + 2) % 3)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_indices_run_x_fastest_and_invert() {
        let grid = Grid { dims: [4, 5, 3] };
        assert_eq!(grid.sample_count(), 60);
        for n in 0..60 {
            let p = grid.position_of(n);
            assert_eq!(grid.index(p), n);
            assert_eq!(grid.checked_index(p), Some(n));
            for axis in 0..3 {
                let mut next = p;
                next[axis] += 1;
                if grid.contains(next) {
                    assert_eq!(grid.index(next), n + grid.step(axis));
                } else {
                    assert_eq!(grid.checked_index(next), None);
                }
                let key = grid.key(p, axis);
                assert_eq!(grid.unkey(key), (p, axis));
                assert_eq!(edge_of_key(key), (n, axis));
            }
        }
        assert_eq!(grid.position_of(1 + 4 * (2 + 5 * 2)), [1, 2, 2]);
        assert_eq!([0, 1, 2].map(|a| grid.step(a)), [1, 4, 20]);
    }

    #[test]
    fn cells_and_their_corners() {
        let grid = Grid { dims: [4, 5, 3] };
        let cells: Vec<[usize; 3]> = grid.cells(0..grid.cell_layers()).collect();
        assert_eq!(cells.len(), 3 * 4 * 2);
        assert_eq!(cells[..2], [[0, 0, 0], [1, 0, 0]]);
        assert_eq!(cells.last(), Some(&[2, 3, 1]));
        assert!(cells.iter().all(|&c| grid.has_cell(c)));
        let nested: Vec<[usize; 3]> = (1..2)
            .flat_map(|k| (0..4).flat_map(move |j| (0..3).map(move |i| [i, j, k])))
            .collect();
        assert_eq!(grid.cells(1..2).collect::<Vec<_>>(), nested);
        assert_eq!(grid.cells(1..1).count(), 0);
        assert_eq!(Grid { dims: [1, 5, 3] }.cells(0..2).count(), 0);
        let corners = grid.corners([1, 2, 1]);
        let base = grid.index([1, 2, 1]);
        for (c, (&at, step)) in corners.iter().zip(grid.corner_steps()).enumerate() {
            assert_eq!(at, base + step);
            assert_eq!(grid.position_of(at), cell_corner([1, 2, 1], c));
        }
        assert_eq!(corner_offset(6), [0, 1, 1]);
    }

    #[test]
    fn an_edge_lies_on_the_faces_and_cells_that_list_it() {
        let grid = Grid { dims: [4, 5, 3] };
        for n in 0..60 {
            let p = grid.position_of(n);
            for axis in 0..3 {
                let mut end = p;
                end[axis] += 1;
                if !grid.contains(end) {
                    continue;
                }
                let edge = grid.key(p, axis);
                let faces = grid.edge_faces(edge);
                let inside = |x: usize, d: usize| (1..d - 1).contains(&x);
                let expected = (0..3)
                    .filter(|&a| a != axis)
                    .map(|a| {
                        let across = 3 - axis - a;
                        if inside(p[across], grid.dims[across]) {
                            2
                        } else {
                            1
                        }
                    })
                    .sum::<usize>();
                assert_eq!(faces.len(), expected, "edge {p:?} {axis}");
                for face in faces {
                    let (low, normal) = grid.unkey(face);
                    assert!(grid.has_face(low, normal));
                    let edges = grid.face_edges(low, normal);
                    assert!(edges.iter().any(|&(e, _)| e == edge));
                    for cell in grid.face_cells(face) {
                        let corners = grid.corners(cell);
                        assert!(grid
                            .face_corners(low, normal)
                            .iter()
                            .all(|&c| corners.contains(&grid.index(c))));
                    }
                }
                for cell in grid.edge_cells(edge) {
                    let corners = grid.corners(cell);
                    assert!(corners.contains(&n) && corners.contains(&grid.index(end)));
                }
                let cells = grid.edge_cells(edge).count();
                let around: usize = (0..3)
                    .filter(|&a| a != axis)
                    .map(|a| if inside(p[a], grid.dims[a]) { 2 } else { 1 })
                    .product();
                assert_eq!(cells, around, "edge {p:?} {axis}");
            }
        }
    }
}
