//! STL (stereolithography) reading, ASCII and binary.

use super::{line_error, parse_point, push_polygon, quoted, truncated, Input};
use crate::mesh::TriangleSoup;
use crate::{Error, Point, Result};

/// Bytes before the first facet of a binary STL: an 80-byte header and a `u32` count.
const BINARY_HEADER_BYTES: usize = 84;
/// Bytes per facet of a binary STL: normal, three corners (12 `f32`) and a `u16`.
const BINARY_FACET_BYTES: usize = 50;

/// Read an STL file from memory, ASCII or binary.
///
/// The file is binary when its size is exactly 84 + 50 × the triangle count stored
/// at byte 80 (even if the header starts with `solid`, as some exporters write);
/// otherwise it must be ASCII (`solid` ... `endsolid`, possibly several solids).
/// STL stores every facet's corners separately, so each triangle gets three new
/// positions: [`crate::mesh::Mesh::from_soup`] welds the duplicates. Facet normals
/// are ignored.
#[cfg(test)]
pub fn read_stl(bytes: &[u8]) -> Result<TriangleSoup> {
    super::parse_bytes(bytes, None, parse)
}

pub(super) fn parse(input: &mut Input<'_>) -> Result<TriangleSoup> {
    let bytes = input.rest();
    let declared = bytes
        .get(80..BINARY_HEADER_BYTES)
        .and_then(|b| b.try_into().ok())
        .map(|b| u64::from(u32::from_le_bytes(b)));
    let binary_size = |n: u64| BINARY_HEADER_BYTES as u64 + BINARY_FACET_BYTES as u64 * n;
    match declared {
        Some(n) if binary_size(n) == bytes.len() as u64 => parse_binary(input, n),
        _ if bytes.trim_ascii_start().starts_with(b"solid") => parse_ascii(input),
        Some(n) => Err(binary_size_error(n, bytes.len())),
        None => Err(Error::Parse(
            "not an STL file: too short for a binary STL and no 'solid' keyword".to_string(),
        )),
    }
}

/// The error for a binary STL whose size does not match its triangle count.
fn binary_size_error(declared: u64, size: usize) -> Error {
    let facets = (size - BINARY_HEADER_BYTES) / BINARY_FACET_BYTES;
    if (facets as u64) < declared {
        truncated(facets, declared as usize, "triangles of the binary STL")
    } else {
        Error::Parse(format!(
            "binary STL: {} bytes follow the {declared} triangles its header announces",
            size - BINARY_HEADER_BYTES - declared as usize * BINARY_FACET_BYTES
        ))
    }
}

fn parse_binary(input: &mut Input<'_>, facet_count: u64) -> Result<TriangleSoup> {
    let too_many = || Error::Parse(format!("binary STL: too many triangles ({facet_count})"));
    let n = usize::try_from(facet_count).map_err(|_| too_many())?;
    u32::try_from(3 * facet_count).map_err(|_| too_many())?;
    input.take(BINARY_HEADER_BYTES);
    let mut soup = TriangleSoup::default();
    soup.positions.reserve(3 * n);
    soup.triangles.reserve(n);
    for i in 0..n {
        let facet = input
            .take(BINARY_FACET_BYTES)
            .ok_or_else(|| truncated(i, n, "triangles of the binary STL"))?;
        // Bytes 0..12 hold the normal; the corners follow.
        soup.positions
            .extend((0..3).map(|k| binary_point(facet, 12 + 12 * k)));
        let first = 3 * i as u32;
        soup.triangles.push([first, first + 1, first + 2]);
    }
    Ok(soup)
}

/// Three little-endian `f32` at `offset` of a facet record.
fn binary_point(facet: &[u8], offset: usize) -> Point {
    let coordinate = |k: usize| {
        let at = offset + 4 * k;
        f64::from(f32::from_le_bytes([
            facet[at],
            facet[at + 1],
            facet[at + 2],
            facet[at + 3],
        ]))
    };
    Point::new(coordinate(0), coordinate(1), coordinate(2))
}

/// Where an ASCII STL parser is.
enum State {
    /// Between solids.
    Outside,
    /// Inside `solid`, between facets.
    InSolid,
    /// Inside `outer loop`: the index of the loop's first vertex.
    InLoop(usize),
}

fn parse_ascii(input: &mut Input<'_>) -> Result<TriangleSoup> {
    let mut soup = TriangleSoup::default();
    let mut scratch = Vec::new();
    let mut state = State::Outside;
    while let Some(record) = input.next_line()? {
        let mut tokens = record.split_ascii_whitespace();
        let Some(keyword) = tokens.next() else {
            continue;
        };
        let line = input.line();
        state = match (keyword, state) {
            ("solid", State::Outside) => State::InSolid,
            ("facet" | "endfacet", State::InSolid) => State::InSolid,
            ("outer", State::InSolid) => State::InLoop(soup.positions.len()),
            ("vertex", State::InLoop(start)) => {
                let point = parse_point(&mut tokens).map_err(|m| line_error(line, m))?;
                soup.positions.push(point);
                State::InLoop(start)
            }
            ("endloop", State::InLoop(start)) => {
                let end = soup.positions.len();
                push_polygon(
                    (start..end).map(|i| i as i64),
                    end,
                    &mut scratch,
                    &mut soup.triangles,
                )
                .map_err(|m| line_error(line, m))?;
                State::InSolid
            }
            ("endsolid", State::InSolid) => State::Outside,
            (other, _) => {
                return Err(line_error(
                    line,
                    format!("unexpected {} in an ASCII STL file", quoted(other)),
                ))
            }
        };
    }
    match state {
        State::Outside => Ok(soup),
        _ => Err(Error::Parse(
            "the file ends inside a solid, before 'endsolid' (truncated file?)".to_string(),
        )),
    }
}
