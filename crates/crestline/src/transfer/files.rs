//! Labelled landmarks in and out: 3D Slicer markups (`.mrk.json`, the control
//! points of every point list, by label), this crate's landmark files (`.json`,
//! labelled by kind and number as their markups are: `extremal-12`) and CSV with a
//! header naming the columns `label`, `x`, `y`, `z` and `space` (RAS or LPS).
//! Transferred landmarks are written in the same three formats with a
//! `confidence` and a `flagged` mark each (`.json`: a `crestline-transferred/1`
//! document, which [`read_labelled`] reads too; `.mrk.json`: in the control
//! point's description).

use std::io::Write;
use std::path::Path;

use serde_json::{json, Value};

use crate::atomic::write_atomically;
use crate::landmarks::{holds_landmarks, read_landmarks, LandmarkFormat};
use crate::lines::markups;
use crate::space::Space;
use crate::{Error, Point, Result};

/// The `format` of the JSON files of transferred landmarks.
pub const FORMAT: &str = "crestline-transferred/1";

/// A named point.
#[derive(Clone, Debug, PartialEq)]
pub struct LabelledPoint {
    /// Its label, as the file gave it.
    pub label: String,
    /// Where it is, in RAS.
    pub position: Point,
}

/// The labelled points of `path`, in the order of the file, positions in RAS
/// (see the module documentation for the formats).
///
/// Errors are [`Error::File`] naming `path`: an unknown extension, a malformed
/// file, or a file without points.
pub fn read_labelled(path: &Path) -> Result<Vec<LabelledPoint>> {
    let format = LandmarkFormat::from_path(path)?;
    let points = match format {
        LandmarkFormat::Json => {
            let text = crate::io::file::read_text(path)?;
            if !holds_landmarks(&text) {
                return transferred(&text).map_err(|message| Error::File {
                    path: path.to_path_buf(),
                    message,
                });
            }
            let (landmarks, space) = read_landmarks(path)?;
            Ok(landmarks
                .points
                .iter()
                .map(|p| LabelledPoint {
                    label: format!("{}-{}", p.kind.name(), p.id),
                    position: space.to_ras(&p.position),
                })
                .collect())
        }
        LandmarkFormat::Slicer => from_markups(&crate::io::file::read_text(path)?),
        LandmarkFormat::Csv => from_csv(&crate::io::file::read_text(path)?),
    };
    let in_file = |message: String| Error::File {
        path: path.to_path_buf(),
        message,
    };
    let points = points.map_err(in_file)?;
    if points.is_empty() {
        return Err(in_file("no landmarks in the file".to_string()));
    }
    Ok(points)
}

/// The landmarks of a [`FORMAT`] document, as [`write_labelled`] writes it.
fn transferred(text: &str) -> std::result::Result<Vec<LabelledPoint>, String> {
    #[derive(serde::Deserialize)]
    struct Document {
        format: String,
        space: Space,
        landmarks: Vec<Row>,
    }
    #[derive(serde::Deserialize)]
    struct Row {
        label: String,
        position: [f64; 3],
    }
    let document: Document = serde_json::from_str(text).map_err(|e| {
        format!(
            "not a landmarks JSON file ({} or {FORMAT}): {e}",
            crate::landmarks::FORMAT
        )
    })?;
    if document.format != FORMAT {
        return Err(format!("the format is '{}', not {FORMAT}", document.format));
    }
    Ok(document
        .landmarks
        .into_iter()
        .map(|row| LabelledPoint {
            label: row.label,
            position: document.space.to_ras(&Point::from(row.position)),
        })
        .collect())
}

/// The control points of the point lists (`Fiducial`) of a markups document.
fn from_markups(text: &str) -> std::result::Result<Vec<LabelledPoint>, String> {
    let document: Value =
        serde_json::from_str(text).map_err(|e| format!("not a 3D Slicer markups file: {e}"))?;
    let all = document["markups"]
        .as_array()
        .ok_or("not a 3D Slicer markups file: no \"markups\" list")?;
    let mut points = Vec::new();
    for markup in all.iter().filter(|m| m["type"] == "Fiducial") {
        let frame = markups::frame(markup)?;
        for point in markup["controlPoints"].as_array().into_iter().flatten() {
            points.push(LabelledPoint {
                label: point["label"].as_str().unwrap_or_default().to_string(),
                position: frame.to_ras(&markups::position(point)?),
            });
        }
    }
    Ok(points)
}

/// The rows of a CSV text whose header names `label`, `x`, `y`, `z` and `space`.
fn from_csv(text: &str) -> std::result::Result<Vec<LabelledPoint>, String> {
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let header: Vec<&str> = lines
        .next()
        .unwrap_or_default()
        .split(',')
        .map(str::trim)
        .collect();
    let column = |name: &str| {
        header
            .iter()
            .position(|h| h.eq_ignore_ascii_case(name))
            .ok_or_else(|| {
                format!("no `{name}` column in the header (label, x, y, z and space: RAS or LPS)")
            })
    };
    let [label, x, y, z, space] = ["label", "x", "y", "z", "space"].map(column);
    let (label, x, y, z, space) = (label?, x?, y?, z?, space?);
    lines
        .enumerate()
        .map(|(n, line)| {
            let fields: Vec<&str> = line.split(',').map(str::trim).collect();
            let field = |i: usize| {
                fields
                    .get(i)
                    .copied()
                    .ok_or_else(|| format!("row {}: {} fields, too few", n + 1, fields.len()))
            };
            let number = |i: usize| -> std::result::Result<f64, String> {
                let text = field(i)?;
                text.parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| format!("row {}: '{text}' is not a finite number", n + 1))
            };
            let frame: Space = field(space)?
                .parse()
                .map_err(|e: Error| format!("row {}: {e}", n + 1))?;
            Ok(LabelledPoint {
                label: field(label)?.to_string(),
                position: frame.to_ras(&Point::new(number(x)?, number(y)?, number(z)?)),
            })
        })
        .collect()
}

/// Write `points` with their `confidence` and whether each is `flagged` to
/// `path` in the format its name gives ([`LandmarkFormat::from_path`]),
/// positions in `space`, labels and order kept, atomically: on an error `path` is
/// untouched.
pub fn write_labelled(
    path: &Path,
    points: &[LabelledPoint],
    confidence: &[f64],
    flagged: &[bool],
    space: Space,
) -> Result<()> {
    let rows = points.iter().zip(confidence.iter().zip(flagged));
    match LandmarkFormat::from_path(path)? {
        LandmarkFormat::Slicer => {
            let control_points = rows
                .enumerate()
                .map(|(n, (p, (c, f)))| {
                    let description = if *f {
                        format!(
                            "confidence {c}; flagged: doubtful, the subject lacks the lines here"
                        )
                    } else {
                        format!("confidence {c}")
                    };
                    markups::control_point(
                        n + 1,
                        p.label.clone(),
                        description,
                        &Space::Ras.to_lps(&p.position),
                    )
                })
                .collect();
            let document = markups::document(vec![markups::markup(
                "Fiducial",
                "landmarks",
                control_points,
            )]);
            write_atomically(path, |w| {
                serde_json::to_writer_pretty(&mut *w, &document)?;
                writeln!(w)
            })
        }
        LandmarkFormat::Json => {
            let landmarks: Vec<Value> = rows
                .map(|(p, (c, f))| {
                    let q = Space::Ras.convert(&p.position, space);
                    json!({"label": p.label, "position": [q.x, q.y, q.z],
                        "confidence": json_number(*c), "flagged": f})
                })
                .collect();
            let document = json!({"format": FORMAT, "space": space.name(),
                "units": crate::space::UNITS, "landmarks": landmarks});
            write_atomically(path, |w| {
                serde_json::to_writer(&mut *w, &document)?;
                writeln!(w)
            })
        }
        LandmarkFormat::Csv => write_atomically(path, |w| {
            writeln!(w, "label,x,y,z,confidence,flagged,space")?;
            for (p, (c, f)) in rows {
                let q = Space::Ras.convert(&p.position, space);
                writeln!(w, "{},{},{},{},{c},{f},{space}", p.label, q.x, q.y, q.z)?;
            }
            Ok(())
        }),
    }
}

/// A number for JSON, which has no infinity: `null` for one.
fn json_number(value: f64) -> Value {
    if value.is_finite() {
        json!(value)
    } else {
        Value::Null
    }
}
