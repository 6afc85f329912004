//! Line drawings: feature lines and silhouettes of a mesh with hidden lines
//! removed, as SVG and optionally PNG.

use crestline::draw::{
    draw as draw_lines, render_png, svg_document, Camera, DrawOptions, Projection, Style, View,
};
use numpy::PyReadonlyArray2;
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::arrays::mesh_of;
use crate::errors::raised;
use crate::lines::{feature_lines, LineParts};

/// The functions of this module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(draw, m)?)?;
    Ok(())
}

/// The SVG drawing of `lines` on the mesh seen from `azimuth` and `elevation`
/// (degrees) on a `width` × `height` canvas, with the silhouettes if asked for,
/// and its PNG rendering if `png`.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
fn draw<'py>(
    py: Python<'py>,
    vertices: PyReadonlyArray2<'py, f64>,
    faces: PyReadonlyArray2<'py, i64>,
    lines: Vec<LineParts<'py>>,
    azimuth: f64,
    elevation: f64,
    width: u32,
    height: u32,
    silhouettes: bool,
    png: bool,
) -> PyResult<(String, Option<Bound<'py, PyBytes>>)> {
    let mesh = mesh_of(vertices.as_array(), faces.as_array())?;
    let lines = feature_lines(lines)?;
    let options = DrawOptions {
        silhouettes,
        ..DrawOptions::default()
    };
    let (svg, image) = py
        .detach(|| -> crestline::Result<(String, Option<Vec<u8>>)> {
            let view = View::Orbit { azimuth, elevation };
            let camera = Camera::framing(
                mesh.positions(),
                view,
                Projection::Orthographic,
                width,
                height,
            )?;
            let drawing = draw_lines(&mesh, &lines, &camera, &options)?;
            let svg = svg_document(&drawing, &Style::default());
            let image = png.then(|| render_png(&svg)).transpose()?;
            Ok((svg, image))
        })
        .map_err(raised)?;
    Ok((svg, image.map(|bytes| PyBytes::new(py, &bytes))))
}
