//! Element lengths checked against the size of the file before dicom-rs parses
//! it.
//!
//! dicom-rs fills a buffer of an element's declared length (up to 4 GiB) before it
//! finds that the file ends sooner, so a file of a few kilobytes with one corrupt
//! length would cost gigabytes and seconds. This walk over the element headers of
//! PS3.5 §7.1 (explicit VR with 2- or 4-byte lengths, implicit VR, items and
//! delimiters of §7.5) refuses any defined length longer than what is left of the
//! file. It enters sequences and items, both of undefined and defined length, to
//! check the elements inside them, and skips the Pixel Data (7FE0,0010) whole or
//! fragment by fragment (PS3.5 A.4), then goes on to any elements after it. The
//! deflated syntax (§A.5) compresses the data set and is not walked; an element of
//! VR UN with an undefined length holds implicit VR data and ends the walk too.

use dicom_core::dictionary::{DataDictionary, DataDictionaryEntry};
use dicom_core::{Tag, VR};
use dicom_dictionary_std::StandardDataDictionary;

use crate::{Error, Result};

/// The transfer syntax UIDs whose data set is encoded differently from explicit
/// VR little endian (PS3.5 A.1–A.5).
const IMPLICIT_LITTLE: &str = "1.2.840.10008.1.2";
const EXPLICIT_BIG: &str = "1.2.840.10008.1.2.2";
const DEFLATED: &str = "1.2.840.10008.1.2.1.99";

/// The tag of Pixel Data.
const PIXEL_DATA: (u16, u16) = (0x7fe0, 0x0010);

/// An undefined length (PS3.5 §7.1.1).
const UNDEFINED: u32 = u32::MAX;

/// Check the lengths in `file`, a DICOM file from its 128-byte preamble on.
pub(super) fn check(file: &[u8]) -> Result<()> {
    let mut walk = Walk {
        bytes: file,
        at: 132,
        explicit: true,
        little: true,
    };
    let syntax = walk.meta_group()?;
    match syntax.as_str() {
        DEFLATED => return Ok(()),
        IMPLICIT_LITTLE => walk.explicit = false,
        EXPLICIT_BIG => walk.little = false,
        _ => {}
    }
    walk.data_set()
}

/// A position in the file and how its elements are encoded.
struct Walk<'a> {
    bytes: &'a [u8],
    at: usize,
    explicit: bool,
    little: bool,
}

/// One element header: tag, explicit VR (if any) and length.
struct ElementHeader {
    tag: (u16, u16),
    vr: Option<VR>,
    length: u32,
}

impl ElementHeader {
    /// The size in bytes of one of its values ([`value_unit`]): by its explicit
    /// VR, or the dictionary's for an implicit one; an item's is a byte.
    fn unit(&self) -> usize {
        match (self.vr, self.tag.0) {
            (Some(vr), _) => value_unit(vr),
            (None, 0xfffe) => 1,
            (None, _) => value_unit(implicit_vr(self.tag)),
        }
    }
}

impl Walk<'_> {
    /// Walk the file meta group (always explicit VR little endian) and return its
    /// Transfer Syntax UID (0002,0010).
    fn meta_group(&mut self) -> Result<String> {
        let mut syntax = String::new();
        while self.bytes.get(self.at..self.at + 2) == Some(&[0x02, 0x00]) {
            let header = self.header()?;
            let value = self.value(&header)?;
            if header.tag == (0x0002, 0x0010) {
                syntax = String::from_utf8_lossy(value)
                    .trim_end_matches(['\0', ' '])
                    .to_string();
            }
        }
        Ok(syntax)
    }

    /// Walk the elements to the end of the file.
    fn data_set(&mut self) -> Result<()> {
        while self.at < self.bytes.len() {
            let header = self.header()?;
            let undefined = header.length == UNDEFINED;
            let item = header.tag.0 == 0xfffe;
            let sequence =
                header.vr == Some(VR::SQ) || (header.vr.is_none() && self.holds_items(&header));
            if header.tag == PIXEL_DATA {
                match undefined {
                    true => self.fragments()?,
                    false => self.value(&header).map(|_| ())?,
                }
                continue;
            }
            if undefined && header.vr == Some(VR::UN) {
                return Ok(());
            }
            // Sequences and items are entered (their elements follow); delimiters
            // have no value; any other value is skipped.
            if !(undefined || item || sequence) {
                self.value(&header)?;
            } else if !undefined {
                self.remaining(&header)?;
            }
        }
        Ok(())
    }

    /// Walk the items of encapsulated pixel data (PS3.5 A.4), skipping each
    /// fragment, to the sequence delimiter.
    fn fragments(&mut self) -> Result<()> {
        loop {
            let header = self.header()?;
            if header.tag == (0xfffe, 0xe0dd) {
                return Ok(());
            }
            self.value(&header)?;
        }
    }

    /// Whether the implicit VR element `header` is a sequence: its value starts
    /// with an item tag (FFFE,E000).
    fn holds_items(&self, header: &ElementHeader) -> bool {
        header.tag.0 != 0xfffe
            && header.length >= 8
            && self.bytes.get(self.at..self.at + 4) == Some(&self.encode_tag((0xfffe, 0xe000))[..])
    }

    /// The bytes of `tag` as this walk encodes it.
    fn encode_tag(&self, (group, element): (u16, u16)) -> [u8; 4] {
        let [g0, g1] = self.u16_bytes(group);
        let [e0, e1] = self.u16_bytes(element);
        [g0, g1, e0, e1]
    }

    fn u16_bytes(&self, value: u16) -> [u8; 2] {
        if self.little {
            value.to_le_bytes()
        } else {
            value.to_be_bytes()
        }
    }

    /// Read the element header at the position. An explicit VR that is not one of
    /// PS3.5 Table 7.1-1 is read as UN (as dicom-rs reads it: 2 reserved bytes and
    /// a 4-byte length), or a corrupt VR would hide a huge length from the walk;
    /// the VR of an implicit one is the dictionary's.
    fn header(&mut self) -> Result<ElementHeader> {
        let tag = (self.u16()?, self.u16()?);
        if tag.0 == 0xfffe || !self.explicit {
            let length = self.u32()?;
            return Ok(ElementHeader {
                tag,
                vr: None,
                length,
            });
        }
        let vr = VR::from_binary([self.byte()?, self.byte()?]).unwrap_or(VR::UN);
        let length = if short_length(vr) {
            u32::from(self.u16()?)
        } else {
            self.u16()?;
            self.u32()?
        };
        Ok(ElementHeader {
            tag,
            vr: Some(vr),
            length,
        })
    }

    /// An error unless the value of `header` fits in the rest of the file.
    fn remaining(&self, header: &ElementHeader) -> Result<()> {
        let left = self.bytes.len() - self.at;
        if header.length as usize <= left {
            return Ok(());
        }
        let (group, element) = header.tag;
        Err(Error::Parse(format!(
            "its element ({group:04X},{element:04X}) at byte {} claims {} bytes, but the file has {left} left \
             (a truncated or corrupt file)",
            self.at,
            header.length
        )))
    }

    /// The value of `header`, after checking that it fits and holds whole
    /// values ([`value_unit`]), moving past it.
    fn value(&mut self, header: &ElementHeader) -> Result<&[u8]> {
        self.remaining(header)?;
        let unit = header.unit();
        if !(header.length as usize).is_multiple_of(unit) {
            let (group, element) = header.tag;
            return Err(Error::Parse(format!(
                "its element ({group:04X},{element:04X}) at byte {} has a length of {} bytes, \
                 not a whole number of its {unit}-byte values (a corrupt file)",
                self.at, header.length
            )));
        }
        let start = self.at;
        self.at += header.length as usize;
        Ok(&self.bytes[start..self.at])
    }

    fn byte(&mut self) -> Result<u8> {
        let byte = self
            .bytes
            .get(self.at)
            .copied()
            .ok_or_else(|| self.ended())?;
        self.at += 1;
        Ok(byte)
    }

    fn u16(&mut self) -> Result<u16> {
        let bytes = [self.byte()?, self.byte()?];
        Ok(if self.little {
            u16::from_le_bytes(bytes)
        } else {
            u16::from_be_bytes(bytes)
        })
    }

    fn u32(&mut self) -> Result<u32> {
        let bytes = [self.byte()?, self.byte()?, self.byte()?, self.byte()?];
        Ok(if self.little {
            u32::from_le_bytes(bytes)
        } else {
            u32::from_be_bytes(bytes)
        })
    }

    /// The error for a file that ends inside an element header.
    fn ended(&self) -> Error {
        Error::Parse(format!(
            "ends inside an element header at byte {} (a truncated file)",
            self.at
        ))
    }
}

/// Whether an explicit `vr` has a 2-byte length (PS3.5 Table 7.1-2).
fn short_length(vr: VR) -> bool {
    use VR::*;
    matches!(
        vr,
        AE | AS
            | AT
            | CS
            | DA
            | DS
            | DT
            | FL
            | FD
            | IS
            | LO
            | LT
            | PN
            | SH
            | SL
            | SS
            | ST
            | TM
            | UI
            | UL
            | US
    )
}

/// The VR a reader gives an implicit VR element: the dictionary's, OW for Pixel
/// Data and overlays (PS3.5 A.1 c), UN for an unknown tag.
fn implicit_vr((group, element): (u16, u16)) -> VR {
    if (group, element) == PIXEL_DATA || (group >> 8 == 0x60 && element == 0x3000) {
        return VR::OW;
    }
    StandardDataDictionary
        .by_tag(Tag(group, element))
        .map_or(VR::UN, |entry| entry.vr().relaxed())
}

/// The size in bytes of one value of `vr`. dicom-rs reads length / size values
/// of a binary VR and moves on by the length: a length that is not a multiple
/// leaves it reading the next elements from the wrong byte, where it may find
/// a length of gigabytes and allocate it before failing.
fn value_unit(vr: VR) -> usize {
    use VR::*;
    match vr {
        US | OW | SS => 2,
        AT | FL | OF | SL | UL | OL => 4,
        FD | OD | SV | UV | OV => 8,
        _ => 1,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A file of explicit VR little endian elements after the preamble.
    fn file(elements: &[u8]) -> Vec<u8> {
        let syntax = b"1.2.840.10008.1.2.1\0";
        let mut bytes = vec![0u8; 128];
        bytes.extend_from_slice(b"DICM");
        bytes.extend_from_slice(&[0x02, 0x00, 0x10, 0x00, b'U', b'I', syntax.len() as u8, 0]);
        bytes.extend_from_slice(syntax);
        bytes.extend_from_slice(elements);
        bytes
    }

    #[test]
    fn lengths_that_fit_pass() {
        // Rows (US, 2 bytes), then a sequence of undefined length with one item.
        let mut elements = vec![0x28, 0x00, 0x10, 0x00, b'U', b'S', 2, 0, 64, 0];
        elements.extend_from_slice(&[
            0x08, 0x00, 0x15, 0x11, b'S', b'Q', 0, 0, 0xff, 0xff, 0xff, 0xff,
        ]);
        elements.extend_from_slice(&[0xfe, 0xff, 0x00, 0xe0, 10, 0, 0, 0]);
        elements.extend_from_slice(&[0x08, 0x00, 0x50, 0x11, b'U', b'I', 2, 0, b'1', 0]);
        elements.extend_from_slice(&[0xfe, 0xff, 0xdd, 0xe0, 0, 0, 0, 0]);
        check(&file(&elements)).unwrap();
    }

    #[test]
    fn a_length_beyond_the_file_is_refused_also_inside_a_sequence() {
        let mut elements = vec![
            0x08, 0x00, 0x15, 0x11, b'S', b'Q', 0, 0, 0xff, 0xff, 0xff, 0xff,
        ];
        elements.extend_from_slice(&[0xfe, 0xff, 0x00, 0xe0, 0xff, 0xff, 0xff, 0xff]);
        elements.extend_from_slice(&[0x08, 0x00, 0x50, 0x11, b'O', b'B', 0, 0, 0, 0, 0, 0x40]);
        let err = check(&file(&elements)).unwrap_err().to_string();
        assert!(
            err.contains("(0008,1150)") && err.contains("claims 1073741824 bytes"),
            "{err}"
        );
        let err = check(&file(&[0x28, 0x00, 0x10])).unwrap_err().to_string();
        assert!(err.contains("ends inside an element header"), "{err}");
    }

    #[test]
    fn an_unknown_vr_takes_a_four_byte_length_as_dicom_rs_reads_it() {
        // (0018,0000) with the corrupt VR "\x01S": a DICOM reader takes it for UN,
        // whose length is the 4 bytes after 2 reserved ones, here 0x2053_4648
        // (542 MB), not the 2 bytes 04 00 a short VR would have.
        let elements = [
            0x18, 0x00, 0x00, 0x00, 0x01, b'S', 0x04, 0x00, b'H', b'F', b'S', b' ',
        ];
        let err = check(&file(&elements)).unwrap_err().to_string();
        assert!(
            err.contains("(0018,0000)") && err.contains("claims 542328392 bytes"),
            "{err}"
        );
        // An undefined length of an unknown VR is UN's: implicit VR data, not walked.
        let elements = [
            0x18, 0x00, 0x00, 0x00, 0x01, b'S', 0, 0, 0xff, 0xff, 0xff, 0xff,
        ];
        check(&file(&elements)).unwrap();
    }

    #[test]
    fn a_binary_value_of_a_broken_length_is_refused() {
        // Rows (US) with 3 bytes: a reader takes one value and loses its place.
        let elements = [0x28, 0x00, 0x10, 0x00, b'U', b'S', 3, 0, 64, 0, 0];
        let err = check(&file(&elements)).unwrap_err().to_string();
        assert!(
            err.contains("(0028,0010)") && err.contains("of its 2-byte values"),
            "{err}"
        );
    }
}
