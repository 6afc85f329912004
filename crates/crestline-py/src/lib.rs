//! Python bindings of crestline: the extension module `crestline._crestline`.
//! The package `crestline` (in `python/`) wraps these functions, checks their
//! arguments (shapes, dtypes, finite values, index ranges) with errors that name
//! the argument, and documents them; here the arrays arrive contiguous, float64
//! vertices and int64 faces with indices in range.

mod arrays;
mod built_mesh;
mod compare;
mod draw;
mod errors;
mod jobs;
mod lines;
mod mesh;
mod progress;
mod transfer;
mod view;
mod volume;

use pyo3::prelude::*;

/// The extension module.
#[pymodule]
fn _crestline(m: &Bound<'_, PyModule>) -> PyResult<()> {
    mesh::register(m)?;
    draw::register(m)?;
    view::register(m)?;
    volume::register(m)?;
    jobs::register(m)?;
    compare::register(m)?;
    transfer::register(m)?;
    m.add_function(wrap_pyfunction!(lines::line_kinds, m)?)?;
    m.add_function(wrap_pyfunction!(lines::write_lines, m)?)?;
    m.add_function(wrap_pyfunction!(lines::write_line_labels, m)?)?;
    m.add_function(wrap_pyfunction!(arrays::write_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(arrays::read_vertex_values, m)?)?;
    m.add_function(wrap_pyfunction!(arrays::write_vertex_values, m)?)?;
    Ok(())
}
