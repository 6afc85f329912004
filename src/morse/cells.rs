//! The 1-cells of every saddle, and the integrals the cancellation criterion needs
//! (Sahner et al. 2008, §3.2–3.4).

use crate::mesh::{EdgeId, FaceId, Mesh, VertexId};

use super::gradient::{Gradient, Keys};

/// The integral of the indicator over a part of the surface or a line, and its
/// measure (area or length): their ratio is the part's mean indicator.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Integral {
    pub integral: f64,
    pub measure: f64,
}

impl Integral {
    /// ∫ I / measure, the mean indicator (0 for an empty part).
    pub fn mean(&self) -> f64 {
        if self.measure > 0.0 {
            self.integral / self.measure
        } else {
            0.0
        }
    }

    fn add(&mut self, weight: f64, value: f64) {
        self.integral += weight * value;
        self.measure += weight;
    }

    /// The sum of two parts.
    pub fn merged(self, other: Integral) -> Integral {
        Integral {
            integral: self.integral + other.integral,
            measure: self.measure + other.measure,
        }
    }
}

/// A saddle edge with its two ascending branches (triangle strips from the faces
/// beside it up to maxima) and two descending branches (edge paths from its end
/// vertices down to minima), each measured up to its first merge with a branch
/// met before (paper §3.4 note 2). On the boundary the missing face's ascending
/// branch is empty.
#[derive(Clone, Debug)]
pub struct Saddle {
    pub edge: EdgeId,
    /// The faces on either side ([`FaceId::INVALID`] on the boundary).
    pub faces: [FaceId; 2],
    pub vertices: [VertexId; 2],
    pub ascending: [Integral; 2],
    pub descending: [Integral; 2],
}

impl Saddle {
    /// The mean indicator along the whole ascending line r = r₁ ∪ r₂.
    pub fn ascending_mean(&self) -> f64 {
        self.ascending[0].merged(self.ascending[1]).mean()
    }

    /// The mean indicator along the whole descending line v = v₁ ∪ v₂.
    pub fn descending_mean(&self) -> f64 {
        self.descending[0].merged(self.descending[1]).mean()
    }
}

impl Gradient {
    /// The next vertex towards the minimum, with the edge leading there.
    pub fn vertex_step(&self, mesh: &Mesh, v: VertexId) -> Option<(EdgeId, VertexId)> {
        let e = self.vertex_parent[v.idx()];
        e.is_valid().then(|| {
            let [a, b] = mesh.edge_vertices(e);
            (e, if a == v { b } else { a })
        })
    }

    /// The next face towards the maximum, with the edge crossed; `None` at a
    /// maximum, or where the flow leaves through a boundary edge.
    pub fn face_step(&self, mesh: &Mesh, f: FaceId) -> Option<(EdgeId, FaceId)> {
        let e = self.face_parent[f.idx()];
        if !e.is_valid() {
            return None;
        }
        let h = mesh.edge_halfedge(e, 0);
        let (g0, g1) = (mesh.face(h), mesh.face(mesh.twin(h)));
        let next = if g0 == f { g1 } else { g0 };
        next.is_valid().then_some((e, next))
    }
}

/// Measure every saddle's branches, in increasing order of the saddle keys, each
/// branch stopping at the first node an earlier branch claimed (that node counts).
/// Ascending strips weight each triangle by area(T) f_T; descending paths weight
/// each edge by |e| f_e, with the saddle edge split half to each branch.
pub fn measure_saddles(mesh: &Mesh, keys: &Keys, gradient: &Gradient) -> Vec<Saddle> {
    let mut order = gradient.saddles.clone();
    order.sort_by(|&a, &b| super::gradient::compare(keys.edge_key(a), keys.edge_key(b)));
    let mut face_claimed = vec![false; mesh.face_count()];
    let mut vertex_claimed = vec![false; mesh.vertex_count()];
    order
        .into_iter()
        .map(|edge| {
            let h = mesh.edge_halfedge(edge, 0);
            let faces = [mesh.face(h), mesh.face(mesh.twin(h))];
            let vertices = mesh.edge_vertices(edge);
            let ascending = faces.map(|f| {
                let mut branch = Integral::default();
                let mut current = f.is_valid().then_some(f);
                while let Some(f) = current {
                    branch.add(mesh.face_area(f), keys.face[f.idx()]);
                    if std::mem::replace(&mut face_claimed[f.idx()], true) {
                        break;
                    }
                    current = gradient.face_step(mesh, f).map(|(_, g)| g);
                }
                branch
            });
            let half_saddle = 0.5 * mesh.edge_length(edge);
            let descending = vertices.map(|v| {
                let mut branch = Integral::default();
                branch.add(half_saddle, keys.edge[edge.idx()]);
                let mut current = v;
                while !std::mem::replace(&mut vertex_claimed[current.idx()], true) {
                    let Some((e, next)) = gradient.vertex_step(mesh, current) else {
                        break;
                    };
                    branch.add(mesh.edge_length(e), keys.edge[e.idx()]);
                    current = next;
                }
                branch
            });
            Saddle {
                edge,
                faces,
                vertices,
                ascending,
                descending,
            }
        })
        .collect()
}

/// ∫ I and area of the region of every maximum (the faces of its dual tree,
/// weighted by area(T) f_T), indexed by face.
pub fn maximum_regions(mesh: &Mesh, keys: &Keys, gradient: &Gradient) -> Vec<Integral> {
    let mut regions = vec![Integral::default(); mesh.face_count()];
    for f in mesh.faces() {
        regions[gradient.face_root[f.idx()].idx()].add(mesh.face_area(f), keys.face[f.idx()]);
    }
    regions
}

/// ∫ I and area of the region of every minimum (the vertices of its primal tree,
/// weighted by area(star v) / 3 and f_v), indexed by vertex.
pub fn minimum_regions(mesh: &Mesh, keys: &Keys, gradient: &Gradient) -> Vec<Integral> {
    let mass = mesh.vertex_areas();
    let mut regions = vec![Integral::default(); mesh.vertex_count()];
    for v in mesh.vertices() {
        regions[gradient.vertex_root[v.idx()].idx()].add(mass[v.idx()], keys.vertex[v.idx()]);
    }
    regions
}
