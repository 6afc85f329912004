//! Disjoint sets that many threads join at once: the connected components of a
//! mesh's faces or vertices, found in parallel over its edges.
//!
//! Union by index: of two roots the larger is linked below the smaller, so every
//! set's root is its least member whatever order the threads join in, and the
//! result is the same on any number of threads. `find` halves paths with
//! compare-and-swap (every parent has a smaller index than its child, and a
//! grandparent stays an ancestor, so a lost race only skips the shortcut).
//! Without union by rank a path can grow to a logarithmic length (Tarjan and van
//! Leeuwen 1984: path halving alone costs O(log n) per operation at worst); on
//! meshes, whose elements are numbered along the surface, the paths stay short.

use std::sync::atomic::{AtomicU32, Ordering};

use rayon::prelude::*;

/// Disjoint sets of `0..n`, joined through a shared reference.
pub(crate) struct SharedSets {
    parent: Vec<AtomicU32>,
}

impl SharedSets {
    /// `n` sets of one element each.
    pub(crate) fn new(n: usize) -> SharedSets {
        SharedSets {
            parent: (0..n as u32).into_par_iter().map(AtomicU32::new).collect(),
        }
    }

    /// The root of `x`'s set.
    fn find(&self, mut x: u32) -> u32 {
        loop {
            let p = self.parent[x as usize].load(Ordering::Acquire);
            if p == x {
                return x;
            }
            let grandparent = self.parent[p as usize].load(Ordering::Acquire);
            if grandparent != p {
                // Another thread may have moved x already: then x keeps its parent.
                let _ = self.parent[x as usize].compare_exchange(
                    p,
                    grandparent,
                    Ordering::AcqRel,
                    Ordering::Acquire,
                );
            }
            x = grandparent;
        }
    }

    /// Joins the sets of `a` and `b`.
    pub(crate) fn union(&self, a: u32, b: u32) {
        let (mut a, mut b) = (a, b);
        loop {
            (a, b) = (self.find(a), self.find(b));
            if a == b {
                return;
            }
            let (low, high) = (a.min(b), a.max(b));
            // Fails if another thread linked `high` meanwhile: find again.
            if self.parent[high as usize]
                .compare_exchange(high, low, Ordering::AcqRel, Ordering::Acquire)
                .is_ok()
            {
                return;
            }
        }
    }

    /// The least member of every element's set.
    pub(crate) fn into_roots(self) -> Vec<u32> {
        (0..self.parent.len() as u32)
            .into_par_iter()
            .map(|x| self.find(x))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use petgraph::unionfind::UnionFind;

    #[test]
    fn concurrent_unions_give_the_serial_sets_rooted_at_their_least_member() {
        let n = 200_000u32;
        // Pairs of a sparse random graph: many sets, some large.
        let pairs: Vec<(u32, u32)> = (0..n / 2 + n / 4)
            .map(|k| {
                let a = k.wrapping_mul(2_654_435_761) % n;
                let b = (k ^ 0x5bd1).wrapping_mul(40_503) % n;
                (a, b)
            })
            .collect();
        let mut serial = UnionFind::<u32>::new(n as usize);
        for &(a, b) in &pairs {
            serial.union(a, b);
        }
        let serial = serial.into_labeling();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(4)
            .build()
            .unwrap();
        let roots = pool.install(|| {
            let sets = SharedSets::new(n as usize);
            pairs.par_iter().for_each(|&(a, b)| sets.union(a, b));
            sets.into_roots()
        });
        let mut least = vec![u32::MAX; n as usize];
        for (x, &label) in serial.iter().enumerate() {
            least[label as usize] = least[label as usize].min(x as u32);
        }
        for (x, (&root, &label)) in roots.iter().zip(&serial).enumerate() {
            assert_eq!(root, least[label as usize], "element {x}");
        }
        assert!(roots.iter().filter(|&&r| r != roots[0]).count() > 0);
        assert!((0..n).filter(|&x| roots[x as usize] == x).count() < n as usize / 2);
    }
}
