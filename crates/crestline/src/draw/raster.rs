//! PNG previews of SVG drawings, rendered with resvg.

use std::io::Write as _;
use std::path::Path;

use resvg::{tiny_skia, usvg};

use crate::atomic::write_atomically;
use crate::{Error, Result};

/// Render the SVG text `svg` at its own size into PNG bytes, on `background` (a
/// CSS colour; transparent without one). The drawings' background is the root's
/// CSS `background-color`, which a plotter ignores and the renderer does too, so it
/// is given here. Errors are [`Error::Parse`]: invalid SVG or colour, an image too
/// large to allocate.
pub fn render_png(svg: &str, background: Option<&str>) -> Result<Vec<u8>> {
    let tree = usvg::Tree::from_str(svg, &usvg::Options::default())
        .map_err(|e| Error::Parse(format!("the drawing is not valid SVG: {e}")))?;
    let size = tree.size().to_int_size();
    let mut pixmap = tiny_skia::Pixmap::new(size.width(), size.height()).ok_or_else(|| {
        Error::Parse(format!(
            "cannot allocate a {} x {} image",
            size.width(),
            size.height()
        ))
    })?;
    if let Some(color) = background {
        let color: svgtypes::Color = color
            .parse()
            .map_err(|e| Error::Parse(format!("the background '{color}' is not a colour: {e}")))?;
        let (r, g, b, a) = (color.red, color.green, color.blue, color.alpha);
        pixmap.fill(tiny_skia::Color::from_rgba8(r, g, b, a));
    }
    resvg::render(
        &tree,
        tiny_skia::Transform::identity(),
        &mut pixmap.as_mut(),
    );
    pixmap
        .encode_png()
        .map_err(|e| Error::Parse(format!("cannot encode the PNG: {e}")))
}

/// Render `svg` on `background` ([`render_png`]) and write it as a PNG file at
/// `path` (under a temporary name, renamed on success).
pub fn write_png(path: &Path, svg: &str, background: Option<&str>) -> Result<()> {
    let bytes = render_png(svg, background).map_err(|e| e.in_file(path))?;
    write_atomically(path, |w| w.write_all(&bytes))
}
