//! Anatomical landmarks from crest lines (Thirion & Gourdon 1993, the applications
//! of the Marching Lines; Thirion's "extremal points"): points where something
//! happens along a ridge or valley line, and a descriptor of every line.
//!
//! From lines of kind [`LineKind::Ridge`] (crests of `k_max`, convex) and
//! [`LineKind::Valley`] (crests of `k_min`, concave), traced on meshes or on the
//! isosurfaces of images, with their per-point values (`k_max`, `k_min`, and
//! `e_max`, `e_min` read along the line, see `lines/oriented.rs`):
//!
//! - **extremal points**: where the other extremality (`e_min` on a ridge, `e_max`
//!   on a valley) changes sign along the line, i.e. where the other principal
//!   curvature is extremal too: the points of the surface where both curvatures
//!   are extremal, Thirion's most stable landmarks. The closing segment of a loop
//!   is not searched: a principal direction carried once around a loop may come
//!   back reversed. A sign change counts only where the signs on both sides hold
//!   for an arc length of at least `LandmarkOptions::persistence`: where the other
//!   curvature barely changes along the line its estimated extremality flickers
//!   about zero.
//! - **curvature maxima**: points where the line's curvature magnitude (`|k_max|`
//!   on a ridge, `|k_min|` on a valley) is the largest within an arc length
//!   `LandmarkOptions::radius` on both sides.
//! - **line ends**: the two ends of every open line.
//!
//! Every line gets a descriptor: length, mean curvature (by arc length), strength
//! and whether it is convex (a ridge) or concave (a valley).

pub(crate) mod export;

pub(crate) use export::read_landmarks;
pub use export::LandmarkFormat;
pub(crate) use export::{holds_landmarks, Space, FORMAT};

use serde::{Deserialize, Serialize};

use crate::lines::{FeatureLines, LineKind, Polyline};
use crate::{Error, Point, Result};

/// What a point landmark marks.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LandmarkKind {
    /// Both principal curvatures extremal: the other extremality changes sign.
    Extremal,
    /// The line's curvature magnitude is largest around this point.
    CurvatureMaximum,
    /// An end of an open line.
    End,
}

impl LandmarkKind {
    /// The lowercase name, as written in files.
    pub fn name(self) -> &'static str {
        match self {
            LandmarkKind::Extremal => "extremal",
            LandmarkKind::CurvatureMaximum => "curvature_maximum",
            LandmarkKind::End => "end",
        }
    }
}

/// A point landmark.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointLandmark {
    /// Its number, from 1.
    pub id: usize,
    /// What it marks.
    pub kind: LandmarkKind,
    /// Where it is.
    pub position: Point,
    /// The curvature of its line there: `k_max` on a ridge, `k_min` on a valley.
    pub curvature: f64,
    /// The id of its line.
    pub line: usize,
}

/// A crest line with its descriptors.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LineLandmark {
    /// Its number, from 1.
    pub id: usize,
    /// [`LineKind::Ridge`] or [`LineKind::Valley`].
    pub kind: LineKind,
    /// Whether it is a loop.
    pub closed: bool,
    /// Its length.
    pub length: f64,
    /// The mean of its curvature (`k_max` on a ridge, `k_min` on a valley) by arc
    /// length.
    pub mean_curvature: f64,
    /// Its strength as the extractor gave it.
    pub strength: f64,
    /// Convex (a ridge) or concave (a valley).
    pub convex: bool,
    /// Its points.
    pub points: Vec<Point>,
}

/// The landmarks of a set of lines.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Landmarks {
    /// Where the lines came from.
    pub source: String,
    /// The point landmarks, numbered from 1.
    pub points: Vec<PointLandmark>,
    /// The crest lines, numbered from 1.
    pub lines: Vec<LineLandmark>,
    /// The anatomical frame of the positions, if the lines had one; the landmark
    /// files write it as their `space`.
    #[serde(skip)]
    pub space: Option<Space>,
}

impl Landmarks {
    /// The landmarks with their positions in `space`: converted from their own
    /// frame, or taken to be in it when they have none.
    pub fn in_space(&self, space: Space) -> Landmarks {
        let mut moved = self.clone();
        let points = moved.points.iter_mut().map(|point| &mut point.position);
        let on_lines = moved
            .lines
            .iter_mut()
            .flat_map(|line| line.points.iter_mut());
        crate::space::convert_all(self.space, space, points.chain(on_lines));
        moved.space = Some(space);
        moved
    }
}

/// Parameters of [`landmarks`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct LandmarkOptions {
    /// A curvature maximum is the largest within this arc length on both sides
    /// (world units).
    pub radius: f64,
    /// An extremal point has the other extremality's sign held for this arc length
    /// on both sides (world units).
    pub persistence: f64,
}

/// The landmarks of the ridge and valley lines of `lines` (see the [module
/// documentation](self)); other kinds of lines are ignored. Extremal points need
/// the per-point values `e_min` (ridges) and `e_max` (valleys), curvature maxima
/// `k_max` (ridges) and `k_min` (valleys): lines without them get none.
///
/// Errors ([`Error::Argument`]) if the radius or the persistence is not finite
/// and positive.
pub(crate) fn landmarks(lines: &FeatureLines, options: &LandmarkOptions) -> Result<Landmarks> {
    let checks = [
        ("the radius of curvature maxima `radius`", options.radius),
        (
            "the persistence of extremal points `persistence`",
            options.persistence,
        ),
    ];
    for (what, value) in checks {
        if !(value.is_finite() && value > 0.0) {
            return Err(Error::Argument(format!(
                "{what} must be finite and positive, got {value}"
            )));
        }
    }
    let mut result = Landmarks {
        source: lines.source.clone(),
        space: lines.space,
        ..Landmarks::default()
    };
    let crests = lines
        .lines
        .iter()
        .filter(|l| matches!(l.kind, LineKind::Ridge | LineKind::Valley) && !l.points.is_empty());
    for line in crests {
        let id = result.lines.len() + 1;
        let curvature = line_curvature(line);
        let found = extremal_points(line, &curvature, options.persistence)
            .into_iter()
            .chain(curvature_maxima(line, &curvature, options.radius))
            .chain(ends(line, &curvature));
        for (kind, position, k) in found {
            result.points.push(PointLandmark {
                id: result.points.len() + 1,
                kind,
                position,
                curvature: k,
                line: id,
            });
        }
        result.lines.push(describe(line, id, &curvature));
    }
    Ok(result)
}

/// The curvature of a crest line at each point: `k_max` on a ridge, `k_min` on a
/// valley (NaN where the line does not carry it).
fn line_curvature(line: &Polyline) -> Vec<f64> {
    let name = if line.kind == LineKind::Ridge {
        "k_max"
    } else {
        "k_min"
    };
    match line.values.get(name) {
        Some(k) if k.len() == line.points.len() => k.clone(),
        _ => vec![f64::NAN; line.points.len()],
    }
}

/// A landmark found on a line: kind, position and the line's curvature there.
type Found = (LandmarkKind, Point, f64);

/// Where the other extremality (`e_min` on a ridge, `e_max` on a valley) changes
/// sign between two consecutive points, linearly interpolated, if the signs on
/// either side hold for an arc length of at least `persistence` (the estimated
/// extremality jitters about zero where the other curvature is nearly constant
/// along the line; such flickers are not landmarks).
fn extremal_points(line: &Polyline, curvature: &[f64], persistence: f64) -> Vec<Found> {
    let name = if line.kind == LineKind::Ridge {
        "e_min"
    } else {
        "e_max"
    };
    let Some(other) = line
        .values
        .get(name)
        .filter(|e| e.len() == line.points.len())
    else {
        return Vec::new();
    };
    let n = line.points.len();
    let (runs, pairs) = changes(sign_runs(line, other), line.closed);
    pairs
        .into_iter()
        .filter(|&(a, b)| runs[a].length >= persistence && runs[b].length >= persistence)
        .map(|(a, _)| {
            let (i, j) = (runs[a].last, (runs[a].last + 1) % n);
            let (e, f) = (other[i], other[j]);
            let t = e / (e - f);
            let position = line.points[i] + (line.points[j] - line.points[i]) * t;
            let k = curvature[i] + (curvature[j] - curvature[i]) * t;
            (LandmarkKind::Extremal, position, k)
        })
        .collect()
}

/// A stretch of a line where a value keeps its sign.
#[derive(Clone, Copy, Debug)]
struct SignRun {
    /// The index of its last point.
    last: usize,
    /// Whether the value is positive on it.
    positive: bool,
    /// Its arc length, to the sign changes (taken half way) or the line's ends.
    length: f64,
}

/// The stretches of `line` where `values` keep a strict sign (zeros and NaN join
/// the stretch they are in), in order from the first point.
fn sign_runs(line: &Polyline, values: &[f64]) -> Vec<SignRun> {
    let span = |i: usize| (line.points[(i + 1) % values.len()] - line.points[i]).norm();
    let mut runs: Vec<SignRun> = Vec::new();
    for i in 0..values.len() {
        let before = if i == 0 { 0.0 } else { 0.5 * span(i - 1) };
        let after = if i + 1 < values.len() || line.closed {
            0.5 * span(i)
        } else {
            0.0
        };
        let sign = match runs.last() {
            _ if values[i] > 0.0 => Some(true),
            _ if values[i] < 0.0 => Some(false),
            last => last.map(|r| r.positive),
        };
        match runs.last_mut() {
            Some(run) if Some(run.positive) == sign || sign.is_none() => {
                run.last = i;
                run.length += before + after;
            }
            _ => runs.push(SignRun {
                last: i,
                positive: sign.unwrap_or(true),
                length: before + after,
            }),
        }
    }
    runs
}

/// The sign changes between consecutive runs, as pairs of run numbers, with the
/// runs they refer to. On a loop the runs meeting at the first point are one run
/// if they have the same sign; if not, the change there counts only if the number
/// of changes around the loop is then even: the sign is carried along the line
/// from its first point, and an odd count means that the direction came back
/// reversed, which is no landmark (the two runs are then one).
fn changes(mut runs: Vec<SignRun>, closed: bool) -> (Vec<SignRun>, Vec<(usize, usize)>) {
    let mut pairs: Vec<(usize, usize)> = (1..runs.len()).map(|r| (r - 1, r)).collect();
    if !closed || runs.len() < 2 {
        return (runs, pairs);
    }
    let last = runs.len() - 1;
    if runs[last].positive != runs[0].positive && pairs.len() % 2 == 1 {
        pairs.push((last, 0));
    } else {
        // The last run continues the first: the change into it is into the first.
        runs[0].length += runs[last].length;
        runs.pop();
        if let Some(pair) = pairs.last_mut() {
            pair.1 = 0;
        }
    }
    (runs, pairs)
}

/// The points whose curvature magnitude, averaged along the line by a Gaussian of
/// arc length σ = `radius` / 2 (the estimated curvature is noisy from point to
/// point), is the largest within arc length `radius` on both sides (strictly
/// larger than the points before, at least as large as those after, so a plateau
/// gives one point); not the ends of an open line. Their curvature is the line's
/// own, unaveraged.
fn curvature_maxima(line: &Polyline, curvature: &[f64], radius: f64) -> Vec<Found> {
    let n = line.points.len();
    let spans: Vec<f64> = (0..n)
        .map(|i| (line.points[(i + 1) % n] - line.points[i]).norm())
        .collect();
    let sigma = 0.5 * radius;
    let magnitude: Vec<f64> = (0..n)
        .map(|i| {
            let near = within(line.closed, &spans, i, 3.0 * sigma, false)
                .chain(within(line.closed, &spans, i, 3.0 * sigma, true))
                .chain([(i, 0.0)])
                .filter(|&(j, _)| curvature[j].is_finite());
            let (sum, weight) = near.fold((0.0, 0.0), |(sum, weight), (j, d)| {
                let w = (-0.5 * (d / sigma).powi(2)).exp();
                (sum + w * curvature[j].abs(), weight + w)
            });
            if weight > 0.0 {
                sum / weight
            } else {
                f64::NAN
            }
        })
        .collect();
    let inner = if line.closed {
        0..n
    } else {
        1..n.saturating_sub(1)
    };
    inner
        .filter(|&i| {
            let k = magnitude[i];
            let lower = |forward: bool, strict: bool| {
                within(line.closed, &spans, i, radius, forward).all(|(j, _)| {
                    let other = magnitude[j];
                    other.is_nan() || if strict { other < k } else { other <= k }
                })
            };
            k.is_finite() && lower(false, true) && lower(true, false)
        })
        .map(|i| (LandmarkKind::CurvatureMaximum, line.points[i], curvature[i]))
        .collect()
}

/// The points within arc length `radius` of point `i` after it (`forward`) or
/// before it, with their distance along the line, whose segment from point `j`
/// has length `spans[j]` (wrapping around a loop, never back to `i`).
fn within(
    closed: bool,
    spans: &[f64],
    i: usize,
    radius: f64,
    forward: bool,
) -> impl Iterator<Item = (usize, f64)> + '_ {
    let n = spans.len();
    let mut distance = 0.0;
    let mut j = i;
    std::iter::from_fn(move || {
        let next = match (forward, closed) {
            (true, true) => (j + 1) % n,
            (false, true) => (j + n - 1) % n,
            (true, false) => j.checked_add(1).filter(|&k| k < n)?,
            (false, false) => j.checked_sub(1)?,
        };
        distance += if forward { spans[j] } else { spans[next] };
        if next == i || distance > radius {
            return None;
        }
        j = next;
        Some((next, distance))
    })
}

/// The two ends of an open line.
fn ends(line: &Polyline, curvature: &[f64]) -> Vec<Found> {
    let last = line.points.len() - 1;
    if line.closed || last == 0 {
        return Vec::new();
    }
    [0, last]
        .map(|i| (LandmarkKind::End, line.points[i], curvature[i]))
        .to_vec()
}

/// The descriptor of line number `id`.
fn describe(line: &Polyline, id: usize, curvature: &[f64]) -> LineLandmark {
    let n = line.points.len();
    let pieces = if line.closed { n } else { n - 1 };
    let (mut length, mut integral) = (0.0, 0.0);
    for i in 0..pieces {
        let j = (i + 1) % n;
        let span = (line.points[j] - line.points[i]).norm();
        length += span;
        integral += 0.5 * (curvature[i] + curvature[j]) * span;
    }
    let mean_curvature = if length > 0.0 {
        integral / length
    } else {
        curvature[0]
    };
    LineLandmark {
        id,
        kind: line.kind,
        closed: line.closed,
        length,
        mean_curvature,
        strength: line.strength,
        convex: line.kind == LineKind::Ridge,
        points: line.points.clone(),
    }
}

#[cfg(test)]
mod tests;
