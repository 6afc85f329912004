//! Line drawings: feature lines and silhouettes of a mesh with hidden lines
//! removed, as SVG and optionally PNG ([`jobs::draw`]).

use crestline::draw::{render_png, Style};
use crestline::jobs;
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::built_mesh::BuiltMesh;
use crate::jobs::job_options;
use crate::lines::{feature_lines, LineParts};
use crate::progress::Callback;

/// The functions of this module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(draw, m)?)?;
    Ok(())
}

/// The SVG drawing of the mesh as the JSON `options` of [`jobs::DrawingOptions`]
/// say, with `lines` drawn instead of those the options choose when given, and
/// its PNG rendering if `png`.
#[pyfunction]
#[pyo3(signature = (mesh, lines, options, png, progress=None))]
fn draw<'py>(
    py: Python<'py>,
    mesh: Bound<'py, BuiltMesh>,
    lines: Option<Vec<LineParts<'py>>>,
    options: &str,
    png: bool,
    progress: Option<Py<PyAny>>,
) -> PyResult<(String, Option<Bound<'py, PyBytes>>)> {
    let surface = mesh.get().surface();
    let given = lines.map(feature_lines).transpose()?;
    let options: jobs::DrawingOptions = job_options("draw", options)?;
    let mut observer = Callback::new(progress);
    let drawn = py.detach(|| -> crestline::Result<(String, Option<Vec<u8>>)> {
        let style = options.style(Style::default())?;
        let drawing = jobs::draw(surface, (None, given), &options, &mut observer)?;
        let svg = drawing.svg(&style);
        let image = png
            .then(|| render_png(&svg, style.background.as_deref()))
            .transpose()?;
        Ok((svg, image))
    });
    let (svg, image) = observer.outcome(drawn)?;
    Ok((svg, image.map(|bytes| PyBytes::new(py, &bytes))))
}
