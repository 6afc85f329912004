//! Separable filtering of a volume by 1-D kernels of several orders along each axis,
//! sharing the 1-D passes between the outputs that need them.
//!
//! Every z slice is computed on its own, in parallel: z passes of the input (once
//! per z order needed) into slice buffers, x passes of those (once per x order
//! needed with that z order) into other slice buffers, and y passes from these into
//! the output slices. For all 20 partials of order ≤ 3 this is 4 + 10 + 20 = 34
//! passes instead of 60, and nothing but the outputs is allocated per volume.
//!
//! Every pass is a correlation of whole rows (runs of `nx` contiguous samples): along
//! x the rows are shifted copies of one padded line, along y and z they are other
//! rows of the slice or volume, so that every inner loop runs over contiguous memory.
//! Symmetric and antisymmetric kernels add or subtract the two rows at `±t` before
//! weighting them. Borders are clamped to the edge (the nearest sample is repeated).

use std::ops::Range;

use rayon::prelude::*;

use super::grid::Grid;

/// The weights of a (anti)symmetric 1-D kernel at offsets `0..=R`.
#[derive(Clone, Debug)]
pub(crate) struct HalfKernel {
    /// `c[t]` for `t = 0..=R`.
    pub taps: Vec<f32>,
    /// Whether `c[−t] = −c[t]` (otherwise `c[−t] = c[t]`).
    pub odd: bool,
}

/// The kernels of orders 0 to 3 along one axis, indexed by order.
pub(crate) type AxisKernels = Vec<HalfKernel>;

/// Filters the z slices `slices` of `samples` (on `grid`, x fastest) into one
/// block of those slices per entry of `orders`, `[x, y, z]` orders each, with
/// `kernels[axis][order]`, in parallel over z slices. Every slice is computed from
/// the samples alone, so a block holds exactly the slices of the whole filtered
/// volume.
pub(crate) fn filter(
    samples: &[f32],
    grid: Grid,
    kernels: &[AxisKernels; 3],
    orders: &[[usize; 3]],
    slices: Range<usize>,
) -> Vec<Vec<f32>> {
    let z_orders = distinct(orders.iter().map(|o| o[2]));
    let z_kernels: Vec<&HalfKernel> = z_orders.iter().map(|&c| &kernels[2][c]).collect();
    let len = grid.plane_len() * slices.len();
    let mut outputs: Vec<Vec<f32>> = orders.iter().map(|_| vec![0.0; len]).collect();
    slices_by_k(&mut outputs, grid.plane_len())
        .into_par_iter()
        .enumerate()
        .for_each_init(Scratch::default, |scratch, (n, mut out_slices)| {
            let z_passes = scratch.z.take(z_orders.len(), grid.plane_len());
            z_slice(samples, grid, slices.start + n, &z_kernels, z_passes);
            for (z_pass, &c) in z_passes.iter().zip(&z_orders) {
                let x_passes = &mut scratch.x;
                finish_slice(z_pass, grid, kernels, orders, c, x_passes, &mut out_slices);
            }
        });
    outputs
}

/// Slice buffers reused from one z slice to the next by a thread.
#[derive(Default)]
struct Scratch {
    /// The z pass of the slice, one buffer per z order.
    z: Buffers,
    /// The x passes of one z pass, one buffer per x order.
    x: Buffers,
}

/// A set of equally long buffers.
#[derive(Default)]
struct Buffers(Vec<Vec<f32>>);

impl Buffers {
    /// `count` buffers of length `len` (contents unspecified).
    fn take(&mut self, count: usize, len: usize) -> &mut [Vec<f32>] {
        if self.0.len() < count {
            self.0.resize_with(count, Vec::new);
        }
        for buffer in &mut self.0[..count] {
            buffer.resize(len, 0.0);
        }
        &mut self.0[..count]
    }
}

/// The z passes of slice `k`, one per kernel, into `outputs`.
fn z_slice(
    samples: &[f32],
    grid: Grid,
    k: usize,
    kernels: &[&HalfKernel],
    outputs: &mut [Vec<f32>],
) {
    let [nx, ny, nz] = grid.dims;
    let mut targets: Vec<&mut [f32]> = outputs.iter_mut().map(|o| o.as_mut_slice()).collect();
    for j in 0..ny {
        let row = |t: isize| {
            let at = grid.index([0, j, clamp(k as isize + t, nz)]);
            &samples[at..at + nx]
        };
        correlate_rows(&mut targets, grid.index([0, j, 0]), kernels, row);
    }
}

/// The x and y passes of one z slice already filtered with z order `c`, into the
/// slices of the outputs whose z order is `c`.
fn finish_slice(
    source: &[f32],
    grid: Grid,
    kernels: &[AxisKernels; 3],
    orders: &[[usize; 3]],
    c: usize,
    scratch: &mut Buffers,
    out_slices: &mut [&mut [f32]],
) {
    let x_orders = distinct(orders.iter().filter(|o| o[2] == c).map(|o| o[0]));
    let x_kernels: Vec<&HalfKernel> = x_orders.iter().map(|&a| &kernels[0][a]).collect();
    let x_passes = scratch.take(x_orders.len(), source.len());
    x_pass(source, grid, &x_kernels, x_passes);
    for (x_pass, &a) in x_passes.iter().zip(&x_orders) {
        let mut targets: Vec<&mut [f32]> = Vec::new();
        let mut y_kernels: Vec<&HalfKernel> = Vec::new();
        for (slice, order) in out_slices.iter_mut().zip(orders) {
            if order[0] == a && order[2] == c {
                targets.push(slice);
                y_kernels.push(&kernels[1][order[1]]);
            }
        }
        y_pass(x_pass, grid, &y_kernels, &mut targets);
    }
}

/// Correlates every x line of `slice` with each kernel, into `outputs`.
fn x_pass(slice: &[f32], grid: Grid, kernels: &[&HalfKernel], outputs: &mut [Vec<f32>]) {
    let nx = grid.dims[0];
    let radius = max_radius(kernels);
    let mut padded = vec![0.0; nx + 2 * radius];
    let mut targets: Vec<&mut [f32]> = outputs.iter_mut().map(|o| o.as_mut_slice()).collect();
    for (j, line) in slice.chunks_exact(nx).enumerate() {
        pad_clamped(line, radius, &mut padded);
        let row = |t: isize| &padded[(radius as isize + t) as usize..][..nx];
        correlate_rows(&mut targets, grid.index([0, j, 0]), kernels, row);
    }
}

/// Correlates every y column of the x-filtered `slice` with each kernel, into
/// `targets` (slices of the outputs).
fn y_pass(slice: &[f32], grid: Grid, kernels: &[&HalfKernel], targets: &mut [&mut [f32]]) {
    let [nx, ny, _] = grid.dims;
    for j in 0..ny {
        let row = |t: isize| {
            let at = grid.index([0, clamp(j as isize + t, ny), 0]);
            &slice[at..at + nx]
        };
        correlate_rows(targets, grid.index([0, j, 0]), kernels, row);
    }
}

/// Writes into `targets[n][at..at + len]` the correlation of kernel `n` with the
/// rows `row(t)` (each `len` long), for every `n`.
fn correlate_rows<'a>(
    targets: &mut [&mut [f32]],
    at: usize,
    kernels: &[&HalfKernel],
    row: impl Fn(isize) -> &'a [f32],
) {
    let center = row(0);
    let len = center.len();
    for (target, kernel) in targets.iter_mut().zip(kernels) {
        let w = kernel.taps[0];
        for (out, &value) in target[at..at + len].iter_mut().zip(center) {
            *out = w * value;
        }
    }
    for t in 1..=max_radius(kernels) {
        let (plus, minus) = (row(t as isize), row(-(t as isize)));
        for (target, kernel) in targets.iter_mut().zip(kernels) {
            if let Some(&w) = kernel.taps.get(t) {
                accumulate(&mut target[at..at + len], w, plus, minus, kernel.odd);
            }
        }
    }
}

/// `out += w (plus − minus)` if `odd`, else `out += w (plus + minus)`.
fn accumulate(out: &mut [f32], w: f32, plus: &[f32], minus: &[f32], odd: bool) {
    let terms = out.iter_mut().zip(plus.iter().zip(minus));
    if odd {
        terms.for_each(|(o, (&p, &m))| *o += w * (p - m));
    } else {
        terms.for_each(|(o, (&p, &m))| *o += w * (p + m));
    }
}

/// `line` with `radius` copies of its first and last sample on either side.
fn pad_clamped(line: &[f32], radius: usize, padded: &mut [f32]) {
    let (first, last) = (line[0], line[line.len() - 1]);
    padded[..radius].fill(first);
    padded[radius..radius + line.len()].copy_from_slice(line);
    padded[radius + line.len()..].fill(last);
}

/// `at` clamped into `0..n`.
fn clamp(at: isize, n: usize) -> usize {
    at.clamp(0, n as isize - 1) as usize
}

/// The largest radius among `kernels`.
fn max_radius(kernels: &[&HalfKernel]) -> usize {
    kernels.iter().map(|k| k.taps.len() - 1).max().unwrap_or(0)
}

/// The distinct values, in increasing order.
fn distinct(values: impl Iterator<Item = usize>) -> Vec<usize> {
    let mut values: Vec<usize> = values.collect();
    values.sort_unstable();
    values.dedup();
    values
}

/// For every z slice `n` of the blocks, the `n`-th slice of each block.
fn slices_by_k(volumes: &mut [Vec<f32>], slice_len: usize) -> Vec<Vec<&mut [f32]>> {
    let nz = volumes.first().map_or(0, |v| v.len() / slice_len);
    let mut by_k: Vec<Vec<&mut [f32]>> =
        (0..nz).map(|_| Vec::with_capacity(volumes.len())).collect();
    for volume in volumes.iter_mut() {
        for (slices, chunk) in by_k.iter_mut().zip(volume.chunks_mut(slice_len)) {
            slices.push(chunk);
        }
    }
    by_k
}
