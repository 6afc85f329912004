//! Legacy ASCII VTK output (`# vtk DataFile Version 3.0`, `DATASET POLYDATA`), as
//! read by ParaView and VisIt.

use std::io::{self, Write};
use std::path::Path;

use super::indexing::{indexed, point_values, points, shared_value_names};
use super::{one_line, write_checked, FeatureLines, FORMAT};
use crate::Result;

/// The longest title line legacy VTK readers accept, in bytes.
const MAX_TITLE: usize = 255;

/// Write `lines` to `path` as a legacy ASCII VTK poly-data file: `POINTS` (double),
/// one `LINES` cell per polyline (a closed line repeats its first point index at
/// the end), and `CELL_DATA` with the scalars `strength` (double) and `kind` (int,
/// the [`LineKind::code`](super::LineKind::code)), and `POINT_DATA` with one double
/// scalar per named per-point value that every line has. Checks as
/// [`super::write_json`] does.
pub fn write_vtk(path: &Path, lines: &FeatureLines) -> Result<()> {
    write_checked(path, lines, |w| {
        write_header(w, lines)?;
        write_points(w, lines)?;
        write_cells(w, lines)?;
        write_cell_data(w, lines)?;
        write_point_data(w, lines)
    })
}

/// The version line, the title (format and source, ASCII, at most [`MAX_TITLE`]
/// bytes), `ASCII` and the dataset type.
fn write_header(w: &mut impl Write, lines: &FeatureLines) -> io::Result<()> {
    let title: String = format!("{FORMAT} feature lines from {}", one_line(&lines.source))
        .chars()
        .map(|c| if c.is_ascii() { c } else { '?' })
        .take(MAX_TITLE)
        .collect();
    writeln!(w, "# vtk DataFile Version 3.0")?;
    writeln!(w, "{title}")?;
    writeln!(w, "ASCII")?;
    writeln!(w, "DATASET POLYDATA")
}

/// `POINTS n double` and one point per row.
fn write_points(w: &mut impl Write, lines: &FeatureLines) -> io::Result<()> {
    writeln!(w, "POINTS {} double", lines.point_count())?;
    for p in points(lines) {
        writeln!(w, "{} {} {}", p.x, p.y, p.z)?;
    }
    Ok(())
}

/// `LINES n size`, size counting every cell's leading count and its indices.
fn write_cells(w: &mut impl Write, lines: &FeatureLines) -> io::Result<()> {
    let size: usize = indexed(lines).map(|item| 1 + item.path_len()).sum();
    writeln!(w, "LINES {} {size}", lines.len())?;
    for item in indexed(lines) {
        write!(w, "{}", item.path_len())?;
        for index in item.path() {
            write!(w, " {index}")?;
        }
        writeln!(w)?;
    }
    Ok(())
}

/// Per-line `strength` and `kind` scalars; nothing when there are no lines.
fn write_cell_data(w: &mut impl Write, lines: &FeatureLines) -> io::Result<()> {
    if lines.is_empty() {
        return Ok(());
    }
    writeln!(w, "CELL_DATA {}", lines.len())?;
    writeln!(w, "SCALARS strength double 1")?;
    writeln!(w, "LOOKUP_TABLE default")?;
    for line in lines {
        writeln!(w, "{}", line.strength)?;
    }
    writeln!(w, "SCALARS kind int 1")?;
    writeln!(w, "LOOKUP_TABLE default")?;
    for line in lines {
        writeln!(w, "{}", line.kind.code())?;
    }
    Ok(())
}

/// The shared per-point values as `POINT_DATA` scalars; nothing when there are none.
fn write_point_data(w: &mut impl Write, lines: &FeatureLines) -> io::Result<()> {
    let names = shared_value_names(lines);
    if names.is_empty() {
        return Ok(());
    }
    writeln!(w, "POINT_DATA {}", lines.point_count())?;
    for name in names {
        writeln!(w, "SCALARS {name} double 1")?;
        writeln!(w, "LOOKUP_TABLE default")?;
        for value in point_values(lines, name) {
            writeln!(w, "{value}")?;
        }
    }
    Ok(())
}
