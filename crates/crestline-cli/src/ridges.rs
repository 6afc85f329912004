//! `crestline ridges`: ridge and valley lines by extremality tracing.

use std::path::{Path, PathBuf};

use crate::report::Report;
use crestline::curvature::Estimator;
use crestline::linalg::Solver;
use crestline::lines::{write_lines, FeatureLines, LineFormat};
use crestline::ridges::{ExtremalityTracer, Fairing, Kinds};
use crestline::{Error, Result};

use super::failure::explain;
use super::load::{report_with_progress, StrictArg};
use super::outputs::{check_paths, Role};
use super::surface::{load_surface, Surface, VolumeArgs};
use super::ReportArg;

/// Options of extremality tracing, shared by every command that traces ridges.
#[derive(clap::Args, Debug, Clone)]
pub struct TracerArgs {
    /// Which lines to extract: ridges (maxima of k_max: convex crests), valleys
    /// (minima of k_min: concave creases) or both.
    #[arg(long, default_value_t, value_parser = super::named::<Kinds>(Kinds::NAMES))]
    pub kind: Kinds,
    /// Curvature estimator: shape-operator (fast) or jet-fit (accurate on irregular meshes).
    #[arg(long, default_value_t, value_parser = super::named::<Estimator>(Estimator::NAMES))]
    pub estimator: Estimator,
    /// Implicit smoothing steps of the extremalities [default: 3]. With jet-fit the
    /// extremalities come from the fitted jets and are smoothed only where the
    /// vertices deviate from them (noise), not on clean meshes.
    #[arg(long, value_name = "N")]
    pub smooth_steps: Option<usize>,
    /// Smoothing time step, in units of the mean edge length squared [default: 2
    /// with shape-operator, 3 with jet-fit].
    #[arg(long, value_name = "TAU")]
    pub smooth_time: Option<f64>,
    /// Keep connected lines whose strength (dimensionless: ∫ k_max ds for ridges,
    /// ∫ |k_min| ds for valleys) is at least this.
    #[arg(long, default_value_t = ExtremalityTracer::DEFAULT_THRESHOLD, value_name = "T")]
    pub threshold: f64,
    /// Implicit smoothing steps of the surface before tracing (for noisy meshes).
    #[arg(long, default_value_t = 0, value_name = "N")]
    pub presmooth: usize,
    /// Solver of the implicit smoothing systems: auto (a conjugate gradient on large,
    /// well-conditioned meshes, else sparse Cholesky), direct or iterative.
    #[arg(long, default_value_t, value_parser = super::named::<Solver>(Solver::NAMES))]
    pub solver: Solver,
    /// Fair the lines as space curves (each point moves at most half a mean edge length).
    #[arg(long)]
    pub fair: bool,
    /// Trace every extremal line, maxima and minima of both curvatures, without the
    /// feature conditions of the paper (eqs. 5, 6).
    #[arg(long)]
    pub all_extrema: bool,
    /// Per-vertex factors for inhomogeneous extremality smoothing: the name of a PLY
    /// vertex property, or a text file with one value per vertex.
    #[arg(long, value_name = "PROPERTY|FILE")]
    pub smoothing_weights: Option<String>,
    #[command(flatten)]
    pub strict: StrictArg,
    #[command(flatten)]
    pub volume: VolumeArgs,
}

impl TracerArgs {
    /// The files these options read besides the mesh `mesh`, with the mesh.
    pub fn inputs<'a>(&'a self, mesh: &'a Path) -> Vec<Role<'a>> {
        std::iter::once(("the input mesh", mesh))
            .chain(weights_file(self).map(|f| ("the --smoothing-weights file", f)))
            .collect()
    }
}

/// Arguments of `crestline ridges`.
#[derive(clap::Args, Debug)]
pub struct RidgesArgs {
    /// The mesh (.obj, .ply, .off, .stl) or 3D image (.nii, .nii.gz, .nrrd, .nhdr,
    /// .mha, .mhd; with --level).
    #[arg(value_name = "MESH|VOLUME")]
    pub mesh: PathBuf,
    /// Output lines: .json, .obj, .ply or .vtk.
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    #[command(flatten)]
    pub tracer: TracerArgs,
    #[command(flatten)]
    pub report: ReportArg,
}

/// The name under which smoothing weights read from a text file are attached.
const WEIGHTS_FROM_FILE: &str = "crestline_smoothing_weights";

/// Load the surface in `path` (a mesh or a 3D image) for tracing: smoothing
/// weights given as a text file are attached before the repairs, and the repairs
/// are reported as warnings.
pub fn load_for_tracing(path: &Path, args: &TracerArgs, report: &mut Report) -> Result<Surface> {
    let weights_file = weights_file(args);
    let extra: Vec<(&str, &Path)> = weights_file
        .map(|f| (WEIGHTS_FROM_FILE, f))
        .into_iter()
        .collect();
    load_surface(
        path,
        (args.strict, &args.volume, args.estimator),
        &extra,
        report,
    )
}

/// `--smoothing-weights` when it names an existing file.
fn weights_file(args: &TracerArgs) -> Option<&Path> {
    args.smoothing_weights
        .as_deref()
        .map(Path::new)
        .filter(|p| p.is_file())
}

/// Trace the lines of `surface` (loaded by [`load_for_tracing`] from `mesh_path`).
pub fn trace_loaded(
    surface: &Surface,
    mesh_path: &Path,
    args: &TracerArgs,
    report: &mut Report,
) -> Result<FeatureLines> {
    let mesh = &surface.mesh;
    let smoothing_weights = match (&args.smoothing_weights, weights_file(args)) {
        (None, _) => None,
        (Some(_), Some(_)) => mesh.vertex_scalar(WEIGHTS_FROM_FILE).map(<[f64]>::to_vec),
        (Some(name), None) => Some(
            mesh.vertex_scalar(name)
                .ok_or_else(|| Error::File {
                    path: mesh_path.to_path_buf(),
                    message: format!("no vertex property '{name}' (and no file of that name) for --smoothing-weights"),
                })?
                .to_vec(),
        ),
    };
    let (smooth_steps, smooth_time) = ExtremalityTracer::smoothing_defaults(args.estimator);
    let tracer = ExtremalityTracer {
        estimator: surface.estimator.clone(),
        kinds: args.kind,
        smooth_steps: args.smooth_steps.unwrap_or(smooth_steps),
        smooth_time: args.smooth_time.unwrap_or(smooth_time),
        threshold: args.threshold,
        presmooth_steps: args.presmooth,
        fairing: args.fair.then(Fairing::default),
        smoothing_weights,
        feature_conditions: !args.all_extrema,
        solver: args.solver,
    };
    report.count("vertices", mesh.vertex_count());
    report.count("faces", mesh.face_count());
    let mut lines = tracer
        .trace(mesh, report)
        .map_err(|e| explain(e, mesh_path))?;
    lines.source = mesh_path.display().to_string();
    warn_unreliable(mesh_path, report);
    if lines.is_empty() {
        super::warn(
            mesh_path,
            &format!(
                "no line is as strong as --threshold {}; try a lower --threshold",
                args.threshold
            ),
        );
    }
    Ok(lines)
}

/// Warn when the curvature estimate was repaired at interior vertices (outliers or
/// non-finite values, replaced by their neighbourhood's median before tracing).
fn warn_unreliable(mesh_path: &Path, report: &Report) {
    let count = report
        .counts
        .get("unreliable_vertices")
        .and_then(|v| v.as_u64());
    if let Some(count) = count.filter(|&n| n > 0) {
        super::warn(
            mesh_path,
            &format!(
                "curvature at {count} interior vertices was an outlier or not finite and was \
                 replaced by its neighbours' median"
            ),
        );
    }
}

/// Trace the lines and write them.
pub fn run(args: &RidgesArgs) -> Result<()> {
    LineFormat::from_path(&args.output)?;
    let outputs: Vec<Role<'_>> = std::iter::once(("-o", args.output.as_path()))
        .chain(args.report.output())
        .collect();
    check_paths(&args.tracer.inputs(&args.mesh), &outputs)?;
    let mut report = report_with_progress("ridges", &args.mesh);
    let surface = load_for_tracing(&args.mesh, &args.tracer, &mut report)?;
    let lines = trace_loaded(&surface, &args.mesh, &args.tracer, &mut report)?;
    args.report
        .write_with_output(&mut report, &args.output, |p| write_lines(p, &lines))
}
