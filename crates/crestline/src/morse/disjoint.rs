//! Disjoint sets for the extrema merged by cancellations.

use std::cell::Cell;
use std::cmp::Ordering;

/// A union-find forest over `0..n` with union by rank, whose finds halve the paths
/// they walk even through a shared reference (the parents are cells), so that the
/// many lookups of the cancellation loop stay short. The representatives are those
/// of union by rank alone (as in `petgraph`'s `UnionFind`): halving a path changes
/// no root and no rank.
pub struct DisjointSets {
    parent: Vec<Cell<u32>>,
    rank: Vec<u8>,
}

impl DisjointSets {
    /// `n` singletons.
    pub fn new(n: usize) -> DisjointSets {
        DisjointSets {
            parent: (0..n as u32).map(Cell::new).collect(),
            rank: vec![0; n],
        }
    }

    /// The representative of the set holding `x`.
    pub fn find(&self, mut x: u32) -> u32 {
        loop {
            let parent = self.parent[x as usize].get();
            if parent == x {
                return x;
            }
            let grandparent = self.parent[parent as usize].get();
            self.parent[x as usize].set(grandparent);
            x = grandparent;
        }
    }

    /// Merge the sets of `x` and `y`; returns the representative of the union: the
    /// root of higher rank, or `x`'s on a tie.
    pub fn union(&mut self, x: u32, y: u32) -> u32 {
        let (x, y) = (self.find(x), self.find(y));
        if x == y {
            return x;
        }
        let (root, child) = match self.rank[x as usize].cmp(&self.rank[y as usize]) {
            Ordering::Less => (y, x),
            Ordering::Greater => (x, y),
            Ordering::Equal => {
                self.rank[x as usize] += 1;
                (x, y)
            }
        };
        self.parent[child as usize].set(root);
        root
    }
}
