//! Reading 3D images into a [`Volume`].
//!
//! [`read_volume`] chooses the reader by the file extension: NIfTI-1 and NIfTI-2
//! (`.nii`, `.nii.gz`), NRRD (`.nrrd`, `.nhdr` with a detached data file) and
//! MetaImage (`.mha`, `.mhd` with a detached data file). [`read_raw_volume`] reads
//! headerless samples whose layout the caller knows. Samples of every type become
//! `f32` (32-bit integers and doubles may lose precision).
//!
//! Headers are checked before their data is read: the voxel count must be at most
//! [`crate::volume::MAX_VOXELS`], and memory for the samples grows only with the
//! bytes actually present, so a corrupt header cannot trigger a huge allocation.
//! Errors are [`Error::File`] naming the file and what is wrong: the line and field
//! of a text header, the field of a binary one, or how many bytes a truncated file
//! holds ("the data ends after N of M bytes").

mod metaimage;
mod nifti;
mod nrrd;
mod text_header;

use std::io::Read;
use std::path::{Path, PathBuf};

use flate2::read::{MultiGzDecoder, ZlibDecoder};

use super::format::{choose_format, extensions, FileFormat};
use crate::volume::{voxel_count, Volume};
use crate::{Error, Result};

/// The type of the samples stored in an image file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SampleType {
    /// Unsigned 8-bit integers.
    U8,
    /// Signed 8-bit integers.
    I8,
    /// Signed 16-bit integers.
    I16,
    /// Unsigned 16-bit integers.
    U16,
    /// Signed 32-bit integers.
    I32,
    /// Unsigned 32-bit integers.
    U32,
    /// 32-bit floats.
    F32,
    /// 64-bit floats.
    F64,
}

impl SampleType {
    /// The size of one sample in bytes.
    pub fn size(self) -> usize {
        match self {
            SampleType::U8 | SampleType::I8 => 1,
            SampleType::I16 | SampleType::U16 => 2,
            SampleType::I32 | SampleType::U32 | SampleType::F32 => 4,
            SampleType::F64 => 8,
        }
    }
}

/// A format's reader of a whole file.
type Reader = fn(&Path) -> Result<Volume>;

/// The formats [`read_volume`] reads, each with its reader, in the order listed
/// in error messages.
const READERS: [(FileFormat, Reader); 6] = [
    (FileFormat::Nifti, nifti::read),
    (FileFormat::NiftiGz, nifti::read),
    (FileFormat::Nrrd, nrrd::read),
    (FileFormat::NrrdHeader, nrrd::read),
    (FileFormat::MetaImage, metaimage::read),
    (FileFormat::MetaImageHeader, metaimage::read),
];

/// The file extensions [`read_volume`] understands (compared case-insensitively).
pub const SUPPORTED_VOLUME_EXTENSIONS: &[&str] = &extensions(&READERS);

/// Whether `path` names an image file by its extension (one of
/// [`SUPPORTED_VOLUME_EXTENSIONS`], in any letter case), so that a command can
/// tell volumes from meshes.
pub fn is_volume_path(path: &Path) -> bool {
    reader_for(path).is_ok()
}

/// Read a 3D image, choosing the reader by the extension in any letter case:
///
/// - `.nii`, `.nii.gz`: NIfTI-1 or NIfTI-2, either byte order. Coordinates are in
///   the NIfTI world (RAS+: x to the right, y to the front, z up) given by the
///   sform if its code is positive, else the qform, else the voxel sizes alone.
///   Of a 4-D (or higher) image the first 3-D volume is read.
/// - `.nrrd`, `.nhdr`: NRRD with raw or gzip encoding, `dimension: 3`; the
///   geometry is reported in the file's own `space` as written.
/// - `.mha`, `.mhd`: MetaImage, `NDims = 3`, raw or zlib-compressed; the geometry
///   is reported as written (ITK writes LPS).
///
/// Errors are [`Error::File`] naming `path` (or a detached data file) and the
/// problem.
pub fn read_volume(path: &Path) -> Result<Volume> {
    let read = reader_for(path)?;
    read(path).map_err(|e| in_file(e, path))
}

/// The files reading the image at `path` reads: the file itself and, for a
/// NRRD or MetaImage header that names one, its detached data file (so that a
/// caller can refuse to write over any of them). A header that cannot be parsed
/// gives the file alone; reading it will say what is wrong.
pub fn volume_files(path: &Path) -> Vec<PathBuf> {
    let data_file = match choose_format(path, "", &READERS).map(|(format, _)| format) {
        Ok(FileFormat::Nrrd | FileFormat::NrrdHeader) => nrrd::data_file(path),
        Ok(FileFormat::MetaImage | FileFormat::MetaImageHeader) => metaimage::data_file(path),
        _ => Ok(None),
    };
    std::iter::once(path.to_path_buf())
        .chain(data_file.ok().flatten())
        .collect()
}

/// How much of a header file [`volume_files`] reads: headers are a few hundred
/// bytes.
const HEAD_BYTES: u64 = 1 << 16;

/// The first [`HEAD_BYTES`] of the file at `path`.
fn read_head(path: &Path) -> Result<Vec<u8>> {
    let mut head = Vec::new();
    std::fs::File::open(path)
        .and_then(|file| file.take(HEAD_BYTES).read_to_end(&mut head))
        .map_err(|e| open_error(path, e))?;
    Ok(head)
}

/// Read a file of bare samples: `dims` samples (x fastest) of type `sample_type`
/// in little- or big-endian byte order, placed with `spacing`, at the origin and
/// axis-aligned. The file must hold exactly the samples.
pub fn read_raw_volume(
    path: &Path,
    dims: [usize; 3],
    spacing: [f64; 3],
    sample_type: SampleType,
    little_endian: bool,
) -> Result<Volume> {
    let read = || {
        let bytes = read_file(path)?;
        let layout = DataLayout {
            dims,
            sample_type,
            little_endian,
            compression: Compression::None,
            skip: Skip::Bytes(0),
        };
        let expected = layout.data_bytes()?;
        if bytes.len() as u64 > expected {
            return Err(Error::Parse(format!(
                "the file has {} bytes, more than the {expected} of {}×{}×{} samples",
                bytes.len(),
                dims[0],
                dims[1],
                dims[2]
            )));
        }
        let samples = layout.read(&bytes)?;
        Volume::new(
            dims,
            spacing,
            [0.0; 3],
            nalgebra::Matrix3::identity(),
            samples,
        )
    };
    read().map_err(|e| in_file(e, path))
}

/// The reader for the extension of `path`.
fn reader_for(path: &Path) -> Result<Reader> {
    choose_format(path, "an image", &READERS).map(|(_, read)| read)
}

/// Name `path` in `err`, also for the argument errors of [`Volume::new`] (a
/// header's geometry is the file's fault).
fn in_file(err: Error, path: &Path) -> Error {
    match err {
        Error::Argument(message) => Error::File {
            path: path.to_path_buf(),
            message,
        },
        other => other.in_file(path),
    }
}

/// The bytes of `path`, with a plain message for a missing file.
fn read_file(path: &Path) -> Result<Vec<u8>> {
    let metadata = std::fs::metadata(path).map_err(|e| open_error(path, e))?;
    if !metadata.is_file() {
        // A device (/dev/zero), a pipe or standard input never ends, or ends when
        // someone else decides: only a file has the size its header promises.
        return Err(Error::File {
            path: path.to_path_buf(),
            message: "is not a regular file (a folder, device or pipe); images are read from files"
                .to_string(),
        });
    }
    std::fs::read(path).map_err(|e| open_error(path, e))
}

/// The error for a file that cannot be opened or read: "no such file" when it is
/// missing.
fn open_error(path: &Path, err: std::io::Error) -> Error {
    match err.kind() {
        std::io::ErrorKind::NotFound => Error::File {
            path: path.to_path_buf(),
            message: "no such file".to_string(),
        },
        _ => Error::io(path, err),
    }
}

/// How the sample bytes are compressed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Compression {
    /// Stored as they are.
    None,
    /// A gzip stream (one or more members).
    Gzip,
    /// A zlib stream.
    Zlib,
}

/// Where the samples start in their (decompressed) data.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Skip {
    /// After this many bytes.
    Bytes(u64),
    /// The samples are the last bytes of the uncompressed data (a header size or
    /// byte skip of -1).
    ToEnd,
}

/// How the samples of an image are stored.
#[derive(Clone, Copy, Debug)]
struct DataLayout {
    dims: [usize; 3],
    sample_type: SampleType,
    little_endian: bool,
    compression: Compression,
    skip: Skip,
}

impl DataLayout {
    /// The number of bytes of the samples, after checking the voxel count.
    fn data_bytes(&self) -> Result<u64> {
        let count = voxel_count(self.dims)?;
        Ok(count as u64 * self.sample_type.size() as u64)
    }

    /// Decode the samples from `data`, the bytes where they are stored.
    fn read(&self, data: &[u8]) -> Result<Vec<f32>> {
        let needed = self.data_bytes()?;
        let (data, skip) = match self.skip {
            Skip::Bytes(skip) => (data, skip),
            Skip::ToEnd if self.compression != Compression::None => {
                return Err(Error::Parse(
                    "a header size or byte skip of -1 needs uncompressed data".to_string(),
                ))
            }
            Skip::ToEnd => {
                let start = (data.len() as u64)
                    .checked_sub(needed)
                    .ok_or_else(|| truncated("data", data.len() as u64, needed))?;
                (&data[start as usize..], 0)
            }
        };
        match self.compression {
            Compression::None => self.read_stream(data, skip),
            Compression::Gzip => self.read_stream(MultiGzDecoder::new(data), skip),
            Compression::Zlib => self.read_stream(ZlibDecoder::new(data), skip),
        }
    }

    /// Skip `skip` bytes of `reader`, then decode the samples from it.
    fn read_stream(&self, mut reader: impl Read, skip: u64) -> Result<Vec<f32>> {
        skip_bytes(&mut reader, skip)?;
        let bytes = read_exactly(&mut reader, self.data_bytes()?, "data")?;
        Ok(decode_samples(&bytes, self.sample_type, self.little_endian))
    }
}

/// Read `n` bytes of `reader`; the error says how many the `what` (e.g. "data",
/// "header") held if it ends early. Memory grows with the bytes read, not `n`.
fn read_exactly(reader: &mut impl Read, n: u64, what: &str) -> Result<Vec<u8>> {
    let mut bytes = Vec::new();
    read_until_length(reader, &mut bytes, n, what)?;
    Ok(bytes)
}

/// Append bytes of `reader` to `bytes` until it holds `total` bytes; the error
/// says how many of `total` the `what` held if it ends early.
fn read_until_length(
    reader: &mut impl Read,
    bytes: &mut Vec<u8>,
    total: u64,
    what: &str,
) -> Result<()> {
    let missing = total.saturating_sub(bytes.len() as u64);
    let result = reader.by_ref().take(missing).read_to_end(bytes);
    match result {
        Ok(_) if bytes.len() as u64 == total => Ok(()),
        Ok(_) => Err(truncated(what, bytes.len() as u64, total)),
        Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => {
            Err(truncated(what, bytes.len() as u64, total))
        }
        Err(e) => Err(Error::Parse(format!("the {what} cannot be read: {e}"))),
    }
}

/// Skip `n` bytes of `reader` (the bytes before the samples).
fn skip_bytes(reader: &mut impl Read, n: u64) -> Result<()> {
    let skipped = std::io::copy(&mut reader.by_ref().take(n), &mut std::io::sink())
        .map_err(|e| Error::Parse(format!("the bytes before the data cannot be read: {e}")))?;
    if skipped < n {
        return Err(truncated("file", skipped, n));
    }
    Ok(())
}

/// The error for input that stops before the bytes its header announced.
fn truncated(what: &str, read: u64, claimed: u64) -> Error {
    Error::Parse(format!(
        "the {what} ends after {read} of {claimed} bytes (truncated file or wrong header?)"
    ))
}

/// The first `N` bytes of `bytes` in little-endian order (reversed if they are
/// stored big-endian). `bytes` holds at least `N` bytes.
fn little_endian_array<const N: usize>(bytes: &[u8], little_endian: bool) -> [u8; N] {
    let mut array = [0; N];
    array.copy_from_slice(&bytes[..N]);
    if !little_endian {
        array.reverse();
    }
    array
}

/// Decode samples of `sample_type` stored with the given byte order into `f32`
/// (a trailing partial sample is ignored).
fn decode_samples(bytes: &[u8], sample_type: SampleType, little_endian: bool) -> Vec<f32> {
    fn decode<const N: usize>(bytes: &[u8], little: bool, f: fn([u8; N]) -> f32) -> Vec<f32> {
        bytes
            .chunks_exact(N)
            .map(|chunk| f(little_endian_array(chunk, little)))
            .collect()
    }
    let little = little_endian;
    match sample_type {
        SampleType::U8 => bytes.iter().map(|&b| f32::from(b)).collect(),
        SampleType::I8 => bytes.iter().map(|&b| f32::from(b as i8)).collect(),
        SampleType::I16 => decode(bytes, little, |a| f32::from(i16::from_le_bytes(a))),
        SampleType::U16 => decode(bytes, little, |a| f32::from(u16::from_le_bytes(a))),
        SampleType::I32 => decode(bytes, little, |a| i32::from_le_bytes(a) as f32),
        SampleType::U32 => decode(bytes, little, |a| u32::from_le_bytes(a) as f32),
        SampleType::F32 => decode(bytes, little, f32::from_le_bytes),
        SampleType::F64 => decode(bytes, little, |a| f64::from_le_bytes(a) as f32),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_decode_in_both_byte_orders() {
        let bytes = [0x01, 0x02, 0xff, 0xfe];
        assert_eq!(
            decode_samples(&bytes, SampleType::I16, true),
            [513.0, -257.0]
        );
        assert_eq!(
            decode_samples(&bytes, SampleType::U16, false),
            [258.0, 65534.0]
        );
        assert_eq!(
            decode_samples(&bytes, SampleType::I8, true),
            [1.0, 2.0, -1.0, -2.0]
        );
        let half = 0.5f64.to_be_bytes();
        assert_eq!(decode_samples(&half, SampleType::F64, false), [0.5]);
    }

    #[test]
    fn a_short_stream_says_how_much_it_held() {
        let err = read_exactly(&mut &[1u8, 2, 3][..], 8, "data").unwrap_err();
        assert!(err.to_string().contains("ends after 3 of 8 bytes"), "{err}");
    }
}
