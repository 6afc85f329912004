//! Global topology: boundary loops, connected components, Euler characteristic, genus.

use rayon::prelude::*;

use super::shared_sets::SharedSets;
use super::{EdgeId, HalfedgeId, Mesh};

/// Counts and topological type of one connected component of a mesh.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct ComponentInfo {
    /// Number of vertices.
    pub vertices: usize,
    /// Number of edges.
    pub edges: usize,
    /// Number of faces.
    pub faces: usize,
    /// Number of closed boundary curves.
    pub boundary_loops: usize,
    /// χ = V − E + F.
    pub euler_characteristic: i64,
    /// g = (2 − χ − b) / 2 for an orientable surface with b boundary loops.
    pub genus: i64,
}

impl Mesh {
    /// The boundary loops, each as its boundary halfedges in order (`next` chains them).
    pub fn boundary_loops(&self) -> Vec<Vec<HalfedgeId>> {
        let mut seen = vec![false; self.halfedge_count()];
        let mut loops = Vec::new();
        for h in (0..self.halfedge_count() as u32).map(HalfedgeId) {
            if seen[h.idx()] || !self.is_boundary_halfedge(h) {
                continue;
            }
            let mut boundary = Vec::new();
            let mut b = h;
            while !seen[b.idx()] {
                seen[b.idx()] = true;
                boundary.push(b);
                b = self.next(b);
            }
            loops.push(boundary);
        }
        loops
    }

    /// The connected component of each vertex, numbered 0.. in order of their lowest vertex.
    pub fn vertex_components(&self) -> (Vec<u32>, usize) {
        let sets = SharedSets::new(self.vertex_count());
        (0..self.edge_count() as u32).into_par_iter().for_each(|e| {
            let [a, b] = self.edge_vertices(EdgeId(e));
            sets.union(a.0, b.0);
        });
        let labels = sets.into_roots();
        let mut number = vec![u32::MAX; self.vertex_count()];
        let mut count = 0u32;
        let component = labels
            .iter()
            .map(|&root| {
                let slot = &mut number[root as usize];
                if *slot == u32::MAX {
                    *slot = count;
                    count += 1;
                }
                *slot
            })
            .collect();
        (component, count as usize)
    }

    /// Counts, Euler characteristic and genus of every connected component.
    pub fn components(&self) -> Vec<ComponentInfo> {
        let (component, count) = self.vertex_components();
        let mut info = vec![
            ComponentInfo {
                vertices: 0,
                edges: 0,
                faces: 0,
                boundary_loops: 0,
                euler_characteristic: 0,
                genus: 0,
            };
            count
        ];
        for v in self.vertices() {
            info[component[v.idx()] as usize].vertices += 1;
        }
        for e in self.edges() {
            info[component[self.edge_vertices(e)[0].idx()] as usize].edges += 1;
        }
        for f in self.faces() {
            info[component[self.face_vertices(f)[0].idx()] as usize].faces += 1;
        }
        for boundary in self.boundary_loops() {
            info[component[self.target(boundary[0]).idx()] as usize].boundary_loops += 1;
        }
        for c in &mut info {
            c.euler_characteristic = c.vertices as i64 - c.edges as i64 + c.faces as i64;
            c.genus = (2 - c.euler_characteristic - c.boundary_loops as i64) / 2;
        }
        info
    }

    /// χ = V − E + F of the whole mesh.
    pub fn euler_characteristic(&self) -> i64 {
        self.vertex_count() as i64 - self.edge_count() as i64 + self.face_count() as i64
    }

    /// Check every connectivity invariant of the halfedge structure; returns the
    /// first violation found. Used by tests and debug builds.
    pub fn check_connectivity(&self) -> Result<(), String> {
        for h in (0..self.halfedge_count() as u32).map(HalfedgeId) {
            let n = self.next(h);
            if self.prev(n) != h {
                return Err(format!("prev(next({h:?})) != {h:?}"));
            }
            if self.source(n) != self.target(h) {
                return Err(format!("{n:?} does not start where {h:?} ends"));
            }
            if self.face(n) != self.face(h) {
                return Err(format!("{h:?} and its next lie in different faces"));
            }
            if self.source(h) == self.target(h) {
                return Err(format!("{h:?} is a loop"));
            }
            if self.is_boundary_halfedge(h) && self.is_boundary_halfedge(self.twin(h)) {
                return Err(format!("edge of {h:?} has no face"));
            }
        }
        for f in self.faces() {
            let [h0, _, h2] = self.face_halfedges(f);
            if self.next(h2) != h0 || self.face(h0) != f {
                return Err(format!("face {f:?} is not a triangle"));
            }
        }
        let mut corners_seen = vec![0usize; self.vertex_count()];
        for f in self.faces() {
            for v in self.face_vertices(f) {
                corners_seen[v.idx()] += 1;
            }
        }
        for v in self.vertices() {
            let h = self.vertex_halfedge(v);
            if self.source(h) != v {
                return Err(format!("vertex {v:?}: its halfedge does not start there"));
            }
            // A single fan: walking around v meets every face at v.
            if self.vertex_faces(v).count() != corners_seen[v.idx()] {
                return Err(format!("vertex {v:?} is not manifold"));
            }
        }
        Ok(())
    }
}
