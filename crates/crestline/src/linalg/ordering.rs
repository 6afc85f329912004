//! The fill-reducing ordering of the factored smoothing systems: approximate
//! minimum degree (Amestoy, Davis and Duff, *An approximate minimum degree
//! ordering algorithm*, SIAM J. Matrix Anal. Appl. 17, 1996; faer's
//! implementation) on the graph of matched pairs of unknowns.
//!
//! The unknowns are paired greedily along the matrix's couplings, each pair
//! becomes one node of a graph half the size, and the ordering of that graph
//! lists both unknowns of a pair one after the other. AMD takes about half the
//! time on the smaller graph, and it is the part of the factorization that the
//! curvature does not hide (the ridges' `smoothing analysis` stage); the factor
//! has more entries, which costs the numeric factorization part of what the
//! ordering saves. On the Stanford dragon's extremality system (437k unknowns):
//! ordering 0.46–0.64 s instead of 0.93–1.0 s, 54 entries of L per unknown
//! instead of 40, numeric factorization 0.62 s instead of 0.46 s; the ridges'
//! `smoothing analysis` stage 0.59–0.86 → 0.22–0.46 s, and the whole `ridges`,
//! median of three interleaved runs, 2.83 → 2.39 s in one comparison, 3.06 and
//! 2.99 → 2.86 and 3.00 s in two more (on a machine whose runs vary by 0.3 s). On
//! the dragon ×4 (1.7M): 67 entries instead of 59, `ridges` 11.8–13.6 → 10.7–12.6 s.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::amd;
use faer::sparse::SymbolicSparseColMatRef;

use super::SymmetricMatrix;
use crate::{Error, Result};

/// A graph in compressed rows: the neighbours of node v are
/// `adjacent[start[v]..start[v + 1]]`, increasing, without v itself.
struct Graph {
    start: Vec<usize>,
    adjacent: Vec<usize>,
}

impl Graph {
    fn size(&self) -> usize {
        self.start.len() - 1
    }

    fn neighbours(&self, v: usize) -> &[usize] {
        &self.adjacent[self.start[v]..self.start[v + 1]]
    }

    /// The graph of the off-diagonal entries of the symmetric `matrix` (whose
    /// columns hold both triangles, sorted).
    fn of_matrix(matrix: &SymmetricMatrix) -> Graph {
        let (col_ptr, row_idx, _) = matrix.csc();
        let mut start = Vec::with_capacity(matrix.size() + 1);
        let mut adjacent = Vec::with_capacity(row_idx.len());
        start.push(0);
        for j in 0..matrix.size() {
            let column = &row_idx[col_ptr[j]..col_ptr[j + 1]];
            adjacent.extend(column.iter().map(|&i| i as usize).filter(|&i| i != j));
            start.push(adjacent.len());
        }
        Graph { start, adjacent }
    }

    /// Greedy matching in node order: each node not yet matched is paired with
    /// its last (highest) neighbour not yet matched, if any. Returns the pair (or
    /// single node) of every node, numbered in the order of their first node, and
    /// the nodes of each pair.
    fn pairs(&self) -> (Vec<usize>, Vec<[usize; 2]>) {
        const NONE: usize = usize::MAX;
        let mut pair = vec![NONE; self.size()];
        let mut members = Vec::with_capacity(self.size() / 2 + 1);
        for v in 0..self.size() {
            if pair[v] != NONE {
                continue;
            }
            let mate = self
                .neighbours(v)
                .iter()
                .rev()
                .find(|&&w| pair[w] == NONE)
                .copied();
            pair[v] = members.len();
            if let Some(w) = mate {
                pair[w] = members.len();
            }
            members.push([v, mate.unwrap_or(v)]);
        }
        (pair, members)
    }

    /// The graph whose nodes are the `members` of `pair` ([`Graph::pairs`]), two
    /// pairs adjacent when some node of one is adjacent to some node of the other.
    fn quotient(&self, pair: &[usize], members: &[[usize; 2]]) -> Graph {
        let mut start = Vec::with_capacity(members.len() + 1);
        let mut adjacent = Vec::with_capacity(self.adjacent.len());
        start.push(0);
        for (p, nodes) in members.iter().enumerate() {
            let first = adjacent.len();
            let distinct = if nodes[0] == nodes[1] { 1 } else { 2 };
            for &v in &nodes[..distinct] {
                adjacent.extend(self.neighbours(v).iter().map(|&w| pair[w]));
            }
            let row = &mut adjacent[first..];
            row.sort_unstable();
            let kept = dedup_without(row, p);
            adjacent.truncate(first + kept);
            start.push(adjacent.len());
        }
        Graph { start, adjacent }
    }

    /// The approximate minimum degree ordering of the graph: `order[k]` is the
    /// node eliminated k-th.
    fn amd(&self) -> Result<Vec<usize>> {
        let n = self.size();
        let pattern = SymbolicSparseColMatRef::new_checked(n, n, &self.start, None, &self.adjacent);
        let (mut order, mut inverse) = (vec![0; n], vec![0; n]);
        let mut scratch =
            MemBuffer::try_new(amd::order_scratch::<usize>(n, self.adjacent.len()))
                .map_err(|err| Error::Argument(format!("no memory for the ordering: {err:?}")))?;
        amd::order(
            &mut order,
            &mut inverse,
            pattern,
            amd::Control::default(),
            MemStack::new(&mut scratch),
        )
        .map_err(|err| Error::Argument(format!("minimum degree ordering failed: {err:?}")))?;
        Ok(order)
    }
}

/// Removes repeats and every `skip` from the sorted `row` in place; returns the
/// number of values kept (at its front).
fn dedup_without(row: &mut [usize], skip: usize) -> usize {
    let mut kept = 0;
    for k in 0..row.len() {
        let value = row[k];
        if value != skip && (kept == 0 || row[kept - 1] != value) {
            row[kept] = value;
            kept += 1;
        }
    }
    kept
}

/// The fill-reducing order of `matrix`: AMD on the graph of matched pairs, each
/// pair's unknowns listed together.
/// Returns the permutation and its inverse (`order[k]` is the unknown eliminated
/// k-th, `rank[order[k]] = k`).
pub(super) fn paired_amd(matrix: &SymmetricMatrix) -> Result<(Vec<usize>, Vec<usize>)> {
    let n = matrix.size();
    let graph = Graph::of_matrix(matrix);
    let (pair, members) = graph.pairs();
    let coarse_order = graph.quotient(&pair, &members).amd()?;
    let mut order = Vec::with_capacity(n);
    for p in coarse_order {
        let [a, b] = members[p];
        order.push(a);
        if b != a {
            order.push(b);
        }
    }
    let mut rank = vec![0; n];
    for (k, &v) in order.iter().enumerate() {
        rank[v] = k;
    }
    Ok((order, rank))
}

#[cfg(test)]
mod tests {
    use faer::perm::PermRef;
    use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, SymmetricOrdering};
    use faer::Side;

    use super::*;
    use crate::linalg::cholesky::LowerTriangle;
    use crate::linalg::SymmetricBuilder;

    /// A `w × h` grid's 5-point Laplacian plus the identity, numbered row by row.
    fn grid(w: usize, h: usize) -> SymmetricMatrix {
        let n = w * h;
        let mut builder = SymmetricBuilder::new(n);
        for j in 0..n {
            builder.add_diagonal(j, 1.0);
            if (j + 1) % w != 0 {
                builder.add_edge(j, j + 1, 1.0);
            }
            if j + w < n {
                builder.add_edge(j, j + w, 1.0);
            }
        }
        builder.build()
    }

    #[test]
    fn the_graph_holds_both_triangles_without_the_diagonal() {
        let graph = Graph::of_matrix(&grid(3, 2));
        // 0 1 2
        // 3 4 5
        let expected: [&[usize]; 6] = [&[1, 3], &[0, 2, 4], &[1, 5], &[0, 4], &[1, 3, 5], &[2, 4]];
        for (v, want) in expected.iter().enumerate() {
            assert_eq!(graph.neighbours(v), *want, "node {v}");
        }
    }

    #[test]
    fn pairs_are_adjacent_and_cover_every_node_once() {
        let a = grid(7, 5);
        let n = a.size();
        let graph = Graph::of_matrix(&a);
        let (pair, members) = graph.pairs();
        let mut covered = vec![0; n];
        for (p, &[a, b]) in members.iter().enumerate() {
            covered[a] += 1;
            if b != a {
                covered[b] += 1;
                assert!(graph.neighbours(a).contains(&b), "pair {a}, {b}");
            }
            assert_eq!((pair[a], pair[b]), (p, p));
        }
        assert!(covered.iter().all(|&c| c == 1), "{covered:?}");
        // A grid has a near-perfect matching; the greedy one finds most of it.
        assert!(
            members.len() <= n * 6 / 10,
            "{} pairs of {n}",
            members.len()
        );
    }

    #[test]
    fn the_quotient_joins_pairs_whose_nodes_touch() {
        let a = grid(7, 5);
        let graph = Graph::of_matrix(&a);
        let (pair, members) = graph.pairs();
        let quotient = graph.quotient(&pair, &members);
        for (p, nodes) in members.iter().enumerate() {
            let mut expected: Vec<usize> = nodes
                .iter()
                .flat_map(|&v| graph.neighbours(v).iter().map(|&w| pair[w]))
                .filter(|&q| q != p)
                .collect();
            expected.sort_unstable();
            expected.dedup();
            assert_eq!(quotient.neighbours(p), &expected[..], "pair {p}");
        }
    }

    #[test]
    fn the_order_is_a_permutation_with_pairs_together() {
        let a = grid(30, 20);
        let n = a.size();
        let (order, rank) = paired_amd(&a).unwrap();
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..n).collect::<Vec<_>>());
        for (k, &v) in order.iter().enumerate() {
            assert_eq!(rank[v], k);
        }
        let graph = Graph::of_matrix(&a);
        let (pair, _) = graph.pairs();
        let together = order
            .windows(2)
            .filter(|w| pair[w[0]] == pair[w[1]])
            .count();
        assert_eq!(together, n - pair.iter().max().unwrap() - 1);
    }

    /// The entries of L for the pattern `lower` in the given ordering.
    fn fill(lower: &LowerTriangle, ordering: SymmetricOrdering<'_, usize>) -> usize {
        factorize_symbolic_cholesky(lower.symbolic(), Side::Lower, ordering, Default::default())
            .unwrap()
            .len_val()
    }

    /// On a 60 × 60 grid the pairs' ordering fills L about as little as AMD on
    /// the whole graph, and far less than the grid's own numbering (whose fill
    /// grows with the grid's width): the order is applied the right way round.
    #[test]
    fn the_paired_order_fills_little() {
        let a = grid(60, 60);
        let n = a.size();
        let lower = LowerTriangle::new(&a).unwrap();
        let (order, rank) = paired_amd(&a).unwrap();
        let paired = fill(
            &lower,
            SymmetricOrdering::Custom(PermRef::new_checked(&order, &rank, n)),
        );
        let amd = fill(&lower, SymmetricOrdering::Amd);
        let identity: Vec<usize> = (0..n).collect();
        let natural = fill(
            &lower,
            SymmetricOrdering::Custom(PermRef::new_checked(&identity, &identity, n)),
        );
        assert!(paired <= amd * 3 / 2, "paired {paired}, AMD {amd}");
        assert!(paired * 2 < natural, "paired {paired}, natural {natural}");
    }
}
