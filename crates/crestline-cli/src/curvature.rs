//! `crestline curvature`: principal curvatures per vertex, written as PLY
//! properties, or one quantity per input vertex as a GIfTI `.shape.gii` or a
//! FreeSurfer curv file.

use std::path::PathBuf;

use crestline::curvature::PER_VERTEX_FORMATS;
use crestline::io::{choose_format, FileFormat};
use crestline::jobs::{curvature, CurvatureOptions, Surface};
use crestline::Result;

use super::failure::explain;
use super::load::{load_mesh, report_with_progress, StrictArg};
use super::outputs::{check_paths, OutputSet};
use super::structure::StructureArg;
use super::ReportArg;

/// Arguments of `crestline curvature`.
#[derive(clap::Args, Debug)]
pub struct CurvatureArgs {
    /// The mesh file (.obj, .ply, .off, .stl, .gii, or a FreeSurfer surface such
    /// as lh.white).
    pub mesh: PathBuf,
    /// Output: a PLY file, the mesh with double vertex properties k_max, k_min,
    /// mean, gauss, dmax_x/y/z, dmin_x/y/z, n_x/y/z, unreliable (1 on the boundary)
    /// and quality (see --quality); or the --quality quantity alone, one value per
    /// vertex of the input file in its order, as a GIfTI .shape.gii (crestline's
    /// sign: positive where convex, on gyral crowns; NaN at vertices the repairs
    /// dropped) or a FreeSurfer .curv (FreeSurfer's sign, as ?h.curv: mean
    /// curvature positive in sulci, negative on gyral crowns; 0 at dropped
    /// vertices).
    #[arg(short, long, value_name = "FILE.ply|FILE.shape.gii|FILE.curv")]
    pub output: PathBuf,
    #[command(flatten)]
    pub options: CurvatureOptions,
    #[command(flatten)]
    pub structure: StructureArg,
    #[command(flatten)]
    pub strict: StrictArg,
    #[command(flatten)]
    pub report: ReportArg,
}

/// Estimate curvature and write the annotated mesh.
pub fn run(args: &CurvatureArgs) -> Result<()> {
    let formats: Vec<FileFormat> = std::iter::once(FileFormat::Ply)
        .chain(PER_VERTEX_FORMATS)
        .collect();
    let format = choose_format(&args.output, "per-vertex curvature", &formats)?;
    let outputs: Vec<_> = std::iter::once(("-o", args.output.as_path()))
        .chain(args.report.output())
        .collect();
    check_paths(&[("the input mesh", &args.mesh)], &outputs)?;
    let mut report = report_with_progress("curvature", &args.mesh);
    let (mesh, repairs) = load_mesh(&args.mesh, args.strict, &mut report)?;
    let surface = Surface::of_mesh(mesh);
    let options = args.options;
    let field = curvature(&surface, &options, &mut report).map_err(|e| explain(e, &args.mesh))?;
    let mesh = &surface.mesh;
    let mut files = OutputSet::default();
    report.stage("write", || {
        files.write(&args.output, |p| match format {
            FileFormat::Ply => field.write_ply_with_quality(p, mesh, options.quality),
            _ => field.write_values(p, mesh, options.quality, args.structure.structure),
        })
    })?;
    if let Some(path) = &args.report.report {
        report.count("vertices", mesh.vertex_count());
        report.count("faces", mesh.face_count());
        report.section("repairs", &repairs);
        files.write(path, |p| report.write(p))?;
    }
    files.commit()
}
