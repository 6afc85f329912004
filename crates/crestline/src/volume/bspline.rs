//! The cubic B-spline through the samples of a volume: a C² function that takes
//! exactly the sample values at the grid points, for evaluation and
//! differentiation between samples without smoothing.
//!
//! Where Thirion & Gourdon (1993) obtain a differentiable image by Gaussian
//! smoothing, this is the interpolating alternative. The spline is
//! `f(u) = Σ c[n] β³(u − n)` over the index space `u`, with coefficients `c`
//! obtained by the standard recursive prefilter (causal then anticausal, pole
//! `z = √3 − 2`, gain 6) along each axis, with mirror (whole-sample symmetric)
//! boundaries: `s[−k] = s[k]`, `s[n − 1 + k] = s[n − 1 − k]`. It reproduces
//! polynomials of degree ≤ 3 exactly away from the border (the effect of the
//! mirror boundary decays by a factor `|z| ≈ 0.27` per voxel). Its third
//! derivatives exist inside each cell but jump across cell faces. The coefficients
//! are stored as `f32`, like the samples (the recursion runs in `f64`).

use super::derivatives::Partial;
use super::grid::Grid;
use super::jet::Jet;
use super::trilinear::on_axis;
use super::Volume;
use crate::{Point, Vector};
use nalgebra::Matrix3;
use rayon::prelude::*;

/// The pole of the cubic B-spline prefilter, `√3 − 2`.
const POLE: f64 = -0.267_949_192_431_122_7;

/// Width (samples along x) of the bundles of z lines prefiltered together.
const Z_BUNDLE: usize = 64;

/// A cubic B-spline interpolating a volume, with its placement in the world.
#[derive(Clone, Debug)]
pub struct BSpline {
    dims: [usize; 3],
    coefficients: Vec<f32>,
    origin: Point,
    /// `∂index / ∂world`: column `i` is the change of the index per unit of world
    /// coordinate `i`.
    world_to_index: Matrix3<f64>,
}

impl BSpline {
    /// The interpolating spline of `volume`: its samples prefiltered along x, y and z
    /// (in parallel over lines).
    pub fn new(volume: &Volume) -> BSpline {
        let grid = volume.grid();
        let mut coefficients = volume.samples().to_vec();
        prefilter_x(&mut coefficients, grid);
        prefilter_y(&mut coefficients, grid);
        prefilter_z(&mut coefficients, grid);
        let origin = Point::from(volume.origin());
        let at_origin = Vector::from(volume.world_to_index(&origin));
        let world_to_index = Matrix3::from_fn(|row, col| {
            let step = origin + Vector::ith(col, 1.0);
            volume.world_to_index(&step)[row] - at_origin[row]
        });
        BSpline {
            dims: grid.dims,
            coefficients,
            origin,
            world_to_index,
        }
    }

    /// The value at the (fractional) voxel index `index`, or `None` outside the
    /// grid (`0 ≤ index[a] ≤ dims[a] − 1`).
    #[cfg(test)]
    pub fn value_at_index(&self, index: [f64; 3]) -> Option<f64> {
        self.partials(index, 0).map(|p| p[0])
    }

    /// The value at world position `point`, or `None` outside the grid.
    #[cfg(test)]
    pub fn value_at_world(&self, point: &Point) -> Option<f64> {
        self.value_at_index(self.index_of(point))
    }

    /// Value and world-space derivatives up to order 3 at the (fractional) voxel
    /// index `index`, or `None` outside the grid. On a cell face the third
    /// derivatives are those of the cell on the side of higher indices.
    pub fn jet_at_index(&self, index: [f64; 3]) -> Option<Jet> {
        let local = Jet::from_partials(&self.partials(index, 3)?);
        Some(local.pulled_back(&self.world_to_index))
    }

    /// Value and world-space derivatives up to order 3 at world position `point`, or
    /// `None` outside the grid.
    pub fn jet_at_world(&self, point: &Point) -> Option<Jet> {
        self.jet_at_index(self.index_of(point))
    }

    /// The fractional voxel index of world position `point`.
    fn index_of(&self, point: &Point) -> [f64; 3] {
        (self.world_to_index * (point - self.origin)).into()
    }

    /// The partials of [`Partial::ALL`] with respect to the index, those above
    /// `max_order` left at zero.
    fn partials(&self, index: [f64; 3], max_order: usize) -> Option<[f64; 20]> {
        let axes = [0, 1, 2].map(|a| AxisWeights::at(index[a], self.dims[a]));
        let [x, y, z] = [axes[0].as_ref()?, axes[1].as_ref()?, axes[2].as_ref()?];
        let grid = Grid { dims: self.dims };
        let mut sums = [0.0; 20];
        for (k, &zk) in z.nodes.iter().enumerate() {
            for (j, &yj) in y.nodes.iter().enumerate() {
                let row = grid.index([0, yj, zk]);
                for (i, &xi) in x.nodes.iter().enumerate() {
                    let c = f64::from(self.coefficients[row + xi]);
                    for (sum, p) in sums.iter_mut().zip(Partial::ALL) {
                        let [a, b, d] = p.orders();
                        if p.order() <= max_order {
                            *sum += c * x.weights[a][i] * y.weights[b][j] * z.weights[d][k];
                        }
                    }
                }
            }
        }
        Some(sums)
    }
}

/// The four grid nodes around a coordinate along one axis (mirrored into the grid)
/// and the B-spline weights of orders 0 to 3 for each.
struct AxisWeights {
    nodes: [usize; 4],
    weights: [[f64; 4]; 4],
}

impl AxisWeights {
    /// The nodes and weights at coordinate `u` along an axis of `n` samples, or
    /// `None` further than [`INDEX_TOLERANCE`](super::trilinear::INDEX_TOLERANCE)
    /// outside `[0, n − 1]` (nearer, `u` is taken at the border).
    fn at(u: f64, n: usize) -> Option<AxisWeights> {
        let u = on_axis(u, n)?;
        let cell = u.floor();
        let t = u - cell;
        let s = 1.0 - t;
        let base = cell as isize - 1;
        Some(AxisWeights {
            nodes: [0, 1, 2, 3].map(|m| mirror(base + m, n)),
            weights: [
                [
                    s * s * s / 6.0,
                    (3.0 * t * t * t - 6.0 * t * t + 4.0) / 6.0,
                    (-3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0) / 6.0,
                    t * t * t / 6.0,
                ],
                [
                    -s * s / 2.0,
                    1.5 * t * t - 2.0 * t,
                    -1.5 * t * t + t + 0.5,
                    t * t / 2.0,
                ],
                [s, 3.0 * t - 2.0, 1.0 - 3.0 * t, t],
                [-1.0, 3.0, -3.0, 1.0],
            ],
        })
    }
}

/// Index `i` mirrored (whole-sample symmetric) into `0..n`.
fn mirror(i: isize, n: usize) -> usize {
    if n == 1 {
        return 0;
    }
    let period = 2 * (n as isize - 1);
    let m = i.rem_euclid(period);
    (if m >= n as isize { period - m } else { m }) as usize
}

/// Prefilters every x line.
fn prefilter_x(samples: &mut [f32], grid: Grid) {
    samples.par_chunks_mut(grid.dims[0]).for_each(|line| {
        let mut buffer: Vec<f64> = line.iter().map(|&v| f64::from(v)).collect();
        prefilter_line(&mut buffer);
        for (out, value) in line.iter_mut().zip(buffer) {
            *out = value as f32;
        }
    });
}

/// Prefilters every y line, in parallel over z slices.
fn prefilter_y(samples: &mut [f32], grid: Grid) {
    samples.par_chunks_mut(grid.plane_len()).for_each(|slice| {
        let mut rows: Vec<&mut [f32]> = slice.chunks_mut(grid.dims[0]).collect();
        prefilter_across(&mut rows);
    });
}

/// Prefilters every z line, in parallel over bundles of [`Z_BUNDLE`] x positions.
fn prefilter_z(samples: &mut [f32], grid: Grid) {
    let slice_len = grid.plane_len();
    let bundles = slice_len.div_ceil(Z_BUNDLE);
    let mut by_bundle: Vec<Vec<&mut [f32]>> = (0..bundles).map(|_| Vec::new()).collect();
    for slice in samples.chunks_mut(slice_len) {
        for (rows, chunk) in by_bundle.iter_mut().zip(slice.chunks_mut(Z_BUNDLE)) {
            rows.push(chunk);
        }
    }
    by_bundle
        .par_iter_mut()
        .for_each(|rows| prefilter_across(rows));
}

/// Prefilters the lines that run across `rows` (line `i` is `rows[n][i]` for every
/// `n`).
fn prefilter_across(rows: &mut [&mut [f32]]) {
    let width = rows.first().map_or(0, |r| r.len());
    let mut buffer = vec![0.0; rows.len()];
    for i in 0..width {
        for (value, row) in buffer.iter_mut().zip(rows.iter()) {
            *value = f64::from(row[i]);
        }
        prefilter_line(&mut buffer);
        for (value, row) in buffer.iter().zip(rows.iter_mut()) {
            row[i] = *value as f32;
        }
    }
}

/// Turns samples into cubic B-spline coefficients in place: gain 6, causal
/// recursion `c⁺[n] = s[n] + z c⁺[n − 1]`, anticausal `c[n] = z (c[n + 1] − c⁺[n])`,
/// with initial values for mirror boundaries (Unser 1999; Thévenaz et al. 2000).
fn prefilter_line(line: &mut [f64]) {
    let n = line.len();
    if n < 2 {
        return;
    }
    line.iter_mut()
        .for_each(|v| *v *= (1.0 - POLE) * (1.0 - 1.0 / POLE));
    line[0] = initial_causal(line);
    for k in 1..n {
        line[k] += POLE * line[k - 1];
    }
    line[n - 1] = POLE / (POLE * POLE - 1.0) * (POLE * line[n - 2] + line[n - 1]);
    for k in (0..n - 1).rev() {
        line[k] = POLE * (line[k + 1] - line[k]);
    }
}

/// `c⁺[0] = Σ_k z^|k| s[k]` over the mirrored, infinite line: truncated where `z^k`
/// is negligible, exact (summed over one period) on short lines.
fn initial_causal(line: &[f64]) -> f64 {
    let n = line.len();
    let horizon = (f64::EPSILON.ln() / POLE.abs().ln()).ceil() as usize;
    if horizon < n {
        let mut power = 1.0;
        return line[..horizon]
            .iter()
            .map(|&s| {
                let term = power * s;
                power *= POLE;
                term
            })
            .sum();
    }
    // Over one period 2n − 2 of the mirrored line, then the geometric series.
    let period = 2 * (n - 1);
    let sum: f64 = (0..period)
        .map(|k| POLE.powi(k as i32) * line[mirror(k as isize, n)])
        .sum();
    sum / (1.0 - POLE.powi(period as i32))
}
