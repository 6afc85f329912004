//! FreeSurfer per-vertex value files in the "new" curv format (`lh.curv`,
//! `lh.sulc`, `lh.thickness`; see the parent module for the layout). The old
//! format, without magic bytes and with values stored as 16-bit integers, is
//! refused.

use std::io::Write;
use std::path::Path;

use crate::atomic::write_atomically;
use crate::io::fits_f32;
use crate::{Error, Result};

use super::{be_i32, count, CURV_MAGIC};

/// Bytes before the values: the magic, and the vertex, face and per-vertex counts.
const HEADER_BYTES: usize = 15;

/// Read a curv file: one value per vertex of its surface, in vertex order.
///
/// Errors ([`Error::File`] naming `path`): no magic bytes, several values per
/// vertex, or fewer values than the header announces.
#[cfg(test)]
pub fn read_curv(path: &Path) -> Result<Vec<f64>> {
    let bytes = crate::io::file::read(path)?;
    parse_curv(&bytes).map_err(|e| e.in_file(path))
}

/// [`read_curv`] of bytes in memory.
pub(crate) fn parse_curv(bytes: &[u8]) -> Result<Vec<f64>> {
    if !bytes.starts_with(&CURV_MAGIC) {
        return Err(Error::Parse(
            "not a FreeSurfer curv file of the new format (no magic bytes FF FF FF)".into(),
        ));
    }
    let mut pos = CURV_MAGIC.len();
    let mut header = [0i32; 3];
    for word in &mut header {
        *word = be_i32(bytes, &mut pos)
            .ok_or_else(|| Error::Parse("the file ends in its header".into()))?;
    }
    let vertex_count = count(header[0], "vertex")?;
    if header[2] != 1 {
        return Err(Error::Parse(format!(
            "{} values per vertex (only files of one value per vertex are read)",
            header[2]
        )));
    }
    let values = &bytes[HEADER_BYTES..];
    if values.len() / 4 < vertex_count {
        return Err(crate::io::truncated(
            values.len() / 4,
            vertex_count,
            "values",
        ));
    }
    Ok(values
        .chunks_exact(4)
        .take(vertex_count)
        .map(|b| f64::from(f32::from_be_bytes([b[0], b[1], b[2], b[3]])))
        .collect())
}

/// Write `values`, one per vertex of a surface of `face_count` faces, as a curv
/// file (32-bit floats). Written atomically.
///
/// Errors ([`Error::File`] naming `path`): a value that is not a finite 32-bit
/// float, or counts too large for the format.
pub fn write_curv(path: &Path, values: &[f64], face_count: usize) -> Result<()> {
    let fail = |message: String| Error::File {
        path: path.to_path_buf(),
        message,
    };
    if let Some(v) = values.iter().position(|&x| !fits_f32(x)) {
        return Err(fail(format!(
            "the value of vertex {v} ({}) is not a finite 32-bit float",
            values[v]
        )));
    }
    let counts = [values.len(), face_count].map(i32::try_from);
    let [Ok(vertex_count), Ok(face_count)] = counts else {
        return Err(fail("too many vertices or faces for the format".into()));
    };
    write_atomically(path, |w| {
        w.write_all(&CURV_MAGIC)?;
        for word in [vertex_count, face_count, 1] {
            w.write_all(&word.to_be_bytes())?;
        }
        for &x in values {
            w.write_all(&(x as f32).to_be_bytes())?;
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curv(header: [i32; 3], values: &[f32]) -> Vec<u8> {
        let mut bytes = CURV_MAGIC.to_vec();
        bytes.extend(header.iter().flat_map(|w| w.to_be_bytes()));
        bytes.extend(values.iter().flat_map(|x| x.to_be_bytes()));
        bytes
    }

    #[test]
    fn values_read_in_order_and_bad_headers_are_refused() {
        let values = [0.5f32, -1.25, 3.0e-7];
        let read = parse_curv(&curv([3, 2, 1], &values)).unwrap();
        assert_eq!(read, values.map(f64::from));
        let short = parse_curv(&curv([4, 2, 1], &values)).unwrap_err();
        assert!(short.to_string().contains("after 3 of 4 values"), "{short}");
        let absurd = parse_curv(&curv([i32::MAX, 2, 1], &values)).unwrap_err();
        assert!(absurd.to_string().contains("truncated"), "{absurd}");
        let several = parse_curv(&curv([3, 2, 3], &values)).unwrap_err();
        assert!(
            several.to_string().contains("3 values per vertex"),
            "{several}"
        );
        assert!(parse_curv(&[0xFF, 0xFF, 0xFF, 0]).is_err());
        assert!(parse_curv(b"0.5\n1.0\n").is_err());
    }

    #[test]
    fn written_files_read_back() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("lh.test.curv");
        write_curv(&path, &[1.5, -0.25], 7).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(bytes, curv([2, 7, 1], &[1.5, -0.25]));
        assert_eq!(read_curv(&path).unwrap(), vec![1.5, -0.25]);
        assert!(write_curv(&path, &[f64::NAN], 1).is_err());
    }
}
