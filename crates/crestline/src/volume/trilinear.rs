//! Trilinear interpolation on the grid: the cell a point lies in, and the weights of
//! its eight corners. Corner `c` of a cell is offset by `(c & 1, c >> 1 & 1, c >> 2
//! & 1)` from its lowest corner.

use super::grid::{cell_corner, corner_offset, Grid};

/// How far (in voxels) outside the grid a point still counts as on it, so that
/// round-off in a world-to-index conversion does not lose it.
pub const INDEX_TOLERANCE: f64 = 1e-6;

/// The coordinate `u` along an axis of `n` samples clamped into `[0, n − 1]`, or
/// `None` if it lies further than [`INDEX_TOLERANCE`] outside (or is NaN).
pub(crate) fn on_axis(u: f64, n: usize) -> Option<f64> {
    let last = (n - 1) as f64;
    (u >= -INDEX_TOLERANCE && u <= last + INDEX_TOLERANCE).then(|| u.clamp(0.0, last))
}

/// The linear indices (x fastest) of the eight corners of the cell holding the
/// fractional voxel `index` of a grid of `dims` samples, and their trilinear
/// weights; `None` outside the grid. On an axis with a single sample both corners
/// are that sample.
pub fn corners_and_weights(dims: [usize; 3], index: [f64; 3]) -> Option<([usize; 8], [f64; 8])> {
    let mut u = [0.0; 3];
    for axis in 0..3 {
        u[axis] = on_axis(index[axis], dims[axis])?;
    }
    let grid = Grid { dims };
    let base = grid.cell_holding(u);
    let local = std::array::from_fn(|a| u[a] - base[a] as f64);
    let corners = std::array::from_fn(|c| {
        let corner = cell_corner(base, c);
        grid.index(std::array::from_fn(|a| corner[a].min(dims[a] - 1)))
    });
    Some((corners, weights(local)))
}

/// The trilinear weights of the eight corners at cell coordinates `u` (each in
/// `[0, 1]`).
pub fn weights(u: [f64; 3]) -> [f64; 8] {
    std::array::from_fn(|c| (0..3).map(|a| factor(u, c, a)).product())
}

/// The derivatives of [`weights`] along each index axis.
pub fn weight_derivatives(u: [f64; 3]) -> [[f64; 8]; 3] {
    let slope = |c: usize, a: usize| if corner_offset(c)[a] == 1 { 1.0 } else { -1.0 };
    std::array::from_fn(|axis| {
        std::array::from_fn(|c| {
            (0..3)
                .map(|a| {
                    if a == axis {
                        slope(c, a)
                    } else {
                        factor(u, c, a)
                    }
                })
                .product()
        })
    })
}

/// Corner `c`'s linear factor along axis `a`.
fn factor(u: [f64; 3], c: usize, a: usize) -> f64 {
    if corner_offset(c)[a] == 1 {
        u[a]
    } else {
        1.0 - u[a]
    }
}
