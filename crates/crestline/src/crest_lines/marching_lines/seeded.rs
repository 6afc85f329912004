//! The randomized Marching Lines (Thirion & Gourdon 1993, §4 and §5): cells drawn
//! at random, and the lines through them followed from cell to cell, instead of
//! visiting every cell.
//!
//! Seeds are drawn uniformly among the cells the isosurface crosses (the only cells
//! a line can pass through), so a line is found with a probability that grows with
//! the number of cells it crosses: "with very few seeds, the lines are extracted
//! roughly in the order corresponding to decreasing length" (§5). A line is
//! followed through the face of each of its end points into the neighbouring cell,
//! whose segments are computed exactly as the extensive sweep computes them, so
//! every line found is a line of [`marching_lines`](super::marching_lines()), point
//! for point.

use std::collections::{HashMap, HashSet};

use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use rayon::prelude::*;

use super::{cell, chain, check_levels, BiIsoLine, PointKey, SecondField, Segment, SLAB_LAYERS};
use crate::volume::grid::Grid;
use crate::volume::Volume;
use crate::Result;

/// The lines through `seeds` cells drawn at random (by a generator seeded with
/// `rng_seed`, so the result is reproducible) among the cells the isosurface
/// `f = level` crosses, for the second field `field` at `g_level`, longest first:
/// the randomized Marching Lines (Thirion & Gourdon 1993, §5). Seeds are drawn
/// uniformly among the crossed cells, so a line is found with a probability that
/// grows with the number of cells it crosses; every line found is a line of
/// [`marching_lines`](super::marching_lines()), point for point. With at least
/// as many seeds as crossed cells, every cell is a seed once: every line is found.
///
/// Errors as [`marching_lines`](super::marching_lines()).
pub fn seeded_marching_lines(
    volume: &Volume,
    level: f64,
    field: &impl SecondField,
    g_level: f64,
    seeds: usize,
    rng_seed: u64,
) -> Result<Vec<BiIsoLine>> {
    check_levels(volume, level, g_level)?;
    let candidates = crossed_cells(volume, level);
    if candidates.is_empty() {
        return Ok(Vec::new());
    }
    let mut walker = Walker {
        volume,
        levels: (level, g_level),
        field,
        segments: HashMap::new(),
        used: HashSet::new(),
    };
    let mut rng = StdRng::seed_from_u64(rng_seed);
    // As many seeds as crossed cells or more: every cell once, so that the work
    // is bounded by the surface, not by the number asked for.
    let all_cells = seeds >= candidates.len();
    let drawn = (0..seeds.min(candidates.len())).map(|i| match all_cells {
        true => candidates[i],
        false => candidates[rng.random_range(0..candidates.len())],
    });
    let mut lines = Vec::new();
    for seed in drawn {
        for n in 0..walker.segments_of(seed).len() {
            if walker.used.insert((seed, n)) {
                lines.extend(chain::chain(&walker.follow(seed, n)));
            }
        }
    }
    let mut measured: Vec<(f64, BiIsoLine)> = lines.into_iter().map(|l| (length(&l), l)).collect();
    measured.sort_by(|a, b| b.0.total_cmp(&a.0));
    Ok(measured.into_iter().map(|(_, line)| line).collect())
}

/// The length of a line, with the closing segment of a loop.
fn length(line: &BiIsoLine) -> f64 {
    let n = line.points.len();
    let pieces = if line.closed { n } else { n.saturating_sub(1) };
    (0..pieces)
        .map(|i| (line.points[(i + 1) % n] - line.points[i]).norm())
        .sum()
}

/// The cells (lowest corners) the isosurface `f = level` crosses, in cell order.
fn crossed_cells(volume: &Volume, level: f64) -> Vec<[usize; 3]> {
    let grid = volume.grid();
    let layers = grid.cell_layers();
    (0..layers)
        .into_par_iter()
        .step_by(SLAB_LAYERS)
        .flat_map_iter(|first| {
            let cells = grid.cells(first..(first + SLAB_LAYERS).min(layers));
            cells.filter(|&cell| {
                let f = grid.corners(cell).map(|at| f64::from(volume.samples()[at]));
                cell::crossed(&f, level)
            })
        })
        .collect()
}

/// Follows lines from cell to cell, computing each cell's segments once.
struct Walker<'a, F> {
    volume: &'a Volume,
    levels: (f64, f64),
    field: &'a F,
    /// The kept segments of each cell visited so far.
    segments: HashMap<[usize; 3], Vec<Segment>>,
    /// The segments already on a line, as (cell, number in the cell).
    used: HashSet<([usize; 3], usize)>,
}

impl<F: SecondField> Walker<'_, F> {
    /// The segments of `cell`, computed on first use.
    fn segments_of(&mut self, cell: [usize; 3]) -> &[Segment] {
        let (volume, levels, field) = (self.volume, self.levels, self.field);
        self.segments.entry(cell).or_insert_with(|| {
            let mut segments = Vec::new();
            cell::push_cell(volume, levels, field, cell, &mut segments);
            segments
        })
    }

    /// The segments of the line through segment `n` of `cell`: from each end point,
    /// into the cell across that point's face, while that cell has an unused
    /// segment ending at the same point.
    fn follow(&mut self, cell: [usize; 3], n: usize) -> Vec<Segment> {
        let first = self.segments_of(cell)[n];
        let mut line = vec![first];
        let mut open: Vec<([usize; 3], PointKey)> = first.keys.map(|key| (cell, key)).to_vec();
        while let Some((from, key)) = open.pop() {
            let Some(next) = across(self.volume.grid(), from, key) else {
                continue;
            };
            let segments = self.segments_of(next).to_vec();
            for (m, segment) in segments.into_iter().enumerate() {
                if segment.keys.contains(&key) && self.used.insert((next, m)) {
                    line.push(segment);
                    let other = segment.keys[usize::from(segment.keys[0] == key)];
                    open.push((next, other));
                }
            }
        }
        line
    }
}

/// The cell that shares with `cell` the face holding point `key` (both of the
/// point's grid edges lie in that face), or `None` at the border of the grid.
fn across(grid: Grid, cell: [usize; 3], key: PointKey) -> Option<[usize; 3]> {
    let ((p, a), (q, b)) = (grid.unkey(key[0]), grid.unkey(key[1]));
    let normal = (0..3).find(|&n| n != a && n != b && p[n] == q[n])?;
    let plane = p[normal];
    let mut next = cell;
    if cell[normal] == plane {
        next[normal] = plane.checked_sub(1)?;
    } else if plane + 1 < grid.dims[normal] {
        next[normal] = plane;
    } else {
        return None;
    }
    Some(next)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_leads_across_the_face_of_its_two_edges() {
        let grid = Grid { dims: [4; 3] };
        let edge = |p, axis| grid.key(p, axis);
        // An x edge and a y edge of the face z = 2 of cell (1, 1, 1): its top face.
        let top = [edge([1, 1, 2], 0), edge([1, 1, 2], 1)];
        assert_eq!(across(grid, [1, 1, 1], top), Some([1, 1, 2]));
        assert_eq!(across(grid, [1, 1, 2], top), Some([1, 1, 1]));
        // Two parallel x edges of the face y = 1 (its front face).
        let front = [edge([1, 1, 1], 0), edge([1, 1, 2], 0)];
        assert_eq!(across(grid, [1, 1, 1], front), Some([1, 0, 1]));
        // The faces of the grid's border lead nowhere.
        let bottom = [edge([0, 0, 0], 0), edge([0, 0, 0], 1)];
        assert_eq!(across(grid, [0, 0, 0], bottom), None);
        let far = [edge([2, 2, 3], 0), edge([2, 2, 3], 1)];
        assert_eq!(across(grid, [2, 2, 2], far), None);
    }
}
