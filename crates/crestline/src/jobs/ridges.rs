//! Ridge and valley lines by extremality tracing (`crestline ridges`;
//! Hildebrandt, Polthier and Wardetzky 2005).

use serde::{Deserialize, Serialize};

use super::image::Surface;
use super::scale::SCALE_SMOOTH_STEPS;
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
    /// The feature scale of a mesh, in world units (`super::scale`): the surface
    /// is smoothed for a time of scale² before its curvature is estimated, and the
    /// extremalities for (scale/2)², both in world units rather than in mean edge
    /// lengths, so that another sampling of the same surface gives the same lines
    /// (`smooth_steps`, `smooth_time` and `presmooth`, when given, still apply).
    /// An image's isosurface takes its image's scale instead (σ,
    /// [`super::IsoOptions::scale`]). Default: none, the smoothing counts mean edge
    /// lengths.
    pub scale: Option<f64>,
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
            scale: None,
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
        let tracer = ExtremalityTracer {
            estimator: surface.estimator(self.estimator),
            kinds: self.kind,
            smooth_steps: self.smooth_steps.unwrap_or(smooth_steps),
            smooth_time: self.smooth_time.unwrap_or(smooth_time),
            threshold: self.threshold,
            presmooth_steps: self.presmooth,
            presmooth_time: ExtremalityTracer::DEFAULT_PRESMOOTH_TIME,
            fairing: self.fair.then(Fairing::default),
            smoothing_weights: self.smoothing_weights.clone(),
            feature_conditions: !self.all_extrema,
            solver: self.solver,
        };
        match (self.scale, surface.image) {
            (Some(scale), None) => self.at_scale(tracer, scale, surface.mesh.mean_edge_length()),
            _ => tracer,
        }
    }

    /// `tracer` with its smoothing times in world units: the surface smoothed for
    /// scale², the extremalities for (scale/2)², each in `presmooth` (or
    /// [`SCALE_SMOOTH_STEPS`]) and `smooth_steps` (or as many) steps, on a mesh of
    /// mean edge length `edge` (the unit of the tracer's times). Measured
    /// (`tools/sampling_invariance.py`, the test `sampling`): a scale of 3 mean
    /// edge lengths or more keeps the lines of an irregular mesh; at 1.5 the
    /// smoothing, as long as the cotan Laplacian's pointwise error on irregular
    /// triangles, adds as much curvature noise as it removes.
    fn at_scale(&self, tracer: ExtremalityTracer, scale: f64, edge: f64) -> ExtremalityTracer {
        let presmooth_steps = if self.presmooth > 0 {
            self.presmooth
        } else {
            SCALE_SMOOTH_STEPS
        };
        let smooth_steps = self.smooth_steps.unwrap_or(SCALE_SMOOTH_STEPS);
        let in_edges = |length: f64, steps: usize| (length / edge).powi(2) / steps as f64;
        ExtremalityTracer {
            presmooth_steps,
            presmooth_time: in_edges(scale, presmooth_steps),
            smooth_steps,
            smooth_time: self
                .smooth_time
                .unwrap_or_else(|| in_edges(scale / 2.0, smooth_steps)),
            ..tracer
        }
    }
}

/// The ridge and valley lines of `surface` as `options` say
/// ([`ExtremalityTracer::trace`]): its stages and counts, the counts `vertices` and
/// `faces`, and warnings for repaired curvature and when no line is strong
/// enough.
///
/// # Examples
///
/// ```
/// # use crestline::jobs::{self, Surface};
/// # use crestline::progress::Silent;
/// # let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../meshes/bunny_small.obj");
/// # let (mesh, _repairs) = jobs::build_mesh(crestline::io::read_mesh(path.as_ref())?, false, &mut Silent)?;
/// # let surface = Surface::of_mesh(mesh);
/// let lines = jobs::ridges(&surface, &jobs::RidgesOptions::default(), &mut Silent)?;
/// assert!(!lines.is_empty());
/// lines.write(std::env::temp_dir().join("bunny_ridges.vtk").as_ref())?;
/// # Ok::<(), crestline::Error>(())
/// ```
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
