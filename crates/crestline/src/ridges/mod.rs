//! Ridge and valley lines by extremality tracing (Hildebrandt, Polthier, Wardetzky:
//! "Smooth feature lines on surface meshes", SGP 2005).
//!
//! The steps of the paper's Table 1, each in its own module (chaining and fairing are
//! the shared line tools of [`crate::lines`]):
//! 1. optional implicit smoothing of the surface ([`presmooth_surface`]);
//! 2. principal curvatures and directions (any [`CurvatureEstimator`]), extremalities
//!    e_max, e_min (eq. 4) and regular triangles (Definition 1) (`extremality()`);
//!    an estimator that gives the extremalities itself
//!    ([`CurvatureField::extremality`]: [`crate::curvature::JetFit`], from the
//!    third-order terms of its fitted jets) is used as it is, which keeps the
//!    fit's precision that differentiating its curvature over the 1-ring loses;
//!    optionally after heat smoothing of the curvature tensor field
//!    ([`ExtremalityTracer::curvature_smooth_steps`], `ridges/tensor.rs`), whose
//!    extremalities are then those of eq. 4;
//! 3. sign-aware implicit smoothing of the extremalities (§5.1)
//!    (`ridges/smoothing.rs`); fitted extremalities are smoothed in
//!    proportion to the noise their fit residual shows
//!    (`fitted_smoothing_factors`), so clean meshes keep their precision;
//! 4. tracing the zero sets in regular triangles under the feature conditions (eqs. 5,
//!    6), then bridging singular triangles (§4.2) (`ridges/trace.rs`), with the shared
//!    zero-set tracer ([`crate::lines::ZeroSet`]);
//! 5. chaining into polylines and the strength filter ∫ k ds ≥ T
//!    ([`crate::lines::chain()`]);
//! 6. optional fairing of the lines as space curves (§5.2)
//!    (`lines/fair.rs`).
//!
//! Ridges are maxima of k_max along its direction (convex crests); valleys are
//! minima of k_min (concave creases), with outward normals.
//!
//! Degrading instead of aborting: the built-in estimators flag non-finite and
//! outlying curvatures unreliable and replace them by the median of their 1-ring
//! (`crate::curvature::repair_outliers`), so such a vertex enters the extremality,
//! its smoothing and the tracing with its neighbourhood's values, and a run never
//! fails on one; their number is reported as `unreliable_vertices`. The geometry
//! of every step is computed on the mesh scaled by a power of two into the unit
//! frame ([`Mesh::in_unit_frame`]), so coordinates of any magnitude work.

pub(crate) mod extremality;
pub(crate) mod smoothing;
mod tensor;
#[cfg(test)]
mod tests;
pub(crate) mod trace;

use std::sync::Arc;
use std::time::Instant;

use rayon::prelude::*;

use crate::curvature::{
    estimate_curvature, CurvatureEstimator, CurvatureField, Estimator, ShapeOperator,
};
use crate::linalg::CholeskyAnalysis;
pub use crate::linalg::Solver;
use crate::lines::chain::chain;
use crate::lines::direction_field::gauge_between;
use crate::lines::fair::fair_polyline;
use crate::lines::oriented::{along_line, DirectedSample};
use crate::lines::zero_set::LinePoint;
use crate::lines::{
    EdgeSigns, FeatureLines, LineExtractor, LineKind, Polyline, SurfaceLocation,
    SurfaceWithCurvature,
};
use crate::mesh::{Mesh, VertexId};
use crate::progress::{checkpoint, stage, try_stage, try_stage_with, Observer, Silent, Timings};
use crate::{Error, Result};

pub(crate) use extremality::extremality;
use extremality::regular_faces;
pub use extremality::Principal;
pub use smoothing::presmooth_surface;
use trace::Extremality;

/// Which lines to extract.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Kinds {
    /// Ridges only (maxima of k_max: convex crests).
    Ridges,
    /// Valleys only (minima of k_min: concave creases).
    Valleys,
    /// Both.
    #[default]
    Both,
}

crate::named::named!(Kinds, "line kind", {
    Ridges => "ridges",
    Valleys => "valleys",
    Both => "both",
});

impl Kinds {
    fn fields(self) -> &'static [Principal] {
        match self {
            Kinds::Ridges => &[Principal::Max],
            Kinds::Valleys => &[Principal::Min],
            Kinds::Both => &[Principal::Max, Principal::Min],
        }
    }
}

/// Fairing of the traced lines as space curves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fairing {
    /// Number of λ|μ smoothing iterations.
    pub iterations: usize,
    /// How far a point may move, in mean edge lengths.
    pub max_distance: f64,
}

impl Default for Fairing {
    fn default() -> Self {
        Fairing {
            iterations: 10,
            max_distance: 0.5,
        }
    }
}

/// Ridge and valley lines by extremality tracing, with every option of the paper.
/// The defaults give clean lines on a clean irregular mesh: 3 smoothing steps of
/// τ = 2 and threshold 2 (see the crate's design notes for the measurements).
#[derive(Clone)]
pub struct ExtremalityTracer {
    /// Curvature estimator ([`ShapeOperator`] by default).
    pub estimator: Arc<dyn CurvatureEstimator + Send + Sync>,
    /// Which lines to extract.
    pub kinds: Kinds,
    /// Implicit smoothing steps of the extremalities. Extremalities the estimator
    /// gives with a fit residual are smoothed only where the residual shows noise
    /// (`fitted_smoothing_factors`).
    pub smooth_steps: usize,
    /// Time step τ of extremality smoothing, in units of the mean edge length squared.
    pub smooth_time: f64,
    /// Keep connected lines whose strength is at least this (dimensionless): ∫ k_max ds
    /// for ridges, ∫ |k_min| ds for valleys (Ohtake et al. 2004).
    pub threshold: f64,
    /// Implicit smoothing steps of the surface before curvature estimation; lines
    /// are traced on the smoothed surface and placed back on the input mesh.
    pub presmooth_steps: usize,
    /// Time step of the surface's smoothing, in units of the input's mean edge
    /// length squared ([`Self::DEFAULT_PRESMOOTH_TIME`]).
    pub presmooth_time: f64,
    /// Implicit heat steps (M + tK) S' = M S of the curvature tensor field
    /// S = k_max d_max d_maxᵀ + k_min d_min d_minᵀ before the extremalities are
    /// taken (eq. 4, from the smoothed principal curvatures and directions),
    /// estimated or given: the surface stays in place. 0 (the default) leaves the
    /// field as it is.
    pub curvature_smooth_steps: usize,
    /// Time step of the curvature tensor's smoothing, in units of the mean edge
    /// length squared of the surface the curvature belongs to (after
    /// presmoothing, if any).
    pub curvature_smooth_time: f64,
    /// Optional fairing of the lines as space curves.
    pub fair: Option<Fairing>,
    /// Optional per-vertex factors for inhomogeneous extremality smoothing (§6).
    pub smoothing_weights: Option<Vec<f64>>,
    /// Trace every extremal line of either curvature, maxima and minima alike (the
    /// generic ridges of Porteous; e.g. all three principal ellipses of an
    /// ellipsoid), without the feature conditions (eqs. 5, 6: maxima of k_max
    /// where it dominates in magnitude, minima of k_min likewise), which keep only
    /// the sharpest one.
    pub all_extrema: bool,
    /// How the implicit smoothing systems (§5.1) are solved: sparse Cholesky,
    /// conjugate gradient, or by mesh size ([`Solver::Auto`], the default).
    pub solver: Solver,
}

impl ExtremalityTracer {
    /// Default number of implicit smoothing steps of the extremalities.
    pub const DEFAULT_SMOOTH_STEPS: usize = 3;
    /// Default smoothing time τ, in units of the mean edge length squared.
    pub const DEFAULT_SMOOTH_TIME: f64 = 2.0;
    /// Default number of implicit smoothing steps of extremalities the estimator
    /// gives ([`CurvatureField::extremality`], e.g. [`crate::curvature::JetFit`]'s),
    /// weighted by `fitted_smoothing_factors`. Measured on a rotated, irregular
    /// 30k-vertex ellipsoid (example `jet_extremality`): on the clean mesh the
    /// weights are about 10⁻⁵ and the ridge stays at 0.0004% of the diagonal from
    /// the true plane (every unweighted step costs precision: 1 step of τ = 0.25
    /// gives 0.0024%, 3 of τ = 2 give 0.0058%); on scans the weights are 1 and
    /// the lines are those of the discrete path in number and smoothness.
    pub const DEFAULT_FITTED_SMOOTH_STEPS: usize = 3;
    /// Default smoothing time τ of extremalities the estimator gives. Fitted
    /// extremalities of noisy meshes need a little more smoothing than the
    /// discrete ones: with normal noise of 0.2 h̄, 3 presmoothing and 5 smoothing
    /// steps, the ridge lies 0.24% of the diagonal from the true plane with τ = 2,
    /// 0.17% with τ = 3, 0.15% with τ = 4 (the discrete path: 0.21% with τ = 2);
    /// more smoothing also removes more of the weaker lines of scans.
    pub const DEFAULT_FITTED_SMOOTH_TIME: f64 = 3.0;
    /// Default smoothing time τ of the extremalities of a presmoothed surface
    /// (presmoothing is what one asks for on noisy scans), unless the estimator's
    /// is longer: the noise presmoothing leaves calls for more than the 2 of clean
    /// meshes. Measured on a rotated, jittered 30k-vertex ellipsoid with isotropic
    /// Gaussian noise, 3 presmoothing and 5 smoothing steps, shape operator, mean
    /// over 3 seeds (example `jet_extremality -- --noise-table`): the ridge lies
    /// 0.052%, 0.21% and 0.43% of the diagonal from the true plane with τ = 2 at
    /// noise 0.05, 0.2 and 0.5 mean edge lengths, 0.033%, 0.14% and 0.33% with
    /// τ = 3 (0.025%, 0.11%, 0.33% with τ = 4, which removes more of the weaker
    /// lines of scans). It is the fitted extremalities' default time as well.
    pub const DEFAULT_PRESMOOTHED_SMOOTH_TIME: f64 = 3.0;
    /// Default number of smoothing steps of the extremalities of an image's
    /// isosurface taken from the image's third derivatives
    /// ([`crate::curvature::ImageCurvature`]), which the Gaussian σ of the image
    /// has smoothed already: one light step ([`Self::DEFAULT_IMAGE_SMOOTH_TIME`])
    /// only clears the saw-tooth their zero set draws across the isosurface's
    /// uneven triangles. Measured on an ellipsoid image turned off the grid axes
    /// (example `image_extremality`, σ = 1 voxel): the ridge lies 0.028 voxel from
    /// the true plane (0.0017 unsmoothed; 0.11 after the 3 steps of τ = 2 of
    /// discrete extremalities, which smooth any extremality that far).
    pub const DEFAULT_IMAGE_SMOOTH_STEPS: usize = 1;
    /// Default smoothing time τ of an image's extremalities, in units of the mean
    /// edge length squared.
    pub const DEFAULT_IMAGE_SMOOTH_TIME: f64 = 0.25;
    /// Default time step of the surface's presmoothing, in units of the mean edge
    /// length squared (Desbrun et al. 1999's implicit fairing step).
    pub const DEFAULT_PRESMOOTH_TIME: f64 = 1.0;
    /// Default strength threshold (dimensionless).
    pub const DEFAULT_THRESHOLD: f64 = 2.0;
    /// The most smoothing steps (of the surface or of the extremalities) accepted.
    pub const MAX_STEPS: usize = 1000;

    /// The default tracer with one of the crate's estimators and the smoothing
    /// defaults of its extremalities: [`Self::DEFAULT_SMOOTH_STEPS`] and
    /// [`Self::DEFAULT_SMOOTH_TIME`] for the discrete ones of the shape operator,
    /// [`Self::DEFAULT_FITTED_SMOOTH_STEPS`] and [`Self::DEFAULT_FITTED_SMOOTH_TIME`]
    /// for those of the jet fit.
    pub fn with_estimator(estimator: Estimator) -> Self {
        let (smooth_steps, smooth_time) = Self::smoothing_defaults(estimator, false);
        ExtremalityTracer {
            estimator: estimator.build(),
            smooth_steps,
            smooth_time,
            ..ExtremalityTracer::default()
        }
    }

    /// The default smoothing steps and time of the extremalities `estimator`
    /// gives or leads to (see [`Self::with_estimator`]), on a surface
    /// `presmoothed` or not (then τ is at least
    /// [`Self::DEFAULT_PRESMOOTHED_SMOOTH_TIME`]).
    pub fn smoothing_defaults(estimator: Estimator, presmoothed: bool) -> (usize, f64) {
        let (steps, time) = match estimator {
            // The jet fit chosen on a clean mesh smooths its extremalities by the
            // residual weights, which vanish there; a noisy mesh gets the shape
            // operator and its smoothing.
            Estimator::ShapeOperator | Estimator::Auto => {
                (Self::DEFAULT_SMOOTH_STEPS, Self::DEFAULT_SMOOTH_TIME)
            }
            Estimator::JetFit => (
                Self::DEFAULT_FITTED_SMOOTH_STEPS,
                Self::DEFAULT_FITTED_SMOOTH_TIME,
            ),
        };
        if presmoothed {
            (steps, time.max(Self::DEFAULT_PRESMOOTHED_SMOOTH_TIME))
        } else {
            (steps, time)
        }
    }
}

impl Default for ExtremalityTracer {
    fn default() -> Self {
        ExtremalityTracer {
            estimator: Arc::new(ShapeOperator),
            kinds: Kinds::Both,
            smooth_steps: Self::DEFAULT_SMOOTH_STEPS,
            smooth_time: Self::DEFAULT_SMOOTH_TIME,
            threshold: Self::DEFAULT_THRESHOLD,
            presmooth_steps: 0,
            presmooth_time: Self::DEFAULT_PRESMOOTH_TIME,
            curvature_smooth_steps: 0,
            curvature_smooth_time: 1.0,
            fair: None,
            smoothing_weights: None,
            all_extrema: false,
            solver: Solver::Auto,
        }
    }
}

impl LineExtractor for ExtremalityTracer {
    fn extract(&self, mesh: &Mesh, observer: &mut dyn Observer) -> Result<FeatureLines> {
        self.trace(mesh, observer)
    }
}

impl LineExtractor<SurfaceWithCurvature<'_>> for ExtremalityTracer {
    fn extract(
        &self,
        surface: &SurfaceWithCurvature<'_>,
        observer: &mut dyn Observer,
    ) -> Result<FeatureLines> {
        self.trace_with_curvature(surface.mesh, surface.curvature, observer)
    }
}

impl ExtremalityTracer {
    /// Extract the lines of `mesh`: optional presmoothing, curvature by
    /// [`Self::estimator`], then [`Self::trace_with_curvature`]'s steps. Stage
    /// timings, the share of singular triangles per field, the number of interior
    /// vertices whose curvature is unreliable (`unreliable_vertices`: non-finite or
    /// outlying estimates, flagged and replaced by the built-in estimators) and line
    /// counts go to `observer`.
    ///
    /// The smoothing systems' ordering depends on the connectivity alone: it is
    /// computed while the curvature, the extremalities and the edge signs are
    /// (stages `curvature`, `extremality`, `edge signs`), and the stage
    /// `smoothing analysis` is the time it takes beyond them.
    pub fn trace(&self, mesh: &Mesh, observer: &mut dyn Observer) -> Result<FeatureLines> {
        self.check()?;
        let (smoothed, analysis) =
            try_stage_with(observer, "presmooth", |log| self.presmoothed(mesh, log))?;
        let work = smoothed.as_ref().unwrap_or(mesh);
        let (unit, factor) = work.in_unit_frame();
        let ((field, fields), smoother) =
            self.alongside_analysis(&unit, analysis, "curvature", observer, |log| {
                let field = try_stage(log, "curvature", || {
                    estimate_curvature(work, self.estimator.as_ref())
                })?;
                let field = self.smoothed_curvature(&unit, field, log)?;
                let fields = self.fields(&unit, factor, &field, log);
                Ok((field, fields))
            })?;
        self.trace_on(&unit, &field, fields, &smoother, mesh, observer)
    }

    /// Runs `prepare` (which reports its stages, the first named `first`, to the
    /// log it is given) while the smoothing systems of `work` are analysed
    /// ([`Self::smoother`], reusing a `known` analysis) on another thread, then
    /// reports `prepare`'s stages and the stage `smoothing analysis`: the time the
    /// analysis took beyond them.
    fn alongside_analysis<T: Send>(
        &self,
        work: &Mesh,
        known: Option<CholeskyAnalysis>,
        first: &str,
        observer: &mut dyn Observer,
        prepare: impl FnOnce(&mut dyn Observer) -> Result<T> + Send,
    ) -> Result<(T, smoothing::ExtremalitySmoother)> {
        checkpoint(observer)?;
        let start = Instant::now();
        observer.stage_started(first);
        let ((log, prepared), smoother) = rayon::join(
            || {
                let mut log = Timings::default();
                let prepared = prepare(&mut log);
                (log, prepared)
            },
            || self.smoother(work, known),
        );
        for (k, (name, seconds)) in log.stages.iter().enumerate() {
            if k > 0 {
                observer.stage_started(name);
            }
            observer.stage_finished(name, *seconds);
        }
        let overlapped: f64 = log.stages.iter().map(|(_, seconds)| seconds).sum();
        observer.stage_started("smoothing analysis");
        let rest = start.elapsed().as_secs_f64() - overlapped;
        observer.stage_finished("smoothing analysis", rest.max(0.0));
        let prepared = prepared?;
        let smoother = smoother.map_err(|e| e.in_stage("smoothing analysis"))?;
        checkpoint(observer)?;
        Ok((prepared, smoother))
    }

    /// The smoother of the extremalities of `work` ([`Self::smooth_time`],
    /// [`Self::smoothing_weights`], [`Self::solver`]), its systems analysed (or
    /// given the `known` analysis of their pattern) if there is smoothing to do.
    fn smoother(
        &self,
        work: &Mesh,
        known: Option<CholeskyAnalysis>,
    ) -> Result<smoothing::ExtremalitySmoother> {
        let weights = self.smoothing_weights.as_deref();
        let smoother =
            smoothing::ExtremalitySmoother::new(work, self.smooth_time, weights, self.solver)?;
        if self.smooth_steps == 0 {
            return Ok(smoother);
        }
        smoother.analyzed(known)
    }

    /// Extract the lines of `mesh` whose principal curvatures and directions are
    /// already known (`field`, one entry per vertex, e.g. from image derivatives or a
    /// custom estimator): extremalities, their smoothing, tracing, chaining, the
    /// strength filter and fairing. [`Self::estimator`] is not used, and
    /// presmoothing is an error (it would change the surface the curvature belongs
    /// to).
    pub fn trace_with_curvature(
        &self,
        mesh: &Mesh,
        field: &CurvatureField,
        observer: &mut dyn Observer,
    ) -> Result<FeatureLines> {
        self.check()?;
        if self.presmooth_steps > 0 {
            return Err(Error::Argument(
                "presmoothing needs the curvature of the smoothed surface: set presmooth_steps to 0 when the curvature is given".into(),
            ));
        }
        field.check(mesh)?;
        let (unit, factor) = mesh.in_unit_frame();
        let smoothed = if self.curvature_smooth_steps > 0 {
            Some(self.smoothed_curvature(&unit, field.clone(), observer)?)
        } else {
            None
        };
        let field = smoothed.as_ref().unwrap_or(field);
        let (fields, smoother) =
            self.alongside_analysis(&unit, None, "extremality", observer, |log| {
                Ok(self.fields(&unit, factor, field, log))
            })?;
        self.trace_on(&unit, field, fields, &smoother, mesh, observer)
    }

    /// The extremality of every field of [`Self::kinds`] on `work` (stage
    /// `extremality`): the field's own if it has them
    /// ([`CurvatureField::extremality`], e.g. from [`crate::curvature::JetFit`]),
    /// else eq. 4; and the fields' signs on every edge (stage `edge signs`), which
    /// the smoothing and the tracing read. `work` is the mesh in the unit frame,
    /// scaled by `factor` ([`Mesh::in_unit_frame`]).
    fn fields(
        &self,
        work: &Mesh,
        factor: f64,
        field: &CurvatureField,
        observer: &mut dyn Observer,
    ) -> (Vec<Vec<f64>>, Vec<EdgeSigns>) {
        let fields = self.kinds.fields();
        let values = stage(observer, "extremality", || {
            fields
                .par_iter()
                .map(|&which| match which.given(field) {
                    // In the unit frame: derivatives of curvature scale by 1/factor².
                    Some(given) => given.iter().map(|e| e / (factor * factor)).collect(),
                    None => extremality(work, field, which),
                })
                .collect::<Vec<_>>()
        });
        let signs = stage(observer, "edge signs", || {
            fields
                .iter()
                .map(|which| EdgeSigns::new(work, which.direction_field(field)))
                .collect()
        });
        (values, signs)
    }

    /// The lines of `work` (whose curvature is `field`, and whose extremalities and
    /// edge signs are `fields`, from [`Self::fields`]) placed on `input` (the same
    /// connectivity, e.g. before presmoothing). `work` may be scaled by any factor
    /// (it is passed in the unit frame, [`Mesh::in_unit_frame`], so that areas
    /// and gradients neither overflow nor underflow): the zero sets of
    /// the extremalities, the feature conditions and the strengths (∫ k ds with k
    /// from `field` and lengths from `input`) do not change with the scale of
    /// `work`.
    fn trace_on(
        &self,
        work: &Mesh,
        field: &CurvatureField,
        (mut values, signs): (Vec<Vec<f64>>, Vec<EdgeSigns>),
        smoother: &smoothing::ExtremalitySmoother,
        input: &Mesh,
        observer: &mut dyn Observer,
    ) -> Result<FeatureLines> {
        let unreliable = unreliable_interior(input, field);
        observer.count("unreliable_vertices", unreliable);
        if unreliable > 0 {
            observer.warning(&format!(
                "curvature at {unreliable} interior vertices was an outlier or not finite and was \
                 replaced by its neighbours' median"
            ));
        }
        let fields = self.kinds.fields();
        try_stage_with(
            observer,
            "smoothing",
            |log| match fitted_smoothing_factors(work, field) {
                Some(factors) if self.smooth_steps > 0 => {
                    let reweighted = smoother.reweighted(work, &factors)?;
                    self.smooth_extremalities(work, &reweighted, field, &signs, &mut values, log)
                }
                _ => self.smooth_extremalities(work, smoother, field, &signs, &mut values, log),
            },
        )?;
        let mut lines = FeatureLines::new(String::new());
        lines.space = input.space();
        for ((&which, field_values), signs) in fields.iter().zip(&values).zip(&signs) {
            let traced = self.trace_field(
                work,
                field,
                (which, signs),
                field_values.clone(),
                input,
                observer,
            );
            for line in traced {
                lines.push(with_extremalities(line, work, field, fields, &values));
            }
        }
        if let Some(fairing) = self.fair {
            let h = input.mean_edge_length();
            stage(observer, "fairing", || {
                for line in &mut lines.lines {
                    fair_polyline(
                        &mut line.points,
                        line.closed,
                        fairing.iterations,
                        fairing.max_distance * h,
                    );
                    // Faired points leave the surface.
                    line.locations.clear();
                }
            });
        }
        observer.count("lines", lines.len());
        observer.count("ridges", lines.of_kind(LineKind::Ridge).count());
        observer.count("valleys", lines.of_kind(LineKind::Valley).count());
        observer.measure("total_length", lines.total_length());
        Ok(lines)
    }

    fn check(&self) -> Result<()> {
        let bad = |what: &str, value: f64| {
            Error::Argument(format!("{what} must be finite and positive, got {value}"))
        };
        let negative = |what: &str, value: f64| {
            Error::Argument(format!(
                "{what} must be finite and not negative, got {value}"
            ))
        };
        if !(self.smooth_time.is_finite() && self.smooth_time > 0.0) {
            return Err(bad("the smoothing time `smooth_time`", self.smooth_time));
        }
        if self.curvature_smooth_steps > 0
            && !(self.curvature_smooth_time.is_finite() && self.curvature_smooth_time > 0.0)
        {
            return Err(bad(
                "the curvature smoothing time `curvature_smooth_time`",
                self.curvature_smooth_time,
            ));
        }
        if !(self.threshold.is_finite() && self.threshold >= 0.0) {
            return Err(negative(
                "the strength threshold `threshold`",
                self.threshold,
            ));
        }
        if let Some(f) = self.fair {
            if !(f.max_distance.is_finite() && f.max_distance >= 0.0) {
                return Err(negative("the fairing distance", f.max_distance));
            }
        }
        for (what, steps) in [
            (
                "extremality smoothing steps (`smooth_steps`)",
                self.smooth_steps,
            ),
            ("presmoothing steps (`presmooth`)", self.presmooth_steps),
            (
                "curvature smoothing steps (`curvature_smooth_steps`)",
                self.curvature_smooth_steps,
            ),
        ] {
            if steps > Self::MAX_STEPS {
                return Err(Error::Argument(format!(
                    "{steps} {what} are more than the limit of {}",
                    Self::MAX_STEPS
                )));
            }
        }
        Ok(())
    }

    /// `field` of `work` (in the unit frame) with its tensors smoothed as
    /// [`Self::curvature_smooth_steps`] says (stage `curvature smoothing`).
    fn smoothed_curvature(
        &self,
        work: &Mesh,
        field: CurvatureField,
        observer: &mut dyn Observer,
    ) -> Result<CurvatureField> {
        if self.curvature_smooth_steps == 0 {
            return Ok(field);
        }
        try_stage_with(observer, "curvature smoothing", |log| {
            tensor::smooth_curvature(
                work,
                &field,
                self.curvature_smooth_steps,
                self.curvature_smooth_time,
                self.solver,
                log,
            )
        })
    }

    /// The smoothed surface, if pre-smoothing is asked for, and the analysis of
    /// its system if it was factored.
    fn presmoothed(
        &self,
        mesh: &Mesh,
        observer: &mut dyn Observer,
    ) -> Result<(Option<Mesh>, Option<CholeskyAnalysis>)> {
        if self.presmooth_steps == 0 {
            return Ok((None, None));
        }
        let (smoothed, analysis) = smoothing::presmooth_analyzed(
            mesh,
            self.presmooth_steps,
            self.presmooth_time,
            self.solver,
            observer,
        )?;
        Ok((Some(smoothed), analysis))
    }

    /// The implicit smoothing (§5.1) of the extremality `values` of every field on
    /// `work`. The two principal fields' systems are one matrix up to a
    /// per-vertex sign ([`gauge_between`]): the valleys' values are carried into
    /// the ridges' gauge, both are smoothed with one factorization or one
    /// multigrid hierarchy, and carried back. `signs` are the fields' edge
    /// signs, one per field of [`Self::kinds`]. Where the fields' signs do not
    /// agree so (directions a caller gave, not orthogonal), each field has its
    /// own system: factored ones in parallel, one field per thread, sharing the
    /// ordering (`smoother`'s); iterated ones one at a time, each in parallel,
    /// which halves the solver's memory.
    fn smooth_extremalities(
        &self,
        work: &Mesh,
        smoother: &smoothing::ExtremalitySmoother,
        field: &CurvatureField,
        signs: &[EdgeSigns],
        values: &mut [Vec<f64>],
        observer: &mut dyn Observer,
    ) -> Result<()> {
        let steps = self.smooth_steps;
        let fields = self.kinds.fields();
        if let ([Principal::Max, Principal::Min], [max, min]) = (fields, &mut *values) {
            let ridges = Principal::Max.direction_field(field);
            let valleys = Principal::Min.direction_field(field);
            let gauge = gauge_between(work, (ridges, &signs[0]), (valleys, &signs[1]));
            if let Some(gauge) = gauge {
                regauge(min, &gauge);
                smoother.smooth(&signs[0], &mut [max, min], steps, observer)?;
                regauge(min, &gauge);
                return Ok(());
            }
        }
        if smoother.iterates() {
            signs
                .iter()
                .zip(values.iter_mut())
                .try_for_each(|(signs, values)| {
                    smoother.smooth(signs, &mut [values], steps, observer)
                })
        } else {
            // The factored solves, a field per thread, are asked nothing: they
            // take a fraction of the factorization's time.
            signs
                .par_iter()
                .zip(values.par_iter_mut())
                .try_for_each(|(signs, values)| {
                    smoother.smooth(signs, &mut [values], steps, &mut Silent)
                })
        }
    }

    /// Tracing and chaining of the smoothed extremality `values` of one field
    /// (with its edge signs) on `work`; line points are placed on `input` (the
    /// same edge and parameter).
    fn trace_field(
        &self,
        work: &Mesh,
        field: &CurvatureField,
        (which, signs): (Principal, &EdgeSigns),
        values: Vec<f64>,
        input: &Mesh,
        observer: &mut dyn Observer,
    ) -> Vec<Polyline> {
        let (name, kind) = match which {
            Principal::Max => ("ridges", LineKind::Ridge),
            Principal::Min => ("valleys", LineKind::Valley),
        };
        let regular = regular_faces(work, signs);
        let singular = regular.iter().filter(|&&r| !r).count();
        observer.measure(
            &format!("{name}_singular_share"),
            singular as f64 / regular.len() as f64,
        );
        let ext = Extremality::new(which, values, field, signs, &regular, !self.all_extrema);
        let segments = stage(observer, &format!("{name}: tracing"), || {
            trace::trace(work, field, &ext)
        });
        let locate = |p: LinePoint| ext.zero_set.location(work, p);
        let integrand = strength_integrand(field, which);
        let chains = stage(observer, &format!("{name}: chaining"), || {
            let position_and_k = |p: LinePoint| {
                let at = locate(p);
                (at.position(input), at.interpolate(work, &integrand))
            };
            chain(&segments, position_and_k, self.threshold)
        });
        chains
            .into_iter()
            .map(|c| {
                let locations: Vec<SurfaceLocation> = c.points.iter().map(|&p| locate(p)).collect();
                let points = locations.iter().map(|at| at.position(input)).collect();
                let at_points = |values: &[f64]| {
                    locations
                        .iter()
                        .map(|at| at.interpolate(work, values))
                        .collect()
                };
                Polyline::new(kind, c.closed, c.strength, points)
                    .with_values("k_max", at_points(&field.k_max))
                    .with_values("k_min", at_points(&field.k_min))
                    .with_locations(locations)
            })
            .collect()
    }
}

/// The line with the smoothed extremality of every field traced (`e_max`,
/// `e_min`) at its points, read along it with the principal direction's sign
/// carried from point to point ([`along_line`]): only their signs along the line
/// are meaningful, and the zero crossings of the other field's extremality on a
/// crest line are Thirion's extremal points.
fn with_extremalities(
    line: Polyline,
    work: &Mesh,
    field: &CurvatureField,
    fields: &[Principal],
    values: &[Vec<f64>],
) -> Polyline {
    fields
        .iter()
        .zip(values)
        .fold(line, |line, (&which, values)| {
            let directions = which.directions(field);
            let samples = line.locations.iter().map(|at| {
                let sample = |(v, weight): (VertexId, f64)| DirectedSample {
                    weight,
                    value: values[v.idx()],
                    direction: directions[v.idx()],
                };
                at.weights(work).into_iter().map(sample).collect::<Vec<_>>()
            });
            let along = along_line(samples);
            line.with_values(which.extremality_name(), along)
        })
}

/// `values` times the per-vertex signs `gauge`: a field's values carried into
/// another choice of its directions' signs (and back, the signs being ±1).
fn regauge(values: &mut [f64], gauge: &[f64]) {
    for (v, g) in values.iter_mut().zip(gauge) {
        *v *= g;
    }
}

/// The fit residual ([`CurvatureField::fit_residual`]) at and above which fitted
/// extremalities are smoothed fully: the residual that tells a clean mesh from a
/// noisy one ([`crate::curvature::CLEAN_FIT_RESIDUAL`], with the measured values).
pub(crate) const FULL_SMOOTHING_RESIDUAL: f64 = crate::curvature::CLEAN_FIT_RESIDUAL;

/// Per-vertex factors of the extremality smoothing where the field's
/// extremalities come from a fit ([`CurvatureField::extremality`] with
/// [`CurvatureField::fit_residual`]): min(1, (r / [`FULL_SMOOTHING_RESIDUAL`])²),
/// r the median residual over the vertex's closed 1-ring. Smoothing then removes
/// noise only: where the vertices lie on the fitted surfaces (a clean mesh) the
/// fitted extremalities are left as they are, since every smoothing step moves
/// their zero set away from the ridge (measured in the example
/// `jet_extremality`). `None` for other fields.
pub(crate) fn fitted_smoothing_factors(mesh: &Mesh, field: &CurvatureField) -> Option<Vec<f64>> {
    field.extremality.as_ref()?;
    let residual = field.fit_residual.as_ref()?;
    Some(
        mesh.par_vertices()
            .map(|v| {
                let mut ring: Vec<f64> = std::iter::once(v)
                    .chain(mesh.neighbors(v))
                    .map(|w| residual[w.idx()])
                    .collect();
                ring.sort_by(f64::total_cmp);
                let median = ring[ring.len() / 2];
                (median / FULL_SMOOTHING_RESIDUAL).powi(2).min(1.0)
            })
            .collect(),
    )
}

/// The number of interior vertices flagged unreliable in `field` (boundary vertices
/// always are, and are not counted).
fn unreliable_interior(mesh: &Mesh, field: &CurvatureField) -> usize {
    mesh.vertices()
        .filter(|&v| field.unreliable[v.idx()] && !mesh.is_boundary_vertex(v))
        .count()
}

/// The integrand of the strength ∫ k ds per vertex: k_max for ridges, |k_min| for
/// valleys (Hildebrandt et al. §4, after Ohtake et al. 2004).
fn strength_integrand(field: &CurvatureField, which: Principal) -> Vec<f64> {
    match which {
        Principal::Max => field.k_max.clone(),
        Principal::Min => field.k_min.iter().map(|k| k.abs()).collect(),
    }
}
