//! Reading 3D images into a [`Volume`].
//!
//! [`read_volume`] chooses the reader by the file extension: NIfTI-1 and NIfTI-2
//! (`.nii`, `.nii.gz`), NRRD (`.nrrd`, `.nhdr` with a detached data file) and
//! MetaImage (`.mha`, `.mhd` with a detached data file); a folder, a DICOMDIR, a
//! `.dcm` or `.dicom` file or any file with the DICOM `DICM` mark is a DICOM
//! series (with the cargo feature `dicom`), and [`read_volume_with`] chooses one of
//! several series in it; [`read_dicom`] reads a series from a list of files.
//! [`read_raw_volume`] reads headerless samples whose layout the caller knows.
//! Samples of every type become `f32` (32-bit integers and doubles may lose
//! precision).
//!
//! Headers are checked before their data is read: the voxel count must be at most
//! [`crate::volume::MAX_VOXELS`]; the sample buffer is reserved fallibly (a header
//! asking for more than can be allocated is an error saying how much, never an
//! abort) and filled a chunk at a time as the bytes arrive, so a short or
//! decompressed stream that ends early fails after reading only what it holds.
//! Errors are [`Error::File`] naming the file and what is wrong: the line and field
//! of a text header, the field of a binary one, or how many bytes a truncated file
//! holds ("the data ends after N of M bytes").

mod dicom;
mod metaimage;
mod nifti;
mod nrrd;
mod text_header;

use std::io::Read;
use std::path::{Path, PathBuf};

use flate2::read::{MultiGzDecoder, ZlibDecoder};

use super::file;
use super::format::{choose_format, FileFormat};
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

/// Whether `path` names a 3D image, so that a command can tell volumes from
/// meshes: a file with an extension [`read_volume`] reads (in any letter
/// case), or DICOM input (a folder, a DICOMDIR, a `.dcm` or `.dicom` file, or a
/// file with the `DICM` mark at byte 128).
pub fn is_volume_path(path: &Path) -> bool {
    reader_for(path).is_ok() || dicom::is_dicom_input(path)
}

/// How [`VolumeReadOptions::read`] reads an image.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct VolumeReadOptions {
    /// The Series Instance UID of the series to read from DICOM input holding
    /// several; `None` reads the only series there (and an error lists the
    /// series if there are several). Other formats refuse a series.
    pub series: Option<String>,
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
/// - a folder, a DICOMDIR, a `.dcm` or `.dicom` file, or a file with the `DICM`
///   mark at byte 128 (such as `.dicom` files): a DICOM series, in LPS; see
///   [`VolumeReadOptions::read`].
///
/// Errors are [`Error::File`] naming `path` (or a detached data file, or the file
/// of a series at fault) and the problem.
///
/// # Examples
///
/// ```
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../volumes/mni152_wm_1mm.nii.gz");
/// let volume = crestline::io::read_volume(path.as_ref())?;
/// assert_eq!(volume.dims(), [197, 233, 189]);
/// # Ok::<(), crestline::Error>(())
/// ```
pub fn read_volume(path: &Path) -> Result<Volume> {
    read_volume_with(path, &VolumeReadOptions::default())
}

/// [`VolumeReadOptions::read`].
pub(crate) fn read_volume_with(path: &Path, options: &VolumeReadOptions) -> Result<Volume> {
    let series = options.series.as_deref();
    match reader_for(path) {
        Ok(read) if series.is_none() => read(path).map_err(|e| in_file(e, path)),
        Ok(_) => Err(Error::File {
            path: path.to_path_buf(),
            message:
                "a series was chosen, but the image is not DICOM: only DICOM input holds series"
                    .to_string(),
        }),
        Err(_) if dicom::is_dicom_input(path) => dicom::read(dicom::Input::Path(path), series),
        Err(err) => Err(err),
    }
}

/// [`VolumeReadOptions::read_dicom`].
pub(crate) fn read_dicom(files: &[PathBuf], options: &VolumeReadOptions) -> Result<Volume> {
    dicom::read(dicom::Input::Files(files), options.series.as_deref())
}

/// The files reading the image at `path` reads: the file itself and, for a
/// NRRD or MetaImage header that names one, its detached data file; for DICOM
/// input, the folder or DICOMDIR and then the DICOM files it holds or references
/// (so that a caller can refuse to write over any of them). A header that cannot
/// be parsed gives the file alone; reading it will say what is wrong.
pub fn volume_files(path: &Path) -> Vec<PathBuf> {
    if reader_for(path).is_err() && dicom::is_dicom_input(path) {
        return dicom::input_files(path);
    }
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
    file::head(path, HEAD_BYTES)
}

/// Read a file of bare samples: `dims` samples (x fastest) of type `sample_type`
/// in little- or big-endian byte order, placed with `spacing`, at the origin and
/// axis-aligned. The file must hold exactly the samples.
#[cfg(test)]
pub fn read_raw_volume(
    path: &Path,
    dims: [usize; 3],
    spacing: [f64; 3],
    sample_type: SampleType,
    little_endian: bool,
) -> Result<Volume> {
    let read = || {
        let bytes = file::read(path)?;
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

/// The reader for the extension of `path`; the error lists the extensions and
/// DICOM input.
fn reader_for(path: &Path) -> Result<Reader> {
    choose_format(path, "an image", &READERS)
        .map(|(_, read)| read)
        .map_err(|err| match err {
            Error::File { path, message } => Error::File {
                path,
                message: format!("{message}, or a DICOM folder, DICOMDIR or .dcm file"),
            },
            other => other,
        })
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
        let count = voxel_count(self.dims)?;
        read_samples(&mut reader, count, self.sample_type, self.little_endian)
    }
}

/// Samples decoded per read: a bounded buffer between the (decompressed) bytes
/// and the samples.
const CHUNK_SAMPLES: usize = 1 << 16;

/// Read and decode `count` samples of `sample_type` from `reader`, a chunk at a
/// time. The sample buffer is reserved fallibly, so a header claiming more than
/// memory (or an address-space limit) allows is an error saying how much it needs,
/// not an abort; a stream that ends early is an error saying how much it held.
fn read_samples(
    reader: &mut impl Read,
    count: usize,
    sample_type: SampleType,
    little_endian: bool,
) -> Result<Vec<f32>> {
    let mut samples = reserve_samples(count)?;
    let size = sample_type.size();
    let total = count as u64 * size as u64;
    let mut chunk = vec![0u8; CHUNK_SAMPLES * size];
    while samples.len() < count {
        let wanted = (count - samples.len()).min(CHUNK_SAMPLES) * size;
        let got = fill(reader, &mut chunk[..wanted])?;
        if got < wanted {
            let read = samples.len() as u64 * size as u64 + got as u64;
            return Err(truncated("data", read, total));
        }
        decode_samples(&chunk[..wanted], sample_type, little_endian, &mut samples);
    }
    Ok(samples)
}

/// Read into `buffer` until it is full or `reader` ends; the number of bytes read.
fn fill(reader: &mut impl Read, buffer: &mut [u8]) -> Result<usize> {
    let mut filled = 0;
    while filled < buffer.len() {
        match reader.read(&mut buffer[filled..]) {
            Ok(0) => break,
            Ok(n) => filled += n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(Error::Parse(format!("the data cannot be read: {e}"))),
        }
    }
    Ok(filled)
}

/// An empty buffer with room for `count` samples, reserved fallibly: a header
/// claiming more than can be allocated is an error saying how much, not an abort.
fn reserve_samples(count: usize) -> Result<Vec<f32>> {
    file::reserve(count, "samples (32-bit floats)")
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

/// Decode samples of `sample_type` stored with the given byte order into `f32`,
/// appended to `out` (a trailing partial sample is ignored).
fn decode_samples(bytes: &[u8], sample_type: SampleType, little_endian: bool, out: &mut Vec<f32>) {
    fn decode<const N: usize>(
        bytes: &[u8],
        little: bool,
        out: &mut Vec<f32>,
        f: fn([u8; N]) -> f32,
    ) {
        out.extend(
            bytes
                .chunks_exact(N)
                .map(|chunk| f(little_endian_array(chunk, little))),
        );
    }
    let little = little_endian;
    match sample_type {
        SampleType::U8 => out.extend(bytes.iter().map(|&b| f32::from(b))),
        SampleType::I8 => out.extend(bytes.iter().map(|&b| f32::from(b as i8))),
        SampleType::I16 => decode(bytes, little, out, |a| f32::from(i16::from_le_bytes(a))),
        SampleType::U16 => decode(bytes, little, out, |a| f32::from(u16::from_le_bytes(a))),
        SampleType::I32 => decode(bytes, little, out, |a| i32::from_le_bytes(a) as f32),
        SampleType::U32 => decode(bytes, little, out, |a| u32::from_le_bytes(a) as f32),
        SampleType::F32 => decode(bytes, little, out, f32::from_le_bytes),
        SampleType::F64 => decode(bytes, little, out, |a| f64::from_le_bytes(a) as f32),
    }
}

impl VolumeReadOptions {
    /// Read a 3D image as [`read_volume`] does, with these options.
    ///
    /// DICOM input (with the cargo feature `dicom`; without it, an error saying so)
    /// is a folder (its files with the `DICM` mark; subfolders, hidden files and
    /// other files are skipped), a DICOMDIR (the files it references) or one file,
    /// single- or multi-frame. Of the images found, those of one series are read:
    /// the only one, or `series`. The volume's index axes are the rows, the
    /// columns and the normal of the slices, in LPS millimetres: slices are ordered by
    /// their Image Position (Patient) along the normal of their Image Orientation
    /// (Patient), and spaced by the step between those positions; an oblique series
    /// keeps its orientation as the direction matrix. Samples are the modality values
    /// (Rescale Slope and Intercept applied). Refused with an error naming the input
    /// and the problem: several series and none chosen (the error lists their UIDs),
    /// a missing slice or uneven spacing (the gap and the expected spacing), a gantry
    /// tilt (its angle; such series are not resampled), mixed orientations, sizes or
    /// pixel spacings, two slices at one position, colour images, and transfer
    /// syntaxes this build cannot decode (JPEG-LS, JPEG 2000; named with the file).
    pub fn read(&self, path: &Path) -> Result<Volume> {
        read_volume_with(path, self)
    }

    /// Read a DICOM series from a list of files, as [`VolumeReadOptions::read`] reads a
    /// folder: files that hold no image are skipped, and of several series
    /// `series` is read. Errors about the series as a whole name the folder
    /// of the first file.
    pub fn read_dicom(&self, files: &[PathBuf]) -> Result<Volume> {
        read_dicom(files, self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn decoded(bytes: &[u8], sample_type: SampleType, little_endian: bool) -> Vec<f32> {
        let mut out = Vec::new();
        decode_samples(bytes, sample_type, little_endian, &mut out);
        out
    }

    #[test]
    fn samples_decode_in_both_byte_orders() {
        let bytes = [0x01, 0x02, 0xff, 0xfe];
        assert_eq!(decoded(&bytes, SampleType::I16, true), [513.0, -257.0]);
        assert_eq!(decoded(&bytes, SampleType::U16, false), [258.0, 65534.0]);
        assert_eq!(
            decoded(&bytes, SampleType::I8, true),
            [1.0, 2.0, -1.0, -2.0]
        );
        let half = 0.5f64.to_be_bytes();
        assert_eq!(decoded(&half, SampleType::F64, false), [0.5]);
    }

    #[test]
    fn a_short_stream_says_how_much_it_held() {
        let err = read_samples(&mut &[1u8, 2, 3][..], 4, SampleType::I16, true).unwrap_err();
        assert!(err.to_string().contains("ends after 3 of 8 bytes"), "{err}");
    }

    #[test]
    fn samples_across_chunks_decode_in_order() {
        let count = CHUNK_SAMPLES * 2 + 3;
        let bytes: Vec<u8> = (0..count).flat_map(|i| (i as u16).to_be_bytes()).collect();
        let samples = read_samples(&mut &bytes[..], count, SampleType::U16, false).unwrap();
        assert_eq!(samples.len(), count);
        assert!(samples
            .iter()
            .enumerate()
            .all(|(i, &v)| v == f32::from(i as u16)));
    }

    #[test]
    fn samples_beyond_memory_are_an_error_saying_how_much() {
        // More than any address space holds: the reservation fails cleanly.
        let err =
            read_samples(&mut &[0u8; 4][..], usize::MAX / 2, SampleType::U8, true).unwrap_err();
        assert!(err.to_string().contains("GiB of memory"), "{err}");
    }
}
