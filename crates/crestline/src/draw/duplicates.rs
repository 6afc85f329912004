//! View-dependent cleanup: where a feature line runs beside a visible silhouette,
//! the silhouette already shows that crest (a ridge seen edge-on is an outline), so
//! the feature line's samples there are dropped. Samples that cross a silhouette
//! or merely approach it at an angle are kept, and so is everything farther away.

use std::collections::HashMap;

use crate::lines::LineKind;

use super::simplify::distance_to_chord;
use super::ScreenPath;

/// Whether lines of `kind` are cleared from beside the silhouettes: the crest
/// lines (ridges, valleys, Morse-Smale cells, crests of images) and creases, not
/// the silhouettes themselves, borders or suggestive contours (which by
/// definition keep away from silhouettes).
pub fn runs_along_outlines(kind: LineKind) -> bool {
    matches!(
        kind,
        LineKind::Ridge
            | LineKind::Valley
            | LineKind::Ascending
            | LineKind::Descending
            | LineKind::Crest
            | LineKind::Crease
    )
}

/// Feature-line samples within the clearance of a silhouette are dropped only when
/// the two run within this angle of each other (degrees).
pub const PARALLEL_ANGLE: f64 = 30.0;

/// The local direction of a feature line is taken over this many pixels on each
/// side of a sample, so that pixel-scale wiggles do not decide it.
const DIRECTION_REACH: f64 = 2.0;

/// The segments of strokes (the visible silhouettes, or the strokes a plotter
/// keeps), bucketed in square cells of the clearance's size so that a query looks
/// at 3 × 3 cells.
pub struct SilhouetteIndex {
    cell: f64,
    segments: Vec<[[f64; 2]; 2]>,
    cells: HashMap<(i64, i64), Vec<usize>>,
}

impl SilhouetteIndex {
    /// Indexes the segments of `paths` (closed paths include their closing
    /// segment) for queries up to `clearance` pixels away.
    pub fn new<'a>(paths: impl IntoIterator<Item = &'a ScreenPath>, clearance: f64) -> Self {
        let mut index = SilhouetteIndex {
            cell: clearance.max(1.0),
            segments: Vec::new(),
            cells: HashMap::new(),
        };
        for path in paths {
            index.insert_path(path);
        }
        index
    }

    /// Adds the segments of `path` (a closed path's closing segment too).
    pub(crate) fn insert_path(&mut self, path: &ScreenPath) {
        let closing = match (path.closed, path.points.first(), path.points.last()) {
            (true, Some(&first), Some(&last)) => Some([last, first]),
            _ => None,
        };
        let segments = path.points.windows(2).map(|w| [w[0], w[1]]);
        for segment in segments.chain(closing) {
            self.insert(segment);
        }
    }

    fn insert(&mut self, segment: [[f64; 2]; 2]) {
        let id = self.segments.len();
        self.segments.push(segment);
        let [a, b] = segment;
        let (lo, hi) = (
            self.cell_of([a[0].min(b[0]), a[1].min(b[1])]),
            self.cell_of([a[0].max(b[0]), a[1].max(b[1])]),
        );
        for i in lo.0..=hi.0 {
            for j in lo.1..=hi.1 {
                self.cells.entry((i, j)).or_default().push(id);
            }
        }
    }

    fn cell_of(&self, p: [f64; 2]) -> (i64, i64) {
        (
            (p[0] / self.cell).floor() as i64,
            (p[1] / self.cell).floor() as i64,
        )
    }

    /// Whether a silhouette segment within `clearance` of `p` runs within
    /// [`PARALLEL_ANGLE`] of the unit `direction`.
    fn runs_beside(&self, p: [f64; 2], direction: [f64; 2], clearance: f64) -> bool {
        let cos_max = PARALLEL_ANGLE.to_radians().cos();
        let (ci, cj) = self.cell_of(p);
        (ci - 1..=ci + 1)
            .flat_map(|i| (cj - 1..=cj + 1).map(move |j| (i, j)))
            .filter_map(|cell| self.cells.get(&cell))
            .flatten()
            .any(|&id| {
                let [a, b] = self.segments[id];
                let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
                let length = dx.hypot(dy);
                length > 0.0
                    && distance_to_chord(&p, &a, &b) <= clearance
                    && (dx * direction[0] + dy * direction[1]).abs() >= cos_max * length
            })
    }
}

/// The parts of `path` (densely sampled, before simplification) that do not run
/// beside a silhouette of `index` within `clearance` pixels. Where samples are
/// dropped, the pieces left between dropped stretches are kept only if they are at
/// least twice the clearance long, so no specks remain along an outline. A path
/// with nothing dropped is returned whole.
pub fn clear_of_silhouettes(
    path: &ScreenPath,
    index: &SilhouetteIndex,
    clearance: f64,
) -> Vec<ScreenPath> {
    let beside = beside(path, index, clearance);
    if !beside.contains(&true) {
        return vec![path.clone()];
    }
    kept_pieces(path, &beside, 2.0 * clearance)
}

/// The parts of `path` (densely sampled) left when its runs beside a stroke of
/// `index` within `clearance` pixels are dropped, those runs at least `shortest`
/// pixels long only: shorter ones (where strokes meet end to end or cross) stay. A
/// path with nothing dropped is returned whole.
pub(crate) fn clear_of(
    path: &ScreenPath,
    index: &SilhouetteIndex,
    clearance: f64,
    shortest: f64,
) -> Vec<ScreenPath> {
    let mut beside = beside(path, index, clearance);
    let points = &path.points;
    let mut start = 0;
    while start < beside.len() {
        let end = (start..beside.len())
            .find(|&i| beside[i] != beside[start])
            .unwrap_or(beside.len());
        if beside[start] && length(&points[start..end]) < shortest {
            beside[start..end].fill(false);
        }
        start = end;
    }
    if !beside.contains(&true) {
        return vec![path.clone()];
    }
    kept_pieces(path, &beside, 0.0)
}

/// Whether each sample of `path` runs beside a stroke of `index` within
/// `clearance`.
fn beside(path: &ScreenPath, index: &SilhouetteIndex, clearance: f64) -> Vec<bool> {
    let points = &path.points;
    (0..points.len())
        .map(|i| index.runs_beside(points[i], direction_at(points, i), clearance))
        .collect()
}

/// The runs of `path` between the samples flagged in `dropped`, as open paths,
/// those at least `shortest` pixels long.
fn kept_pieces(path: &ScreenPath, dropped: &[bool], shortest: f64) -> Vec<ScreenPath> {
    let points = &path.points;
    let piece = |range: std::ops::Range<usize>| ScreenPath {
        points: points[range.clone()].to_vec(),
        // Paths made without depths or facings keep none.
        depths: path.depths.get(range.clone()).unwrap_or_default().to_vec(),
        facings: path.facings.get(range.clone()).unwrap_or_default().to_vec(),
        closed: false,
        strength: path.strength,
    };
    let mut pieces = Vec::new();
    let mut start = 0;
    for (i, &dropped) in dropped.iter().chain([&true]).enumerate() {
        if dropped {
            if i > start + 1 && length(&points[start..i]) >= shortest {
                pieces.push(piece(start..i));
            }
            start = i + 1;
        }
    }
    pieces
}

/// The unit direction of the polyline at sample `i`, from the samples about
/// [`DIRECTION_REACH`] pixels before and after it (the ends clamped).
fn direction_at(points: &[[f64; 2]], i: usize) -> [f64; 2] {
    let reach = |range: &mut dyn Iterator<Item = usize>| {
        let mut last = i;
        for j in range {
            last = j;
            if distance(points[i], points[j]) >= DIRECTION_REACH {
                break;
            }
        }
        points[last]
    };
    let before = reach(&mut (0..i).rev());
    let after = reach(&mut (i + 1..points.len()));
    let (dx, dy) = (after[0] - before[0], after[1] - before[1]);
    let norm = dx.hypot(dy);
    if norm > 0.0 {
        [dx / norm, dy / norm]
    } else {
        [0.0, 0.0]
    }
}

fn distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    (b[0] - a[0]).hypot(b[1] - a[1])
}

/// The length of a polyline.
fn length(points: &[[f64; 2]]) -> f64 {
    points.windows(2).map(|w| distance(w[0], w[1])).sum()
}
