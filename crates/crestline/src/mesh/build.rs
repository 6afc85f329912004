//! Building a [`Mesh`] from a [`TriangleSoup`], repairing what real files contain.
//!
//! The steps, in order:
//! 1. reject non-finite coordinates and out-of-range indices;
//! 2. weld vertices with exactly equal positions (STL files repeat every vertex);
//! 3. drop degenerate (zero-area) and repeated faces, and back-to-back pairs (a face
//!    and its reverse on the same three corners: a sheet of zero thickness);
//! 4. pair the faces along each edge; an edge with three or more faces is split so
//!    that at most two faces share each copy;
//! 5. orient every edge-connected component consistently and turn closed components
//!    with negative volume outside-out. A component that cannot be oriented
//!    (Möbius-like) is cut along the edges where its faces still disagree, which
//!    leaves orientable patches ([`Mesh::from_soup_strict`] refuses it instead);
//! 6. split vertices whose faces form several fans (bow-ties, and vertices on a cut)
//!    into one vertex per fan;
//! 7. drop unreferenced vertices and connect the halfedges.
//!
//! Every step takes time linear in the size of the soup (the components' union–find
//! within a logarithmic factor, `mesh/shared_sets.rs`). The bucketing by vertex, the
//! pairing of edges and the components run in parallel; the linking of the
//! halfedges is one sequential pass (filled in parallel from the corners it took
//! longer on two cores: 1.0–1.1 s against 0.72 s on the dragon ×16).
//!
//! Faces are addressed by *corners*: corner `3f + i` is corner `i` of face `f`, and
//! also names the directed edge from corner `i` to corner `i + 1` of that face.

use std::fmt;
use std::sync::atomic::{AtomicU32, Ordering};

use petgraph::unionfind::UnionFind;
use rayon::prelude::*;

use super::buckets::Buckets;
use super::geometry::unit_scale;
use super::shared_sets::SharedSets;
use super::{FaceId, HalfedgeId, Mesh, ScalarProperty, TriangleSoup, VertexId};
use crate::{Error, Point, Result};

/// What [`Mesh::from_soup`] changed to make the input a clean oriented manifold.
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct RepairReport {
    /// Vertices merged into another vertex with exactly the same position.
    pub welded_vertices: usize,
    /// Vertices no face refers to (after dropping faces), removed.
    pub unreferenced_vertices: usize,
    /// Faces with a repeated corner or zero area, removed.
    pub degenerate_faces: usize,
    /// Faces with the same three corners as a face that is kept, removed. Of the
    /// faces on the same corners, one with the orientation most of them have is kept.
    pub duplicate_faces: usize,
    /// Back-to-back pairs removed: a face and its reverse on the same three corners,
    /// e.g. (a, b, c) and (a, c, b). Where the corners appear equally often in both
    /// orientations nothing tells which side is the surface, and every one of those
    /// faces is removed (each pair counted once).
    pub back_to_back_pairs: usize,
    /// Edges shared by three or more faces, split into manifold edges.
    pub non_manifold_edges: usize,
    /// Vertices where several fans of faces met, in the input or after cutting edges
    /// (see `cut_edges`), split into one vertex per fan.
    pub non_manifold_vertices: usize,
    /// Faces whose orientation disagreed with the rest of their component, flipped.
    pub flipped_faces: usize,
    /// Edges cut open (each side becomes a boundary edge) so that a component that
    /// could not be oriented consistently (it was Möbius-like) falls into orientable
    /// patches: the edges across which its faces still disagreed once oriented.
    pub cut_edges: usize,
    /// Closed components with negative signed volume, turned outside-out.
    pub inverted_components: usize,
}

impl RepairReport {
    /// Whether the input needed no repair at all.
    pub fn is_clean(&self) -> bool {
        *self == RepairReport::default()
    }

    /// One human-readable sentence per repair made.
    pub fn messages(&self) -> Vec<String> {
        let items = [
            (self.welded_vertices, "duplicate vertices welded"),
            (self.unreferenced_vertices, "unreferenced vertices dropped"),
            (
                self.degenerate_faces,
                "degenerate (zero-area) faces dropped",
            ),
            (self.duplicate_faces, "repeated faces dropped"),
            (
                self.back_to_back_pairs,
                "back-to-back face pairs dropped (a face and its reverse on the same corners)",
            ),
            (self.non_manifold_edges, "non-manifold edges split"),
            (self.non_manifold_vertices, "non-manifold vertices split"),
            (
                self.flipped_faces,
                "faces re-oriented to agree with their component",
            ),
            (
                self.cut_edges,
                "edges cut open to make non-orientable (Möbius-like) components orientable",
            ),
            (
                self.inverted_components,
                "inside-out closed components re-oriented (negative volume)",
            ),
        ];
        items
            .iter()
            .filter(|(n, _)| *n > 0)
            .map(|(n, what)| format!("{n} {what}"))
            .collect()
    }
}

impl fmt::Display for RepairReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let messages = self.messages();
        if messages.is_empty() {
            write!(f, "no repairs")
        } else {
            write!(f, "{}", messages.join("; "))
        }
    }
}

/// Marker for an unpaired corner (a boundary edge) or an unassigned slot.
const NONE: u32 = u32::MAX;

impl Mesh {
    /// Build a manifold, consistently oriented halfedge mesh from `soup`, repairing
    /// duplicate vertices, degenerate, repeated and back-to-back faces, non-manifold
    /// edges and vertices, and inconsistent or inside-out orientation. A component
    /// that cannot be oriented at all (Möbius-like) is cut open along the edges where
    /// its faces disagree, into orientable patches. Every repair is counted in the
    /// returned [`RepairReport`].
    ///
    /// Errors: a non-finite coordinate or out-of-range index (naming the vertex or
    /// face), or no faces left.
    pub fn from_soup(soup: TriangleSoup) -> Result<(Mesh, RepairReport)> {
        build(soup, Orienting::Repair(Unorientable::Cut))
    }

    /// [`Mesh::from_soup`] for callers who would rather be told than have a surface
    /// cut: a component that cannot be oriented consistently is an error naming it,
    /// instead of being cut open. Every other repair is made as by
    /// [`Mesh::from_soup`].
    pub fn from_soup_strict(soup: TriangleSoup) -> Result<(Mesh, RepairReport)> {
        build(soup, Orienting::Repair(Unorientable::Refuse))
    }

    /// [`Mesh::from_soup`] for soups whose orientation carries meaning and must be
    /// kept, such as isosurfaces, where a closed component of negative volume is a
    /// cavity rather than an inside-out surface: no face is flipped, and faces that
    /// disagree across an edge are an error naming the edge. Every other repair is
    /// made as by [`Mesh::from_soup`].
    pub fn from_oriented_soup(soup: TriangleSoup) -> Result<(Mesh, RepairReport)> {
        build(soup, Orienting::Keep)
    }
}

/// How [`build`] orients the faces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Orienting {
    /// Make neighbours agree and turn closed components of negative volume
    /// outside-out, doing with unorientable components what the value says.
    Repair(Unorientable),
    /// Keep every face as given; neighbours that disagree are an error.
    Keep,
}

/// What to do with a component that cannot be oriented consistently.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Unorientable {
    /// Cut it open along the edges where its faces disagree.
    Cut,
    /// Return an error naming it.
    Refuse,
}

/// The steps of the module documentation, in order.
fn build(soup: TriangleSoup, orienting: Orienting) -> Result<(Mesh, RepairReport)> {
    let TriangleSoup {
        positions,
        triangles,
        vertex_scalars,
        space,
        volume_geometry,
    } = soup;
    validate(&positions, &triangles, &vertex_scalars)?;
    let mut report = RepairReport::default();

    let weld = weld_coincident(&positions);
    report.welded_vertices = positions.len() - weld.distinct;
    let welded: Vec<[u32; 3]> = triangles
        .par_iter()
        .map(|t| t.map(|v| weld.representative[v as usize]))
        .collect();
    // Geometric tests (zero area, signed volume) on a copy scaled by a power of two
    // into the unit frame: exact, and free of overflow and underflow at any scale.
    let factor = unit_scale(&positions);
    let unit: Vec<Point> = positions.par_iter().map(|p| p * factor).collect();
    let mut tris = drop_bad_faces(&unit, positions.len(), welded, &mut report);
    if tris.is_empty() {
        return Err(Error::Mesh(
            "no faces (after dropping degenerate, repeated and back-to-back faces)".into(),
        ));
    }

    let mut partner = pair_edges(&tris, positions.len(), &mut report);
    match orienting {
        Orienting::Repair(unorientable) => {
            orient(&unit, &mut tris, &mut partner, unorientable, &mut report)?
        }
        Orienting::Keep => check_agreement(&tris, &partner)?,
    }
    let mut positions = positions;
    let mut scalars = vertex_scalars;
    split_fans(
        &mut tris,
        &partner,
        &mut positions,
        &mut scalars,
        &mut report,
    );
    let new_index = compact_vertices(&mut tris, &mut positions, &mut scalars);
    report.unreferenced_vertices = weld.distinct - (positions.len() - report.non_manifold_vertices);
    // An input vertex became its representative, which keeps its number through
    // the splitting of fans (the first fan keeps it) until the compaction.
    let input_vertices = weld
        .representative
        .iter()
        .map(|&r| {
            Some(new_index[r as usize])
                .filter(|&v| v != NONE)
                .map(VertexId)
        })
        .collect();

    let mut mesh = connect(positions, &tris, &partner, scalars);
    mesh.space = space;
    mesh.volume_geometry = volume_geometry;
    mesh.input_vertices = input_vertices;
    Ok((mesh, report))
}

/// Reject non-finite coordinates, out-of-range indices and mis-sized properties.
fn validate(positions: &[Point], triangles: &[[u32; 3]], scalars: &[ScalarProperty]) -> Result<()> {
    if positions.len() >= NONE as usize / 2 || triangles.len() >= NONE as usize / 3 {
        return Err(Error::Mesh(format!(
            "too many elements ({} vertices, {} faces)",
            positions.len(),
            triangles.len()
        )));
    }
    if let Some(i) = positions
        .iter()
        .position(|p| !p.iter().all(|c| c.is_finite()))
    {
        let p = positions[i];
        return Err(Error::Mesh(format!(
            "vertex {i} has a non-finite coordinate ({}, {}, {})",
            p.x, p.y, p.z
        )));
    }
    let n = positions.len();
    if let Some((f, t)) = triangles
        .iter()
        .enumerate()
        .find(|(_, t)| t.iter().any(|&v| v as usize >= n))
    {
        return Err(Error::Mesh(format!(
            "face {f} refers to vertex {} but there are only {n} vertices",
            t.iter().max().copied().unwrap_or_default()
        )));
    }
    if let Some(p) = scalars.iter().find(|p| p.values.len() != n) {
        return Err(Error::Mesh(format!(
            "vertex property '{}' has {} values for {n} vertices",
            p.name,
            p.values.len()
        )));
    }
    Ok(())
}

/// The result of welding: each vertex's representative (the first vertex with the
/// same position) and the number of distinct positions.
struct Weld {
    representative: Vec<u32>,
    distinct: usize,
}

/// Find vertices at exactly the same position (`-0.0` equals `0.0`), in linear
/// time: vertices are bucketed by a hash of their coordinates and compared exactly
/// within a bucket. The representative is the lowest-numbered vertex of a position.
fn weld_coincident(positions: &[Point]) -> Weld {
    // Adding 0.0 turns -0.0 into +0.0, so both get the same bits.
    let key = |p: &Point| [p.x + 0.0, p.y + 0.0, p.z + 0.0].map(f64::to_bits);
    let n = positions.len();
    let hashes: Vec<u32> = positions
        .par_iter()
        .map(|p| {
            let [x, y, z] = key(p);
            let mixed =
                (x ^ y.rotate_left(21) ^ z.rotate_left(42)).wrapping_mul(0x9E37_79B9_7F4A_7C15);
            ((mixed >> 32) % n.max(1) as u64) as u32
        })
        .collect();
    let mut representative: Vec<u32> = (0..n as u32).collect();
    let mut distinct = n;
    for bucket in Buckets::new(n, &hashes).iter() {
        for (k, &i) in bucket.iter().enumerate() {
            let same = bucket[..k].iter().find(|&&j| {
                representative[j as usize] == j
                    && key(&positions[j as usize]) == key(&positions[i as usize])
            });
            if let Some(&j) = same {
                representative[i as usize] = j;
                distinct -= 1;
            }
        }
    }
    Weld {
        representative,
        distinct,
    }
}

/// Remove faces with a repeated corner or zero area, then settle the faces that share
/// their three corners with others (see [`settle_same_corners`]).
fn drop_bad_faces(
    positions: &[Point],
    vertex_count: usize,
    tris: Vec<[u32; 3]>,
    report: &mut RepairReport,
) -> Vec<[u32; 3]> {
    let before = tris.len();
    let tris: Vec<[u32; 3]> = tris
        .into_par_iter()
        .filter(|t| !is_degenerate(positions, t))
        .collect();
    report.degenerate_faces = before - tris.len();

    let sorted_key = |f: u32| {
        let mut k = tris[f as usize];
        k.sort_unstable();
        k
    };
    // Faces with the same corners share their lowest corner: compare within buckets.
    let lowest: Vec<u32> = tris.par_iter().map(|t| t[0].min(t[1]).min(t[2])).collect();
    let same_corners = Buckets::new(vertex_count, &lowest).shared(sorted_key);
    if same_corners.iter().next().is_none() {
        return tris;
    }
    let mut keep = vec![true; tris.len()];
    for faces in same_corners.iter() {
        settle_same_corners(&tris, faces.iter().copied(), &mut keep, report);
    }
    tris.par_iter()
        .zip(&keep)
        .filter_map(|(t, &k)| k.then_some(*t))
        .collect()
}

/// Decide which of several faces on the same three corners (given in input order)
/// survive. Faces in opposite orientations cancel in pairs, as a sheet of zero
/// thickness: if both orientations are equally frequent all the faces go (counted as
/// back-to-back pairs); otherwise the first face of the more frequent orientation is
/// kept and the others go (counted as duplicates).
fn settle_same_corners(
    tris: &[[u32; 3]],
    faces: impl Iterator<Item = u32> + Clone,
    keep: &mut [bool],
    report: &mut RepairReport,
) {
    let winds_up = |f: &u32| winds_upwards(&tris[*f as usize]);
    let count = faces.clone().count();
    let upwards = faces.clone().filter(winds_up).count();
    let survivor = match (2 * upwards).cmp(&count) {
        std::cmp::Ordering::Equal => None,
        std::cmp::Ordering::Greater => faces.clone().find(winds_up),
        std::cmp::Ordering::Less => faces.clone().find(|f| !winds_up(f)),
    };
    for f in faces.filter(|&f| Some(f) != survivor) {
        keep[f as usize] = false;
    }
    match survivor {
        None => report.back_to_back_pairs += upwards,
        Some(_) => report.duplicate_faces += count - 1,
    }
}

/// Whether the corners of `t` run through its vertex numbers in increasing cyclic
/// order, (a, b, c) with a < b < c up to rotation; its reverse does not.
fn winds_upwards(t: &[u32; 3]) -> bool {
    let rises = (t[0] < t[1]) as u8 + (t[1] < t[2]) as u8 + (t[2] < t[0]) as u8;
    rises == 2
}

/// A face is degenerate if two corners coincide or its area vanishes relative to
/// its longest edge (collinear corners, up to rounding).
fn is_degenerate(positions: &[Point], t: &[u32; 3]) -> bool {
    if t[0] == t[1] || t[1] == t[2] || t[2] == t[0] {
        return true;
    }
    let [a, b, c] = t.map(|v| positions[v as usize]);
    let (ab, ac, bc) = (b - a, c - a, c - b);
    let longest = ab
        .norm_squared()
        .max(ac.norm_squared())
        .max(bc.norm_squared());
    ab.cross(&ac).norm() <= 8.0 * f64::EPSILON * longest
}

/// Start and end vertex of the directed edge of corner `c`.
#[inline]
fn corner_edge(tris: &[[u32; 3]], c: usize) -> (u32, u32) {
    let t = &tris[c / 3];
    (t[c % 3], t[(c + 1) % 3])
}

/// Pair the corners (directed face edges) that lie on the same undirected edge.
/// `partner[c]` is the corner across the edge, or [`NONE`] on the boundary. Edges
/// with three or more faces are split: faces traversing the edge in opposite
/// directions are paired first, the rest become boundary.
fn pair_edges(tris: &[[u32; 3]], vertex_count: usize, report: &mut RepairReport) -> Vec<u32> {
    let corner_count = tris.len() * 3;
    // Corners on the same edge share the edge's lower vertex: bucket by it, then
    // group each (small) bucket by the upper vertex.
    let lower: Vec<u32> = (0..corner_count)
        .into_par_iter()
        .map(|c| {
            let (a, b) = corner_edge(tris, c);
            a.min(b)
        })
        .collect();
    let upper = |c: u32| {
        let (a, b) = corner_edge(tris, c as usize);
        a.max(b)
    };
    let edges = Buckets::new(vertex_count, &lower).shared(upper);
    let paired: Vec<AtomicU32> = (0..corner_count)
        .into_par_iter()
        .map(|_| AtomicU32::new(NONE))
        .collect();
    // Every corner is on one edge: no two edges write the same slot.
    let non_manifold: Vec<&[u32]> = edges
        .par_iter()
        .filter_map(|edge| match *edge {
            [c, d] => {
                paired[c as usize].store(d, Ordering::Relaxed);
                paired[d as usize].store(c, Ordering::Relaxed);
                None
            }
            _ => Some(edge),
        })
        .collect();
    let mut partner: Vec<u32> = paired.into_iter().map(AtomicU32::into_inner).collect();
    report.non_manifold_edges += non_manifold.len();
    for edge in non_manifold {
        pair_non_manifold(tris, edge, &mut partner);
    }
    partner
}

/// Pair the faces around one edge with three or more faces: each face that runs
/// along the edge forwards with one that runs backwards, in input order.
fn pair_non_manifold(tris: &[[u32; 3]], corners: &[u32], partner: &mut [u32]) {
    let (forward, backward): (Vec<u32>, Vec<u32>) = corners.iter().copied().partition(|&c| {
        let (a, b) = corner_edge(tris, c as usize);
        a < b
    });
    for (&c, &d) in forward.iter().zip(&backward) {
        partner[c as usize] = d;
        partner[d as usize] = c;
    }
}

/// Corner `i` of a face becomes corner `FLIPPED_CORNER[i]` when the face's corners
/// 1 and 2 are swapped (the directed edge it names is reversed).
const FLIPPED_CORNER: [usize; 3] = [2, 1, 0];

/// Orient every edge-connected component consistently, keeping the orientation of
/// the majority of its faces, and turn closed components with negative volume
/// outside-out. A component that cannot be oriented is cut open along the edges
/// where its faces still disagree (their corners are unpaired in `partner`), or
/// refused, as `unorientable` says. Flips faces in `tris` and renumbers `partner` to
/// match.
fn orient(
    positions: &[Point],
    tris: &mut [[u32; 3]],
    partner: &mut [u32],
    unorientable: Unorientable,
    report: &mut RepairReport,
) -> Result<()> {
    let flip = if first_disagreement(tris, partner).is_none() {
        outward_flips(tris, partner, positions, report)
    } else {
        let flip = consistent_flips(tris, partner, positions, unorientable, report)?;
        report.cut_edges = cut_disagreeing_edges(tris, partner, &flip);
        flip
    };
    if !flip.iter().any(|&f| f) {
        return Ok(());
    }
    let mut renumbered = vec![NONE; partner.len()];
    let new_corner = |c: usize| {
        let (f, i) = (c / 3, c % 3);
        3 * f + if flip[f] { FLIPPED_CORNER[i] } else { i }
    };
    for (c, &d) in partner.iter().enumerate() {
        if d != NONE {
            renumbered[new_corner(c)] = new_corner(d as usize) as u32;
        }
    }
    partner.copy_from_slice(&renumbered);
    for (t, &f) in tris.iter_mut().zip(&flip) {
        if f {
            t.swap(1, 2);
        }
    }
    Ok(())
}

/// The first corner (directed face edge) that runs along its edge in the same
/// direction as its partner, if any.
fn first_disagreement(tris: &[[u32; 3]], partner: &[u32]) -> Option<usize> {
    (0..partner.len()).into_par_iter().find_first(|&c| {
        let d = partner[c];
        d != NONE && same_direction(tris, c, d as usize)
    })
}

/// An error naming the first edge across which two faces disagree in orientation.
fn check_agreement(tris: &[[u32; 3]], partner: &[u32]) -> Result<()> {
    match first_disagreement(tris, partner) {
        None => Ok(()),
        Some(c) => {
            let (a, b) = corner_edge(tris, c);
            Err(Error::Mesh(format!(
                "faces {} and {} disagree in orientation across the edge from vertex {a} to \
                 vertex {b}",
                c / 3,
                partner[c] / 3
            )))
        }
    }
}

/// The flips for a mesh whose neighbours already agree: only closed components
/// with negative volume are turned outside-out. Components are found with a
/// union-find and volumes summed in face order (cheaper than the search of
/// [`consistent_flips`], which this equals on consistent input).
fn outward_flips(
    tris: &[[u32; 3]],
    partner: &[u32],
    positions: &[Point],
    report: &mut RepairReport,
) -> Vec<bool> {
    let components = SharedSets::new(tris.len());
    partner.par_iter().enumerate().for_each(|(c, &d)| {
        if d != NONE && (c as u32) < d {
            components.union((c / 3) as u32, d / 3);
        }
    });
    let label = components.into_roots();
    let mut closed = vec![true; tris.len()];
    let mut volume = vec![0.0; tris.len()];
    for (f, t) in tris.iter().enumerate() {
        let root = label[f] as usize;
        closed[root] &= partner[3 * f..3 * f + 3].iter().all(|&d| d != NONE);
        let [a, b, c] = t.map(|v| positions[v as usize].coords);
        volume[root] += a.dot(&b.cross(&c));
    }
    let inside_out: Vec<bool> = closed
        .iter()
        .zip(&volume)
        .map(|(&c, &v)| c && v < 0.0)
        .collect();
    report.inverted_components = (0..tris.len())
        .filter(|&f| label[f] as usize == f && inside_out[f])
        .count();
    label
        .iter()
        .map(|&root| inside_out[root as usize])
        .collect()
}

/// Decide which faces to flip: a breadth-first search over each component makes
/// neighbours agree; the component then keeps its majority orientation, unless it
/// is closed and that orientation encloses negative volume. Where the search finds
/// that a component cannot be oriented, it is an error if `unorientable` says so;
/// otherwise the flips are improved locally so that few edges disagree, and
/// [`cut_disagreeing_edges`] cuts the rest.
fn consistent_flips(
    tris: &[[u32; 3]],
    partner: &[u32],
    positions: &[Point],
    unorientable: Unorientable,
    report: &mut RepairReport,
) -> Result<Vec<bool>> {
    let face_count = tris.len();
    let mut flip = vec![false; face_count];
    let mut visited = vec![false; face_count];
    let mut faces = Vec::new();
    let mut component = 0usize;
    for seed in 0..face_count {
        if visited[seed] {
            continue;
        }
        let spread = spread_orientation(tris, partner, seed, &mut flip, &mut visited, &mut faces);
        if spread.disagreement {
            if unorientable == Unorientable::Refuse {
                return Err(Error::Mesh(format!(
                    "component {component} (the faces connected to face {seed}) cannot be \
                     oriented consistently (it is Möbius-like)"
                )));
            }
            reduce_disagreement(tris, partner, &faces, &mut flip);
        }
        // A component that is cut open is no longer closed.
        let closed = spread.closed && !spread.disagreement;
        choose_side(positions, tris, &faces, closed, &mut flip, report);
        component += 1;
    }
    Ok(flip)
}

/// What [`spread_orientation`] found about a component.
struct Spread {
    /// Every edge of the component has two faces.
    closed: bool,
    /// Some paired faces disagree however the faces are flipped (it is Möbius-like).
    disagreement: bool,
}

/// Breadth-first search from `seed` over paired edges, setting `flip` of each face
/// reached so that it agrees with the face it was reached from. `faces` receives the
/// component's faces in the order they were reached.
fn spread_orientation(
    tris: &[[u32; 3]],
    partner: &[u32],
    seed: usize,
    flip: &mut [bool],
    visited: &mut [bool],
    faces: &mut Vec<usize>,
) -> Spread {
    faces.clear();
    faces.push(seed);
    visited[seed] = true;
    let mut spread = Spread {
        closed: true,
        disagreement: false,
    };
    let mut head = 0;
    while let Some(&f) = faces.get(head) {
        head += 1;
        for (c, &d) in partner.iter().enumerate().skip(3 * f).take(3) {
            if d == NONE {
                spread.closed = false;
                continue;
            }
            let g = d as usize / 3;
            // Neighbours must run along the shared edge in opposite directions.
            let want = flip[f] ^ same_direction(tris, c, d as usize);
            if !visited[g] {
                visited[g] = true;
                flip[g] = want;
                faces.push(g);
            } else if flip[g] != want {
                spread.disagreement = true;
            }
        }
    }
    spread
}

/// Whether the paired corners `c` and `d` run along their edge in the same direction
/// (so that one of their faces must be flipped for them to agree).
#[inline]
fn same_direction(tris: &[[u32; 3]], c: usize, d: usize) -> bool {
    corner_edge(tris, c) == corner_edge(tris, d)
}

/// Whether the faces of paired corners `c` and `d`, flipped as `flip` says, still run
/// along their edge in the same direction.
#[inline]
fn disagree(tris: &[[u32; 3]], flip: &[bool], c: usize, d: usize) -> bool {
    same_direction(tris, c, d) ^ (flip[c / 3] != flip[d / 3])
}

/// The number of edges of face `f` across which it disagrees with its neighbour.
fn disagreeing_edges(tris: &[[u32; 3]], partner: &[u32], flip: &[bool], f: usize) -> usize {
    (3 * f..3 * f + 3)
        .filter(|&c| partner[c] != NONE && disagree(tris, flip, c, partner[c] as usize))
        .count()
}

/// Shorten the cut of a component that cannot be oriented: flip each face that
/// disagrees with its neighbours across two or three of its edges, until no face
/// does. Every flip lowers the number of disagreeing edges, so this ends after
/// fewer flips than there are such edges.
fn reduce_disagreement(tris: &[[u32; 3]], partner: &[u32], faces: &[usize], flip: &mut [bool]) {
    let mut pending: Vec<usize> = faces
        .iter()
        .copied()
        .filter(|&f| disagreeing_edges(tris, partner, flip, f) >= 2)
        .collect();
    while let Some(f) = pending.pop() {
        if disagreeing_edges(tris, partner, flip, f) < 2 {
            continue;
        }
        flip[f] = !flip[f];
        let neighbours = partner[3 * f..3 * f + 3].iter().filter(|&&d| d != NONE);
        pending.extend(neighbours.map(|&d| d as usize / 3));
    }
}

/// Keep the majority orientation of a component's `faces` (counting the faces that
/// disagreed with it as flipped), or, for a closed component, the orientation that
/// encloses positive volume.
fn choose_side(
    positions: &[Point],
    tris: &[[u32; 3]],
    faces: &[usize],
    closed: bool,
    flip: &mut [bool],
    report: &mut RepairReport,
) {
    let flipped = faces.iter().filter(|&&f| flip[f]).count();
    let mut invert = 2 * flipped > faces.len();
    report.flipped_faces += flipped.min(faces.len() - flipped);
    if closed && signed_volume(positions, tris, faces, flip) * sign(invert) < 0.0 {
        invert = !invert;
        report.inverted_components += 1;
    }
    if invert {
        for &f in faces {
            flip[f] = !flip[f];
        }
    }
}

/// Unpair the corners whose faces, flipped as `flip` says, still disagree across their
/// edge: the edge becomes a boundary edge on both sides. Returns the number of edges
/// cut.
fn cut_disagreeing_edges(tris: &[[u32; 3]], partner: &mut [u32], flip: &[bool]) -> usize {
    let mut cut = 0;
    for c in 0..partner.len() {
        let d = partner[c];
        if d != NONE && disagree(tris, flip, c, d as usize) {
            partner[c] = NONE;
            partner[d as usize] = NONE;
            cut += 1;
        }
    }
    cut
}

fn sign(negative: bool) -> f64 {
    if negative {
        -1.0
    } else {
        1.0
    }
}

/// Six times the signed volume enclosed by `faces`, each flipped where `flip` says.
fn signed_volume(positions: &[Point], tris: &[[u32; 3]], faces: &[usize], flip: &[bool]) -> f64 {
    faces
        .iter()
        .map(|&f| {
            let [a, b, c] = tris[f].map(|v| positions[v as usize].coords);
            a.dot(&b.cross(&c)) * sign(flip[f])
        })
        .sum()
}

/// Give each fan of faces around a vertex its own vertex: corners at the same vertex
/// belong to one fan when they are linked through paired edges. Extra fans get new
/// vertices (copies of the position and of every per-vertex property).
fn split_fans(
    tris: &mut [[u32; 3]],
    partner: &[u32],
    positions: &mut Vec<Point>,
    scalars: &mut [ScalarProperty],
    report: &mut RepairReport,
) {
    if every_vertex_has_one_fan(tris, partner, positions.len()) {
        return;
    }
    let corner_count = partner.len();
    let mut fans = UnionFind::<u32>::new(corner_count);
    for (c, &d) in partner.iter().enumerate() {
        if d == NONE {
            continue;
        }
        // Edge c runs a -> b and edge d runs b -> a: corner c (at a) meets the
        // corner after d (at a), and the corner after c (at b) meets corner d.
        fans.union(c as u32, next_corner(d as usize) as u32);
        fans.union(next_corner(c) as u32, d);
    }
    let fan_of = fans.into_labeling();
    let mut fan_vertex = vec![NONE; corner_count];
    let mut vertex_taken = vec![false; positions.len()];
    for (c, &fan) in fan_of.iter().enumerate() {
        let (f, i) = (c / 3, c % 3);
        let fan = fan as usize;
        if fan_vertex[fan] == NONE {
            let v = tris[f][i] as usize;
            fan_vertex[fan] = if vertex_taken[v] {
                report.non_manifold_vertices += 1;
                positions.push(positions[v]);
                for p in scalars.iter_mut() {
                    p.values.push(p.values[v]);
                }
                (positions.len() - 1) as u32
            } else {
                vertex_taken[v] = true;
                v as u32
            };
        }
        tris[f][i] = fan_vertex[fan];
    }
}

/// Whether walking around each vertex through paired edges meets all its corners
/// (the usual case, checked in parallel before any splitting is set up).
fn every_vertex_has_one_fan(tris: &[[u32; 3]], partner: &[u32], vertex_count: usize) -> bool {
    let mut first_corner = vec![NONE; vertex_count];
    let mut corners = vec![0u32; vertex_count];
    for (c, &v) in tris.iter().flatten().enumerate() {
        first_corner[v as usize] = c as u32;
        corners[v as usize] += 1;
    }
    (0..vertex_count).into_par_iter().all(|v| {
        let start = first_corner[v];
        start == NONE || fan_size(partner, start as usize, corners[v]) == corners[v]
    })
}

/// The number of corners in the fan of corner `start`, walking both ways around its
/// vertex through paired edges; stops after `limit` corners.
fn fan_size(partner: &[u32], start: usize, limit: u32) -> u32 {
    // Forwards: the edge into the vertex (the previous corner's edge) is paired with
    // an edge out of it, whose corner is the next one around the vertex.
    let mut size = 1;
    let mut c = start;
    loop {
        let d = partner[prev_corner(c)];
        if d == NONE {
            break;
        }
        c = d as usize;
        if c == start || size > limit {
            return size;
        }
        size += 1;
    }
    // Hit the boundary: walk backwards from the start to the other boundary.
    let mut c = start;
    while let Some(d) = Some(partner[c]).filter(|&d| d != NONE) {
        c = next_corner(d as usize);
        size += 1;
        if size > limit {
            break;
        }
    }
    size
}

#[inline]
fn prev_corner(c: usize) -> usize {
    if c.is_multiple_of(3) {
        c + 2
    } else {
        c - 1
    }
}

#[inline]
fn next_corner(c: usize) -> usize {
    if c % 3 == 2 {
        c - 2
    } else {
        c + 1
    }
}

/// Drop vertices no face refers to, keeping the order of the others; returns the
/// new number of each vertex ([`NONE`] for a dropped one).
fn compact_vertices(
    tris: &mut [[u32; 3]],
    positions: &mut Vec<Point>,
    scalars: &mut [ScalarProperty],
) -> Vec<u32> {
    let mut new_index = vec![NONE; positions.len()];
    for t in tris.iter() {
        for &v in t {
            new_index[v as usize] = 0;
        }
    }
    let mut kept = 0u32;
    for slot in new_index.iter_mut() {
        if *slot == 0 {
            *slot = kept;
            kept += 1;
        }
    }
    if kept as usize == positions.len() {
        // Every vertex is used: the numbering stays as it is.
        return new_index;
    }
    let keep = |values: &[f64]| -> Vec<f64> {
        values
            .iter()
            .zip(&new_index)
            .filter_map(|(x, &n)| (n != NONE).then_some(*x))
            .collect()
    };
    for p in scalars.iter_mut() {
        p.values = keep(&p.values);
    }
    *positions = positions
        .iter()
        .zip(&new_index)
        .filter_map(|(x, &n)| (n != NONE).then_some(*x))
        .collect();
    for t in tris.iter_mut() {
        *t = t.map(|v| new_index[v as usize]);
    }
    new_index
}

/// Create the halfedge arrays. Each pair of partner corners becomes one edge; each
/// unpaired corner becomes an edge whose other halfedge is a boundary halfedge.
/// Boundary halfedges are linked into loops through each boundary vertex's unique
/// outgoing boundary halfedge (unique because every vertex has a single fan).
fn connect(
    positions: Vec<Point>,
    tris: &[[u32; 3]],
    partner: &[u32],
    scalars: Vec<ScalarProperty>,
) -> Mesh {
    let corner_count = partner.len();
    let mut corner_halfedge = vec![NONE; corner_count];
    let mut edge_count = 0u32;
    for c in 0..corner_count {
        if corner_halfedge[c] != NONE {
            continue;
        }
        corner_halfedge[c] = 2 * edge_count;
        if partner[c] != NONE {
            corner_halfedge[partner[c] as usize] = 2 * edge_count + 1;
        }
        edge_count += 1;
    }

    let halfedge_count = 2 * edge_count as usize;
    let mut next = vec![HalfedgeId::INVALID; halfedge_count];
    let mut prev = vec![HalfedgeId::INVALID; halfedge_count];
    let mut target = vec![VertexId::INVALID; halfedge_count];
    let mut face = vec![FaceId::INVALID; halfedge_count];
    let mut vertex_halfedge = vec![HalfedgeId::INVALID; positions.len()];
    let mut boundary_out = vec![HalfedgeId::INVALID; positions.len()];
    for c in 0..corner_count {
        let h = HalfedgeId(corner_halfedge[c]);
        let (from, to) = corner_edge(tris, c);
        next[h.idx()] = HalfedgeId(corner_halfedge[next_corner(c)]);
        prev[next[h.idx()].idx()] = h;
        target[h.idx()] = VertexId(to);
        face[h.idx()] = FaceId((c / 3) as u32);
        vertex_halfedge[from as usize] = h;
        if partner[c] == NONE {
            let b = HalfedgeId(h.0 ^ 1);
            target[b.idx()] = VertexId(from);
            boundary_out[to as usize] = b;
        }
    }
    for h in (0..halfedge_count as u32).map(HalfedgeId) {
        if !face[h.idx()].is_valid() {
            let n = boundary_out[target[h.idx()].idx()];
            next[h.idx()] = n;
            prev[n.idx()] = h;
        }
    }
    for (v, b) in boundary_out.iter().enumerate() {
        if b.is_valid() {
            vertex_halfedge[v] = *b;
        }
    }
    let face_halfedge = (0..tris.len())
        .map(|f| HalfedgeId(corner_halfedge[3 * f]))
        .collect();

    Mesh {
        positions,
        vertex_halfedge,
        face_halfedge,
        halfedge_next: next,
        halfedge_prev: prev,
        halfedge_target: target,
        halfedge_face: face,
        vertex_scalars: scalars,
        space: None,
        volume_geometry: None,
        input_vertices: Vec::new(),
    }
}
