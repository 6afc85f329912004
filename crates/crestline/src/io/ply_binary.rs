//! Fast decoding of binary PLY payloads straight from the file's bytes: fixed-size
//! vertex records column by column, and face records without per-record
//! allocation. Used for every binary file whose vertex element has only scalar
//! properties and whose face element has only its index list (the layout every
//! common tool writes); other layouts go through the general record reader.

use rayon::prelude::*;

use super::ply_header::{Element, PropertyType, ScalarType};
use super::ply_records::corner_count;
use super::{push_polygon, truncated, Input};
use crate::{Error, Point, Result};

/// Byte order of a binary payload.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(super) enum Endian {
    Little,
    Big,
}

/// The scalar of type `t` at the start of `b` (which holds at least its size).
#[inline]
pub(super) fn decode(t: ScalarType, b: &[u8], endian: Endian) -> f64 {
    macro_rules! read {
        ($ty:ty, $n:expr) => {{
            let mut raw = [0u8; $n];
            raw.copy_from_slice(&b[..$n]);
            match endian {
                Endian::Little => <$ty>::from_le_bytes(raw) as f64,
                Endian::Big => <$ty>::from_be_bytes(raw) as f64,
            }
        }};
    }
    match t {
        ScalarType::Char => read!(i8, 1),
        ScalarType::UChar => read!(u8, 1),
        ScalarType::Short => read!(i16, 2),
        ScalarType::UShort => read!(u16, 2),
        ScalarType::Int => read!(i32, 4),
        ScalarType::UInt => read!(u32, 4),
        ScalarType::Float => read!(f32, 4),
        ScalarType::Double => read!(f64, 8),
    }
}

/// The byte offset and type of each scalar property of a vertex record, and the
/// record size; `None` if a property is a list (records of varying size).
pub(super) fn fixed_layout(def: &Element) -> Option<(Vec<(usize, ScalarType)>, usize)> {
    let mut offset = 0;
    let mut columns = Vec::with_capacity(def.properties.len());
    for p in &def.properties {
        let PropertyType::Scalar(t) = p.kind else {
            return None;
        };
        columns.push((offset, t));
        offset += t.size();
    }
    Some((columns, offset))
}

/// The count and item types of an element made of a single list property.
pub(super) fn single_list(def: &Element) -> Option<(ScalarType, ScalarType)> {
    match def.properties.as_slice() {
        [p] => match p.kind {
            PropertyType::List { count, item } => Some((count, item)),
            PropertyType::Scalar(_) => None,
        },
        _ => None,
    }
}

/// Decode `def.count` fixed-size vertex records: positions from the columns `xyz`
/// and one `f64` column per entry of `extras`.
pub(super) fn read_vertices(
    input: &mut Input<'_>,
    def: &Element,
    (columns, stride): (&[(usize, ScalarType)], usize),
    xyz: [usize; 3],
    extras: &[usize],
    endian: Endian,
) -> Result<(Vec<Point>, Vec<Vec<f64>>)> {
    let available = input.remaining() / stride.max(1);
    if available < def.count {
        return Err(truncated(available, def.count, "'vertex' elements"));
    }
    let bytes = input.take(def.count * stride).unwrap_or_default();
    let value = |record: &[u8], column: usize| {
        let (offset, t) = columns[column];
        decode(t, &record[offset..], endian)
    };
    let positions = bytes
        .par_chunks_exact(stride)
        .map(|r| Point::new(value(r, xyz[0]), value(r, xyz[1]), value(r, xyz[2])))
        .collect();
    let extra_columns = extras
        .iter()
        .map(|&c| {
            bytes
                .par_chunks_exact(stride)
                .map(|r| value(r, c))
                .collect()
        })
        .collect();
    Ok((positions, extra_columns))
}

/// Decode `def.count` face records made of one index list (count type, index
/// type), fanning polygons into `triangles`. Errors name the face and its offset.
pub(super) fn read_faces(
    input: &mut Input<'_>,
    def: &Element,
    (count_type, index_type): (ScalarType, ScalarType),
    vertex_count: usize,
    endian: Endian,
    triangles: &mut Vec<[u32; 3]>,
) -> Result<()> {
    let bytes = input.rest();
    let (count_size, index_size) = (count_type.size(), index_type.size());
    triangles.reserve(def.count.min(bytes.len() / (count_size + 3 * index_size)));
    let mut scratch = Vec::new();
    let mut at = 0;
    for face in 0..def.count {
        let start = at;
        let locate = |message: String| {
            Error::Parse(format!(
                "face {face} (byte {}): {message}",
                input.position() + start
            ))
        };
        let count = bytes
            .get(at..at + count_size)
            .map(|b| decode(count_type, b, endian))
            .ok_or_else(|| truncated(face, def.count, "'face' elements"))?;
        let n = corner_count(count).map_err(locate)?;
        let end = at + count_size + n * index_size;
        let Some(list) = bytes.get(at + count_size..end) else {
            return Err(truncated(face, def.count, "'face' elements"));
        };
        let indices = list
            .chunks_exact(index_size)
            .map(|b| decode(index_type, b, endian) as i64);
        push_polygon(indices, vertex_count, &mut scratch, triangles).map_err(locate)?;
        at = end;
    }
    input.advance(at);
    Ok(())
}
