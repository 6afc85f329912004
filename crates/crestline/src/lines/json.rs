//! The `crestline-lines/1` JSON format:
//!
//! ```json
//! {"format": "crestline-lines/1", "source": "...",
//!  "lines": [{"kind": "ridge", "closed": false, "strength": 3.2, "points": [[x, y, z], ...]}]}
//! ```
//!
//! Keys appear in exactly this order. Numbers are written so that they read back
//! bit for bit.

use std::borrow::Cow;
use std::io::Write;
use std::path::Path;

use serde::{Deserialize, Serialize};

use super::{write_checked, FeatureLines, Polyline};
use crate::{Error, Result};

/// The value of the `format` key of the JSON files this version writes and reads.
pub const FORMAT: &str = "crestline-lines/1";

/// The whole file, borrowed when writing and owned when reading.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Document<'a> {
    format: Cow<'a, str>,
    source: Cow<'a, str>,
    lines: Cow<'a, [Polyline]>,
}

/// Just the `format` key, read first so that a file of another format gets a clear
/// error rather than one about its content.
#[derive(Deserialize)]
struct Header {
    format: Option<String>,
}

/// Write `lines` to `path` as `crestline-lines/1` JSON.
///
/// A non-finite coordinate or strength, or a line with too few points, is an
/// [`Error::Argument`] naming the line, raised before any file is created.
pub fn write_json(path: &Path, lines: &FeatureLines) -> Result<()> {
    let document = Document {
        format: Cow::Borrowed(FORMAT),
        source: Cow::Borrowed(&lines.source),
        lines: Cow::Borrowed(&lines.lines),
    };
    write_checked(path, lines, |w| {
        serde_json::to_writer(&mut *w, &document)?;
        writeln!(w)
    })
}

/// Read a `crestline-lines/1` JSON file written by [`write_json`].
///
/// Malformed JSON, a missing or different `format`, unknown keys or kinds, and lines
/// that [`FeatureLines::validate`] would reject are an [`Error::File`] naming `path`.
pub fn read_json(path: &Path) -> Result<FeatureLines> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let malformed = |message: String| Error::File {
        path: path.to_path_buf(),
        message,
    };
    let header: Header = serde_json::from_str(&text)
        .map_err(|e| malformed(format!("not a {FORMAT} JSON file: {e}")))?;
    match header.format.as_deref() {
        Some(FORMAT) => {}
        Some(other) => {
            return Err(malformed(format!(
                "unsupported format {other:?}, expected {FORMAT:?}"
            )))
        }
        None => return Err(malformed(format!("no \"format\" key; expected {FORMAT:?}"))),
    }
    let document: Document = serde_json::from_str(&text)
        .map_err(|e| malformed(format!("malformed {FORMAT} file: {e}")))?;
    let lines = FeatureLines {
        source: document.source.into_owned(),
        lines: document.lines.into_owned(),
    };
    match lines.problem() {
        Some(message) => Err(malformed(message)),
        None => Ok(lines),
    }
}

/// Serde adapter storing a `Vec<Point>` as an array of `[x, y, z]` arrays.
pub(super) mod point_arrays {
    use serde::{Deserialize, Deserializer, Serializer};

    use crate::Point;

    /// Write the points as `[[x, y, z], ...]`.
    pub fn serialize<S: Serializer>(points: &[Point], serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_seq(points.iter().map(|p| [p.x, p.y, p.z]))
    }

    /// Read points written by [`serialize`].
    pub fn deserialize<'de, D: Deserializer<'de>>(deserializer: D) -> Result<Vec<Point>, D::Error> {
        let arrays = Vec::<[f64; 3]>::deserialize(deserializer)?;
        Ok(arrays.into_iter().map(Point::from).collect())
    }
}
