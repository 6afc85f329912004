//! Chaining segments into polylines, and the strength filter of Ohtake, Belyaev and
//! Seidel (2004) as used by Hildebrandt et al. (2005, §4). Generic over the key that
//! names a point (an edge crossing on a mesh, a face centre, a point of a volume
//! cell): segments that share a key are joined.

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

/// The segments as a graph on their distinct end points.
struct Graph<K> {
    nodes: Vec<K>,
    /// Each segment as a pair of node indices.
    segments: Vec<[u32; 2]>,
    /// The segments at each node.
    incident: Buckets,
}

impl<K: Copy + Ord> Graph<K> {
    fn new(segments: &[[K; 2]]) -> Graph<K> {
        let mut nodes: Vec<K> = segments.iter().flatten().copied().collect();
        nodes.sort_unstable();
        nodes.dedup();
        let index = |p: &K| nodes.binary_search(p).map_or(0, |i| i as u32);
        let segments: Vec<[u32; 2]> = segments.iter().map(|s| s.map(|p| index(&p))).collect();
        // Half-segments 2s and 2s + 1 start at the segment's first and second node.
        let starts: Vec<u32> = segments.iter().flatten().copied().collect();
        let incident = Buckets::new(nodes.len(), &starts);
        Graph {
            nodes,
            segments,
            incident,
        }
    }

    fn degree(&self, node: u32) -> usize {
        self.incident.get(node as usize).len()
    }

    /// The node at the other end of half-segment `half` (which starts at a node).
    fn other_end(&self, half: u32) -> u32 {
        self.segments[(half / 2) as usize][(1 - half % 2) as usize]
    }
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
    let graph = Graph::new(segments);
    let located: Vec<(Point, f64)> = graph.nodes.iter().map(|&p| locate(p)).collect();
    let (piece_of, strength) = piece_strengths(&graph, &located);
    let kept = |half: u32| strength[piece_of[(half / 2) as usize]] >= threshold;

    let mut used = vec![false; graph.segments.len()];
    let mut chains = Vec::new();
    // Open polylines start at nodes of degree other than two.
    for node in 0..graph.nodes.len() as u32 {
        if graph.degree(node) == 2 {
            continue;
        }
        for &half in graph.incident.get(node as usize) {
            if !used[(half / 2) as usize] && kept(half) {
                chains.push(walk(&graph, half, &mut used, &strength, &piece_of));
            }
        }
    }
    // What is left of the kept pieces are loops through degree-two nodes.
    for s in 0..graph.segments.len() as u32 {
        if !used[s as usize] && kept(2 * s) {
            chains.push(walk(&graph, 2 * s, &mut used, &strength, &piece_of));
        }
    }
    chains
}

/// Strength ∫ k ds of every connected piece, and each segment's piece.
fn piece_strengths<K>(graph: &Graph<K>, located: &[(Point, f64)]) -> (Vec<usize>, Vec<f64>) {
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

/// Follow the graph from the start of half-segment `half` until a node of degree
/// other than two, or back to the start (a loop).
fn walk<K: Copy + Ord>(
    graph: &Graph<K>,
    half: u32,
    used: &mut [bool],
    strength: &[f64],
    piece_of: &[usize],
) -> Chain<K> {
    let start = graph.segments[(half / 2) as usize][(half % 2) as usize];
    let mut points = vec![graph.nodes[start as usize]];
    let mut current = half;
    let closed = loop {
        used[(current / 2) as usize] = true;
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
    Chain {
        points,
        closed,
        strength: strength[piece_of[(half / 2) as usize]],
    }
}
