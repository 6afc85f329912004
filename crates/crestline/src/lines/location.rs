//! Where a point of a feature line lies on the surface it was found on.

use serde::{Deserialize, Serialize};

use crate::mesh::{EdgeId, FaceId, Mesh, VertexId};
use crate::Point;

/// A point on a triangle mesh, by the element it lies on. Serialized without a tag,
/// e.g. `{"edge": 12, "t": 0.25}`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged, deny_unknown_fields)]
pub enum SurfaceLocation {
    /// At a vertex.
    Vertex {
        /// The vertex id.
        vertex: u32,
    },
    /// On an edge, at parameter `t` from its first to its second vertex
    /// ([`Mesh::edge_vertices`]).
    Edge {
        /// The edge id.
        edge: u32,
        /// The parameter along the edge, in [0, 1].
        t: f64,
    },
    /// Inside a face, with barycentric weights of its corners in the order of
    /// [`Mesh::face_vertices`].
    Face {
        /// The face id.
        face: u32,
        /// The weights of the three corners, summing to 1.
        barycentric: [f64; 3],
    },
}

impl SurfaceLocation {
    /// Why the location cannot be on `mesh`, if it cannot: its element is beyond
    /// the mesh's (lines traced on another mesh), e.g. `edge 12, but the mesh has
    /// 10 edges`.
    pub fn missing_on(&self, mesh: &Mesh) -> Option<String> {
        let (what, id, count) = match *self {
            SurfaceLocation::Vertex { vertex } => ("vertex", vertex, mesh.vertex_count()),
            SurfaceLocation::Edge { edge, .. } => ("edge", edge, mesh.edge_count()),
            SurfaceLocation::Face { face, .. } => ("face", face, mesh.face_count()),
        };
        ((id as usize) >= count).then(|| format!("{what} {id}, but the mesh has {count}"))
    }

    /// The vertices the location interpolates, with their weights.
    pub fn weights(&self, mesh: &Mesh) -> Vec<(VertexId, f64)> {
        match *self {
            SurfaceLocation::Vertex { vertex } => vec![(VertexId(vertex), 1.0)],
            SurfaceLocation::Edge { edge, t } => {
                let [a, b] = mesh.edge_vertices(EdgeId(edge));
                vec![(a, 1.0 - t), (b, t)]
            }
            SurfaceLocation::Face { face, barycentric } => mesh
                .face_vertices(FaceId(face))
                .into_iter()
                .zip(barycentric)
                .collect(),
        }
    }

    /// The position of the location on `mesh`.
    pub fn position(&self, mesh: &Mesh) -> Point {
        let sum: crate::Vector = self
            .weights(mesh)
            .iter()
            .map(|&(v, w)| mesh.position(v).coords * w)
            .sum();
        Point::from(sum)
    }

    /// A per-vertex quantity interpolated linearly at the location.
    pub fn interpolate(&self, mesh: &Mesh, values: &[f64]) -> f64 {
        self.weights(mesh)
            .iter()
            .map(|&(v, w)| values[v.idx()] * w)
            .sum()
    }
}
