//! `crestline curvature`: principal curvatures per vertex, written as PLY properties.

use std::path::PathBuf;
use std::sync::Arc;

use crestline::curvature::{
    estimate_curvature, write_curvature_ply, CurvatureEstimator, JetFit, ShapeOperator,
};
use crestline::{Error, Result};

use super::load::{load_mesh, report_with_progress};
use super::ReportArg;

/// Which curvature estimator to use.
#[derive(clap::ValueEnum, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum EstimatorChoice {
    /// The discrete shape operator (Hildebrandt et al. 2005): fast, best on regular meshes.
    #[default]
    ShapeOperator,
    /// A quartic least-squares fit over a ring neighbourhood: slower, accurate on
    /// irregular meshes.
    #[value(alias = "quadric")]
    JetFit,
}

impl EstimatorChoice {
    /// The estimator this choice names, with its default settings.
    pub fn estimator(self) -> Arc<dyn CurvatureEstimator + Send + Sync> {
        match self {
            EstimatorChoice::ShapeOperator => Arc::new(ShapeOperator),
            EstimatorChoice::JetFit => Arc::new(JetFit::default()),
        }
    }
}

/// Arguments of `crestline curvature`.
#[derive(clap::Args, Debug)]
pub struct CurvatureArgs {
    /// The mesh file (.obj, .ply, .off, .stl).
    pub mesh: PathBuf,
    /// Output PLY file: the mesh with float vertex properties k_max, k_min, mean,
    /// gauss, dmax_x/y/z, dmin_x/y/z, nx/ny/nz and unreliable (1 on the boundary).
    #[arg(short, long, value_name = "FILE.ply")]
    pub output: PathBuf,
    /// Curvature estimator.
    #[arg(long, value_enum, default_value_t)]
    pub estimator: EstimatorChoice,
    #[command(flatten)]
    pub report: ReportArg,
}

/// Estimate curvature and write the annotated mesh.
pub fn run(args: &CurvatureArgs) -> Result<()> {
    let is_ply = args
        .output
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("ply"));
    if !is_ply {
        return Err(Error::File {
            path: args.output.clone(),
            message: "curvature output must be a .ply file (it carries per-vertex properties)"
                .into(),
        });
    }
    let mut report = report_with_progress("curvature", &args.mesh);
    let (mesh, repairs) = load_mesh(&args.mesh, &mut report)?;
    super::load::warn_repairs(&args.mesh, &repairs);
    let estimator = args.estimator.estimator();
    let field = report
        .stage("estimate", || estimate_curvature(&mesh, estimator.as_ref()))
        .map_err(|e| e.in_file(&args.mesh))?;
    report.stage("write", || write_curvature_ply(&args.output, &mesh, &field))?;
    if let Some(path) = &args.report.report {
        report.count("vertices", mesh.vertex_count());
        report.count("faces", mesh.face_count());
        report.count(
            "unreliable",
            field.unreliable.iter().filter(|&&u| u).count(),
        );
        report.section("repairs", &repairs);
        report.write(path)?;
    }
    Ok(())
}
