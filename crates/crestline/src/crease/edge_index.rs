//! The crossings of each grid edge looked up by its key (`3 · point + axis`, see
//! [`crate::volume::grid`]), and the cells around the crossed edges.

use std::collections::HashMap;

use super::edges::EdgeCrossing;
use crate::volume::grid::Grid;

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
        let mut cells: Vec<[usize; 3]> = self
            .ranges
            .keys()
            .flat_map(|&edge| grid.edge_cells(edge))
            .collect();
        cells.sort_unstable_by_key(|c| [c[2], c[1], c[0]]);
        cells.dedup();
        cells
    }
}
