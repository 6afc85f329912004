//! 3D Slicer markups (`.mrk.json`) as features to compare: point lists, their
//! points of a kind by label, and curves, lines of a kind by name.

use std::path::Path;

use serde_json::Value;

use super::Features;
use crate::lines::markups;
use crate::space::Space;
use crate::{Error, Point, Result};

/// The features of the markups file `path`: the control points of every point
/// list (`Fiducial`), each of the kind its label names, and every curve (`Curve`,
/// `OpenCurve`, `ClosedCurve`) as a line of the kind its name names — a label
/// or name `ridge-12` is of kind `ridge`, one without a trailing number (`nasion`)
/// its own kind. Positions in RAS, from the markup's `coordinateSystem` (LPS when
/// it names none, as 3D Slicer writes). Other markups (planes, angles) are
/// passed over.
///
/// Errors are [`Error::File`] naming `path`: not a markups document, or a
/// control point without three finite coordinates.
pub(super) fn read_markups(path: &Path) -> Result<Features> {
    let text = crate::io::file::read_text(path)?;
    let malformed = |message: String| Error::File {
        path: path.to_path_buf(),
        message,
    };
    let document: Value = serde_json::from_str(&text)
        .map_err(|e| malformed(format!("not a 3D Slicer markups file: {e}")))?;
    let markups = document["markups"]
        .as_array()
        .ok_or_else(|| malformed("not a 3D Slicer markups file: no \"markups\" list".into()))?;
    let mut features = Features {
        declared: Some(Space::Lps),
        ..Features::default()
    };
    for (number, markup) in markups.iter().enumerate() {
        add_markup(&mut features, markup)
            .map_err(|message| malformed(format!("markup {}: {message}", number + 1)))?;
    }
    Ok(features)
}

/// Add the points or the line of one markup.
fn add_markup(features: &mut Features, markup: &Value) -> std::result::Result<(), String> {
    let frame = markups::frame(markup)?;
    let points = markup["controlPoints"]
        .as_array()
        .map_or(&[][..], Vec::as_slice);
    let ras = |point: &Value| markups::position(point).map(|p| frame.to_ras(&p));
    match markup["type"].as_str().unwrap_or_default() {
        "Fiducial" => {
            for point in points {
                let label = point["label"].as_str().unwrap_or("point");
                features.add_point(kind_of(label), ras(point)?);
            }
        }
        kind @ ("Curve" | "OpenCurve" | "ClosedCurve") => {
            let line: Vec<Point> = points
                .iter()
                .map(ras)
                .collect::<std::result::Result<_, _>>()?;
            let name = markup["name"].as_str().unwrap_or("curve");
            features.add_line(kind_of(name), &line, kind == "ClosedCurve");
        }
        _ => {}
    }
    Ok(())
}

/// The kind a label or name gives: what stands before a trailing `-number`.
fn kind_of(label: &str) -> &str {
    match label.rsplit_once('-') {
        Some((kind, number)) if !kind.is_empty() && number.parse::<u64>().is_ok() => kind,
        _ => label,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_come_from_labels_without_their_numbers() {
        assert_eq!(kind_of("extremal-12"), "extremal");
        assert_eq!(kind_of("curvature_maximum-3"), "curvature_maximum");
        assert_eq!(kind_of("nasion"), "nasion");
        assert_eq!(kind_of("left-eye"), "left-eye");
    }

    #[test]
    fn points_and_curves_are_read_in_ras() {
        let markups = serde_json::json!({"markups": [
            {"type": "Fiducial", "coordinateSystem": "LPS", "controlPoints": [
                {"label": "end-1", "position": [1.0, 2.0, 3.0]},
                {"label": "nasion", "position": [0.0, 90.0, 10.0]}]},
            {"type": "ClosedCurve", "name": "ridge-4", "coordinateSystem": "RAS", "controlPoints": [
                {"label": "ridge-4-1", "position": [0.0, 0.0, 0.0]},
                {"label": "ridge-4-2", "position": [1.0, 0.0, 0.0]},
                {"label": "ridge-4-3", "position": [1.0, 1.0, 0.0]}]},
            {"type": "Plane", "controlPoints": []}]});
        let mut features = Features::default();
        for markup in markups["markups"].as_array().unwrap() {
            add_markup(&mut features, markup).unwrap();
        }
        assert_eq!(features.points["end"], [Point::new(-1.0, -2.0, 3.0)]);
        assert_eq!(features.points["nasion"], [Point::new(0.0, -90.0, 10.0)]);
        assert_eq!(features.segments["ridge"].len(), 3);
        assert_eq!(features.line_counts["ridge"], 1);
        let bad = serde_json::json!({"type": "Fiducial", "controlPoints": [{"label": "x", "position": [1.0]}]});
        assert!(add_markup(&mut features, &bad).unwrap_err().contains("'x'"));
    }
}
