//! What crestline reads of each DICOM file before its pixels: the series it
//! belongs to, how its pixels are stored (PS3.3 C.7.6.3 Image Pixel Module) and
//! where each of its frames lies ([`super::multiframe`]).
//!
//! Each file is read whole (for [`super::lengths`] to check it against its size)
//! but parsed only up to the Pixel Data element (7FE0,0010): grouping and checking
//! a series decodes no pixel. A file without Rows (0028,0010) is not an image (a
//! DICOMDIR, a structure set, a report) and is skipped.

use std::path::{Path, PathBuf};

use dicom_dictionary_std::tags;
use dicom_object::file::ReadPreamble;
use dicom_object::{DefaultDicomObject, InMemDicomObject, OpenFileOptions, Tag};

use super::pixels::{self, Rescale};
use super::{lengths, multiframe};
use crate::volume::voxel_count;
use crate::{Error, Point, Result, Vector};

/// A DICOM data set (the root of a file or an item of a sequence).
pub(super) type Object = InMemDicomObject;

/// One 2D image of a file: where it lies and how its stored values become
/// modality values.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Frame {
    /// The frame's number in its file, from 0.
    pub number: u32,
    /// Its plane in the patient coordinate system.
    pub plane: Plane,
    /// Its modality LUT (PS3.3 C.11.1).
    pub rescale: Rescale,
}

/// The placement of a frame, as the Image Plane Module (PS3.3 C.7.6.2) or the
/// Plane Position, Plane Orientation and Pixel Measures functional groups
/// (C.7.6.16.2.3–5) give it; absent attributes are `None`.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Plane {
    /// Rows (0028,0010) and Columns (0028,0011).
    pub size: [u32; 2],
    /// Image Position (Patient) (0020,0032): the centre of the first pixel, mm.
    pub position: Option<Point>,
    /// Image Orientation (Patient) (0020,0037): the direction of the rows (of
    /// increasing column index) and of the columns.
    pub orientation: Option<[Vector; 2]>,
    /// Pixel Spacing (0028,0030): between rows, then between columns, mm.
    pub pixel_spacing: Option<[f64; 2]>,
    /// Slice Thickness (0018,0050), mm: the slice spacing of a lone slice only.
    pub thickness: Option<f64>,
}

/// The attributes of a DICOM image file that reading its series needs.
#[derive(Clone, Debug)]
pub(super) struct Header {
    /// The file.
    pub path: PathBuf,
    /// Series Instance UID (0020,000E), empty if absent.
    pub series: String,
    /// Its frames, in the order stored.
    pub frames: Vec<Frame>,
}

/// The header of the DICOM file at `path`, or `None` if it holds no image.
/// Errors name the file: one that cannot be parsed, pixels that are not one
/// sample of 8, 16 or 32 bits, a transfer syntax this build cannot decode.
pub(super) fn read(path: &Path) -> Result<Option<Header>> {
    let object = open(path, Some(tags::PIXEL_DATA))?;
    let header = || -> Result<Option<Header>> {
        let Some(rows) = unsigned(&object, tags::ROWS, "Rows")? else {
            return Ok(None);
        };
        let columns = unsigned(&object, tags::COLUMNS, "Columns")?
            .ok_or_else(|| missing("Columns", tags::COLUMNS))?;
        check_pixel_format(&object)?;
        pixels::check_transfer_syntax(object.meta().transfer_syntax())?;
        let count = unsigned(&object, tags::NUMBER_OF_FRAMES, "Number of Frames")?.unwrap_or(1);
        voxel_count([columns as usize, rows as usize, count as usize])?;
        Ok(Some(Header {
            path: path.to_path_buf(),
            series: text(&object, tags::SERIES_INSTANCE_UID).unwrap_or_default(),
            frames: multiframe::frames(&object, [rows, columns], count)?,
        }))
    };
    header().map_err(|e| super::super::in_file(e, path))
}

/// The DICOM file at `path`, parsed up to the element `until` (all of it for
/// `None`) after checking its `DICM` mark and its element lengths
/// ([`super::lengths`]). Errors name the file.
pub(super) fn open(path: &Path, until: Option<Tag>) -> Result<DefaultDicomObject> {
    let bytes = crate::io::file::read(path)?;
    let fail = |message: String| Error::File {
        path: path.to_path_buf(),
        message,
    };
    if bytes.get(128..132) != Some(b"DICM") {
        return Err(fail(
            "has no DICM mark at byte 128: not a DICOM file (or one without the preamble of PS3.10 §7.1)"
                .to_string(),
        ));
    }
    lengths::check(&bytes).map_err(|e| super::super::in_file(e, path))?;
    let options = OpenFileOptions::new().read_preamble(ReadPreamble::Never);
    let options = match until {
        Some(tag) => options.read_until(tag),
        None => options,
    };
    options
        .from_reader(&bytes[128..])
        .map_err(|e| fail(format!("cannot be read as DICOM: {}", causes(&e))))
}

/// `err` and the errors that caused it, on one line, its backticks made quotes.
pub(super) fn causes(err: &dyn std::error::Error) -> String {
    let mut text = err.to_string();
    let mut source = err.source();
    while let Some(cause) = source {
        let message = cause.to_string();
        if !text.contains(&message) {
            text = format!("{text}: {message}");
        }
        source = cause.source();
    }
    // A library's message may quote a name between backticks: it is a quote, not
    // one of crestline's option names (which messages write between backticks).
    let text = text.replace(['\n', '\r'], " ").replace('`', "'");
    // jpeg-decoder names the feature it lacks by its Rust value.
    text.replace("SamplePrecision(", "sample precision (bits: ")
}

/// An error unless the pixels are one sample (PS3.3 C.7.6.3.1.1) of 8, 16 or 32
/// allocated bits, at most that many stored.
fn check_pixel_format(object: &Object) -> Result<()> {
    let samples = unsigned(object, tags::SAMPLES_PER_PIXEL, "Samples per Pixel")?.unwrap_or(1);
    if samples != 1 {
        return Err(Error::Parse(format!(
            "has {samples} samples per pixel (a colour image); a volume needs one (MONOCHROME1 or MONOCHROME2)"
        )));
    }
    let allocated = unsigned(object, tags::BITS_ALLOCATED, "Bits Allocated")?
        .ok_or_else(|| missing("Bits Allocated", tags::BITS_ALLOCATED))?;
    if ![8, 16, 32].contains(&allocated) {
        return Err(Error::Parse(format!(
            "has Bits Allocated (0028,0100) {allocated}; 8, 16 or 32 are supported"
        )));
    }
    let stored = unsigned(object, tags::BITS_STORED, "Bits Stored")?.unwrap_or(allocated);
    if stored == 0 || stored > allocated {
        return Err(Error::Parse(format!(
            "has Bits Stored (0028,0101) {stored} for {allocated} bits allocated"
        )));
    }
    Ok(())
}

/// The error for a required attribute that is absent.
fn missing(name: &str, tag: Tag) -> Error {
    Error::Parse(format!("has no {name} {tag}"))
}

/// The value of the unsigned attribute `tag` (US, UL or IS), if present.
pub(super) fn unsigned(object: &Object, tag: Tag, name: &str) -> Result<Option<u32>> {
    match object.get(tag) {
        None => Ok(None),
        Some(element) => element
            .to_int::<u32>()
            .map(Some)
            .map_err(|_| Error::Parse(format!("its {name} {tag} is not a count"))),
    }
}

/// The `N` finite numbers of the decimal attribute `tag` (DS or FD), if present
/// and not empty (type 2 attributes may be empty).
pub(super) fn numbers<const N: usize>(
    object: &Object,
    tag: Tag,
    name: &str,
) -> Result<Option<[f64; N]>> {
    let values = decimals(object, tag, name, N)?;
    Ok(values.map(|values| std::array::from_fn(|i| values[i])))
}

/// The `count` finite numbers of the decimal attribute `tag` (DS or FD), if
/// present and not empty.
pub(super) fn decimals(
    object: &Object,
    tag: Tag,
    name: &str,
    count: usize,
) -> Result<Option<Vec<f64>>> {
    let Some(element) = object.get(tag) else {
        return Ok(None);
    };
    if text(object, tag).is_some_and(|text| text.is_empty()) {
        return Ok(None);
    }
    let valid = |values: Vec<f64>| {
        Some(values).filter(|values| values.len() == count && values.iter().all(|v| v.is_finite()))
    };
    // An element of VR UN (written by a tool that did not know the attribute)
    // holds the decimal string as bytes.
    let values = element
        .to_multi_float64()
        .ok()
        .and_then(valid)
        .or_else(|| decimal_strings(&element.to_bytes().ok()?).and_then(valid));
    values
        .map(Some)
        .ok_or_else(|| Error::Parse(format!("its {name} {tag} is not {count} finite numbers")))
}

/// The tag that the attribute `tag` (AT) holds, if present; of VR UN, the
/// little-endian group and element numbers of its bytes.
pub(super) fn tag_value(object: &Object, tag: Tag) -> Option<Tag> {
    let element = object.get(tag)?;
    element.value().to_tag().ok().or_else(|| {
        let bytes = element.to_bytes().ok()?;
        let [g0, g1, e0, e1] = *bytes.as_ref() else {
            return None;
        };
        Some(Tag(
            u16::from_le_bytes([g0, g1]),
            u16::from_le_bytes([e0, e1]),
        ))
    })
}

/// The numbers of a multi-valued decimal string (PS3.5 §6.2, DS) in `bytes`.
fn decimal_strings(bytes: &[u8]) -> Option<Vec<f64>> {
    std::str::from_utf8(bytes)
        .ok()?
        .trim_matches(|c: char| c.is_whitespace() || c == '\0')
        .split('\\')
        .map(|value| value.trim().parse().ok())
        .collect()
}

/// The text of the attribute `tag` without padding, if present.
pub(super) fn text(object: &Object, tag: Tag) -> Option<String> {
    let value = object.get(tag)?.to_str().ok()?;
    Some(
        value
            .trim_matches(|c: char| c.is_whitespace() || c == '\0')
            .to_string(),
    )
}

/// The first item of the sequence `tag` of `object`, if it has one.
pub(super) fn first_item(object: &Object, tag: Tag) -> Option<&Object> {
    object.get(tag)?.items()?.first()
}

#[cfg(test)]
mod tests {
    use super::causes;

    #[test]
    fn a_decoders_rust_value_reads_as_words() {
        let error = std::io::Error::other("unsupported JPEG feature: SamplePrecision(12)");
        assert_eq!(
            causes(&error),
            "unsupported JPEG feature: sample precision (bits: 12)"
        );
    }
}
