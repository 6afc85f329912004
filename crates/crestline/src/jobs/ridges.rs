//! Ridge and valley lines by extremality tracing (`crestline ridges`;
//! Hildebrandt, Polthier and Wardetzky 2005).

use serde::{Deserialize, Serialize};

use super::image::Surface;
use crate::curvature::Estimator;
use crate::linalg::Solver;
use crate::lines::FeatureLines;
use crate::progress::Observer;
use crate::ridges::{ExtremalityTracer, Fairing, Kinds};
use crate::Result;

/// Options of [`ridges`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RidgesOptions {
    /// Which lines: ridges (maxima of k_max: convex crests), valleys (minima of
    /// k_min: concave creases) or both. Default: both.
    pub kind: Kinds,
    /// Curvature estimator of a mesh (an isosurface may carry its image's
    /// curvature instead). Default: [`Estimator::Auto`], the jet fit on a clean
    /// mesh and the shape operator on a noisy one.
    pub estimator: Estimator,
    /// Implicit smoothing steps of the extremalities. Default (`None`): the
    /// estimator's ([`ExtremalityTracer::smoothing_defaults`]), or one light step
    /// on an isosurface with its image's extremalities (σ > 0), which come from
    /// the smoothed image ([`ExtremalityTracer::DEFAULT_IMAGE_SMOOTH_STEPS`]).
    pub smooth_steps: Option<usize>,
    /// Smoothing time step, in units of the mean edge length squared. Default
    /// (`None`): the estimator's, at least
    /// [`ExtremalityTracer::DEFAULT_PRESMOOTHED_SMOOTH_TIME`] on a presmoothed
    /// surface, or [`ExtremalityTracer::DEFAULT_IMAGE_SMOOTH_TIME`] on an
    /// isosurface with its image's extremalities.
    pub smooth_time: Option<f64>,
    /// Keep connected lines whose strength (dimensionless: ∫ k_max ds for ridges,
    /// ∫ |k_min| ds for valleys) is at least this. Default:
    /// [`ExtremalityTracer::DEFAULT_THRESHOLD`].
    pub threshold: f64,
    /// Implicit smoothing steps of the surface before tracing (for noisy meshes).
    /// Default: 0.
    pub presmooth: usize,
    /// Solver of the implicit smoothing systems. Default: chosen by the size and
    /// conditioning of the mesh.
    pub solver: Solver,
    /// Fair the lines as space curves ([`Fairing::default`]). Default: no.
    pub fair: bool,
    /// Trace every extremal line, without the feature conditions of the paper
    /// (eqs. 5, 6). Default: no.
    pub all_extrema: bool,
    /// Per-vertex factors for inhomogeneous extremality smoothing. Default: none.
    #[serde(skip)]
    pub smoothing_weights: Option<Vec<f64>>,
}

impl Default for RidgesOptions {
    fn default() -> Self {
        RidgesOptions {
            kind: Kinds::default(),
            estimator: Estimator::Auto,
            smooth_steps: None,
            smooth_time: None,
            threshold: ExtremalityTracer::DEFAULT_THRESHOLD,
            presmooth: 0,
            solver: Solver::default(),
            fair: false,
            all_extrema: false,
            smoothing_weights: None,
        }
    }
}

impl RidgesOptions {
    /// The tracer these options describe, on `surface`.
    pub fn tracer(&self, surface: &Surface) -> ExtremalityTracer {
        let (smooth_steps, smooth_time) = if surface.has_image_extremalities() {
            (
                ExtremalityTracer::DEFAULT_IMAGE_SMOOTH_STEPS,
                ExtremalityTracer::DEFAULT_IMAGE_SMOOTH_TIME,
            )
        } else {
            ExtremalityTracer::smoothing_defaults(self.estimator, self.presmooth > 0)
        };
        ExtremalityTracer {
            estimator: surface.estimator(self.estimator),
            kinds: self.kind,
            smooth_steps: self.smooth_steps.unwrap_or(smooth_steps),
            smooth_time: self.smooth_time.unwrap_or(smooth_time),
            threshold: self.threshold,
            presmooth_steps: self.presmooth,
            fairing: self.fair.then(Fairing::default),
            smoothing_weights: self.smoothing_weights.clone(),
            feature_conditions: !self.all_extrema,
            solver: self.solver,
        }
    }
}

/// The ridge and valley lines of `surface` as `options` say
/// ([`ExtremalityTracer::trace`]): its stages and counts, the counts `vertices` and
/// `faces`, and warnings for repaired curvature and when no line is strong
/// enough.
pub fn ridges(
    surface: &Surface,
    options: &RidgesOptions,
    observer: &mut dyn Observer,
) -> Result<FeatureLines> {
    let mesh = &surface.mesh;
    observer.count("vertices", mesh.vertex_count());
    observer.count("faces", mesh.face_count());
    let lines = options.tracer(surface).trace(mesh, observer)?;
    if lines.is_empty() {
        observer.warning(&format!(
            "no line is as strong as the threshold {}; try a lower `threshold`",
            options.threshold
        ));
    }
    Ok(lines)
}
