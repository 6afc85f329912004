//! `crestline crest-lines`: crest lines (and parabolic lines) of the isosurfaces of
//! a 3D image, by the Marching Lines algorithm (Thirion & Gourdon 1993).

use std::path::PathBuf;

use crestline::crest_lines::{crest_lines, iso_gaussian_lines, parabolic_lines};
use crestline::io::read_volume;
use crestline::lines::{write_lines, FeatureLines, LineFormat, MinLength, MinStrength};
use crestline::Result;

use super::load::report_with_progress;
use super::outputs::check_paths;
use super::surface::{default_sigma, naming, require_image};
use super::ReportArg;

/// Which lines to trace.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum LineFamily {
    /// Ridges (maxima of k_max where k_max > |k_min|: convex crests, gyri) and
    /// valleys (the mirror case: concave crests, sulci).
    #[default]
    Crest,
    /// Parabolic lines, where the Gaussian curvature is zero.
    Parabolic,
    /// Iso-Gaussian curves, where the Gaussian curvature is this value.
    Gauss(f64),
}

impl std::str::FromStr for LineFamily {
    type Err = String;

    fn from_str(text: &str) -> std::result::Result<LineFamily, String> {
        match text {
            "crest" => Ok(LineFamily::Crest),
            "parabolic" => Ok(LineFamily::Parabolic),
            _ => text
                .strip_prefix("gauss=")
                .and_then(|j| j.parse::<f64>().ok())
                .filter(|j| j.is_finite())
                .map(LineFamily::Gauss)
                .ok_or_else(|| format!("'{text}' is not crest, parabolic or gauss=J (J a number)")),
        }
    }
}

/// Arguments of `crestline crest-lines`.
#[derive(clap::Args, Debug)]
pub struct CrestArgs {
    /// The 3D image (.nii, .nii.gz, .nrrd, .nhdr, .mha, .mhd).
    pub volume: PathBuf,
    /// The isosurface level I; inside is value ≥ I.
    #[arg(long, value_name = "I", allow_hyphen_values = true)]
    pub level: f64,
    /// Gaussian smoothing σ in world units (mm); default one voxel.
    #[arg(long, value_name = "S")]
    pub sigma: Option<f64>,
    /// Output lines: .json, .obj, .ply or .vtk.
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    /// Which lines: crest (ridges and valleys), parabolic (K = 0) or gauss=J (the
    /// iso-Gaussian curves K = J, J in world units⁻²).
    #[arg(long, default_value = "crest", value_name = "crest|parabolic|gauss=J")]
    pub kind: LineFamily,
    /// Keep lines at least this long, in world units (mm); default three voxels.
    #[arg(long, value_name = "L")]
    pub min_length: Option<f64>,
    /// Keep lines whose strength ∫|k| ds (dimensionless) is at least this.
    #[arg(long, default_value_t = 0.0, value_name = "T")]
    pub min_strength: f64,
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
    let volume = report.stage("read", || read_volume(&args.volume))?;
    let sigma = args.sigma.unwrap_or_else(|| default_sigma(&volume));
    let trace = || match args.kind {
        LineFamily::Crest => crest_lines(&volume, args.level, sigma),
        LineFamily::Parabolic => parabolic_lines(&volume, args.level, sigma),
        LineFamily::Gauss(j) => iso_gaussian_lines(&volume, args.level, sigma, j),
    };
    let traced = report
        .stage("marching lines", trace)
        .map_err(|e| naming(e, &args.volume))?;
    let mut lines = FeatureLines::new(args.volume.display().to_string());
    lines.lines = traced;
    report.count("traced", lines.len());
    lines.filter(&MinLength(
        args.min_length.unwrap_or(3.0 * default_sigma(&volume)),
    ));
    lines.filter(&MinStrength(args.min_strength));
    report.count("lines", lines.len());
    if lines.is_empty() {
        super::warn(
            &args.volume,
            "no line is as long and strong as asked; try a lower --min-length or --min-strength",
        );
    }
    args.report
        .write_with_output(&mut report, &args.output, |p| write_lines(p, &lines))
}
