//! Trilinear interpolation on the grid: the cell a point lies in, and the weights of
//! its eight corners. Corner `c` of a cell is offset by `(c & 1, c >> 1 & 1, c >> 2
//! & 1)` from its lowest corner.

/// How far (in voxels) outside the grid a point still counts as on it, so that
/// round-off in a world-to-index conversion does not lose it.
pub const INDEX_TOLERANCE: f64 = 1e-6;

/// The linear indices (x fastest) of the eight corners of the cell holding the
/// fractional voxel `index` of a grid of `dims` samples, and their trilinear
/// weights; `None` outside the grid. On an axis with a single sample both corners
/// are that sample.
pub fn corners_and_weights(dims: [usize; 3], index: [f64; 3]) -> Option<([usize; 8], [f64; 8])> {
    let mut base = [0usize; 3];
    let mut local = [0.0; 3];
    for axis in 0..3 {
        let last = (dims[axis] - 1) as f64;
        let u = index[axis];
        if !(u >= -INDEX_TOLERANCE && u <= last + INDEX_TOLERANCE) {
            return None;
        }
        let u = u.clamp(0.0, last);
        base[axis] = (u.floor() as usize).min(dims[axis].saturating_sub(2));
        local[axis] = u - base[axis] as f64;
    }
    let corners = std::array::from_fn(|c| {
        let at: [usize; 3] = std::array::from_fn(|a| (base[a] + ((c >> a) & 1)).min(dims[a] - 1));
        at[0] + dims[0] * (at[1] + dims[1] * at[2])
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
    let slope = |c: usize, a: usize| if (c >> a) & 1 == 1 { 1.0 } else { -1.0 };
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
    if (c >> a) & 1 == 1 {
        u[a]
    } else {
        1.0 - u[a]
    }
}
