//! The half-edge triangle mesh every stage works on.
//!
//! A [`Mesh`] is built from a [`TriangleSoup`] by [`Mesh::from_soup`], which repairs
//! what real files contain (duplicate vertices, inconsistent orientation,
//! non-manifold edges and vertices, degenerate, repeated and back-to-back faces, and
//! Möbius-like components, which are cut open into orientable patches) and reports
//! each repair in a [`RepairReport`]; [`Mesh::from_soup_strict`] refuses a component
//! that cannot be oriented instead, and [`Mesh::from_oriented_soup`] keeps every face
//! as given (for surfaces such as isosurfaces, whose orientation carries meaning). The result is always an oriented 2-manifold,
//! possibly with boundary and several components.
//!
//! The repairs renumber vertices; [`Mesh::input_vertices`] keeps, for each vertex of
//! the soup, the mesh vertex it became, and [`Mesh::to_input_order`] takes
//! per-vertex results back to the file's order (FreeSurfer and GIfTI per-vertex
//! files must match their surface vertex for vertex).
//!
//! Storage is a set of plain arrays indexed by u32 ids. Halfedges come in pairs:
//! halfedge `2e` and `2e + 1` are the two sides of edge `e`, so the twin of `h` is
//! `h ^ 1`. A boundary halfedge has no face ([`FaceId::INVALID`]); every boundary
//! vertex's outgoing halfedge is its boundary halfedge.

pub(crate) mod buckets;
mod build;
#[cfg(feature = "generate")]
pub mod generate;
pub(crate) mod geometry;
mod ids;
mod locality;
pub(crate) mod morton;
mod shared_sets;
mod soup;
mod topology;

pub use build::RepairReport;
pub use ids::{EdgeId, FaceId, HalfedgeId, VertexId};
pub use soup::{ScalarProperty, TriangleSoup};
pub use topology::ComponentInfo;

use crate::space::VolumeGeometry;
use crate::{Point, Space};

/// An oriented manifold triangle mesh with halfedge connectivity.
#[derive(Clone, Debug)]
pub struct Mesh {
    positions: Vec<Point>,
    /// One outgoing halfedge per vertex; the boundary one for boundary vertices.
    vertex_halfedge: Vec<HalfedgeId>,
    /// One halfedge per face (the one from corner 0 to corner 1).
    face_halfedge: Vec<HalfedgeId>,
    halfedge_next: Vec<HalfedgeId>,
    halfedge_prev: Vec<HalfedgeId>,
    /// The vertex a halfedge points to.
    halfedge_target: Vec<VertexId>,
    /// The face on a halfedge's left, or [`FaceId::INVALID`] on the boundary.
    halfedge_face: Vec<FaceId>,
    vertex_scalars: Vec<ScalarProperty>,
    /// The anatomical frame of the positions, from the soup ([`TriangleSoup::space`]).
    space: Option<Space>,
    /// The image of a FreeSurfer surface, from the soup
    /// ([`TriangleSoup::volume_geometry`]).
    volume_geometry: Option<VolumeGeometry>,
    /// For each vertex of the soup, the vertex it became (see
    /// [`Mesh::input_vertices`]).
    input_vertices: Vec<Option<VertexId>>,
}

impl Mesh {
    /// The anatomical frame of the positions, if known ([`TriangleSoup::space`]).
    pub fn space(&self) -> Option<Space> {
        self.space
    }

    /// The mesh with its positions declared to be in `space`.
    pub fn with_space(self, space: Option<Space>) -> Mesh {
        Mesh { space, ..self }
    }

    /// The mesh with its positions in `space`: converted from its own frame (a
    /// half turn about z, which keeps the orientation), or taken to be in it when
    /// it has none. The connectivity is the same.
    pub fn in_space(&self, space: Space) -> Mesh {
        let mut moved = self.clone();
        crate::space::convert_all(self.space, space, &mut moved.positions);
        moved.space = Some(space);
        moved
    }

    /// The image a FreeSurfer surface was made from, if the mesh was read from one
    /// with a volume geometry footer ([`TriangleSoup::volume_geometry`]).
    pub fn volume_geometry(&self) -> Option<&VolumeGeometry> {
        self.volume_geometry.as_ref()
    }

    /// For each vertex of the soup the mesh was built from, in the soup's (the
    /// file's) order, the mesh vertex it became: the repairs of
    /// [`Mesh::from_soup`] weld duplicates into one vertex, give a vertex where
    /// several fans of faces meet one copy per fan (the first keeps the input
    /// vertex's place here) and drop unreferenced vertices (`None` here).
    pub fn input_vertices(&self) -> &[Option<VertexId>] {
        &self.input_vertices
    }

    /// `values`, one per mesh vertex, rearranged into one per vertex of the soup
    /// the mesh was built from, in its order ([`Mesh::input_vertices`]):
    /// `missing` for the vertices the repairs dropped. This is how per-vertex
    /// results go back to a file that must match the input surface vertex for
    /// vertex (FreeSurfer curv and label files, GIfTI shape and label files).
    ///
    /// Panics if `values` has fewer values than the mesh has vertices.
    pub fn to_input_order<T: Copy>(&self, values: &[T], missing: T) -> Vec<T> {
        self.input_vertices
            .iter()
            .map(|v| v.map_or(missing, |v| values[v.idx()]))
            .collect()
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    pub fn face_count(&self) -> usize {
        self.face_halfedge.len()
    }

    /// Number of undirected edges.
    pub fn edge_count(&self) -> usize {
        self.halfedge_next.len() / 2
    }

    /// Number of halfedges (twice the edges).
    pub fn halfedge_count(&self) -> usize {
        self.halfedge_next.len()
    }

    /// All vertex positions, indexed by [`VertexId`].
    pub fn positions(&self) -> &[Point] {
        &self.positions
    }

    /// Position of vertex `v`.
    #[inline]
    pub fn position(&self, v: VertexId) -> Point {
        self.positions[v.idx()]
    }

    /// Replace all positions (same count), e.g. after smoothing. Connectivity is kept.
    pub fn set_positions(&mut self, positions: Vec<Point>) -> crate::Result<()> {
        if positions.len() != self.positions.len() {
            return Err(crate::Error::Argument(format!(
                "{} positions given for a mesh with {} vertices",
                positions.len(),
                self.positions.len()
            )));
        }
        self.positions = positions;
        Ok(())
    }

    /// Per-vertex scalars carried over from the input file (e.g. PLY properties).
    pub fn vertex_scalars(&self) -> &[ScalarProperty] {
        &self.vertex_scalars
    }

    /// The per-vertex scalar called `name`, if the input had one.
    pub fn vertex_scalar(&self, name: &str) -> Option<&[f64]> {
        self.vertex_scalars
            .iter()
            .find(|p| p.name == name)
            .map(|p| p.values.as_slice())
    }

    /// Iterate over vertex ids.
    pub fn vertices(&self) -> impl ExactSizeIterator<Item = VertexId> + Clone {
        (0..self.vertex_count() as u32).map(VertexId)
    }

    /// Iterate over face ids.
    pub fn faces(&self) -> impl ExactSizeIterator<Item = FaceId> + Clone {
        (0..self.face_count() as u32).map(FaceId)
    }

    /// Iterate over edge ids.
    pub fn edges(&self) -> impl ExactSizeIterator<Item = EdgeId> + Clone {
        (0..self.edge_count() as u32).map(EdgeId)
    }

    /// The halfedge after `h` around its face (or boundary loop).
    #[inline]
    pub fn next(&self, h: HalfedgeId) -> HalfedgeId {
        self.halfedge_next[h.idx()]
    }

    /// The halfedge before `h` around its face (or boundary loop).
    #[inline]
    pub fn prev(&self, h: HalfedgeId) -> HalfedgeId {
        self.halfedge_prev[h.idx()]
    }

    /// The opposite halfedge of the same edge.
    #[inline]
    pub fn twin(&self, h: HalfedgeId) -> HalfedgeId {
        HalfedgeId(h.0 ^ 1)
    }

    /// The vertex `h` points to.
    #[inline]
    pub fn target(&self, h: HalfedgeId) -> VertexId {
        self.halfedge_target[h.idx()]
    }

    /// The vertex `h` starts from.
    #[inline]
    pub fn source(&self, h: HalfedgeId) -> VertexId {
        self.halfedge_target[h.idx() ^ 1]
    }

    /// The face on the left of `h`, or [`FaceId::INVALID`] for a boundary halfedge.
    #[inline]
    pub fn face(&self, h: HalfedgeId) -> FaceId {
        self.halfedge_face[h.idx()]
    }

    /// Whether `h` lies on the boundary (has no face).
    #[inline]
    pub fn is_boundary_halfedge(&self, h: HalfedgeId) -> bool {
        !self.halfedge_face[h.idx()].is_valid()
    }

    /// The edge `h` belongs to.
    #[inline]
    pub fn edge(&self, h: HalfedgeId) -> EdgeId {
        EdgeId(h.0 >> 1)
    }

    /// One of the two halfedges of `e` (`side` 0 or 1).
    #[inline]
    pub fn edge_halfedge(&self, e: EdgeId, side: u32) -> HalfedgeId {
        HalfedgeId(2 * e.0 + side)
    }

    /// The two end vertices of `e`.
    #[inline]
    pub fn edge_vertices(&self, e: EdgeId) -> [VertexId; 2] {
        let h = self.edge_halfedge(e, 0);
        [self.source(h), self.target(h)]
    }

    /// Whether `e` has a face on one side only.
    #[inline]
    pub fn is_boundary_edge(&self, e: EdgeId) -> bool {
        let h = self.edge_halfedge(e, 0);
        self.is_boundary_halfedge(h) || self.is_boundary_halfedge(self.twin(h))
    }

    /// An outgoing halfedge of `v`: the boundary one if `v` is on the boundary.
    #[inline]
    pub fn vertex_halfedge(&self, v: VertexId) -> HalfedgeId {
        self.vertex_halfedge[v.idx()]
    }

    /// Whether `v` lies on the boundary.
    #[inline]
    pub fn is_boundary_vertex(&self, v: VertexId) -> bool {
        self.is_boundary_halfedge(self.vertex_halfedge(v))
    }

    /// The halfedge from corner 0 to corner 1 of `f`.
    #[inline]
    pub fn face_halfedge(&self, f: FaceId) -> HalfedgeId {
        self.face_halfedge[f.idx()]
    }

    /// The three halfedges of `f`, counter-clockwise.
    #[inline]
    pub fn face_halfedges(&self, f: FaceId) -> [HalfedgeId; 3] {
        let h0 = self.face_halfedge(f);
        let h1 = self.next(h0);
        [h0, h1, self.next(h1)]
    }

    /// The three corners of `f`, counter-clockwise (corner i is the source of
    /// halfedge i of [`Mesh::face_halfedges`]).
    #[inline]
    pub fn face_vertices(&self, f: FaceId) -> [VertexId; 3] {
        let [h0, h1, h2] = self.face_halfedges(f);
        [self.target(h2), self.target(h0), self.target(h1)]
    }

    /// The three corner positions of `f`, counter-clockwise.
    #[inline]
    pub fn face_points(&self, f: FaceId) -> [Point; 3] {
        self.face_vertices(f).map(|v| self.position(v))
    }

    /// The mesh as a soup: its positions, triangles, vertex scalars and frame.
    pub fn to_soup(&self) -> TriangleSoup {
        TriangleSoup {
            positions: self.positions.clone(),
            triangles: self.triangles(),
            vertex_scalars: self.vertex_scalars.clone(),
            space: self.space,
            volume_geometry: self.volume_geometry.clone(),
        }
    }

    /// All triangles as corner index triples (for writers and external code).
    pub fn triangles(&self) -> Vec<[u32; 3]> {
        self.faces()
            .map(|f| self.face_vertices(f).map(|v| v.0))
            .collect()
    }

    /// The outgoing halfedges of `v`, counter-clockwise, starting with
    /// [`Mesh::vertex_halfedge`] (so on the boundary the first is the boundary one).
    pub fn outgoing(&self, v: VertexId) -> impl Iterator<Item = HalfedgeId> + '_ {
        let start = self.vertex_halfedge(v);
        Outgoing {
            mesh: self,
            start,
            current: Some(start),
        }
    }

    /// The neighbours of `v` (targets of its outgoing halfedges), counter-clockwise.
    pub fn neighbors(&self, v: VertexId) -> impl Iterator<Item = VertexId> + '_ {
        self.outgoing(v).map(move |h| self.target(h))
    }

    /// The faces around `v`, counter-clockwise.
    pub fn vertex_faces(&self, v: VertexId) -> impl Iterator<Item = FaceId> + '_ {
        self.outgoing(v)
            .map(move |h| self.face(h))
            .filter(|f| f.is_valid())
    }

    /// Number of edges at `v`.
    pub fn valence(&self, v: VertexId) -> usize {
        self.outgoing(v).count()
    }
}

/// Iterator over the outgoing halfedges of a vertex; see [`Mesh::outgoing`].
pub(crate) struct Outgoing<'a> {
    mesh: &'a Mesh,
    start: HalfedgeId,
    current: Option<HalfedgeId>,
}

impl Iterator for Outgoing<'_> {
    type Item = HalfedgeId;

    fn next(&mut self) -> Option<HalfedgeId> {
        let h = self.current?;
        // Counter-clockwise rotation: the twin of the previous halfedge of h.
        let next = self.mesh.twin(self.mesh.prev(h));
        self.current = (next != self.start).then_some(next);
        Some(h)
    }
}
