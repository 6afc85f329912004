//! The segments of bi-iso-lines inside one cell: the isosurface polygons of the
//! cell (BUILDCYCLES), the labelled points of `g = J` on their edges
//! (CYCLESTOPOINTS) and their pairing (CYCLETOSEGS), Thirion & Gourdon 1993 §4.2.

use std::ops::Range;

use super::{PointKey, SecondField, Segment};
use crate::isosurface::cell::{crossing_fraction, decide_faces, CaseTable, EDGES};
use crate::volume::grid::{cell_corner, edge_key};
use crate::volume::Volume;

/// A vertex of an isosurface polygon: the key of its grid edge, its position in
/// grid index coordinates and the value of `g` there.
#[derive(Clone, Copy, Debug)]
struct Vertex {
    key: u64,
    index: [f64; 3],
    g: f64,
}

/// A point of `g = J` on a polygon edge, labelled `+` if the edge ends at a vertex
/// with `g ≥ J`.
#[derive(Clone, Copy, Debug)]
struct Labelled {
    key: PointKey,
    index: [f64; 3],
    plus: bool,
}

/// One cell: its place in the grid, the linear indices of its corners and the
/// values of `f` and `g` there.
struct Cell {
    index: [usize; 3],
    corners: [usize; 8],
    f: [f64; 8],
    g: [f64; 8],
}

impl Cell {
    /// The vertex of the isosurface `f = level` on cell edge `edge`: where `f`
    /// crosses the level along it (as the isosurface places it) and `g` there.
    fn vertex(&self, edge: u8, level: f64) -> Vertex {
        let (c, axis) = EDGES[edge as usize];
        let d = c | (1 << axis);
        let t = crossing_fraction(self.f[c], self.f[d], level);
        let mut index = cell_corner(self.index, c).map(|x| x as f64);
        index[axis] += t;
        Vertex {
            key: edge_key(self.corners[c], axis),
            index,
            g: self.g[c] + t * (self.g[d] - self.g[c]),
        }
    }
}

/// CYCLESTOPOINTS: the labelled points of `g = g_level` on the edges of the
/// polygon `vertices` (in its order), each computed from the edge's ends in key
/// order so that the neighbouring cell computes the same point.
fn cycle_to_points(vertices: &[Vertex], g_level: f64) -> Vec<Labelled> {
    let n = vertices.len();
    (0..n)
        .filter_map(|m| {
            let (a, b) = (vertices[m], vertices[(m + 1) % n]);
            let plus = b.g >= g_level;
            if (a.g >= g_level) == plus {
                return None;
            }
            let (p, q) = if a.key < b.key { (a, b) } else { (b, a) };
            let s = crossing_fraction(p.g, q.g, g_level);
            Some(Labelled {
                key: [p.key, q.key],
                index: std::array::from_fn(|i| p.index[i] + s * (q.index[i] - p.index[i])),
                plus,
            })
        })
        .collect()
}

/// CYCLETOSEGS: the labelled points (alternately `−` and `+` around the polygon),
/// rotated so that the first is `−`, paired from `−` to `+` as `Q0→Q1, Q2→Q3, …`
/// (joining the `+` sides of the polygon) or `Q2→Q1, …, Q0→Q(n−1)` (joining its
/// `−` sides).
fn cycle_to_segments(mut points: Vec<Labelled>, join_plus: bool) -> Vec<[Labelled; 2]> {
    let n = points.len();
    if let Some(first) = points.iter().position(|q| !q.plus) {
        points.rotate_left(first);
    }
    (0..n / 2)
        .map(|m| {
            let to = if join_plus {
                2 * m + 1
            } else {
                (2 * m + n - 1) % n
            };
            [points[2 * m], points[to]]
        })
        .collect()
}

/// The segments of one cell, in grid index coordinates, with the mean-value
/// convention choosing the pairing per polygon.
fn cell_segments(cell: &Cell, level: f64, g_level: f64) -> Vec<[Labelled; 2]> {
    let mask = (0..8).fold(0u8, |m, c| m | (u8::from(cell.f[c] >= level) << c));
    let table = CaseTable::get();
    let connected = decide_faces(table.ambiguous_faces(mask), &cell.f, level);
    let mut segments = Vec::new();
    for polygon in table.polygons(mask, connected).iter() {
        let vertices: Vec<Vertex> = polygon.iter().map(|&e| cell.vertex(e, level)).collect();
        let points = cycle_to_points(&vertices, g_level);
        if !points.is_empty() {
            let mean = vertices.iter().map(|v| v.g).sum::<f64>() / vertices.len() as f64;
            segments.extend(cycle_to_segments(points, mean >= g_level));
        }
    }
    segments
}

/// Whether the isosurface crosses a cell with these corner values of `f`.
pub(super) fn crossed(f: &[f64; 8], level: f64) -> bool {
    let inside = f.iter().filter(|&&v| v >= level).count();
    inside != 0 && inside != 8
}

/// Append the kept segments of cell `index` to `segments`, in world coordinates,
/// each running with `g ≥ J` on its left seen from `f < I` (reversed on a
/// mirrored grid, where the polygons' winding in index space is reversed in the
/// world).
pub(super) fn push_cell(
    volume: &Volume,
    (level, g_level): (f64, f64),
    field: &impl SecondField,
    index: [usize; 3],
    segments: &mut Vec<Segment>,
) {
    let corners = volume.grid().corners(index);
    let f = corners.map(|at| f64::from(volume.samples()[at]));
    if !crossed(&f, level) {
        return;
    }
    let Some(g) = field.corners(index) else {
        return;
    };
    let cell = Cell {
        index,
        corners,
        f,
        g,
    };
    let mirrored = volume.direction().determinant() < 0.0;
    for [a, b] in cell_segments(&cell, level, g_level) {
        let local = std::array::from_fn(|n| 0.5 * (a.index[n] + b.index[n]) - index[n] as f64);
        if field.keep(index, &g, local) {
            let [a, b] = if mirrored { [b, a] } else { [a, b] };
            segments.push(Segment {
                keys: [a.key, b.key],
                points: [a.index, b.index].map(|x| volume.index_to_world(x)),
            });
        }
    }
}

/// The segments of all cells of the z layers `layers`, in cell order.
pub(super) fn slab_segments(
    volume: &Volume,
    levels: (f64, f64),
    field: &impl SecondField,
    layers: Range<usize>,
) -> Vec<Segment> {
    let mut segments = Vec::new();
    for cell in volume.grid().cells(layers) {
        push_cell(volume, levels, field, cell, &mut segments);
    }
    segments
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::volume::grid::Grid;

    /// Labelled points with keys `[n, n]` and the given labels, in cycle order.
    fn labelled(labels: &[bool]) -> Vec<Labelled> {
        let point = |(n, &plus): (usize, &bool)| Labelled {
            key: [n as u64; 2],
            index: [0.0; 3],
            plus,
        };
        labels.iter().enumerate().map(point).collect()
    }

    /// The segments as pairs of point numbers.
    fn pairs(segments: &[[Labelled; 2]]) -> Vec<[u64; 2]> {
        segments.iter().map(|s| s.map(|q| q.key[0])).collect()
    }

    #[test]
    fn both_pairings_run_from_minus_to_plus_without_crossing() {
        // Q0 is '+': the cycle is rotated to start at Q1, the first '−'.
        let points = labelled(&[true, false, true, false, true, false]);
        let joining_plus = cycle_to_segments(points.clone(), true);
        assert_eq!(pairs(&joining_plus), [[1, 2], [3, 4], [5, 0]]);
        let joining_minus = cycle_to_segments(points, false);
        assert_eq!(pairs(&joining_minus), [[1, 0], [3, 2], [5, 4]]);
    }

    #[test]
    fn two_points_give_one_segment_either_way() {
        let points = labelled(&[true, false]);
        assert_eq!(pairs(&cycle_to_segments(points.clone(), true)), [[1, 0]]);
        assert_eq!(pairs(&cycle_to_segments(points, false)), [[1, 0]]);
    }

    /// The g value of the polygon vertex that each segment of a saddle cell cuts
    /// off, for g = `saddle` + `offset` on a horizontal isosurface quad.
    fn cut_off_values(offset: f64) -> Vec<f64> {
        // f crosses 0 half way up every z edge; g alternates around the quad.
        let saddle = [1.0, -1.0, -1.0, 1.0].map(|v: f64| v + offset);
        let g = std::array::from_fn(|c| saddle[c & 3]);
        let f = std::array::from_fn(|c| if c < 4 { -1.0 } else { 1.0 });
        let corners = Grid { dims: [2; 3] }.corners([0, 0, 0]);
        let cell = Cell {
            index: [0, 0, 0],
            corners,
            f,
            g,
        };
        let vertex_g = |key: u64| {
            (0..4)
                .find(|&c| edge_key(corners[c], 2) == key)
                .map(|c| g[c])
        };
        cell_segments(&cell, 0.0, 0.0)
            .iter()
            .map(|[a, b]| {
                let shared = a.key.iter().find(|k| b.key.contains(k)).unwrap();
                vertex_g(*shared).unwrap()
            })
            .collect()
    }

    #[test]
    fn the_mean_of_g_chooses_which_sides_the_segments_join() {
        // Mean above J: the '+' sides are joined, each segment cuts off a '−' vertex.
        let above = cut_off_values(0.5);
        assert_eq!(above.len(), 2);
        assert!(above.iter().all(|&g| g < 0.0), "{above:?}");
        let below = cut_off_values(-0.5);
        assert_eq!(below.len(), 2);
        assert!(below.iter().all(|&g| g >= 0.0), "{below:?}");
    }

    #[test]
    fn points_are_labelled_by_the_end_of_their_edge_and_keyed_in_order() {
        let vertex = |key: u64, x: f64, g: f64| Vertex {
            key,
            index: [x, 0.0, 0.0],
            g,
        };
        // A triangle with g = −1, 1, 3 at keys 7, 2, 5.
        let triangle = [
            vertex(7, 0.0, -1.0),
            vertex(2, 1.0, 1.0),
            vertex(5, 2.0, 3.0),
        ];
        let points = cycle_to_points(&triangle, 0.0);
        assert_eq!(points.len(), 2);
        assert!(points[0].plus && !points[1].plus);
        assert_eq!(points[0].key, [2, 7]);
        assert_eq!(points[1].key, [5, 7]);
        assert!((points[0].index[0] - 0.5).abs() < 1e-12);
        assert!((points[1].index[0] - 0.5).abs() < 1e-12);
    }
}
