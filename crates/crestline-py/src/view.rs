//! Interactive 3D views: a mesh with its lines as one self-contained HTML page
//! ([`jobs::view`], [`crestline::view::view_html`]).

use crestline::draw::Style;
use crestline::jobs;
use crestline::view::view_html;
use pyo3::prelude::*;

use crate::built_mesh::BuiltMesh;
use crate::jobs::job_options;
use crate::lines::{feature_lines, LineParts};
use crate::progress::Callback;

/// The functions of this module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(view, m)?)?;
    Ok(())
}

/// The HTML view of the mesh titled `title`, with `lines` shown instead of those
/// the JSON `options` of [`jobs::ViewOptions`] choose when given.
#[pyfunction]
#[pyo3(signature = (mesh, lines, options, title, progress=None))]
fn view<'py>(
    py: Python<'py>,
    mesh: Bound<'py, BuiltMesh>,
    lines: Option<Vec<LineParts<'py>>>,
    options: &str,
    title: &str,
    progress: Option<Py<PyAny>>,
) -> PyResult<String> {
    let surface = mesh.get().surface();
    let given = lines.map(feature_lines).transpose()?;
    let options: jobs::ViewOptions = job_options("view", options)?;
    let mut observer = Callback::new(progress);
    let html = py.detach(|| -> crestline::Result<String> {
        let (lines, curvature) = jobs::view(surface, (None, given), &options, &mut observer)?;
        let style = Style::default();
        Ok(view_html(
            &surface.mesh,
            &lines,
            Some(&curvature),
            &style,
            title,
        ))
    });
    observer.outcome(html)
}
