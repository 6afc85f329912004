//! Drawings for pen plotters: every stroke drawn once, strokes joined where their
//! ends meet, and the strokes of each layer ordered and turned so that the pen
//! travels little in the air.
//!
//! 1. Duplicates ([`without_duplicates`], on the densely sampled pieces before
//!    simplification): in plotting order, the runs of a piece that lie along a stroke
//!    already kept (closer than [`DUPLICATE_DISTANCE`] and within
//!    [`PARALLEL_ANGLE`](super::PARALLEL_ANGLE) of parallel, over at least
//!    [`SHORTEST_DUPLICATE`]) are dropped: a silhouette traced twice is drawn once.
//!    Shorter runs, where two strokes meet end to end or cross, are kept.
//! 2. Joining ([`join_ends`]): within a layer, open strokes whose ends lie closer
//!    than [`JOIN_DISTANCE`] are chained into one, turned as needed (vpype's
//!    `linemerge` joins at 0.05 mm, which these pixels exceed on any page).
//! 3. Ordering ([`plotting_order`]): from where the pen is (the origin, then the end
//!    of the previous layer), the stroke with the nearest end next, turned to start
//!    there (a closed stroke starts at its nearest point), as vpype's `linesort`
//!    does, then improved by exchanging the ends of runs of strokes (2-opt) while
//!    that shortens the travel.
//!
//! Points are first put on the SVG's grid of hundredths of a pixel, so that what
//! is ordered is what is written.

use std::collections::HashMap;

use crate::lines::LineKind;

use super::duplicates::{clear_of, SilhouetteIndex};
use super::{Drawing, ScreenPath};

/// Strokes closer than this (pixels) and parallel are the same stroke drawn twice.
pub const DUPLICATE_DISTANCE: f64 = 1.0;

/// Runs along another stroke shorter than this (pixels) are kept: ends meeting and
/// crossings.
pub const SHORTEST_DUPLICATE: f64 = 1.0;

/// Ends closer than this (pixels) are joined.
pub const JOIN_DISTANCE: f64 = 1.0;

/// Passes of 2-opt over a layer at most.
const TWO_OPT_PASSES: usize = 20;

/// Layers of more strokes than this are ordered greedily only (2-opt is quadratic
/// per pass).
const TWO_OPT_MOST_STROKES: usize = 2000;

/// Drops from the dense `pieces` of every kind (in plotting order) the runs that lie
/// along a stroke kept before them ([`DUPLICATE_DISTANCE`], [`SHORTEST_DUPLICATE`]).
pub(crate) fn without_duplicates(pieces: &mut [(LineKind, Vec<ScreenPath>)]) {
    let mut kept = SilhouetteIndex::new(std::iter::empty(), DUPLICATE_DISTANCE);
    for (_, paths) in pieces.iter_mut() {
        let mut unique = Vec::with_capacity(paths.len());
        for path in paths.drain(..) {
            for piece in clear_of(&path, &kept, DUPLICATE_DISTANCE, SHORTEST_DUPLICATE) {
                kept.insert_path(&piece);
                unique.push(piece);
            }
        }
        *paths = unique;
    }
}

/// Joins and orders the strokes of every layer of `drawing` for a pen plotter (see
/// the module documentation). Per-point depths and facings are dropped: a pen
/// draws every stroke alike.
pub fn for_plotter(drawing: &mut Drawing) {
    let mut pen = [0.0, 0.0];
    for group in &mut drawing.groups {
        let strokes: Vec<Stroke> = group.paths.drain(..).map(Stroke::from).collect();
        let ordered = plotting_order(join_ends(strokes), pen);
        if let Some(last) = ordered.last() {
            pen = last.end();
        }
        group.paths = ordered.into_iter().map(Stroke::into_path).collect();
    }
}

/// A stroke being joined and ordered.
#[derive(Clone, Debug)]
struct Stroke {
    points: Vec<[f64; 2]>,
    closed: bool,
    strength: f64,
}

impl From<ScreenPath> for Stroke {
    fn from(path: ScreenPath) -> Stroke {
        let mut points: Vec<[f64; 2]> = path.points.iter().map(|p| p.map(on_grid)).collect();
        points.dedup();
        Stroke {
            points,
            closed: path.closed,
            strength: path.strength,
        }
    }
}

impl Stroke {
    fn start(&self) -> [f64; 2] {
        self.points[0]
    }

    fn end(&self) -> [f64; 2] {
        if self.closed {
            self.points[0]
        } else {
            self.points[self.points.len() - 1]
        }
    }

    fn into_path(self) -> ScreenPath {
        ScreenPath {
            points: self.points,
            depths: Vec::new(),
            facings: Vec::new(),
            closed: self.closed,
            strength: self.strength,
        }
    }
}

/// `x` on the grid of hundredths the SVG writes.
fn on_grid(x: f64) -> f64 {
    (x * 100.0).round() / 100.0
}

fn distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    (b[0] - a[0]).hypot(b[1] - a[1])
}

/// A point and its key.
type Keyed = ([f64; 2], usize);

/// Points bucketed in square cells, each with a key, for nearest-point queries
/// that skip removed keys.
struct PointGrid {
    cell: f64,
    cells: HashMap<(i64, i64), Vec<Keyed>>,
    /// The bounding cells of every point inserted.
    low: (i64, i64),
    high: (i64, i64),
}

impl PointGrid {
    fn new(cell: f64) -> PointGrid {
        PointGrid {
            cell,
            cells: HashMap::new(),
            low: (i64::MAX, i64::MAX),
            high: (i64::MIN, i64::MIN),
        }
    }

    fn cell_of(&self, p: [f64; 2]) -> (i64, i64) {
        (
            (p[0] / self.cell).floor() as i64,
            (p[1] / self.cell).floor() as i64,
        )
    }

    fn insert(&mut self, p: [f64; 2], key: usize) {
        let c = self.cell_of(p);
        self.low = (self.low.0.min(c.0), self.low.1.min(c.1));
        self.high = (self.high.0.max(c.0), self.high.1.max(c.1));
        self.cells.entry(c).or_default().push((p, key));
    }

    /// The nearest point to `p` whose key `alive` accepts, with its key, looking
    /// in growing rings of cells until no nearer point can be found; ties go to the
    /// smaller key.
    fn nearest(&self, p: [f64; 2], alive: impl Fn(usize) -> bool) -> Option<Keyed> {
        let (ci, cj) = self.cell_of(p);
        let reach = (ci - self.low.0)
            .abs()
            .max((self.high.0 - ci).abs())
            .max((cj - self.low.1).abs())
            .max((self.high.1 - cj).abs());
        let mut best: Option<(f64, [f64; 2], usize)> = None;
        for ring in 0..=reach {
            if let Some((d, ..)) = best {
                if d < (ring - 1).max(0) as f64 * self.cell {
                    break;
                }
            }
            for (i, j) in ring_cells(ci, cj, ring) {
                for &(q, key) in self.cells.get(&(i, j)).into_iter().flatten() {
                    if !alive(key) {
                        continue;
                    }
                    let d = distance(p, q);
                    if best.is_none_or(|(bd, _, bk)| d < bd || (d == bd && key < bk)) {
                        best = Some((d, q, key));
                    }
                }
            }
        }
        best.map(|(_, q, key)| (q, key))
    }
}

/// The cells at Chebyshev distance `ring` from `(ci, cj)`.
fn ring_cells(ci: i64, cj: i64, ring: i64) -> impl Iterator<Item = (i64, i64)> {
    (ci - ring..=ci + ring)
        .flat_map(move |i| (cj - ring..=cj + ring).map(move |j| (i, j)))
        .filter(move |&(i, j)| (i - ci).abs() == ring || (j - cj).abs() == ring)
}

/// A cell size for `count` points spread over the box of `strokes`: a few points
/// per cell.
fn cell_size(strokes: &[Stroke], count: usize) -> f64 {
    let (mut low, mut high) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in strokes.iter().flat_map(|s| [s.start(), s.end()]) {
        low = [low[0].min(p[0]), low[1].min(p[1])];
        high = [high[0].max(p[0]), high[1].max(p[1])];
    }
    let area = ((high[0] - low[0]) * (high[1] - low[1])).max(1.0);
    (area / count.max(1) as f64).sqrt().max(JOIN_DISTANCE)
}

/// The open strokes of `strokes` chained where an end lies within
/// [`JOIN_DISTANCE`] of another's, nearest first; closed strokes as they are.
fn join_ends(strokes: Vec<Stroke>) -> Vec<Stroke> {
    let mut grid = PointGrid::new(cell_size(&strokes, 2 * strokes.len()));
    for (n, stroke) in strokes.iter().enumerate().filter(|(_, s)| !s.closed) {
        grid.insert(stroke.start(), 2 * n);
        grid.insert(stroke.end(), 2 * n + 1);
    }
    let mut used = vec![false; strokes.len()];
    let mut joined = Vec::with_capacity(strokes.len());
    for n in 0..strokes.len() {
        if used[n] {
            continue;
        }
        used[n] = true;
        let mut chain = strokes[n].clone();
        if !chain.closed {
            extend(&mut chain, &strokes, &grid, &mut used);
            chain.points.reverse();
            extend(&mut chain, &strokes, &grid, &mut used);
        }
        joined.push(chain);
    }
    joined
}

/// Appends to the end of `chain` the unused strokes whose nearest end lies within
/// [`JOIN_DISTANCE`] of it, one after the other.
fn extend(chain: &mut Stroke, strokes: &[Stroke], grid: &PointGrid, used: &mut [bool]) {
    loop {
        let end = chain.end();
        let Some((at, key)) = grid.nearest(end, |key| !used[key / 2]) else {
            return;
        };
        if distance(end, at) > JOIN_DISTANCE {
            return;
        }
        let next = &strokes[key / 2];
        used[key / 2] = true;
        let mut points = next.points.clone();
        if key % 2 == 1 {
            points.reverse();
        }
        let skip = usize::from(points[0] == end);
        chain.points.extend_from_slice(&points[skip..]);
        chain.strength = chain.strength.max(next.strength);
    }
}

/// `strokes` in the order a pen starting at `pen` draws them: greedily the nearest
/// stroke end next (turned, or a closed stroke started at its nearest point), then
/// 2-opt.
fn plotting_order(strokes: Vec<Stroke>, pen: [f64; 2]) -> Vec<Stroke> {
    // Keys: open strokes by their two ends (2n, 2n + 1), closed strokes by their
    // points (2n, with the point found again by position).
    let mut grid = PointGrid::new(cell_size(&strokes, 2 * strokes.len()));
    for (n, stroke) in strokes.iter().enumerate() {
        if stroke.closed {
            stroke.points.iter().for_each(|&p| grid.insert(p, 2 * n));
        } else {
            grid.insert(stroke.start(), 2 * n);
            grid.insert(stroke.end(), 2 * n + 1);
        }
    }
    let mut used = vec![false; strokes.len()];
    let mut ordered = Vec::with_capacity(strokes.len());
    let mut at = pen;
    while let Some((point, key)) = grid.nearest(at, |key| !used[key / 2]) {
        used[key / 2] = true;
        let mut stroke = strokes[key / 2].clone();
        if stroke.closed {
            let first = stroke.points.iter().position(|&p| p == point).unwrap_or(0);
            stroke.points.rotate_left(first);
        } else if key % 2 == 1 {
            stroke.points.reverse();
        }
        at = stroke.end();
        ordered.push(stroke);
    }
    if ordered.len() <= TWO_OPT_MOST_STROKES {
        two_opt(&mut ordered);
    }
    ordered
}

/// Shortens the pen's travel over `strokes` by reversing runs of strokes (each
/// stroke in the run turned) while a reversal shortens it, for at most
/// [`TWO_OPT_PASSES`] passes. The first stroke stays first, so the travel between
/// the strokes is never longer than the greedy order's from it (vpype's
/// `linesort`); closed strokes keep their start.
fn two_opt(strokes: &mut [Stroke]) {
    let n = strokes.len();
    for _ in 0..TWO_OPT_PASSES {
        let mut improved = false;
        for i in 1..n {
            for j in i..n {
                let before = strokes[i - 1].end();
                let after = strokes.get(j + 1).map(Stroke::start);
                let now = distance(before, strokes[i].start())
                    + after.map_or(0.0, |a| distance(strokes[j].end(), a));
                let then = distance(before, strokes[j].end())
                    + after.map_or(0.0, |a| distance(strokes[i].start(), a));
                if then < now - 1e-9 {
                    strokes[i..=j].reverse();
                    for stroke in &mut strokes[i..=j] {
                        if !stroke.closed {
                            stroke.points.reverse();
                        }
                    }
                    improved = true;
                }
            }
        }
        if !improved {
            break;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn open(points: &[[f64; 2]]) -> Stroke {
        Stroke {
            points: points.to_vec(),
            closed: false,
            strength: 1.0,
        }
    }

    fn travel(strokes: &[Stroke]) -> f64 {
        strokes
            .windows(2)
            .map(|w| distance(w[0].end(), w[1].start()))
            .sum()
    }

    #[test]
    fn pieces_meeting_end_to_end_in_any_direction_become_one_stroke() {
        // A zigzag cut in four pieces, shuffled, two of them turned around, with
        // gaps of 0, 0.5 and 0.9 pixels.
        let pieces = vec![
            open(&[[30.0, 10.0], [20.0, 0.0]]),
            open(&[[0.0, 0.0], [10.0, 10.0]]),
            open(&[[30.9, 10.0], [40.0, 0.0]]),
            open(&[[10.0, 10.5], [20.0, 0.0]]),
            open(&[[100.0, 100.0], [110.0, 100.0]]),
        ];
        let mut joined = join_ends(pieces);
        assert_eq!(joined.len(), 2);
        joined.sort_by_key(|s| std::cmp::Reverse(s.points.len()));
        let zigzag = &joined[0].points;
        let ends = [zigzag[0], zigzag[zigzag.len() - 1]];
        assert!(
            ends.contains(&[0.0, 0.0]) && ends.contains(&[40.0, 0.0]),
            "{zigzag:?}"
        );
        // The shared point [20, 0] is written once.
        assert_eq!(zigzag.iter().filter(|&&p| p == [20.0, 0.0]).count(), 1);
        assert_eq!(zigzag.len(), 7);
    }

    #[test]
    fn strokes_are_taken_nearest_end_first_around_a_circle() {
        // Short strokes on a circle, shuffled and each turned at random.
        let strokes: Vec<Stroke> = (0..60)
            .map(|n| (n * 7) % 60)
            .map(|k| {
                let (a, b) = (k as f64 * 0.1, k as f64 * 0.1 + 0.05);
                let p = |t: f64| [500.0 + 400.0 * t.cos(), 500.0 + 400.0 * t.sin()];
                if k % 3 == 0 {
                    open(&[p(b), p(a)])
                } else {
                    open(&[p(a), p(b)])
                }
            })
            .collect();
        let before = travel(&strokes);
        let ordered = plotting_order(strokes.clone(), [900.0, 500.0]);
        assert_eq!(ordered.len(), strokes.len());
        // Around the circle: every hop is the gap between neighbouring strokes.
        let hops: Vec<f64> = ordered
            .windows(2)
            .map(|w| distance(w[0].end(), w[1].start()))
            .collect();
        assert!(hops.iter().all(|&h| h < 25.0), "{hops:?}");
        assert!(travel(&ordered) < 0.1 * before);
        // The first stroke is the one nearest the pen, started at its nearer end.
        assert_eq!(ordered[0].start(), [900.0, 500.0]);
    }

    #[test]
    fn a_closed_stroke_starts_where_the_pen_is_nearest() {
        let square = Stroke {
            points: vec![[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]],
            closed: true,
            strength: 1.0,
        };
        let ordered = plotting_order(vec![square], [12.0, 11.0]);
        assert_eq!(ordered[0].points[0], [10.0, 10.0]);
        assert_eq!(ordered[0].end(), [10.0, 10.0]);
    }
}
