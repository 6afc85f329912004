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

use crate::{Error, Result};

/// The transfer syntax UIDs whose data set is encoded differently from explicit
/// VR little endian (PS3.5 A.1–A.5).
const IMPLICIT_LITTLE: &str = "1.2.840.10008.1.2";
const EXPLICIT_BIG: &str = "1.2.840.10008.1.2.2";
const DEFLATED: &str = "1.2.840.10008.1.2.1.99";

/// The explicit VRs whose length takes 4 bytes after 2 reserved ones (PS3.5
/// Table 7.1-1).
const LONG_VRS: [&[u8; 2]; 13] = [
    b"OB", b"OD", b"OF", b"OL", b"OV", b"OW", b"SQ", b"SV", b"UC", b"UN", b"UR", b"UT", b"UV",
];

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
    vr: Option<[u8; 2]>,
    length: u32,
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
                header.vr == Some(*b"SQ") || (header.vr.is_none() && self.holds_items(&header));
            if header.tag == PIXEL_DATA {
                match undefined {
                    true => self.fragments()?,
                    false => self.value(&header).map(|_| ())?,
                }
                continue;
            }
            if undefined && header.vr == Some(*b"UN") {
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

    /// Read the element header at the position.
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
        let vr = [self.byte()?, self.byte()?];
        let length = if LONG_VRS.contains(&&vr) {
            self.u16()?;
            self.u32()?
        } else {
            u32::from(self.u16()?)
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

    /// The value of `header`, after checking that it fits, moving past it.
    fn value(&mut self, header: &ElementHeader) -> Result<&[u8]> {
        self.remaining(header)?;
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
}
