//! MetaImage images (`.mha` with `ElementDataFile = LOCAL`, `.mhd` with a data
//! file).
//!
//! Read: `NDims = 3`, `DimSize`, `ElementSpacing`, `Offset` (or `Origin`,
//! `Position`), `TransformMatrix` (or `Rotation`, `Orientation`: the first three
//! numbers are the direction of the first index axis, as ITK writes them),
//! `ElementType` `MET_UCHAR`, `MET_CHAR`, `MET_SHORT`, `MET_USHORT`, `MET_INT`,
//! `MET_UINT`, `MET_FLOAT`, `MET_DOUBLE`, `BinaryDataByteOrderMSB`,
//! `CompressedData` (zlib) and `HeaderSize` (-1 for uncompressed data at the end
//! of the file). The geometry is taken as written (ITK writes LPS). Refused with a
//! clear error: other dimensions, types, multi-channel and ASCII data, and lists
//! of data files.

use std::path::{Path, PathBuf};

use nalgebra::Matrix3;

use super::text_header::{detached_path, lines, read_detached, Field, Fields};
use super::{file, read_head, Compression, DataLayout, SampleType};
use crate::volume::Volume;
use crate::{Error, Result, Space};

/// Read a `.mha` or `.mhd` file.
pub(super) fn read(path: &Path) -> Result<Volume> {
    let bytes = file::read(path)?;
    let (fields, data_start) = parse_header(&bytes)?;
    check_image_kind(&fields)?;
    let layout = layout(&fields)?;
    let data_file = fields.require(&["ElementDataFile"])?;
    let samples = match data_file.value {
        "LOCAL" | "local" | "Local" => layout.read(&bytes[data_start..])?,
        list if list.starts_with("LIST") || list.contains('%') => {
            return Err(data_file.error("lists of data files are not supported"))
        }
        _ => read_detached(path, data_file, &layout)?,
    };
    let (spacing, origin, direction) = geometry(&fields)?;
    // ITK's geometry is LPS whatever `AnatomicalOrientation` says (ITK ignores it).
    Ok(Volume::new(layout.dims, spacing, origin, direction, samples)?.with_space(Some(Space::Lps)))
}

/// The detached data file the MetaImage header at `path` names, if any.
pub(super) fn data_file(path: &Path) -> Result<Option<PathBuf>> {
    let bytes = read_head(path)?;
    let (fields, _) = parse_header(&bytes)?;
    let data_file = fields.require(&["ElementDataFile"])?;
    Ok(match data_file.value {
        "LOCAL" | "local" | "Local" => None,
        name => Some(detached_path(path, name)),
    })
}

/// The fields of the header, which ends with the `ElementDataFile` line, and the
/// offset of the byte after it.
fn parse_header(bytes: &[u8]) -> Result<(Fields<'_>, usize)> {
    let mut fields = Vec::new();
    for line in lines(bytes) {
        let line = line?;
        if line.text.trim().is_empty() {
            continue;
        }
        let (key, value) = line.text.split_once('=').ok_or_else(|| {
            Error::Parse(format!(
                "line {}: expected 'Key = Value', found '{}'",
                line.number, line.text
            ))
        })?;
        let field = Field {
            key: key.trim(),
            value: value.trim(),
            line: line.number,
        };
        let last = field.key.eq_ignore_ascii_case("ElementDataFile");
        fields.push(field);
        if last {
            return Ok((Fields(fields), line.end));
        }
    }
    Err(Error::Parse(
        "missing field 'ElementDataFile' (the header must end with it)".to_string(),
    ))
}

/// Check that the file holds one scalar 3-D binary image.
fn check_image_kind(fields: &Fields<'_>) -> Result<()> {
    let dims = fields.require(&["NDims"])?;
    if dims.number::<i64>()? != 3 {
        return Err(dims.error("only 3-D images are read"));
    }
    if let Some(field) = fields.get(&["ElementNumberOfChannels"]) {
        if field.number::<i64>()? != 1 {
            return Err(field.error("only single-channel images are read"));
        }
    }
    if let Some(field) = fields.get(&["BinaryData"]) {
        if !field.boolean()? {
            return Err(field.error("ASCII data is not supported"));
        }
    }
    Ok(())
}

/// How the samples are stored.
fn layout(fields: &Fields<'_>) -> Result<DataLayout> {
    let flag = |names: &[&str]| fields.get(names).map_or(Ok(false), Field::boolean);
    let compressed = flag(&["CompressedData"])?;
    Ok(DataLayout {
        dims: fields.require(&["DimSize"])?.three()?,
        sample_type: sample_type(fields.require(&["ElementType"])?)?,
        little_endian: !flag(&["BinaryDataByteOrderMSB", "ElementByteOrderMSB"])?,
        compression: if compressed {
            Compression::Zlib
        } else {
            Compression::None
        },
        skip: fields.skip(&["HeaderSize"])?,
    })
}

/// The sample type named by `ElementType`.
fn sample_type(field: &Field<'_>) -> Result<SampleType> {
    Ok(match field.value {
        "MET_UCHAR" => SampleType::U8,
        "MET_CHAR" => SampleType::I8,
        "MET_SHORT" => SampleType::I16,
        "MET_USHORT" => SampleType::U16,
        "MET_INT" => SampleType::I32,
        "MET_UINT" => SampleType::U32,
        "MET_FLOAT" => SampleType::F32,
        "MET_DOUBLE" => SampleType::F64,
        other => return Err(field.error(format!("unsupported ElementType '{other}'"))),
    })
}

/// Spacing, origin and direction as written.
fn geometry(fields: &Fields<'_>) -> Result<([f64; 3], [f64; 3], Matrix3<f64>)> {
    let spacing = match fields.get(&["ElementSpacing", "ElementSize"]) {
        Some(field) => field.three()?,
        None => [1.0; 3],
    };
    let origin = match fields.get(&["Offset", "Origin", "Position"]) {
        Some(field) => field.three()?,
        None => [0.0; 3],
    };
    let direction = match fields.get(&["TransformMatrix", "Rotation", "Orientation"]) {
        Some(field) => {
            let t: Vec<f64> = field.numbers(field.value, char::is_whitespace, 9)?;
            Matrix3::from_fn(|row, axis| t[3 * axis + row])
        }
        None => Matrix3::identity(),
    };
    Ok((spacing, origin, direction))
}
