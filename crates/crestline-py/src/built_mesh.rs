//! A mesh built once from numpy arrays and passed to every job, so that several
//! jobs on one mesh (curvature, ridges, Morse lines, drawings) check its arrays
//! and build its half-edge structure once.

use crestline::jobs::Surface;
use numpy::PyReadonlyArray2;
use pyo3::prelude::*;

use crate::arrays::mesh_of;

/// The half-edge mesh of a vertex and a face array that need no renumbering
/// repairs ([`mesh_of`]), immutable; the package's `crestline.Mesh` holds one.
#[pyclass(frozen, module = "crestline._crestline", name = "Mesh")]
pub struct BuiltMesh {
    surface: Surface,
}

#[pymethods]
impl BuiltMesh {
    #[new]
    fn new(
        py: Python<'_>,
        vertices: PyReadonlyArray2<f64>,
        faces: PyReadonlyArray2<i64>,
    ) -> PyResult<Self> {
        let (vertices, faces) = (vertices.as_array(), faces.as_array());
        let mesh = py.detach(|| mesh_of(vertices, faces))?;
        Ok(BuiltMesh {
            surface: Surface::of_mesh(mesh),
        })
    }

    /// The mean length of the mesh's edges, each counted once (the length scale
    /// of the jobs' defaults).
    fn mean_edge_length(&self) -> f64 {
        self.surface.mesh.mean_edge_length()
    }
}

impl BuiltMesh {
    /// The mesh, as a surface whose curvature the jobs estimate by the estimator
    /// their options name.
    pub fn surface(&self) -> &Surface {
        &self.surface
    }
}
