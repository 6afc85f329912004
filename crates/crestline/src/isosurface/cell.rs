//! One cell of the grid: which corners are inside, the segments on its six faces
//! (BUILDSEGMENTS, with the asymptotic decider on ambiguous faces) and the oriented
//! polygons they chain into (BUILDCYCLES), after Thirion & Gourdon 1993, §2–3.
//!
//! The polygons depend only on the 8 inside bits of the corners and, on each
//! ambiguous face, whether the decider connects the two inside corners, so they are
//! tabulated once for all 256 × 64 cases ([`CaseTable`]).
//!
//! Corner `c` of a cell is at offset `(c & 1, (c >> 1) & 1, (c >> 2) & 1)` from the
//! cell's lowest corner ([`corner_offset`](crate::volume::grid::corner_offset)).
//! Cell edge `4a + n` runs along axis `a` from corner [`EDGES`]`[4a + n].0`. Face
//! `2a + s` is the face normal to axis `a` on side `s` (0: low, 1: high).

use std::sync::OnceLock;

use crate::volume::grid::in_face_axes;

/// The 12 cell edges as (start corner, axis): the 4 edges along x, then y, then z.
pub(crate) const EDGES: [(usize, usize); 12] = [
    (0, 0),
    (2, 0),
    (4, 0),
    (6, 0),
    (0, 1),
    (1, 1),
    (4, 1),
    (5, 1),
    (0, 2),
    (1, 2),
    (2, 2),
    (3, 2),
];

/// The cell edge between corners `c` and `d`, which differ along exactly one axis.
fn edge_between(c: usize, d: usize) -> usize {
    let axis = (c ^ d).trailing_zeros() as usize;
    let start = c.min(d);
    let found = EDGES[4 * axis..4 * axis + 4]
        .iter()
        .position(|&(corner, _)| corner == start);
    4 * axis + found.expect("corners that differ along one axis bound a cell edge")
}

/// The corner of face `face` at offset `(du, dv)` along the face's two axes
/// `u = a + 1`, `v = a + 2` (mod 3), which make `(u, v, a)` right-handed.
fn face_corner(face: usize, du: usize, dv: usize) -> usize {
    let (axis, side) = (face / 2, face % 2);
    let (u, v) = in_face_axes(axis);
    (side << axis) | (du << u) | (dv << v)
}

/// The corners of face `face` counter-clockwise seen from outside the cell.
fn face_cycle(face: usize) -> [usize; 4] {
    let at = |du, dv| face_corner(face, du, dv);
    if face % 2 == 1 {
        [at(0, 0), at(1, 0), at(1, 1), at(0, 1)]
    } else {
        [at(0, 0), at(0, 1), at(1, 1), at(1, 0)]
    }
}

/// The corners of face `face` in the fixed order `(s00, s10, s11, s01)` of the
/// asymptotic decider. It depends only on the face's position in the grid, so the
/// two cells that share a face read its values in the same order and decide alike.
fn decider_corners(face: usize) -> [usize; 4] {
    let at = |du, dv| face_corner(face, du, dv);
    [at(0, 0), at(1, 0), at(1, 1), at(0, 1)]
}

/// The asymptotic decider (Thirion & Gourdon 1993, equation 1; docs/design/images.md): on an
/// ambiguous face with corner values `(s00, s10, s11, s01)`, the value of the
/// bilinear interpolant at the crossing of its asymptotes,
/// `v̂ = (s00 s11 − s10 s01) / (s00 + s11 − s10 − s01)`, decides: `v̂ ≥ level`
/// connects the two inside corners across the face, otherwise the outside ones.
fn inside_corners_connected([s00, s10, s11, s01]: [f64; 4], level: f64) -> bool {
    let saddle = (s00 * s11 - s10 * s01) / (s00 + s11 - s10 - s01);
    saddle >= level
}

/// Whether face `face` is ambiguous for the inside bits `mask`: its inside corners
/// are the two ends of one diagonal.
fn is_ambiguous(mask: usize, face: usize) -> bool {
    let inside = face_cycle(face).map(|c| (mask >> c) & 1);
    inside[0] == inside[2] && inside[1] == inside[3] && inside[0] != inside[1]
}

/// The decider's choice on each ambiguous face (bits of `ambiguous`) of a cell
/// whose corners have the sample values `values`: bit `f` set where face `f` joins
/// its inside corners.
pub(crate) fn decide_faces(ambiguous: u8, values: &[f64; 8], level: f64) -> u8 {
    (0..6)
        .filter(|&face| (ambiguous >> face) & 1 == 1)
        .filter(|&face| inside_corners_connected(decider_corners(face).map(|c| values[c]), level))
        .fold(0, |bits, face| bits | (1 << face))
}

/// How far a crossing stays from the ends of its edge, as a fraction of the edge:
/// where `f = I` at a corner, the crossings of its edges would otherwise coincide.
const END_GAP: f64 = 1e-4;

/// Where the linear interpolation from `a` (fraction 0) to `b` (fraction 1) crosses
/// `level`, kept [`END_GAP`] away from the ends (the paper's ε shift).
pub(crate) fn crossing_fraction(a: f64, b: f64, level: f64) -> f64 {
    ((level - a) / (b - a)).clamp(END_GAP, 1.0 - END_GAP)
}

/// No segment leaves this cell edge (it has no crossing).
const NO_EDGE: u8 = u8::MAX;

/// BUILDSEGMENTS on face `face`: for each segment, `next[from] = to`, from the
/// crossing on `from` to the crossing on `to`. Walking the face's corners
/// counter-clockwise seen from outside, a segment runs from a crossing entering the
/// inside to one leaving it, so that the inside corners lie on its right seen from
/// outside: the polygons then wind counter-clockwise seen from the region f < I.
/// On an ambiguous face, `connected` says whether the inside corners are joined.
fn face_segments(mask: usize, face: usize, connected: bool, next: &mut [u8; 12]) {
    let cycle = face_cycle(face);
    let inside = |k: usize| (mask >> cycle[k % 4]) & 1 == 1;
    let side_edge = |k: usize| edge_between(cycle[k % 4], cycle[(k + 1) % 4]) as u8;
    let entering = |k: usize| !inside(k) && inside(k + 1);
    let leaving = |k: usize| inside(k) && !inside(k + 1);
    for k in (0..4).filter(|&k| entering(k)) {
        let to = if is_ambiguous(mask, face) {
            // The next side (k + 1) cuts off inside corner k + 1; the previous one
            // (k − 1) cuts off outside corner k and joins the inside corners.
            if connected {
                k + 3
            } else {
                k + 1
            }
        } else {
            (k + 1..k + 4)
                .find(|&m| leaving(m))
                .expect("a face entered once is left once")
        };
        next[side_edge(k) as usize] = side_edge(to);
    }
}

/// The oriented polygons of one cell case, as cell edges in order, one polygon
/// after the other.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Polygons {
    edges: [u8; 12],
    lengths: [u8; 4],
    count: u8,
    /// Triangles and barycentres of the triangulation (see [`Polygons::push`]).
    triangles: u8,
    centres: u8,
}

impl Polygons {
    /// The cell edges of each polygon, in order (at least 3 each).
    pub(crate) fn iter(&self) -> impl Iterator<Item = &[u8]> + '_ {
        let mut start = 0;
        self.lengths[..self.count as usize].iter().map(move |&n| {
            let polygon = &self.edges[start..start + n as usize];
            start += n as usize;
            polygon
        })
    }

    /// The number of triangles: one per triangle, `n` for a polygon of `n > 3`
    /// corners, fanned around its barycentre.
    pub(super) fn triangle_count(&self) -> usize {
        self.triangles as usize
    }

    /// The number of polygons of more than three corners (each gets a barycentre).
    pub(super) fn centre_count(&self) -> usize {
        self.centres as usize
    }

    fn push(&mut self, polygon: &[u8]) {
        let fanned = is_fanned(polygon.len());
        self.triangles += if fanned { polygon.len() as u8 } else { 1 };
        self.centres += u8::from(fanned);
        let start: usize = self.lengths[..self.count as usize]
            .iter()
            .map(|&n| n as usize)
            .sum();
        self.edges[start..start + polygon.len()].copy_from_slice(polygon);
        self.lengths[self.count as usize] = polygon.len() as u8;
        self.count += 1;
    }
}

/// Whether a polygon of `n` corners is fanned around its barycentre (`n > 3`)
/// rather than kept as one triangle.
pub(crate) fn is_fanned(n: usize) -> bool {
    n > 3
}

/// The triangles of a polygon with corners `ids`, wound as the polygon: the
/// polygon itself if it is a triangle, otherwise the fan around `centre`, the
/// vertex at its barycentre (ignored for a triangle).
pub(crate) fn triangulate(ids: &[u32], centre: u32) -> impl Iterator<Item = [u32; 3]> + '_ {
    let (n, fanned) = (ids.len(), is_fanned(ids.len()));
    (0..if fanned { n } else { 1 }).map(move |k| {
        if fanned {
            [centre, ids[k], ids[(k + 1) % n]]
        } else {
            [ids[0], ids[1], ids[2]]
        }
    })
}

/// BUILDCYCLES: the segments of all six faces chained into closed oriented
/// polygons. Every crossing has one segment leaving it (on the face where it is
/// entered walking counter-clockwise) and one arriving (on the other face of its
/// edge), so the chains close. Each polygon starts at its lowest cell edge.
/// `connected` has bit `f` set where ambiguous face `f` joins its inside corners.
fn build_cycles(mask: usize, connected: u8) -> Polygons {
    let mut next = [NO_EDGE; 12];
    for face in 0..6 {
        face_segments(mask, face, (connected >> face) & 1 == 1, &mut next);
    }
    let mut polygons = Polygons::default();
    let mut seen = [false; 12];
    for first in 0..12 {
        if seen[first] || next[first] == NO_EDGE {
            continue;
        }
        let mut polygon = Vec::with_capacity(12);
        let mut edge = first;
        while !seen[edge] {
            seen[edge] = true;
            polygon.push(edge as u8);
            edge = next[edge] as usize;
        }
        polygons.push(&polygon);
    }
    polygons
}

/// The polygons of every cell case, and the ambiguous faces of every corner mask.
pub(crate) struct CaseTable {
    ambiguous: [u8; 256],
    polygons: Vec<Polygons>,
}

impl CaseTable {
    /// The table, built on first use.
    pub(crate) fn get() -> &'static CaseTable {
        static TABLE: OnceLock<CaseTable> = OnceLock::new();
        TABLE.get_or_init(CaseTable::build)
    }

    fn build() -> CaseTable {
        let ambiguous = std::array::from_fn(|mask| {
            (0..6)
                .filter(|&face| is_ambiguous(mask, face))
                .fold(0, |bits, face| bits | (1 << face))
        });
        let polygons = (0..256 * 64)
            .map(|case| build_cycles(case / 64, (case % 64) as u8))
            .collect();
        CaseTable {
            ambiguous,
            polygons,
        }
    }

    /// The ambiguous faces of a cell whose inside corners are the bits of `mask`,
    /// as bits `1 << face`.
    pub(crate) fn ambiguous_faces(&self, mask: u8) -> u8 {
        self.ambiguous[mask as usize]
    }

    /// The polygons of a cell with inside bits `mask` whose ambiguous faces join
    /// their inside corners where `connected` has their bit set.
    pub(crate) fn polygons(&self, mask: u8, connected: u8) -> &Polygons {
        &self.polygons[mask as usize * 64 + connected as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::volume::grid::corner_offset;

    fn corner_point(c: usize) -> [f64; 3] {
        corner_offset(c).map(|x| x as f64)
    }

    fn edge_midpoint(e: u8) -> [f64; 3] {
        let (corner, axis) = EDGES[e as usize];
        let mut p = corner_point(corner);
        p[axis] += 0.5;
        p
    }

    /// The crossing edges of `mask`: edges whose two corners differ.
    fn crossing_edges(mask: usize) -> Vec<u8> {
        (0..12u8)
            .filter(|&e| {
                let (c, axis) = EDGES[e as usize];
                (mask >> c) & 1 != (mask >> (c | (1 << axis))) & 1
            })
            .collect()
    }

    #[test]
    fn edges_join_corners_one_axis_apart() {
        for (e, &(c, axis)) in EDGES.iter().enumerate() {
            assert_eq!(c & (1 << axis), 0);
            assert_eq!(edge_between(c, c | (1 << axis)), e);
        }
    }

    /// (b − a) × (c − a).
    fn triangle_normal(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> crate::Vector {
        let [a, b, c] = [a, b, c].map(crate::Vector::from);
        (b - a).cross(&(c - a))
    }

    #[test]
    fn face_cycles_run_counter_clockwise_seen_from_outside() {
        for face in 0..6 {
            let [a, b, c, _] = face_cycle(face).map(corner_point);
            let normal = triangle_normal(a, b, c);
            let (axis, side) = (face / 2, face % 2);
            let outward = if side == 1 { 1.0 } else { -1.0 };
            assert_eq!(normal[axis], outward, "face {face}");
        }
    }

    #[test]
    fn every_case_uses_each_crossing_once_in_closed_polygons() {
        let table = CaseTable::get();
        for mask in 0..256usize {
            for connected in 0..64u8 {
                let polygons = table.polygons(mask as u8, connected);
                let mut used: Vec<u8> = polygons.iter().flatten().copied().collect();
                used.sort_unstable();
                assert_eq!(used, crossing_edges(mask), "mask {mask:08b}");
                assert!(polygons.iter().all(|p| (3..=12).contains(&p.len())));
                assert!(polygons.count <= 4);
            }
        }
    }

    #[test]
    fn a_single_inside_corner_is_cut_off_facing_away_from_it() {
        let table = CaseTable::get();
        for corner in 0..8 {
            let polygons: Vec<&[u8]> = table.polygons(1 << corner, 0).iter().collect();
            assert_eq!(polygons.len(), 1);
            let [a, b, c] = [0, 1, 2].map(|k| edge_midpoint(polygons[0][k]));
            let normal = triangle_normal(a, b, c);
            // The normal points from the inside corner toward the cell centre.
            let p = corner_point(corner);
            let to_centre: f64 = (0..3).map(|i| normal[i] * (0.5 - p[i])).sum();
            assert!(to_centre > 0.0, "corner {corner}: {normal:?}");
        }
    }

    #[test]
    fn the_decider_bit_joins_or_separates_the_inside_corners() {
        // Corners 0 and 3 inside: the bottom face (z = 0, face 4) is ambiguous.
        let table = CaseTable::get();
        let mask = 0b0000_1001;
        assert_eq!(table.ambiguous_faces(mask), 1 << 4);
        let apart: Vec<usize> = table.polygons(mask, 0).iter().map(<[u8]>::len).collect();
        assert_eq!(apart, [3, 3]);
        let joined: Vec<usize> = table
            .polygons(mask, 1 << 4)
            .iter()
            .map(<[u8]>::len)
            .collect();
        assert_eq!(joined, [6]);
    }

    #[test]
    fn complementary_cases_give_the_same_polygons_reversed() {
        // Swapping inside and outside (and so the decider's choice) reverses every
        // segment: the polygons are the same cycles run backwards.
        let table = CaseTable::get();
        let canonical = |polygons: &Polygons, reverse: bool| {
            let mut cycles: Vec<Vec<u8>> = polygons
                .iter()
                .map(|p| {
                    let mut cycle = p.to_vec();
                    if reverse {
                        cycle.reverse();
                    }
                    let lowest = (0..cycle.len()).min_by_key(|&i| cycle[i]).unwrap();
                    cycle.rotate_left(lowest);
                    cycle
                })
                .collect();
            cycles.sort();
            cycles
        };
        for mask in 0..256usize {
            let ambiguous = table.ambiguous_faces(mask as u8);
            for connected in 0..64u8 {
                let connected = connected & ambiguous;
                let flipped = !connected & ambiguous;
                let a = table.polygons(mask as u8, connected);
                let b = table.polygons(!mask as u8, flipped);
                assert_eq!(canonical(a, false), canonical(b, true), "mask {mask:08b}");
            }
        }
    }

    #[test]
    fn the_decider_is_symmetric_in_the_diagonals() {
        let values = [3.0, -1.0, 2.0, -2.0];
        let level = 0.5;
        let saddle: f64 = (3.0 * 2.0 - (-1.0 * -2.0)) / (3.0 + 2.0 + 1.0 + 2.0);
        assert_eq!(inside_corners_connected(values, level), saddle >= level);
        let [s00, s10, s11, s01] = values;
        assert_eq!(
            inside_corners_connected([s10, s11, s01, s00], level),
            inside_corners_connected(values, level)
        );
    }
}
