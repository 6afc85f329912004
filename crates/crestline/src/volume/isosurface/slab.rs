//! Extraction over the whole grid, in parallel over slabs of z.
//!
//! Crossings are numbered plane by plane: the crossings of grid plane `z = k` are
//! those on its x and y edges and on the z edges leaving it upwards, in scan order
//! (y, then x, then axis). A first pass counts them per plane, so that each plane's
//! first vertex number is known; then every slab of cell layers numbers the planes
//! it touches into dense per-plane arrays (no hashing), computes the crossings of
//! the planes it owns and the polygons of its cells. Polygon centres get numbers
//! after all crossings, slab after slab. The numbering does not depend on how the
//! slabs are spread over threads, so the output is the same for any thread count.

use rayon::prelude::*;

use super::cell::{corner_offset, decider_corners, inside_corners_connected, CaseTable, EDGES};
use super::VertexSource;
use crate::volume::Volume;
use crate::{Error, Point, Result};

/// Cell layers per slab: a fixed number, so the slabs (and the output) do not
/// depend on the number of threads.
const SLAB_LAYERS: usize = 8;

/// How far a crossing stays from the ends of its edge, as a fraction of the edge:
/// where `f = I` at a corner, the crossings of its edges would otherwise coincide.
const END_GAP: f64 = 1e-4;

/// Marks a vertex number inside a slab as a polygon centre (numbered per slab).
const CENTRE: u32 = 1 << 31;

/// No crossing on this edge.
const NONE: u32 = u32::MAX;

/// Vertices and triangles of the isosurface, with where each came from.
pub(super) struct Extraction {
    pub(super) positions: Vec<Point>,
    pub(super) sources: Vec<VertexSource>,
    pub(super) triangles: Vec<[u32; 3]>,
    pub(super) face_cells: Vec<u64>,
}

/// The volume seen as a grid of cells at one level.
struct Grid<'a> {
    volume: &'a Volume,
    samples: &'a [f32],
    dims: [usize; 3],
    level: f64,
    /// Corner `c` of a cell is sample `cell + corner_step[c]`.
    corner_step: [usize; 8],
    /// Cell edge `e` is slot `cell slot + edge_slot[e].1` of the cell's lower plane
    /// (`edge_slot[e].0` false) or upper plane (true).
    edge_slot: [(bool, usize); 12],
    /// The grid is mirrored (the direction has a negative determinant): triangles
    /// are wound the other way so that they stay counter-clockwise from outside.
    mirrored: bool,
}

impl<'a> Grid<'a> {
    fn new(volume: &'a Volume, level: f64) -> Grid<'a> {
        let [nx, ny, _] = volume.dims();
        let corner_step = std::array::from_fn(|c| {
            let [dx, dy, dz] = corner_offset(c);
            dx + nx * (dy + ny * dz)
        });
        let edge_slot = EDGES.map(|(corner, axis)| {
            let [dx, dy, dz] = corner_offset(corner);
            (dz == 1, 3 * (dx + nx * dy) + axis)
        });
        Grid {
            volume,
            samples: volume.samples(),
            dims: volume.dims(),
            level,
            corner_step,
            edge_slot,
            mirrored: volume.direction().determinant() < 0.0,
        }
    }

    /// The object/background convention: a sample with `f ≥ I` is inside.
    fn inside(&self, at: usize) -> bool {
        f64::from(self.samples[at]) >= self.level
    }

    /// Call `visit(slot, sample, axis)` for every crossing of plane `k`, in the
    /// order that numbers them; `slot = 3 (i + nx j) + axis` and `sample` is the
    /// linear index of the edge's start.
    fn scan_plane(&self, k: usize, mut visit: impl FnMut(usize, usize, usize)) {
        let [nx, ny, nz] = self.dims;
        let steps = [1, nx, nx * ny];
        let open = [nx - 1, ny - 1, nz - 1];
        for j in 0..ny {
            for i in 0..nx {
                let at = i + nx * (j + ny * k);
                let here = self.inside(at);
                for (axis, index) in [i, j, k].into_iter().enumerate() {
                    if index < open[axis] && self.inside(at + steps[axis]) != here {
                        visit(3 * (i + nx * j) + axis, at, axis);
                    }
                }
            }
        }
    }

    /// The crossing on the edge from sample `at` along `axis`: its world position
    /// (linear interpolation, kept [`END_GAP`] away from the ends) and source.
    fn crossing(&self, at: usize, axis: usize) -> (Point, VertexSource) {
        let [nx, ny, _] = self.dims;
        let step = [1, nx, nx * ny][axis];
        let (a, b) = (
            f64::from(self.samples[at]),
            f64::from(self.samples[at + step]),
        );
        let t = ((self.level - a) / (b - a)).clamp(END_GAP, 1.0 - END_GAP);
        let mut index = [at % nx, (at / nx) % ny, at / (nx * ny)].map(|x| x as f64);
        index[axis] += t;
        let source = VertexSource::Edge {
            point: at as u64,
            axis: axis as u8,
            t,
        };
        (self.volume.index_to_world(index), source)
    }
}

/// The crossings of one grid plane: a dense slot → number array and their points.
struct Plane {
    /// Number of the plane's first crossing.
    base: u32,
    /// For each slot `3 (i + nx j) + axis`, the crossing's number within the plane.
    slot: Vec<u32>,
    points: Vec<Point>,
    sources: Vec<VertexSource>,
}

impl Plane {
    fn new(grid: &Grid) -> Plane {
        let [nx, ny, _] = grid.dims;
        Plane {
            base: 0,
            slot: vec![NONE; 3 * nx * ny],
            points: Vec::new(),
            sources: Vec::new(),
        }
    }

    /// Number and place the crossings of plane `k`, the first being number `base`.
    fn fill(&mut self, grid: &Grid, k: usize, base: u32) {
        self.base = base;
        self.slot.fill(NONE);
        self.points.clear();
        self.sources.clear();
        grid.scan_plane(k, |slot, at, axis| {
            self.slot[slot] = self.points.len() as u32;
            let (point, source) = grid.crossing(at, axis);
            self.points.push(point);
            self.sources.push(source);
        });
    }
}

/// What one slab produced; centres are numbered `CENTRE | n` in `triangles`.
#[derive(Default)]
struct Piece {
    points: Vec<Point>,
    sources: Vec<VertexSource>,
    triangles: Vec<[u32; 3]>,
    face_cells: Vec<u64>,
    centres: Vec<Point>,
    centre_cells: Vec<u64>,
}

impl Piece {
    fn take_crossings(&mut self, plane: &Plane) {
        self.points.extend_from_slice(&plane.points);
        self.sources.extend_from_slice(&plane.sources);
    }

    fn push_triangle(&mut self, grid: &Grid, [a, b, c]: [u32; 3], cell: usize) {
        let triangle = if grid.mirrored { [a, c, b] } else { [a, b, c] };
        self.triangles.push(triangle);
        self.face_cells.push(cell as u64);
    }

    /// Triangulate one polygon of `cell`: a triangle as it is, a larger polygon as
    /// a fan around its barycentre (a new vertex of this cell).
    fn push_polygon(&mut self, grid: &Grid, ids: &[u32], points: &[Point], cell: usize) {
        if let [a, b, c] = *ids {
            self.push_triangle(grid, [a, b, c], cell);
            return;
        }
        let sum = points.iter().fold(Point::origin(), |s, p| s + p.coords);
        let centre = CENTRE | self.centres.len() as u32;
        self.centres.push(sum / points.len() as f64);
        self.centre_cells.push(cell as u64);
        for (k, &a) in ids.iter().enumerate() {
            let b = ids[(k + 1) % ids.len()];
            self.push_triangle(grid, [centre, a, b], cell);
        }
    }
}

/// The polygons of the cells of layer `k`, between planes `lower` (`z = k`) and
/// `upper` (`z = k + 1`).
fn cell_layer(grid: &Grid, k: usize, lower: &Plane, upper: &Plane, piece: &mut Piece) {
    let [nx, ny, _] = grid.dims;
    let table = CaseTable::get();
    let mut ids = [0u32; 12];
    let mut points = [Point::origin(); 12];
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let cell = i + nx * (j + ny * k);
            let values = grid.corner_step.map(|step| grid.samples[cell + step]);
            let mask = (0..8).fold(0u8, |mask, c| {
                mask | (u8::from(f64::from(values[c]) >= grid.level) << c)
            });
            if mask == 0 || mask == u8::MAX {
                continue;
            }
            let connected = decide_faces(grid, table.ambiguous_faces(mask), &values);
            let cell_slot = 3 * (i + nx * j);
            for polygon in table.polygons(mask, connected).iter() {
                for (n, &edge) in polygon.iter().enumerate() {
                    let (up, offset) = grid.edge_slot[edge as usize];
                    let plane = if up { upper } else { lower };
                    let local = plane.slot[cell_slot + offset] as usize;
                    ids[n] = plane.base + local as u32;
                    points[n] = plane.points[local];
                }
                let n = polygon.len();
                piece.push_polygon(grid, &ids[..n], &points[..n], cell);
            }
        }
    }
}

/// The decider's choice on each ambiguous face (bits of `ambiguous`): bit `f` set
/// where face `f` joins its inside corners.
fn decide_faces(grid: &Grid, ambiguous: u8, values: &[f32; 8]) -> u8 {
    (0..6)
        .filter(|&face| (ambiguous >> face) & 1 == 1)
        .filter(|&face| {
            let corners = decider_corners(face).map(|c| f64::from(values[c]));
            inside_corners_connected(corners, grid.level)
        })
        .fold(0, |bits, face| bits | (1 << face))
}

/// The cell layers `first..end`: it owns (outputs the crossings of) planes
/// `first..end`, and also the last plane if it is the last slab.
fn slab(grid: &Grid, bases: &[u32], first: usize, end: usize) -> Piece {
    let last_plane = grid.dims[2] - 1;
    let mut piece = Piece::default();
    let mut lower = Plane::new(grid);
    let mut upper = Plane::new(grid);
    lower.fill(grid, first, bases[first]);
    piece.take_crossings(&lower);
    for k in first..end {
        upper.fill(grid, k + 1, bases[k + 1]);
        if k + 1 < end || k + 1 == last_plane {
            piece.take_crossings(&upper);
        }
        cell_layer(grid, k, &lower, &upper, &mut piece);
        std::mem::swap(&mut lower, &mut upper);
    }
    piece
}

/// The number of the first crossing of each plane, and (last) the total, or an
/// error if the surface has too many vertices for 32-bit numbers.
fn plane_bases(grid: &Grid) -> Result<Vec<u32>> {
    let counts: Vec<u64> = (0..grid.dims[2])
        .into_par_iter()
        .map(|k| {
            let mut count = 0u64;
            grid.scan_plane(k, |_, _, _| count += 1);
            count
        })
        .collect();
    let mut bases = Vec::with_capacity(counts.len() + 1);
    let mut total = 0u64;
    bases.push(0);
    for count in counts {
        total += count;
        bases.push(
            u32::try_from(total)
                .ok()
                .filter(|&t| t < CENTRE)
                .ok_or_else(too_many)?,
        );
    }
    Ok(bases)
}

fn too_many() -> Error {
    Error::Argument("the isosurface has more than 2^31 vertices".into())
}

/// Join the slabs' pieces in order, numbering the centres after all crossings.
fn join(pieces: Vec<Piece>, crossings: u32) -> Result<Extraction> {
    let centres: usize = pieces.iter().map(|p| p.centres.len()).sum();
    let total = crossings as usize + centres;
    if total >= CENTRE as usize {
        return Err(too_many());
    }
    let triangles: usize = pieces.iter().map(|p| p.triangles.len()).sum();
    let mut out = Extraction {
        positions: Vec::with_capacity(total),
        sources: Vec::with_capacity(total),
        triangles: Vec::with_capacity(triangles),
        face_cells: Vec::with_capacity(triangles),
    };
    for piece in &pieces {
        out.positions.extend_from_slice(&piece.points);
        out.sources.extend_from_slice(&piece.sources);
    }
    for piece in pieces {
        let first_centre = out.positions.len() as u32;
        let number = |v: u32| {
            if v & CENTRE != 0 {
                first_centre + (v & !CENTRE)
            } else {
                v
            }
        };
        out.triangles
            .extend(piece.triangles.iter().map(|t| t.map(number)));
        out.face_cells.extend_from_slice(&piece.face_cells);
        out.positions.extend_from_slice(&piece.centres);
        let cells = piece.centre_cells.iter();
        out.sources
            .extend(cells.map(|&cell| VertexSource::Cell { cell }));
    }
    Ok(out)
}

/// The polygons of every cell of `volume` at `level`, triangulated. The samples
/// must be finite and every dimension at least 2 (checked by the caller).
pub(super) fn extract(volume: &Volume, level: f64) -> Result<Extraction> {
    let grid = Grid::new(volume, level);
    let bases = plane_bases(&grid)?;
    let layers = grid.dims[2] - 1;
    let pieces: Vec<Piece> = (0..layers.div_ceil(SLAB_LAYERS))
        .into_par_iter()
        .map(|s| {
            let first = s * SLAB_LAYERS;
            slab(&grid, &bases, first, (first + SLAB_LAYERS).min(layers))
        })
        .collect();
    join(pieces, bases[grid.dims[2]])
}
