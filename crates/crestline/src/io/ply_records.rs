//! Reading PLY records of any layout, ASCII or binary, one value at a time: the
//! general path, for every element the fast binary decoders of
//! [`super::ply_binary`] do not handle. Every list length is checked before its
//! items are read, and no buffer grows beyond the values actually present.

use super::ply_binary::{decode, Endian};
use super::ply_header::{Element, Encoding, PropertyType, ScalarType};
use super::{check_corner_count, line_error, quoted, truncated, Input};
use crate::{Error, Result};

/// Why a value could not be read.
enum Problem {
    /// The file ended first.
    End,
    /// The value is malformed; the message says how.
    Malformed(String),
}

impl From<String> for Problem {
    fn from(message: String) -> Self {
        Problem::Malformed(message)
    }
}

/// Where the values of a record come from.
trait Values {
    /// The next value, of type `t`, of property `property`.
    fn value(&mut self, t: ScalarType, property: &str) -> std::result::Result<f64, Problem>;
}

/// The values of an ASCII record: the tokens of its line.
struct Tokens<'a>(std::str::SplitAsciiWhitespace<'a>);

impl Values for Tokens<'_> {
    fn value(&mut self, t: ScalarType, property: &str) -> std::result::Result<f64, Problem> {
        let token = self
            .0
            .next()
            .ok_or_else(|| format!("the line has no value for property {}", quoted(property)))?;
        Ok(parse_ascii(t, token)?)
    }
}

/// The values of a binary record: the bytes of the input.
struct Bytes<'i, 'a> {
    input: &'i mut Input<'a>,
    endian: Endian,
}

impl Values for Bytes<'_, '_> {
    fn value(&mut self, t: ScalarType, _: &str) -> std::result::Result<f64, Problem> {
        let bytes = self.input.take(t.size()).ok_or(Problem::End)?;
        Ok(decode(t, bytes, self.endian))
    }
}

/// A value of type `t` written as text: an integer in the type's range, or any
/// floating-point number (`nan` and `inf` included, as in the other readers).
fn parse_ascii(t: ScalarType, token: &str) -> std::result::Result<f64, String> {
    match t {
        ScalarType::Float => token.parse::<f32>().map(f64::from).ok(),
        ScalarType::Double => token.parse::<f64>().ok(),
        _ => return parse_ascii_integer(t, token),
    }
    .ok_or_else(|| format!("cannot read {} as a number ({})", quoted(token), t.name()))
}

/// An integer of type `t` written as text.
fn parse_ascii_integer(t: ScalarType, token: &str) -> std::result::Result<f64, String> {
    let (min, max) = t.integer_range();
    match token.parse::<i64>() {
        Ok(value) if (min..=max).contains(&value) => Ok(value as f64),
        _ if is_integer_text(token) => Err(format!(
            "{} is out of range for the type {}",
            quoted(token),
            t.name()
        )),
        _ => Err(format!(
            "cannot read {} as an integer ({})",
            quoted(token),
            t.name()
        )),
    }
}

/// Whether `token` is written as an integer: digits after an optional sign.
fn is_integer_text(token: &str) -> bool {
    let digits = token.strip_prefix(['-', '+']).unwrap_or(token);
    !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit())
}

/// A list length read as `value` (of an integer type).
fn list_length(value: f64) -> std::result::Result<u64, String> {
    if value < 0.0 {
        return Err(format!("a list has the negative length {value}"));
    }
    Ok(value as u64)
}

/// The corner count of a face list read as `value`, checked.
pub(super) fn corner_count(value: f64) -> std::result::Result<usize, String> {
    check_corner_count(list_length(value)?)
}

/// The values of one record that the readers keep.
#[derive(Default)]
pub(super) struct Record {
    /// The scalar properties, in header order.
    pub scalars: Vec<f64>,
    /// The items of the face index list, if the element has one.
    pub corners: Vec<i64>,
}

/// Read one record of `element` into `record`. The items of the list property at
/// `corner_list` (if any) are face corners; other lists are read and dropped.
fn read_record(
    values: &mut impl Values,
    element: &Element,
    corner_list: Option<usize>,
    record: &mut Record,
) -> std::result::Result<(), Problem> {
    record.scalars.clear();
    record.corners.clear();
    for (k, property) in element.properties.iter().enumerate() {
        let name = property.name.as_str();
        match property.kind {
            PropertyType::Scalar(t) => record.scalars.push(values.value(t, name)?),
            PropertyType::List { count, item } if corner_list == Some(k) => {
                let n = corner_count(values.value(count, name)?)?;
                for _ in 0..n {
                    record.corners.push(values.value(item, name)? as i64);
                }
            }
            PropertyType::List { count, item } => {
                // Each item takes at least a byte or a token: the input bounds the loop.
                for _ in 0..list_length(values.value(count, name)?)? {
                    values.value(item, name)?;
                }
            }
        }
    }
    Ok(())
}

/// Read every record of `element`, passing each to `sink`. Errors name the record
/// and where it is: the line (ASCII) or the byte offset (binary).
pub(super) fn read_element(
    input: &mut Input<'_>,
    encoding: Encoding,
    element: &Element,
    corner_list: Option<usize>,
    mut sink: impl FnMut(&Record) -> std::result::Result<(), String>,
) -> Result<()> {
    if element.properties.is_empty() {
        // Records without properties take no room: nothing to read, however
        // large the count.
        return Ok(());
    }
    let mut record = Record::default();
    for i in 0..element.count {
        let offset = input.position();
        let outcome = match encoding {
            Encoding::Ascii => match input.next_line()? {
                Some(line) => read_record(
                    &mut Tokens(line.split_ascii_whitespace()),
                    element,
                    corner_list,
                    &mut record,
                ),
                None => Err(Problem::End),
            },
            Encoding::Binary(endian) => read_record(
                &mut Bytes { input, endian },
                element,
                corner_list,
                &mut record,
            ),
        };
        let result = match outcome {
            Ok(()) => sink(&record),
            Err(Problem::Malformed(message)) => Err(message),
            Err(Problem::End) => {
                let what = format!("{} elements", quoted(&element.name));
                return Err(truncated(i, element.count, &what));
            }
        };
        result.map_err(|message| locate(input, encoding, (element, i), offset, &message))?;
    }
    Ok(())
}

/// An error about record `i` of `element`, which starts at byte `offset`.
fn locate(
    input: &Input<'_>,
    encoding: Encoding,
    (element, i): (&Element, usize),
    offset: usize,
    message: &str,
) -> Error {
    match encoding {
        Encoding::Ascii => line_error(input.line(), format!("{} {i}: {message}", element.name)),
        Encoding::Binary(_) => {
            Error::Parse(format!("{} {i} (byte {offset}): {message}", element.name))
        }
    }
}
