//! Outputs of lines that refer to the vertices of the input mesh file rather
//! than to positions: vertex labels and Workbench border files
//! ([`crestline::lines::write_on_surface`]).

use std::path::Path;

use crestline::io::{choose_format, is_volume_path, FileFormat, FormatChoice};
use crestline::lines::LineFormat;
use crestline::{Error, Result};

/// The format of the output `path` of lines (`what`): a format of lines, or
/// `None` for one of `on_surface`, the formats that refer to the input mesh.
pub fn line_output(
    path: &Path,
    what: &str,
    on_surface: &[FileFormat],
) -> Result<Option<LineFormat>> {
    let lines = LineFormat::ALL.map(|format| (format.file_format(), Some(format)));
    let choices: Vec<(FileFormat, Option<LineFormat>)> = lines
        .into_iter()
        .chain(on_surface.iter().map(|&format| (format, None)))
        .collect();
    choose_format(path, what, &choices).map(|(_, format)| format)
}

/// Refuse an `output` that refers to the vertices of the input where it cannot
/// be made: on an isosurface of an image (no vertices of a file to refer to) or
/// when the lines are `faired` off the surface.
pub fn check_on_surface(input: &Path, output: &Path, faired: bool) -> Result<()> {
    let problem = if is_volume_path(input) {
        "vertex labels and borders (.label.gii, .label, .border) refer to the vertices of a \
         mesh file; an isosurface of a 3D image has none"
    } else if faired {
        "vertex labels and borders (.label.gii, .label, .border) need the lines on the surface; \
         --fair moves them off it"
    } else {
        return Ok(());
    };
    Err(Error::File {
        path: output.to_path_buf(),
        message: problem.into(),
    })
}
