//! `crestline iso`: the isosurface of a 3D image as a mesh, with the image's
//! curvature per vertex ([`crestline::jobs::isosurface`]).

use std::path::PathBuf;

use crestline::curvature::DerivativeOrder;
use crestline::curvature::Estimator;
use crestline::io::{soup_format, write_soup_of_structure, FileFormat};
use crestline::jobs::{curvature, CurvatureOptions, IsoOptions};
use crestline::Result;

use super::failure::explain;
use super::frame::OutputSpaceArg;
use super::load::{report_with_progress, StrictArg};
use super::outputs::check_paths;
use super::structure::StructureArg;
use super::surface::{load_surface, require_image, VolumeArgs};
use super::ReportArg;

/// Arguments of `crestline iso`.
#[derive(clap::Args, Debug)]
pub struct IsoArgs {
    /// The 3D image (.nii, .nii.gz, .nrrd, .nhdr, .mha, .mhd, or a DICOM folder,
    /// DICOMDIR or .dcm file).
    pub volume: PathBuf,
    /// Output surface: .ply (with the double vertex properties k_max, k_min, mean,
    /// gauss, dmax_x/y/z, dmin_x/y/z, n_x/y/z, unreliable and quality, the mean
    /// curvature again for MeshLab), .obj, .vtk or .surf.gii (GIfTI, RAS; the
    /// surface alone).
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    #[command(flatten)]
    pub surface: VolumeArgs,
    /// Mesh curvature estimator, for --curvature mesh.
    #[arg(long, default_value_t = IsoOptions::default().estimator,
          value_parser = super::named::<Estimator>(Estimator::NAMES))]
    pub estimator: Estimator,
    #[command(flatten)]
    pub structure: StructureArg,
    #[command(flatten)]
    pub frame: OutputSpaceArg,
    #[command(flatten)]
    pub report: ReportArg,
}

impl IsoArgs {
    /// The job's options.
    fn options(&self) -> IsoOptions {
        IsoOptions {
            estimator: self.estimator,
            ..self.surface.iso
        }
    }
}

/// Extract the isosurface and write it (with curvature to PLY).
pub fn run(args: &IsoArgs) -> Result<()> {
    require_image(&args.volume, "iso")?;
    let with_curvature = soup_format(&args.output)? == FileFormat::Ply;
    let outputs: Vec<_> = std::iter::once(("-o", args.output.as_path()))
        .chain(args.report.output())
        .collect();
    check_paths(&[("the input image", &args.volume)], &outputs)?;
    let mut report = report_with_progress("iso", &args.volume);
    let options = args.options();
    let surface = load_surface(
        &args.volume,
        (
            StrictArg::default(),
            &args.surface,
            options,
            with_curvature.then_some(DerivativeOrder::Second),
        ),
        &[],
        &mut report,
    )?
    .surface;
    let mesh = &surface.mesh;
    report.count("euler_characteristic", mesh.euler_characteristic());
    report.count("boundary_loops", mesh.boundary_loops().len());
    let curvature_options = CurvatureOptions {
        estimator: options.estimator,
        ..CurvatureOptions::default()
    };
    let field = with_curvature
        .then(|| curvature(&surface, &curvature_options, &mut report))
        .transpose()
        .map_err(|e| explain(e, &args.volume))?;
    let (mesh, field) = args.frame.surface(mesh, field)?;
    args.report
        .write_with_output(&mut report, &args.output, |p| match &field {
            Some(field) => field.write_ply(p, &mesh),
            None => write_soup_of_structure(p, &mesh.to_soup(), args.structure.structure),
        })
}
