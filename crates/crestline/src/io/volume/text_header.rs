//! The text headers of NRRD and MetaImage files: lines of `key <separator> value`
//! fields, and the data files they may name.

use std::path::{Path, PathBuf};
use std::str::FromStr;

use super::{file, DataLayout, Skip};
use crate::{Error, Result};

/// One line of a text header.
pub(super) struct Line<'a> {
    /// The line without its line break.
    pub text: &'a str,
    /// Its 1-based number.
    pub number: usize,
    /// The offset of the byte after its line break.
    pub end: usize,
}

/// The lines of `bytes`, lazily (a caller stops where binary data begins); a line
/// that is not UTF-8 text is an error.
pub(super) fn lines(bytes: &[u8]) -> impl Iterator<Item = Result<Line<'_>>> {
    let mut pos = 0;
    let mut number = 0;
    std::iter::from_fn(move || {
        let rest = bytes.get(pos..).filter(|rest| !rest.is_empty())?;
        let (raw, consumed) = match rest.iter().position(|&b| b == b'\n') {
            Some(end) => (&rest[..end], end + 1),
            None => (rest, rest.len()),
        };
        pos += consumed;
        number += 1;
        let raw = raw.strip_suffix(b"\r").unwrap_or(raw);
        Some(
            std::str::from_utf8(raw)
                .map(|text| Line {
                    text,
                    number,
                    end: pos,
                })
                .map_err(|_| {
                    Error::Parse(format!(
                        "line {number}: not text (binary data before the end of the header?)"
                    ))
                }),
        )
    })
}

/// One field of a text header.
pub(super) struct Field<'a> {
    /// The field's name as written.
    pub key: &'a str,
    /// Its value, trimmed.
    pub value: &'a str,
    /// The line it is on.
    pub line: usize,
}

impl Field<'_> {
    /// An error about this field, naming it and its line.
    pub fn error(&self, message: impl std::fmt::Display) -> Error {
        Error::Parse(format!(
            "line {}: field '{}': {message}",
            self.line, self.key
        ))
    }

    /// Exactly `count` numbers in `text` (part of the value), split at the
    /// characters where `separator` is true.
    pub fn numbers<T: FromStr>(
        &self,
        text: &str,
        separator: fn(char) -> bool,
        count: usize,
    ) -> Result<Vec<T>> {
        let tokens: Vec<&str> = text.split(separator).filter(|t| !t.is_empty()).collect();
        if tokens.len() != count {
            return Err(self.error(format!(
                "expected {count} values, found {} in '{text}'",
                tokens.len()
            )));
        }
        tokens
            .iter()
            .map(|token| {
                token
                    .parse()
                    .map_err(|_| self.error(format!("cannot read '{token}' as a number")))
            })
            .collect()
    }

    /// Three whitespace-separated numbers.
    pub fn three<T: FromStr + Copy>(&self) -> Result<[T; 3]> {
        let values = self.numbers(self.value, char::is_whitespace, 3)?;
        Ok([values[0], values[1], values[2]])
    }

    /// A single number.
    pub fn number<T: FromStr + Copy>(&self) -> Result<T> {
        Ok(self.numbers(self.value, char::is_whitespace, 1)?[0])
    }

    /// `True` or `False` (any letter case).
    pub fn boolean(&self) -> Result<bool> {
        match self.value.to_ascii_lowercase().as_str() {
            "true" => Ok(true),
            "false" => Ok(false),
            _ => Err(self.error(format!("expected True or False, found '{}'", self.value))),
        }
    }
}

/// The fields of a header, looked up by name in any letter case.
pub(super) struct Fields<'a>(pub Vec<Field<'a>>);

impl Fields<'_> {
    /// The first field called one of `names`, if any.
    pub fn get(&self, names: &[&str]) -> Option<&Field<'_>> {
        self.0.iter().find(|field| {
            names
                .iter()
                .any(|name| field.key.eq_ignore_ascii_case(name))
        })
    }

    /// The field called `names[0]` (or one of its aliases), or an error saying it
    /// is missing.
    pub fn require(&self, names: &[&str]) -> Result<&Field<'_>> {
        self.get(names)
            .ok_or_else(|| Error::Parse(format!("missing field '{}'", names[0])))
    }

    /// Where the samples start, from the byte count of the field `names` (`byte
    /// skip`, `HeaderSize`): -1 means at the end of the data, no field at the start.
    pub fn skip(&self, names: &[&str]) -> Result<Skip> {
        let Some(field) = self.get(names) else {
            return Ok(Skip::Bytes(0));
        };
        match field.number::<i64>()? {
            -1 => Ok(Skip::ToEnd),
            skip => u64::try_from(skip)
                .map(Skip::Bytes)
                .map_err(|_| field.error("must be -1 or at least 0")),
        }
    }
}

/// The samples stored in the data file named by `field` of the header
/// `header_path` (relative names are relative to the header's folder).
pub(super) fn read_detached(
    header_path: &Path,
    field: &Field<'_>,
    layout: &DataLayout,
) -> Result<Vec<f32>> {
    let data_path = detached_path(header_path, field.value);
    let bytes = file::read(&data_path).map_err(|e| {
        let reason = match e {
            Error::File { message, .. } => message,
            other => other.to_string(),
        };
        field.error(format!(
            "data file {} cannot be read: {reason}",
            data_path.display()
        ))
    })?;
    layout.read(&bytes).map_err(|e| match e {
        Error::Parse(message) => {
            Error::Parse(format!("data file {}: {message}", data_path.display()))
        }
        other => other,
    })
}

/// The path of a data file named `name` in the header at `header_path`.
pub(super) fn detached_path(header_path: &Path, name: &str) -> PathBuf {
    header_path
        .parent()
        .map_or_else(|| PathBuf::from(name), |folder| folder.join(name))
}
