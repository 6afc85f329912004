//! Landmark files: JSON (this crate's own, read back by [`read_landmarks`]), CSV
//! of the point landmarks, and 3D Slicer markups (`.mrk.json`, markups schema
//! v1.0.3: one `Fiducial` markup of the point landmarks and one `Curve` markup per
//! line, in Slicer's LPS coordinates).

use std::io::Write;
use std::path::Path;

use serde::{Deserialize, Serialize};
use serde_json::Value;

use super::{Landmarks, LineLandmark};
use crate::atomic::write_atomically;
use crate::io::{choose_format, FileFormat, FormatChoice};
use crate::lines::markups;
pub use crate::space::Space;
use crate::{Error, Result};

/// The `format` of this crate's landmark JSON files.
pub const FORMAT: &str = "crestline-landmarks/1";

/// A landmark file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LandmarkFormat {
    /// `.json`: every landmark and line with its descriptors.
    Json,
    /// `.csv`: the point landmarks, one per row.
    Csv,
    /// `.mrk.json`: 3D Slicer markups.
    Slicer,
}

impl LandmarkFormat {
    /// Every format, in the order listed in error messages.
    pub const ALL: [LandmarkFormat; 3] = [
        LandmarkFormat::Slicer,
        LandmarkFormat::Json,
        LandmarkFormat::Csv,
    ];

    /// The format named by the extension of `path` (case-insensitive,
    /// [`choose_format`]); another extension is an [`Error::File`] listing the
    /// supported ones.
    pub fn from_path(path: &Path) -> Result<LandmarkFormat> {
        choose_format(path, "landmarks", &Self::ALL)
    }
}

impl FormatChoice for LandmarkFormat {
    fn file_format(self) -> FileFormat {
        match self {
            LandmarkFormat::Json => FileFormat::Json,
            LandmarkFormat::Csv => FileFormat::Csv,
            LandmarkFormat::Slicer => FileFormat::SlicerMarkups,
        }
    }
}

/// This crate's landmark JSON document.
#[derive(Serialize, Deserialize)]
struct Document {
    format: String,
    space: Space,
    #[serde(default)]
    units: Option<String>,
    #[serde(flatten)]
    landmarks: Landmarks,
}

/// [`Landmarks::write`].
pub(crate) fn write_landmarks(path: &Path, landmarks: &Landmarks, space: Space) -> Result<()> {
    match LandmarkFormat::from_path(path)? {
        LandmarkFormat::Json => {
            let document = Document {
                format: FORMAT.to_string(),
                space,
                units: Space::units_of(Some(space)).map(str::to_string),
                landmarks: landmarks.clone(),
            };
            write_atomically(path, |w| {
                serde_json::to_writer(&mut *w, &document)?;
                writeln!(w)
            })
        }
        LandmarkFormat::Csv => write_atomically(path, |w| write_csv(w, landmarks, space)),
        LandmarkFormat::Slicer => {
            let document = slicer_markups(landmarks, space);
            write_atomically(path, |w| {
                serde_json::to_writer_pretty(&mut *w, &document)?;
                writeln!(w)
            })
        }
    }
}

/// Whether the JSON `text` says it is a landmark file ([`FORMAT`]), read before
/// the whole of it: a lines file says another format.
pub fn holds_landmarks(text: &str) -> bool {
    #[derive(Deserialize)]
    struct FormatOnly {
        format: Option<String>,
    }
    serde_json::from_str::<FormatOnly>(text)
        .ok()
        .and_then(|f| f.format)
        .is_some_and(|format| format == FORMAT)
}

/// [`Landmarks::read`].
pub(crate) fn read_landmarks(path: &Path) -> Result<(Landmarks, Space)> {
    let text = crate::io::file::read_text(path)?;
    let malformed = |message: String| Error::File {
        path: path.to_path_buf(),
        message,
    };
    let document: Document = serde_json::from_str(&text)
        .map_err(|e| malformed(format!("not a {FORMAT} JSON file: {e}")))?;
    if document.format != FORMAT {
        return Err(malformed(format!(
            "the format is '{}', not {FORMAT}",
            document.format
        )));
    }
    let landmarks = Landmarks {
        space: Some(document.space),
        ..document.landmarks
    };
    Ok((landmarks, document.space))
}

/// The point landmarks as CSV: `id,kind,x,y,z,curvature,line,space`, the frame
/// of the positions (`RAS` or `LPS`) in a column of its own rather than a comment,
/// which spreadsheets and CSV readers would take for a row.
fn write_csv(w: &mut impl Write, landmarks: &Landmarks, space: Space) -> std::io::Result<()> {
    writeln!(w, "id,kind,x,y,z,curvature,line,space")?;
    for p in &landmarks.points {
        let [x, y, z] = [p.position.x, p.position.y, p.position.z];
        let (id, kind, k, line) = (p.id, p.kind.name(), p.curvature, p.line);
        writeln!(w, "{id},{kind},{x},{y},{z},{k},{line},{space}")?;
    }
    Ok(())
}

/// The markups document: a `Fiducial` markup of the point landmarks, then one
/// `Curve` per line, positions in LPS millimetres.
fn slicer_markups(landmarks: &Landmarks, space: Space) -> Value {
    let fiducials: Vec<Value> = landmarks
        .points
        .iter()
        .map(|p| {
            let label = format!("{}-{}", p.kind.name(), p.id);
            let description = format!("line {}, curvature {}", p.line, p.curvature);
            markups::control_point(p.id, label, description, &space.to_lps(&p.position))
        })
        .collect();
    let mut all = vec![markups::markup("Fiducial", "landmarks", fiducials)];
    all.extend(landmarks.lines.iter().map(|line| curve(line, space)));
    markups::document(all)
}

/// A line as a `Curve` (`ClosedCurve` for a loop) markup named by kind and id,
/// with its descriptors in the description of its first point.
fn curve(line: &LineLandmark, space: Space) -> Value {
    let name = format!("{}-{}", line.kind.name(), line.id);
    let description = format!(
        "length {}, mean curvature {}, strength {}, {}",
        line.length,
        line.mean_curvature,
        line.strength,
        if line.convex { "convex" } else { "concave" }
    );
    markups::curve(&name, line.closed, &description, (&line.points, space))
}

impl Landmarks {
    /// Write these landmarks, whose positions are in `space`, to `path` in the format
    /// its name gives ([`LandmarkFormat::from_path`]), atomically: on an error `path`
    /// is untouched.
    pub fn write(&self, path: &Path, space: Space) -> Result<()> {
        write_landmarks(path, self, space)
    }

    /// Read a landmark JSON file written by [`Landmarks::write`]: the landmarks and the
    /// space of their positions. Malformed files are an [`Error::File`] naming `path`.
    pub fn read(path: &Path) -> Result<(Landmarks, Space)> {
        read_landmarks(path)
    }
}
