//! Feature lines from the Morse-Smale complex of a curvature indicator (Sahner,
//! Weber, Prohaska, Lamecker: "Extraction of feature lines on surface meshes based on
//! discrete Morse theory", EuroVis 2008).
//!
//! The steps:
//! 1. an indicator per vertex ([`Indicator`]: curvedness, k_max, k_min or a user
//!    property);
//! 2. Forman's discrete gradient as two spanning forests with fixed roots
//!    (`morse/gradient.rs`);
//! 3. the 1-cells of every saddle, measured up to their first merge (`morse/cells.rs`);
//! 4. the cancellation hierarchy by the feature-preserving criterion or by
//!    persistence (`morse/cancel/`);
//! 5. discarding lines forced by topology (§3.5), optional smoothing (§3.6), and
//!    output of the ascending (ridge-like) and descending (valley-like) 1-cells.
//!
//! The one parameter is how far to simplify: a number of cancellations or of
//! saddles to keep. Lines are always connected, and the method needs no derivative
//! of the indicator, so it is robust to noise.

pub(crate) mod cancel;
pub(crate) mod cells;
mod disjoint;
pub(crate) mod gradient;
mod heap;
mod indicator;
mod output;
#[cfg(test)]
mod tests;

use std::sync::Arc;

use crate::curvature::{CurvatureEstimator, ShapeOperator};
use crate::lines::{FeatureLines, LineExtractor, SurfaceWithValues};
use crate::mesh::Mesh;
use crate::progress::{checkpoint, stage, try_stage, try_stage_with, Observer};
use crate::{Error, Result};

pub use cancel::{Cancellation, Criterion};
pub use indicator::Indicator;
pub use output::Cells;

/// How far to simplify the complex.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Simplification {
    /// Make this many cancellations (fewer if no valid one is left).
    Cancel(usize),
    /// Cancel until at most this many saddles that could still be cancelled are
    /// left. Saddles forced by topology (with no valid cancellation, e.g. the 2g
    /// saddles of a closed surface of genus g) are kept besides and not counted.
    KeepSaddles(usize),
}

/// Feature lines as 1-cells of a simplified Morse-Smale complex.
#[derive(Clone)]
pub struct MorseSmale {
    /// Estimator for curvature indicators ([`ShapeOperator`] by default; on irregular
    /// meshes its spikes become long-lived maxima: prefer the jet fit there).
    pub estimator: Arc<dyn CurvatureEstimator + Send + Sync>,
    /// The scalar field whose complex is built.
    pub indicator: Indicator,
    /// How saddles are ranked for cancellation.
    pub criterion: Criterion,
    /// How far to simplify.
    pub simplification: Simplification,
    /// Which 1-cells to output.
    pub cells: Cells,
    /// Keep the lines that no valid cancellation could remove and that are less
    /// significant than the last cancellation (§3.5); hidden by default.
    pub keep_forced: bool,
    /// Fairing iterations of the output lines (§3.6), done on the surface so that
    /// every point stays on the mesh and on the crest it follows (the indicator
    /// does not drop below the lower of its value before fairing and its upper
    /// quartile; for descending lines the mirror); 0 for none.
    pub smooth: usize,
}

impl Default for MorseSmale {
    fn default() -> Self {
        MorseSmale {
            estimator: Arc::new(ShapeOperator),
            indicator: Indicator::Curvedness,
            criterion: Criterion::Feature,
            simplification: Simplification::KeepSaddles(Self::DEFAULT_KEEP_SADDLES),
            cells: Cells::Ascending,
            keep_forced: false,
            smooth: Self::DEFAULT_SMOOTH_ITERATIONS,
        }
    }
}

/// Counts of critical points.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct CriticalCounts {
    /// Minima (vertices).
    pub minima: usize,
    /// Saddles (edges).
    pub saddles: usize,
    /// Maxima (faces).
    pub maxima: usize,
}

/// What a run produced besides the lines.
#[derive(Clone, Debug)]
pub struct MorseSummary {
    /// Critical points of the initial gradient.
    pub initial: CriticalCounts,
    /// Critical points after the cancellations.
    pub after: CriticalCounts,
    /// How many of the saddles left no valid cancellation could remove (forced by
    /// topology; hidden from the output unless [`MorseSmale::keep_forced`] is on).
    pub forced_saddles: usize,
    /// The cancellation sequence.
    pub hierarchy: Vec<Cancellation>,
}

impl LineExtractor for MorseSmale {
    fn extract(&self, mesh: &Mesh, observer: &mut dyn Observer) -> Result<FeatureLines> {
        Ok(self.run(mesh, observer)?.0)
    }
}

impl LineExtractor<SurfaceWithValues<'_>> for MorseSmale {
    fn extract(
        &self,
        surface: &SurfaceWithValues<'_>,
        observer: &mut dyn Observer,
    ) -> Result<FeatureLines> {
        Ok(self
            .run_with_values(surface.mesh, surface.values.to_vec(), observer)?
            .0)
    }
}

impl MorseSmale {
    /// Default number of saddles kept by [`Simplification::KeepSaddles`].
    pub const DEFAULT_KEEP_SADDLES: usize = 100;
    /// Default fairing iterations on the surface: the staircases of mesh edges
    /// turn 36 radians per 100 px in a drawing of the bunny, 7 after 20 and 6 after
    /// 40 iterations, while the share of their length on the indicator's crest
    /// (upper quartile) stays at 81–82% (`src/draw/tests/morse_drawing.rs`).
    pub const DEFAULT_SMOOTH_ITERATIONS: usize = 30;
    /// The most fairing iterations ([`Self::smooth`]) accepted.
    pub const MAX_SMOOTH_ITERATIONS: usize = 1000;

    /// Compute the [`Self::indicator`] of `mesh`, then build, simplify and output its
    /// complex ([`Self::run_with_values`]), telling `observer` each stage.
    pub fn run(
        &self,
        mesh: &Mesh,
        observer: &mut dyn Observer,
    ) -> Result<(FeatureLines, MorseSummary)> {
        self.check()?;
        let values = try_stage(observer, "indicator", || {
            self.indicator.values(mesh, self.estimator.as_ref())
        })?;
        self.run_with_values(mesh, values, observer)
    }

    /// Build, simplify and output the complex of `values` (one finite value per
    /// vertex of `mesh`, e.g. an indicator computed elsewhere); [`Self::indicator`]
    /// and [`Self::estimator`] are not used.
    pub fn run_with_values(
        &self,
        mesh: &Mesh,
        values: Vec<f64>,
        observer: &mut dyn Observer,
    ) -> Result<(FeatureLines, MorseSummary)> {
        self.check()?;
        check_values(mesh, &values)?;
        // The gradient's stage includes its keys (the values on edges and faces).
        let (keys, gradient) = stage(observer, "gradient", || {
            let keys = gradient::Keys::new(mesh, values);
            let gradient = gradient::Gradient::new(mesh, &keys);
            (keys, gradient)
        });
        let (saddles, regions) = stage(observer, "cells", || {
            rayon::join(
                || cells::measure_saddles(mesh, &keys, &gradient),
                || {
                    rayon::join(
                        || cells::minimum_regions(mesh, &keys, &gradient),
                        || cells::maximum_regions(mesh, &keys, &gradient),
                    )
                },
            )
        });
        let initial = CriticalCounts {
            minima: gradient.minima.len(),
            saddles: gradient.saddles.len(),
            maxima: gradient.maxima.len(),
        };
        let hierarchy = try_stage_with(observer, "cancellation", |log| {
            let mut hierarchy =
                cancel::Hierarchy::new(mesh, &keys, gradient, saddles, regions, self.criterion);
            self.simplify(&mut hierarchy, log)?;
            Ok(hierarchy)
        })?;
        let (minima, maxima) = hierarchy.extremum_counts();
        let after = CriticalCounts {
            minima,
            saddles: hierarchy.saddle_count(),
            maxima,
        };
        let lines = stage(observer, "lines", || {
            output::lines(mesh, &keys.vertex, &hierarchy, self)
        });
        let summary = MorseSummary {
            initial,
            after,
            forced_saddles: hierarchy.saddle_count() - hierarchy.cancellable_count(),
            hierarchy: hierarchy.cancelled,
        };
        Ok((lines, summary))
    }

    /// The options are in range: an error says which is not.
    fn check(&self) -> Result<()> {
        if self.smooth > Self::MAX_SMOOTH_ITERATIONS {
            return Err(Error::Argument(format!(
                "{} fairing iterations of the Morse-Smale lines; at most {} are accepted",
                self.smooth,
                Self::MAX_SMOOTH_ITERATIONS
            )));
        }
        Ok(())
    }

    /// Cancel saddles in criterion order until [`Self::simplification`] is met or
    /// no valid cancellation is left, telling `observer` the progress and asking it
    /// whether to go on every [`CANCELLATIONS_PER_CHECKPOINT`] cancellations
    /// ([`Error::Cancelled`] if not).
    fn simplify(
        &self,
        hierarchy: &mut cancel::Hierarchy<'_>,
        observer: &mut dyn Observer,
    ) -> Result<()> {
        let mut count = 0;
        loop {
            if count % CANCELLATIONS_PER_CHECKPOINT == 0 {
                observer.progress(count, count + self.cancellations_left(hierarchy, count));
                checkpoint(observer)?;
            }
            let done = match self.simplification {
                Simplification::Cancel(n) => count >= n,
                Simplification::KeepSaddles(n) => hierarchy.cancellable_count() <= n,
            };
            if done || hierarchy.cancel_next().is_none() {
                observer.progress(count, count);
                return Ok(());
            }
            count += 1;
        }
    }

    /// At most how many cancellations are left after `count`, for the progress:
    /// each removes one cancellable saddle and may leave others forced (no longer
    /// cancellable), so the number falls at least one a cancellation.
    fn cancellations_left(&self, hierarchy: &cancel::Hierarchy<'_>, count: usize) -> usize {
        let cancellable = hierarchy.cancellable_count();
        match self.simplification {
            Simplification::Cancel(n) => n.saturating_sub(count).min(cancellable),
            Simplification::KeepSaddles(n) => cancellable.saturating_sub(n),
        }
    }
}

/// How many cancellations [`MorseSmale::simplify`] makes between two questions to
/// its observer: a few milliseconds' worth (about 2 µs each on the dragon ×16,
/// whose 3 million take 6–7 s).
const CANCELLATIONS_PER_CHECKPOINT: usize = 4096;

/// One finite value per vertex, or an error saying what is wrong.
fn check_values(mesh: &Mesh, values: &[f64]) -> Result<()> {
    if values.len() != mesh.vertex_count() {
        return Err(Error::Argument(format!(
            "{} values for the {} vertices of the mesh",
            values.len(),
            mesh.vertex_count()
        )));
    }
    if let Some(v) = values.iter().position(|x| !x.is_finite()) {
        return Err(Error::Mesh(format!(
            "the indicator's value at vertex {v} is {}, not a finite number",
            values[v]
        )));
    }
    let (low, high) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        });
    if !(high - low).is_finite() {
        return Err(Error::Mesh(format!(
            "the indicator's values range over [{low:e}, {high:e}], too wide for their \
             differences to be finite numbers; rescale them"
        )));
    }
    Ok(())
}
