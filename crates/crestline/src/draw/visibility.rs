//! Hidden-line removal: a line is resampled finely on the canvas, each sample is
//! tested against the [`DepthBuffer`], and the runs of visible samples become the
//! pieces that are drawn.

use crate::lines::Polyline;
use crate::Point;

use super::camera::Camera;
use super::depth::DepthBuffer;
use super::{ScreenPath, FACING};

/// The visible pieces of `line` on the canvas. Samples are taken along each segment
/// (interpolated in 3D, then projected) at most `spacing` pixels apart; a sample
/// is visible if it lies on the canvas and passes [`DepthBuffer::is_visible`] with
/// `tolerance` (mesh units). Every run of at least two visible samples is a piece;
/// a closed line seen whole stays closed. Pieces carry the line's strength.
pub fn visible_pieces(
    line: &Polyline,
    camera: &Camera,
    buffer: &DepthBuffer,
    tolerance: f64,
    spacing: f64,
) -> Vec<ScreenPath> {
    let facing = line
        .values
        .get(FACING)
        .filter(|f| f.len() == line.points.len());
    let seen: Vec<Option<Sample>> = samples(line, facing, camera, spacing)
        .into_iter()
        .map(|(p, facing)| {
            let s = camera.project(&p)?;
            let inside = (0.0..=f64::from(camera.width())).contains(&s.x)
                && (0.0..=f64::from(camera.height())).contains(&s.y);
            (inside && buffer.is_visible(&s, tolerance)).then_some(Sample {
                point: [s.x, s.y],
                depth: s.depth,
                facing,
            })
        })
        .collect();
    let piece = |run: Vec<Sample>, closed: bool| ScreenPath {
        points: run.iter().map(|s| s.point).collect(),
        depths: run.iter().map(|s| s.depth).collect(),
        facings: match facing {
            Some(_) => run.iter().map(|s| s.facing).collect(),
            None => Vec::new(),
        },
        closed,
        strength: line.strength,
    };
    if line.closed && seen.iter().all(Option::is_some) {
        return vec![piece(seen.into_iter().flatten().collect(), true)];
    }
    // A closed line is read from a hidden sample, so no run wraps around the end.
    let start = if line.closed {
        seen.iter().position(Option::is_none).unwrap_or(0)
    } else {
        0
    };
    let mut pieces = Vec::new();
    let mut run: Vec<Sample> = Vec::new();
    for sample in seen[start..].iter().chain(&seen[..start]) {
        match sample {
            Some(point) => run.push(*point),
            None => close_run(&mut run, &mut pieces, &piece),
        }
    }
    close_run(&mut run, &mut pieces, &piece);
    pieces
}

/// Move the current run into `pieces` if it has a segment, and start a new one.
fn close_run(
    run: &mut Vec<Sample>,
    pieces: &mut Vec<ScreenPath>,
    piece: &impl Fn(Vec<Sample>, bool) -> ScreenPath,
) {
    let points = std::mem::take(run);
    if points.len() >= 2 {
        pieces.push(piece(points, false));
    }
}

/// A visible sample of a line on the canvas.
#[derive(Clone, Copy)]
struct Sample {
    point: [f64; 2],
    depth: f64,
    facing: f64,
}

/// Points along `line`, at most about `spacing` pixels apart on the canvas, with
/// the line's `facing` value interpolated there (0 without one). The last point of
/// an open line is included; a closed line ends just before its first point.
///
/// Bounded work: a segment gets at most as many samples as the canvas diagonal
/// needs (the most of any segment that can be seen on the canvas), so a segment
/// reaching far off the canvas (a huge triangle's silhouette, a point near a
/// perspective camera's eye) is sampled more sparsely instead of without bound.
fn samples(
    line: &Polyline,
    facing: Option<&Vec<f64>>,
    camera: &Camera,
    spacing: f64,
) -> Vec<(Point, f64)> {
    let diagonal = f64::from(camera.width()).hypot(f64::from(camera.height()));
    let max_samples = (diagonal / spacing).ceil().max(1.0);
    let n = line.points.len();
    let facing_at = |i: usize| facing.map_or(0.0, |f| f[i % n]);
    let mut points = Vec::with_capacity(n);
    for (i, (a, b)) in line.segments().enumerate() {
        let pixels = match (camera.project(a), camera.project(b)) {
            (Some(pa), Some(pb)) => (pb.x - pa.x).hypot(pb.y - pa.y),
            _ => 0.0,
        };
        let count = (pixels / spacing).ceil().clamp(1.0, max_samples) as usize;
        let (fa, fb) = (facing_at(i), facing_at(i + 1));
        points.extend((0..count).map(|k| {
            let t = k as f64 / count as f64;
            (a + (b - a) * t, fa + (fb - fa) * t)
        }));
    }
    if !line.closed {
        points.extend(line.points.last().map(|&p| (p, facing_at(n - 1))));
    }
    points
}
