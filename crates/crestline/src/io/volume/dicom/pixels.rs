//! Decoding pixel data into modality values.
//!
//! The transfer syntax of a file (PS3.5 §10) says how its pixels are stored:
//! native (implicit or explicit VR little endian, explicit VR big endian,
//! deflated) or encapsulated (PS3.5 A.4: JPEG baseline, extended and lossless,
//! RLE lossless) are decoded by dicom-rs; JPEG-LS, JPEG 2000, JPEG XL and the
//! video syntaxes need codecs this build lacks and are refused by name before
//! any pixel is read. Stored values are masked to Bits Stored and sign-extended
//! when Pixel Representation (0028,0103) says they are signed (PS3.5 §8.1.1), then
//! mapped by the frame's modality LUT (PS3.3 C.11.1): `slope · stored +
//! intercept`, e.g. Hounsfield units of CT.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering as AtomicOrdering};
use std::sync::Once;

use dicom_pixeldata::{PixelDecoder, PixelRepresentation};
use dicom_transfer_syntax_registry::{TransferSyntaxIndex, TransferSyntaxRegistry};

use super::header::causes;
use crate::{Error, Result};

/// The linear modality LUT of a frame: Rescale Slope and Intercept (PS3.3
/// C.11.1.1.2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Rescale {
    /// Rescale Slope (0028,1053).
    pub slope: f64,
    /// Rescale Intercept (0028,1052).
    pub intercept: f64,
}

/// An error unless the transfer syntax `uid` is known and this build decodes its
/// pixel data, naming the syntax.
pub(super) fn check_transfer_syntax(uid: &str) -> Result<()> {
    match TransferSyntaxRegistry.get(uid) {
        Some(syntax) if syntax.can_decode_all() => Ok(()),
        Some(syntax) => Err(Error::Parse(format!(
            "is stored in the transfer syntax {} ({uid}), which crestline cannot decode; \
             supported: uncompressed (implicit or explicit VR, little or big endian, deflated), \
             8-bit JPEG baseline and extended, JPEG lossless, and RLE lossless (convert the \
             series first, e.g. with gdcmconv --raw)",
            syntax.name()
        ))),
        None => Err(Error::Parse(format!(
            "is stored in the unknown transfer syntax {uid}"
        ))),
    }
}

/// A frame to decode: its number in the file, its modality LUT, and where its
/// samples go (rows × columns values, row by row).
pub(super) type Target<'a> = (u32, Rescale, &'a mut [f32]);

/// How many decodings run now, on any thread: while one does, panics are silent.
static DECODING: AtomicUsize = AtomicUsize::new(0);

/// Sets, once, a process panic hook that is silent while a decoding runs (a
/// decoder's panic, on the calling thread or a worker, becomes an error about the
/// file, without its text on stderr) and passes every other panic to the hook
/// that was set before: the default one, Python's, or a program's own.
fn chain_quiet_hook() {
    static CHAINED: Once = Once::new();
    CHAINED.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if DECODING.load(AtomicOrdering::SeqCst) == 0 {
                previous(info);
            }
        }));
    });
}

/// `decode()`, a panic in it caught ([`chain_quiet_hook`]).
fn quietly<T>(decode: impl FnOnce() -> T) -> std::thread::Result<T> {
    chain_quiet_hook();
    DECODING.fetch_add(1, AtomicOrdering::SeqCst);
    let result = catch_unwind(AssertUnwindSafe(decode));
    DECODING.fetch_sub(1, AtomicOrdering::SeqCst);
    result
}

/// Decode the frames of the file at `path` that `targets` ask for. Errors name
/// the file: one that cannot be read or decoded, or whose pixel data is shorter
/// than its frames.
pub(super) fn decode(path: &Path, targets: Vec<Target<'_>>) -> Result<()> {
    let fail = |message: String| Error::File {
        path: path.to_path_buf(),
        message,
    };
    let object = super::header::open(path, None)?;
    super::encapsulated::check(&object).map_err(|e| super::super::in_file(e, path))?;
    // dicom-rs's RLE decoder indexes corrupt segments without checking them: its
    // panic is an error about the file like any other.
    let decoded = quietly(|| object.decode_pixel_data())
        .map_err(|_| {
            fail(
                "its pixel data cannot be decoded: the decoder stopped on corrupt data".to_string(),
            )
        })?
        .map_err(|e| fail(format!("its pixel data cannot be decoded: {}", causes(&e))))?;
    let bytes = usize::from(decoded.bits_allocated() / 8);
    let bits = u32::from(decoded.bits_stored());
    if ![1, 2, 4].contains(&bytes) || bits == 0 || bits as usize > 8 * bytes {
        return Err(fail(format!(
            "its decoded pixels have {} bits allocated and {bits} stored; 8, 16 or 32 allocated are supported",
            decoded.bits_allocated()
        )));
    }
    let stored = Stored {
        bytes,
        bits,
        signed: decoded.pixel_representation() == PixelRepresentation::Signed,
    };
    let data = decoded.data();
    for (frame, rescale, out) in targets {
        let size = out.len() * bytes;
        let start = frame as usize * size;
        let frame_bytes = data.get(start..start + size).ok_or_else(|| {
            fail(format!(
                "its pixel data holds {} bytes, too few for frame {} of {} bytes (a truncated file?)",
                data.len(),
                frame + 1,
                size
            ))
        })?;
        stored.decode(frame_bytes, rescale, out);
    }
    Ok(())
}

/// How stored values are laid out: bytes per value, bits used and sign.
#[derive(Clone, Copy, Debug)]
struct Stored {
    bytes: usize,
    bits: u32,
    signed: bool,
}

impl Stored {
    /// The modality values of the stored values in `data` (native byte order),
    /// into `out`.
    fn decode(self, data: &[u8], rescale: Rescale, out: &mut [f32]) {
        let unused = 32 - self.bits;
        for (value, chunk) in out.iter_mut().zip(data.chunks_exact(self.bytes)) {
            let mut word = [0u8; 4];
            let raw = match self.bytes {
                1 => u32::from(chunk[0]),
                2 => u32::from(u16::from_ne_bytes([chunk[0], chunk[1]])),
                _ => {
                    word.copy_from_slice(chunk);
                    u32::from_ne_bytes(word)
                }
            };
            // Keep the stored bits at the top of a word, then shift them back:
            // arithmetically (sign-extending) for signed values.
            let top = raw << unused;
            let stored = if self.signed {
                f64::from((top as i32) >> unused)
            } else {
                f64::from(top >> unused)
            };
            *value = (rescale.slope * stored + rescale.intercept) as f32;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn decoded(stored: Stored, data: &[u8], rescale: Rescale) -> Vec<f32> {
        let mut out = vec![0.0; data.len() / stored.bytes];
        stored.decode(data, rescale, &mut out);
        out
    }

    const IDENTITY: Rescale = Rescale {
        slope: 1.0,
        intercept: 0.0,
    };

    #[test]
    fn stored_bits_are_masked_or_sign_extended() {
        let data: Vec<u8> = [0x0fffu16, 0xf800, 0x0801]
            .iter()
            .flat_map(|v| v.to_ne_bytes())
            .collect();
        let twelve = |signed| Stored {
            bytes: 2,
            bits: 12,
            signed,
        };
        assert_eq!(
            decoded(twelve(false), &data, IDENTITY),
            [4095.0, 2048.0, 2049.0]
        );
        assert_eq!(
            decoded(twelve(true), &data, IDENTITY),
            [-1.0, -2048.0, -2047.0]
        );
    }

    #[test]
    fn the_modality_lut_maps_stored_values() {
        let ct = Rescale {
            slope: 2.0,
            intercept: -1024.0,
        };
        let bytes = Stored {
            bytes: 1,
            bits: 8,
            signed: false,
        };
        assert_eq!(decoded(bytes, &[0, 12], ct), [-1024.0, -1000.0]);
        let words = Stored {
            bytes: 4,
            bits: 32,
            signed: true,
        };
        let data = (-5i32).to_ne_bytes();
        assert_eq!(decoded(words, &data, IDENTITY), [-5.0]);
    }

    #[test]
    fn undecodable_syntaxes_are_named() {
        check_transfer_syntax("1.2.840.10008.1.2.1").unwrap();
        let err = check_transfer_syntax("1.2.840.10008.1.2.4.90")
            .unwrap_err()
            .to_string();
        assert!(err.contains("JPEG 2000"), "{err}");
        let err = check_transfer_syntax("1.2.3.4").unwrap_err().to_string();
        assert!(err.contains("unknown transfer syntax 1.2.3.4"), "{err}");
    }
}
