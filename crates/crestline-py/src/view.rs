//! Interactive 3D views: a mesh with its lines as one self-contained HTML page
//! ([`jobs::view`], [`crestline::view::view_html`]).

use crestline::draw::Style;
use crestline::jobs::{self, Surface};
use crestline::view::view_html;
use numpy::PyReadonlyArray2;
use pyo3::prelude::*;

use crate::arrays::mesh_of;
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
#[pyo3(signature = (vertices, faces, lines, options, title, progress=None))]
fn view<'py>(
    py: Python<'py>,
    vertices: PyReadonlyArray2<'py, f64>,
    faces: PyReadonlyArray2<'py, i64>,
    lines: Option<Vec<LineParts<'py>>>,
    options: &str,
    title: &str,
    progress: Option<Py<PyAny>>,
) -> PyResult<String> {
    let surface = Surface::of_mesh(mesh_of(vertices.as_array(), faces.as_array())?);
    let given = lines.map(feature_lines).transpose()?;
    let options: jobs::ViewOptions = job_options("view", options)?;
    let mut observer = Callback::new(progress);
    let html = py.detach(|| -> crestline::Result<String> {
        let (lines, curvature) = jobs::view(&surface, (None, given), &options, &mut observer)?;
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
