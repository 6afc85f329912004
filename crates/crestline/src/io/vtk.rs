//! Legacy ASCII VTK poly data (`# vtk DataFile Version 3.0`, `DATASET POLYDATA`),
//! as read by ParaView, VisIt and the `vtk`, `meshio` and `pyvista` readers: the
//! sections every VTK file of the crate is written with, in file order.
//!
//! ```text
//! # vtk DataFile Version 3.0
//! <title>
//! ASCII
//! DATASET POLYDATA
//! POINTS <n> double          one point a row
//! LINES|POLYGONS <n> <size>  one cell a row: its point count, then its indices
//! CELL_DATA|POINT_DATA <n>   then SCALARS arrays, one value a row
//! ```

use std::io::{self, Write};

use crate::{Point, Space};

/// The longest title line legacy VTK readers accept, in bytes.
const MAX_TITLE: usize = 255;

/// A title line: `text`, then 3D Slicer's mark of `space` if there is one (kept
/// within the length readers accept).
pub(crate) fn title(text: &str, space: Option<Space>) -> String {
    match space {
        Some(space) => {
            let mark = space.slicer_mark();
            let room = MAX_TITLE - mark.len() - 1;
            let text: String = text.chars().take(room).collect();
            format!("{text} {mark}")
        }
        None => text.to_string(),
    }
}

/// The version line, `title` (control characters as spaces, other non-ASCII
/// characters as `?`, cut to [`MAX_TITLE`] bytes), `ASCII` and the dataset type.
pub(crate) fn write_header(w: &mut impl Write, title: &str) -> io::Result<()> {
    let title: String = title
        .chars()
        .map(|c| match c {
            c if c.is_control() => ' ',
            c if c.is_ascii() => c,
            _ => '?',
        })
        .take(MAX_TITLE)
        .collect();
    writeln!(w, "# vtk DataFile Version 3.0")?;
    writeln!(w, "{title}")?;
    writeln!(w, "ASCII")?;
    writeln!(w, "DATASET POLYDATA")
}

/// `POINTS count double` and the `count` `points`, one a row.
pub(crate) fn write_points<'p>(
    w: &mut impl Write,
    count: usize,
    points: impl IntoIterator<Item = &'p Point>,
) -> io::Result<()> {
    writeln!(w, "POINTS {count} double")?;
    for p in points {
        writeln!(w, "{} {} {}", p.x, p.y, p.z)?;
    }
    Ok(())
}

/// The kind of the cells of a poly-data file.
#[derive(Clone, Copy, Debug)]
pub(crate) enum CellType {
    /// Polylines.
    Lines,
    /// Polygons.
    Polygons,
}

/// `LINES` or `POLYGONS` with the cell count and the size (every cell's point
/// count and indices), then one cell a row. `cells` yields the cells, each as its
/// point indices; it is called once to count them and once to write them.
pub(crate) fn write_cells<C, I>(
    w: &mut impl Write,
    cell_type: CellType,
    cells: impl Fn() -> C,
) -> io::Result<()>
where
    C: Iterator<Item = I>,
    I: IntoIterator<Item = usize>,
{
    let keyword = match cell_type {
        CellType::Lines => "LINES",
        CellType::Polygons => "POLYGONS",
    };
    let (count, size) = cells().fold((0, 0), |(count, size), cell| {
        (count + 1, size + 1 + cell.into_iter().count())
    });
    writeln!(w, "{keyword} {count} {size}")?;
    let mut indices = Vec::new();
    for cell in cells() {
        indices.clear();
        indices.extend(cell);
        write!(w, "{}", indices.len())?;
        for index in &indices {
            write!(w, " {index}")?;
        }
        writeln!(w)?;
    }
    Ok(())
}

/// What the data arrays that follow are attached to.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Attachment {
    /// One value per point.
    Points,
    /// One value per cell.
    Cells,
}

/// `POINT_DATA count` or `CELL_DATA count`: the start of the arrays attached to
/// the `count` points or cells.
pub(crate) fn write_data(
    w: &mut impl Write,
    attachment: Attachment,
    count: usize,
) -> io::Result<()> {
    let keyword = match attachment {
        Attachment::Points => "POINT_DATA",
        Attachment::Cells => "CELL_DATA",
    };
    writeln!(w, "{keyword} {count}")
}

/// A value type of a `SCALARS` array.
pub(crate) trait Scalar: std::fmt::Display {
    /// The VTK name of the type.
    const TYPE: &'static str;
}

impl Scalar for f64 {
    const TYPE: &'static str = "double";
}

impl Scalar for i32 {
    const TYPE: &'static str = "int";
}

/// A `SCALARS name <type> 1` array with the default lookup table, one value a row.
pub(crate) fn write_scalars<V: Scalar>(
    w: &mut impl Write,
    name: &str,
    values: impl IntoIterator<Item = V>,
) -> io::Result<()> {
    writeln!(w, "SCALARS {name} {} 1", V::TYPE)?;
    writeln!(w, "LOOKUP_TABLE default")?;
    for value in values {
        writeln!(w, "{value}")?;
    }
    Ok(())
}
