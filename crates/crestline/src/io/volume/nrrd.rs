//! NRRD images (`.nrrd` with attached data, `.nhdr` with `data file:`).
//!
//! Read: `dimension: 3`, the scalar types of [`SampleType`], `raw` and `gzip`
//! encodings, `endian`, `byte skip` (-1 for raw data), `sizes`, and either
//! `space directions` with `space origin` or `spacings`. The geometry is taken as
//! written, in the file's `space`. Refused with a clear error: other dimensions,
//! encodings (`ascii`, `hex`, `bzip2`), types, `line skip` and multi-file data.

use std::path::{Path, PathBuf};

use nalgebra::Matrix3;

use super::text_header::{detached_path, lines, read_detached, Field, Fields};
use super::{file, read_head, Compression, DataLayout, SampleType};
use crate::volume::Volume;
use crate::{Error, Result, Space};

/// Read a `.nrrd` or `.nhdr` file.
pub(super) fn read(path: &Path) -> Result<Volume> {
    let bytes = file::read(path)?;
    let (fields, data_start) = parse_header(&bytes)?;
    let layout = layout(&fields)?;
    let samples = match fields.get(&["data file", "datafile"]) {
        Some(field) => read_detached(path, field, &layout)?,
        None => {
            let start = data_start.ok_or_else(|| {
                Error::Parse(
                    "no data: the header has neither a 'data file' field nor a blank line before attached data"
                        .to_string(),
                )
            })?;
            layout.read(&bytes[start..])?
        }
    };
    let (spacing, mut origin, mut direction) = geometry(&fields)?;
    let space = match fields.get(&["space"]).map(|field| field.value.trim()) {
        Some("right-anterior-superior" | "RAS") => Some(Space::Ras),
        Some("left-posterior-superior" | "LPS") => Some(Space::Lps),
        Some("left-anterior-superior" | "LAS") => {
            // LAS differs from RAS by the sign of x alone: read as RAS.
            origin[0] = -origin[0];
            direction.row_mut(0).neg_mut();
            Some(Space::Ras)
        }
        _ => None,
    };
    Ok(Volume::new(layout.dims, spacing, origin, direction, samples)?.with_space(space))
}

/// The detached data file the NRRD header at `path` names, if any.
pub(super) fn data_file(path: &Path) -> Result<Option<PathBuf>> {
    let bytes = read_head(path)?;
    let (fields, _) = parse_header(&bytes)?;
    Ok(fields
        .get(&["data file", "datafile"])
        .map(|field| detached_path(path, field.value)))
}

/// The fields of the header and, if it ends with a blank line, the offset of the
/// attached data after it.
fn parse_header(bytes: &[u8]) -> Result<(Fields<'_>, Option<usize>)> {
    let mut lines = lines(bytes);
    let first = lines.next().transpose()?;
    if !first.is_some_and(|line| line.text.starts_with("NRRD000")) {
        return Err(Error::Parse(
            "line 1: not a NRRD file (it must start with NRRD0001 to NRRD0005)".to_string(),
        ));
    }
    let mut fields = Vec::new();
    for line in lines {
        let line = line?;
        let text = line.text;
        if text.is_empty() {
            return Ok((Fields(fields), Some(line.end)));
        }
        if text.starts_with('#') || text.contains(":=") {
            continue; // a comment or a key/value pair
        }
        let (key, value) = text.split_once(": ").ok_or_else(|| {
            Error::Parse(format!(
                "line {}: expected 'field: value', found '{text}'",
                line.number
            ))
        })?;
        fields.push(Field {
            key: key.trim(),
            value: value.trim(),
            line: line.number,
        });
    }
    Ok((Fields(fields), None))
}

/// How the samples are stored, from `dimension`, `type`, `sizes`, `encoding`,
/// `endian` and `byte skip`.
fn layout(fields: &Fields<'_>) -> Result<DataLayout> {
    let dimension = fields.require(&["dimension"])?;
    if dimension.number::<i64>()? != 3 {
        return Err(dimension.error("only 3-D images are read"));
    }
    let type_field = fields.require(&["type"])?;
    let sample_type = sample_type(type_field)?;
    let encoding = fields.require(&["encoding"])?;
    let compression = match encoding.value.to_ascii_lowercase().as_str() {
        "raw" => Compression::None,
        "gzip" | "gz" => Compression::Gzip,
        other => {
            return Err(encoding.error(format!(
                "unsupported encoding '{other}' (raw and gzip are read)"
            )))
        }
    };
    if let Some(field) = fields.get(&["line skip", "lineskip"]) {
        if field.number::<i64>()? != 0 {
            return Err(field.error("a line skip is not supported"));
        }
    }
    Ok(DataLayout {
        dims: fields.require(&["sizes"])?.three()?,
        sample_type,
        little_endian: little_endian(fields, sample_type)?,
        compression,
        skip: fields.skip(&["byte skip", "byteskip"])?,
    })
}

/// The sample type named by the `type` field.
fn sample_type(field: &Field<'_>) -> Result<SampleType> {
    Ok(match field.value {
        "uchar" | "unsigned char" | "uint8" | "uint8_t" => SampleType::U8,
        "signed char" | "int8" | "int8_t" => SampleType::I8,
        "short" | "short int" | "signed short" | "signed short int" | "int16" | "int16_t" => {
            SampleType::I16
        }
        "ushort" | "unsigned short" | "unsigned short int" | "uint16" | "uint16_t" => {
            SampleType::U16
        }
        "int" | "signed int" | "int32" | "int32_t" => SampleType::I32,
        "uint" | "unsigned int" | "uint32" | "uint32_t" => SampleType::U32,
        "float" => SampleType::F32,
        "double" => SampleType::F64,
        other => return Err(field.error(format!("unsupported type '{other}'"))),
    })
}

/// The byte order from `endian`, which samples wider than a byte need.
fn little_endian(fields: &Fields<'_>, sample_type: SampleType) -> Result<bool> {
    match fields.get(&["endian"]) {
        Some(field) => match field.value {
            "little" => Ok(true),
            "big" => Ok(false),
            other => Err(field.error(format!("expected little or big, found '{other}'"))),
        },
        None if sample_type.size() == 1 => Ok(true),
        None => Err(Error::Parse(
            "missing field 'endian' (needed for samples wider than a byte)".to_string(),
        )),
    }
}

/// Spacing, origin and direction: from `space directions` (the world vector of
/// each index step) and `space origin`, else `spacings` on the identity.
fn geometry(fields: &Fields<'_>) -> Result<([f64; 3], [f64; 3], Matrix3<f64>)> {
    let origin = match fields.get(&["space origin"]) {
        Some(field) => vectors(field, 1)?[0],
        None => [0.0; 3],
    };
    if let Some(field) = fields.get(&["space directions"]) {
        let steps = vectors(field, 3)?;
        let spacing: [f64; 3] =
            std::array::from_fn(|a| steps[a].iter().map(|c| c * c).sum::<f64>().sqrt());
        let direction = Matrix3::from_fn(|row, axis| steps[axis][row] / spacing[axis]);
        return Ok((spacing, origin, direction));
    }
    let spacing = match fields.get(&["spacings"]) {
        Some(field) => field.three()?,
        None => [1.0; 3],
    };
    Ok((spacing, origin, Matrix3::identity()))
}

/// `count` vectors of 3 numbers written `(x,y,z)`, separated by whitespace.
fn vectors(field: &Field<'_>, count: usize) -> Result<Vec<[f64; 3]>> {
    let pieces: Vec<&str> = field
        .value
        .split(')')
        .map(str::trim)
        .filter(|piece| !piece.is_empty())
        .collect();
    if pieces.len() != count {
        return Err(field.error(format!(
            "expected {count} vectors like (1,0,0), found '{}'",
            field.value
        )));
    }
    pieces
        .iter()
        .map(|piece| {
            let inner = piece.strip_prefix('(').ok_or_else(|| {
                field.error(format!("expected a vector like (1,0,0), found '{piece}'"))
            })?;
            let v = field.numbers(inner, |c| c == ',' || c.is_whitespace(), 3)?;
            Ok([v[0], v[1], v[2]])
        })
        .collect()
}
