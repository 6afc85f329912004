//! The baseline that Schultz, Theisel and Seidel (2010), "Crease Surfaces: From
//! Theory to Extraction and Application to Diffusion Tensor MRI", §5 (Tables 2–3),
//! compare their crease surfaces with: marching cubes of g·e3 after orienting the
//! eigenvectors e3 per cell.

use std::collections::HashMap;

use super::edges::CrossingOptions;
use super::field::CreaseField;
use super::surface::{compact, Mesh};
use crate::isosurface::cell::{
    crossing_fraction, decide_faces, is_fanned, triangulate, CaseTable, EDGES,
};
use crate::mesh::TriangleSoup;
use crate::volume::grid::cell_corner;
use crate::Vector;

/// The ridge surface of `field` as plain marching cubes extract it: the baseline of
/// Schultz, Theisel and Seidel 2010, §5 (Tables 2–3), where marching cubes of g·e3
/// after a per-cell orientation of e3 are compared with the crease surface.
///
/// In each cell, the eigenvectors e3 at its eight corners are oriented to corner
/// 0's (e → −e where e·e3₀ < 0), and the values g·e3 at the corners are contoured
/// at 0 with the isosurface's case table ([`crate::isosurface::isosurface()`]: inside
/// is g·e3 ≥ 0, the asymptotic decider on ambiguous faces, polygons of more than
/// three corners fanned around their barycentre). A crossed cell edge carries one
/// vertex, at the linear interpolation of g·e3, keyed by its grid edge: two cells
/// that both cross an edge place the crossing at the same point (its fraction does
/// not depend on the edge's orientation) and share it. Where the orientations of
/// neighbouring cells disagree, one may cross an edge that the other does not, and
/// the surface has a crack there; nothing closes it (the paper's §3.2: around a
/// Hessian degeneracy e3 cannot be oriented consistently; Table 3 counts the short
/// boundary components this leaves).
///
/// The side constraint as for [`super::crease_surface`]: triangles with a vertex
/// where −λ3 (interpolated linearly along the edge, averaged at a barycentre) is
/// below `options.strength` are dropped, not trimmed. For valleys the field holds
/// −f ([`CreaseField::new`]), so the same rule keeps valleys of f. The soup carries
/// the vertex scalars [`super::STRENGTH`] and [`super::DEGENERATE`] (0 everywhere:
/// marching cubes find no degenerate points). Only `options.strength` is read.
#[cfg(test)]
pub fn oriented_marching_cubes(field: &CreaseField, options: &CrossingOptions) -> TriangleSoup {
    let grid = field.grid();
    let table = CaseTable::get();
    let mut vertices: HashMap<u64, u32> = HashMap::new();
    let mut positions = Vec::new();
    let mut strength = Vec::new();
    let mut triangles = Vec::new();
    for cell in grid.cells(0..grid.cell_layers()) {
        let corners: [[usize; 3]; 8] = std::array::from_fn(|c| cell_corner(cell, c));
        let samples = corners.map(|c| field.sample(c));
        let reference = samples[0].frame.e3;
        let values = samples.map(|s| {
            let e3 = if s.frame.e3.dot(&reference) < 0.0 {
                -s.frame.e3
            } else {
                s.frame.e3
            };
            s.gradient.dot(&e3)
        });
        let mask = (0..8)
            .filter(|&c| values[c] >= 0.0)
            .fold(0u8, |bits, c| bits | (1 << c));
        if mask == 0 || mask == u8::MAX {
            continue;
        }
        let connected = decide_faces(table.ambiguous_faces(mask), &values, 0.0);
        let mut ids = [0u32; 12];
        for polygon in table.polygons(mask, connected).iter() {
            for (n, &edge) in polygon.iter().enumerate() {
                let (a, axis) = EDGES[edge as usize];
                let b = a | (1 << axis);
                let key = grid.key(corners[a], axis);
                ids[n] = *vertices.entry(key).or_insert_with(|| {
                    let t = crossing_fraction(values[a], values[b], 0.0);
                    let (pa, pb) = (field.position(corners[a]), field.position(corners[b]));
                    positions.push(pa + (pb - pa) * t);
                    let l3 = |c: usize| samples[c].frame.eigenvalues[2];
                    strength.push(-(l3(a) * (1.0 - t) + l3(b) * t));
                    (positions.len() - 1) as u32
                });
            }
            let ids = &ids[..polygon.len()];
            let mut centre = 0;
            if is_fanned(ids.len()) {
                let n = ids.len() as f64;
                let sum = ids.iter().map(|&v| positions[v as usize].coords);
                positions.push((sum.sum::<Vector>() / n).into());
                strength.push(ids.iter().map(|&v| strength[v as usize]).sum::<f64>() / n);
                centre = (positions.len() - 1) as u32;
            }
            triangles.extend(triangulate(ids, centre));
        }
    }
    let strong = |t: &[u32; 3]| t.iter().all(|&v| strength[v as usize] >= options.strength);
    let triangles = triangles.into_iter().filter(strong).collect();
    compact(
        Mesh {
            degenerate: vec![0.0; positions.len()],
            positions,
            strength,
            triangles,
        },
        field.space(),
    )
}
