//! Coarsening by smoothed aggregation (Vaněk, Mandel and Brezina 1996): strongly
//! coupled unknowns grouped into aggregates, each with a tentative basis vector
//! whose signs follow the couplings it grew along, and the prolongator smoothed by
//! one damped Jacobi step on the finest level.

use rayon::prelude::*;

use super::super::SymmetricMatrix;
use super::sparse::{compressed_rows, galerkin, Rows};

/// Strength threshold θ: a_ij is a strong coupling when a_ij² ≥ θ² a_ii a_jj
/// (Vaněk et al. §4 use θ = 0.08 · ½^level; a fixed θ keeps coarse levels sparse).
pub(super) const STRENGTH: f64 = 0.08;

/// The next level of `a`: its prolongator P, Pᵀ and the Galerkin matrix, or
/// `None` if nothing is strongly coupled.
pub(super) fn coarsen(a: &SymmetricMatrix, depth: usize) -> Option<(Rows, Rows, SymmetricMatrix)> {
    let diagonal = &a.diagonal();
    let (aggregate, sign, count) = aggregate(a, diagonal);
    if count == 0 {
        return None;
    }
    // Smoothing the coarser levels' prolongators too left the iteration counts as
    // they were (dragon and dragon ×4) and made their matrices five times denser.
    let omega = if depth == 0 {
        smoothing_weight(a, diagonal)
    } else {
        0.0
    };
    let prolongator = prolongator(a, diagonal, &aggregate, &sign, omega);
    let restrictor = prolongator.transpose(count);
    let coarse = galerkin(a, &prolongator, &restrictor, count);
    Some((prolongator, restrictor, coarse))
}

/// Marks a vertex that belongs to no aggregate.
pub(super) const NONE: usize = usize::MAX;

/// Whether a_ij (i ≠ j) is a strong coupling.
pub(super) fn strong(a_ij: f64, a_ii: f64, a_jj: f64) -> bool {
    a_ij * a_ij >= STRENGTH * STRENGTH * a_ii * a_jj
}

/// Greedy aggregation (Vaněk et al. §4): first every unknown whose strong
/// neighbours are all free starts an aggregate with them; then every unknown
/// left joins the aggregate of its strongest neighbour among the first pass's.
/// Unknowns with no strong coupling stay out (their rows are nearly diagonal, and
/// the smoother solves them). Returns each unknown's aggregate (or [`NONE`]), its
/// sign in the aggregate's basis vector, and the number of aggregates.
pub(super) fn aggregate(a: &SymmetricMatrix, diagonal: &[f64]) -> (Vec<usize>, Vec<f64>, usize) {
    let n = a.size();
    let mut aggregate = vec![NONE; n];
    let mut sign = vec![1.0; n];
    let mut count = 0;
    let strong_neighbours = |i: usize| {
        a.column(i)
            .filter(move |&(j, v)| j != i && strong(v, diagonal[i], diagonal[j]))
    };
    for i in 0..n {
        if aggregate[i] != NONE {
            continue;
        }
        let isolated = strong_neighbours(i).next().is_none();
        if isolated || strong_neighbours(i).any(|(j, _)| aggregate[j] != NONE) {
            continue;
        }
        aggregate[i] = count;
        for (j, v) in strong_neighbours(i) {
            aggregate[j] = count;
            // Along a coupling a_ij = −t w σ the near-kernel has x_j = σ x_i.
            sign[j] = -v.signum();
        }
        count += 1;
    }
    let first = aggregate.clone();
    for i in 0..n {
        if aggregate[i] != NONE {
            continue;
        }
        let strongest = strong_neighbours(i)
            .filter(|&(j, _)| first[j] != NONE)
            .max_by(|x, y| x.1.abs().total_cmp(&y.1.abs()));
        if let Some((j, v)) = strongest {
            aggregate[i] = first[j];
            sign[i] = -v.signum() * sign[j];
        }
    }
    (aggregate, sign, count)
}

/// The prolongator smoothing's weight ω = 4 / (3 ρ), ρ ≥ ρ(D⁻¹ A) by Gershgorin
/// (Vaněk et al. §3); 0 (no smoothing) if ρ is not finite.
pub(super) fn smoothing_weight(a: &SymmetricMatrix, diagonal: &[f64]) -> f64 {
    let rho = (0..a.size())
        .into_par_iter()
        .map(|i| a.column(i).map(|(_, v)| v.abs()).sum::<f64>() / diagonal[i])
        .reduce(|| 0.0, f64::max);
    let omega = 4.0 / (3.0 * rho);
    if omega.is_finite() {
        omega
    } else {
        0.0
    }
}

/// P = (I − ω D⁻¹ A) P₀ with the tentative prolongator P₀ (row i: `sign[i]` in
/// column `aggregate[i]`); P₀ itself for ω = 0.
pub(super) fn prolongator(
    a: &SymmetricMatrix,
    diagonal: &[f64],
    aggregate: &[usize],
    sign: &[f64],
    omega: f64,
) -> Rows {
    let (ptr, cols, values) = compressed_rows(
        a.size(),
        || (),
        |(), i, row| {
            if aggregate[i] != NONE {
                row.push((aggregate[i] as u32, sign[i]));
            }
            if omega != 0.0 {
                let scale = omega / diagonal[i];
                for (j, v) in a.column(i).filter(|&(j, _)| aggregate[j] != NONE) {
                    row.push((aggregate[j] as u32, -scale * v * sign[j]));
                }
            }
            row.sort_unstable_by_key(|&(c, _)| c);
            row.dedup_by(|next, kept| {
                let same = next.0 == kept.0;
                if same {
                    kept.1 += next.1;
                }
                same
            });
        },
    );
    Rows { ptr, cols, values }
}
