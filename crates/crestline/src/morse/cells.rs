//! The 1-cells of every saddle, and the integrals the cancellation criterion needs
//! (Sahner et al. 2008, §3.2–3.4).

use rayon::prelude::*;

use crate::mesh::{EdgeId, FaceId, Mesh, VertexId};

use super::gradient::{face_across, vertex_across, Gradient, Keys};

/// The integral of the indicator over a part of the surface or a line, and its
/// measure (area or length): their ratio is the part's mean indicator.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Integral {
    /// ∫ I over the region or line.
    pub integral: f64,
    /// Its area or length.
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
    /// The saddle edge.
    pub edge: EdgeId,
    /// The faces on either side ([`FaceId::INVALID`] on the boundary).
    pub faces: [FaceId; 2],
    /// The two vertices of the edge, where the descending branches start.
    pub vertices: [VertexId; 2],
    /// The measured ascending branches (triangle strips).
    pub ascending: [Integral; 2],
    /// The measured descending branches (vertex paths).
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
        e.is_valid().then(|| (e, vertex_across(mesh, v, e)))
    }

    /// The next face towards the maximum, with the edge crossed; `None` at a
    /// maximum, or where the flow leaves through a boundary edge.
    pub fn face_step(&self, mesh: &Mesh, f: FaceId) -> Option<(EdgeId, FaceId)> {
        let e = self.face_parent[f.idx()];
        if !e.is_valid() {
            return None;
        }
        let next = face_across(mesh, f, e);
        next.is_valid().then_some((e, next))
    }
}

/// Measure every saddle's branches, each restricted to the part uniquely associated
/// with the saddle (paper §3.4, note 2): from the saddle up to the first branching
/// point, the first node that another branch also passes through (the saddle's own
/// other branch included), that node counted. Ascending strips weight each triangle
/// by area(T) f_T; descending paths weight each edge by |e| f_e, with the saddle edge
/// split half to each branch. The result does not depend on the order of the saddles.
pub fn measure_saddles(mesh: &Mesh, keys: &Keys, gradient: &Gradient) -> Vec<Saddle> {
    let sides: Vec<([FaceId; 2], [VertexId; 2])> = gradient
        .saddles
        .iter()
        .map(|&edge| {
            let h = mesh.edge_halfedge(edge, 0);
            (
                [mesh.face(h), mesh.face(mesh.twin(h))],
                mesh.edge_vertices(edge),
            )
        })
        .collect();
    let (face_shared, vertex_shared) = rayon::join(
        || {
            branching_points(
                mesh.face_count(),
                sides
                    .iter()
                    .flat_map(|(faces, _)| faces.iter().filter(|f| f.is_valid()).map(|f| f.0)),
                |f| gradient.face_step(mesh, FaceId(f)).map(|(_, g)| g.0),
            )
        },
        || {
            branching_points(
                mesh.vertex_count(),
                sides
                    .iter()
                    .flat_map(|(_, vertices)| vertices.iter().map(|v| v.0)),
                |v| gradient.vertex_step(mesh, VertexId(v)).map(|(_, w)| w.0),
            )
        },
    );
    gradient
        .saddles
        .par_iter()
        .zip(sides)
        .map(|(&edge, (faces, vertices))| Saddle {
            edge,
            faces,
            vertices,
            ascending: faces.map(|f| ascending_branch(mesh, keys, gradient, f, &face_shared)),
            descending: vertices
                .map(|v| descending_branch(mesh, keys, gradient, edge, v, &vertex_shared)),
        })
        .collect()
}

/// The triangle strip from `start` (none if invalid) up to and including the
/// first branching point in `shared`, each triangle weighted by its area.
fn ascending_branch(
    mesh: &Mesh,
    keys: &Keys,
    gradient: &Gradient,
    start: FaceId,
    shared: &[bool],
) -> Integral {
    let mut branch = Integral::default();
    let mut current = start.is_valid().then_some(start);
    while let Some(f) = current {
        branch.add(mesh.face_area(f), keys.face[f.idx()]);
        if shared[f.idx()] {
            break;
        }
        current = gradient.face_step(mesh, f).map(|(_, g)| g);
    }
    branch
}

/// Half the saddle edge, then the vertex path from `start` down to the first
/// branching point in `shared`, each edge weighted by its length.
fn descending_branch(
    mesh: &Mesh,
    keys: &Keys,
    gradient: &Gradient,
    saddle: EdgeId,
    start: VertexId,
    shared: &[bool],
) -> Integral {
    let mut branch = Integral::default();
    branch.add(0.5 * mesh.edge_length(saddle), keys.edge[saddle.idx()]);
    let mut current = start;
    while !shared[current.idx()] {
        let Some((e, next)) = gradient.vertex_step(mesh, current) else {
            break;
        };
        branch.add(mesh.edge_length(e), keys.edge[e.idx()]);
        current = next;
    }
    branch
}

/// Which of `n` forest nodes are branching points of the paths from `starts` to
/// their roots: the first node of a path that another path also reaches. Each
/// path is walked until it meets a node already walked, which marks that node;
/// the first marked node along any path is then its first branching point.
fn branching_points(
    n: usize,
    starts: impl Iterator<Item = u32>,
    next: impl Fn(u32) -> Option<u32>,
) -> Vec<bool> {
    let mut walked = vec![false; n];
    let mut shared = vec![false; n];
    for start in starts {
        let mut current = Some(start);
        while let Some(node) = current {
            if std::mem::replace(&mut walked[node as usize], true) {
                shared[node as usize] = true;
                break;
            }
            current = next(node);
        }
    }
    shared
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
