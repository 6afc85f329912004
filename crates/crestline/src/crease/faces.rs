//! The pairing of a face's points into segments (Schultz, Theisel and Seidel 2010,
//! §4.5): among the pairings whose segments do not cross (2D line-line test), the
//! one that agrees best with the normals.

use std::sync::OnceLock;

use super::edges::MAX_CROSSINGS_PER_EDGE;
use super::points::Points;
use crate::Vector;

/// The segments of one face: the crossings `around` it (in cyclic order) and its
/// degenerate point `inner`, if any, paired without crossing segments, minimising
/// Σ |(q − p)·n_p| + |(q − p)·n_q| with the normals projected into the face (a
/// degenerate point takes part with the normal computed at it). An odd number of
/// points gives no segment.
pub(crate) fn face_segments(
    around: &[usize],
    inner: Option<usize>,
    axis: usize,
    points: &Points,
) -> Vec<[usize; 2]> {
    if (around.len() + usize::from(inner.is_some())) % 2 == 1 {
        return Vec::new();
    }
    let cost = |pairs: &[[usize; 2]]| -> f64 {
        pairs
            .iter()
            .map(|&[p, q]| pair_cost(p, q, axis, points))
            .sum()
    };
    let Some(centre) = inner else {
        return best_cyclic_matching(around, &cost);
    };
    // The degenerate point pairs with one crossing; the others pair among
    // themselves in cyclic order without crossing that segment.
    let mut best = (f64::INFINITY, Vec::new());
    for (k, &partner) in around.iter().enumerate() {
        let rest: Vec<usize> = around[k + 1..]
            .iter()
            .chain(&around[..k])
            .copied()
            .collect();
        let spoke = [centre, partner].map(|id| points.in_face(id, axis));
        for matching in cyclic_matchings(rest.len()).iter() {
            let mut pairs: Vec<[usize; 2]> =
                matching.iter().map(|&[a, b]| [rest[a], rest[b]]).collect();
            let crosses = pairs.iter().any(|&[p, q]| {
                segments_cross(spoke, [points.in_face(p, axis), points.in_face(q, axis)])
            });
            if crosses {
                continue;
            }
            pairs.push([centre, partner]);
            let total = cost(&pairs);
            if total < best.0 {
                best = (total, pairs);
            }
        }
    }
    best.1
}

/// The cheapest non-crossing perfect matching of the points `around` a face, in
/// cyclic order.
fn best_cyclic_matching(around: &[usize], cost: &dyn Fn(&[[usize; 2]]) -> f64) -> Vec<[usize; 2]> {
    let mut best = (f64::INFINITY, Vec::new());
    for matching in cyclic_matchings(around.len()).iter() {
        let pairs: Vec<[usize; 2]> = matching
            .iter()
            .map(|&[a, b]| [around[a], around[b]])
            .collect();
        let total = cost(&pairs);
        if total < best.0 {
            best = (total, pairs);
        }
    }
    best.1
}

/// |(q − p)·n_p| + |(q − p)·n_q| with the normals projected into the face normal to
/// grid `axis`: how much the segment pq leaves the tangent planes at its ends.
fn pair_cost(p: usize, q: usize, axis: usize, points: &Points) -> f64 {
    let in_face = |n: &Vector| {
        let mut n = *n;
        n[axis] = 0.0;
        n
    };
    let d = points.position[q] - points.position[p];
    d.dot(&in_face(&points.normal[p])).abs() + d.dot(&in_face(&points.normal[q])).abs()
}

/// The largest number of points whose matchings are tabulated: four edges of
/// [`MAX_CROSSINGS_PER_EDGE`] crossings.
const TABULATED: usize = 4 * MAX_CROSSINGS_PER_EDGE;

/// Every perfect matching of `n` points in cyclic order without crossing pairs,
/// tabulated once for up to [`TABULATED`] points.
fn cyclic_matchings(n: usize) -> std::borrow::Cow<'static, [Vec<[usize; 2]>]> {
    static TABLE: OnceLock<Vec<Vec<Vec<[usize; 2]>>>> = OnceLock::new();
    let table = TABLE.get_or_init(|| (0..=TABULATED).map(non_crossing_matchings).collect());
    match table.get(n) {
        Some(all) => std::borrow::Cow::Borrowed(all.as_slice()),
        None => std::borrow::Cow::Owned(non_crossing_matchings(n)),
    }
}

/// Every perfect matching of `n` points in cyclic order without crossing pairs.
pub(crate) fn non_crossing_matchings(n: usize) -> Vec<Vec<[usize; 2]>> {
    fn within(lo: usize, hi: usize) -> Vec<Vec<[usize; 2]>> {
        if lo >= hi {
            return vec![Vec::new()];
        }
        let mut all = Vec::new();
        // `lo` pairs with a point at odd distance, splitting the rest in two.
        for partner in (lo + 1..hi).step_by(2) {
            for inner in within(lo + 1, partner) {
                for outer in within(partner + 1, hi) {
                    let mut m = vec![[lo, partner]];
                    m.extend(inner.iter().copied());
                    m.extend(outer.iter().copied());
                    all.push(m);
                }
            }
        }
        all
    }
    within(0, n)
}

/// Whether the 2D segments `a` and `b` cross at a point interior to both.
pub(crate) fn segments_cross(a: [[f64; 2]; 2], b: [[f64; 2]; 2]) -> bool {
    let orient = |p: [f64; 2], q: [f64; 2], r: [f64; 2]| {
        (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])
    };
    let (a0, a1) = (orient(a[0], a[1], b[0]), orient(a[0], a[1], b[1]));
    let (b0, b1) = (orient(b[0], b[1], a[0]), orient(b[0], b[1], a[1]));
    a0 * a1 < 0.0 && b0 * b1 < 0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn non_crossing_matchings_are_counted_by_catalan_numbers() {
        let counts: Vec<usize> = (0..5)
            .map(|k| non_crossing_matchings(2 * k).len())
            .collect();
        assert_eq!(counts, [1, 1, 2, 5, 14]);
    }

    #[test]
    fn crossing_and_touching_segments() {
        let x = [[0.0, 0.0], [1.0, 1.0]];
        assert!(segments_cross(x, [[0.0, 1.0], [1.0, 0.0]]));
        assert!(!segments_cross(x, [[1.0, 1.0], [2.0, 0.0]]));
        assert!(!segments_cross(x, [[0.0, 0.5], [0.4, 0.9]]));
    }
}
