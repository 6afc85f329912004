//! Text for the XML formats crestline writes (SVG, HTML, VTK XML, GIfTI, border
//! files), and a check of the XML it reads (GIfTI) before parsing.

/// The most attributes an element of an XML file crestline reads may have. The
/// parser checks each attribute against the element's earlier ones (duplicates
/// are an error in XML), which takes time growing with the square of their
/// number: 200,000 attributes on one element took minutes. GIfTI's elements
/// have a dozen at most.
pub(crate) const MAX_ATTRIBUTES: usize = 1000;

/// An error, naming the line, when an element of the XML `text` has more than
/// [`MAX_ATTRIBUTES`] attributes; a scan linear in the text. Comments, CDATA
/// sections, processing instructions and declarations are skipped; an attribute is
/// counted by its `=` outside quoted values.
pub(crate) fn check_attribute_counts(text: &str) -> Result<(), String> {
    let bytes = text.as_bytes();
    let mut at = 0;
    while let Some(offset) = find_byte(b'<', &bytes[at..]) {
        let start = at + offset;
        let rest = &bytes[start..];
        at = if rest.starts_with(b"<!--") {
            skip_past(bytes, start, b"-->")
        } else if rest.starts_with(b"<![CDATA[") {
            skip_past(bytes, start, b"]]>")
        } else if rest.starts_with(b"<?") {
            skip_past(bytes, start, b"?>")
        } else {
            let (end, count) = tag_attributes(bytes, start + 1);
            if count > MAX_ATTRIBUTES {
                let line = 1 + bytes[..start].iter().filter(|&&b| b == b'\n').count();
                return Err(format!(
                    "line {line}: an element with {count} attributes, more than the \
                     {MAX_ATTRIBUTES} read"
                ));
            }
            end
        };
    }
    Ok(())
}

/// The position of the first `byte` in `bytes`.
fn find_byte(byte: u8, bytes: &[u8]) -> Option<usize> {
    bytes.iter().position(|&b| b == byte)
}

/// The position just past the first `end` at or after `from` (the end of the text
/// when there is none).
fn skip_past(bytes: &[u8], from: usize, end: &[u8]) -> usize {
    bytes[from..]
        .windows(end.len())
        .position(|w| w == end)
        .map_or(bytes.len(), |p| from + p + end.len())
}

/// From `from`, just past the `<` of a tag (or declaration): the position past its
/// closing `>` and the number of `=` outside quoted values in between.
fn tag_attributes(bytes: &[u8], from: usize) -> (usize, usize) {
    let mut quote = None;
    let mut count = 0;
    for (i, &b) in bytes.iter().enumerate().skip(from) {
        match (quote, b) {
            (Some(q), _) if b == q => quote = None,
            (Some(_), _) => {}
            (None, b'"' | b'\'') => quote = Some(b),
            (None, b'=') => count += 1,
            (None, b'>') => return (i + 1, count),
            (None, _) => {}
        }
    }
    (bytes.len(), count)
}

/// `text` with the XML special characters escaped (and control characters made
/// spaces), for element text and attribute values.
pub(crate) fn escape(text: &str) -> String {
    text.chars()
        .map(|c| match c {
            '&' => "&amp;".to_string(),
            '<' => "&lt;".to_string(),
            '>' => "&gt;".to_string(),
            '"' => "&quot;".to_string(),
            c if c.is_control() => " ".to_string(),
            c => c.to_string(),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn elements_with_too_many_attributes_are_found_in_linear_time() {
        let attributes: String = (0..200_000).map(|i| format!(" a{i}=\"{i}\"")).collect();
        let text = format!("<?xml version=\"1.0\"?>\n<!-- <x {attributes} -->\n<G\n{attributes}/>");
        let err = check_attribute_counts(&text).unwrap_err();
        assert_eq!(
            err,
            "line 3: an element with 200000 attributes, more than the 1000 read"
        );
        let fine = "<G a=\"x=y>\" b='1'><![CDATA[<a b=c>]]><D/></G>";
        assert_eq!(check_attribute_counts(fine), Ok(()));
    }

    #[test]
    fn special_and_control_characters_are_escaped() {
        assert_eq!(
            super::escape("a<b & \"c\">\n"),
            "a&lt;b &amp; &quot;c&quot;&gt; "
        );
    }
}
