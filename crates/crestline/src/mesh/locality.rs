//! Renumbering a soup whose vertex order is scattered, so that every stage after
//! the build reads its per-vertex arrays mostly from nearby memory.
//!
//! A subdivided or re-exported scan may list a vertex's neighbours millions of
//! entries apart (midpoint subdivision appends every new vertex after the old
//! ones), and then every stage that walks the surface misses the caches at each
//! step. Such soups get their vertices along the Morton curve of their positions
//! ([`morton_order`]) and their faces in the order of their first vertex; soups in
//! a local order already (a scan's or a marching cubes' order) are left alone, so
//! that their vertices keep the numbers of the file.

use rayon::prelude::*;

use super::morton::{morton_order, ranks};
use super::{Mesh, RepairReport, TriangleSoup};
use crate::Result;

/// How far apart in the vertex list the corners of a face may lie and still be
/// near in memory: 2¹⁶ positions take 1.5 MB, about what a core's caches hold.
const NEAR: u32 = 1 << 16;

impl Mesh {
    /// [`Mesh::from_soup`] (or, if `strict`, [`Mesh::from_soup_strict`]) for a
    /// soup read from a file, renumbered first if its vertex order is scattered:
    /// if over half of its faces have corners more than 2¹⁶ entries apart in the
    /// vertex list, its vertices go along the Morton curve of their positions and
    /// its faces in the order of their first corner, so that the stages after the
    /// build read nearby memory. [`Mesh::input_vertices`] still name the file's
    /// vertices, so per-vertex results go back to the file's order through
    /// [`Mesh::to_input_order`].
    pub fn from_file_soup(soup: TriangleSoup, strict: bool) -> Result<(Mesh, RepairReport)> {
        let build = if strict {
            Mesh::from_soup_strict
        } else {
            Mesh::from_soup
        };
        if !is_scattered(&soup) {
            return build(soup);
        }
        let (soup, rank) = in_locality_order(soup);
        let (mut mesh, report) = build(soup)?;
        mesh.input_vertices = rank
            .iter()
            .map(|&r| mesh.input_vertices[r as usize])
            .collect();
        Ok((mesh, report))
    }
}

/// Whether most faces (over half) have corners further than [`NEAR`] apart in the
/// vertex list.
fn is_scattered(soup: &TriangleSoup) -> bool {
    let far = soup
        .triangles
        .par_iter()
        .filter(|&&[a, b, c]| a.max(b).max(c) - a.min(b).min(c) > NEAR)
        .count();
    2 * far > soup.triangles.len()
}

/// The soup with its vertices in Morton order and its faces ordered by their
/// first corner (each keeps its corners' cyclic order, so its orientation), and
/// the new number of each vertex.
fn in_locality_order(mut soup: TriangleSoup) -> (TriangleSoup, Vec<u32>) {
    let order = morton_order(&soup.positions);
    let rank = ranks(&order);
    soup.positions = order
        .par_iter()
        .map(|&v| soup.positions[v as usize])
        .collect();
    for property in &mut soup.vertex_scalars {
        property.values = order.iter().map(|&v| property.values[v as usize]).collect();
    }
    soup.triangles
        .par_iter_mut()
        .for_each(|t| *t = t.map(|v| rank[v as usize]));
    soup.triangles = by_first_corner(&soup.triangles, rank.len());
    (soup, rank)
}

/// The triangles (over `vertex_count` vertices) ordered by their first corner: a
/// counting sort, linear and stable.
fn by_first_corner(triangles: &[[u32; 3]], vertex_count: usize) -> Vec<[u32; 3]> {
    let mut start = vec![0u32; vertex_count + 1];
    for t in triangles {
        start[t[0] as usize + 1] += 1;
    }
    for k in 0..vertex_count {
        start[k + 1] += start[k];
    }
    let mut sorted = vec![[0; 3]; triangles.len()];
    for t in triangles {
        let slot = &mut start[t[0] as usize];
        sorted[*slot as usize] = *t;
        *slot += 1;
    }
    sorted
}

#[cfg(test)]
mod tests;
