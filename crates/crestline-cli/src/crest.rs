//! `crestline crest-lines`: crest lines (and parabolic lines) of the isosurfaces of
//! a 3D image, by the Marching Lines algorithm (Thirion & Gourdon 1993;
//! [`crestline::jobs::crest_lines`]).

use std::path::PathBuf;

use crestline::jobs::{crest_lines, CrestLinesOptions};
use crestline::lines::LineFormat;
use crestline::Result;

use super::frame::OutputSpaceArg;
use super::load::report_with_progress;
use super::outputs::check_paths;
use super::surface::{naming, read_image, require_image, SeriesArg};
use super::ReportArg;

/// Arguments of `crestline crest-lines`.
#[derive(clap::Args, Debug)]
pub struct CrestArgs {
    /// The 3D image (.nii, .nii.gz, .nrrd, .nhdr, .mha, .mhd, or a DICOM folder,
    /// DICOMDIR or .dcm file).
    pub volume: PathBuf,
    #[command(flatten)]
    pub series: SeriesArg,
    /// The isosurface level I; inside is value ≥ I.
    #[arg(long, value_name = "I", allow_hyphen_values = true)]
    pub level: f64,
    /// Output lines: .json, .obj, .ply, .vtk, .vtp, .vtu (segments, for meshio)
    /// or .mrk.json (3D Slicer markups).
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    #[command(flatten)]
    pub options: CrestLinesOptions,
    #[command(flatten)]
    pub frame: OutputSpaceArg,
    #[command(flatten)]
    pub report: ReportArg,
}

/// Trace the lines and write them.
pub fn run(args: &CrestArgs) -> Result<()> {
    require_image(&args.volume, "crest-lines")?;
    LineFormat::from_path(&args.output)?;
    let outputs: Vec<_> = std::iter::once(("-o", args.output.as_path()))
        .chain(args.report.output())
        .collect();
    check_paths(&[("the input image", &args.volume)], &outputs)?;
    let mut report = report_with_progress("crest-lines", &args.volume);
    let volume = read_image(&args.volume, &args.series, &mut report)?;
    let mut lines = crest_lines(&volume, args.level, &args.options, &mut report)
        .map_err(|e| naming(e, &args.volume))?;
    lines.source = args.volume.display().to_string();
    let lines = args.frame.lines(lines)?;
    args.report
        .write_with_output(&mut report, &args.output, |p| lines.write(p))
}
