//! 3D Slicer markups (`.mrk.json`, markups schema v1.0.3): the JSON document
//! Slicer's Markups module loads, with each feature line as a `Curve` markup
//! (`ClosedCurve` for a loop) and positions in LPS millimetres, as Slicer writes
//! them. The landmark files ([`crate::landmarks`]) share the document's pieces.

use std::io::Write;
use std::path::Path;

use serde_json::{json, Value};

use super::{write_checked, FeatureLines, Polyline};
use crate::{Point, Result, Space};

/// The schema URL that 3D Slicer writes into markups files.
pub const SLICER_SCHEMA: &str = "https://raw.githubusercontent.com/slicer/slicer/master/Modules/Loadable/Markups/Resources/Schema/markups-schema-v1.0.3.json#";

/// The whole document: the schema and the `markups`.
pub(crate) fn document(markups: Vec<Value>) -> Value {
    json!({ "@schema": SLICER_SCHEMA, "markups": markups })
}

/// One markup of `kind` named `name` with `control_points` (positions in LPS).
pub(crate) fn markup(kind: &str, name: &str, control_points: Vec<Value>) -> Value {
    json!({
        "type": kind,
        "name": name,
        "coordinateSystem": "LPS",
        "coordinateUnits": "mm",
        "locked": true,
        "controlPoints": control_points,
    })
}

/// A control point numbered `id` at `lps` (a position in LPS).
pub(crate) fn control_point(id: usize, label: String, description: String, lps: &Point) -> Value {
    json!({
        "id": id.to_string(),
        "label": label,
        "description": description,
        "position": [lps.x, lps.y, lps.z],
        "positionStatus": "defined",
    })
}

/// The frame of a markup's positions: its `coordinateSystem`, LPS when it names
/// none (as 3D Slicer writes).
pub(crate) fn frame(markup: &Value) -> std::result::Result<Space, String> {
    match markup["coordinateSystem"].as_str() {
        None | Some("LPS") => Ok(Space::Lps),
        Some("RAS") => Ok(Space::Ras),
        Some(other) => Err(format!("unknown coordinate system '{other}'")),
    }
}

/// The position of a control point, in its markup's frame.
pub(crate) fn position(point: &Value) -> std::result::Result<Point, String> {
    let xyz: Vec<f64> = point["position"]
        .as_array()
        .map(|values| values.iter().filter_map(Value::as_f64).collect())
        .unwrap_or_default();
    match xyz[..] {
        [x, y, z] if xyz.iter().all(|v| v.is_finite()) => Ok(Point::new(x, y, z)),
        _ => Err(format!(
            "control point '{}' has no position of three numbers",
            point["label"].as_str().unwrap_or("")
        )),
    }
}

/// A curve markup (`ClosedCurve` when `closed`) named `name` through `points` of
/// frame `space`, with `description` on its first point.
pub(crate) fn curve(
    name: &str,
    closed: bool,
    description: &str,
    (points, space): (&[Point], Space),
) -> Value {
    let control_points = points
        .iter()
        .enumerate()
        .map(|(n, p)| {
            let text = if n == 0 { description } else { "" };
            control_point(
                n + 1,
                format!("{name}-{}", n + 1),
                text.to_string(),
                &space.to_lps(p),
            )
        })
        .collect();
    markup(
        if closed { "ClosedCurve" } else { "Curve" },
        name,
        control_points,
    )
}

/// Write `lines` as 3D Slicer markups: one curve per line, named by its kind and
/// number (`ridge-1`), its strength in the first point's description. Points of
/// lines without a frame are written as they are, in LPS, the frame 3D Slicer
/// gives a model that declares none.
pub fn write_markups(path: &Path, lines: &FeatureLines) -> Result<()> {
    let space = lines.space.unwrap_or(Space::Lps);
    let markups: Vec<Value> = lines
        .iter()
        .enumerate()
        .map(|(n, line)| line_curve(n + 1, line, space))
        .collect();
    let document = document(markups);
    write_checked(path, lines, |w| {
        serde_json::to_writer_pretty(&mut *w, &document)?;
        writeln!(w)
    })
}

/// Line number `number` as a curve markup.
fn line_curve(number: usize, line: &Polyline, space: Space) -> Value {
    let name = format!("{}-{number}", line.kind);
    let description = format!("strength {}", line.strength);
    curve(&name, line.closed, &description, (&line.points, space))
}
