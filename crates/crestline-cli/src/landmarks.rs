//! `crestline landmarks`: anatomical landmarks from crest lines (extremal points,
//! curvature maxima, line ends, and line descriptors) in the formats 3D Slicer and
//! spreadsheets load.

use std::path::{Path, PathBuf};

use crestline::crest_lines::LineTracing;
use crestline::io::is_volume_path;
use crestline::landmarks::{landmarks, write_landmarks, LandmarkFormat, LandmarkOptions, Space};
use crestline::lines::FeatureLines;
use crestline::Result;

use super::crest::trace_image_lines;
use super::load::report_with_progress;
use super::outputs::check_paths;
use super::report::Report;
use super::ridges::{load_for_tracing, trace_loaded, TracerArgs};
use super::surface::{default_sigma, read_image, required_level};
use super::ReportArg;

/// The frame of the input's coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum SpaceArg {
    /// Right, anterior, superior (the NIfTI world).
    Ras,
    /// Left, posterior, superior (DICOM, NRRD, MetaImage, 3D Slicer's models).
    Lps,
}

/// Arguments of `crestline landmarks`.
#[derive(clap::Args, Debug)]
pub struct LandmarksArgs {
    /// The mesh (.obj, .ply, .off, .stl: ridges by extremality tracing) or 3D image
    /// (.nii, .nii.gz, .nrrd, .nhdr, .mha, .mhd, with --level: crest lines by
    /// Marching Lines).
    #[arg(value_name = "MESH|VOLUME")]
    pub input: PathBuf,
    /// Output: .mrk.json (3D Slicer markups), .json (every landmark and line with
    /// its descriptors) or .csv (the point landmarks).
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    /// A curvature maximum is the largest within this arc length on both sides
    /// (world units); default five mean edge lengths or five voxels.
    #[arg(long, value_name = "R")]
    pub radius: Option<f64>,
    /// An extremal point needs the other extremality's sign to hold this long on
    /// both sides (world units); default two mean edge lengths or two voxels.
    #[arg(long, value_name = "P")]
    pub persistence: Option<f64>,
    /// For a 3D image: keep crest lines at least this long (world units); default
    /// three voxels.
    #[arg(long, value_name = "L")]
    pub min_length: Option<f64>,
    /// The frame of the input's coordinates. Default: RAS for NIfTI, LPS for the
    /// other images and for meshes (as 3D Slicer reads models).
    #[arg(long, value_enum)]
    pub space: Option<SpaceArg>,
    #[command(flatten)]
    pub tracer: TracerArgs,
    #[command(flatten)]
    pub report: ReportArg,
}

/// Find the landmarks and write them.
pub fn run(args: &LandmarksArgs) -> Result<()> {
    LandmarkFormat::from_path(&args.output)?;
    let outputs: Vec<_> = std::iter::once(("-o", args.output.as_path()))
        .chain(args.report.output())
        .collect();
    check_paths(&args.tracer.inputs(&args.input), &outputs)?;
    let mut report = report_with_progress("landmarks", &args.input);
    let (lines, scale) = if is_volume_path(&args.input) {
        image_crest_lines(args, &mut report)?
    } else {
        let surface = load_for_tracing(&args.input, &args.tracer, &mut report)?;
        let lines = trace_loaded(&surface, &args.input, &args.tracer, &mut report)?;
        (lines, surface.mesh.mean_edge_length())
    };
    let options = LandmarkOptions {
        radius: args.radius.unwrap_or(5.0 * scale),
        persistence: args.persistence.unwrap_or(2.0 * scale),
    };
    let found = report.stage("landmarks", || landmarks(&lines, &options))?;
    report.count("landmarks", found.points.len());
    report.count("crest_lines", found.lines.len());
    let space = input_space(args);
    args.report
        .write_with_output(&mut report, &args.output, |p| {
            write_landmarks(p, &found, space)
        })
}

/// The crest lines of the image `args.input` by Marching Lines, and its voxel
/// size.
fn image_crest_lines(args: &LandmarksArgs, report: &mut Report) -> Result<(FeatureLines, f64)> {
    let path: &Path = &args.input;
    let level = required_level(path, &args.tracer.volume)?;
    let volume = read_image(path, report)?;
    let voxel = default_sigma(&volume);
    let sigma = args.tracer.volume.sigma.unwrap_or(voxel);
    let tracing = LineTracing::new(level, sigma);
    let lines = trace_image_lines(&volume, path, &tracing, (args.min_length, 0.0), report)?;
    Ok((lines, voxel))
}

/// The frame `--space` names.
pub fn space_of(arg: SpaceArg) -> Space {
    match arg {
        SpaceArg::Ras => Space::Ras,
        SpaceArg::Lps => Space::Lps,
    }
}

/// `--space`, or the frame the input's format implies.
fn input_space(args: &LandmarksArgs) -> Space {
    let name = args.input.to_string_lossy().to_lowercase();
    let nifti = name.ends_with(".nii") || name.ends_with(".nii.gz");
    match args.space {
        Some(space) => space_of(space),
        None if nifti => Space::Ras,
        None => Space::Lps,
    }
}
