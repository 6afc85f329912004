//! A depth buffer of the mesh: the nearest surface depth at every pixel, rasterized
//! from the triangles (front and back faces alike) in parallel bands.
//!
//! Bounded work: a triangle costs the buffer pixels of its (clipped) bounding box.
//! On a mesh with scrambled connectivity every triangle can span the canvas, so a
//! triangle may cover at most max([`MIN_TRIANGLE_PIXELS`],
//! [`WORK_PER_PIXEL`] × buffer pixels / triangles) pixels; a larger one is
//! rasterized into a coarser level of the buffer (each level halves the
//! resolution), as few levels down as bring it under the cap. The whole buffer
//! then costs at most about [`WORK_PER_PIXEL`] passes over its pixels plus
//! [`MIN_TRIANGLE_PIXELS`] per triangle. On an ordinary mesh no triangle reaches
//! the cap and only the full-resolution level exists; a coarse level decides
//! visibility near its triangles' edges to within one of its pixels.

use rayon::prelude::*;

use crate::mesh::Mesh;

use super::camera::{Camera, ScreenPoint};

/// Rows of buffer pixels rasterized together by one task.
const BAND_ROWS: usize = 32;

/// The longest side of a depth buffer, in pixels (bounds memory at 256 MB).
const MAX_BUFFER_SIDE: f64 = 8192.0;

/// Buffer pixels any triangle may cover at full resolution, however many there are.
const MIN_TRIANGLE_PIXELS: f64 = 1024.0;

/// The budget of rasterized pixels per buffer pixel, shared by the triangles.
const WORK_PER_PIXEL: f64 = 16.0;

/// The nearest surface depth per pixel, on a grid `resolution` times finer than the
/// canvas; pixels the mesh does not cover hold +∞.
#[derive(Clone, Debug)]
pub struct DepthBuffer {
    /// Buffer pixels per canvas pixel.
    resolution: f64,
    /// Level `l` has pixels 2^l buffer pixels wide; level 0 always exists.
    levels: Vec<Grid>,
    /// The mesh's mean edge length: the unit of depth tolerances.
    edge_length: f64,
}

/// One level of the buffer: depths on a grid of `width` × `height` pixels.
#[derive(Clone, Debug)]
struct Grid {
    width: usize,
    height: usize,
    depth: Vec<f32>,
}

impl DepthBuffer {
    /// Rasterize `mesh` as seen by `camera`, `supersampling` buffer pixels per canvas
    /// pixel along each axis (reduced if the buffer would exceed 8192 pixels a side).
    /// Triangles with a corner behind a perspective camera's eye are left out;
    /// triangles too large for the work cap go to coarser levels (module docs).
    pub fn render(mesh: &Mesh, camera: &Camera, supersampling: u32) -> DepthBuffer {
        let longest = f64::from(camera.width().max(camera.height()));
        let resolution = f64::from(supersampling.max(1)).min(MAX_BUFFER_SIDE / longest);
        let width = (f64::from(camera.width()) * resolution).ceil() as usize;
        let height = (f64::from(camera.height()) * resolution).ceil() as usize;
        let corners: Vec<Option<ScreenPoint>> = mesh
            .positions()
            .par_iter()
            .map(|p| {
                camera.project(p).map(|s| ScreenPoint {
                    x: s.x * resolution,
                    y: s.y * resolution,
                    depth: camera.linear_depth(s.depth),
                })
            })
            .collect();
        let triangles: Vec<[ScreenPoint; 3]> = mesh
            .faces()
            .filter_map(|f| {
                let [a, b, c] = mesh.face_vertices(f).map(|v| corners[v.idx()]);
                Some([a?, b?, c?])
            })
            .collect();
        let cap = MIN_TRIANGLE_PIXELS
            .max(WORK_PER_PIXEL * (width * height) as f64 / triangles.len().max(1) as f64);
        let level_of: Vec<usize> = triangles
            .par_iter()
            .map(|t| level(t, width, height, cap))
            .collect();
        let level_count = level_of.iter().max().map_or(1, |&l| l + 1);
        let levels = (0..level_count)
            .map(|l| {
                let shrink = (1u64 << l) as f64;
                let members: Vec<[ScreenPoint; 3]> = triangles
                    .iter()
                    .zip(&level_of)
                    .filter(|&(_, &at)| at == l)
                    .map(|(t, _)| {
                        t.map(|p| ScreenPoint {
                            x: p.x / shrink,
                            y: p.y / shrink,
                            ..p
                        })
                    })
                    .collect();
                let size = |n: usize| (n as f64 / shrink).ceil() as usize;
                Grid::render(&members, size(width), size(height), camera)
            })
            .collect();
        DepthBuffer {
            resolution,
            levels,
            edge_length: mesh.mean_edge_length(),
        }
    }

    /// The mesh's mean edge length, the unit of depth tolerances.
    pub fn edge_length(&self) -> f64 {
        self.edge_length
    }

    /// Whether a surface point seen at `point` is visible: its depth is at most
    /// `tolerance` (mesh units) behind the farthest buffer depth among the 3 × 3
    /// buffer pixels around it (in every level; the nearest of the levels counts).
    /// Taking the farthest of the neighbourhood absorbs the change of depth across a
    /// pixel, however steep the surface, so lines lying on the surface are never
    /// hidden by the surface itself.
    pub fn is_visible(&self, point: &ScreenPoint, tolerance: f64) -> bool {
        let (bx, by) = (point.x * self.resolution, point.y * self.resolution);
        let nearest = self
            .levels
            .iter()
            .enumerate()
            .map(|(l, grid)| {
                let shrink = (1u64 << l) as f64;
                grid.farthest_around(bx / shrink, by / shrink)
            })
            .fold(f32::INFINITY, f32::min);
        point.depth <= f64::from(nearest) + tolerance
    }
}

impl Grid {
    /// Rasterize `triangles` (in this grid's pixel coordinates) into a grid of
    /// `width` × `height` pixels.
    fn render(
        triangles: &[[ScreenPoint; 3]],
        width: usize,
        height: usize,
        camera: &Camera,
    ) -> Grid {
        let bands = bin_by_band(triangles, height);
        let mut depth = vec![f32::INFINITY; width * height];
        depth
            .par_chunks_mut(width * BAND_ROWS)
            .zip(bands.par_iter())
            .enumerate()
            .for_each(|(band, (rows, members))| {
                let first_row = band * BAND_ROWS;
                for &t in members {
                    fill_triangle(rows, width, first_row, &triangles[t as usize], camera);
                }
            });
        Grid {
            width,
            height,
            depth,
        }
    }

    /// The farthest depth among the 3 × 3 pixels around the point (x, y) (in this
    /// grid's pixel coordinates); pixels off the grid count as +∞.
    fn farthest_around(&self, x: f64, y: f64) -> f32 {
        let col = (x.floor().max(0.0) as usize).min(self.width - 1);
        let row = (y.floor().max(0.0) as usize).min(self.height - 1);
        let mut farthest = f32::NEG_INFINITY;
        for r in row.saturating_sub(1)..=(row + 1) {
            for c in col.saturating_sub(1)..=(col + 1) {
                let value = if r < self.height && c < self.width {
                    self.depth[r * self.width + c]
                } else {
                    f32::INFINITY
                };
                farthest = farthest.max(value);
            }
        }
        farthest
    }
}

/// The level a triangle is rasterized into: the first where its bounding box,
/// clipped to the `width` × `height` buffer, covers at most `cap` pixels.
fn level(corners: &[ScreenPoint; 3], width: usize, height: usize, cap: f64) -> usize {
    let span = |low: f64, high: f64, count: usize| {
        pixel_span(low, high, count).map_or(0.0, |(a, b)| (b - a + 1) as f64)
    };
    let (xs, ys) = (corners.map(|p| p.x), corners.map(|p| p.y));
    let extent = |v: [f64; 3]| {
        (
            v.iter().copied().fold(f64::INFINITY, f64::min),
            v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        )
    };
    let ((x0, x1), (y0, y1)) = (extent(xs), extent(ys));
    let mut pixels = span(x0, x1, width) * span(y0, y1, height);
    let mut l = 0;
    while pixels > cap {
        pixels /= 4.0;
        l += 1;
    }
    l
}

/// The triangles overlapping each band of [`BAND_ROWS`] rows.
fn bin_by_band(triangles: &[[ScreenPoint; 3]], height: usize) -> Vec<Vec<u32>> {
    let band_count = height.div_ceil(BAND_ROWS);
    let mut bands = vec![Vec::new(); band_count];
    for (t, corners) in triangles.iter().enumerate() {
        if let Some((low, high)) = row_range(corners, height) {
            for band in bands
                .iter_mut()
                .take(high / BAND_ROWS + 1)
                .skip(low / BAND_ROWS)
            {
                band.push(t as u32);
            }
        }
    }
    bands
}

/// The rows whose pixel centres the triangle may cover, clipped to the buffer.
fn row_range(corners: &[ScreenPoint; 3], height: usize) -> Option<(usize, usize)> {
    let low = corners.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
    let high = corners
        .iter()
        .map(|p| p.y)
        .fold(f64::NEG_INFINITY, f64::max);
    pixel_span(low, high, height)
}

/// The pixels `i` with centre `i + 0.5` in `[low, high]`, clipped to `0..count`.
fn pixel_span(low: f64, high: f64, count: usize) -> Option<(usize, usize)> {
    if !(low.is_finite() && high.is_finite()) {
        return None;
    }
    let first = (low - 0.5).ceil().max(0.0);
    let last = (high - 0.5).floor().min(count as f64 - 1.0);
    (first <= last).then_some((first as usize, last as usize))
}

/// Write the triangle's depth into the band `rows` (starting at buffer row
/// `first_row`) where it is nearer than what is there. Corners carry the linear
/// depth ([`Camera::linear_depth`]), interpolated with screen barycentrics.
fn fill_triangle(
    rows: &mut [f32],
    width: usize,
    first_row: usize,
    [a, b, c]: &[ScreenPoint; 3],
    camera: &Camera,
) {
    let area = edge_function(a, b, c.x, c.y);
    if area.abs() < 1e-12 {
        return;
    }
    let band_rows = rows.len() / width;
    let low_y = a.y.min(b.y).min(c.y).max(first_row as f64);
    let high_y = a.y.max(b.y).max(c.y).min((first_row + band_rows) as f64);
    let Some((row_low, row_high)) = pixel_span(low_y, high_y, first_row + band_rows) else {
        return;
    };
    let low_x = a.x.min(b.x).min(c.x);
    let high_x = a.x.max(b.x).max(c.x);
    let Some((col_low, col_high)) = pixel_span(low_x, high_x, width) else {
        return;
    };
    for row in row_low.max(first_row)..=row_high {
        let y = row as f64 + 0.5;
        let line = &mut rows[(row - first_row) * width..(row - first_row + 1) * width];
        for (col, stored) in line.iter_mut().enumerate().take(col_high + 1).skip(col_low) {
            let x = col as f64 + 0.5;
            let weights = [
                edge_function(b, c, x, y) / area,
                edge_function(c, a, x, y) / area,
                edge_function(a, b, x, y) / area,
            ];
            if weights.iter().any(|&w| w < -1e-9) {
                continue;
            }
            let linear = weights[0] * a.depth + weights[1] * b.depth + weights[2] * c.depth;
            let depth = camera.depth_from_linear(linear) as f32;
            if depth < *stored {
                *stored = depth;
            }
        }
    }
}

/// Twice the signed area of the triangle (p, q, (x, y)).
fn edge_function(p: &ScreenPoint, q: &ScreenPoint, x: f64, y: f64) -> f64 {
    (q.x - p.x) * (y - p.y) - (q.y - p.y) * (x - p.x)
}
