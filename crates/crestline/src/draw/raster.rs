//! PNG previews of SVG drawings, rendered with resvg.

use std::io::Write as _;
use std::path::Path;

use resvg::{tiny_skia, usvg};

use crate::atomic::write_atomically;
use crate::{Error, Result};

/// Render the SVG text `svg` at its own size into PNG bytes. Errors are
/// [`Error::Parse`]: invalid SVG, an image too large to allocate.
pub fn render_png(svg: &str) -> Result<Vec<u8>> {
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
    resvg::render(
        &tree,
        tiny_skia::Transform::identity(),
        &mut pixmap.as_mut(),
    );
    pixmap
        .encode_png()
        .map_err(|e| Error::Parse(format!("cannot encode the PNG: {e}")))
}

/// Render `svg` and write it as a PNG file at `path` (under a temporary name,
/// renamed on success).
pub fn write_png(path: &Path, svg: &str) -> Result<()> {
    let bytes = render_png(svg).map_err(|e| e.in_file(path))?;
    write_atomically(path, |w| w.write_all(&bytes))
}
