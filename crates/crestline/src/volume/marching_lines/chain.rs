//! Chaining the segments of all cells into polylines by point key.
//!
//! Each point is shared by the segments of the (at most two) cells around its face,
//! so most points have degree two; points of other degree (the border of the
//! volume, cells where the second field is undefined or a segment was dropped) end
//! lines. The graph is walked without regard to the segments' directions, because a
//! [`SecondField`](super::SecondField) may flip its sign from cell to cell; each
//! line then takes the direction most of its segments have.

use super::{BiIsoLine, PointKey, Segment};
use crate::Point;

/// The segments as a graph on their distinct end points.
struct Graph {
    keys: Vec<PointKey>,
    points: Vec<Point>,
    /// The two nodes of each segment, from its first end to its second.
    ends: Vec<[u32; 2]>,
    /// Half-segment `2s + e` starts at end `e` of segment `s`; the half-segments
    /// starting at node `n` are `halves[offsets[n]..offsets[n + 1]]`.
    offsets: Vec<usize>,
    halves: Vec<u32>,
}

impl Graph {
    fn new(segments: &[Segment]) -> Graph {
        let mut located: Vec<(PointKey, Point)> = segments
            .iter()
            .flat_map(|s| s.keys.into_iter().zip(s.points))
            .collect();
        located.sort_unstable_by_key(|&(key, _)| key);
        located.dedup_by_key(|&mut (key, _)| key);
        let (keys, points): (Vec<PointKey>, Vec<Point>) = located.into_iter().unzip();
        let node = |key: &PointKey| keys.binary_search(key).map_or(0, |n| n as u32);
        let ends: Vec<[u32; 2]> = segments.iter().map(|s| s.keys.map(|k| node(&k))).collect();
        let mut offsets = vec![0; keys.len() + 1];
        for &n in ends.iter().flatten() {
            offsets[n as usize + 1] += 1;
        }
        for n in 0..keys.len() {
            offsets[n + 1] += offsets[n];
        }
        let mut filled = offsets.clone();
        let mut halves = vec![0; 2 * ends.len()];
        for (half, &n) in ends.iter().flatten().enumerate() {
            halves[filled[n as usize]] = half as u32;
            filled[n as usize] += 1;
        }
        Graph {
            keys,
            points,
            ends,
            offsets,
            halves,
        }
    }

    /// The half-segments starting at node `n`.
    fn at(&self, n: u32) -> &[u32] {
        &self.halves[self.offsets[n as usize]..self.offsets[n as usize + 1]]
    }

    /// The node where half-segment `half` starts.
    fn start(&self, half: u32) -> u32 {
        self.ends[(half / 2) as usize][(half % 2) as usize]
    }

    /// The node where half-segment `half` ends.
    fn end(&self, half: u32) -> u32 {
        self.ends[(half / 2) as usize][(1 - half % 2) as usize]
    }
}

/// Chain `segments` into maximal polylines: open lines between nodes whose degree
/// is not two, then loops, in the order of their lowest node or segment.
pub(super) fn chain(segments: &[Segment]) -> Vec<BiIsoLine> {
    let graph = Graph::new(segments);
    let mut used = vec![false; segments.len()];
    let mut lines = Vec::new();
    for node in 0..graph.keys.len() as u32 {
        if graph.at(node).len() != 2 {
            for &half in graph.at(node) {
                if !used[(half / 2) as usize] {
                    lines.push(walk(&graph, half, &mut used));
                }
            }
        }
    }
    for s in 0..segments.len() as u32 {
        if !used[s as usize] {
            lines.push(walk(&graph, 2 * s, &mut used));
        }
    }
    lines
}

/// Follow the graph from half-segment `half` until a node of degree other than
/// two or back to the start, and orient the line as most of its segments are.
fn walk(graph: &Graph, half: u32, used: &mut [bool]) -> BiIsoLine {
    let start = graph.start(half);
    let mut nodes = vec![start];
    let mut forward = 0i64;
    let mut current = half;
    let closed = loop {
        used[(current / 2) as usize] = true;
        forward += if current.is_multiple_of(2) { 1 } else { -1 };
        let node = graph.end(current);
        if node == start {
            break true;
        }
        nodes.push(node);
        let next = graph.at(node).iter().find(|&&h| !used[(h / 2) as usize]);
        match next {
            Some(&h) if graph.at(node).len() == 2 => current = h,
            _ => break false,
        }
    };
    if forward < 0 {
        nodes.reverse();
        if closed {
            nodes.rotate_right(1);
        }
    }
    BiIsoLine {
        points: nodes.iter().map(|&n| graph.points[n as usize]).collect(),
        keys: nodes.iter().map(|&n| graph.keys[n as usize]).collect(),
        closed,
    }
}
