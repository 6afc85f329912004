//! Crease surfaces from the edge crossings: per face, the crossings are paired into
//! segments; per cell, the segments of its six faces are chained into polygons and
//! triangulated (Schultz, Theisel and Seidel 2010, §4.4–4.5; DESIGN.md, "Crease
//! surfaces").
//!
//! Faces crossed an odd number of times hold a degenerate point, where the surface
//! ends; such faces are left unpaired for now, so the surface is open there.

use std::collections::HashMap;

use rayon::prelude::*;

use super::edges::{edge_crossings, CrossingOptions, EdgeCrossing};
use super::field::CreaseField;
use crate::mesh::{ScalarProperty, TriangleSoup};
use crate::{Point, Vector};

/// The name of the per-vertex ridge strength −λ3 in the surface's soup.
pub const STRENGTH: &str = "strength";

/// The crease surface of `field` with `options`: triangles that need not be
/// consistently orientable, with the ridge strength −λ3 of each vertex as the
/// vertex scalar [`STRENGTH`]. Connected pieces of fewer than `min_component`
/// triangles are dropped.
pub fn crease_surface(
    field: &CreaseField,
    options: &CrossingOptions,
    min_component: usize,
) -> TriangleSoup {
    let crossings = edge_crossings(field, options);
    let normals: Vec<Vector> = crossings
        .par_iter()
        .map(|c| field.normal_at(&c.position, options.epsilon))
        .collect();
    let index = EdgeIndex::new(&crossings);
    let [nx, ny, nz] = field.dims();
    let cells: Vec<[usize; 3]> = index
        .touched_cells(field.dims())
        .into_iter()
        .filter(|c| c[0] + 1 < nx && c[1] + 1 < ny && c[2] + 1 < nz)
        .collect();
    let polygons: Vec<Vec<Vec<usize>>> = cells
        .par_iter()
        .map(|&cell| cell_polygons(cell, field, &index, &crossings, &normals))
        .collect();
    let (positions, triangles, strength) = triangulate(&crossings, polygons.into_iter().flatten());
    let triangles = large_components(triangles, positions.len(), min_component);
    compact(positions, triangles, strength)
}

/// The triangles of the connected pieces (sharing vertices) of at least `min`
/// triangles.
fn large_components(triangles: Vec<[u32; 3]>, vertices: usize, min: usize) -> Vec<[u32; 3]> {
    if min <= 1 {
        return triangles;
    }
    let mut pieces = petgraph::unionfind::UnionFind::<u32>::new(vertices);
    for [a, b, c] in &triangles {
        pieces.union(*a, *b);
        pieces.union(*a, *c);
    }
    let mut size = vec![0usize; vertices];
    for t in &triangles {
        size[pieces.find(t[0]) as usize] += 1;
    }
    triangles
        .into_iter()
        .filter(|t| size[pieces.find(t[0]) as usize] >= min)
        .collect()
}

/// The crossings of each grid edge, by edge key.
struct EdgeIndex {
    /// Edge key → the range of its crossings in the (edge-sorted) list.
    ranges: HashMap<u64, (usize, usize)>,
}

impl EdgeIndex {
    fn new(crossings: &[EdgeCrossing]) -> EdgeIndex {
        let mut ranges = HashMap::new();
        for (n, c) in crossings.iter().enumerate() {
            ranges
                .entry(c.edge)
                .and_modify(|r: &mut (usize, usize)| r.1 = n + 1)
                .or_insert((n, n + 1));
        }
        EdgeIndex { ranges }
    }

    /// The ids of the crossings on `edge`, by increasing t.
    fn on(&self, edge: u64) -> std::ops::Range<usize> {
        self.ranges.get(&edge).map_or(0..0, |&(a, b)| a..b)
    }

    /// The cells (lowest corners) around every crossed edge, sorted, deduplicated.
    fn touched_cells(&self, [nx, ny, _]: [usize; 3]) -> Vec<[usize; 3]> {
        let mut cells: Vec<[usize; 3]> = Vec::new();
        for &edge in self.ranges.keys() {
            let (point, axis) = ((edge / 3) as usize, (edge % 3) as usize);
            let p = [point % nx, (point / nx) % ny, point / (nx * ny)];
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            for (du, dv) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let mut cell = p;
                if (du == 1 && cell[u] == 0) || (dv == 1 && cell[v] == 0) {
                    continue;
                }
                cell[u] -= du;
                cell[v] -= dv;
                cells.push(cell);
            }
        }
        cells.sort_unstable_by_key(|c| [c[2], c[1], c[0]]);
        cells.dedup();
        cells
    }
}

/// The corners (offsets) of face `axis`/`side` of a cell in cyclic order.
fn face_corners(axis: usize, side: usize) -> [[usize; 3]; 4] {
    let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
    [(0, 0), (1, 0), (1, 1), (0, 1)].map(|(du, dv)| {
        let mut c = [0; 3];
        c[axis] = side;
        c[u] = du;
        c[v] = dv;
        c
    })
}

/// The crossings around a face of the cell at `cell`, in cyclic order.
fn face_crossings(
    cell: [usize; 3],
    (axis, side): (usize, usize),
    field: &CreaseField,
    index: &EdgeIndex,
) -> Vec<usize> {
    let corners =
        face_corners(axis, side).map(|o| [cell[0] + o[0], cell[1] + o[1], cell[2] + o[2]]);
    let mut around = Vec::new();
    for k in 0..4 {
        let (a, b) = (corners[k], corners[(k + 1) % 4]);
        let forward = a <= b;
        let low = if forward { a } else { b };
        let edge_axis = (0..3).find(|&x| a[x] != b[x]).expect("adjacent corners");
        let key = 3 * field.linear_index(low) as u64 + edge_axis as u64;
        let ids: Vec<usize> = index.on(key).collect();
        if forward {
            around.extend(ids);
        } else {
            around.extend(ids.into_iter().rev());
        }
    }
    around
}

/// The segments of one face: its crossings paired without crossings, minimising
/// Σ |(q − p)·n_p| + |(q − p)·n_q| with the normals projected into the face. Odd
/// counts (a degenerate point on the face) give no segment.
fn face_segments(
    around: &[usize],
    axis: usize,
    crossings: &[EdgeCrossing],
    normals: &[Vector],
) -> Vec<[usize; 2]> {
    if around.len() % 2 == 1 {
        return Vec::new();
    }
    let in_face = |n: &Vector| {
        let mut n = *n;
        n[axis] = 0.0;
        n
    };
    let cost = |p: usize, q: usize| {
        let d = crossings[q].position - crossings[p].position;
        d.dot(&in_face(&normals[p])).abs() + d.dot(&in_face(&normals[q])).abs()
    };
    let mut best = (f64::INFINITY, Vec::new());
    for matching in non_crossing_matchings(around.len()) {
        let total: f64 = matching
            .iter()
            .map(|&[a, b]| cost(around[a], around[b]))
            .sum();
        if total < best.0 {
            best = (total, matching);
        }
    }
    best.1
        .into_iter()
        .map(|[a, b]| [around[a], around[b]])
        .collect()
}

/// Every perfect matching of `n` points in cyclic order without crossing pairs.
fn non_crossing_matchings(n: usize) -> Vec<Vec<[usize; 2]>> {
    fn within(lo: usize, hi: usize) -> Vec<Vec<[usize; 2]>> {
        if lo >= hi {
            return vec![Vec::new()];
        }
        let mut all = Vec::new();
        // `lo` pairs with a point at odd distance, splitting the rest in two.
        for partner in (lo + 1..hi).step_by(2) {
            for inner in within(lo + 1, partner) {
                for outer in within(partner + 1, hi) {
                    let mut m = vec![[lo, partner]];
                    m.extend(inner.iter().copied());
                    m.extend(outer.iter().copied());
                    all.push(m);
                }
            }
        }
        all
    }
    within(0, n)
}

/// The closed polygons of one cell: the segments of its six faces chained by their
/// shared crossings. Chains that do not close (next to a degenerate point) are
/// dropped.
fn cell_polygons(
    cell: [usize; 3],
    field: &CreaseField,
    index: &EdgeIndex,
    crossings: &[EdgeCrossing],
    normals: &[Vector],
) -> Vec<Vec<usize>> {
    let mut neighbours: HashMap<usize, Vec<usize>> = HashMap::new();
    for axis in 0..3 {
        for side in 0..2 {
            let around = face_crossings(cell, (axis, side), field, index);
            for [p, q] in face_segments(&around, axis, crossings, normals) {
                neighbours.entry(p).or_default().push(q);
                neighbours.entry(q).or_default().push(p);
            }
        }
    }
    let mut starts: Vec<usize> = neighbours.keys().copied().collect();
    starts.sort_unstable();
    let mut used = std::collections::HashSet::new();
    let mut polygons = Vec::new();
    for start in starts {
        if used.contains(&start) {
            continue;
        }
        if let Some(cycle) = walk(start, &neighbours) {
            used.extend(cycle.iter().copied());
            polygons.push(cycle);
        } else {
            used.insert(start);
        }
    }
    polygons
}

/// The cycle through `start` in a graph of degree-2 vertices, or `None` if the
/// walk meets a vertex of another degree.
fn walk(start: usize, neighbours: &HashMap<usize, Vec<usize>>) -> Option<Vec<usize>> {
    let mut cycle = vec![start];
    let (mut previous, mut current) = (start, *neighbours.get(&start)?.first()?);
    while current != start {
        let next = neighbours.get(&current)?;
        if next.len() != 2 || cycle.len() > neighbours.len() {
            return None;
        }
        cycle.push(current);
        let following = if next[0] == previous {
            next[1]
        } else {
            next[0]
        };
        (previous, current) = (current, following);
    }
    (cycle.len() >= 3 && neighbours[&start].len() == 2).then_some(cycle)
}

/// Triangles of the polygons: triangles as they are, quadrilaterals split along
/// their shorter diagonal, larger polygons fanned around their barycentre.
fn triangulate(
    crossings: &[EdgeCrossing],
    polygons: impl Iterator<Item = Vec<usize>>,
) -> (Vec<Point>, Vec<[u32; 3]>, Vec<f64>) {
    let mut positions: Vec<Point> = crossings.iter().map(|c| c.position).collect();
    let mut strength: Vec<f64> = crossings.iter().map(|c| -c.lambda3).collect();
    let mut triangles = Vec::new();
    for polygon in polygons {
        let ids: Vec<u32> = polygon.iter().map(|&i| i as u32).collect();
        match ids.len() {
            3 => triangles.push([ids[0], ids[1], ids[2]]),
            4 => {
                let d02 = (positions[polygon[0]] - positions[polygon[2]]).norm();
                let d13 = (positions[polygon[1]] - positions[polygon[3]]).norm();
                if d02 <= d13 {
                    triangles.extend([[ids[0], ids[1], ids[2]], [ids[0], ids[2], ids[3]]]);
                } else {
                    triangles.extend([[ids[1], ids[2], ids[3]], [ids[1], ids[3], ids[0]]]);
                }
            }
            n => {
                let centre = Point::from(
                    polygon.iter().map(|&i| positions[i].coords).sum::<Vector>() / n as f64,
                );
                let c = positions.len() as u32;
                positions.push(centre);
                strength.push(polygon.iter().map(|&i| strength[i]).sum::<f64>() / n as f64);
                for k in 0..n {
                    triangles.push([ids[k], ids[(k + 1) % n], c]);
                }
            }
        }
    }
    (positions, triangles, strength)
}

/// The surface without the vertices no triangle uses (crossings whose polygon did
/// not close, pieces dropped for their size), with the strength as a vertex scalar.
fn compact(
    positions: Vec<Point>,
    mut triangles: Vec<[u32; 3]>,
    strength: Vec<f64>,
) -> TriangleSoup {
    let mut new_id = vec![u32::MAX; positions.len()];
    let mut kept_positions = Vec::new();
    let mut kept_strength = Vec::new();
    for corner in triangles.iter_mut().flatten() {
        let old = *corner as usize;
        if new_id[old] == u32::MAX {
            new_id[old] = kept_positions.len() as u32;
            kept_positions.push(positions[old]);
            kept_strength.push(strength[old]);
        }
        *corner = new_id[old];
    }
    TriangleSoup {
        positions: kept_positions,
        triangles,
        vertex_scalars: vec![ScalarProperty {
            name: STRENGTH.to_string(),
            values: kept_strength,
        }],
    }
}
