//! The drawing as an SVG document: one `<g>` per kind of line (its id the
//! [`group_name`]), one `<path>` per visible piece, coordinates in canvas pixels
//! with two decimals, and a `viewBox` of the canvas.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::Path;

use crate::atomic::write_atomically;
use crate::Result;

use super::style::{group_name, KindStyle, Style};
use super::{Drawing, Group, ScreenPath};

/// The smallest and largest factor [`KindStyle::width_by_strength`] applies.
const WIDTH_FACTORS: (f64, f64) = (0.5, 2.0);

/// The SVG text of `drawing` in `style`.
pub fn svg_document(drawing: &Drawing, style: &Style) -> String {
    let (width, height) = (drawing.width, drawing.height);
    let mut svg = String::new();
    svg.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(
        svg,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"{width}\" height=\"{height}\" viewBox=\"0 0 {width} {height}\">"
    );
    let _ = writeln!(svg, "<title>{}</title>", escape(&drawing.source));
    if let Some(background) = &style.background {
        let _ = writeln!(
            svg,
            "<rect id=\"background\" x=\"0\" y=\"0\" width=\"{width}\" height=\"{height}\" fill=\"{background}\"/>"
        );
    }
    for group in &drawing.groups {
        write_group(&mut svg, group, style.kind(group.kind));
    }
    svg.push_str("</svg>\n");
    svg
}

/// One `<g>` with the stroke of its kind and a `<path>` per piece.
fn write_group(svg: &mut String, group: &Group, stroke: &KindStyle) {
    let _ = writeln!(
        svg,
        "<g id=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"{}\" stroke-linecap=\"round\" stroke-linejoin=\"round\">",
        group_name(group.kind),
        stroke.color,
        stroke.width
    );
    let median = median_strength(&group.paths);
    for path in &group.paths {
        svg.push_str("<path d=\"");
        path_data(svg, path);
        svg.push('"');
        if stroke.width_by_strength && median > 0.0 {
            let factor = (path.strength / median).clamp(WIDTH_FACTORS.0, WIDTH_FACTORS.1);
            let _ = write!(svg, " stroke-width=\"{:.2}\"", stroke.width * factor);
        }
        svg.push_str("/>\n");
    }
    svg.push_str("</g>\n");
}

/// `M x y L x y ... [Z]` with two decimals.
fn path_data(svg: &mut String, path: &ScreenPath) {
    for (i, [x, y]) in path.points.iter().enumerate() {
        let command = if i == 0 { 'M' } else { 'L' };
        let _ = write!(svg, "{command}{x:.2} {y:.2}");
    }
    if path.closed {
        svg.push('Z');
    }
}

/// The median strength of the paths (0 without paths or strengths).
fn median_strength(paths: &[ScreenPath]) -> f64 {
    let mut strengths: Vec<f64> = paths.iter().map(|p| p.strength).collect();
    strengths.sort_by(f64::total_cmp);
    strengths.get(strengths.len() / 2).copied().unwrap_or(0.0)
}

/// `text` with the XML special characters escaped.
fn escape(text: &str) -> String {
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

/// Write the SVG text `svg` to `path` (under a temporary name, renamed on success).
pub fn write_svg(path: &Path, svg: &str) -> Result<()> {
    write_atomically(path, |w| w.write_all(svg.as_bytes()))
}
