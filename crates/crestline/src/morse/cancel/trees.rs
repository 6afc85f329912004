//! The forests of cancelled saddles: which initial tree of a merged extremum set
//! is reached through which cancelled saddle, walked breadth first from the
//! surviving extremum.

use std::collections::VecDeque;

use crate::mesh::EdgeId;

/// A cancelled saddle as a link between two initial trees of one forest (set
/// elements; the boundary for a missing face), with its node in each (its
/// vertices, or its faces) and its edge.
#[derive(Clone, Copy)]
pub(super) struct Link {
    pub(super) trees: [u32; 2],
    pub(super) nodes: [u32; 2],
    pub(super) edge: EdgeId,
}

/// Walk the `n` trees joined by `links` breadth first from `roots`: the node and
/// edge of the link by which every other tree is reached. The cancellations link
/// the initial trees of a set into a tree, so each is reached once.
pub(super) fn attach(
    n: usize,
    roots: impl Iterator<Item = usize>,
    links: &[Link],
) -> Vec<(u32, EdgeId)> {
    let (first, incident) = incidence(n, links);
    let mut reached = vec![false; n];
    let mut queue: VecDeque<usize> = roots.collect();
    for &tree in &queue {
        reached[tree] = true;
    }
    let mut attachments = Vec::with_capacity(n);
    while let Some(tree) = queue.pop_front() {
        for &(l, side) in &incident[first[tree]..first[tree + 1]] {
            let link = links[l];
            let next = link.trees[side] as usize;
            if !std::mem::replace(&mut reached[next], true) {
                attachments.push((link.nodes[side], link.edge));
                queue.push_back(next);
            }
        }
    }
    attachments
}

/// The links at each of `n` trees, in compressed rows: those of tree `t` are
/// `incident[first[t]..first[t + 1]]`, each as the link and the side across it.
pub(super) fn incidence(n: usize, links: &[Link]) -> (Vec<usize>, Vec<(usize, usize)>) {
    let mut first = vec![0; n + 1];
    for link in links {
        for tree in link.trees {
            first[tree as usize + 1] += 1;
        }
    }
    for i in 0..n {
        first[i + 1] += first[i];
    }
    let mut fill = first.clone();
    let mut incident = vec![(0, 0); 2 * links.len()];
    for (l, link) in links.iter().enumerate() {
        for (side, &tree) in link.trees.iter().enumerate() {
            incident[fill[tree as usize]] = (l, 1 - side);
            fill[tree as usize] += 1;
        }
    }
    (first, incident)
}
