//! "Is a feature within this distance?": a uniform grid over segments or points.

use std::collections::HashMap;

use crate::Point;

/// Segments (points are segments of length 0) in a grid of cells, each filed under
/// the cell of its midpoint, for the question whether a point lies within
/// `tolerance` of one of them.
pub(super) struct Near {
    pieces: Vec<[Point; 2]>,
    cells: HashMap<[i64; 3], Vec<u32>>,
    cell: f64,
    tolerance: f64,
}

/// The most pieces the segments are cut into, and the most samples a share is
/// taken from: a tolerance far below the lines' length costs time and memory
/// bounded by this, the pieces and samples then longer than the tolerance asks.
pub(super) const MOST_PIECES: f64 = 1e6;

/// The length of the pieces `length` (the segments' total) is cut into for a
/// tolerance `tolerance`: `tolerance / per_tolerance`, or longer so that there
/// are at most [`MOST_PIECES`].
pub(super) fn piece_length(length: f64, tolerance: f64, per_tolerance: f64) -> f64 {
    (tolerance / per_tolerance).max(length / MOST_PIECES)
}

/// The segment `p q` cut into equal pieces at most `longest` long (one, if it
/// is shorter).
pub(super) fn pieces([p, q]: &[Point; 2], longest: f64) -> impl Iterator<Item = [Point; 2]> + '_ {
    let count = ((q - p).norm() / longest).ceil().max(1.0) as usize;
    let at = move |i: usize| -> Point { p.coords.lerp(&q.coords, i as f64 / count as f64).into() };
    (0..count).map(move |i| [at(i), at(i + 1)])
}

impl Near {
    /// The grid of `segments`, each cut into pieces at most `tolerance` long (or
    /// longer, [`piece_length`]).
    pub(super) fn of_segments(segments: &[[Point; 2]], tolerance: f64) -> Near {
        let total: f64 = segments.iter().map(|[p, q]| (q - p).norm()).sum();
        let longest = piece_length(total, tolerance, 1.0);
        let pieces = segments
            .iter()
            .flat_map(|segment| pieces(segment, longest))
            .collect();
        // A point within `tolerance` of a piece at most `longest` long is within
        // tolerance + longest / 2 of its midpoint: the 27 cells around the
        // point's hold it.
        Near::of_pieces(pieces, tolerance + 0.5 * longest, tolerance)
    }

    /// The grid of `points`.
    pub(super) fn of_points(points: &[Point], tolerance: f64) -> Near {
        Near::of_pieces(
            points.iter().map(|&p| [p, p]).collect(),
            tolerance,
            tolerance,
        )
    }

    /// The grid of `pieces` with cells `cell` wide.
    fn of_pieces(pieces: Vec<[Point; 2]>, cell: f64, tolerance: f64) -> Near {
        let mut cells: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
        for (index, [p, q]) in pieces.iter().enumerate() {
            let midpoint = p.coords.lerp(&q.coords, 0.5).into();
            let index = u32::try_from(index).expect("fewer than 2³² pieces");
            cells
                .entry(cell_of(&midpoint, cell))
                .or_default()
                .push(index);
        }
        Near {
            pieces,
            cells,
            cell,
            tolerance,
        }
    }

    /// Whether `point` lies within the tolerance of one of the pieces.
    pub(super) fn within(&self, point: &Point) -> bool {
        let [i, j, k] = cell_of(point, self.cell);
        let neighbours = (-1..=1).flat_map(|di| {
            (-1..=1).flat_map(move |dj| (-1..=1).map(move |dk| [i + di, j + dj, k + dk]))
        });
        neighbours
            .filter_map(|key| self.cells.get(&key))
            .flatten()
            .any(|&index| {
                let [p, q] = &self.pieces[index as usize];
                distance_to_segment(point, p, q) <= self.tolerance
            })
    }
}

/// The cell of side `cell` holding `point`.
fn cell_of(point: &Point, cell: f64) -> [i64; 3] {
    [point.x, point.y, point.z].map(|x| (x / cell).floor() as i64)
}

/// The distance from `point` to the segment `p q` (to `p` when they coincide).
pub(super) fn distance_to_segment(point: &Point, p: &Point, q: &Point) -> f64 {
    let along = q - p;
    let squared = along.norm_squared();
    let t = if squared > 0.0 {
        ((point - p).dot(&along) / squared).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (point - (p + along * t)).norm()
}
