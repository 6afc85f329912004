//! Wavefront OBJ output: all points as `v` records, then per line an `o` record
//! named after its index and kind, a comment with its closure and strength, and an
//! `l` record (1-based indices; a closed line repeats its first index at the end).

use std::io::{self, Write};
use std::path::Path;

use super::indexing::{indexed, points};
use super::{one_line, write_checked, FeatureLines, FORMAT};
use crate::io::obj::write_vertices;
use crate::Result;

/// Write `lines` to `path` as a Wavefront OBJ file of `l` (polyline) records.
///
/// Each line is an object named `line<index>_<kind>` followed by a comment
/// `# <kind> open|closed strength <s>`. Checks as [`super::write_json`] does.
pub fn write_obj(path: &Path, lines: &FeatureLines) -> Result<()> {
    write_checked(path, lines, |w| write_body(w, lines))
}

/// The whole file.
fn write_body(w: &mut impl Write, lines: &FeatureLines) -> io::Result<()> {
    match lines.space {
        Some(space) => writeln!(w, "# {FORMAT} feature lines {}", space.slicer_mark())?,
        None => writeln!(w, "# {FORMAT} feature lines")?,
    }
    writeln!(w, "# source: {}", one_line(&lines.source))?;
    writeln!(w, "# {} lines, {} points", lines.len(), lines.point_count())?;
    write_vertices(w, points(lines))?;
    for item in indexed(lines) {
        let line = item.line;
        let closure = if line.closed { "closed" } else { "open" };
        writeln!(w, "o line{}_{}", item.number, line.kind)?;
        writeln!(w, "# {} {closure} strength {}", line.kind, line.strength)?;
        write!(w, "l")?;
        for index in item.path() {
            write!(w, " {}", index + 1)?;
        }
        writeln!(w)?;
    }
    Ok(())
}
