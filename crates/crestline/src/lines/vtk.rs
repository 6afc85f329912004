//! Legacy ASCII VTK output (`# vtk DataFile Version 3.0`, `DATASET POLYDATA`), as
//! read by ParaView and VisIt, through the crate's one VTK writer.

use std::io::{self, Write};
use std::path::Path;

use super::indexing::{indexed, point_values, points, shared_value_names};
use super::{write_checked, FeatureLines, FORMAT};
use crate::io::vtk::{self, Attachment, CellType};
use crate::Result;

/// Write `lines` to `path` as a legacy ASCII VTK poly-data file: `POINTS` (double),
/// one `LINES` cell per polyline (a closed line repeats its first point index at
/// the end), and `CELL_DATA` with the scalars `strength` (double) and `kind` (int,
/// the [`LineKind::code`](super::LineKind::code)), and `POINT_DATA` with one double
/// scalar per named per-point value that every line has. The title holds the
/// format and the source (ASCII, at most 255 bytes). Checks as
/// [`super::write_json`] does.
pub fn write_vtk(path: &Path, lines: &FeatureLines) -> Result<()> {
    write_checked(path, lines, |w| {
        let text = format!("{FORMAT} feature lines from {}", lines.source);
        vtk::write_header(w, &vtk::title(&text, lines.space))?;
        vtk::write_points(w, lines.point_count(), points(lines))?;
        vtk::write_cells(w, CellType::Lines, || {
            indexed(lines).map(|item| item.path())
        })?;
        write_cell_data(w, lines)?;
        write_point_data(w, lines)
    })
}

/// Per-line `strength` and `kind` scalars; nothing when there are no lines.
fn write_cell_data(w: &mut impl Write, lines: &FeatureLines) -> io::Result<()> {
    if lines.is_empty() {
        return Ok(());
    }
    vtk::write_data(w, Attachment::Cells, lines.len())?;
    vtk::write_scalars(w, "strength", lines.iter().map(|line| line.strength))?;
    vtk::write_scalars(
        w,
        "kind",
        lines.iter().map(|line| i32::from(line.kind.code())),
    )
}

/// The shared per-point values as `POINT_DATA` scalars; nothing when there are none.
fn write_point_data(w: &mut impl Write, lines: &FeatureLines) -> io::Result<()> {
    let names = shared_value_names(lines);
    if names.is_empty() {
        return Ok(());
    }
    vtk::write_data(w, Attachment::Points, lines.point_count())?;
    for name in names {
        vtk::write_scalars(w, name, point_values(lines, name))?;
    }
    Ok(())
}
