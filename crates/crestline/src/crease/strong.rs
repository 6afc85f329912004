//! Where a crease may be strong enough to keep: the side constraint λ3 < 0 with the
//! margin of the strength s (Schultz, Theisel and Seidel 2010, §4.5; docs/design/crease.md,
//! "Crease surfaces": skip cells where no corner has −λ3 ≥ s, then trim).
//!
//! λ3 is concave in the Hessian, and the Hessian is interpolated linearly between
//! the samples, so inside a cell −λ3 stays below its largest corner value: a cell
//! with no corner as strong as s holds no point of the surface that is kept. The
//! surface is built in the other cells from crossings of any strength (λ3 < 0),
//! so that the strength never leaves a face crossed an odd number of times, and is
//! then trimmed along −λ3 = s (see `surface.rs`).

use super::field::CreaseField;
use crate::volume::grid::Grid;
use crate::volume::voxel_set::{VoxelSet, VoxelSetBuilder};

/// The samples at least as strong as the strength, and the cells, faces and edges
/// around them.
pub(crate) struct StrongCells {
    grid: Grid,
    /// The samples where −λ3 ≥ s.
    strong: VoxelSet,
}

impl StrongCells {
    /// The samples of `field` where −λ3 is at least `strength`.
    pub fn new(field: &CreaseField, strength: f64) -> StrongCells {
        let grid = field.grid();
        let strong = VoxelSetBuilder::from_fn(grid.sample_count(), |n| {
            -field.sample(grid.position_of(n)).frame.eigenvalues[2] >= strength
        })
        .build();
        StrongCells { grid, strong }
    }

    /// Whether a sample is at least as strong as the strength.
    fn sample(&self, index: [usize; 3]) -> bool {
        self.strong.contains(self.grid.index(index))
    }

    /// Whether the cell with lowest corner `cell` (inside the grid) has a strong
    /// corner.
    pub fn cell(&self, cell: [usize; 3]) -> bool {
        self.grid
            .corners(cell)
            .iter()
            .any(|&at| self.strong.contains(at))
    }

    /// Whether one of the (up to four) cells around grid edge `key` is strong.
    pub fn edge(&self, key: u64) -> bool {
        self.grid.edge_cells(key).any(|cell| self.cell(cell))
    }

    /// Whether one of the (up to two) cells of face `face` (`3 · lowest corner +
    /// normal axis`) is strong.
    pub fn face(&self, face: u64) -> bool {
        self.grid.face_cells(face).any(|cell| self.cell(cell))
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
