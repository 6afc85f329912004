//! Text for the XML formats crestline writes (SVG, HTML, VTK XML, GIfTI, border
//! files).

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
    #[test]
    fn special_and_control_characters_are_escaped() {
        assert_eq!(
            super::escape("a<b & \"c\">\n"),
            "a&lt;b &amp; &quot;c&quot;&gt; "
        );
    }
}
