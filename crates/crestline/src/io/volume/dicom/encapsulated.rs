//! Checks of encapsulated pixel data (PS3.5 A.4) before a decoder sees it.
//!
//! dicom-rs's decoders trust the headers inside the fragments: an RLE header
//! claiming 0xFFFFFFFF segments made it allocate 16 GiB, a JPEG frame header
//! claiming 65535 × 65535 pixels 4 GiB, whatever the file's Rows and Columns. Here
//! each RLE fragment's header (PS3.5 G.5) and each JPEG frame header (ITU T.81
//! B.2.2) is checked against the file's attributes first, so that what a decoder
//! allocates is bounded by the frames the file declares (whose voxel count was
//! checked, and whose samples were reserved, before any pixel is decoded).

use dicom_dictionary_std::tags;
use dicom_object::DefaultDicomObject;

use super::header::unsigned;
use crate::{Error, Result};

/// The transfer syntax of RLE Lossless (PS3.5 A.4.2).
const RLE_LOSSLESS: &str = "1.2.840.10008.1.2.5";

/// The prefix of the JPEG family's transfer syntaxes (PS3.5 A.4.1), the only
/// other encapsulated syntaxes crestline decodes.
const JPEG_FAMILY: &str = "1.2.840.10008.1.2.4.";

/// The most segments an RLE frame may have (PS3.5 G.5: the header has room for 15).
const MAX_RLE_SEGMENTS: u32 = 15;

/// Bytes of an RLE header: the segment count and 15 offsets.
const RLE_HEADER_BYTES: usize = 64;

/// An error unless the encapsulated pixel data of `object`, if any, agrees with
/// its Rows, Columns, Number of Frames and Bits Allocated.
pub(super) fn check(object: &DefaultDicomObject) -> Result<()> {
    let Some(fragments) = object
        .element(tags::PIXEL_DATA)
        .ok()
        .and_then(|element| element.value().fragments())
    else {
        return Ok(());
    };
    let syntax = object
        .meta()
        .transfer_syntax()
        .trim_end_matches(['\0', ' ']);
    let count = |tag, name| unsigned(object, tag, name).map(|n| n.unwrap_or(0));
    let rows = count(tags::ROWS, "Rows")?;
    let columns = count(tags::COLUMNS, "Columns")?;
    if syntax == RLE_LOSSLESS {
        let frames = unsigned(object, tags::NUMBER_OF_FRAMES, "Number of Frames")?.unwrap_or(1);
        let bytes = count(tags::BITS_ALLOCATED, "Bits Allocated")?.div_ceil(8);
        check_rle(fragments, frames, bytes)
    } else if syntax.starts_with(JPEG_FAMILY) {
        fragments
            .iter()
            .try_for_each(|fragment| check_jpeg(fragment, [rows, columns]))
    } else {
        Ok(())
    }
}

/// An error unless there is one RLE fragment per frame, each with a header of at
/// least `bytes` and at most 15 segments whose offsets lie, in order, within it.
fn check_rle(fragments: &[Vec<u8>], frames: u32, bytes: u32) -> Result<()> {
    if fragments.len() != frames as usize {
        return Err(corrupt(format!(
            "its RLE pixel data has {} fragments for {frames} frames (one each)",
            fragments.len()
        )));
    }
    for (number, fragment) in fragments.iter().enumerate() {
        let word = |i: usize| {
            let b = &fragment[4 * i..4 * i + 4];
            u32::from_le_bytes([b[0], b[1], b[2], b[3]])
        };
        let frame = number + 1;
        if fragment.len() < RLE_HEADER_BYTES {
            return Err(corrupt(format!(
                "the RLE data of frame {frame} is shorter than its header"
            )));
        }
        let segments = word(0);
        if segments < bytes || segments > MAX_RLE_SEGMENTS {
            return Err(corrupt(format!(
                "the RLE header of frame {frame} declares {segments} segments \
                 ({bytes} to {MAX_RLE_SEGMENTS} expected)"
            )));
        }
        let mut previous = RLE_HEADER_BYTES as u64;
        for i in 1..=segments as usize {
            let offset = u64::from(word(i));
            if offset < previous || offset > fragment.len() as u64 || (i == 1 && offset != previous)
            {
                return Err(corrupt(format!(
                    "the RLE header of frame {frame} puts segment {i} at byte {offset}, \
                     outside its {} bytes or out of order",
                    fragment.len()
                )));
            }
            previous = offset;
        }
    }
    Ok(())
}

/// An error when the JPEG image starting `fragment` declares more rows or columns
/// than the file (`size`: Rows, Columns). Only the marker segments before the
/// scan are read; a fragment that does not start an image (a continuation, or
/// one too damaged to walk) is left to the decoder to report.
fn check_jpeg(fragment: &[u8], [rows, columns]: [u32; 2]) -> Result<()> {
    let Some(mut at) = fragment.starts_with(&[0xFF, 0xD8]).then_some(2) else {
        return Ok(());
    };
    while let (Some(&0xFF), Some(&marker)) = (fragment.get(at), fragment.get(at + 1)) {
        if marker == 0xFF {
            // A fill byte before a marker.
            at += 1;
            continue;
        }
        if marker == 0xDA || marker == 0xD9 {
            break; // The scan (or the end) starts: no frame header follows.
        }
        let field = |offset: usize| {
            fragment
                .get(at + offset..at + offset + 2)
                .map(|b| u32::from(u16::from_be_bytes([b[0], b[1]])))
        };
        let Some(length) = field(2) else { break };
        if is_frame_header(marker) {
            let (Some(height), Some(width)) = (field(5), field(7)) else {
                break;
            };
            if height > rows || width > columns {
                return Err(corrupt(format!(
                    "its JPEG data declares a {width} × {height} image in a frame of \
                     {columns} × {rows} pixels"
                )));
            }
        }
        at += 2 + length as usize;
    }
    Ok(())
}

/// Whether `marker` starts a frame header (SOF0–SOF15 but DHT, JPG and DAC).
fn is_frame_header(marker: u8) -> bool {
    (0xC0..=0xCF).contains(&marker) && ![0xC4, 0xC8, 0xCC].contains(&marker)
}

/// The error for pixel data whose own headers disagree with the file.
fn corrupt(message: String) -> Error {
    Error::Parse(format!("its pixel data cannot be decoded: {message}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rle_header(segments: u32, offsets: &[u32], len: usize) -> Vec<u8> {
        let mut bytes = vec![0u8; len];
        bytes[..4].copy_from_slice(&segments.to_le_bytes());
        for (i, offset) in offsets.iter().enumerate() {
            bytes[4 + 4 * i..8 + 4 * i].copy_from_slice(&offset.to_le_bytes());
        }
        bytes
    }

    #[test]
    fn rle_headers_must_fit_their_fragment() {
        let good = rle_header(2, &[64, 80], 100);
        check_rle(std::slice::from_ref(&good), 1, 2).unwrap();
        let err = |fragments: &[Vec<u8>], frames| {
            check_rle(fragments, frames, 2).unwrap_err().to_string()
        };
        assert!(err(std::slice::from_ref(&good), 2).contains("1 fragments for 2 frames"));
        let huge = rle_header(u32::MAX, &[64], 100);
        assert!(err(&[huge], 1).contains("declares 4294967295 segments"));
        let outside = rle_header(2, &[64, 4000], 100);
        assert!(err(&[outside], 1).contains("segment 2 at byte 4000"));
        let backwards = rle_header(2, &[80, 70], 100);
        assert!(err(&[backwards], 1).contains("segment 1 at byte 80"));
        assert!(err(&[vec![1, 0, 0, 0]], 1).contains("shorter than its header"));
    }

    #[test]
    fn a_jpeg_frame_larger_than_the_image_is_refused() {
        // SOI, an APP0 segment whose payload holds FF C0, then SOF0 of h × w.
        let jpeg = |h: u16, w: u16| {
            let mut bytes = vec![0xFF, 0xD8, 0xFF, 0xE0, 0x00, 0x06, 0xFF, 0xC0, 0xFF, 0xFF];
            bytes.extend([0xFF, 0xC0, 0x00, 0x0B, 0x08]);
            bytes.extend(h.to_be_bytes());
            bytes.extend(w.to_be_bytes());
            bytes.extend([0x01, 0x01, 0x11, 0x00, 0xFF, 0xDA]);
            bytes
        };
        check_jpeg(&jpeg(64, 32), [64, 32]).unwrap();
        let err = check_jpeg(&jpeg(65535, 65535), [64, 32]).unwrap_err();
        assert!(
            err.to_string()
                .contains("a 65535 × 65535 image in a frame of 32 × 64"),
            "{err}"
        );
        check_jpeg(&[0x00, 0x01, 0xFF, 0xC0], [1, 1]).unwrap();
    }
}
