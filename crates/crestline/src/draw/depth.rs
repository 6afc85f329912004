//! A depth buffer of the mesh: the nearest surface depth at every pixel, rasterized
//! from the triangles (front and back faces alike) in parallel bands.

use rayon::prelude::*;

use crate::mesh::Mesh;

use super::camera::{Camera, ScreenPoint};

/// Rows of buffer pixels rasterized together by one task.
const BAND_ROWS: usize = 32;

/// The longest side of a depth buffer, in pixels (bounds memory at 256 MB).
const MAX_BUFFER_SIDE: f64 = 8192.0;

/// The nearest surface depth per pixel, on a grid `resolution` times finer than the
/// canvas; pixels the mesh does not cover hold +∞.
#[derive(Clone, Debug)]
pub struct DepthBuffer {
    width: usize,
    height: usize,
    /// Buffer pixels per canvas pixel.
    resolution: f64,
    depth: Vec<f32>,
    /// The mesh's mean edge length: the unit of depth tolerances.
    edge_length: f64,
}

impl DepthBuffer {
    /// Rasterize `mesh` as seen by `camera`, `supersampling` buffer pixels per canvas
    /// pixel along each axis (reduced if the buffer would exceed 8192 pixels a side).
    /// Triangles with a corner behind a perspective camera's eye are left out.
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
        let bands = bin_by_band(&triangles, height);
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
        DepthBuffer {
            width,
            height,
            resolution,
            depth,
            edge_length: mesh.mean_edge_length(),
        }
    }

    /// The mesh's mean edge length, the unit of depth tolerances.
    pub fn edge_length(&self) -> f64 {
        self.edge_length
    }

    /// Whether a surface point seen at `point` is visible: its depth is at most
    /// `tolerance` (mesh units) behind the farthest buffer depth among the 3 × 3
    /// buffer pixels around it. Taking the farthest of the neighbourhood absorbs the
    /// change of depth across a pixel, however steep the surface, so lines lying on
    /// the surface are never hidden by the surface itself.
    pub fn is_visible(&self, point: &ScreenPoint, tolerance: f64) -> bool {
        let (bx, by) = (point.x * self.resolution, point.y * self.resolution);
        let col = (bx.floor().max(0.0) as usize).min(self.width - 1);
        let row = (by.floor().max(0.0) as usize).min(self.height - 1);
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
        point.depth <= f64::from(farthest) + tolerance
    }
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
