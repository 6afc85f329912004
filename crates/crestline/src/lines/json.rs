//! The `crestline-lines/1.1` JSON format:
//!
//! ```json
//! {"format": "crestline-lines/1.1", "source": "...", "space": "RAS", "units": "mm",
//!  "lines": [{"kind": "ridge", "closed": false, "strength": 3.2, "points": [[x, y, z], ...]}]}
//! ```
//!
//! Keys appear in exactly this order. `space` is the anatomical frame of the
//! points (`"RAS"`, `"LPS"`, or `null` when the input declared none) and `units`
//! their length unit (`"mm"` in an anatomical frame, else `null`). Numbers are
//! written so that they read back bit for bit.
//!
//! Versions: the reader takes `crestline-lines/1` (no `space`: read as `null`) and
//! `1.1`, refusing unknown keys; of a later `1.x` it ignores the keys it does not
//! know, so that a minor version may add keys without breaking older readers.

use std::borrow::Cow;
use std::io::Write;
use std::path::Path;

use serde::{Deserialize, Serialize};

use super::{write_checked, FeatureLines, Polyline};
use crate::{Error, Result, Space};

/// The value of the `format` key of the JSON files this version writes.
pub const FORMAT: &str = "crestline-lines/1.1";

/// The format's name and major version: every `format` this reader takes starts
/// with it (`crestline-lines/1`, `crestline-lines/1.1`, ...).
const MAJOR: &str = "crestline-lines/1";

/// The minor version written ([`FORMAT`]); files of a later minor version may
/// hold keys this reader does not know.
const MINOR: u32 = 1;

/// The keys of the document and of a line that this version knows.
const DOCUMENT_KEYS: [&str; 5] = ["format", "source", "space", "units", "lines"];
const LINE_KEYS: [&str; 6] = [
    "kind",
    "closed",
    "strength",
    "points",
    "locations",
    "values",
];

/// The whole file, borrowed when writing and owned when reading.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Document<'a> {
    format: Cow<'a, str>,
    source: Cow<'a, str>,
    #[serde(default)]
    space: Option<Space>,
    #[serde(default)]
    units: Option<Cow<'a, str>>,
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
        space: lines.space,
        units: Space::units_of(lines.space).map(Cow::Borrowed),
        lines: Cow::Borrowed(&lines.lines),
    };
    write_checked(path, lines, |w| {
        serde_json::to_writer(&mut *w, &document)?;
        writeln!(w)
    })
}

/// [`FeatureLines::read_json`].
pub(crate) fn read_json(path: &Path) -> Result<FeatureLines> {
    let text = crate::io::file::read_text(path)?;
    let malformed = |message: String| Error::File {
        path: path.to_path_buf(),
        message,
    };
    let header: Header = serde_json::from_str(&text)
        .map_err(|e| malformed(format!("not a {FORMAT} JSON file: {e}")))?;
    let minor = match header.format.as_deref() {
        Some(format) => minor_version(format).ok_or_else(|| {
            malformed(format!(
                "unsupported format {format:?}, expected {MAJOR:?} or a {MAJOR}.x version"
            ))
        })?,
        None => return Err(malformed(format!("no \"format\" key; expected {FORMAT:?}"))),
    };
    let parsed = if minor > MINOR {
        let mut value: serde_json::Value = serde_json::from_str(&text)
            .map_err(|e| malformed(format!("malformed {FORMAT} file: {e}")))?;
        keep_known_keys(&mut value);
        serde_json::from_value(value)
    } else {
        serde_json::from_str(&text)
    };
    let document: Document =
        parsed.map_err(|e| malformed(format!("malformed {FORMAT} file: {e}")))?;
    let lines = FeatureLines {
        source: document.source.into_owned(),
        lines: document.lines.into_owned(),
        space: document.space,
    };
    match lines.problem() {
        Some(message) => Err(malformed(message)),
        None => Ok(lines),
    }
}

/// The minor version of a `format` value of this format's major version:
/// `crestline-lines/1` is 0, `crestline-lines/1.1` is 1; `None` for another format.
fn minor_version(format: &str) -> Option<u32> {
    match format.strip_prefix(MAJOR)? {
        "" => Some(0),
        rest => rest.strip_prefix('.')?.parse().ok(),
    }
}

/// Drop the keys of the document and of its lines that this version does not know.
fn keep_known_keys(document: &mut serde_json::Value) {
    let Some(object) = document.as_object_mut() else {
        return;
    };
    object.retain(|key, _| DOCUMENT_KEYS.contains(&key.as_str()));
    if let Some(serde_json::Value::Array(lines)) = object.get_mut("lines") {
        for line in lines
            .iter_mut()
            .filter_map(serde_json::Value::as_object_mut)
        {
            line.retain(|key, _| LINE_KEYS.contains(&key.as_str()));
        }
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

impl FeatureLines {
    /// Read a `crestline-lines/1` JSON file written by `write_json`.
    ///
    /// Malformed JSON, a missing or different `format`, unknown keys or kinds, and lines
    /// that [`FeatureLines::validate`] would reject are an [`Error::File`] naming `path`.
    pub fn read_json(path: &Path) -> Result<FeatureLines> {
        read_json(path)
    }
}
