//! Wavefront OBJ: reading `v` and `f` records, writing vertices and triangles.
//!
//! The reader is hand-written rather than built on `tobj`: `tobj` renumbers vertices
//! in order of first use (dropping unreferenced ones) and splits the file by group,
//! so its indices are not the file's vertex numbers, and it reports errors without a
//! line number.

use std::io::{self, Write};
use std::path::Path;

use super::{line_error, parse_number, parse_point, push_polygon, Input};
use crate::mesh::{Mesh, TriangleSoup};
use crate::{Point, Result, Space};

/// Read an OBJ file from memory.
///
/// Reads the `v x y z` records (any further values such as `w` or vertex colours are
/// ignored) and the `f` records, whose corners may be written `v`, `v/vt`, `v/vt/vn`
/// or `v//vn`, with 1-based or negative (relative) indices; polygons are fanned into
/// triangles. Faces may refer to vertices defined later in the file. All other
/// records (normals, texture coordinates, groups, materials, lines) are ignored.
#[cfg(test)]
pub fn read_obj(bytes: &[u8]) -> Result<TriangleSoup> {
    super::parse_bytes(bytes, None, parse)
}

/// The largest vertex index referred to so far and the line that refers to it.
#[derive(Default)]
struct LargestIndex {
    index: u32,
    line: usize,
}

pub(super) fn parse(input: &mut Input<'_>) -> Result<TriangleSoup> {
    let mut soup = TriangleSoup::default();
    let mut largest = LargestIndex::default();
    let mut scratch = Vec::new();
    let mut corners = Vec::new();
    while let Some(record) = input.next_record()? {
        let mut tokens = record.split_ascii_whitespace();
        let line = input.line();
        match tokens.next() {
            Some("v") => {
                let point = parse_point(&mut tokens).map_err(|m| line_error(line, m))?;
                soup.positions.push(point);
            }
            Some("f") => {
                corners.clear();
                for token in tokens {
                    let index = face_corner(token, soup.positions.len())
                        .map_err(|m| line_error(line, m))?;
                    if index >= largest.index {
                        largest = LargestIndex { index, line };
                    }
                    corners.push(i64::from(index));
                }
                // Indices are checked against the final vertex count below.
                push_polygon(
                    corners.iter().copied(),
                    u32::MAX as usize,
                    &mut scratch,
                    &mut soup.triangles,
                )
                .map_err(|m| line_error(line, m))?;
            }
            _ => {}
        }
    }
    if !soup.triangles.is_empty() && largest.index as usize >= soup.positions.len() {
        return Err(line_error(
            largest.line,
            format!(
                "a face refers to vertex {}, but the file has only {} vertices",
                u64::from(largest.index) + 1,
                soup.positions.len()
            ),
        ));
    }
    Ok(soup)
}

/// The 0-based vertex index of a face corner such as `7`, `7/3`, `7//2` or `-1`;
/// `defined` is the number of vertices read so far (for relative indices).
fn face_corner(token: &str, defined: usize) -> std::result::Result<u32, String> {
    let vertex = token.split('/').next().unwrap_or(token);
    let index: i64 = parse_number(vertex)?;
    let resolved = match index {
        0 => return Err("vertex index 0 in a face (OBJ indices start at 1)".to_string()),
        i if i > 0 => i - 1,
        i => defined as i64 + i,
    };
    if resolved < 0 {
        return Err(format!(
            "relative vertex index {index} points before the first vertex ({defined} defined so far)"
        ));
    }
    u32::try_from(resolved)
        .ok()
        .filter(|&i| i < u32::MAX)
        .ok_or_else(|| format!("vertex index {index} is too large"))
}

/// Write `mesh` as an OBJ file: one `v x y z` line per vertex (full `f64` precision,
/// so reading the file back gives the same coordinates) and one 1-based `f a b c`
/// line per triangle. The file is written atomically.
pub fn write_obj(path: &Path, mesh: &Mesh) -> Result<()> {
    write_triangles_obj(path, mesh.positions(), &mesh.triangles(), mesh.space())
}

/// The `v x y z` record of every point, in full `f64` precision: the vertices of
/// a mesh's file and of a lines file alike.
pub(crate) fn write_vertices<'a>(
    w: &mut impl Write,
    points: impl IntoIterator<Item = &'a Point>,
) -> io::Result<()> {
    for p in points {
        writeln!(w, "v {} {} {}", p.x, p.y, p.z)?;
    }
    Ok(())
}

/// [`write_obj`] for any indexed triangles (checked by the caller to be in range),
/// with their frame marked in a leading comment as 3D Slicer does.
pub(super) fn write_triangles_obj(
    path: &Path,
    positions: &[Point],
    triangles: &[[u32; 3]],
    space: Option<Space>,
) -> Result<()> {
    crate::atomic::write_atomically(path, |w| {
        if let Some(space) = space {
            writeln!(w, "# {}", space.slicer_mark())?;
        }
        write_vertices(w, positions)?;
        for triangle in triangles {
            let [a, b, c] = triangle.map(|v| u64::from(v) + 1);
            writeln!(w, "f {a} {b} {c}")?;
        }
        Ok(())
    })
}
