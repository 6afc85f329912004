//! NIfTI-1 and NIfTI-2 single-file images (`.nii`, `.nii.gz`).
//!
//! The header is parsed by hand: its size (348 bytes for NIfTI-1, 540 for
//! NIfTI-2) tells the version and, read in either byte order, the byte order of the
//! whole file. Coordinates are in the NIfTI world (RAS+). Of a 4-D or higher image
//! the first 3-D volume is read. Samples are scaled by `scl_slope`, `scl_inter`
//! when the slope is finite and not zero.

use std::io::{BufRead, BufReader, Read};
use std::path::Path;

use flate2::read::MultiGzDecoder;
use nalgebra::{Matrix3, Matrix4, Vector3};

use super::{little_endian_array, read_until_length, DataLayout, SampleType, Skip};
use crate::error::readable;
use crate::volume::{split_affine, Volume};
use crate::{Error, Result, Space};

/// Size of a NIfTI-1 header.
const NIFTI1_SIZE: usize = 348;
/// Size of a NIfTI-2 header.
const NIFTI2_SIZE: usize = 540;

/// The first bytes of a gzip stream.
const GZIP_MAGIC: [u8; 2] = [0x1f, 0x8b];

/// Read a `.nii` or `.nii.gz` file (gzip is recognised by its magic bytes, so a
/// misnamed file still reads).
pub(super) fn read(path: &Path) -> Result<Volume> {
    let file = crate::io::file::open(path)?;
    let mut buffered = BufReader::new(file);
    let start = buffered.fill_buf().map_err(|e| Error::io(path, e))?;
    let volume = if start.starts_with(&GZIP_MAGIC) {
        read_stream(&mut MultiGzDecoder::new(buffered))
    } else {
        read_stream(&mut buffered)
    }?;
    Ok(volume.with_space(Some(Space::Ras)))
}

/// Read a NIfTI image from the (decompressed) bytes of a `.nii` file.
fn read_stream(reader: &mut impl Read) -> Result<Volume> {
    let mut bytes = Vec::new();
    read_until_length(reader, &mut bytes, 4, "header")?;
    let (size, little_endian) = header_size(&bytes)?;
    read_until_length(reader, &mut bytes, size as u64, "header")?;
    let fields = Fields {
        bytes: &bytes,
        little_endian,
    };
    let header = if size == NIFTI1_SIZE {
        fields.nifti1()?
    } else {
        fields.nifti2()?
    };
    header.read_volume(reader, size as u64, little_endian)
}

/// The header size and byte order announced by `sizeof_hdr`, the first 4 bytes.
fn header_size(bytes: &[u8]) -> Result<(usize, bool)> {
    let little = i32::from_le_bytes(little_endian_array(bytes, true));
    let big = i32::from_le_bytes(little_endian_array(bytes, false));
    for size in [NIFTI1_SIZE, NIFTI2_SIZE] {
        if little == size as i32 {
            return Ok((size, true));
        }
        if big == size as i32 {
            return Ok((size, false));
        }
    }
    Err(Error::Parse(format!(
        "not a NIfTI file: sizeof_hdr is {little} (expected 348 or 540 in either byte order)"
    )))
}

/// A header's bytes, read as numbers of the file's byte order.
struct Fields<'a> {
    bytes: &'a [u8],
    little_endian: bool,
}

impl Fields<'_> {
    fn array<const N: usize>(&self, at: usize) -> [u8; N] {
        little_endian_array(&self.bytes[at..], self.little_endian)
    }
    fn i16(&self, at: usize) -> i64 {
        i64::from(i16::from_le_bytes(self.array(at)))
    }
    fn i32(&self, at: usize) -> i64 {
        i64::from(i32::from_le_bytes(self.array(at)))
    }
    fn i64(&self, at: usize) -> i64 {
        i64::from_le_bytes(self.array(at))
    }
    fn f32(&self, at: usize) -> f64 {
        f64::from(f32::from_le_bytes(self.array(at)))
    }
    fn f64(&self, at: usize) -> f64 {
        f64::from_le_bytes(self.array(at))
    }

    /// `N` consecutive values of `width` bytes from `at`, each read by `read`.
    fn values<const N: usize, T>(
        &self,
        at: usize,
        width: usize,
        read: fn(&Self, usize) -> T,
    ) -> [T; N] {
        std::array::from_fn(|i| read(self, at + i * width))
    }

    /// The magic string, checked against the single-file signature `expected`.
    fn check_magic(&self, at: usize, expected: &[u8], pair: &[u8]) -> Result<()> {
        let magic = &self.bytes[at..at + expected.len()];
        if magic == expected {
            return Ok(());
        }
        if magic.starts_with(pair) {
            return Err(Error::Parse(
                "a header of a .hdr/.img pair; only single-file .nii images are read".to_string(),
            ));
        }
        // Shown as text: the error's display writes the control bytes as `\xNN`.
        Err(Error::Parse(format!(
            "bad magic \"{}\" in the header (expected \"{}\")",
            String::from_utf8_lossy(magic),
            String::from_utf8_lossy(expected)
        )))
    }

    /// The fields of a NIfTI-1 header (offsets of `nifti1.h`).
    fn nifti1(&self) -> Result<Header> {
        self.check_magic(344, b"n+1\0", b"ni1")?;
        Ok(Header {
            dim: self.values(40, 2, Self::i16),
            datatype: self.i16(70),
            pixdim: self.values(76, 4, Self::f32),
            vox_offset: self.f32(108),
            scl_slope: self.f32(112),
            scl_inter: self.f32(116),
            qform_code: self.i16(252),
            sform_code: self.i16(254),
            quatern: self.values(256, 4, Self::f32),
            srow: [
                self.values(280, 4, Self::f32),
                self.values(296, 4, Self::f32),
                self.values(312, 4, Self::f32),
            ],
        })
    }

    /// The fields of a NIfTI-2 header (offsets of `nifti2.h`).
    fn nifti2(&self) -> Result<Header> {
        self.check_magic(4, b"n+2\0\r\n\x1a\n", b"ni2")?;
        Ok(Header {
            dim: self.values(16, 8, Self::i64),
            datatype: self.i16(12),
            pixdim: self.values(104, 8, Self::f64),
            vox_offset: self.i64(168) as f64,
            scl_slope: self.f64(176),
            scl_inter: self.f64(184),
            qform_code: self.i32(344),
            sform_code: self.i32(348),
            quatern: self.values(352, 8, Self::f64),
            srow: [
                self.values(400, 8, Self::f64),
                self.values(432, 8, Self::f64),
                self.values(464, 8, Self::f64),
            ],
        })
    }
}

/// The fields of a NIfTI header that a [`Volume`] needs, version-independent.
struct Header {
    dim: [i64; 8],
    datatype: i64,
    pixdim: [f64; 8],
    vox_offset: f64,
    scl_slope: f64,
    scl_inter: f64,
    qform_code: i64,
    sform_code: i64,
    /// `quatern_b, c, d, qoffset_x, y, z`.
    quatern: [f64; 6],
    /// `srow_x, srow_y, srow_z`.
    srow: [[f64; 4]; 3],
}

impl Header {
    /// Read the samples that follow the `header_size` bytes already read and
    /// build the volume.
    fn read_volume(
        &self,
        reader: &mut impl Read,
        header_size: u64,
        little_endian: bool,
    ) -> Result<Volume> {
        let offset = self.data_offset(header_size)?;
        let layout = DataLayout {
            dims: self.dims()?,
            sample_type: self.sample_type()?,
            little_endian,
            compression: super::Compression::None,
            skip: Skip::Bytes(offset),
        };
        let mut samples = layout.read_stream(reader, offset)?;
        self.scale(&mut samples)?;
        let (spacing, origin, direction) = self.geometry();
        Volume::new(layout.dims, spacing, origin, direction, samples)
    }

    /// The three spatial dimensions; dimensions past the third (time, ...) are
    /// checked but only their first 3-D volume is read.
    fn dims(&self) -> Result<[usize; 3]> {
        let rank = self.dim[0];
        if !(1..=7).contains(&rank) {
            return Err(Error::Parse(format!(
                "dim[0] is {rank}: the number of dimensions must be 1 to 7"
            )));
        }
        let mut dims = [1usize; 3];
        for axis in 1..=rank as usize {
            let n = self.dim[axis];
            let size = usize::try_from(n).ok().filter(|&n| n > 0).ok_or_else(|| {
                Error::Parse(format!("dim[{axis}] is {n}: dimensions must be positive"))
            })?;
            if axis <= 3 {
                dims[axis - 1] = size;
            }
        }
        Ok(dims)
    }

    /// The sample type of the `datatype` code.
    fn sample_type(&self) -> Result<SampleType> {
        Ok(match self.datatype {
            2 => SampleType::U8,
            4 => SampleType::I16,
            8 => SampleType::I32,
            16 => SampleType::F32,
            64 => SampleType::F64,
            256 => SampleType::I8,
            512 => SampleType::U16,
            768 => SampleType::U32,
            other => {
                return Err(Error::Parse(format!(
                    "unsupported datatype {other} (supported: uint8, int8, int16, uint16, int32, uint32, float32, float64)"
                )))
            }
        })
    }

    /// The bytes between the end of the header and the samples, from `vox_offset`.
    fn data_offset(&self, header_size: u64) -> Result<u64> {
        let offset = self.vox_offset;
        if !(offset.is_finite() && offset.fract() == 0.0 && offset >= header_size as f64) {
            return Err(Error::Parse(format!(
                "vox_offset {offset} is not a whole number of bytes at or after the {header_size}-byte header"
            )));
        }
        Ok(offset as u64 - header_size)
    }

    /// Apply `scl_slope` and `scl_inter`, unless the slope is zero or not finite
    /// (the NIfTI way of saying "no scaling"). Scaling that takes a finite sample
    /// beyond the range of 32-bit floats is an error naming both fields.
    fn scale(&self, samples: &mut [f32]) -> Result<()> {
        let (slope, inter) = (self.scl_slope, self.scl_inter);
        if !(slope != 0.0 && slope.is_finite() && inter.is_finite() && (slope, inter) != (1.0, 0.0))
        {
            return Ok(());
        }
        for sample in samples {
            let scaled = (f64::from(*sample) * slope + inter) as f32;
            if sample.is_finite() && !scaled.is_finite() {
                return Err(Error::Parse(format!(
                    "scl_slope {} and scl_inter {} scale the sample {sample} to {}, beyond the range of 32-bit floats",
                    readable(slope),
                    readable(inter),
                    readable(f64::from(*sample) * slope + inter)
                )));
            }
            *sample = scaled;
        }
        Ok(())
    }

    /// Spacing, origin and direction in RAS+ world coordinates: from the sform if
    /// `sform_code > 0`, else from the qform if `qform_code > 0`, else the voxel
    /// sizes `pixdim[1..4]` alone.
    fn geometry(&self) -> ([f64; 3], [f64; 3], Matrix3<f64>) {
        if self.sform_code > 0 {
            let affine = Matrix4::from_fn(|row, column| match row {
                3 => f64::from(u8::from(column == 3)),
                _ => self.srow[row][column],
            });
            split_affine(&affine)
        } else if self.qform_code > 0 {
            let [b, c, d, x, y, z] = self.quatern;
            let spacing = [self.pixdim[1], self.pixdim[2], self.pixdim[3]];
            let qfac = if self.pixdim[0] < 0.0 { -1.0 } else { 1.0 };
            let mut direction = quaternion_rotation(b, c, d);
            direction.set_column(2, &(direction.column(2) * qfac));
            (spacing, [x, y, z], direction)
        } else {
            let spacing = [self.pixdim[1], self.pixdim[2], self.pixdim[3]];
            (spacing, [0.0; 3], Matrix3::identity())
        }
    }
}

/// The rotation of the unit quaternion `(a, b, c, d)`, `a` computed from the
/// other three as in `nifti1.h` (a tiny negative `1 - b² - c² - d²` means `a = 0`
/// and `(b, c, d)` is renormalised).
fn quaternion_rotation(b: f64, c: f64, d: f64) -> Matrix3<f64> {
    let a_squared = 1.0 - (b * b + c * c + d * d);
    let (a, b, c, d) = if a_squared < 1e-7 {
        let n = Vector3::new(b, c, d).norm();
        if n > 0.0 {
            (0.0, b / n, c / n, d / n)
        } else {
            (1.0, 0.0, 0.0, 0.0)
        }
    } else {
        (a_squared.sqrt(), b, c, d)
    };
    Matrix3::new(
        a * a + b * b - c * c - d * d,
        2.0 * (b * c - a * d),
        2.0 * (b * d + a * c),
        2.0 * (b * c + a * d),
        a * a + c * c - b * b - d * d,
        2.0 * (c * d - a * b),
        2.0 * (b * d - a * c),
        2.0 * (c * d + a * b),
        a * a + d * d - c * c - b * b,
    )
}
