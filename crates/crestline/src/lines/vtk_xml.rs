//! VTK XML files of lines (ASCII): poly data (`.vtp`, one polyline cell per line;
//! ParaView, VTK, 3D Slicer) and unstructured grids (`.vtu`, one line-segment cell
//! per edge, the cell type meshio reads; ParaView, VTK, 3D Slicer, meshio). Both
//! hold the points, the shared per-point values and the per-cell `strength` and
//! `kind` (and `line`, the polyline of a segment, in `.vtu`).
//!
//! The frame: `.vtp` has it as 3D Slicer writes it
//! (`vtkMRMLModelStorageNode::WriteDataInternal`), a field-data string array named
//! `SPACE`. meshio refuses files with string arrays, so `.vtu` has its points in
//! LPS, the frame 3D Slicer gives a file that declares none, and says so in a
//! comment only.

use std::io::{self, Write};
use std::path::Path;

use super::indexing::{indexed, point_values, points, shared_value_names};
use super::{one_line, write_checked, FeatureLines, FORMAT};
use crate::xml::escape;
use crate::{Result, Space};

/// Write `lines` to `path` as VTK XML poly data (see the module documentation).
/// A closed line repeats its first point index at the end. Checks as
/// [`super::write_json`] does.
pub fn write_vtp(path: &Path, lines: &FeatureLines) -> Result<()> {
    write_checked(path, lines, |w| {
        let piece = format!(
            r#"NumberOfPoints="{}" NumberOfVerts="0" NumberOfLines="{}" NumberOfStrips="0" NumberOfPolys="0""#,
            lines.point_count(),
            lines.len()
        );
        write_start(w, lines, "PolyData")?;
        write_field_data(w, lines)?;
        writeln!(w, "<Piece {piece}>")?;
        write_point_data(w, lines)?;
        writeln!(w, "<CellData>")?;
        write_array(
            w,
            ("Float64", "strength", 1),
            lines.iter().map(|l| l.strength),
        )?;
        write_array(w, ("Int32", "kind", 1), lines.iter().map(|l| l.kind.code()))?;
        writeln!(w, "</CellData>")?;
        write_points(w, lines)?;
        let ends = indexed(lines).scan(0, |end, line| {
            *end += line.path_len();
            Some(*end)
        });
        writeln!(w, "<Lines>")?;
        write_array(
            w,
            ("Int64", "connectivity", 1),
            indexed(lines).flat_map(|l| l.path().collect::<Vec<_>>()),
        )?;
        write_array(w, ("Int64", "offsets", 1), ends)?;
        writeln!(w, "</Lines>")?;
        writeln!(w, "</Piece>\n</PolyData>\n</VTKFile>")
    })
}

/// Write `lines` to `path` as a VTK XML unstructured grid of line segments (see
/// the module documentation). Checks as [`super::write_json`] does.
pub fn write_vtu(path: &Path, lines: &FeatureLines) -> Result<()> {
    let lines = &lines.in_space(Space::Lps);
    write_checked(path, lines, |w| {
        let segments =
            || indexed(lines).flat_map(|l| l.edges().map(move |e| (l.number, l.line, e)));
        let count = segments().count();
        let piece = format!(
            r#"NumberOfPoints="{}" NumberOfCells="{count}""#,
            lines.point_count()
        );
        write_start(w, lines, "UnstructuredGrid")?;
        writeln!(w, "<Piece {piece}>")?;
        write_point_data(w, lines)?;
        writeln!(w, "<CellData>")?;
        write_array(
            w,
            ("Float64", "strength", 1),
            segments().map(|(_, l, _)| l.strength),
        )?;
        write_array(
            w,
            ("Int32", "kind", 1),
            segments().map(|(_, l, _)| l.kind.code()),
        )?;
        write_array(w, ("Int64", "line", 1), segments().map(|(n, _, _)| n))?;
        writeln!(w, "</CellData>")?;
        write_points(w, lines)?;
        writeln!(w, "<Cells>")?;
        write_array(
            w,
            ("Int64", "connectivity", 1),
            segments().flat_map(|(_, _, (a, b))| [a, b]),
        )?;
        write_array(w, ("Int64", "offsets", 1), (1..=count).map(|n| 2 * n))?;
        write_array(w, ("UInt8", "types", 1), (0..count).map(|_| VTK_LINE))?;
        writeln!(w, "</Cells>")?;
        writeln!(w, "</Piece>\n</UnstructuredGrid>\n</VTKFile>")
    })
}

/// VTK's cell type of a two-point line segment.
const VTK_LINE: u8 = 3;

/// The XML declaration, a comment with the source (and the frame's mark), and
/// the `VTKFile` and `dataset` elements.
fn write_start(w: &mut impl Write, lines: &FeatureLines, dataset: &str) -> io::Result<()> {
    writeln!(w, r#"<?xml version="1.0"?>"#)?;
    let mark = lines
        .space
        .map(|s| format!(" {}", s.slicer_mark()))
        .unwrap_or_default();
    writeln!(
        w,
        "<!-- {FORMAT} feature lines from {}{mark} -->",
        comment(&lines.source)
    )?;
    writeln!(
        w,
        r#"<VTKFile type="{dataset}" version="1.0" byte_order="LittleEndian" header_type="UInt64">"#
    )?;
    writeln!(w, "<{dataset}>")
}

/// The points, in double precision.
fn write_points(w: &mut impl Write, lines: &FeatureLines) -> io::Result<()> {
    writeln!(w, "<Points>")?;
    let coordinates = points(lines).flat_map(|p| [p.x, p.y, p.z]);
    write_array(w, ("Float64", "Points", 3), coordinates)?;
    writeln!(w, "</Points>")
}

/// The frame as the string array `SPACE` (ASCII strings are their bytes, each
/// ended by a 0), if the lines have one.
fn write_field_data(w: &mut impl Write, lines: &FeatureLines) -> io::Result<()> {
    let Some(space) = lines.space else {
        return Ok(());
    };
    let bytes: Vec<String> = space
        .name()
        .bytes()
        .chain([0])
        .map(|b| b.to_string())
        .collect();
    writeln!(w, "<FieldData>")?;
    writeln!(
        w,
        r#"<Array type="String" Name="SPACE" NumberOfTuples="1" format="ascii">{}</Array>"#,
        bytes.join(" ")
    )?;
    writeln!(w, "</FieldData>")
}

/// The shared per-point values, one array each.
fn write_point_data(w: &mut impl Write, lines: &FeatureLines) -> io::Result<()> {
    writeln!(w, "<PointData>")?;
    for name in shared_value_names(lines) {
        write_array(w, ("Float64", name, 1), point_values(lines, name))?;
    }
    writeln!(w, "</PointData>")
}

/// One ASCII `DataArray` of `values` (`(type, name, components)`), written so that
/// they read back exactly.
fn write_array<V: std::fmt::Display>(
    w: &mut impl Write,
    (kind, name, components): (&str, &str, usize),
    values: impl Iterator<Item = V>,
) -> io::Result<()> {
    write!(
        w,
        r#"<DataArray type="{kind}" Name="{}" NumberOfComponents="{components}" format="ascii">"#,
        escape(name)
    )?;
    for (n, value) in values.enumerate() {
        if n > 0 {
            write!(w, " ")?;
        }
        write!(w, "{value}")?;
    }
    writeln!(w, "</DataArray>")
}

/// `text` inside an XML comment: on one line, without `--`.
fn comment(text: &str) -> String {
    one_line(text).replace("--", "- -")
}
