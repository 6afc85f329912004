//! How well two sets of feature lines or landmarks agree (`crestline compare`): a
//! test–retest measure for two scans of one object, two samplings of one surface,
//! or two versions of the tool.
//!
//! For each kind (lines: `ridge`, `valley`, `crest`, …; landmarks: `extremal`,
//! `curvature_maximum`, `end`) [`Features::compare`] gives the share of A's line length
//! that lies within the tolerance of a line of the same kind in B (the distance to
//! B's segments, not to its vertices, so B's sampling does not count), the share
//! of A's landmarks with a landmark of the same kind in B within the tolerance,
//! and the same from B to A. B's points can first be moved into A's frame by a
//! rigid motion ([`RigidTransform::read`](crate::register::RigidTransform::read)).

mod line_files;
mod markups;
mod near;
mod read;

use std::collections::BTreeMap;

use rayon::prelude::*;
use serde::Serialize;

use crate::landmarks::Landmarks;
use crate::lines::FeatureLines;
use crate::register::RigidTransform;
use crate::space::{convert_all, Space};
use crate::{Error, Point, Result};
use near::Near;

/// Lines and landmarks by kind, as [`Features::compare`] takes them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Features {
    /// The segments of the lines of each kind.
    pub segments: BTreeMap<String, Vec<[Point; 2]>>,
    /// How many lines of each kind.
    pub line_counts: BTreeMap<String, usize>,
    /// The point landmarks of each kind.
    pub points: BTreeMap<String, Vec<Point>>,
    /// The frame the file stated its points in, which are then held in RAS;
    /// `None`: the points as the file holds them (a mesh's lines).
    pub declared: Option<Space>,
}

impl Features {
    /// The segments of `lines` by kind, in RAS if they state a frame.
    pub fn of_lines(lines: &FeatureLines) -> Features {
        let mut features = Features {
            declared: lines.space,
            ..Features::default()
        };
        for line in &lines.lines {
            let mut points = line.points.clone();
            convert_all(lines.space, Space::Ras, &mut points);
            features.add_line(line.kind.name(), &points, line.closed);
        }
        features
    }

    /// The point landmarks and line segments of `landmarks` by kind, in RAS if
    /// they state a frame.
    pub fn of_landmarks(landmarks: &Landmarks) -> Features {
        let landmarks = match landmarks.space {
            Some(_) => landmarks.in_space(Space::Ras),
            None => landmarks.clone(),
        };
        let mut features = Features {
            declared: landmarks.space,
            ..Features::default()
        };
        for line in &landmarks.lines {
            features.add_line(line.kind.name(), &line.points, line.closed);
        }
        for point in &landmarks.points {
            features.add_point(point.kind.name(), point.position);
        }
        features
    }

    /// Add the line through `points` (a loop if `closed`) to `kind`.
    pub fn add_line(&mut self, kind: &str, points: &[Point], closed: bool) {
        let segments = crate::lines::segments(points, closed).map(|(p, q)| [*p, *q]);
        self.segments
            .entry(kind.to_string())
            .or_default()
            .extend(segments);
        *self.line_counts.entry(kind.to_string()).or_default() += 1;
    }

    /// Add a point landmark of `kind`.
    pub fn add_point(&mut self, kind: &str, position: Point) {
        self.points
            .entry(kind.to_string())
            .or_default()
            .push(position);
    }

    /// Every point of the features (segment ends and landmarks).
    fn all_points(&self) -> impl Iterator<Item = &Point> + '_ {
        let ends = self.segments.values().flatten().flatten();
        ends.chain(self.points.values().flatten())
    }

    /// The diagonal of the box around every point: 0 for no point.
    pub fn diagonal(&self) -> f64 {
        let mut points = self.all_points();
        let Some(first) = points.next() else {
            return 0.0;
        };
        let (low, high) = points.fold((*first, *first), |(low, high), p| (low.inf(p), high.sup(p)));
        (high - low).norm()
    }

    /// The features with every point mapped by `map`.
    fn mapped(&self, map: impl Fn(&Point) -> Point) -> Features {
        let move_segment = |[a, b]: &[Point; 2]| [map(a), map(b)];
        Features {
            segments: self
                .segments
                .iter()
                .map(|(kind, s)| (kind.clone(), s.iter().map(move_segment).collect()))
                .collect(),
            line_counts: self.line_counts.clone(),
            points: self
                .points
                .iter()
                .map(|(kind, p)| (kind.clone(), p.iter().map(&map).collect()))
                .collect(),
            declared: self.declared,
        }
    }

    /// The features moved by `motion` (in RAS where the file stated its frame).
    pub fn moved(&self, motion: &RigidTransform) -> Features {
        self.mapped(|p| motion.apply(p))
    }

    /// The features as the file held them: in the frame it stated, not RAS.
    fn as_written(&self) -> Features {
        match self.declared {
            Some(frame) => Features {
                declared: None,
                ..self.mapped(|p| Space::Ras.convert(p, frame))
            },
            None => self.clone(),
        }
    }
}

/// [`Features::in_one_frame`].
pub(crate) fn in_one_frame(a: Features, b: Features) -> (Features, Features) {
    match (a.declared, b.declared) {
        (None, Some(_)) => (a, b.as_written()),
        (Some(_), None) => (a.as_written(), b),
        _ => (a, b),
    }
}

/// The agreement of one kind of lines or landmarks.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Agreement {
    /// The kind (`ridge`, `extremal`, …).
    pub kind: String,
    /// A's amount: line length, or landmark count.
    pub a: f64,
    /// B's amount.
    pub b: f64,
    /// How many lines of the kind A has (landmarks: as many as `a`).
    pub a_count: usize,
    /// How many B has.
    pub b_count: usize,
    /// The share (0 to 1) of A's amount within the tolerance of B's features of
    /// the kind; 0 when A has none.
    pub a_in_b: f64,
    /// The share of B's amount within the tolerance of A's.
    pub b_in_a: f64,
}

/// The agreement of two sets of features, kind by kind.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Comparison {
    /// The tolerance, in world units.
    pub tolerance: f64,
    /// The lines' agreement, a row per kind either set has.
    pub lines: Vec<Agreement>,
    /// The landmarks' agreement, a row per kind either set has.
    pub landmarks: Vec<Agreement>,
}

/// How far apart two features may be and still count as the same.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Tolerance {
    /// A length in world units.
    World(f64),
    /// A share of the diagonal of the box around A's features.
    OfDiagonal(f64),
}

impl Tolerance {
    /// The default: 0.5% of the diagonal.
    pub const DEFAULT: Tolerance = Tolerance::OfDiagonal(0.005);

    /// The tolerance in world units for the features `a`; an error unless it is
    /// positive and finite.
    pub fn resolve(self, a: &Features) -> Result<f64> {
        let length = match self {
            Tolerance::World(length) => length,
            Tolerance::OfDiagonal(share) => share * a.diagonal(),
        };
        if length.is_finite() && length > 0.0 {
            return Ok(length);
        }
        let why = match self {
            Tolerance::OfDiagonal(share) if share > 0.0 => " (A's features have no extent)",
            _ => "",
        };
        Err(Error::Argument(format!(
            "the tolerance is {length}; it must be a positive, finite length{why}"
        )))
    }
}

impl std::str::FromStr for Tolerance {
    type Err = Error;

    /// A length in world units (`1.5`), or a share of A's diagonal in percent
    /// (`0.5%`).
    fn from_str(text: &str) -> Result<Tolerance> {
        let text = text.trim();
        let (number, percent) = match text.strip_suffix('%') {
            Some(number) => (number, true),
            None => (text, false),
        };
        let value: f64 = number.trim().parse().map_err(|_| {
            Error::Argument(format!(
                "the tolerance '{text}' is neither a length (1.5) nor a share of the diagonal (0.5%)"
            ))
        })?;
        Ok(if percent {
            Tolerance::OfDiagonal(value / 100.0)
        } else {
            Tolerance::World(value)
        })
    }
}

impl std::fmt::Display for Tolerance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Tolerance::World(length) => write!(f, "{length}"),
            Tolerance::OfDiagonal(share) => write!(f, "{}%", share * 100.0),
        }
    }
}

impl Default for Tolerance {
    fn default() -> Self {
        Tolerance::DEFAULT
    }
}

/// [`Features::compare`].
pub(crate) fn compare(a: &Features, b: &Features, tolerance: f64) -> Comparison {
    let line_kinds = kinds(a.segments.keys().chain(b.segments.keys()));
    let point_kinds = kinds(a.points.keys().chain(b.points.keys()));
    let lines = line_kinds
        .into_iter()
        .map(|kind| {
            let (sa, sb) = (of_kind(&a.segments, kind), of_kind(&b.segments, kind));
            let (length_a, length_b) = (total_length(sa), total_length(sb));
            let count = |f: &Features| f.line_counts.get(kind).copied().unwrap_or(0);
            Agreement {
                kind: kind.to_string(),
                a: length_a,
                b: length_b,
                a_count: count(a),
                b_count: count(b),
                a_in_b: share(length_near(sa, length_a, sb, tolerance), length_a),
                b_in_a: share(length_near(sb, length_b, sa, tolerance), length_b),
            }
        })
        .collect();
    let landmarks = point_kinds
        .into_iter()
        .map(|kind| {
            let (pa, pb) = (of_kind(&a.points, kind), of_kind(&b.points, kind));
            Agreement {
                kind: kind.to_string(),
                a: pa.len() as f64,
                b: pb.len() as f64,
                a_count: pa.len(),
                b_count: pb.len(),
                a_in_b: point_share_near(pa, pb, tolerance),
                b_in_a: point_share_near(pb, pa, tolerance),
            }
        })
        .collect();
    Comparison {
        tolerance,
        lines,
        landmarks,
    }
}

/// The distinct kinds among `names`, in order.
fn kinds<'a>(names: impl Iterator<Item = &'a String>) -> Vec<&'a str> {
    let mut kinds: Vec<&str> = names.map(String::as_str).collect();
    kinds.sort_unstable();
    kinds.dedup();
    kinds
}

/// The items of `kind`, none if the map lacks it.
fn of_kind<'m, T>(map: &'m BTreeMap<String, Vec<T>>, kind: &str) -> &'m [T] {
    map.get(kind).map_or(&[], Vec::as_slice)
}

/// The summed length of `segments` (0, not the empty sum's −0, when there are
/// none).
fn total_length(segments: &[[Point; 2]]) -> f64 {
    segments
        .iter()
        .fold(0.0, |sum, [p, q]| sum + (q - p).norm())
}

/// `part` of `whole` (at most 1: the pieces' lengths add up to the whole's to
/// rounding), 0 for no whole.
fn share(part: f64, whole: f64) -> f64 {
    if whole > 0.0 {
        (part / whole).min(1.0)
    } else {
        0.0
    }
}

/// The length of `segments` (`length` in all) within `tolerance` of `others`:
/// the segments are cut into pieces at most a quarter of the tolerance long (or
/// longer, [`near::piece_length`]), and a piece counts whole when its midpoint
/// is near.
fn length_near(segments: &[[Point; 2]], length: f64, others: &[[Point; 2]], tolerance: f64) -> f64 {
    if length <= 0.0 || others.is_empty() {
        return 0.0;
    }
    let near = Near::of_segments(others, tolerance);
    let step = near::piece_length(length, tolerance, 4.0);
    let per_segment: Vec<f64> = segments
        .par_iter()
        .map(|segment| {
            near::pieces(segment, step)
                .filter(|[p, q]| near.within(&p.coords.lerp(&q.coords, 0.5).into()))
                .map(|[p, q]| (q - p).norm())
                .sum()
        })
        .collect();
    // Summed in order: the same files give the same figures to the last bit.
    per_segment.iter().sum()
}

/// The share of `points` within `tolerance` of one of `others`; 0 for no point.
fn point_share_near(points: &[Point], others: &[Point], tolerance: f64) -> f64 {
    if points.is_empty() || others.is_empty() {
        return 0.0;
    }
    let near = Near::of_points(others, tolerance);
    let matched = points.par_iter().filter(|p| near.within(p)).count();
    matched as f64 / points.len() as f64
}

impl Features {
    /// `a` and `b` in one frame: RAS when both files stated theirs; when one did not
    /// (a mesh's lines against its markups), the other's points as its file holds
    /// them, which the undeclared ones share.
    pub fn in_one_frame(a: Features, b: Features) -> (Features, Features) {
        in_one_frame(a, b)
    }

    /// How far these features and `other` agree within `tolerance` (world units),
    /// kind by kind, both ways; `other` is taken to be in this one's frame already
    /// ([`Features::moved`]).
    pub fn compare(&self, other: &Features, tolerance: f64) -> Comparison {
        compare(self, other, tolerance)
    }
}

#[cfg(test)]
mod tests;
