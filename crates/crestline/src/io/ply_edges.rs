//! The edges of a PLY file, as line files hold them: a `vertex` element with
//! scalar `x`, `y`, `z` and an `edge` element with `vertex1` and `vertex2`, and
//! optionally the scalars `kind` (a [`crate::lines::LineKind::code`]) and `line`
//! (the index of the polyline an edge belongs to) that the lines' PLY writer adds.
//! ASCII and binary files of either byte order, through the mesh reader's header
//! and record parsers.

use super::ply_header;
use super::ply_records::read_element;
use super::Input;
use crate::{Error, Point, Result, Space};

/// The points and edges of a PLY file, and the frame its header marks.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct PlyEdges {
    pub(crate) positions: Vec<Point>,
    pub(crate) edges: Vec<PlyEdge>,
    pub(crate) space: Option<Space>,
    /// Whether it has faces too (a mesh).
    pub(crate) faces: bool,
}

/// One record of the `edge` element.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PlyEdge {
    /// The indices of its two vertices.
    pub(crate) ends: [usize; 2],
    /// The `kind` property, if the element has one.
    pub(crate) kind: Option<f64>,
    /// The `line` property, if the element has one.
    pub(crate) line: Option<f64>,
}

/// The edges of the PLY file in `bytes` (errors do not name the file: see
/// [`Error::in_file`]). A file without an `edge` element has none; one without a
/// `vertex` element, or whose edges refer to vertices it does not have, is an
/// error.
pub(crate) fn read_ply_edges(bytes: &[u8]) -> Result<PlyEdges> {
    if bytes.is_empty() {
        return Err(Error::Parse("the file is empty".to_string()));
    }
    let mut input = Input::new(bytes, None);
    let header = ply_header::read_header(&mut input)?;
    ply_header::check_counts_fit(&header, input.rest())?;
    let mut found = PlyEdges {
        space: super::declared_space(bytes),
        ..PlyEdges::default()
    };
    for element in &header.elements {
        match element.name.as_str() {
            "vertex" => {
                let [x, y, z] = ["x", "y", "z"].map(|name| element.scalar_column(name));
                let xyz = [x?, y?, z?];
                read_element(&mut input, header.encoding, element, None, |record| {
                    let p = xyz.map(|c| record.scalars[c]);
                    found.positions.push(Point::new(p[0], p[1], p[2]));
                    Ok(())
                })?;
            }
            "edge" => {
                let ends = [
                    element.scalar_column("vertex1")?,
                    element.scalar_column("vertex2")?,
                ];
                let (kind, line) = (
                    element.scalar_column("kind").ok(),
                    element.scalar_column("line").ok(),
                );
                read_element(&mut input, header.encoding, element, None, |record| {
                    let [a, b] = ends.map(|c| record.scalars[c]).map(vertex_index);
                    found.edges.push(PlyEdge {
                        ends: [a?, b?],
                        kind: kind.map(|c| record.scalars[c]),
                        line: line.map(|c| record.scalars[c]),
                    });
                    Ok(())
                })?;
            }
            other => {
                found.faces |= other == "face" && element.count > 0;
                read_element(&mut input, header.encoding, element, None, |_| Ok(()))?;
            }
        }
    }
    let n = found.positions.len();
    if let Some(edge) = found.edges.iter().find(|e| e.ends.iter().any(|&v| v >= n)) {
        return Err(Error::Parse(format!(
            "an edge joins vertices {} and {}, but the file has {n} vertices",
            edge.ends[0], edge.ends[1]
        )));
    }
    Ok(found)
}

/// A vertex index read as a number: a whole number, at least 0.
fn vertex_index(value: f64) -> std::result::Result<usize, String> {
    if value >= 0.0 && value.fract() == 0.0 && value < u32::MAX as f64 {
        Ok(value as usize)
    } else {
        Err(format!("{value} is not a vertex index"))
    }
}
