//! Forman's discrete gradient of a vertex function as two spanning forests (Sahner
//! et al. 2008, §2.2): a primal forest of vertices and edges whose trees descend to
//! the minima, and a dual forest of triangles and edges whose trees ascend to the
//! maxima. Edges in neither forest are the saddles.
//!
//! Any two edge-disjoint spanning forests give a valid, acyclic gradient. Built by
//! Kruskal's algorithm, the tree paths need not be monotone; here every element is
//! paired with a strictly lower (vertex) or higher (face) neighbour, so every
//! descending 1-cell falls and every ascending 1-cell climbs.

use std::cmp::Ordering;
use std::collections::VecDeque;

use rayon::prelude::*;

use crate::mesh::{EdgeId, FaceId, Mesh, VertexId};

/// Function values on vertices, edges and faces. An edge's value is the mean of its
/// two vertices', a face's the mean of its three, each computed once in a fixed
/// order; ties are broken by element id (simulation of simplicity).
pub struct Keys {
    /// The value per vertex.
    pub vertex: Vec<f64>,
    /// The mean of its two vertices per edge.
    pub edge: Vec<f64>,
    /// The mean of its three vertices per face.
    pub face: Vec<f64>,
}

/// Compare two (value, id) keys: by value, then by id.
#[inline]
pub fn compare(a: (f64, u32), b: (f64, u32)) -> Ordering {
    a.0.total_cmp(&b.0).then(a.1.cmp(&b.1))
}

impl Keys {
    /// The keys of `values` (one per vertex) on `mesh`.
    pub fn new(mesh: &Mesh, values: Vec<f64>) -> Keys {
        let edge = (0..mesh.edge_count() as u32)
            .into_par_iter()
            .map(|e| {
                let [a, b] = mesh.edge_vertices(EdgeId(e));
                0.5 * (values[a.idx()] + values[b.idx()])
            })
            .collect();
        let face = mesh
            .par_faces()
            .map(|f| {
                let [a, b, c] = mesh.face_vertices(f);
                (values[a.idx()] + values[b.idx()] + values[c.idx()]) / 3.0
            })
            .collect();
        Keys {
            vertex: values,
            edge,
            face,
        }
    }

    /// The (value, id) key of vertex `v`.
    pub fn vertex_key(&self, v: VertexId) -> (f64, u32) {
        (self.vertex[v.idx()], v.0)
    }

    /// The (value, id) key of face `f`.
    pub fn face_key(&self, f: FaceId) -> (f64, u32) {
        (self.face[f.idx()], f.0)
    }
}

/// What an edge is in the gradient.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EdgeRole {
    /// Paired with a vertex: part of the primal (descending) forest.
    Primal,
    /// Paired with a triangle: part of the dual (ascending) forest.
    Dual,
    /// Critical: a saddle.
    Saddle,
}

/// The discrete gradient: both forests, oriented towards their roots.
#[derive(Clone, Debug)]
pub struct Gradient {
    /// What each edge is in the gradient.
    pub edge_role: Vec<EdgeRole>,
    /// The edge from each vertex towards its minimum ([`EdgeId::INVALID`] at minima).
    pub vertex_parent: Vec<EdgeId>,
    /// The edge from each face towards its maximum ([`EdgeId::INVALID`] at maxima).
    pub face_parent: Vec<EdgeId>,
    /// The minimum whose tree holds each vertex.
    pub vertex_root: Vec<VertexId>,
    /// The maximum whose tree holds each face.
    pub face_root: Vec<FaceId>,
    /// The critical vertices.
    pub minima: Vec<VertexId>,
    /// The critical faces.
    pub maxima: Vec<FaceId>,
    /// The critical edges.
    pub saddles: Vec<EdgeId>,
}

impl Gradient {
    /// Build a gradient of `keys` on `mesh` whose 1-cells are monotone. Every vertex
    /// that is not a local minimum is paired with an edge to a lower neighbour, and
    /// every face that is not a local maximum with an edge to a higher neighbour
    /// face, each edge used at most once: a bipartite matching of elements to edges,
    /// found greedily (steepest neighbour first) and completed by augmenting paths.
    /// The pairs form two spanning forests (primal, descending to the minima; dual,
    /// ascending to the maxima) because every parent is strictly lower or higher;
    /// the roots are exactly the local extrema of the data (plus, should an element
    /// find no augmenting path, that element). Edges in neither forest are saddles.
    pub fn new(mesh: &Mesh, keys: &Keys) -> Gradient {
        let mut matching = Matching::new(mesh, keys);
        matching.take_steepest();
        // Every vertex got its steepest option (see `take_steepest`) and augmenting
        // paths keep paired nodes paired: only faces can be left without an edge.
        let vertex_count = mesh.vertex_count() as u32;
        for f in 0..mesh.face_count() as u32 {
            let node = f + vertex_count;
            if !matching.paired(node) {
                matching.augment(node);
            }
        }
        matching.into_gradient()
    }

    /// The gradient with its trees re-hung (the cancellations of §2.1): for each
    /// `(v, edge)` of `vertex_attachments` the primal path from vertex v to its
    /// minimum reversed and v hung on `edge` (whose other end leads to another
    /// tree's root), and likewise the dual paths of `face_attachments` (across
    /// `edge` lies another tree, or the boundary). The two forests are re-hung
    /// side by side; roots, critical cells and edge roles are copied as they are.
    pub fn rehung(
        &self,
        mesh: &Mesh,
        vertex_attachments: &[(u32, EdgeId)],
        face_attachments: &[(u32, EdgeId)],
    ) -> Gradient {
        let (vertex_parent, face_parent) = rayon::join(
            || {
                rehang(&self.vertex_parent, vertex_attachments, |v, e| {
                    Some(vertex_across(mesh, VertexId(v), e).0)
                })
            },
            || {
                rehang(&self.face_parent, face_attachments, |f, e| {
                    let next = face_across(mesh, FaceId(f), e);
                    next.is_valid().then_some(next.0)
                })
            },
        );
        Gradient {
            edge_role: self.edge_role.clone(),
            vertex_parent,
            face_parent,
            vertex_root: self.vertex_root.clone(),
            face_root: self.face_root.clone(),
            minima: self.minima.clone(),
            maxima: self.maxima.clone(),
            saddles: self.saddles.clone(),
        }
    }
}

/// The other end of edge `e` from its end `v`.
pub(super) fn vertex_across(mesh: &Mesh, v: VertexId, e: EdgeId) -> VertexId {
    let [a, b] = mesh.edge_vertices(e);
    if a == v {
        b
    } else {
        a
    }
}

/// The face on the other side of edge `e` from its side `f`
/// ([`FaceId::INVALID`] across the boundary).
pub(super) fn face_across(mesh: &Mesh, f: FaceId, e: EdgeId) -> FaceId {
    let h = mesh.edge_halfedge(e, 0);
    let (g0, g1) = (mesh.face(h), mesh.face(mesh.twin(h)));
    if g0 == f {
        g1
    } else {
        g0
    }
}

/// The forest `parent` (the edge from each node towards its root) with, for
/// each `(start, edge)` of `attachments`, the path from `start` to its root
/// reversed and `start` hung on `edge`. `across(node, e)` is the node across edge
/// `e`, `None` where the path leaves the mesh.
fn rehang(
    parent: &[EdgeId],
    attachments: &[(u32, EdgeId)],
    across: impl Fn(u32, EdgeId) -> Option<u32>,
) -> Vec<EdgeId> {
    let mut parent = parent.to_vec();
    for &(start, edge) in attachments {
        let (mut current, mut incoming) = (start, edge);
        loop {
            let e = parent[current as usize];
            let next = if e.is_valid() {
                across(current, e)
            } else {
                None
            };
            parent[current as usize] = incoming;
            match next {
                Some(next) => (current, incoming) = (next, e),
                None => break,
            }
        }
    }
    parent
}

/// The pairing of elements with edges under construction. Nodes are numbered
/// vertices first, then faces (offset by the vertex count).
struct Matching<'a> {
    mesh: &'a Mesh,
    keys: &'a Keys,
    /// The node each edge is paired with, or `u32::MAX`.
    owner: Vec<u32>,
    /// The edge each node is paired with.
    pair: Vec<EdgeId>,
    /// Per-edge stamp of the augmenting search that last visited it.
    visited: Vec<u32>,
    /// The node from which the current search reached each edge.
    came_from: Vec<u32>,
    stamp: u32,
    /// The buffers of the augmenting searches: nodes to expand, and the options
    /// of the node being expanded.
    queue: VecDeque<u32>,
    options: Vec<((f64, u32), EdgeId)>,
}

const FREE: u32 = u32::MAX;
/// Edges an augmenting search may visit before giving up on a node.
const SEARCH_LIMIT: usize = 20_000;

impl<'a> Matching<'a> {
    fn new(mesh: &'a Mesh, keys: &'a Keys) -> Matching<'a> {
        Matching {
            mesh,
            keys,
            owner: vec![FREE; mesh.edge_count()],
            pair: vec![EdgeId::INVALID; mesh.vertex_count() + mesh.face_count()],
            visited: vec![0; mesh.edge_count()],
            came_from: vec![FREE; mesh.edge_count()],
            stamp: 0,
            queue: VecDeque::new(),
            options: Vec::new(),
        }
    }

    fn paired(&self, node: u32) -> bool {
        self.pair[node as usize].is_valid()
    }

    /// Call `visit(key, edge)` for every edge `node` may pair with, in no order:
    /// for a vertex the edges to lower neighbours (keyed by the neighbour), for a
    /// face the interior edges to higher faces (keyed by the face).
    fn for_each_option(&self, node: u32, mut visit: impl FnMut((f64, u32), EdgeId)) {
        let (mesh, keys) = (self.mesh, self.keys);
        let vertex_count = mesh.vertex_count() as u32;
        if node < vertex_count {
            let v = VertexId(node);
            let own = keys.vertex_key(v);
            for h in mesh.outgoing(v) {
                let key = keys.vertex_key(mesh.target(h));
                if compare(key, own) == Ordering::Less {
                    visit(key, mesh.edge(h));
                }
            }
        } else {
            let f = FaceId(node - vertex_count);
            let own = keys.face_key(f);
            for h in mesh.face_halfedges(f) {
                let g = mesh.face(mesh.twin(h));
                if g.is_valid() && compare(keys.face_key(g), own) == Ordering::Greater {
                    visit(keys.face_key(g), mesh.edge(h));
                }
            }
        }
    }

    /// Option keys of `node` ordered steepest first: lower first for a vertex,
    /// higher first for a face.
    fn steepest_first(&self, node: u32, a: (f64, u32), b: (f64, u32)) -> Ordering {
        if node < self.mesh.vertex_count() as u32 {
            compare(a, b)
        } else {
            compare(b, a)
        }
    }

    fn assign(&mut self, node: u32, e: EdgeId) {
        self.owner[e.idx()] = node;
        self.pair[node as usize] = e;
    }

    /// The steepest option of `node` that `free` accepts, if any (one pass, no
    /// allocation: this runs for every element).
    fn steepest(&self, node: u32, free: impl Fn(EdgeId) -> bool) -> EdgeId {
        let mut best: Option<((f64, u32), EdgeId)> = None;
        self.for_each_option(node, |key, e| {
            let steeper =
                |(b, _): ((f64, u32), EdgeId)| self.steepest_first(node, key, b) == Ordering::Less;
            if free(e) && best.is_none_or(steeper) {
                best = Some((key, e));
            }
        });
        best.map_or(EdgeId::INVALID, |(_, e)| e)
    }

    /// Pair every element with its steepest free option, as if taking the vertices
    /// and then the faces one by one, but in parallel: an edge is an option of at
    /// most one vertex (its upper end) and of at most one face (its lower side), so
    /// every vertex gets its steepest option, and a face's choice depends only on the
    /// edges the vertices took.
    fn take_steepest(&mut self) {
        let vertex_count = self.mesh.vertex_count();
        let mut pair = std::mem::take(&mut self.pair);
        let (vertex_pairs, face_pairs) = pair.split_at_mut(vertex_count);
        vertex_pairs
            .par_iter_mut()
            .enumerate()
            .for_each(|(v, e)| *e = self.steepest(v as u32, |_| true));
        self.own(vertex_pairs, 0);
        face_pairs.par_iter_mut().enumerate().for_each(|(f, e)| {
            *e = self.steepest((vertex_count + f) as u32, |e| self.owner[e.idx()] == FREE);
        });
        self.own(face_pairs, vertex_count);
        self.pair = pair;
    }

    /// Record the nodes `first`, `first + 1`, … as the owners of their edges `pairs`.
    fn own(&mut self, pairs: &[EdgeId], first: usize) {
        for (i, e) in pairs.iter().enumerate() {
            if e.is_valid() {
                self.owner[e.idx()] = (first + i) as u32;
            }
        }
    }

    /// Breadth-first search for an augmenting path from the unpaired `start`: a
    /// chain of paired nodes each of which can move to another eligible edge, ending
    /// at a free edge. Shifts the pairs along it; returns whether one was found.
    fn augment(&mut self, start: u32) -> bool {
        self.stamp += 1;
        // The search buffers are kept between searches.
        let mut queue = std::mem::take(&mut self.queue);
        let mut options = std::mem::take(&mut self.options);
        queue.clear();
        queue.push_back(start);
        let found = self.search(start, &mut queue, &mut options);
        self.queue = queue;
        self.options = options;
        found
    }

    /// The search of [`Self::augment`] from `start`, expanding the nodes of `queue`
    /// in turn, each node's options (gathered in `options`) steepest first.
    fn search(
        &mut self,
        start: u32,
        queue: &mut VecDeque<u32>,
        options: &mut Vec<((f64, u32), EdgeId)>,
    ) -> bool {
        let mut explored = 0;
        while let Some(node) = queue.pop_front() {
            options.clear();
            self.for_each_option(node, |key, e| options.push((key, e)));
            options.sort_by(|a, b| self.steepest_first(node, a.0, b.0));
            for &(_, e) in options.iter() {
                if self.visited[e.idx()] == self.stamp {
                    continue;
                }
                self.visited[e.idx()] = self.stamp;
                self.came_from[e.idx()] = node;
                explored += 1;
                match self.owner[e.idx()] {
                    FREE => {
                        self.shift(start, node, e);
                        return true;
                    }
                    other => queue.push_back(other),
                }
                if explored > SEARCH_LIMIT {
                    return false;
                }
            }
        }
        false
    }

    /// Give `e` to `node`, whose old edge goes to the node that reached it, and so
    /// on back to `start`.
    fn shift(&mut self, start: u32, mut node: u32, mut e: EdgeId) {
        loop {
            let old = self.pair[node as usize];
            self.assign(node, e);
            if node == start {
                return;
            }
            e = old;
            node = self.came_from[old.idx()];
        }
    }

    /// The forests the pairs define, with root labels. Elements left unpaired
    /// (local extrema, or no augmenting path) are the roots.
    fn into_gradient(self) -> Gradient {
        let (mesh, vertex_count) = (self.mesh, self.mesh.vertex_count());
        let edge_role: Vec<EdgeRole> = self
            .owner
            .par_iter()
            .map(|&node| match node {
                FREE => EdgeRole::Saddle,
                node if (node as usize) < vertex_count => EdgeRole::Primal,
                _ => EdgeRole::Dual,
            })
            .collect();
        let mut vertex_parent = self.pair;
        let face_parent = vertex_parent.split_off(vertex_count);
        let (vertex_root, face_root) = rayon::join(
            || roots_of(&vertex_parent, |v, e| vertex_across(mesh, VertexId(v), e).0),
            || roots_of(&face_parent, |f, e| face_across(mesh, FaceId(f), e).0),
        );
        let unpaired = |parent: &[EdgeId]| -> Vec<u32> {
            (0..parent.len() as u32)
                .filter(|&i| !parent[i as usize].is_valid())
                .collect()
        };
        Gradient {
            minima: unpaired(&vertex_parent).into_iter().map(VertexId).collect(),
            maxima: unpaired(&face_parent).into_iter().map(FaceId).collect(),
            saddles: mesh
                .edges()
                .filter(|e| edge_role[e.idx()] == EdgeRole::Saddle)
                .collect(),
            edge_role,
            vertex_parent,
            face_parent,
            vertex_root: vertex_root.into_iter().map(VertexId).collect(),
            face_root: face_root.into_iter().map(FaceId).collect(),
        }
    }
}

/// The root of every node of a forest given by parent edges (`step(node, edge)` is
/// the node across `edge`), following each path once with memoisation.
fn roots_of(parent: &[EdgeId], step: impl Fn(u32, EdgeId) -> u32) -> Vec<u32> {
    let n = parent.len();
    let mut root = vec![FREE; n];
    let mut path = Vec::new();
    for start in 0..n as u32 {
        let mut node = start;
        while root[node as usize] == FREE && parent[node as usize].is_valid() {
            path.push(node);
            node = step(node, parent[node as usize]);
        }
        let top = if root[node as usize] == FREE {
            node
        } else {
            root[node as usize]
        };
        root[node as usize] = top;
        for p in path.drain(..) {
            root[p as usize] = top;
        }
    }
    root
}

/// Faces whose key is above every edge-adjacent face's.
#[cfg(test)]
pub fn local_maximum_faces(mesh: &Mesh, keys: &Keys) -> Vec<bool> {
    mesh.par_faces()
        .map(|f| {
            mesh.face_halfedges(f).iter().all(|&h| {
                let g = mesh.face(mesh.twin(h));
                !g.is_valid() || compare(keys.face_key(f), keys.face_key(g)) == Ordering::Greater
            })
        })
        .collect()
}

/// Vertices whose key is below every neighbour's.
#[cfg(test)]
pub fn local_minimum_vertices(mesh: &Mesh, keys: &Keys) -> Vec<bool> {
    mesh.par_vertices()
        .map(|v| {
            mesh.neighbors(v)
                .all(|w| compare(keys.vertex_key(v), keys.vertex_key(w)) == Ordering::Less)
        })
        .collect()
}
