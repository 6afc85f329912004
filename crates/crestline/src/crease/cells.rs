//! The polygons of one cell (Schultz, Theisel and Seidel 2010, §4.5): the segments
//! of its six faces, closed by pairing the degenerate points of those faces, chained
//! into cycles.

use std::collections::HashMap;

use super::edge_index::EdgeIndex;
use super::faces::face_segments;
use super::points::Points;
use crate::volume::grid::Grid;
use crate::{Point, Vector};

/// The crossings, the faces' degenerate points and the grid a cell is built from.
pub(crate) struct CellInput<'a> {
    pub grid: Grid,
    pub index: &'a EdgeIndex,
    pub points: &'a Points,
    /// Face key → the id of its degenerate point.
    pub degenerate: &'a HashMap<u64, usize>,
}

/// The closed polygons of the cell with lowest corner `cell`: the segments of its
/// six faces, the degenerate points paired ([`pair_degenerate_points`]), chained by
/// their shared points. Chains that do not close are dropped.
pub(crate) fn cell_polygons(cell: [usize; 3], input: &CellInput) -> Vec<Vec<usize>> {
    fn link(p: usize, q: usize, neighbours: &mut HashMap<usize, Vec<usize>>) {
        neighbours.entry(p).or_default().push(q);
        neighbours.entry(q).or_default().push(p);
    }
    let mut neighbours: HashMap<usize, Vec<usize>> = HashMap::new();
    let mut inner = Vec::new();
    for axis in 0..3 {
        for side in 0..2 {
            let mut low = cell;
            low[axis] += side;
            let around = input.index.around_face(&input.grid, low, axis);
            let degenerate = input.degenerate.get(&input.grid.key(low, axis)).copied();
            inner.extend(degenerate);
            for [p, q] in face_segments(&around, degenerate, axis, input.points) {
                link(p, q, &mut neighbours);
            }
        }
    }
    inner.sort_unstable();
    for [p, q] in pair_degenerate_points(&inner, &neighbours, input.points) {
        link(p, q, &mut neighbours);
    }
    cycles(&neighbours)
}

/// The pairing of a cell's degenerate points that joins them into the cell's
/// polygons: among the perfect matchings whose quads (neighbour, degenerate point,
/// degenerate point, neighbour) do not intersect each other, the one minimising
/// Σ |(q − p)·n_p| + |(q − p)·n_q|; the cheapest of all if every matching has
/// intersecting quads. A neighbour is the point a degenerate point is paired with
/// on its face. An odd count leaves the last point unpaired.
pub(crate) fn pair_degenerate_points(
    ids: &[usize],
    neighbours: &HashMap<usize, Vec<usize>>,
    points: &Points,
) -> Vec<[usize; 2]> {
    let even = &ids[..ids.len() - ids.len() % 2];
    match even {
        [] => return Vec::new(),
        &[p, q] => return vec![[p, q]],
        _ => {}
    }
    let neighbour = |d: usize| {
        neighbours
            .get(&d)
            .and_then(|n| n.first().copied())
            .unwrap_or(d)
    };
    let quad = |[p, q]: [usize; 2]| [neighbour(p), p, q, neighbour(q)].map(|i| points.position[i]);
    let cost = |m: &[[usize; 2]]| -> f64 {
        m.iter()
            .map(|&[p, q]| {
                let d = points.position[q] - points.position[p];
                d.dot(&points.normal[p]).abs() + d.dot(&points.normal[q]).abs()
            })
            .sum()
    };
    let mut best: Option<(bool, f64, Vec<[usize; 2]>)> = None;
    for matching in perfect_matchings(even) {
        let quads: Vec<[Point; 4]> = matching.iter().map(|&pair| quad(pair)).collect();
        let clear = quads
            .iter()
            .enumerate()
            .all(|(a, qa)| quads[a + 1..].iter().all(|qb| !quads_intersect(qa, qb)));
        let total = cost(&matching);
        let better = match &best {
            None => true,
            Some((was_clear, was_cost, _)) => (clear, -total) > (*was_clear, -*was_cost),
        };
        if better {
            best = Some((clear, total, matching));
        }
    }
    best.map(|b| b.2).unwrap_or_default()
}

/// Every perfect matching of `ids` (an even number of them).
fn perfect_matchings(ids: &[usize]) -> Vec<Vec<[usize; 2]>> {
    let Some((&first, rest)) = ids.split_first() else {
        return vec![Vec::new()];
    };
    let mut all = Vec::new();
    for (k, &partner) in rest.iter().enumerate() {
        let others: Vec<usize> = rest[..k].iter().chain(&rest[k + 1..]).copied().collect();
        for mut m in perfect_matchings(&others) {
            m.insert(0, [first, partner]);
            all.push(m);
        }
    }
    all
}

/// Whether two quads, each split into two triangles, intersect away from shared
/// corners: an edge of one passes through the interior of a triangle of the other.
fn quads_intersect(a: &[Point; 4], b: &[Point; 4]) -> bool {
    let triangles = |q: &[Point; 4]| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]];
    let edges = |q: &[Point; 4]| [[q[0], q[1]], [q[1], q[2]], [q[2], q[3]], [q[3], q[0]]];
    let hits = |edges: [[Point; 2]; 4], triangles: [[Point; 3]; 2]| {
        edges
            .iter()
            .any(|e| triangles.iter().any(|t| segment_hits_triangle(e, t)))
    };
    hits(edges(a), triangles(b)) || hits(edges(b), triangles(a))
}

/// Whether the segment crosses the triangle strictly inside both (Möller–Trumbore
/// with open bounds: touching at a corner or along an edge does not count).
fn segment_hits_triangle([p, q]: &[Point; 2], [a, b, c]: &[Point; 3]) -> bool {
    const MARGIN: f64 = 1e-9;
    let direction: Vector = q - p;
    let (e1, e2) = (b - a, c - a);
    let pv = direction.cross(&e2);
    let det = e1.dot(&pv);
    if det.abs() < 1e-14 {
        return false;
    }
    let tv = p - a;
    let u = tv.dot(&pv) / det;
    let qv = tv.cross(&e1);
    let v = direction.dot(&qv) / det;
    let t = e2.dot(&qv) / det;
    u > MARGIN && v > MARGIN && u + v < 1.0 - MARGIN && t > MARGIN && t < 1.0 - MARGIN
}

/// The cycles of a graph whose vertices have degree 2; components with a vertex of
/// another degree are skipped.
fn cycles(neighbours: &HashMap<usize, Vec<usize>>) -> Vec<Vec<usize>> {
    let mut starts: Vec<usize> = neighbours.keys().copied().collect();
    starts.sort_unstable();
    let mut used = std::collections::HashSet::new();
    let mut polygons = Vec::new();
    for start in starts {
        if used.contains(&start) {
            continue;
        }
        if let Some(cycle) = walk(start, neighbours) {
            used.extend(cycle.iter().copied());
            polygons.push(cycle);
        } else {
            used.insert(start);
        }
    }
    polygons
}

/// The cycle through `start` in a graph of degree-2 vertices, or `None` if the
/// walk meets a vertex of another degree.
fn walk(start: usize, neighbours: &HashMap<usize, Vec<usize>>) -> Option<Vec<usize>> {
    let mut cycle = vec![start];
    let (mut previous, mut current) = (start, *neighbours.get(&start)?.first()?);
    while current != start {
        let next = neighbours.get(&current)?;
        if next.len() != 2 || cycle.len() > neighbours.len() {
            return None;
        }
        cycle.push(current);
        let following = if next[0] == previous {
            next[1]
        } else {
            next[0]
        };
        (previous, current) = (current, following);
    }
    (cycle.len() >= 3 && neighbours[&start].len() == 2).then_some(cycle)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn perfect_matchings_of_six_points() {
        let all = perfect_matchings(&[1, 2, 3, 4, 5, 6]);
        assert_eq!(all.len(), 15);
        assert!(all.iter().all(|m| {
            let mut seen: Vec<usize> = m.iter().flatten().copied().collect();
            seen.sort_unstable();
            seen == [1, 2, 3, 4, 5, 6]
        }));
    }

    #[test]
    fn a_segment_through_a_triangle_hits_it_and_one_touching_a_corner_does_not() {
        let t = [
            Point::new(0.0, 0.0, 0.0),
            Point::new(1.0, 0.0, 0.0),
            Point::new(0.0, 1.0, 0.0),
        ];
        let through = [Point::new(0.2, 0.2, -1.0), Point::new(0.2, 0.2, 1.0)];
        let corner = [Point::new(0.0, 0.0, 0.0), Point::new(0.0, 0.0, 1.0)];
        let beside = [Point::new(0.8, 0.8, -1.0), Point::new(0.8, 0.8, 1.0)];
        assert!(segment_hits_triangle(&through, &t));
        assert!(!segment_hits_triangle(&corner, &t));
        assert!(!segment_hits_triangle(&beside, &t));
    }
}
