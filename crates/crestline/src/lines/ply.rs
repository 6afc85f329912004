//! Binary little-endian PLY output: an `edge` element holding the segments of all
//! lines, each with its two vertices, the [`LineKind`](super::LineKind) code, the
//! strength and the index of its line.

use std::io::{self, Write};
use std::path::Path;

use super::indexing::{indexed, point_values, points, shared_value_names};
use super::{one_line, write_checked, FeatureLines, LineKind, FORMAT};
use crate::io::ply_header::{self, Element, Property, ScalarType};
use crate::Space;
use crate::{Error, Result};

/// Write `lines` to `path` as a binary little-endian PLY file:
///
/// ```text
/// element vertex <points>   property float x, y, z, and one float property per
///                           named per-point value that every line has
/// element edge <segments>   property int vertex1, int vertex2, uchar kind,
///                           float strength, int line
/// ```
///
/// A closed line contributes the segment from its last point back to its first. The
/// kind codes are listed in a `comment` header line (see [`LineKind::code`]).
/// Besides the checks of [`super::write_json`], every value must fit in a 32-bit
/// float; otherwise the error ([`Error::Argument`]) comes before any file is created.
pub fn write_ply(path: &Path, lines: &FeatureLines) -> Result<()> {
    if let Some(message) = lines.first_problem(crate::io::fits_f32, "not a finite 32-bit float") {
        return Err(Error::Argument(message));
    }
    write_checked(path, lines, |w| {
        write_header(w, lines)?;
        write_vertices(w, lines)?;
        write_edges(w, lines)
    })
}

/// The ASCII header, up to and including `end_header`.
fn write_header(w: &mut impl Write, lines: &FeatureLines) -> io::Result<()> {
    let comments: Vec<String> = [
        format!("{FORMAT} feature lines"),
        format!("source: {}", one_line(&lines.source)),
        format!("edge kind codes: {}", LineKind::code_table()),
        "edge line: index of the polyline the edge belongs to".to_string(),
    ]
    .into_iter()
    .chain(lines.space.map(Space::slicer_mark))
    .collect();
    let vertex = Element {
        name: "vertex".to_string(),
        count: lines.point_count(),
        properties: ["x", "y", "z"]
            .into_iter()
            .chain(shared_value_names(lines))
            .map(|name| Property::scalar(ScalarType::Float, name))
            .collect(),
    };
    let edge = Element {
        name: "edge".to_string(),
        count: indexed(lines).map(|item| item.path_len() - 1).sum(),
        properties: vec![
            Property::scalar(ScalarType::Int, "vertex1"),
            Property::scalar(ScalarType::Int, "vertex2"),
            Property::scalar(ScalarType::UChar, "kind"),
            Property::scalar(ScalarType::Float, "strength"),
            Property::scalar(ScalarType::Int, "line"),
        ],
    };
    ply_header::write_header(w, &comments, &[vertex, edge])
}

/// The `vertex` element: x, y, z and the shared per-point values as little-endian
/// 32-bit floats.
fn write_vertices(w: &mut impl Write, lines: &FeatureLines) -> io::Result<()> {
    let names = shared_value_names(lines);
    let mut columns: Vec<_> = names.iter().map(|name| point_values(lines, name)).collect();
    for p in points(lines) {
        let values = columns.iter_mut().filter_map(|column| column.next());
        for v in [p.x, p.y, p.z].into_iter().chain(values) {
            // Range checked in `write_ply`.
            w.write_all(&(v as f32).to_le_bytes())?;
        }
    }
    Ok(())
}

/// The `edge` element, one record per segment.
fn write_edges(w: &mut impl Write, lines: &FeatureLines) -> io::Result<()> {
    for item in indexed(lines) {
        let kind = item.line.kind.code();
        let strength = item.line.strength as f32;
        let line = ply_int(item.number)?;
        for (a, b) in item.edges() {
            w.write_all(&ply_int(a)?.to_le_bytes())?;
            w.write_all(&ply_int(b)?.to_le_bytes())?;
            w.write_all(&[kind])?;
            w.write_all(&strength.to_le_bytes())?;
            w.write_all(&line.to_le_bytes())?;
        }
    }
    Ok(())
}

/// An index as a PLY `int`; more than `i32::MAX` points or lines do not fit.
fn ply_int(index: usize) -> io::Result<i32> {
    i32::try_from(index).map_err(|_| {
        io::Error::new(
            io::ErrorKind::InvalidData,
            format!("index {index} does not fit in a PLY int"),
        )
    })
}
