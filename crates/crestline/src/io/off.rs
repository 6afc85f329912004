//! Object File Format (OFF) reading.

use super::{
    capped_capacity, check_corner_count, line_error, parse_number, parse_point, push_polygon,
    quoted, truncated, Input,
};
use crate::mesh::TriangleSoup;
use crate::{Error, Result};

/// Header keywords accepted: plain OFF and the variants that append per-vertex
/// colours (`C`) or normals (`N`) after the coordinates, which are ignored.
const KEYWORDS: &[&str] = &["OFF", "COFF", "NOFF", "CNOFF", "NCOFF"];

/// Fewest bytes a vertex line can take (`0 0 0` and a line break).
const MIN_VERTEX_BYTES: usize = 6;
/// Fewest bytes a face line can take (`3 0 1 2` and a line break).
const MIN_FACE_BYTES: usize = 8;

/// Read an OFF file from memory.
///
/// Accepts the `OFF`, `COFF`, `NOFF`, `CNOFF` and `NCOFF` headers (or none, as the format
/// allows), counts on the header line or the next one, `#` comments and blank
/// lines, one vertex per line (values after x, y, z are ignored) and one face per
/// line (`n i1 ... in`, 0-based, optionally followed by a colour; 3 to
/// [`super::MAX_FACE_CORNERS`] corners). Polygons are fanned into triangles.
#[cfg(test)]
pub fn read_off(bytes: &[u8]) -> Result<TriangleSoup> {
    super::parse_bytes(bytes, None, parse)
}

pub(super) fn parse(input: &mut Input<'_>) -> Result<TriangleSoup> {
    let (vertex_count, face_count) = read_header(input)?;
    let mut soup = TriangleSoup::default();
    soup.positions.reserve(capped_capacity(
        vertex_count,
        input.remaining(),
        MIN_VERTEX_BYTES,
    ));
    for i in 0..vertex_count {
        let record = input
            .next_record()?
            .ok_or_else(|| truncated(i, vertex_count, "vertices"))?;
        let point = parse_point(&mut record.split_ascii_whitespace())
            .map_err(|m| line_error(input.line(), format!("vertex {i}: {m}")))?;
        soup.positions.push(point);
    }
    soup.triangles.reserve(capped_capacity(
        face_count,
        input.remaining(),
        MIN_FACE_BYTES,
    ));
    let mut face = FaceBuffers::default();
    for i in 0..face_count {
        let record = input
            .next_record()?
            .ok_or_else(|| truncated(i, face_count, "faces"))?;
        face.push(record, vertex_count, &mut soup.triangles)
            .map_err(|m| line_error(input.line(), format!("face {i}: {m}")))?;
    }
    Ok(soup)
}

/// The vertex and face counts from the header.
fn read_header(input: &mut Input<'_>) -> Result<(usize, usize)> {
    let first = input
        .next_record()?
        .ok_or_else(|| Error::Parse("no OFF header: the file has only comments".to_string()))?;
    let keyword = first.split_ascii_whitespace().next().unwrap_or(first);
    let counts = if KEYWORDS.contains(&keyword) {
        match first[keyword.len()..].trim() {
            "" => input
                .next_record()?
                .ok_or_else(|| Error::Parse("the file ends after the OFF header".to_string()))?,
            rest => rest,
        }
    } else if keyword.ends_with("OFF") {
        return Err(line_error(
            input.line(),
            format!(
                "unsupported OFF variant {} (supported: {})",
                quoted(keyword),
                KEYWORDS.join(", ")
            ),
        ));
    } else if keyword.parse::<u64>().is_ok() {
        first
    } else {
        return Err(line_error(
            input.line(),
            format!("not an OFF file: expected 'OFF', found {}", quoted(keyword)),
        ));
    };
    parse_counts(counts).map_err(|m| line_error(input.line(), m))
}

/// `vertices faces [edges]`.
fn parse_counts(line: &str) -> std::result::Result<(usize, usize), String> {
    let mut tokens = line.split_ascii_whitespace();
    let mut count = |what: &str| {
        let token = tokens
            .next()
            .ok_or_else(|| format!("the header has no {what} count"))?;
        token
            .parse::<usize>()
            .map_err(|_| format!("cannot read the {what} count {}", quoted(token)))
    };
    Ok((count("vertex")?, count("face")?))
}

/// Reusable buffers for reading face lines.
#[derive(Default)]
struct FaceBuffers {
    corners: Vec<i64>,
    scratch: Vec<u32>,
}

impl FaceBuffers {
    /// Parse a face line `n i1 ... in [colour]` and fan it into `triangles`.
    fn push(
        &mut self,
        record: &str,
        vertex_count: usize,
        triangles: &mut Vec<[u32; 3]>,
    ) -> std::result::Result<(), String> {
        let mut tokens = record.split_ascii_whitespace();
        let n = check_corner_count(parse_number(tokens.next().unwrap_or(record))?)?;
        self.corners.clear();
        for k in 0..n {
            let token = tokens
                .next()
                .ok_or_else(|| format!("the face has {n} corners but lists only {k} indices"))?;
            self.corners.push(parse_number(token)?);
        }
        push_polygon(
            self.corners.iter().copied(),
            vertex_count,
            &mut self.scratch,
            triangles,
        )
    }
}
