//! Feature lines from the Morse-Smale complex of a curvature indicator (Sahner,
//! Weber, Prohaska, Lamecker: "Extraction of feature lines on surface meshes based on
//! discrete Morse theory", EuroVis 2008).
//!
//! The steps:
//! 1. an indicator per vertex ([`Indicator`]: curvedness, k_max, k_min or a user
//!    property);
//! 2. Forman's discrete gradient as two spanning forests with fixed roots
//!    ([`gradient`]);
//! 3. the 1-cells of every saddle, measured up to their first merge ([`cells`]);
//! 4. the cancellation hierarchy by the feature-preserving criterion or by
//!    persistence ([`cancel`]);
//! 5. discarding lines forced by topology (§3.5), optional smoothing (§3.6), and
//!    output of the ascending (ridge-like) and descending (valley-like) 1-cells.
//!
//! The one parameter is how far to simplify: a number of cancellations or of
//! saddles to keep. Lines are always connected, and the method needs no derivative
//! of the indicator, so it is robust to noise.

pub mod cancel;
pub mod cells;
pub mod gradient;
mod indicator;
mod output;

use std::sync::Arc;

use crate::curvature::{CurvatureEstimator, ShapeOperator};
use crate::lines::{FeatureLines, LineExtractor};
use crate::mesh::Mesh;
use crate::progress::{stage, Observer, Silent};
use crate::Result;

pub use cancel::{Cancellation, Criterion};
pub use indicator::Indicator;
pub use output::Cells;

/// How far to simplify the complex.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Simplification {
    /// Make this many cancellations (fewer if no valid one is left).
    Cancel(usize),
    /// Cancel until at most this many saddles are left.
    KeepSaddles(usize),
}

/// Feature lines as 1-cells of a simplified Morse-Smale complex.
#[derive(Clone)]
pub struct MorseSmale {
    /// Estimator for curvature indicators ([`ShapeOperator`] by default; on irregular
    /// meshes its spikes become long-lived maxima: prefer the jet fit there).
    pub estimator: Arc<dyn CurvatureEstimator + Send + Sync>,
    pub indicator: Indicator,
    pub criterion: Criterion,
    pub simplification: Simplification,
    /// Which 1-cells to output.
    pub cells: Cells,
    /// Hide lines that no valid cancellation could remove and that are less
    /// significant than the last cancellation (§3.5).
    pub hide_forced: bool,
    /// Fairing iterations of the output lines (§3.6); 0 for none.
    pub smooth_iterations: usize,
}

impl Default for MorseSmale {
    fn default() -> Self {
        MorseSmale {
            estimator: Arc::new(ShapeOperator),
            indicator: Indicator::Curvedness,
            criterion: Criterion::Feature,
            simplification: Simplification::KeepSaddles(100),
            cells: Cells::Ascending,
            hide_forced: true,
            smooth_iterations: 0,
        }
    }
}

/// Counts of critical points.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct CriticalCounts {
    pub minima: usize,
    pub saddles: usize,
    pub maxima: usize,
}

/// What a run produced besides the lines.
#[derive(Clone, Debug)]
pub struct MorseSummary {
    pub initial: CriticalCounts,
    pub after: CriticalCounts,
    /// The cancellation sequence.
    pub hierarchy: Vec<Cancellation>,
}

impl LineExtractor for MorseSmale {
    fn extract(&self, mesh: &Mesh) -> Result<FeatureLines> {
        Ok(self.run(mesh, &mut Silent)?.0)
    }
}

impl MorseSmale {
    /// Build, simplify and output the complex of `mesh`, recording stage timings
    /// in `report`.
    pub fn run(
        &self,
        mesh: &Mesh,
        observer: &mut dyn Observer,
    ) -> Result<(FeatureLines, MorseSummary)> {
        let values = stage(observer, "indicator", || {
            self.indicator.values(mesh, self.estimator.as_ref())
        })?;
        let keys = gradient::Keys::new(mesh, values);
        let gradient = stage(observer, "gradient", || {
            gradient::Gradient::new(mesh, &keys)
        });
        let (saddles, regions) = stage(observer, "cells", || {
            let saddles = cells::measure_saddles(mesh, &keys, &gradient);
            let regions = (
                cells::minimum_regions(mesh, &keys, &gradient),
                cells::maximum_regions(mesh, &keys, &gradient),
            );
            (saddles, regions)
        });
        let initial = CriticalCounts {
            minima: gradient.minima.len(),
            saddles: gradient.saddles.len(),
            maxima: gradient.maxima.len(),
        };
        let mut hierarchy =
            cancel::Hierarchy::new(mesh, &keys, gradient, saddles, regions, self.criterion);
        stage(observer, "cancellation", || self.simplify(&mut hierarchy));
        let (minima, maxima) = hierarchy.extremum_counts();
        let after = CriticalCounts {
            minima,
            saddles: hierarchy.saddle_count(),
            maxima,
        };
        let lines = stage(observer, "lines", || output::lines(mesh, &hierarchy, self));
        let summary = MorseSummary {
            initial,
            after,
            hierarchy: hierarchy.cancelled,
        };
        Ok((lines, summary))
    }

    fn simplify(&self, hierarchy: &mut cancel::Hierarchy<'_>) {
        let mut count = 0;
        loop {
            let done = match self.simplification {
                Simplification::Cancel(n) => count >= n,
                Simplification::KeepSaddles(n) => hierarchy.saddle_count() <= n,
            };
            if done || hierarchy.cancel_next().is_none() {
                break;
            }
            count += 1;
        }
    }
}
