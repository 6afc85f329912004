//! Where a crease may be strong enough to keep: the side constraint λ3 < 0 with the
//! margin of the strength s (Schultz, Theisel and Seidel 2010, §4.5; docs/design.md,
//! "Crease surfaces": skip cells where no corner has −λ3 ≥ s, then trim).
//!
//! λ3 is concave in the Hessian, and the Hessian is interpolated linearly between
//! the samples, so inside a cell −λ3 stays below its largest corner value: a cell
//! with no corner as strong as s holds no point of the surface that is kept. The
//! surface is built in the other cells from crossings of any strength (λ3 < 0),
//! so that the strength never leaves a face crossed an odd number of times, and is
//! then trimmed along −λ3 = s (see `surface.rs`).

use rayon::prelude::*;

use super::field::CreaseField;
use super::grid::{in_face_axes, Grid};

/// The samples at least as strong as the strength, and the cells, faces and edges
/// around them.
pub(crate) struct StrongCells {
    grid: Grid,
    /// Per sample: −λ3 ≥ s.
    strong: Vec<bool>,
}

impl StrongCells {
    /// The samples of `field` where −λ3 is at least `strength`.
    pub fn new(field: &CreaseField, strength: f64) -> StrongCells {
        let grid = Grid { dims: field.dims() };
        let count = grid.dims.iter().product::<usize>();
        let strong = (0..count)
            .into_par_iter()
            .map(|n| -field.sample(grid.index(n)).frame.eigenvalues[2] >= strength)
            .collect();
        StrongCells { grid, strong }
    }

    /// Whether a sample is at least as strong as the strength.
    pub fn sample(&self, index: [usize; 3]) -> bool {
        self.strong[self.grid.linear(index)]
    }

    /// Whether the cell with lowest corner `cell` (inside the grid) has a strong
    /// corner.
    pub fn cell(&self, cell: [usize; 3]) -> bool {
        (0..8).any(|c| self.sample([0, 1, 2].map(|a| cell[a] + ((c >> a) & 1))))
    }

    /// Whether a cell of the grid with lowest corner `cell` exists and is strong.
    fn existing_cell(&self, cell: [Option<usize>; 3]) -> bool {
        let dims = self.grid.dims;
        let inside = |a: usize| cell[a].filter(|&c| c + 1 < dims[a]);
        match [inside(0), inside(1), inside(2)] {
            [Some(i), Some(j), Some(k)] => self.cell([i, j, k]),
            _ => false,
        }
    }

    /// Whether one of the (up to four) cells around grid edge `key` is strong.
    pub fn edge(&self, key: u64) -> bool {
        let (point, axis) = self.grid.unkey(key);
        let (u, v) = in_face_axes(axis);
        [(0, 0), (1, 0), (0, 1), (1, 1)]
            .into_iter()
            .any(|(du, dv)| {
                let mut cell = point.map(Some);
                cell[u] = point[u].checked_sub(du);
                cell[v] = point[v].checked_sub(dv);
                self.existing_cell(cell)
            })
    }

    /// Whether one of the (up to two) cells of face `face` (`3 · lowest corner +
    /// normal axis`) is strong.
    pub fn face(&self, face: u64) -> bool {
        let (low, axis) = self.grid.unkey(face);
        [0, 1].into_iter().any(|below| {
            let mut cell = low.map(Some);
            cell[axis] = low[axis].checked_sub(below);
            self.existing_cell(cell)
        })
    }

    /// Whether a corner of face `face` is strong.
    pub fn face_corner(&self, face: u64) -> bool {
        let (low, axis) = self.grid.unkey(face);
        self.grid
            .face_corners(low, axis)
            .into_iter()
            .any(|c| self.sample(c))
    }
}
