//! The indexed triangle list that readers produce and [`crate::mesh::Mesh`] is built from.

use crate::space::VolumeGeometry;
use crate::{Point, Space};

/// A named per-vertex scalar, e.g. a PLY vertex property such as `quality` or a
/// user's indicator field.
#[derive(Clone, Debug, PartialEq)]
pub struct ScalarProperty {
    /// The property name.
    pub name: String,
    /// One value per vertex.
    pub values: Vec<f64>,
}

/// Positions and triangles exactly as a file states them: nothing welded, oriented
/// or checked. Polygons with more than three corners are fanned into triangles by
/// the readers. Indices are in range (readers check that).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleSoup {
    /// Vertex positions.
    pub positions: Vec<Point>,
    /// Triangles as three vertex indices each.
    pub triangles: Vec<[u32; 3]>,
    /// Per-vertex scalars carried along through construction (same length as `positions`).
    pub vertex_scalars: Vec<ScalarProperty>,
    /// The anatomical frame of the positions, if known: a surface of an image has
    /// the image's, a file that declares one (3D Slicer's `SPACE=` mark) has that.
    pub space: Option<Space>,
    /// The image a FreeSurfer surface was made from (its file's footer), kept to
    /// write the surface and its labels back in the file's tkr-RAS coordinates.
    pub volume_geometry: Option<VolumeGeometry>,
}

impl TriangleSoup {
    /// The soup with its positions in `space`: converted from its own frame, or
    /// taken to be in it when it has none.
    pub fn in_space(mut self, space: Space) -> TriangleSoup {
        crate::space::convert_all(self.space, space, &mut self.positions);
        self.space = Some(space);
        self
    }
}
