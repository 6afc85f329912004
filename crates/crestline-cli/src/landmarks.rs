//! `crestline landmarks`: anatomical landmarks from crest lines (extremal points,
//! curvature maxima, line ends, and line descriptors) in the formats 3D Slicer and
//! spreadsheets load.

use std::path::{Path, PathBuf};

use crestline::io::is_volume_path;
use crestline::jobs::{landmarks, CrestLinesOptions, LandmarksOptions, Length, LinesFrom};
use crestline::landmarks::LandmarkFormat;
use crestline::space::Space;
use crestline::Result;

use super::failure::explain;
use super::frame::OutputSpaceArg;
use super::load::report_with_progress;
use super::outputs::check_paths;
use super::ridges::{load_for_tracing, options_for, TracerArgs};
use super::surface::{naming, read_image, required_level};
use super::ReportArg;

/// Arguments of `crestline landmarks`.
#[derive(clap::Args, Debug)]
pub struct LandmarksArgs {
    /// The mesh (.obj, .ply, .off, .stl, .gii, a FreeSurfer surface: ridges by
    /// extremality tracing) or 3D image (.nii, .nii.gz, .nrrd, .nhdr, .mha, .mhd, a
    /// DICOM folder, DICOMDIR or .dcm file, with --level: crest lines by Marching
    /// Lines).
    #[arg(value_name = "MESH|VOLUME")]
    pub input: PathBuf,
    /// Output: .mrk.json (3D Slicer markups), .json (every landmark and line with
    /// its descriptors) or .csv (the point landmarks).
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    #[command(flatten)]
    pub options: LandmarksOptions,
    /// For a 3D image: keep crest lines at least this long, in world units or in
    /// feature scales.
    #[arg(long, value_name = "L", default_value_t = CrestLinesOptions::default().min_length)]
    pub min_length: Length,
    /// The frame of the input's coordinates, for a mesh that does not state it
    /// (3D Slicer's `SPACE=` mark): RAS or LPS; default LPS, as 3D Slicer reads
    /// models. Images state their own (NIfTI: RAS; NRRD: its space; MetaImage:
    /// LPS); a contradiction is an error.
    #[arg(long, ignore_case = true, value_parser = super::named::<Space>(Space::NAMES))]
    pub space: Option<Space>,
    #[command(flatten)]
    pub tracer: TracerArgs,
    #[command(flatten)]
    pub frame: OutputSpaceArg,
    #[command(flatten)]
    pub report: ReportArg,
}

impl LandmarksArgs {
    /// How the crest lines of an image are traced: `--sigma` and `--min-length`.
    fn crest_options(&self) -> CrestLinesOptions {
        let defaults = CrestLinesOptions::default();
        CrestLinesOptions {
            scale: self.tracer.volume.iso.scale,
            sigma: self.tracer.volume.iso.sigma,
            min_length: self.min_length,
            ..defaults
        }
    }
}

/// Find the landmarks and write them.
pub fn run(args: &LandmarksArgs) -> Result<()> {
    LandmarkFormat::from_path(&args.output)?;
    let outputs: Vec<_> = std::iter::once(("-o", args.output.as_path()))
        .chain(args.report.output())
        .collect();
    check_paths(&args.tracer.inputs(&args.input), &outputs)?;
    let mut report = report_with_progress("landmarks", &args.input);
    let path: &Path = &args.input;
    let mut found = if is_volume_path(path) {
        let level = required_level(path, &args.tracer.volume)?;
        let volume = read_image(path, &args.tracer.volume.series, &mut report)?;
        let crest = args.crest_options();
        let input = LinesFrom::Image {
            volume: &volume,
            level,
            options: &crest,
        };
        landmarks(input, &args.options, &mut report).map_err(|e| naming(e, path))?
    } else {
        let loaded = load_for_tracing(path, &args.tracer, &mut report)?;
        let ridges = options_for(&loaded.surface.mesh, path, &args.tracer)?;
        let input = LinesFrom::Surface {
            surface: &loaded.surface,
            options: &ridges,
        };
        landmarks(input, &args.options, &mut report).map_err(|e| explain(e, path))?
    };
    found.source = path.display().to_string();
    let space = Space::resolve(found.space, args.space)
        .map_err(|e| naming(e, path))?
        .unwrap_or(Space::Lps);
    let (found, space) = args.frame.landmarks(found, space)?;
    args.report
        .write_with_output(&mut report, &args.output, |p| found.write(p, space))
}
