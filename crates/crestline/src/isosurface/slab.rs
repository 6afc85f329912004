//! Extraction over the whole grid, in parallel over slabs of z.
//!
//! Crossings are numbered plane by plane: the crossings of grid plane `z = k` are
//! those on its x and y edges and on the z edges leaving it upwards, in scan order
//! (y, then x, then axis). Polygon centres come after all crossings, and triangles
//! are in cell order. A first pass over the slabs of cell layers counts the
//! crossings of each plane and the triangles and centres of each slab; the output
//! arrays are then allocated once and split into the parts each slab fills in a
//! second pass, numbering the planes it touches through dense per-plane arrays (no
//! hashing) and writing its crossings, centres and triangles in place. The slabs
//! have a fixed size, so the output is the same for any number of threads.

use rayon::prelude::*;

use super::cell::{
    crossing_fraction, decide_faces, is_fanned, triangulate, CaseTable, Polygons, EDGES,
};
use super::cell_key;
use crate::slices::cut;
use crate::volume::grid::{corner_offset, edge_key, Grid};
use crate::volume::Volume;
use crate::{Error, Point, Result, Vector};

/// Cell layers per slab: a fixed number, so the slabs (and the output) do not
/// depend on the number of threads.
const SLAB_LAYERS: usize = 8;

/// Most vertices a surface may have (its vertex numbers are `u32`).
const MAX_VERTICES: usize = u32::MAX as usize;

/// Vertices and triangles of the isosurface, with where each vertex came from.
pub(super) struct Extraction {
    pub(super) positions: Vec<Point>,
    /// Per vertex, the key of its grid edge or cell (see [`edge_key`], [`cell_key`])
    /// and its fraction along the edge (0 for a cell's centre).
    pub(super) keys: Vec<u64>,
    pub(super) fractions: Vec<f64>,
    pub(super) triangles: Vec<[u32; 3]>,
}

/// The volume seen as a grid of cells at one level.
struct LevelGrid<'a> {
    volume: &'a Volume,
    samples: &'a [f32],
    layout: Grid,
    level: f64,
    /// Cell edge `e` runs along axis `edge_square[e].2` from the sample `square +
    /// edge_square[e].1` of the cell's lower plane (`edge_square[e].0` false) or
    /// upper plane (true), `square` the cell's lowest corner in its plane.
    edge_square: [(bool, usize, usize); 12],
    /// Corner `c` of a cell is sample `cell + corner_step[c]`.
    corner_step: [usize; 8],
    /// The grid is mirrored (the direction has a negative determinant): triangles
    /// are wound the other way so that they stay counter-clockwise from outside.
    mirrored: bool,
}

impl<'a> LevelGrid<'a> {
    fn new(volume: &'a Volume, level: f64) -> LevelGrid<'a> {
        let layout = volume.grid();
        let edge_square = EDGES.map(|(corner, axis)| {
            let [dx, dy, dz] = corner_offset(corner);
            (dz == 1, layout.index([dx, dy, 0]), axis)
        });
        LevelGrid {
            volume,
            samples: volume.samples(),
            layout,
            level,
            edge_square,
            corner_step: layout.corner_steps(),
            mirrored: volume.direction().determinant() < 0.0,
        }
    }

    /// The samples of plane `z = k`.
    fn plane_samples(&self, k: usize) -> &[f32] {
        let size = self.layout.plane_len();
        self.samples.get(k * size..(k + 1) * size).unwrap_or(&[])
    }

    /// The object/background convention: 1 where `f ≥ I` (inside), 0 elsewhere.
    fn inside(&self, value: f32) -> u8 {
        u8::from(f64::from(value) >= self.level)
    }

    /// The inside flags of the samples of plane `k`.
    fn classify(&self, k: usize, inside: &mut Vec<u8>) {
        inside.clear();
        inside.extend(self.plane_samples(k).iter().map(|&v| self.inside(v)));
    }

    /// Call `visit(i, j, axis)` for every crossing of plane `k` (whose inside flags
    /// are `inside`), in the order that numbers them.
    fn scan_plane(&self, k: usize, inside: &[u8], mut visit: impl FnMut(usize, usize, usize)) {
        let [nx, ny, _] = self.layout.dims;
        let above = self.plane_samples(k + 1);
        for j in 0..ny {
            let start = self.layout.index([0, j, 0]);
            let row = &inside[start..start + nx];
            let next_row = inside.get(start + nx..start + 2 * nx);
            for (i, &here) in row.iter().enumerate() {
                if row.get(i + 1).is_some_and(|&x| x != here) {
                    visit(i, j, 0);
                }
                if next_row.is_some_and(|r| r[i] != here) {
                    visit(i, j, 1);
                }
                if above
                    .get(start + i)
                    .is_some_and(|&v| self.inside(v) != here)
                {
                    visit(i, j, 2);
                }
            }
        }
    }

    /// The crossing on the edge from sample `(i, j, k)` along `axis`: its world
    /// position (linear interpolation, kept away from the ends) and
    /// source.
    fn crossing(&self, [i, j, k]: [usize; 3], axis: usize) -> (Point, u64, f64) {
        let at = self.layout.index([i, j, k]);
        let step = self.layout.step(axis);
        let (a, b) = (
            f64::from(self.samples[at]),
            f64::from(self.samples[at + step]),
        );
        let t = crossing_fraction(a, b, self.level);
        let mut index = [i, j, k].map(|x| x as f64);
        index[axis] += t;
        let key = edge_key(at, axis);
        (self.volume.index_to_world(index), key, t)
    }
}

/// One grid plane: its inside flags, the inside bits of its squares and its
/// crossings, numbered through a dense slot array (no hashing).
struct Plane {
    /// Number of the plane's first crossing.
    base: u32,
    inside: Vec<u8>,
    /// For square `i + nx j`, the inside bits of its corners `(i, j)`, `(i + 1, j)`,
    /// `(i, j + 1)`, `(i + 1, j + 1)` (bits 0 to 3, as the cell corners 0 to 3).
    squares: Vec<u8>,
    /// For each [`slot_of`] that has a crossing, its number within the plane (other
    /// slots hold stale values and are never read).
    slot: Vec<u32>,
    points: Vec<Point>,
    keys: Vec<u64>,
    fractions: Vec<f64>,
}

impl Plane {
    fn new(grid: &LevelGrid) -> Plane {
        let size = grid.layout.plane_len();
        Plane {
            base: 0,
            inside: Vec::with_capacity(size),
            squares: vec![0; size],
            slot: vec![0; slot_of(size, 0)],
            points: Vec::new(),
            keys: Vec::new(),
            fractions: Vec::new(),
        }
    }

    /// The inside flags of plane `k` and of its squares' corners.
    fn classify(&mut self, grid: &LevelGrid, k: usize) {
        let nx = grid.layout.dims[0];
        grid.classify(k, &mut self.inside);
        let rows = self.inside.chunks_exact(nx);
        let pairs = rows.clone().zip(rows.skip(1));
        for ((low, high), squares) in pairs.zip(self.squares.chunks_exact_mut(nx)) {
            for i in 0..nx - 1 {
                squares[i] = low[i] | (low[i + 1] << 1) | (high[i] << 2) | (high[i + 1] << 3);
            }
        }
    }

    /// The number of crossings of plane `k`, once classified.
    fn count_crossings(&self, grid: &LevelGrid, k: usize) -> u32 {
        let mut count = 0;
        grid.scan_plane(k, &self.inside, |_, _, _| count += 1);
        count
    }

    /// Classify plane `k`, then number and place its crossings, the first being
    /// number `base`.
    fn fill(&mut self, grid: &LevelGrid, k: usize, base: u32) {
        self.classify(grid, k);
        self.base = base;
        self.points.clear();
        self.keys.clear();
        self.fractions.clear();
        grid.scan_plane(k, &self.inside, |i, j, axis| {
            self.slot[slot_of(grid.layout.index([i, j, 0]), axis)] = self.points.len() as u32;
            let (point, key, t) = grid.crossing([i, j, k], axis);
            self.points.push(point);
            self.keys.push(key);
            self.fractions.push(t);
        });
    }
}

/// The slot of the crossing on the edge along `axis` from sample `square` (`i + nx·j`)
/// of a plane in [`Plane::slot`]: the key the edge would have in the plane `z = 0`.
#[inline]
fn slot_of(square: usize, axis: usize) -> usize {
    edge_key(square, axis) as usize
}

/// Call `visit(cell, square, polygons)` for every cell of layer `k` (between the
/// classified planes `lower`, `z = k`, and `upper`, `z = k + 1`) that the surface
/// crosses, with the cell's linear index, the index of its lowest corner within
/// its plane and its polygons.
fn surface_cells<'t>(
    grid: &LevelGrid,
    k: usize,
    lower: &Plane,
    upper: &Plane,
    mut visit: impl FnMut(usize, usize, &'t Polygons),
) {
    let [nx, ny, _] = grid.layout.dims;
    let table = CaseTable::get();
    for j in 0..ny - 1 {
        let row = grid.layout.index([0, j, 0]);
        let low = &lower.squares[row..row + nx - 1];
        let high = &upper.squares[row..row + nx - 1];
        let mut i = 0;
        while i < nx - 1 {
            if uniform_run(low, high, i) {
                i += RUN;
                continue;
            }
            let mask = low[i] | (high[i] << 4);
            if mask != 0 && mask != u8::MAX {
                let cell = grid.layout.index([i, j, k]);
                let connected = decide_cell_faces(grid, table.ambiguous_faces(mask), cell);
                visit(cell, row + i, table.polygons(mask, connected));
            }
            i += 1;
        }
    }
}

/// Cells skipped at once where none is crossed.
const RUN: usize = 8;

/// Whether the [`RUN`] cells from `i` on all lie inside or all outside (their
/// squares in the planes below and above, `low` and `high`, are all 0 or all 15).
fn uniform_run(low: &[u8], high: &[u8], i: usize) -> bool {
    let word = |squares: &[u8]| {
        let bytes = squares.get(i..i + RUN).and_then(|run| run.try_into().ok());
        bytes.map(u64::from_le_bytes)
    };
    match (word(low), word(high)) {
        (Some(low), Some(high)) => low | high == 0 || low & high == 0x0f0f_0f0f_0f0f_0f0f,
        _ => false,
    }
}

/// The decider's choice on each ambiguous face (bits of `ambiguous`) of `cell`:
/// bit `f` set where face `f` joins its inside corners.
fn decide_cell_faces(grid: &LevelGrid, ambiguous: u8, cell: usize) -> u8 {
    if ambiguous == 0 {
        return 0;
    }
    let values = grid
        .corner_step
        .map(|step| f64::from(grid.samples[cell + step]));
    decide_faces(ambiguous, &values, grid.level)
}

/// What a slab of cell layers `first..end` holds: it owns the crossings of planes
/// `first..end` (and of the last plane if it is the last slab).
#[derive(Clone, Debug, Default)]
struct SlabCount {
    first: usize,
    end: usize,
    /// Crossings of each plane it owns.
    crossings: Vec<u32>,
    triangles: usize,
    centres: usize,
}

/// The first pass over the slab of cell layers `first..end`.
fn count_slab(grid: &LevelGrid, first: usize, end: usize) -> SlabCount {
    let mut count = SlabCount {
        first,
        end,
        ..SlabCount::default()
    };
    let (mut lower, mut upper) = (Plane::new(grid), Plane::new(grid));
    lower.classify(grid, first);
    count.crossings.push(lower.count_crossings(grid, first));
    for k in first..end {
        upper.classify(grid, k + 1);
        if k + 1 < owned_end(grid, end) {
            count.crossings.push(upper.count_crossings(grid, k + 1));
        }
        surface_cells(grid, k, &lower, &upper, |_, _, polygons| {
            count.triangles += polygons.triangle_count();
            count.centres += polygons.centre_count();
        });
        std::mem::swap(&mut lower, &mut upper);
    }
    count
}

/// The end of the planes owned by the slab of cell layers ending at `end`.
fn owned_end(grid: &LevelGrid, end: usize) -> usize {
    if end == grid.layout.cell_layers() {
        end + 1
    } else {
        end
    }
}

/// The part of the output one slab fills.
struct Part<'a> {
    /// Number of its first crossing, and its crossings.
    first_crossing: u32,
    points: &'a mut [Point],
    keys: &'a mut [u64],
    fractions: &'a mut [f64],
    /// Number of its first centre, and its centres.
    first_centre: u32,
    centres: &'a mut [Point],
    centre_keys: &'a mut [u64],
    /// Its triangles.
    triangles: &'a mut [[u32; 3]],
    /// How many triangles and centres are written.
    written: usize,
    written_centres: usize,
    mirrored: bool,
}

impl Part<'_> {
    /// Copy the crossings of an owned plane into place.
    fn take(&mut self, plane: &Plane) {
        let at = (plane.base - self.first_crossing) as usize;
        let end = at + plane.points.len();
        self.points[at..end].copy_from_slice(&plane.points);
        self.keys[at..end].copy_from_slice(&plane.keys);
        self.fractions[at..end].copy_from_slice(&plane.fractions);
    }

    fn push_triangle(&mut self, [a, b, c]: [u32; 3]) {
        let triangle = if self.mirrored { [a, c, b] } else { [a, b, c] };
        self.triangles[self.written] = triangle;
        self.written += 1;
    }

    /// Triangulate one polygon of `cell` with corners `ids`: a triangle as it is, a
    /// larger polygon as a fan around its barycentre (a new vertex of this cell),
    /// `sum / n` from the sum of its corners' positions.
    fn push_polygon(&mut self, ids: &[u32], sum: Vector, cell: usize) {
        let mut centre = 0;
        if is_fanned(ids.len()) {
            let n = self.written_centres;
            self.written_centres += 1;
            self.centres[n] = Point::from(sum / ids.len() as f64);
            self.centre_keys[n] = cell_key(cell as u64);
            centre = self.first_centre + n as u32;
        }
        for triangle in triangulate(ids, centre) {
            self.push_triangle(triangle);
        }
    }
}

/// The second pass over a slab: its crossings, centres and triangles.
fn fill_slab(grid: &LevelGrid, bases: &[u32], count: &SlabCount, mut part: Part) {
    let (first, end) = (count.first, count.end);
    let (mut lower, mut upper) = (Plane::new(grid), Plane::new(grid));
    lower.fill(grid, first, bases[first]);
    part.take(&lower);
    let mut ids = [0u32; 12];
    for k in first..end {
        upper.fill(grid, k + 1, bases[k + 1]);
        if k + 1 < owned_end(grid, end) {
            part.take(&upper);
        }
        surface_cells(grid, k, &lower, &upper, |cell, square, polygons| {
            for polygon in polygons.iter() {
                let mut sum = Vector::zeros();
                for (n, &edge) in polygon.iter().enumerate() {
                    let (up, offset, axis) = grid.edge_square[edge as usize];
                    let plane = if up { &upper } else { &lower };
                    let local = plane.slot[slot_of(square + offset, axis)] as usize;
                    ids[n] = plane.base + local as u32;
                    if is_fanned(polygon.len()) {
                        sum += plane.points[local].coords;
                    }
                }
                part.push_polygon(&ids[..polygon.len()], sum, cell);
            }
        });
        std::mem::swap(&mut lower, &mut upper);
    }
}

/// The number of the first crossing of each plane (and, last, the total) and of
/// the first centre of each slab, or an error if there are too many vertices.
fn numbering(counts: &[SlabCount]) -> Result<(Vec<u32>, Vec<u32>)> {
    let plane_counts = counts.iter().flat_map(|c| &c.crossings);
    let mut bases = vec![0];
    let mut total = 0usize;
    for &n in plane_counts {
        total += n as usize;
        bases.push(total.min(MAX_VERTICES) as u32);
    }
    let mut first_centres = Vec::with_capacity(counts.len());
    for count in counts {
        first_centres.push(total.min(MAX_VERTICES) as u32);
        total += count.centres;
    }
    if total >= MAX_VERTICES {
        return Err(Error::Argument(format!(
            "the isosurface has {total} vertices, more than the {MAX_VERTICES} supported"
        )));
    }
    Ok((bases, first_centres))
}

/// `values` of length `n`, filled in parallel.
fn filled<T: Clone + Send + Sync>(n: usize, value: T) -> Vec<T> {
    let mut values = Vec::with_capacity(n);
    values.par_extend(rayon::iter::repeat_n(value, n));
    values
}

/// The polygons of every cell of `volume` at `level`, triangulated. The samples
/// must be finite and every dimension at least 2 (checked by the caller).
pub(super) fn extract(volume: &Volume, level: f64) -> Result<Extraction> {
    let grid = LevelGrid::new(volume, level);
    let layers = grid.layout.cell_layers();
    let counts: Vec<SlabCount> = (0..layers)
        .into_par_iter()
        .step_by(SLAB_LAYERS)
        .map(|first| count_slab(&grid, first, (first + SLAB_LAYERS).min(layers)))
        .collect();
    let (bases, first_centres) = numbering(&counts)?;
    let crossings = *bases.last().expect("a base per plane") as usize;
    let centres: usize = counts.iter().map(|c| c.centres).sum();
    let triangle_count: usize = counts.iter().map(|c| c.triangles).sum();
    let mut positions = filled(crossings + centres, Point::origin());
    // Zeroed memory comes from the allocator untouched: the slabs' writes are the
    // first, in parallel (centres keep their fraction 0).
    let mut keys = vec![0u64; crossings + centres];
    let mut fractions = vec![0f64; crossings + centres];
    let mut triangles = vec![[0u32; 3]; triangle_count];
    let (mut points, mut centre_points) = positions.split_at_mut(crossings);
    let (mut crossing_keys, mut centre_keys) = keys.split_at_mut(crossings);
    let mut fractions_left = &mut fractions[..crossings];
    let mut triangles_left = &mut triangles[..];
    let mut parts = Vec::with_capacity(counts.len());
    for (count, &first_centre) in counts.iter().zip(&first_centres) {
        let owned = count.crossings.iter().map(|&n| n as usize).sum();
        parts.push(Part {
            first_crossing: bases[count.first],
            points: cut(&mut points, owned),
            keys: cut(&mut crossing_keys, owned),
            fractions: cut(&mut fractions_left, owned),
            first_centre,
            centres: cut(&mut centre_points, count.centres),
            centre_keys: cut(&mut centre_keys, count.centres),
            triangles: cut(&mut triangles_left, count.triangles),
            written: 0,
            written_centres: 0,
            mirrored: grid.mirrored,
        });
    }
    parts
        .into_par_iter()
        .zip(&counts)
        .for_each(|(part, count)| fill_slab(&grid, &bases, count, part));
    Ok(Extraction {
        positions,
        keys,
        fractions,
        triangles,
    })
}
