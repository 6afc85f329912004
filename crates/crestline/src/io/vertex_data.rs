//! Per-vertex values in files of their own, in the order of a mesh file's
//! vertices: FreeSurfer curv files (`lh.curv`, `lh.sulc`, told by their magic
//! bytes whatever their name), GIfTI `.shape.gii`/`.func.gii` (any `.gii`), or
//! text with one number per line. [`write_vertex_values`] writes the first two.

use std::path::Path;

use super::format::{choose_format, FileFormat};
use super::freesurfer::{curv, CURV_MAGIC};
use super::gifti::{self, Metadata};
use super::Structure;
use crate::{Error, Result};

/// The formats [`write_vertex_values`] writes.
pub const VERTEX_VALUE_FORMATS: [FileFormat; 3] = [
    FileFormat::GiftiShape,
    FileFormat::GiftiFunc,
    FileFormat::FreeSurferCurv,
];

/// Write one value per vertex in the format of the extension of `path`: a GIfTI
/// `.shape.gii` (`NIFTI_INTENT_SHAPE`) or `.func.gii` (`NIFTI_INTENT_NONE`), the
/// array with `metadata` (e.g. its `Name`) and the file with `structure` (as
/// Workbench's `AnatomicalStructurePrimary`, which it reads from the file's
/// metadata to place the values), or a FreeSurfer `.curv` of a surface of
/// `face_count` faces (no metadata, and no NaN). Written atomically.
///
/// Errors ([`Error::File`] naming `path`): an unsupported extension, a value too
/// large for a 32-bit float, a NaN in a curv file.
pub fn write_vertex_values(
    path: &Path,
    values: &[f64],
    (metadata, structure): (&Metadata<'_>, Structure),
    face_count: usize,
) -> Result<()> {
    let file_metadata = structure.gifti_metadata();
    match choose_format(path, "per-vertex values", &VERTEX_VALUE_FORMATS)? {
        FileFormat::FreeSurferCurv => curv::write_curv(path, values, face_count),
        FileFormat::GiftiShape => {
            gifti::write_gifti_values(path, values, "NIFTI_INTENT_SHAPE", metadata, &file_metadata)
        }
        _ => gifti::write_gifti_values(path, values, "NIFTI_INTENT_NONE", metadata, &file_metadata),
    }
}

/// Read one value per vertex from `path`: a FreeSurfer curv file (by its magic
/// bytes), a GIfTI file (by its `.gii` extension: its first array) or text (one
/// number per non-empty line).
///
/// Errors are [`Error::File`] naming `path` and the problem (the line of a text
/// file, the `DataArray` of a GIfTI file).
pub fn read_vertex_values(path: &Path) -> Result<Vec<f64>> {
    let bytes = super::file::read(path)?;
    let values = if bytes.starts_with(&CURV_MAGIC) {
        curv::parse_curv(&bytes)
    } else if choose_format(path, "", &[FileFormat::Gifti]).is_ok() {
        gifti::parse_values(&bytes)
    } else {
        parse_text(&bytes)
    };
    values.map_err(|e| e.in_file(path))
}

/// One number per non-empty line.
fn parse_text(bytes: &[u8]) -> Result<Vec<f64>> {
    let text = std::str::from_utf8(bytes).map_err(|_| {
        Error::Parse(
            "neither text with one number per line, nor a FreeSurfer curv or GIfTI file".into(),
        )
    })?;
    text.lines()
        .enumerate()
        .filter(|(_, line)| !line.trim().is_empty())
        .map(|(i, line)| {
            line.trim().parse::<f64>().map_err(|_| {
                super::line_error(
                    i + 1,
                    format!("{} is not a number", super::quoted(line.trim())),
                )
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_kind_of_file_is_told_apart() {
        let dir = tempfile::tempdir().unwrap();
        let text = dir.path().join("weights.txt");
        std::fs::write(&text, "1\n\n2.5\n").unwrap();
        assert_eq!(read_vertex_values(&text).unwrap(), [1.0, 2.5]);
        std::fs::write(&text, "1\nx\n").unwrap();
        let error = read_vertex_values(&text).unwrap_err().to_string();
        assert!(
            error.contains("weights.txt: line 2: 'x' is not a number"),
            "{error}"
        );
        let sulc = dir.path().join("lh.sulc");
        curv::write_curv(&sulc, &[0.25, -1.0], 1).unwrap();
        assert_eq!(read_vertex_values(&sulc).unwrap(), [0.25, -1.0]);
        let shape = dir.path().join("lh.thickness.shape.gii");
        gifti::write_gifti_values(&shape, &[3.0], "NIFTI_INTENT_SHAPE", &[], &[]).unwrap();
        assert_eq!(read_vertex_values(&shape).unwrap(), [3.0]);
    }
}
