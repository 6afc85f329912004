//! Ridge and valley lines by extremality tracing (`crestline ridges`;
//! Hildebrandt, Polthier and Wardetzky 2005).

use serde::{Deserialize, Serialize};

use super::image::Surface;
use super::scale::{SCALE_PRESMOOTH_SHARE, SCALE_SMOOTH_STEPS};
use crate::curvature::Estimator;
use crate::linalg::Solver;
use crate::lines::FeatureLines;
use crate::progress::Observer;
use crate::ridges::{ExtremalityTracer, Fairing, Kinds};
use crate::Result;

/// Options of [`ridges`]. Each field is an option of the tool (`--smooth-steps`)
/// and a keyword argument of the Python package (`smooth_steps=`), documented
/// here once: with the feature `clap` this struct is the tool's arguments.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
#[serde(default, deny_unknown_fields)]
pub struct RidgesOptions {
    /// Which lines to extract: ridges (maxima of k_max: convex crests), valleys
    /// (minima of k_min: concave creases) or both.
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = RidgesOptions::default().kind))]
    pub kind: Kinds,
    /// Curvature estimator: auto (the jet fit on a clean mesh, the shape operator on
    /// a noisy one, told apart by the fit's residual), shape-operator (fast) or
    /// jet-fit (accurate on irregular meshes). An image's isosurface may carry its
    /// image's curvature instead.
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = RidgesOptions::default().estimator))]
    pub estimator: Estimator,
    /// Implicit smoothing steps of the extremalities [default: 3; 1 on an image's
    /// isosurface, whose extremalities come from the smoothed image]. With jet-fit
    /// the extremalities come from the fitted jets and are smoothed only where the
    /// vertices deviate from them (noise), not on clean meshes.
    #[cfg_attr(feature = "clap", arg(long, value_name = "N"))]
    pub smooth_steps: Option<usize>,
    /// Smoothing time step, in units of the mean edge length squared [default: 2
    /// with shape-operator or auto, 3 with jet-fit or with --presmooth, 0.25 on an
    /// image's isosurface].
    #[cfg_attr(feature = "clap", arg(long, value_name = "TAU"))]
    pub smooth_time: Option<f64>,
    /// Keep connected lines whose strength (dimensionless: ∫ k_max ds for ridges,
    /// ∫ |k_min| ds for valleys) is at least this.
    #[cfg_attr(feature = "clap", arg(long, value_name = "T",
        default_value_t = RidgesOptions::default().threshold))]
    pub threshold: f64,
    /// Implicit smoothing steps of the surface before tracing (for noisy meshes).
    #[cfg_attr(feature = "clap", arg(long, value_name = "N", default_value_t = RidgesOptions::default().presmooth))]
    pub presmooth: usize,
    /// Solver of the implicit smoothing systems: auto (a multigrid-preconditioned
    /// conjugate gradient from 2M vertices on or for a smoothing time of at most 0.5,
    /// else sparse Cholesky), direct or iterative.
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = RidgesOptions::default().solver))]
    pub solver: Solver,
    /// Fair the lines as space curves (each point moves at most half a mean edge length).
    #[cfg_attr(feature = "clap", arg(long))]
    pub fair: bool,
    /// Trace every extremal line, maxima and minima of both curvatures, without the
    /// feature conditions of the paper (eqs. 5, 6).
    #[cfg_attr(feature = "clap", arg(long))]
    pub all_extrema: bool,
    /// The feature scale of a mesh, in world units (`super::scale`): the surface
    /// is smoothed for a time of (0.7 scale)² before its curvature is estimated,
    /// the curvature tensor field for scale² and the extremalities for
    /// (scale/2)², all in world units rather than in mean edge lengths, so that
    /// another sampling of the same surface gives the same lines (`smooth_steps`,
    /// `smooth_time` and `presmooth`, when given, still apply).
    /// An image's isosurface takes its image's scale instead (σ,
    /// [`super::IsoOptions::scale`]). Default: none, the smoothing counts mean edge
    /// lengths. (The tool's `--scale` is shared with the image's options.)
    #[cfg_attr(feature = "clap", arg(skip))]
    pub scale: Option<f64>,
    /// Per-vertex factors for inhomogeneous extremality smoothing. Default: none.
    /// (The tool reads them from a file or a vertex property.)
    #[serde(skip)]
    #[cfg_attr(feature = "clap", arg(skip))]
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
            curvature_smooth_steps: 0,
            curvature_smooth_time: 1.0,
            fair: self.fair.then(Fairing::default),
            smoothing_weights: self.smoothing_weights.clone(),
            all_extrema: self.all_extrema,
            solver: self.solver,
        };
        match (self.scale, surface.image) {
            (Some(scale), None) => self.at_scale(tracer, scale, surface.mesh.mean_edge_length()),
            _ => tracer,
        }
    }

    /// `tracer` with its smoothing times in world units, on a mesh of mean edge
    /// length `edge` (the unit of the tracer's times): the surface smoothed for
    /// ([`SCALE_PRESMOOTH_SHARE`] · scale)² in `presmooth` (or
    /// [`SCALE_SMOOTH_STEPS`]) steps, its curvature tensor field for scale² and
    /// the extremalities for (scale/2)², each in `smooth_steps` (or
    /// [`SCALE_SMOOTH_STEPS`]) steps. The heat operator M + tK with the lumped
    /// mass matrix converges as the mesh is refined, so a time in world units is
    /// the same filter on every sampling of the surface. Smoothing the surface
    /// lightly first evens out the curvature of irregular triangles before it is
    /// estimated; smoothing the tensors rather than the surface for the rest
    /// keeps parts thinner than the scale in place, which mean curvature flow
    /// would shrink.
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
            presmooth_time: in_edges(SCALE_PRESMOOTH_SHARE * scale, presmooth_steps),
            curvature_smooth_steps: SCALE_SMOOTH_STEPS,
            curvature_smooth_time: in_edges(scale, SCALE_SMOOTH_STEPS),
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
