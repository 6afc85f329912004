//! Rigid registration of two sets of crest-line points: Thirion's use of crest
//! lines, aligning two scans of the same subject.
//!
//! [`jobs::register`](crate::jobs::register()) finds the rigid motion taking the
//! `moving` set onto the `fixed` one in three steps:
//! 1. starting guesses from the moments of the line points (`register/initial.rs`): the
//!    centroids matched without rotation, and the 24 right-handed alignments of the
//!    principal axes;
//! 2. each guess refined by a few iterations of trimmed ICP (`register/icp.rs`) on an evenly
//!    strided sample of the moving line points, on the key points first when both
//!    sets have at least three not on one line; the guess with the lowest trimmed
//!    objective wins;
//! 3. trimmed ICP on all moving line points from there to convergence.
//!
//! Robustness to outliers and partial overlap is by trimming (Chetverikov et al.
//! 2002): at each iteration only the closest share ξ of the closest-point pairs is
//! fitted, ξ chosen automatically as the minimizer of `e(ξ) / ξ³` (e the mean squared
//! distance of the kept pairs) over `ξ ≥` [`RegistrationOptions::min_overlap`].
//! Closest points come from a k-d tree over the fixed points; each step is the
//! least-squares fit of `fit::best_rigid_fit` (Kabsch 1976, Umeyama 1991).
//! Everything is deterministic: no random sampling, ties broken by order.
//!
//! [`Registration::write`] saves the result as JSON or as an ITK/3D Slicer transform
//! file.

pub(crate) mod fit;
pub(crate) mod icp;
pub(crate) mod initial;
pub(crate) mod input;
pub(crate) mod output;
pub(crate) mod transform;

use rayon::prelude::*;

use crate::{Error, Point, Result};
use icp::{trimmed_icp, Alignment, Schedule, Target};
use initial::{hypotheses, principal_frame};

#[cfg(test)]
pub(crate) use fit::best_rigid_fit;
pub use output::TransformFormat;
#[cfg(test)]
pub(crate) use transform::rotation_angle;
pub use transform::RigidTransform;

/// The points of one scan to register.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PointSet {
    /// Points of its crest lines (at least three, not all on one line).
    pub line_points: Vec<Point>,
    /// Extremal points or other landmarks; may be empty. Used for the coarse stage
    /// when both sets have at least three, not all on one line.
    pub key_points: Vec<Point>,
}

/// Settings of [`jobs::register`](crate::jobs::register()) (and of `crestline register`).
/// The first two are options of the tool and keyword arguments of the Python
/// package, documented here once (with the feature `clap` this struct is the
/// tool's arguments); the schedule of the coarse stage and the tolerance are the
/// library's to tune.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
#[serde(default, deny_unknown_fields)]
pub struct RegistrationOptions {
    /// The smallest share of moving points that may be matched (0.1 to 1): the
    /// expected overlap of the two sets should be above it.
    #[cfg_attr(feature = "clap", arg(long, value_name = "S",
        default_value_t = RegistrationOptions::default().min_overlap))]
    pub min_overlap: f64,
    /// At most this many ICP iterations after the coarse stage (1 to 10 000).
    #[cfg_attr(feature = "clap", arg(long, value_name = "N",
        default_value_t = RegistrationOptions::default().max_iterations))]
    pub max_iterations: usize,
    /// ICP iterations for each starting guess in the coarse stage (1 to 10 000).
    #[cfg_attr(feature = "clap", arg(skip = RegistrationOptions::default().coarse_iterations))]
    pub coarse_iterations: usize,
    /// At most this many moving line points in the coarse stage (at least 3).
    #[cfg_attr(feature = "clap", arg(skip = RegistrationOptions::default().coarse_points))]
    pub coarse_points: usize,
    /// ICP stops once an iteration moves the points by less than this share of
    /// their RMS radius (finite, in `[0, 0.1]`).
    #[cfg_attr(feature = "clap", arg(skip = RegistrationOptions::default().tolerance))]
    pub tolerance: f64,
}

impl Default for RegistrationOptions {
    fn default() -> Self {
        RegistrationOptions {
            min_overlap: 0.4,
            max_iterations: 200,
            coarse_iterations: 20,
            coarse_points: 2000,
            tolerance: 1e-7,
        }
    }
}

impl RegistrationOptions {
    /// An [`Error::Argument`] naming the first setting out of its range.
    pub fn validate(&self) -> Result<()> {
        let bad = |message: String| Err(Error::Argument(message));
        if !(0.1..=1.0).contains(&self.min_overlap) {
            return bad(format!(
                "`min_overlap` is {}, expected a share in [0.1, 1]",
                self.min_overlap
            ));
        }
        for (name, value) in [
            ("max_iterations", self.max_iterations),
            ("coarse_iterations", self.coarse_iterations),
        ] {
            if !(1..=10_000).contains(&value) {
                return bad(format!("`{name}` is {value}, expected 1 to 10000"));
            }
        }
        if self.coarse_points < 3 {
            return bad(format!(
                "`coarse_points` is {}, expected at least 3",
                self.coarse_points
            ));
        }
        if !(0.0..=0.1).contains(&self.tolerance) {
            return bad(format!(
                "`tolerance` is {}, expected a number in [0, 0.1]",
                self.tolerance
            ));
        }
        Ok(())
    }

    fn schedule(&self, max_iterations: usize) -> Schedule {
        Schedule {
            max_iterations,
            min_overlap: self.min_overlap,
            tolerance: self.tolerance,
        }
    }
}

/// The result of [`jobs::register`](crate::jobs::register()).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Registration {
    /// The rigid motion taking the moving points onto the fixed ones.
    pub transform: RigidTransform,
    /// RMS distance between matched moving points (transformed) and their closest
    /// fixed points.
    pub rms: f64,
    /// The number of moving line points matched (kept by the trimming).
    pub matched: usize,
    /// `matched` as a share of the moving line points.
    pub matched_share: f64,
    /// ICP iterations of the final stage.
    pub iterations: usize,
}

/// The rigid motion taking `moving` onto `fixed`, by trimmed ICP from the best of
/// the moment-based starting guesses (see the [module](self) documentation).
///
/// Errors ([`Error::Argument`]) if a set has fewer than three line points, its
/// line points lie on one line, a coordinate is not finite, or an option is out
/// of range.
pub(crate) fn register(
    fixed: &PointSet,
    moving: &PointSet,
    options: &RegistrationOptions,
) -> Result<Registration> {
    options.validate()?;
    check_set(fixed, "fixed")?;
    check_set(moving, "moving")?;
    let frames = (
        principal_frame(&fixed.line_points, "fixed")?,
        principal_frame(&moving.line_points, "moving")?,
    );
    let target = Target::new(&fixed.line_points);
    let sample = strided_sample(&moving.line_points, options.coarse_points);
    let keys = (usable_key_points(fixed) && usable_key_points(moving))
        .then(|| (Target::new(&fixed.key_points), moving.key_points.as_slice()));
    let coarse = options.schedule(options.coarse_iterations);
    let candidates = hypotheses(&frames.0, &frames.1)
        .into_par_iter()
        .map(|start| {
            let start = match &keys {
                Some((key_target, key_points)) => {
                    trimmed_icp(key_target, key_points, start, &coarse)?.transform
                }
                None => start,
            };
            trimmed_icp(&target, &sample, start, &coarse)
        })
        .collect::<Result<Vec<Alignment>>>()?;
    let best = candidates
        .into_iter()
        .min_by(|a, b| a.objective.total_cmp(&b.objective))
        .map_or_else(RigidTransform::identity, |a| a.transform);
    let fine = trimmed_icp(
        &target,
        &moving.line_points,
        best,
        &options.schedule(options.max_iterations),
    )?;
    Ok(Registration {
        transform: fine.transform,
        rms: fine.rms,
        matched: fine.matched,
        matched_share: fine.share,
        iterations: fine.iterations,
    })
}

/// At least three line points, and every coordinate finite.
fn check_set(set: &PointSet, what: &str) -> Result<()> {
    if set.line_points.len() < 3 {
        return Err(Error::Argument(format!(
            "the {what} set has {} line points; registration needs at least 3",
            set.line_points.len()
        )));
    }
    for (kind, points) in [("line", &set.line_points), ("key", &set.key_points)] {
        if let Some((i, p)) = points
            .iter()
            .enumerate()
            .find(|(_, p)| !p.iter().all(|c| c.is_finite()))
        {
            return Err(Error::Argument(format!(
                "{what} {kind} point {i} has a non-finite coordinate ({}, {}, {})",
                p.x, p.y, p.z
            )));
        }
    }
    Ok(())
}

/// Whether the key points of `set` can lead the coarse stage: at least three, not
/// all on one line (which would leave the rotation about it to chance).
fn usable_key_points(set: &PointSet) -> bool {
    set.key_points.len() >= 3 && principal_frame(&set.key_points, "key").is_ok()
}

/// Every `⌈n / at_most⌉`-th point of `points`, at most `at_most` of them.
fn strided_sample(points: &[Point], at_most: usize) -> Vec<Point> {
    let stride = points.len().div_ceil(at_most);
    points.iter().step_by(stride).copied().collect()
}

#[cfg(test)]
mod tests;
