//! A locality order of points: along the Morton (Z-order) curve of their
//! bounding box, so that points near each other in space are mostly near each
//! other in the order too. Sparse systems over a mesh whose unknowns follow it
//! touch memory locally: a refined or shuffled scan's vertex list may put a
//! vertex's neighbours millions of entries apart.

use rayon::prelude::*;

use crate::Point;

/// Bits per axis of the Morton code: 3 × 21 = 63 bits.
const BITS: u32 = 21;

/// The indices of `points` in Morton order (ties, and non-finite coordinates,
/// by index).
pub(crate) fn morton_order(points: &[Point]) -> Vec<u32> {
    let finite = points.iter().filter(|p| p.iter().all(|x| x.is_finite()));
    let (lo, hi) = finite.fold(
        (
            Point::from([f64::INFINITY; 3]),
            Point::from([f64::NEG_INFINITY; 3]),
        ),
        |(lo, hi), p| (lo.inf(p), hi.sup(p)),
    );
    let extent = (0..3).map(|a| hi[a] - lo[a]).fold(0.0, f64::max);
    let scale = if extent > 0.0 {
        f64::from((1u32 << BITS) - 1) / extent
    } else {
        0.0
    };
    let mut keyed: Vec<(u64, u32)> = points
        .par_iter()
        .enumerate()
        .map(|(i, p)| {
            // Non-finite and out-of-box coordinates clamp to the box (NaN to 0).
            let cell = |a: usize| {
                ((p[a] - lo[a]) * scale).clamp(0.0, f64::from((1u32 << BITS) - 1)) as u64
            };
            (
                spread(cell(0)) | spread(cell(1)) << 1 | spread(cell(2)) << 2,
                i as u32,
            )
        })
        .collect();
    keyed.par_sort_unstable();
    keyed.into_iter().map(|(_, i)| i).collect()
}

/// The place of each index in `order` (a permutation of 0..n): the inverse
/// permutation, `rank[order[k]] = k`.
pub(crate) fn ranks(order: &[u32]) -> Vec<u32> {
    let mut rank = vec![0; order.len()];
    for (k, &v) in order.iter().enumerate() {
        rank[v as usize] = k as u32;
    }
    rank
}

/// The low 21 bits of `x` moved to every third bit (bit k to bit 3k).
fn spread(x: u64) -> u64 {
    let mut x = x & 0x1f_ffff;
    x = (x | x << 32) & 0x1f_0000_0000_ffff;
    x = (x | x << 16) & 0x1f_0000_ff00_00ff;
    x = (x | x << 8) & 0x100f_00f0_0f00_f00f;
    x = (x | x << 4) & 0x10c3_0c30_c30c_30c3;
    x = (x | x << 2) & 0x1249_2492_4924_9249;
    x
}

#[cfg(test)]
mod tests {
    use super::{morton_order, spread};
    use crate::Point;

    #[test]
    fn spreading_puts_bit_k_at_bit_3k() {
        for k in 0..21 {
            assert_eq!(spread(1 << k), 1 << (3 * k), "bit {k}");
        }
        assert_eq!(spread(u64::MAX), 0x1249_2492_4924_9249);
    }

    #[test]
    fn the_order_is_a_permutation_that_visits_octants_one_after_another() {
        // A 4 × 4 × 4 grid of points, listed in a scrambled order.
        let mut points: Vec<Point> = (0..64)
            .map(|i| Point::new((i % 4) as f64, (i / 4 % 4) as f64, (i / 16) as f64))
            .collect();
        points.reverse();
        points.swap(3, 40);
        points.push(Point::new(f64::NAN, 0.0, 0.0));
        let order = morton_order(&points);
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..65).collect::<Vec<u32>>());
        // Each run of 8 is one 2 × 2 × 2 octant of the grid (the NaN point sits
        // with the low corner, after the first run's 8 by index order or within).
        let finite: Vec<Point> = order
            .iter()
            .map(|&i| points[i as usize])
            .filter(|p| p.x.is_finite())
            .collect();
        for octant in finite.chunks(8) {
            let corner = octant[0].map(|x| (x / 2.0).floor());
            assert!(
                octant
                    .iter()
                    .all(|p| p.map(|x| (x / 2.0).floor()) == corner),
                "{octant:?}"
            );
        }
        assert_eq!(finite[0], Point::new(0.0, 0.0, 0.0));
        assert_eq!(finite[63], Point::new(3.0, 3.0, 3.0));
    }
}
