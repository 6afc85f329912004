//! `crestline crest-lines`: crest lines (and parabolic lines) of the isosurfaces of
//! a 3D image, by the Marching Lines algorithm (Thirion & Gourdon 1993;
//! [`crestline::jobs::crest_lines`]).

use std::path::PathBuf;

use crestline::crest_lines::LineFamily;
use crestline::jobs::{crest_lines, CrestLinesOptions, Length};
use crestline::lines::LineFormat;
use crestline::Result;

use super::frame::OutputSpaceArg;
use super::load::report_with_progress;
use super::outputs::check_paths;
use super::surface::{naming, read_image, require_image, SeriesArg};
use super::ReportArg;

/// The `--kind` argument, read by the library.
fn parse_family(text: &str) -> std::result::Result<LineFamily, String> {
    text.parse().map_err(|e: crestline::Error| e.to_string())
}

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
    /// The feature scale in world units (mm), from which σ, --min-length and the
    /// landmarks' lengths are derived; default from the size of the object the
    /// isosurface encloses (2% of the cube root of its volume, at least a voxel),
    /// not from the grid, so that a rescan finds the same lines.
    #[arg(long, value_name = "L")]
    pub scale: Option<f64>,
    /// Gaussian smoothing σ in world units (mm); default one feature scale.
    #[arg(long, value_name = "S")]
    pub sigma: Option<f64>,
    /// Output lines: .json, .obj, .ply, .vtk, .vtp, .vtu (segments, for meshio)
    /// or .mrk.json (3D Slicer markups).
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    /// Which lines: crest (ridges and valleys), parabolic (K = 0) or gauss=J (the
    /// iso-Gaussian curves K = J, J in world units⁻²).
    #[arg(
        long,
        default_value_t = CrestLinesOptions::default().family,
        value_name = "crest|parabolic|gauss=J",
        value_parser = parse_family
    )]
    pub kind: LineFamily,
    /// The randomized Marching Lines: follow only the lines through N cells drawn
    /// at random on the isosurface; the longest lines come first, at a fraction of
    /// the cost. Default: every cell, every line.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    pub seeds: Option<u64>,
    /// The seed of the random draw of --seeds (the same seed, the same lines).
    #[arg(long, default_value_t = CrestLinesOptions::default().rng_seed, value_name = "S",
          requires = "seeds")]
    pub rng_seed: u64,
    /// Keep lines at least this long, in world units (mm); default 1.5 feature
    /// scales.
    #[arg(long, value_name = "L")]
    pub min_length: Option<f64>,
    /// Keep lines whose strength ∫|k| ds (dimensionless) is at least this.
    #[arg(long, default_value_t = CrestLinesOptions::default().min_strength, value_name = "T")]
    pub min_strength: f64,
    #[command(flatten)]
    pub frame: OutputSpaceArg,
    #[command(flatten)]
    pub report: ReportArg,
}

impl CrestArgs {
    /// The job's options.
    fn options(&self) -> CrestLinesOptions {
        let defaults = CrestLinesOptions::default();
        CrestLinesOptions {
            scale: self.scale,
            sigma: self.sigma.map_or(defaults.sigma, Length::World),
            family: self.kind,
            seeds: self.seeds.map(|n| n as usize),
            rng_seed: self.rng_seed,
            min_length: self.min_length.map_or(defaults.min_length, Length::World),
            min_strength: self.min_strength,
        }
    }
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
    let mut lines = crest_lines(&volume, args.level, &args.options(), &mut report)
        .map_err(|e| naming(e, &args.volume))?;
    lines.source = args.volume.display().to_string();
    let lines = args.frame.lines(lines)?;
    args.report
        .write_with_output(&mut report, &args.output, |p| lines.write(p))
}
