//! Chaining segments into polylines, and the strength filter of Ohtake, Belyaev and
//! Seidel (2004) as used by Hildebrandt et al. (2005, §4). Generic over the key that
//! names a point (an edge crossing on a mesh, a face centre, a point of a volume
//! cell): segments that share a key are joined.
//!
//! Both [`chain`] (lines on meshes) and [`chain_oriented`] (the bi-iso-lines of the
//! Marching Lines, whose ends carry their positions along with their keys) walk the
//! segment graph the same way: open polylines between nodes whose degree is not
//! two (ends and junctions), from those nodes in key order, then loops in the order
//! of their lowest segment.

use petgraph::unionfind::UnionFind;

use crate::mesh::buckets::Buckets;
use crate::Point;

/// A chained line: its points in order, whether it closes on itself, and the
/// strength of the connected piece it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct Chain<K> {
    /// The keys of the points, in order (a closed chain does not repeat its first).
    pub points: Vec<K>,
    /// Whether the chain is a loop.
    pub closed: bool,
    /// The strength of the connected piece the chain belongs to.
    pub strength: f64,
}

/// A chained line of [`chain_oriented`]: its end points in order and whether it
/// closes on itself.
#[derive(Clone, Debug, PartialEq)]
pub struct OrientedChain<E> {
    /// The points, in order (a closed chain does not repeat its first).
    pub points: Vec<E>,
    /// Whether the chain is a loop.
    pub closed: bool,
}

/// The segments as a graph on their end points, one node per distinct key.
struct Graph<E> {
    /// The end point of each node (the first of those with its key, in the order
    /// of an unstable sort), sorted by key.
    nodes: Vec<E>,
    /// Each segment as a pair of node indices.
    segments: Vec<[u32; 2]>,
    /// The segments at each node.
    incident: Buckets,
}

impl<E: Copy> Graph<E> {
    /// The graph of `segments`, whose end points are joined where `key` is equal.
    fn new<K: Ord>(segments: &[[E; 2]], key: impl Fn(&E) -> K) -> Graph<E> {
        let mut nodes: Vec<E> = segments.iter().flatten().copied().collect();
        nodes.sort_unstable_by_key(&key);
        nodes.dedup_by_key(|e| key(e));
        let index = |e: &E| {
            let found = nodes.binary_search_by_key(&key(e), &key);
            found.map_or(0, |i| i as u32)
        };
        let segments: Vec<[u32; 2]> = segments.iter().map(|s| s.map(|e| index(&e))).collect();
        // Half-segments 2s and 2s + 1 start at the segment's first and second node.
        let starts: Vec<u32> = segments.iter().flatten().copied().collect();
        let incident = Buckets::new(nodes.len(), &starts);
        Graph {
            nodes,
            segments,
            incident,
        }
    }
}

impl<E> Graph<E> {
    /// The number of segments at `node`.
    fn degree(&self, node: u32) -> usize {
        self.incident.get(node as usize).len()
    }

    /// The node where half-segment `half` starts.
    fn start(&self, half: u32) -> u32 {
        self.segments[(half / 2) as usize][(half % 2) as usize]
    }

    /// The node at the other end of half-segment `half` (which starts at a node).
    fn other_end(&self, half: u32) -> u32 {
        self.segments[(half / 2) as usize][(1 - half % 2) as usize]
    }
}

/// One maximal polyline of the segment graph, as walked.
struct Walk<E> {
    /// The end points of its nodes in order (a loop does not repeat its first).
    points: Vec<E>,
    /// Whether it is a loop.
    closed: bool,
    /// The segment it starts with.
    first: usize,
    /// The number of its segments walked from their first end to their second,
    /// minus the number walked the other way.
    forward: i64,
}

/// Chain `segments` into maximal polylines: connected pieces of the segment graph
/// are measured first (strength = ∫ k ds by the trapezoid rule, with `locate`
/// giving each point's position and integrand k), pieces weaker than `threshold`
/// are dropped, and the rest split into polylines between nodes whose degree is not
/// two (ends and junctions); pieces without such nodes are closed loops. Every
/// polyline carries the strength of its piece.
pub fn chain<K: Copy + Ord>(
    segments: &[[K; 2]],
    locate: impl Fn(K) -> (Point, f64),
    threshold: f64,
) -> Vec<Chain<K>> {
    let graph = Graph::new(segments, |&k| k);
    let located: Vec<(Point, f64)> = graph.nodes.iter().map(|&p| locate(p)).collect();
    let (piece_of, strength) = piece_strengths(&graph, &located);
    let strength_of = |segment: usize| strength[piece_of[segment]];
    let kept = |segment: usize| strength_of(segment) >= threshold;
    walks(&graph, kept, |walk| Chain {
        points: walk.points,
        closed: walk.closed,
        strength: strength_of(walk.first),
    })
}

/// Chain directed `segments` (from their first end to their second), whose ends
/// meet where `key` gives them the same key, into maximal polylines as [`chain`]
/// does, without measuring or dropping pieces and without regard to the segments'
/// directions; then give each polyline the direction most of its segments have (the
/// direction walked if as many run either way; a reversed loop still starts at the
/// same point). Of the ends that share a key, a polyline carries one. This is how
/// the segments of the Marching Lines (Thirion & Gourdon 1993, §4) are chained: the
/// second field may flip its sign from cell to cell, so their directions only
/// agree for the most part.
pub fn chain_oriented<E: Copy, K: Ord>(
    segments: &[[E; 2]],
    key: impl Fn(&E) -> K,
) -> Vec<OrientedChain<E>> {
    let graph = Graph::new(segments, key);
    walks(
        &graph,
        |_| true,
        |mut walk| {
            if walk.forward < 0 {
                walk.points.reverse();
                if walk.closed {
                    walk.points.rotate_right(1);
                }
            }
            OrientedChain {
                points: walk.points,
                closed: walk.closed,
            }
        },
    )
}

/// Strength ∫ k ds of every connected piece, and each segment's piece.
fn piece_strengths<E>(graph: &Graph<E>, located: &[(Point, f64)]) -> (Vec<usize>, Vec<f64>) {
    let mut pieces = UnionFind::<u32>::new(graph.nodes.len());
    for &[a, b] in &graph.segments {
        pieces.union(a, b);
    }
    let labels = pieces.into_labeling();
    let piece_of: Vec<usize> = graph
        .segments
        .iter()
        .map(|s| labels[s[0] as usize] as usize)
        .collect();
    let mut strength = vec![0.0; graph.nodes.len()];
    for (s, &[a, b]) in graph.segments.iter().enumerate() {
        let ((pa, ka), (pb, kb)) = (located[a as usize], located[b as usize]);
        strength[piece_of[s]] += 0.5 * (ka + kb) * (pb - pa).norm();
    }
    (piece_of, strength)
}

/// The maximal polylines of the segments that are `kept`, each made into a line by
/// `finish`: open ones from the nodes of degree other than two, in node order, then
/// loops through degree-two nodes, in the order of their lowest segment.
fn walks<E: Copy, L>(
    graph: &Graph<E>,
    kept: impl Fn(usize) -> bool,
    finish: impl Fn(Walk<E>) -> L,
) -> Vec<L> {
    let mut lines = Vec::new();
    let mut used = vec![false; graph.segments.len()];
    for node in 0..graph.nodes.len() as u32 {
        if graph.degree(node) == 2 {
            continue;
        }
        for &half in graph.incident.get(node as usize) {
            let segment = (half / 2) as usize;
            if !used[segment] && kept(segment) {
                lines.push(finish(walk(graph, half, &mut used)));
            }
        }
    }
    for segment in 0..graph.segments.len() {
        if !used[segment] && kept(segment) {
            lines.push(finish(walk(graph, 2 * segment as u32, &mut used)));
        }
    }
    lines
}

/// Follow the graph from the start of half-segment `half` until a node of degree
/// other than two, or back to the start (a loop).
fn walk<E: Copy>(graph: &Graph<E>, half: u32, used: &mut [bool]) -> Walk<E> {
    let start = graph.start(half);
    let mut points = vec![graph.nodes[start as usize]];
    let mut forward = 0;
    let mut current = half;
    let closed = loop {
        used[(current / 2) as usize] = true;
        forward += if current.is_multiple_of(2) { 1 } else { -1 };
        let node = graph.other_end(current);
        if node == start {
            break true;
        }
        points.push(graph.nodes[node as usize]);
        if graph.degree(node) != 2 {
            break false;
        }
        let next = graph
            .incident
            .get(node as usize)
            .iter()
            .copied()
            .find(|&h| !used[(h / 2) as usize]);
        match next {
            Some(h) => current = h,
            None => break false,
        }
    };
    Walk {
        points,
        closed,
        first: (half / 2) as usize,
        forward,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lines of `chain_oriented` as (points, closed).
    fn oriented(segments: &[[u32; 2]]) -> Vec<(Vec<u32>, bool)> {
        chain_oriented(segments, |&k| k)
            .into_iter()
            .map(|c| (c.points, c.closed))
            .collect()
    }

    #[test]
    fn an_open_line_runs_the_way_most_of_its_segments_do() {
        assert_eq!(
            oriented(&[[1, 2], [3, 2], [3, 4]]),
            [(vec![1, 2, 3, 4], false)]
        );
        assert_eq!(
            oriented(&[[2, 1], [3, 2], [3, 4]]),
            [(vec![4, 3, 2, 1], false)]
        );
    }

    #[test]
    fn a_reversed_loop_keeps_its_first_point() {
        assert_eq!(oriented(&[[1, 2], [3, 2], [1, 3]]), [(vec![1, 3, 2], true)]);
        assert_eq!(oriented(&[[1, 2], [2, 3], [3, 1]]), [(vec![1, 2, 3], true)]);
    }

    #[test]
    fn lines_end_at_junctions_and_follow_the_plain_chain() {
        let star = [[0, 1], [0, 2], [3, 0]];
        let lines = oriented(&star);
        assert_eq!(
            lines,
            [
                (vec![0, 1], false),
                (vec![0, 2], false),
                (vec![3, 0], false)
            ]
        );
        let plain = chain(&star, |k| (Point::new(f64::from(k), 0.0, 0.0), 1.0), 0.0);
        let walked: Vec<Vec<u32>> = plain.into_iter().map(|c| c.points).collect();
        assert_eq!(walked, [vec![0, 1], vec![0, 2], vec![0, 3]]);
    }
}
