//! `crestline crease`: ridge or valley surfaces of a 3D image (Schultz, Theisel and
//! Seidel 2010; [`crestline::jobs::crease`]).

use std::path::PathBuf;

use crestline::io::write_soup_of_structure;
use crestline::jobs::{crease, CreaseOptions};
use crestline::Result;

use super::frame::OutputSpaceArg;
use super::load::report_with_progress;
use super::outputs::check_paths;
use super::structure::StructureArg;
use super::surface::{naming, read_image, require_image, SeriesArg};
use super::ReportArg;

/// Arguments of `crestline crease`.
#[derive(clap::Args, Debug)]
pub struct CreaseArgs {
    /// The 3D image (.nii, .nii.gz, .nrrd, .nhdr, .mha, .mhd, or a DICOM folder,
    /// DICOMDIR or .dcm file).
    pub volume: PathBuf,
    #[command(flatten)]
    pub series: SeriesArg,
    /// Output surface: .ply (with the vertex properties strength = −λ3 and degenerate,
    /// 1 on the degenerate lines where the surface ends), .obj, .vtk or .surf.gii
    /// (GIfTI, RAS).
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    #[command(flatten)]
    pub options: CreaseOptions,
    #[command(flatten)]
    pub structure: StructureArg,
    #[command(flatten)]
    pub frame: OutputSpaceArg,
    #[command(flatten)]
    pub report: ReportArg,
}

/// Extract the crease surface and write it.
pub fn run(args: &CreaseArgs) -> Result<()> {
    require_image(&args.volume, "crease")?;
    let options = args.options;
    options.check()?;
    let outputs: Vec<_> = std::iter::once(("-o", args.output.as_path()))
        .chain(args.report.output())
        .collect();
    check_paths(&[("the input image", &args.volume)], &outputs)?;
    let mut report = report_with_progress("crease", &args.volume);
    let volume = read_image(&args.volume, &args.series, &mut report)?;
    let soup = crease(&volume, &options, &mut report).map_err(|e| naming(e, &args.volume))?;
    let soup = args.frame.soup(soup)?;
    args.report
        .write_with_output(&mut report, &args.output, |p| {
            write_soup_of_structure(p, &soup, args.structure.structure)
        })
}
