//! Keys and neighbourhoods of the grid's edges and faces, and the crossings of each
//! edge looked up by key.
//!
//! An edge is keyed `3 · point + axis` (its first sample and the axis it runs
//! along), a face `3 · point + axis` (its lowest corner and the axis normal to it):
//! both cells of a face and all four cells of an edge name it alike.

use std::collections::HashMap;

use super::edges::EdgeCrossing;

/// Linear index ↔ grid index of a grid of `dims` samples.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Grid {
    pub dims: [usize; 3],
}

impl Grid {
    /// The linear index (x fastest) of `index`.
    pub fn linear(&self, [i, j, k]: [usize; 3]) -> usize {
        i + self.dims[0] * (j + self.dims[1] * k)
    }

    /// The grid index of linear index `n`.
    pub fn index(&self, n: usize) -> [usize; 3] {
        let [nx, ny, _] = self.dims;
        [n % nx, (n / nx) % ny, n / (nx * ny)]
    }

    /// The key `3 · linear(point) + axis`.
    pub fn key(&self, point: [usize; 3], axis: usize) -> u64 {
        3 * self.linear(point) as u64 + axis as u64
    }

    /// The point and axis of a key.
    pub fn unkey(&self, key: u64) -> ([usize; 3], usize) {
        (self.index((key / 3) as usize), (key % 3) as usize)
    }

    /// Whether `index` is a sample of the grid.
    pub fn contains(&self, index: [usize; 3]) -> bool {
        (0..3).all(|a| index[a] < self.dims[a])
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
}

/// The two index axes spanning a face normal to `axis`, in cyclic order.
pub(crate) fn in_face_axes(axis: usize) -> (usize, usize) {
    ((axis + 1) % 3, (axis + 2) % 3)
}

/// The crossings of each grid edge, by edge key.
pub(crate) struct EdgeIndex {
    /// Edge key → the range of its crossings in the (edge-sorted) list.
    ranges: HashMap<u64, (usize, usize)>,
}

impl EdgeIndex {
    /// The index of `crossings`, sorted by edge.
    pub fn new(crossings: &[EdgeCrossing]) -> EdgeIndex {
        let mut ranges = HashMap::new();
        for (n, c) in crossings.iter().enumerate() {
            ranges
                .entry(c.edge)
                .and_modify(|r: &mut (usize, usize)| r.1 = n + 1)
                .or_insert((n, n + 1));
        }
        EdgeIndex { ranges }
    }

    /// The ids of the crossings on `edge`, by increasing t.
    pub fn on(&self, edge: u64) -> std::ops::Range<usize> {
        self.ranges.get(&edge).map_or(0..0, |&(a, b)| a..b)
    }

    /// The keys of the crossed edges, sorted.
    pub fn edges(&self) -> Vec<u64> {
        let mut keys: Vec<u64> = self.ranges.keys().copied().collect();
        keys.sort_unstable();
        keys
    }

    /// The ids of the crossings around a face, in cyclic order.
    pub fn around_face(&self, grid: &Grid, low: [usize; 3], axis: usize) -> Vec<usize> {
        let mut around = Vec::new();
        for (edge, forward) in grid.face_edges(low, axis) {
            let ids = self.on(edge);
            if forward {
                around.extend(ids);
            } else {
                around.extend(ids.rev());
            }
        }
        around
    }

    /// The cells (lowest corners) around every crossed edge that lie in the grid,
    /// sorted, deduplicated.
    pub fn touched_cells(&self, grid: &Grid) -> Vec<[usize; 3]> {
        let mut cells: Vec<[usize; 3]> = Vec::new();
        for &edge in self.ranges.keys() {
            let (p, axis) = grid.unkey(edge);
            let (u, v) = in_face_axes(axis);
            for (du, dv) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let mut cell = p;
                if (du == 1 && cell[u] == 0) || (dv == 1 && cell[v] == 0) {
                    continue;
                }
                cell[u] -= du;
                cell[v] -= dv;
                if grid.contains(cell.map(|x| x + 1)) {
                    cells.push(cell);
                }
            }
        }
        cells.sort_unstable_by_key(|c| [c[2], c[1], c[0]]);
        cells.dedup();
        cells
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_edge_lies_on_the_faces_that_list_it() {
        let grid = Grid { dims: [4, 5, 3] };
        for n in 0..60 {
            let p = grid.index(n);
            assert_eq!(grid.linear(p), n);
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
                }
            }
        }
    }
}
