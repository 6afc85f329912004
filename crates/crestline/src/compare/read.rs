//! Reading the features [`super::compare`] takes: lines files (`crestline-lines`
//! JSON, OBJ, PLY and legacy VTK, [`super::line_files`]) and landmark files (`crestline-landmarks` JSON, or the CSV the
//! `landmarks` job writes), positions in RAS when the file states its frame.

use std::path::Path;

use super::Features;
use crate::landmarks::{holds_landmarks, read_landmarks, LandmarkFormat};
use crate::lines::{read_json, LineFormat};
use crate::space::Space;
use crate::{Error, Point, Result};

/// [`Features::read`].
pub(crate) fn read_features(path: &Path) -> Result<Features> {
    match LineFormat::from_path(path) {
        Ok(LineFormat::Obj) => return super::line_files::read_obj_lines(path),
        Ok(LineFormat::Vtk) => return super::line_files::read_vtk_lines(path),
        Ok(LineFormat::Ply) => return super::line_files::read_ply_lines(path),
        _ => {}
    }
    let format = LandmarkFormat::from_path(path).map_err(|_| Error::File {
        path: path.to_path_buf(),
        message: "not a file of lines or landmarks: compare reads .json (lines or \
                  landmarks), .obj, .ply and .vtk (lines), .mrk.json (3D Slicer markups) and \
                  .csv (landmarks)"
            .into(),
    })?;
    match format {
        LandmarkFormat::Slicer => super::markups::read_markups(path),
        LandmarkFormat::Csv => read_csv(path),
        LandmarkFormat::Json if holds_landmarks(&crate::io::file::read_text(path)?) => {
            let (landmarks, _) = read_landmarks(path)?;
            Ok(Features::of_landmarks(&landmarks))
        }
        LandmarkFormat::Json => Ok(Features::of_lines(&read_json(path)?)),
    }
}

/// The point landmarks of a CSV file as the `landmarks` job writes it: a header
/// naming at least `kind`, `x`, `y` and `z` (and `space`, RAS or LPS, per row).
fn read_csv(path: &Path) -> Result<Features> {
    let text = crate::io::file::read_text(path)?;
    let malformed = |line: usize, message: String| Error::File {
        path: path.to_path_buf(),
        message: format!("line {line}: {message}"),
    };
    let mut rows = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let header: Vec<&str> = rows
        .next()
        .map(|(_, l)| l.split(',').map(str::trim).collect())
        .unwrap_or_default();
    let column = |name: &str| header.iter().position(|h| *h == name);
    let (Some(kind), Some(x), Some(y), Some(z)) =
        (column("kind"), column("x"), column("y"), column("z"))
    else {
        return Err(malformed(
            1,
            "the header names no kind, x, y and z columns".into(),
        ));
    };
    let space = column("space");
    let mut features = Features {
        declared: space.map(|_| Space::Ras),
        ..Features::default()
    };
    for (index, row) in rows {
        let cells: Vec<&str> = row.split(',').map(str::trim).collect();
        let cell = |i: usize| cells.get(i).copied().unwrap_or("");
        let number = |i: usize| {
            cell(i)
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    malformed(
                        index + 1,
                        format!("'{}' is not a finite coordinate", cell(i)),
                    )
                })
        };
        let mut position = Point::new(number(x)?, number(y)?, number(z)?);
        if let Some(space) = space {
            let frame: Space = cell(space).parse().map_err(|_| {
                malformed(index + 1, format!("'{}' is not RAS or LPS", cell(space)))
            })?;
            position = frame.to_ras(&position);
        }
        features.add_point(cell(kind), position);
    }
    Ok(features)
}

impl Features {
    /// The lines and landmarks of the file `path`, by kind: a lines JSON file (its
    /// segments), a landmarks JSON file (its point landmarks, and its lines'
    /// segments), 3D Slicer markups (`.mrk.json`: point lists and curves), or a
    /// landmarks CSV file (its points). Positions are converted into
    /// RAS when the file states its frame, and taken as they are otherwise (a mesh's
    /// lines).
    ///
    /// Errors are [`Error::File`] naming `path`: another kind of file, or one that
    /// does not read.
    pub fn read(path: &Path) -> Result<Features> {
        read_features(path)
    }
}
