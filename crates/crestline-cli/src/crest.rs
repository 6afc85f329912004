//! `crestline crest-lines`: crest lines (and parabolic lines) of the isosurfaces of
//! a 3D image, by the Marching Lines algorithm (Thirion & Gourdon 1993).

use std::path::{Path, PathBuf};

use crestline::crest_lines::{trace, LineFamily, LineTracing};
use crestline::lines::{write_lines, FeatureLines, LineFormat, MinLength, MinStrength};
use crestline::volume::{Sweep, Volume};
use crestline::Result;

use super::load::report_with_progress;
use super::outputs::check_paths;
use super::surface::{default_sigma, naming, read_image, require_image};
use super::ReportArg;
use crate::report::Report;

/// The `--kind` argument: crest, parabolic or gauss=J.
fn parse_family(text: &str) -> std::result::Result<LineFamily, String> {
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
    #[arg(
        long,
        default_value = "crest",
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
    #[arg(long, default_value_t = 1, value_name = "S", requires = "seeds")]
    pub rng_seed: u64,
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
    let volume = read_image(&args.volume, &mut report)?;
    let sigma = args.sigma.unwrap_or_else(|| default_sigma(&volume));
    let tracing = LineTracing {
        family: args.kind,
        sweep: args.seeds.map_or(Sweep::Every, |count| Sweep::Seeds {
            count: count as usize,
            rng_seed: args.rng_seed,
        }),
        ..LineTracing::new(args.level, sigma)
    };
    let filters = (args.min_length, args.min_strength);
    let lines = trace_image_lines(&volume, &args.volume, &tracing, filters, &mut report)?;
    args.report
        .write_with_output(&mut report, &args.output, |p| write_lines(p, &lines))
}

/// The lines `tracing` asks for in `volume` (read from `path`), at least
/// `min_length` long (default three voxels) and `min_strength` strong, with the
/// stage "marching lines" and the counts in `report`, and a warning if none is
/// left.
pub fn trace_image_lines(
    volume: &Volume,
    path: &Path,
    tracing: &LineTracing,
    (min_length, min_strength): (Option<f64>, f64),
    report: &mut Report,
) -> Result<FeatureLines> {
    let traced = report
        .stage("marching lines", || trace(volume, tracing))
        .map_err(|e| naming(e, path))?;
    let mut lines = FeatureLines::new(path.display().to_string());
    lines.lines = traced;
    report.count("traced", lines.len());
    lines.filter(&MinLength(
        min_length.unwrap_or(3.0 * default_sigma(volume)),
    ));
    lines.filter(&MinStrength(min_strength));
    report.count("lines", lines.len());
    if lines.is_empty() {
        super::warn(
            path,
            "no line is as long and strong as asked; try a lower --min-length or --min-strength",
        );
    }
    Ok(lines)
}
