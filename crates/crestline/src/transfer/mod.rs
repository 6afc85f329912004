//! Carrying a template's landmarks onto another scan of the same anatomy by
//! registering the template's crest lines onto the subject's, rigidly and then
//! non-rigidly, and mapping the landmarks by the same deformation.
//!
//! [`transfer`] works in three steps:
//! 1. the rigid motion of [`jobs::register`](crate::jobs::register()) (trimmed ICP from
//!    moment-based guesses; Chetverikov et al. 2002) takes the template's line
//!    points onto the subject's;
//! 2. a smooth displacement field is then grown coarse to fine, as Thirion's
//!    demons (1998) grow theirs, on line points instead of voxels: at each
//!    iteration every template point is paired with the closest subject point of
//!    the same line kind whose line runs along its own (tangents within
//!    [`TransferOptions::max_angle`]), and every subject point with the closest
//!    such template point (both ways, so that neither side's extra lines pull the
//!    other);
//!    pairs farther apart than [`TransferOptions::max_distance`] smoothing scales
//!    are dropped (lines present in one scan only); the pairs' displacements are
//!    averaged by a Gaussian of the current scale σ (their sum over the weight
//!    plus a prior of one pair of zero displacement, so that where pairs are few
//!    the points move less), and the template points and the landmarks move by
//!    that average. The largest scales take up most of the global (affine) part
//!    of the motion, the smaller ones the local shape;
//! 3. each landmark gets a confidence: the RMS distance of the template's line
//!    points around it (Gaussian weights of [`TransferOptions::confidence_radius`])
//!    to their closest subject points of their kind after the last step, in
//!    world units; lower is better, and a landmark without line points near it
//!    gets infinity. Its coverage is the length of the subject's lines around
//!    where it lands over the length of the template's lines moved there (the
//!    same Gaussian weights): near 1 where the subject shows what the template
//!    does, near 0 where that part of the anatomy is missing from the subject (cut
//!    off, out of the field of view). A landmark is flagged when its coverage is
//!    below [`TransferOptions::min_coverage`] or it has no confidence; it is
//!    still placed, by the deformation its neighbours give.

mod files;
mod smooth;

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::length::Length;
use crate::lines::{FeatureLines, LineKind};
use crate::progress::{checkpoint, Observer};
use crate::register::{register, PointSet, Registration, RegistrationOptions};
use crate::{Error, Point, Result, Vector};

pub use files::{read_labelled, write_labelled, LabelledPoint};

/// Settings of [`transfer`] (and of `crestline transfer`). Each field is an
/// option of the tool and a keyword argument of the Python package, documented
/// here once: with the feature `clap` this struct is the tool's arguments.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
#[serde(default, deny_unknown_fields)]
pub struct TransferOptions {
    /// The rigid stage.
    #[cfg_attr(feature = "clap", command(flatten))]
    pub registration: RegistrationOptions,
    /// The Gaussian smoothing scales σ of the displacement field, in world units
    /// (mm), coarse to fine, comma-separated (each positive, at least one).
    #[cfg_attr(feature = "clap", arg(long, value_name = "S,S,…", value_delimiter = ',',
        default_values_t = TransferOptions::default().scales))]
    pub scales: Vec<f64>,
    /// Iterations at each scale (1 to 1000).
    #[cfg_attr(feature = "clap", arg(long, value_name = "N",
        default_value_t = TransferOptions::default().iterations))]
    pub iterations: usize,
    /// Pairs of points farther apart than this many smoothing scales σ are not
    /// used (positive).
    #[cfg_attr(feature = "clap", arg(long, value_name = "K",
        default_value_t = TransferOptions::default().max_distance))]
    pub max_distance: f64,
    /// Points are paired only if their lines' tangents make at most this angle, in
    /// degrees (0 to 90; 90 pairs any two).
    #[cfg_attr(feature = "clap", arg(long, value_name = "DEG",
        default_value_t = TransferOptions::default().max_angle))]
    pub max_angle: f64,
    /// At most this many line points of each scan are paired (evenly strided; at
    /// least 100).
    #[cfg_attr(feature = "clap", arg(long, value_name = "N",
        default_value_t = TransferOptions::default().max_points))]
    pub max_points: usize,
    /// The standard deviation of the Gaussian weights of the line points around a
    /// landmark in its confidence, in world units (positive).
    #[cfg_attr(feature = "clap", arg(long, value_name = "R",
        default_value_t = TransferOptions::default().confidence_radius))]
    pub confidence_radius: f64,
    /// Of images: the feature scale at which the crest lines registered are traced
    /// (σ and the shortest line follow from it, as in `crest-lines`), in world
    /// units (mm) or voxels ("1 unit"). Finer than the landmarks' scale: many
    /// short lines pin the deformation down where a few long ones let it slide
    /// along them, and the smooth deformation averages out their noise (measured
    /// in docs/design/landmarks.md, "Transfer").
    #[cfg_attr(feature = "clap", arg(long, value_name = "L",
        default_value_t = TransferOptions::default().image_scale))]
    pub image_scale: Length,
    /// Of images: more isosurfaces, inside the level's, whose crest lines are
    /// registered with its own, at these quantiles of the samples at or above the
    /// level (each between 0 and 1, comma-separated): the anatomy under the
    /// surface holds the deformation of the surface in place.
    #[cfg_attr(feature = "clap", arg(long, value_name = "Q,Q,…", value_delimiter = ',',
        default_values_t = TransferOptions::default().inner_levels))]
    pub inner_levels: Vec<f64>,
    /// Of meshes: the least strength of the ridges and valleys registered (the
    /// ridges' threshold; at least 0). 0, every line, places the landmarks best
    /// (measured in docs/design/landmarks.md, "Transfer").
    #[cfg_attr(feature = "clap", arg(long, value_name = "T",
        default_value_t = TransferOptions::default().mesh_threshold))]
    pub mesh_threshold: f64,
    /// A landmark is flagged when the subject's lines around it cover less than
    /// this share of the template's (0 to 1): that part of the anatomy is missing
    /// from the subject (measured in docs/design/landmarks.md, "Transfer").
    #[cfg_attr(feature = "clap", arg(long, value_name = "C",
        default_value_t = TransferOptions::default().min_coverage))]
    pub min_coverage: f64,
}

impl Default for TransferOptions {
    fn default() -> Self {
        TransferOptions {
            registration: RegistrationOptions::default(),
            scales: vec![32.0, 24.0, 16.0, 12.0, 8.0],
            iterations: 20,
            max_distance: 2.0,
            max_angle: 30.0,
            max_points: 200_000,
            confidence_radius: 5.0,
            image_scale: Length::units(1.0),
            inner_levels: vec![0.5],
            mesh_threshold: 0.0,
            min_coverage: 0.5,
        }
    }
}

impl TransferOptions {
    /// An [`Error::Argument`] naming the first setting out of its range.
    pub fn validate(&self) -> Result<()> {
        self.registration.validate()?;
        let bad = |message: String| Err(Error::Argument(message));
        if self.scales.is_empty() || !self.scales.iter().all(|s| s.is_finite() && *s > 0.0) {
            return bad(format!(
                "`scales` is {:?}, expected at least one finite positive length",
                self.scales
            ));
        }
        if !(1..=1000).contains(&self.iterations) {
            return bad(format!(
                "`iterations` is {}, expected 1 to 1000",
                self.iterations
            ));
        }
        for (name, value) in [
            ("max_distance", self.max_distance),
            ("confidence_radius", self.confidence_radius),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return bad(format!("`{name}` is {value}, expected a positive number"));
            }
        }
        let (Length::World(scale)
        | Length::Relative { units: scale }
        | Length::Scaled { scales: scale }) = self.image_scale;
        if !(scale.is_finite() && scale > 0.0) {
            return bad(format!(
                "`image_scale` is {}, expected a positive length",
                self.image_scale
            ));
        }
        if !self.inner_levels.iter().all(|q| *q > 0.0 && *q < 1.0) {
            return bad(format!(
                "`inner_levels` is {:?}, expected quantiles between 0 and 1",
                self.inner_levels
            ));
        }
        if !(self.mesh_threshold.is_finite() && self.mesh_threshold >= 0.0) {
            return bad(format!(
                "`mesh_threshold` is {}, expected a finite strength of at least 0",
                self.mesh_threshold
            ));
        }
        if !(0.0..=1.0).contains(&self.min_coverage) {
            return bad(format!(
                "`min_coverage` is {}, expected 0 to 1",
                self.min_coverage
            ));
        }
        if !(0.0..=90.0).contains(&self.max_angle) {
            return bad(format!(
                "`max_angle` is {}, expected 0 to 90 degrees",
                self.max_angle
            ));
        }
        if self.max_points < 100 {
            return bad(format!(
                "`max_points` is {}, expected at least 100",
                self.max_points
            ));
        }
        Ok(())
    }
}

/// The result of [`transfer`].
#[derive(Clone, Debug, PartialEq)]
pub struct Transfer {
    /// Where each landmark lands in the subject, in the order given.
    pub positions: Vec<Point>,
    /// Each landmark's local residual (see the [module](self) documentation).
    pub confidence: Vec<f64>,
    /// Each landmark's coverage: the subject's lines around it over the
    /// template's (see the [module](self) documentation).
    pub coverage: Vec<f64>,
    /// Whether each landmark is doubtful: its coverage is below
    /// [`TransferOptions::min_coverage`] or it has no confidence.
    pub flagged: Vec<bool>,
    /// The rigid stage.
    pub rigid: Registration,
    /// The RMS distance of the kept pairs after the last step, all points.
    pub rms: f64,
}

/// The line points of one scan with their line's kind and unit tangent.
struct KindedPoints {
    points: Vec<Point>,
    kinds: Vec<LineKind>,
    tangents: Vec<Vector>,
    /// How many of the lines' points each kept point stands for.
    stride: usize,
}

impl KindedPoints {
    /// At most `at_most` of the points of `lines` (evenly strided).
    fn of(lines: &FeatureLines, at_most: usize) -> KindedPoints {
        let all: Vec<(Point, LineKind, Vector)> = lines
            .iter()
            .flat_map(|line| {
                let n = line.points.len();
                (0..n).map(move |i| {
                    let (before, after) = if line.closed {
                        ((i + n - 1) % n, (i + 1) % n)
                    } else {
                        (i.saturating_sub(1), (i + 1).min(n - 1))
                    };
                    let chord = line.points[after] - line.points[before];
                    let tangent = chord.try_normalize(0.0).unwrap_or_else(Vector::zeros);
                    (line.points[i], line.kind, tangent)
                })
            })
            .collect();
        let stride = all.len().div_ceil(at_most).max(1);
        let mut set = KindedPoints {
            points: Vec::new(),
            kinds: Vec::new(),
            tangents: Vec::new(),
            stride,
        };
        for (point, kind, tangent) in all.into_iter().step_by(stride) {
            set.points.push(point);
            set.kinds.push(kind);
            set.tangents.push(tangent);
        }
        set
    }
}

/// The distinct kinds of `kinds`, in order of first appearance.
fn distinct(kinds: &[LineKind]) -> Vec<LineKind> {
    let mut found: Vec<LineKind> = Vec::new();
    for kind in kinds {
        if !found.contains(kind) {
            found.push(*kind);
        }
    }
    found
}

/// How many closest points of a kind are tried for one whose line runs along the
/// query's.
const CANDIDATES: usize = 8;

/// Closest-point queries among the points of one kind whose lines run along the
/// query's.
struct ByKind<'a> {
    /// Per kind: the kind, the indices of its points and a tree over them.
    trees: Vec<(LineKind, Vec<usize>, ImmutableKdTree<f64, 3>)>,
    /// The unit tangents of the points.
    tangents: &'a [Vector],
    /// The smallest |cosine| between the query's tangent and a match's.
    alignment: f64,
}

impl<'a> ByKind<'a> {
    fn new(set: &'a KindedPoints, alignment: f64) -> ByKind<'a> {
        let (points, kinds) = (&set.points, &set.kinds);
        let trees = distinct(kinds)
            .into_iter()
            .map(|kind| {
                let indices: Vec<usize> = (0..points.len()).filter(|&i| kinds[i] == kind).collect();
                let coordinates: Vec<[f64; 3]> = indices
                    .iter()
                    .map(|&i| [points[i].x, points[i].y, points[i].z])
                    .collect();
                (kind, indices, ImmutableKdTree::new_from_slice(&coordinates))
            })
            .collect();
        ByKind {
            trees,
            tangents: &set.tangents,
            alignment,
        }
    }

    /// The index and distance of the closest point of `kind` to `query` among
    /// its [`CANDIDATES`] closest whose tangent is within the alignment of
    /// `tangent` (either way); `None` when there is none.
    fn closest(&self, kind: LineKind, query: &Point, tangent: &Vector) -> Option<(usize, f64)> {
        let (_, indices, tree) = self.trees.iter().find(|(k, _, _)| *k == kind)?;
        let nearest = tree.nearest_n::<SquaredEuclidean>(
            &[query.x, query.y, query.z],
            std::num::NonZero::new(CANDIDATES).expect("a positive count"),
        );
        nearest.into_iter().find_map(|found| {
            let index = indices[found.item as usize];
            (self.tangents[index].dot(tangent).abs() >= self.alignment)
                .then(|| (index, found.distance.sqrt()))
        })
    }
}

/// The landmarks `landmarks` of the template, whose crest lines are `template`,
/// carried onto the subject of crest lines `subject` (both in the same frame; see
/// the [module](self) documentation). The stages are reported to `observer`:
/// `rigid`, then `deform` with the count `pairs` of the last iteration, and the
/// measure `rms` ([`Transfer::rms`]).
///
/// Errors ([`Error::Argument`]) if an option is out of range, the two sets share
/// no line kind, or the rigid registration fails (too few points).
pub fn transfer(
    template: &FeatureLines,
    subject: &FeatureLines,
    landmarks: &[Point],
    options: &TransferOptions,
    observer: &mut dyn Observer,
) -> Result<Transfer> {
    options.validate()?;
    let mut moving = KindedPoints::of(template, options.max_points);
    let fixed = KindedPoints::of(subject, options.max_points);
    let (template_kinds, subject_kinds) = (distinct(&moving.kinds), distinct(&fixed.kinds));
    if !template_kinds.iter().any(|k| subject_kinds.contains(k)) {
        return Err(Error::Argument(format!(
            "the template's lines ({template_kinds:?}) and the subject's ({subject_kinds:?}) \
             share no kind"
        )));
    }
    let finest = options
        .scales
        .iter()
        .fold(options.confidence_radius, |a, &b| a.min(b));
    smooth::check_grid(
        moving.points.iter().chain(&fixed.points).chain(landmarks),
        finest,
    )?;
    checkpoint(observer)?;
    let rigid = crate::progress::try_stage(observer, "rigid", || {
        register(
            &PointSet {
                line_points: fixed.points.clone(),
                key_points: Vec::new(),
            },
            &PointSet {
                line_points: moving.points.clone(),
                key_points: Vec::new(),
            },
            &options.registration,
        )
    })?;
    for (p, t) in moving.points.iter_mut().zip(&mut moving.tangents) {
        *p = rigid.transform.apply(p);
        *t = rigid.transform.rotation * *t;
    }
    let alignment = options.max_angle.to_radians().cos();
    let mut positions: Vec<Point> = landmarks.iter().map(|p| rigid.transform.apply(p)).collect();
    let targets = ByKind::new(&fixed, alignment);
    let mut pairs = 0;
    crate::progress::try_stage(observer, "deform", || -> Result<()> {
        for &sigma in &options.scales {
            for _ in 0..options.iterations {
                let reach = options.max_distance * sigma;
                let (sites, steps) = paired_steps(&moving, &fixed, &targets, reach, alignment);
                pairs = sites.len();
                let mut queries = moving.points.clone();
                queries.extend_from_slice(&positions);
                let field = smooth::smoothed(&sites, &steps, sigma, 1.0, &queries);
                let (on_lines, on_landmarks) = field.split_at(moving.points.len());
                for (p, (step, _)) in moving.points.iter_mut().zip(on_lines) {
                    *p += Vector::from(*step);
                }
                for (p, (step, _)) in positions.iter_mut().zip(on_landmarks) {
                    *p += Vector::from(*step);
                }
            }
        }
        Ok(())
    })?;
    observer.count("pairs", pairs);
    let residuals: Vec<Option<f64>> = moving
        .points
        .par_iter()
        .zip(&moving.kinds)
        .zip(&moving.tangents)
        .map(|((p, kind), t)| targets.closest(*kind, p, t).map(|(_, d)| d))
        .collect();
    let (sites, squares): (Vec<Point>, Vec<[f64; 1]>) = moving
        .points
        .iter()
        .zip(&residuals)
        .filter_map(|(p, r)| r.map(|r| (*p, [r * r])))
        .unzip();
    let kept: Vec<f64> = squares
        .iter()
        .map(|[s]| *s)
        .filter(|s| s.sqrt() <= options.max_distance * options.scales[options.scales.len() - 1])
        .collect();
    let rms = (kept.iter().sum::<f64>() / kept.len().max(1) as f64).sqrt();
    observer.measure("rms", rms);
    let confidence: Vec<f64> =
        smooth::smoothed(&sites, &squares, options.confidence_radius, 0.0, &positions)
            .into_iter()
            .map(|([mean], weight)| {
                if weight > 1e-3 {
                    mean.sqrt()
                } else {
                    f64::INFINITY
                }
            })
            .collect();
    let coverage = coverage(&moving, &fixed, &positions, options.confidence_radius);
    let flagged = confidence
        .iter()
        .zip(&coverage)
        .map(|(c, v)| !c.is_finite() || *v < options.min_coverage)
        .collect();
    Ok(Transfer {
        positions,
        confidence,
        coverage,
        flagged,
        rigid,
        rms,
    })
}

/// At each of `positions`, the Gaussian-weighted count (standard deviation
/// `radius`) of the subject's line points over that of the template's moved line
/// points, each point counted for the points it stands for; 0 where the template
/// has none.
fn coverage(
    template: &KindedPoints,
    subject: &KindedPoints,
    positions: &[Point],
    radius: f64,
) -> Vec<f64> {
    let weights = |set: &KindedPoints| -> Vec<f64> {
        let none = vec![[0.0; 0]; set.points.len()];
        smooth::smoothed(&set.points, &none, radius, 0.0, positions)
            .into_iter()
            .map(|(_, weight)| weight * set.stride as f64)
            .collect()
    };
    weights(subject)
        .into_iter()
        .zip(weights(template))
        .map(|(s, t)| if t > 1e-3 { s / t } else { 0.0 })
        .collect()
}

/// The pairs (a, b) of every point a of `from` with its closest point b of the
/// set `index` was made of (same kind, aligned tangents), within `reach`.
fn closest_pairs<'a>(
    from: &'a KindedPoints,
    index: &'a ByKind<'_>,
    reach: f64,
) -> impl ParallelIterator<Item = (usize, usize)> + 'a {
    from.points
        .par_iter()
        .zip(&from.kinds)
        .zip(&from.tangents)
        .enumerate()
        .filter_map(move |(a, ((p, kind), t))| {
            let (b, d) = index.closest(*kind, p, t)?;
            (d <= reach).then_some((a, b))
        })
}

/// The displacements of one iteration: for every moving point its closest fixed
/// point of its kind, and for every fixed point its closest moving point of its
/// kind, pairs within `reach` only; each displacement (fixed minus moving) at the
/// moving point's position.
fn paired_steps(
    moving: &KindedPoints,
    fixed: &KindedPoints,
    targets: &ByKind,
    reach: f64,
    alignment: f64,
) -> (Vec<Point>, Vec<[f64; 3]>) {
    let sources = ByKind::new(moving, alignment);
    let forward = closest_pairs(moving, targets, reach);
    let backward = closest_pairs(fixed, &sources, reach).map(|(j, i)| (i, j));
    forward
        .chain(backward)
        .map(|(i, j)| {
            let p = moving.points[i];
            (p, <[f64; 3]>::from(fixed.points[j] - p))
        })
        .unzip()
}
