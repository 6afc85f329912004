//! The header of a PLY file: its grammar, checked line by line, the check that
//! the element counts it announces fit in the rest of the file, and the writer of
//! the headers of every PLY file the crate writes ([`write_header`]).
//!
//! ```text
//! ply
//! format ascii|binary_little_endian|binary_big_endian 1.0
//! comment ... | obj_info ...
//! element <name> <count>
//! property <type> <name> | property list <count type> <item type> <name>
//! end_header
//! ```

use std::io::{self, Write};

use super::ply_binary::Endian;
use super::{line_error, quoted, truncated, Input};
use crate::{Error, Result};

/// How the records after the header are written.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(super) enum Encoding {
    /// One record per line, values as text.
    Ascii,
    /// Records as packed binary values.
    Binary(Endian),
}

/// A PLY scalar type.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) enum ScalarType {
    Char,
    UChar,
    Short,
    UShort,
    Int,
    UInt,
    Float,
    Double,
}

/// Every type name of the format, with its synonyms.
const TYPE_NAMES: &[(&str, ScalarType)] = &[
    ("char", ScalarType::Char),
    ("int8", ScalarType::Char),
    ("uchar", ScalarType::UChar),
    ("uint8", ScalarType::UChar),
    ("short", ScalarType::Short),
    ("int16", ScalarType::Short),
    ("ushort", ScalarType::UShort),
    ("uint16", ScalarType::UShort),
    ("int", ScalarType::Int),
    ("int32", ScalarType::Int),
    ("uint", ScalarType::UInt),
    ("uint32", ScalarType::UInt),
    ("float", ScalarType::Float),
    ("float32", ScalarType::Float),
    ("double", ScalarType::Double),
    ("float64", ScalarType::Double),
];

impl ScalarType {
    /// The type called `name` in a header.
    fn from_name(name: &str) -> std::result::Result<ScalarType, String> {
        TYPE_NAMES
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, t)| *t)
            .ok_or_else(|| format!("unknown PLY type {}", quoted(name)))
    }

    /// The usual name of the type, for messages.
    pub(super) fn name(self) -> &'static str {
        TYPE_NAMES
            .iter()
            .find(|(_, t)| *t == self)
            .map_or("?", |(n, _)| n)
    }

    /// Size in bytes in a binary file.
    pub(super) fn size(self) -> usize {
        match self {
            ScalarType::Char | ScalarType::UChar => 1,
            ScalarType::Short | ScalarType::UShort => 2,
            ScalarType::Int | ScalarType::UInt | ScalarType::Float => 4,
            ScalarType::Double => 8,
        }
    }

    /// Whether the type is `float` or `double`.
    pub(super) fn is_float(self) -> bool {
        matches!(self, ScalarType::Float | ScalarType::Double)
    }

    /// The smallest and largest value of an integer type.
    pub(super) fn integer_range(self) -> (i64, i64) {
        match self {
            ScalarType::Char => (i8::MIN.into(), i8::MAX.into()),
            ScalarType::UChar => (0, u8::MAX.into()),
            ScalarType::Short => (i16::MIN.into(), i16::MAX.into()),
            ScalarType::UShort => (0, u16::MAX.into()),
            ScalarType::Int => (i32::MIN.into(), i32::MAX.into()),
            ScalarType::UInt => (0, u32::MAX.into()),
            ScalarType::Float | ScalarType::Double => (i64::MIN, i64::MAX),
        }
    }
}

/// The type of a property: one value, or a list with its length first.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) enum PropertyType {
    Scalar(ScalarType),
    List { count: ScalarType, item: ScalarType },
}

/// A property of an element.
#[derive(Clone, Debug)]
pub(crate) struct Property {
    pub name: String,
    pub kind: PropertyType,
}

impl Property {
    /// A property of one value of type `scalar`.
    pub(crate) fn scalar(scalar: ScalarType, name: impl Into<String>) -> Property {
        Property {
            name: name.into(),
            kind: PropertyType::Scalar(scalar),
        }
    }
}

/// An element of the header: `count` records of the same properties.
#[derive(Clone, Debug)]
pub(crate) struct Element {
    pub name: String,
    pub count: usize,
    pub properties: Vec<Property>,
}

impl Element {
    /// The property called `name`.
    pub(super) fn property(&self, name: &str) -> Option<(usize, &Property)> {
        self.properties
            .iter()
            .enumerate()
            .find(|(_, p)| p.name == name)
    }

    /// The column of the scalar property `name` among the element's scalar
    /// properties (the order of a record's scalars, [`super::ply_records::Record`]).
    pub(super) fn scalar_column(&self, name: &str) -> Result<usize> {
        self.properties
            .iter()
            .filter(|p| matches!(p.kind, PropertyType::Scalar(_)))
            .position(|p| p.name == name)
            .ok_or_else(|| {
                Error::Parse(format!(
                    "the PLY {} element has no scalar property '{name}'",
                    self.name
                ))
            })
    }

    /// Fewest bytes a binary record can take (a list may be empty).
    fn min_binary_bytes(&self) -> usize {
        self.properties
            .iter()
            .map(|p| match p.kind {
                PropertyType::Scalar(t) | PropertyType::List { count: t, .. } => t.size(),
            })
            .sum()
    }
}

/// What a PLY header declares.
#[derive(Debug)]
pub(super) struct Header {
    pub encoding: Encoding,
    /// In file order; names are unique.
    pub elements: Vec<Element>,
}

/// Read the header, leaving `input` at the first byte after `end_header`'s line.
pub(super) fn read_header(input: &mut Input<'_>) -> Result<Header> {
    read_magic(input)?;
    let mut builder = HeaderBuilder::default();
    loop {
        let Some(line) = input.next_line()? else {
            return Err(Error::Parse(
                "the PLY header has no 'end_header' line (truncated file?)".to_string(),
            ));
        };
        let mut tokens = line.split_ascii_whitespace();
        let outcome = match tokens.next() {
            None | Some("comment" | "obj_info") => Ok(()),
            Some("end_header") => break,
            Some("format") => builder.format(tokens),
            Some("element") => builder.element(tokens, input.line()),
            Some("property") => builder.property(tokens),
            Some(other) => Err(format!("unexpected {} in the PLY header", quoted(other))),
        };
        outcome.map_err(|message| line_error(input.line(), message))?;
    }
    builder.finish()
}

/// The first line: `ply`.
fn read_magic(input: &mut Input<'_>) -> Result<()> {
    if !input.rest().starts_with(b"ply") {
        return Err(Error::Parse(
            "not a PLY file: it does not start with 'ply'".to_string(),
        ));
    }
    let line = input.next_line()?.unwrap_or_default();
    if line.trim_end() == "ply" {
        return Ok(());
    }
    Err(line_error(
        1,
        format!("not a PLY file: the first line is {}", quoted(line)),
    ))
}

/// The header read so far.
#[derive(Default)]
struct HeaderBuilder {
    encoding: Option<Encoding>,
    elements: Vec<Element>,
    /// The header line declaring each element.
    element_lines: Vec<usize>,
}

/// The problem with a header line, without its line number.
type LineResult = std::result::Result<(), String>;

impl HeaderBuilder {
    /// `format <encoding> <version>`.
    fn format<'t>(&mut self, mut tokens: impl Iterator<Item = &'t str>) -> LineResult {
        if self.encoding.is_some() {
            return Err("a second 'format' line".to_string());
        }
        let encoding = match tokens.next() {
            Some("ascii") => Encoding::Ascii,
            Some("binary_little_endian") => Encoding::Binary(Endian::Little),
            Some("binary_big_endian") => Encoding::Binary(Endian::Big),
            Some(other) => {
                return Err(format!(
                "unknown PLY format {} (expected ascii, binary_little_endian or binary_big_endian)",
                quoted(other)
            ))
            }
            None => return Err("the 'format' line names no format".to_string()),
        };
        match tokens.next() {
            Some(version) if is_version(version) => {}
            Some(other) => return Err(format!("cannot read the PLY version {}", quoted(other))),
            None => return Err("the 'format' line has no version".to_string()),
        }
        no_more(tokens, "the format")?;
        self.encoding = Some(encoding);
        Ok(())
    }

    /// `element <name> <count>`, declared on header line `line`.
    fn element<'t>(
        &mut self,
        mut tokens: impl Iterator<Item = &'t str>,
        line: usize,
    ) -> LineResult {
        let name = tokens
            .next()
            .ok_or("an 'element' line needs a name and a count")?;
        if let Some(first) = self.elements.iter().position(|e| e.name == name) {
            return Err(format!(
                "a second element {} (the first is on line {}); element names must be unique",
                quoted(name),
                self.element_lines[first]
            ));
        }
        let count = tokens
            .next()
            .ok_or_else(|| format!("element {} has no count", quoted(name)))?;
        let count = parse_count(name, count)?;
        no_more(tokens, "the element count")?;
        self.elements.push(Element {
            name: name.to_string(),
            count,
            properties: Vec::new(),
        });
        self.element_lines.push(line);
        Ok(())
    }

    /// `property <type> <name>` or `property list <count type> <item type> <name>`.
    fn property<'t>(&mut self, mut tokens: impl Iterator<Item = &'t str>) -> LineResult {
        let element = self
            .elements
            .last_mut()
            .ok_or("a 'property' line before any 'element' line")?;
        let kind = match tokens.next() {
            Some("list") => list_type(&mut tokens)?,
            Some(name) => PropertyType::Scalar(ScalarType::from_name(name)?),
            None => return Err("a 'property' line needs a type and a name".to_string()),
        };
        let name = tokens.next().ok_or("the property has no name")?;
        no_more(tokens, "the property name")?;
        if element.property(name).is_some() {
            return Err(format!(
                "a second property {} in element {}",
                quoted(name),
                quoted(&element.name)
            ));
        }
        element.properties.push(Property {
            name: name.to_string(),
            kind,
        });
        Ok(())
    }

    /// The header, once `end_header` is reached.
    fn finish(self) -> Result<Header> {
        let encoding = self
            .encoding
            .ok_or_else(|| Error::Parse("the PLY header has no 'format' line".to_string()))?;
        Ok(Header {
            encoding,
            elements: self.elements,
        })
    }
}

/// The two types after `property list`; the count type must be an integer type.
fn list_type<'t>(
    tokens: &mut impl Iterator<Item = &'t str>,
) -> std::result::Result<PropertyType, String> {
    let mut next_type = || {
        tokens
            .next()
            .ok_or_else(|| {
                "a list property needs a count type, an item type and a name".to_string()
            })
            .and_then(ScalarType::from_name)
    };
    let (count, item) = (next_type()?, next_type()?);
    if count.is_float() {
        return Err(format!(
            "a list length cannot have the floating-point type '{}'",
            count.name()
        ));
    }
    Ok(PropertyType::List { count, item })
}

/// An element count: a non-negative integer that fits in memory sizes.
fn parse_count(element: &str, token: &str) -> std::result::Result<usize, String> {
    if token.is_empty() || !token.bytes().all(|b| b.is_ascii_digit()) {
        return Err(format!(
            "cannot read the count of element {}: {} is not a non-negative integer",
            quoted(element),
            quoted(token)
        ));
    }
    token
        .parse::<u64>()
        .ok()
        .and_then(|n| usize::try_from(n).ok())
        .ok_or_else(|| {
            format!(
                "the count of element {} is too large: {}",
                quoted(element),
                quoted(token)
            )
        })
}

/// A version number such as `1.0`.
fn is_version(token: &str) -> bool {
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    match token.split_once('.') {
        Some((major, minor)) => digits(major) && digits(minor),
        None => digits(token),
    }
}

/// Fail if a header line goes on after `what`.
fn no_more<'t>(mut tokens: impl Iterator<Item = &'t str>, what: &str) -> LineResult {
    match tokens.next() {
        Some(extra) => Err(format!("unexpected {} after {what}", quoted(extra))),
        None => Ok(()),
    }
}

/// Check, before anything is allocated, that the `payload` after the header can
/// hold the records the header announces: in an ASCII file one line per record, in
/// a binary file the fewest bytes each record can take. Elements without properties
/// take no room.
pub(super) fn check_counts_fit(header: &Header, payload: &[u8]) -> Result<()> {
    let (mut room, cost): (u128, fn(&Element) -> u128) = match header.encoding {
        Encoding::Ascii => (count_lines(payload) as u128, |_| 1),
        Encoding::Binary(_) => (payload.len() as u128, |e| e.min_binary_bytes() as u128),
    };
    for element in header.elements.iter().filter(|e| !e.properties.is_empty()) {
        let each = cost(element).max(1);
        let needed = element.count as u128 * each;
        if needed > room {
            let fits = (room / each) as usize;
            let what = format!("{} elements", quoted(&element.name));
            return Err(truncated(fits, element.count, &what));
        }
        room -= needed;
    }
    Ok(())
}

/// Number of lines in `bytes`, the last one counted even without a line break.
fn count_lines(bytes: &[u8]) -> usize {
    let breaks = bytes.iter().filter(|&&b| b == b'\n').count();
    breaks + usize::from(bytes.last().is_some_and(|&b| b != b'\n'))
}

/// Write the header of a binary little-endian PLY file: `ply`, the format, one
/// `comment` line per comment, each element with its properties, and
/// `end_header`.
pub(crate) fn write_header(
    w: &mut impl Write,
    comments: &[impl AsRef<str>],
    elements: &[Element],
) -> io::Result<()> {
    writeln!(w, "ply")?;
    writeln!(w, "format binary_little_endian 1.0")?;
    for comment in comments {
        writeln!(w, "comment {}", comment.as_ref())?;
    }
    for element in elements {
        writeln!(w, "element {} {}", element.name, element.count)?;
        for property in &element.properties {
            match property.kind {
                PropertyType::Scalar(scalar) => {
                    writeln!(w, "property {} {}", scalar.name(), property.name)?
                }
                PropertyType::List { count, item } => writeln!(
                    w,
                    "property list {} {} {}",
                    count.name(),
                    item.name(),
                    property.name
                )?,
            }
        }
    }
    writeln!(w, "end_header")
}
