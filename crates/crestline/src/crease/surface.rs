//! Crease surfaces from the edge crossings and the degenerate points: per face, the
//! points are paired into segments; per cell, the segments of its six faces and the
//! pairs of its degenerate points close into polygons, which are triangulated
//! (Schultz, Theisel and Seidel 2010, §4.3–4.5; docs/design/crease.md, "Crease surfaces").
//! Only the cells with a corner as strong as the strength are built, from
//! crossings of any strength, and the surface is then trimmed along −λ3 = s.

use std::borrow::Cow;
use std::collections::HashMap;

use rayon::prelude::*;

use super::cells::{cell_polygons, CellInput};
use super::degenerate::{degenerate_points, DegeneratePoint};
use super::edge_index::EdgeIndex;
use super::edges::{crossings_in_strong_cells, CrossingOptions, EdgeCrossing};
use super::field::CreaseField;
use super::points::Points;
use super::strong::StrongCells;
use super::trim::trimmed;
use crate::mesh::{ScalarProperty, TriangleSoup};
#[cfg(test)]
use crate::progress::Silent;
use crate::progress::{try_stage, Observer};
use crate::volume::grid::Grid;
use crate::{Point, Result, Space, Vector};

/// The name of the per-vertex ridge strength −λ3 in the surface's soup.
pub const STRENGTH: &str = "strength";

/// The name of the per-vertex mark of degenerate points in the surface's soup: 1 at
/// the points where λ2 = λ3 (on the degenerate lines where the surface ends), 0
/// elsewhere. A boundary edge whose two ends are marked lies on a degenerate line.
/// Fallback points (faces crossed an odd number of times where no degenerate point
/// was found) are 0.
pub const DEGENERATE: &str = "degenerate";

/// The stages of [`crease_surface_observed`], in order, as its observer is told
/// them: the crossings of the grid edges ([`super::edge_crossings`]); the
/// degenerate points of the faces crossed an odd number of times, with their edges
/// searched again at raised θ; the normals at every point; and the pairing per face
/// and per cell, the triangulation, the trimming to the strength and the component
/// filter.
pub const STAGES: [&str; 4] = [
    "crossings",
    "degenerate points",
    "normals",
    "pairing and triangulation",
];

/// The crease surface of `field` with `options`: triangles that need not be
/// consistently orientable, with the ridge strength −λ3 of each vertex as the
/// vertex scalar [`STRENGTH`] and the mark of degenerate points as [`DEGENERATE`],
/// where −λ3 is at least `options.strength` (trimmed along that level). Connected
/// pieces of fewer than `min_component` triangles are dropped; a `min_component`
/// above every triangle found is an error.
#[cfg(test)]
pub fn crease_surface(
    field: &CreaseField,
    options: &CrossingOptions,
    min_component: usize,
) -> Result<TriangleSoup> {
    crease_surface_observed(field, options, min_component, &mut Silent)
}

/// [`crease_surface`], telling `observer` of each of the [`STAGES`] and asking it
/// between them whether to go on ([`crate::Error::Cancelled`] if not).
#[cfg(test)]
pub fn crease_surface_observed(
    field: &CreaseField,
    options: &CrossingOptions,
    min_component: usize,
    observer: &mut dyn Observer,
) -> Result<TriangleSoup> {
    surface_of(Cow::Borrowed(field), options, min_component, observer)
}

/// [`crease_surface_observed`] taking the field, whose values are dropped once the
/// normals are computed (the triangulation needs only its grid), so that they and
/// the surface are not held at once.
pub fn crease_surface_of(
    field: CreaseField,
    options: &CrossingOptions,
    min_component: usize,
    observer: &mut dyn Observer,
) -> Result<TriangleSoup> {
    surface_of(Cow::Owned(field), options, min_component, observer)
}

/// The stages of [`crease_surface_observed`] on a borrowed or owned field.
fn surface_of(
    field: Cow<'_, CreaseField>,
    options: &CrossingOptions,
    min_component: usize,
    observer: &mut dyn Observer,
) -> Result<TriangleSoup> {
    if options.strength < field.least_strength() {
        return Err(crate::Error::Argument(format!(
            "the crease field keeps only creases of strength −λ3 ≥ {}, not {}: survey it \
             for the lower strength",
            field.least_strength(),
            options.strength
        )));
    }
    let [crossings_stage, degenerate_stage, normals_stage, triangulation_stage] = STAGES;
    let (strong, crossings) = try_stage(observer, crossings_stage, || {
        let strong = StrongCells::new(&field, options.strength);
        let crossings = crossings_in_strong_cells(&field, options, &strong);
        Ok((strong, crossings))
    })?;
    let (crossings, degenerate) = try_stage(observer, degenerate_stage, || {
        Ok(degenerate_points(&field, options, crossings, &strong))
    })?;
    let points = try_stage(observer, normals_stage, || {
        Ok(Points::new(
            &field,
            options.epsilon,
            &crossings,
            &degenerate,
        ))
    })?;
    let (grid, space) = (field.grid(), field.space());
    drop(field);
    let (soup, sizes) = try_stage(observer, triangulation_stage, || {
        let pieces = Pieces {
            strong: &strong,
            crossings: &crossings,
            degenerate: &degenerate,
            points: &points,
        };
        Ok(triangulated((grid, space), options, &pieces, min_component))
    })?;
    check_kept(&sizes, min_component, observer)?;
    Ok(soup)
}

/// An error when `min_component` exceeds every triangle found (no value of the
/// surface could pass it); a warning naming the option that emptied the surface
/// otherwise.
fn check_kept(sizes: &PieceSizes, min_component: usize, observer: &mut dyn Observer) -> Result<()> {
    if sizes.total > 0 && min_component > sizes.total {
        return Err(crate::Error::Argument(format!(
            "`min_component` {min_component} is more than the {} triangles of the whole crease surface: no piece could be kept",
            sizes.total
        )));
    }
    if sizes.total == 0 {
        observer.warning("no crease surface is as strong as asked; try a lower `strength`");
    } else if sizes.kept == 0 {
        observer.warning(&format!(
            "every piece of the crease surface has fewer than `min_component` ({min_component}) triangles, the largest {}; try a lower `min_component`",
            sizes.largest
        ));
    }
    Ok(())
}

/// Triangle counts of the surface before and after small pieces are dropped.
struct PieceSizes {
    /// Triangles found.
    total: usize,
    /// Triangles of the largest connected piece.
    largest: usize,
    /// Triangles kept.
    kept: usize,
}

/// What the first three stages of [`crease_surface_observed`] found.
struct Pieces<'a> {
    strong: &'a StrongCells,
    crossings: &'a [EdgeCrossing],
    degenerate: &'a [DegeneratePoint],
    points: &'a Points,
}

/// The last stage of [`crease_surface_observed`]: the polygons of the strong cells,
/// triangulated, trimmed to the strength, the small pieces dropped.
fn triangulated(
    (grid, space): (Grid, Option<Space>),
    options: &CrossingOptions,
    pieces: &Pieces<'_>,
    min_component: usize,
) -> (TriangleSoup, PieceSizes) {
    let Pieces {
        strong,
        crossings,
        degenerate,
        points,
    } = *pieces;
    let index = EdgeIndex::new(crossings);
    let on_face: HashMap<u64, usize> = degenerate
        .iter()
        .enumerate()
        .map(|(n, d)| (d.face, crossings.len() + n))
        .collect();
    let input = CellInput {
        grid,
        index: &index,
        points,
        degenerate: &on_face,
    };
    let polygons: Vec<Vec<Vec<usize>>> = index
        .touched_cells(&grid)
        .par_iter()
        .filter(|&&cell| strong.cell(cell))
        .map(|&cell| cell_polygons(cell, &input))
        .collect();
    let mesh = trimmed(
        triangulate(points, polygons.into_iter().flatten()),
        options.strength,
    );
    let total = mesh.triangles.len();
    let (triangles, largest) =
        large_components(mesh.triangles, mesh.positions.len(), min_component);
    let sizes = PieceSizes {
        total,
        largest,
        kept: triangles.len(),
    };
    (compact(Mesh { triangles, ..mesh }, space), sizes)
}

/// The triangles of the connected pieces (sharing vertices) of at least `min`
/// triangles, and the size of the largest piece.
fn large_components(
    triangles: Vec<[u32; 3]>,
    vertices: usize,
    min: usize,
) -> (Vec<[u32; 3]>, usize) {
    let mut pieces = petgraph::unionfind::UnionFind::<u32>::new(vertices);
    for [a, b, c] in &triangles {
        pieces.union(*a, *b);
        pieces.union(*a, *c);
    }
    let mut size = vec![0usize; vertices];
    for t in &triangles {
        size[pieces.find(t[0]) as usize] += 1;
    }
    let largest = size.iter().copied().max().unwrap_or(0);
    let kept = triangles
        .into_iter()
        .filter(|t| size[pieces.find(t[0]) as usize] >= min)
        .collect();
    (kept, largest)
}

/// Vertices (with their scalars) and triangles before compaction.
pub(super) struct Mesh {
    pub positions: Vec<Point>,
    pub strength: Vec<f64>,
    pub degenerate: Vec<f64>,
    pub triangles: Vec<[u32; 3]>,
}

/// Triangles of the polygons: triangles as they are, quadrilaterals split along
/// their shorter diagonal, larger polygons fanned around their barycentre.
fn triangulate(points: &Points, polygons: impl Iterator<Item = Vec<usize>>) -> Mesh {
    let mut positions = points.position.clone();
    let mut strength = points.strength.clone();
    let mut degenerate: Vec<f64> = points
        .degenerate
        .iter()
        .map(|&d| f64::from(u8::from(d)))
        .collect();
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
                degenerate.push(0.0);
                for k in 0..n {
                    triangles.push([ids[k], ids[(k + 1) % n], c]);
                }
            }
        }
    }
    Mesh {
        positions,
        strength,
        degenerate,
        triangles,
    }
}

/// The surface without the vertices no triangle uses (points whose polygon did not
/// close, pieces dropped for their size), with the vertex scalars [`STRENGTH`] and
/// [`DEGENERATE`], in the frame `space`.
pub(super) fn compact(mesh: Mesh, space: Option<Space>) -> TriangleSoup {
    let Mesh {
        positions,
        strength,
        degenerate,
        mut triangles,
    } = mesh;
    let mut new_id = vec![u32::MAX; positions.len()];
    let mut kept = Vec::new();
    for corner in triangles.iter_mut().flatten() {
        let old = *corner as usize;
        if new_id[old] == u32::MAX {
            new_id[old] = kept.len() as u32;
            kept.push(old);
        }
        *corner = new_id[old];
    }
    let scalar = |name: &str, values: &[f64]| ScalarProperty {
        name: name.to_string(),
        values: kept.iter().map(|&i| values[i]).collect(),
    };
    TriangleSoup {
        positions: kept.iter().map(|&i| positions[i]).collect(),
        vertex_scalars: vec![scalar(STRENGTH, &strength), scalar(DEGENERATE, &degenerate)],
        triangles,
        space,
        volume_geometry: None,
    }
}
