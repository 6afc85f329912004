//! Isosurfaces `f = I` of a volume as closed, oriented triangle meshes, after
//! Thirion & Gourdon 1993 ("The 3D marching lines algorithm"), second part §2–3,
//! with the conventions of docs/design/images.md ("Isosurfaces and implicit curvature").
//!
//! - **Inside** is `f ≥ I` (the object/background convention: a sample equal to the
//!   level is inside). A grid edge whose two samples differ in this respect carries
//!   one vertex, at the linear interpolation of `f`, kept a fraction 10⁻⁴ of the edge
//!   away from its ends so that the crossings of edges meeting at a sample equal to
//!   `I` stay distinct (the paper's ε shift). The vertex belongs to the edge, so all
//!   cells around the edge share it.
//! - On each face of a cell, segments join the crossings (BUILDSEGMENTS). On an
//!   ambiguous face (inside corners on one diagonal) the asymptotic decider chooses:
//!   `v̂ = (s00 s11 − s10 s01) / (s00 + s11 − s10 − s01)`, and `v̂ ≥ I` joins the
//!   two inside corners. The four values are read in an order fixed by the face's
//!   place in the grid, so the two cells of a face make the same choice.
//! - The segments of a cell's six faces chain into closed polygons (BUILDCYCLES),
//!   counter-clockwise seen from outside (`f < I`): face normals point toward
//!   decreasing `f`, along `n = −∇f/|∇f|`. A polygon of three corners is one
//!   triangle; a larger one is fanned around its barycentre, a vertex of its own.
//! - Inside a cell, nothing more is decided: as in the paper, each cycle is its own
//!   polygon, so where the trilinear interpolant would join two cycles by a tunnel
//!   through the cell, the surface keeps them apart. Every face segment belongs to
//!   exactly one polygon on each side of its face, run in opposite directions, so
//!   the surface is a closed, consistently oriented manifold whatever the cell
//!   interiors look like; at the border of the volume it is open.
//!
//! Positions are in world coordinates (origin, spacing, direction of the
//! [`Volume`]). A mirrored grid (direction of negative determinant) has its
//! triangles wound the other way, so normals still point toward decreasing `f`.
//! The cells are processed in parallel over slabs of z; the output does not depend
//! on the number of threads. Vertices are numbered plane by plane of crossings,
//! then polygon centres; [`Isosurface::source`] tells which grid edge (and where on
//! it) or cell each vertex comes from, and [`Isosurface::to_mesh`] builds the
//! half-edge [`Mesh`] with the same numbers, keeping the orientation (a cavity's
//! surface faces into the cavity).
//!
//! Bad input is an error, never a panic: a non-finite sample (naming its voxel; a
//! NaN is not read as outside, which would silently turn missing data into
//! surface), a non-finite level, a volume less than 2 samples thick, or a level
//! that no grid edge crosses (no surface; the message gives the samples' range).

pub(crate) mod cell;
mod slab;

use rayon::prelude::*;

use crate::error::readable;
use crate::mesh::{Mesh, TriangleSoup};
use crate::volume::grid::edge_of_key;
use crate::volume::Volume;
use crate::{Error, Result};

/// Where a vertex of an [`Isosurface`] comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum VertexSource {
    /// The crossing on the grid edge from sample `point` (a linear index into
    /// [`Volume::samples`]) one step along index axis `axis` (0, 1, 2 for x, y, z),
    /// a fraction `t` of the way (in `(0, 1)`). The crossing is keyed by the grid
    /// edge, `3 · point + axis`, and shared by all cells around it.
    Edge {
        /// Linear index of the edge's first sample.
        point: u64,
        /// Index axis of the edge.
        axis: u8,
        /// Position along the edge, as a fraction of its length from `point`.
        t: f64,
    },
    /// The barycentre of a polygon of more than three corners in the cell whose
    /// lowest corner is sample `cell` (a linear index into [`Volume::samples`]).
    Cell {
        /// Linear index of the cell's lowest corner.
        cell: u64,
    },
}

/// Marks the key of a cell (its centre vertex) rather than of a grid edge.
const CELL: u64 = 1 << 63;

/// The key of the cell whose lowest corner is sample `cell`.
fn cell_key(cell: u64) -> u64 {
    CELL | cell
}

impl VertexSource {
    /// The source with key `key` (see [`edge_key`](crate::volume::grid::edge_key),
    /// [`cell_key`]) and fraction `t`.
    fn from_key(key: u64, t: f64) -> VertexSource {
        if key & CELL != 0 {
            VertexSource::Cell { cell: key & !CELL }
        } else {
            let (point, axis) = edge_of_key(key);
            VertexSource::Edge {
                point: point as u64,
                axis: axis as u8,
                t,
            }
        }
    }
}

/// An isosurface of a volume: shared vertices and triangles, and where each vertex
/// comes from. [`Isosurface::to_mesh`] connects it into a half-edge [`Mesh`] with
/// the same vertex and face numbers.
#[derive(Clone, Debug)]
pub struct Isosurface {
    soup: TriangleSoup,
    /// Per vertex, the key of its grid edge or cell and its fraction along the edge.
    keys: Vec<u64>,
    fractions: Vec<f64>,
}

impl Isosurface {
    /// Vertex positions (world coordinates) and triangles, counter-clockwise seen
    /// from `f < I`; every edge has two triangles running along it in opposite
    /// directions, except at the border of the volume.
    pub fn soup(&self) -> &TriangleSoup {
        &self.soup
    }

    /// The vertices and triangles, without the sources.
    pub fn into_soup(self) -> TriangleSoup {
        self.soup
    }

    /// Where vertex `v` (an index into `soup().positions`) comes from.
    ///
    /// Panics if `v` is not a vertex.
    pub fn source(&self, v: usize) -> VertexSource {
        VertexSource::from_key(self.keys[v], self.fractions[v])
    }

    /// Where each vertex comes from, in vertex order.
    pub fn sources(&self) -> impl ExactSizeIterator<Item = VertexSource> + '_ {
        let pairs = self.keys.iter().zip(&self.fractions);
        pairs.map(|(&key, &t)| VertexSource::from_key(key, t))
    }

    /// The surface as a half-edge [`Mesh`], vertex `v` and face `f` being
    /// `soup().positions[v]` and `soup().triangles[f]`: a manifold, oriented as the
    /// triangles are (a closed component around a cavity keeps its negative volume),
    /// closed except at the border of the volume.
    ///
    /// Errors ([`Error::Stage`]) if building the mesh would need a repair, which the
    /// construction rules out.
    pub fn to_mesh(&self) -> Result<Mesh> {
        let (mesh, report) = Mesh::from_oriented_soup(self.soup.clone())?;
        if report.is_clean() {
            Ok(mesh)
        } else {
            Err(Error::Stage {
                stage: "isosurface".into(),
                message: format!("the extracted surface needed repairs: {report}"),
            })
        }
    }
}

/// The isosurface `f = level` of `volume` (Thirion & Gourdon 1993, §2–3; see the
/// source file `isosurface/mod.rs` for the conventions): inside is `f ≥ level`, faces
/// are split by the asymptotic decider, and each cell's polygons (BUILDCYCLES) are
/// triangulated, so the surface is closed, manifold and consistently oriented
/// except at the volume border, with normals toward decreasing `f`.
///
/// Errors ([`Error::Argument`]): `level` is not finite, a dimension of the volume is
/// below 2 (there are no cells), a sample is not finite (naming the voxel), or no
/// grid edge crosses the level (no surface; the message gives the range of the
/// samples).
pub fn isosurface(volume: &Volume, level: f64) -> Result<Isosurface> {
    check_input(volume, level)?;
    let extraction = slab::extract(volume, level)?;
    if extraction.triangles.is_empty() {
        return Err(no_surface(volume, level));
    }
    Ok(Isosurface {
        soup: TriangleSoup {
            positions: extraction.positions,
            triangles: extraction.triangles,
            vertex_scalars: Vec::new(),
            space: volume.space(),
            volume_geometry: None,
        },
        keys: extraction.keys,
        fractions: extraction.fractions,
    })
}

/// Refuse a non-finite level, a volume without cells and non-finite samples.
pub(crate) fn check_input(volume: &Volume, level: f64) -> Result<()> {
    if !level.is_finite() {
        return Err(Error::Argument(format!(
            "the isosurface level {level} is not finite"
        )));
    }
    let dims = volume.dims();
    if dims.iter().any(|&n| n < 2) {
        return Err(Error::Argument(format!(
            "an isosurface needs at least 2 samples along each axis, the volume has {}×{}×{}",
            dims[0], dims[1], dims[2]
        )));
    }
    // A branch-free pass over blocks first (a search that stops early is much
    // slower): the position is looked for only if there is a bad sample.
    let samples = volume.samples();
    let all_finite = |block: &[f32]| block.iter().fold(true, |ok, v| ok & v.is_finite());
    if samples.par_chunks(1 << 16).all(all_finite) {
        return Ok(());
    }
    match samples.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(at) => {
            let [i, j, k] = volume.grid().position_of(at);
            Err(Error::Argument(format!(
                "the sample at voxel ({i}, {j}, {k}) is {}: an isosurface needs finite samples",
                volume.samples()[at]
            )))
        }
    }
}

/// The error for a level that no grid edge crosses.
fn no_surface(volume: &Volume, level: f64) -> Error {
    let (low, high) = volume.value_range();
    Error::Argument(format!(
        "no isosurface at level {}: no grid edge crosses it (the samples range over \
         [{}, {}])",
        readable(level),
        readable(low.into()),
        readable(high.into())
    ))
}
