//! `crestline crease`: ridge or valley surfaces of a 3D image (Schultz, Theisel and
//! Seidel 2010).

use std::path::PathBuf;

use crestline::io::write_soup;
use crestline::volume::crease::{crease_surface, CreaseField, DEFAULT_STRENGTH_FRACTION};
use crestline::volume::Derivatives;
use crestline::{Error, Result};

use super::load::report_with_progress;
use super::outputs::check_paths;
use super::surface::{naming, read_image, require_image};
use super::ReportArg;

/// Arguments of `crestline crease`.
#[derive(clap::Args, Debug)]
pub struct CreaseArgs {
    /// The 3D image (.nii, .nii.gz, .nrrd, .nhdr, .mha, .mhd).
    pub volume: PathBuf,
    /// Output surface: .ply (with the vertex properties strength = −λ3 and degenerate,
    /// 1 on the degenerate lines where the surface ends), .obj or .vtk.
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    /// Valley surfaces (ridges of −f) instead of ridge surfaces.
    #[arg(long)]
    pub valley: bool,
    /// Gaussian smoothing σ in world units (mm); 0, the default, differentiates the
    /// approximating cubic B-spline of the samples, which smooths least.
    #[arg(
        long,
        default_value_t = 0.0,
        value_name = "S",
        allow_hyphen_values = true
    )]
    pub sigma: f64,
    /// Least ridge strength −λ3, as a fraction of the strongest in the image.
    #[arg(long, default_value_t = DEFAULT_STRENGTH_FRACTION, value_name = "T")]
    pub strength: f64,
    /// Drop connected pieces of fewer triangles than this.
    #[arg(long, default_value_t = 20, value_name = "N")]
    pub min_component: usize,
    #[command(flatten)]
    pub report: ReportArg,
}

/// Extract the crease surface and write it.
pub fn run(args: &CreaseArgs) -> Result<()> {
    require_image(&args.volume, "crease")?;
    if !(args.strength.is_finite() && (0.0..=1.0).contains(&args.strength)) {
        return Err(Error::Argument(format!(
            "--strength is a fraction of the strongest ridge, from 0 to 1, not {}",
            args.strength
        )));
    }
    let outputs: Vec<_> = std::iter::once(("-o", args.output.as_path()))
        .chain(args.report.output())
        .collect();
    check_paths(&[("the input image", &args.volume)], &outputs)?;
    let mut report = report_with_progress("crease", &args.volume);
    let in_file = |e| naming(e, &args.volume);
    let volume = read_image(&args.volume, &mut report)?;
    let derivatives = report
        .stage("reconstruction", || {
            if args.sigma == 0.0 {
                Derivatives::cubic_spline(&volume, 2)
            } else {
                Derivatives::new(&volume, args.sigma, 2)
            }
        })
        .map_err(in_file)?;
    let field = report
        .stage("eigenframes", || {
            CreaseField::new(&volume, &derivatives, !args.valley)
        })
        .map_err(in_file)?;
    drop(derivatives);
    let mut options = field.default_options();
    options.strength *= args.strength / DEFAULT_STRENGTH_FRACTION;
    let soup = report.stage("surface", || {
        crease_surface(&field, &options, args.min_component)
    });
    report.count("vertices", soup.positions.len());
    report.count("triangles", soup.triangles.len());
    if soup.triangles.is_empty() {
        super::warn(
            &args.volume,
            "no crease surface is as strong as --strength; try a lower --strength",
        );
    }
    args.report
        .write_with_output(&mut report, &args.output, |p| write_soup(p, &soup))
}
