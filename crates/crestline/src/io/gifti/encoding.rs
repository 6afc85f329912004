//! The numbers of a GIfTI `DataArray` (GIfTI 1.0 spec, section 2.5): their type
//! (`DataType`), how the `Data` element holds them (`Encoding`), their byte
//! order (`Endian`) and how many there are (`Dim0` × `Dim1` × ...).
//!
//! Decoding checks every size before allocating: the count a header declares is
//! compared with what the payload can hold (a base64 text of `n` characters
//! holds at most `3n / 4` bytes; deflate expands at most 1032-fold), and
//! decompression stops one byte past the declared size, so a huge `Dim0` over a
//! tiny payload or a gzip bomb fails at once with an error.

use std::io::Read;

use base64::engine::general_purpose::STANDARD;
use base64::Engine;
use flate2::read::ZlibDecoder;
use flate2::write::ZlibEncoder;
use flate2::Compression;

use crate::io::file;

/// Largest expansion of deflate (zlib's bound on its compression ratio).
const MAX_DEFLATE_RATIO: usize = 1032;

/// Bytes inflated per read.
const INFLATE_CHUNK: usize = 1 << 16;

/// A `DataType` crestline reads and writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum DataType {
    /// `NIFTI_TYPE_FLOAT32`.
    Float32,
    /// `NIFTI_TYPE_INT32`.
    Int32,
    /// `NIFTI_TYPE_UINT8`.
    Uint8,
}

impl DataType {
    /// The type named by a `DataType` attribute.
    pub(crate) fn from_name(name: &str) -> Result<DataType, String> {
        match name {
            "NIFTI_TYPE_FLOAT32" => Ok(DataType::Float32),
            "NIFTI_TYPE_INT32" => Ok(DataType::Int32),
            "NIFTI_TYPE_UINT8" => Ok(DataType::Uint8),
            _ => Err(format!(
                "unsupported DataType '{name}' (NIFTI_TYPE_FLOAT32, NIFTI_TYPE_INT32 and NIFTI_TYPE_UINT8 are read)"
            )),
        }
    }

    /// The attribute's value.
    pub(crate) fn name(self) -> &'static str {
        match self {
            DataType::Float32 => "NIFTI_TYPE_FLOAT32",
            DataType::Int32 => "NIFTI_TYPE_INT32",
            DataType::Uint8 => "NIFTI_TYPE_UINT8",
        }
    }

    /// Bytes per number.
    fn size(self) -> usize {
        match self {
            DataType::Float32 | DataType::Int32 => 4,
            DataType::Uint8 => 1,
        }
    }

    /// The number of `size` bytes in the given byte order.
    fn value(self, bytes: &[u8], little_endian: bool) -> f64 {
        let word = || {
            let word = [bytes[0], bytes[1], bytes[2], bytes[3]];
            if little_endian {
                word
            } else {
                [word[3], word[2], word[1], word[0]]
            }
        };
        match self {
            DataType::Float32 => f64::from(f32::from_le_bytes(word())),
            DataType::Int32 => f64::from(i32::from_le_bytes(word())),
            DataType::Uint8 => f64::from(bytes[0]),
        }
    }
}

/// How the numbers of a `DataArray` are stored, and how many there are.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Layout {
    pub data_type: DataType,
    /// The `Encoding`: `ASCII`, `Base64Binary`, `GZipBase64Binary` (an
    /// `ExternalFileBinary` array is refused before decoding).
    pub encoding: Encoding,
    /// Little-endian unless `Endian="BigEndian"`.
    pub little_endian: bool,
    /// The product of the dimensions.
    pub count: usize,
}

/// The `Encoding` of a `DataArray`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Encoding {
    Ascii,
    Base64,
    GzipBase64,
}

impl Encoding {
    /// The encoding named by an `Encoding` attribute.
    pub(crate) fn from_name(name: &str) -> Result<Encoding, String> {
        match name {
            "ASCII" => Ok(Encoding::Ascii),
            "Base64Binary" => Ok(Encoding::Base64),
            "GZipBase64Binary" => Ok(Encoding::GzipBase64),
            "ExternalFileBinary" => Err(
                "the data is in an external file (ExternalFileBinary), which crestline does not read; \
                 convert the file with all data inside it"
                    .into(),
            ),
            _ => Err(format!("unknown Encoding '{name}'")),
        }
    }
}

/// The numbers of a `Data` element's text, as `layout` says, in the order
/// stored. Integers and 32-bit floats are exact as f64.
pub(crate) fn decode(text: &str, layout: &Layout) -> Result<Vec<f64>, String> {
    let bytes = match layout.encoding {
        Encoding::Ascii => return decode_ascii(text, layout),
        Encoding::Base64 => base64_bytes(text, payload_bytes(layout)?)?,
        Encoding::GzipBase64 => {
            let expected = payload_bytes(layout)?;
            let compressed = base64_bytes(text, 0)?;
            inflate(&compressed, expected)?
        }
    };
    let size = layout.data_type.size();
    if bytes.len() != layout.count * size {
        return Err(format!(
            "the data holds {} bytes where the dimensions declare {} numbers of {size} bytes",
            bytes.len(),
            layout.count
        ));
    }
    let mut values =
        file::reserve(layout.count, "numbers (as 64-bit floats)").map_err(|e| e.to_string())?;
    values.extend(
        bytes
            .chunks_exact(size)
            .map(|b| layout.data_type.value(b, layout.little_endian)),
    );
    Ok(values)
}

/// The bytes the dimensions declare, or an error when they overflow.
fn payload_bytes(layout: &Layout) -> Result<usize, String> {
    layout
        .count
        .checked_mul(layout.data_type.size())
        .ok_or_else(|| format!("absurd dimensions ({} numbers)", layout.count))
}

/// Numbers written as text, separated by white space.
fn decode_ascii(text: &str, layout: &Layout) -> Result<Vec<f64>, String> {
    // A number takes at least two characters with its separator.
    if layout.count > text.len() / 2 + 1 {
        return Err(format!(
            "the dimensions declare {} numbers but the data has {} characters",
            layout.count,
            text.len()
        ));
    }
    let mut values =
        file::reserve(layout.count, "numbers (as 64-bit floats)").map_err(|e| e.to_string())?;
    let mut found = 0;
    for token in text.split_ascii_whitespace() {
        let value = token.parse::<f64>().map_err(|_| {
            format!(
                "cannot read '{}' as a number",
                token.chars().take(40).collect::<String>()
            )
        })?;
        if found < layout.count {
            values.push(value);
        }
        found += 1;
    }
    if found != layout.count {
        return Err(format!(
            "the data has {found} numbers where the dimensions declare {}",
            layout.count
        ));
    }
    Ok(values)
}

/// The bytes of a base64 text (white space ignored). With `expected` nonzero,
/// a text too short or too long for that many bytes is refused before decoding.
fn base64_bytes(text: &str, expected: usize) -> Result<Vec<u8>, String> {
    let compact: Vec<u8> = text.bytes().filter(|b| !b.is_ascii_whitespace()).collect();
    let holds = compact.len() / 4 * 3;
    if expected != 0 && (expected > holds || holds > expected + 3) {
        return Err(format!(
            "the base64 data holds about {holds} bytes where the dimensions declare {expected}"
        ));
    }
    STANDARD
        .decode(&compact)
        .map_err(|e| format!("the data is not valid base64 ({e})"))
}

/// Inflate zlib data, refusing it when it could not hold `expected` bytes or
/// holds more (reading stops one byte past `expected`). The buffer grows as the
/// data arrives, fallibly: the declared size is not reserved up front, and data
/// that inflates to more than can be allocated is an error, not an abort.
fn inflate(compressed: &[u8], expected: usize) -> Result<Vec<u8>, String> {
    if expected / MAX_DEFLATE_RATIO > compressed.len() {
        return Err(format!(
            "the dimensions declare {expected} bytes, more than {} compressed bytes can hold",
            compressed.len()
        ));
    }
    let mut decoder = ZlibDecoder::new(compressed).take(expected as u64 + 1);
    let mut bytes = Vec::new();
    let mut chunk = vec![0u8; INFLATE_CHUNK];
    loop {
        let n = match decoder.read(&mut chunk) {
            Ok(0) => break,
            Ok(n) => n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(format!("the compressed data is corrupt ({e})")),
        };
        file::grow(&mut bytes, n, "decompressed bytes").map_err(|e| e.to_string())?;
        bytes.extend_from_slice(&chunk[..n]);
    }
    if bytes.len() > expected {
        return Err(format!(
            "the compressed data holds more than the {expected} bytes the dimensions declare"
        ));
    }
    Ok(bytes)
}

/// `bytes` as GIfTI's `GZipBase64Binary`: zlib-compressed, then base64.
pub(crate) fn encode(bytes: &[u8]) -> String {
    let mut encoder = ZlibEncoder::new(Vec::new(), Compression::default());
    // Writing to a vector cannot fail.
    let compressed = std::io::Write::write_all(&mut encoder, bytes)
        .and_then(|()| encoder.finish())
        .unwrap_or_default();
    STANDARD.encode(compressed)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layout(data_type: DataType, encoding: Encoding, count: usize) -> Layout {
        Layout {
            data_type,
            encoding,
            little_endian: true,
            count,
        }
    }

    #[test]
    fn every_encoding_and_byte_order_decodes() {
        let floats = [1.5f32, -2.0, 3.25e-3];
        let le: Vec<u8> = floats.iter().flat_map(|x| x.to_le_bytes()).collect();
        let be: Vec<u8> = floats.iter().flat_map(|x| x.to_be_bytes()).collect();
        let expected: Vec<f64> = floats.iter().map(|&x| f64::from(x)).collect();
        let f32_layout = |encoding| layout(DataType::Float32, encoding, 3);
        assert_eq!(
            decode(&encode(&le), &f32_layout(Encoding::GzipBase64)).unwrap(),
            expected
        );
        assert_eq!(
            decode(&STANDARD.encode(&le), &f32_layout(Encoding::Base64)).unwrap(),
            expected
        );
        let big = Layout {
            little_endian: false,
            ..f32_layout(Encoding::Base64)
        };
        assert_eq!(decode(&STANDARD.encode(&be), &big).unwrap(), expected);
        assert_eq!(
            decode(" 1.5 -2\n0.00325 ", &f32_layout(Encoding::Ascii)).unwrap(),
            [1.5, -2.0, 0.00325]
        );
        let ints: Vec<u8> = [-7i32, 9].iter().flat_map(|x| x.to_le_bytes()).collect();
        let int_layout = layout(DataType::Int32, Encoding::Base64, 2);
        assert_eq!(
            decode(&STANDARD.encode(&ints), &int_layout).unwrap(),
            [-7.0, 9.0]
        );
        let byte_layout = layout(DataType::Uint8, Encoding::Base64, 3);
        assert_eq!(
            decode(&STANDARD.encode([0u8, 7, 255]), &byte_layout).unwrap(),
            [0.0, 7.0, 255.0]
        );
    }

    #[test]
    fn sizes_are_checked_before_allocating() {
        let tiny = STANDARD.encode([0u8; 12]);
        let huge = layout(DataType::Float32, Encoding::Base64, usize::MAX / 8);
        assert!(decode(&tiny, &huge).unwrap_err().contains("declare"));
        let huge_gzip = Layout {
            encoding: Encoding::GzipBase64,
            ..huge
        };
        assert!(decode(&encode(&[0u8; 12]), &huge_gzip)
            .unwrap_err()
            .contains("more than"));
        let overflow = layout(DataType::Float32, Encoding::Base64, usize::MAX);
        assert!(decode(&tiny, &overflow).unwrap_err().contains("absurd"));
        // A bomb: ten megabytes of zeros declared as three floats.
        let bomb = encode(&vec![0u8; 10 << 20]);
        let small = layout(DataType::Float32, Encoding::GzipBase64, 3);
        assert!(decode(&bomb, &small)
            .unwrap_err()
            .contains("more than the 12 bytes"));
        let ascii = layout(DataType::Float32, Encoding::Ascii, 1 << 40);
        assert!(decode("1 2 3", &ascii).unwrap_err().contains("declare"));
        let bad = layout(DataType::Float32, Encoding::Base64, 3);
        assert!(decode("!!!!!!!!!!!!!!!!", &bad)
            .unwrap_err()
            .contains("base64"));
        assert!(Encoding::from_name("ExternalFileBinary")
            .unwrap_err()
            .contains("external"));
    }
}
