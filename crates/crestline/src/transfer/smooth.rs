//! Gaussian-weighted averages of values scattered in space, by splatting them
//! onto a regular grid of spacing σ/2, blurring the grid with a separable
//! Gaussian and reading it back by trilinear interpolation (the smoothing of
//! Thirion's demons, 1998, on scattered points).

use rayon::prelude::*;

use crate::{Error, Point, Result, Vector};

/// Gaussian kernel radius, in standard deviations.
const REACH: f64 = 3.0;

/// The most nodes a grid may have (its data take 32 bytes a node, twice).
const MAX_NODES: usize = 20_000_000;

/// An [`Error::Argument`] if the grid of [`smoothed`] over `points` at the
/// smoothing scale `sigma` would have more than [`MAX_NODES`] nodes (a scale
/// far too small for the points' extent, as when the scales are in millimetres
/// and the scans in metres).
pub(crate) fn check_grid<'a>(points: impl Iterator<Item = &'a Point>, sigma: f64) -> Result<()> {
    let grid = Grid::around(points, 0.5 * sigma, REACH * sigma);
    let nodes = grid.dims.iter().map(|&n| n as f64).product::<f64>();
    if nodes <= MAX_NODES as f64 {
        return Ok(());
    }
    let extent = grid.dims.iter().map(|&n| n as f64).fold(0.0, f64::max) * grid.spacing;
    Err(Error::Argument(format!(
        "the smoothing scale {sigma} is too small for lines {extent:.4} across (a grid of \
         {nodes:.2e} nodes); give scales in the scans' units, at least a hundredth of their size"
    )))
}

/// A box of grid cells: corner, spacing and the number of nodes along each axis.
struct Grid {
    origin: Point,
    spacing: f64,
    dims: [usize; 3],
}

impl Grid {
    /// A grid of spacing `spacing` over every point of `points`, with a margin.
    fn around<'a>(points: impl Iterator<Item = &'a Point>, spacing: f64, margin: f64) -> Grid {
        let (mut low, mut high) = (
            Vector::repeat(f64::INFINITY),
            Vector::repeat(f64::NEG_INFINITY),
        );
        for p in points {
            low = low.inf(&p.coords);
            high = high.sup(&p.coords);
        }
        let origin = Point::from(low - Vector::repeat(margin));
        let extent = high - low + Vector::repeat(2.0 * margin);
        let dims = [0, 1, 2].map(|axis| (extent[axis] / spacing).ceil() as usize + 2);
        Grid {
            origin,
            spacing,
            dims,
        }
    }

    /// The node below `p` and the fractions of the way to the next one, per axis.
    fn locate(&self, p: &Point) -> ([usize; 3], [f64; 3]) {
        let mut node = [0; 3];
        let mut fraction = [0.0; 3];
        for axis in 0..3 {
            let at = ((p[axis] - self.origin[axis]) / self.spacing)
                .clamp(0.0, (self.dims[axis] - 2) as f64);
            node[axis] = (at.floor() as usize).min(self.dims[axis] - 2);
            fraction[axis] = at - node[axis] as f64;
        }
        (node, fraction)
    }

    /// The eight nodes around `p` with their trilinear weights.
    fn corners(&self, p: &Point) -> impl Iterator<Item = (usize, f64)> {
        let ([x, y, z], [fx, fy, fz]) = self.locate(p);
        let [nx, ny, _] = self.dims;
        (0..8).map(move |corner: usize| {
            let (dx, dy, dz) = (corner & 1, (corner >> 1) & 1, corner >> 2);
            let weight = [1.0 - fx, fx][dx] * [1.0 - fy, fy][dy] * [1.0 - fz, fz][dz];
            ((x + dx) + nx * ((y + dy) + ny * (z + dz)), weight)
        })
    }

    /// `data` convolved along `axis` with the symmetric `kernel` (`kernel[k]` the
    /// weight at an offset of `k` nodes), zero outside the grid.
    fn blur<const C: usize>(
        &self,
        data: &[[f64; C]],
        axis: usize,
        kernel: &[f64],
    ) -> Vec<[f64; C]> {
        let [nx, ny, _] = self.dims;
        let stride = [1, nx, nx * ny][axis];
        let extent = self.dims[axis];
        let reach = kernel.len() - 1;
        let mut out = vec![[0.0; C]; data.len()];
        out.par_chunks_mut(nx * ny)
            .enumerate()
            .for_each(|(z, slice)| {
                for y in 0..ny {
                    for x in 0..nx {
                        let along = [x, y, z][axis];
                        let base = x + nx * (y + ny * z) - along * stride;
                        let mut sum = [0.0; C];
                        for at in along.saturating_sub(reach)..=(along + reach).min(extent - 1) {
                            let weight = kernel[at.abs_diff(along)];
                            let value = &data[base + at * stride];
                            for c in 0..C {
                                sum[c] += weight * value[c];
                            }
                        }
                        slice[x + nx * y] = sum;
                    }
                }
            });
        out
    }
}

/// At each point of `queries`, the Gaussian-weighted mean
/// `Σ G(x − sᵢ) vᵢ / (Σ G(x − sᵢ) + prior)` of the `values` `vᵢ` at the `sites`
/// `sᵢ`, G of standard deviation `sigma` and peak 1: a `prior` of 1 counts as one
/// site of value zero at every query, so that a query far from every site gets a
/// value near zero. Also returns the weight `Σ G` at each query. `sigma` is
/// positive.
pub(crate) fn smoothed<const C: usize>(
    sites: &[Point],
    values: &[[f64; C]],
    sigma: f64,
    prior: f64,
    queries: &[Point],
) -> Vec<([f64; C], f64)> {
    let spacing = 0.5 * sigma;
    let grid = Grid::around(sites.iter().chain(queries), spacing, REACH * sigma);
    let cells = grid.dims.iter().product();
    // Each node holds the weighted values and, last, the weight.
    let mut data = vec![[0.0; 4]; cells];
    assert!(C <= 3, "at most three values per site");
    for (site, value) in sites.iter().zip(values) {
        for (node, share) in grid.corners(site) {
            for c in 0..C {
                data[node][c] += share * value[c];
            }
            data[node][3] += share;
        }
    }
    let reach = (REACH * sigma / spacing).ceil() as usize;
    let kernel: Vec<f64> = (0..=reach)
        .map(|k| (-0.5 * (k as f64 * spacing / sigma).powi(2)).exp())
        .collect();
    for axis in 0..3 {
        data = grid.blur(&data, axis, &kernel);
    }
    queries
        .par_iter()
        .map(|q| {
            let mut sum = [0.0; 4];
            for (node, share) in grid.corners(q) {
                for c in 0..4 {
                    sum[c] += share * data[node][c];
                }
            }
            let mut mean = [0.0; C];
            for c in 0..C {
                mean[c] = sum[c] / (sum[3] + prior);
            }
            (mean, sum[3])
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_constant_is_kept_where_sites_are_dense() {
        let sites: Vec<Point> = (0..20)
            .flat_map(|i| (0..20).map(move |j| Point::new(i as f64, j as f64, 0.0)))
            .collect();
        let values = vec![[2.0, -1.0, 0.5]; sites.len()];
        let queries = [Point::new(9.5, 9.5, 0.0), Point::new(200.0, 0.0, 0.0)];
        let found = smoothed(&sites, &values, 3.0, 0.0, &queries);
        for (c, expected) in [2.0, -1.0, 0.5].into_iter().enumerate() {
            assert!((found[0].0[c] - expected).abs() < 1e-9, "{found:?}");
        }
        let damped = smoothed(&sites, &values, 3.0, 1.0, &queries);
        assert!(damped[0].0[0] < 2.0 && damped[0].0[0] > 1.9, "{damped:?}");
        // Far away there is no weight and, with a prior, no value.
        assert_eq!(damped[1].1, 0.0);
        assert_eq!(damped[1].0, [0.0; 3]);
    }

    #[test]
    fn one_site_spreads_as_a_gaussian() {
        let site = [Point::new(0.0, 0.0, 0.0)];
        let queries = [Point::new(0.0, 0.0, 0.0), Point::new(4.0, 0.0, 0.0)];
        let found = smoothed(&site, &[[1.0]], 4.0, 0.0, &queries);
        // Trilinear splatting and reading add a little blur to the Gaussian's.
        assert!((found[0].1 - 1.0).abs() < 0.1, "{found:?}");
        assert!((found[1].1 - (-0.5f64).exp()).abs() < 0.1, "{found:?}");
    }
}
