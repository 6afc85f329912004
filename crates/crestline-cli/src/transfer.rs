//! `crestline transfer`: a template's labelled landmarks carried onto another
//! scan through their crest lines (rigid, then a smooth deformation;
//! [`crestline::transfer`]).

use std::path::{Path, PathBuf};

use crestline::jobs::{crest_lines, transfer, CrestLinesOptions};
use crestline::landmarks::LandmarkFormat;
use crestline::lines::FeatureLines;
use crestline::transfer::{read_labelled, write_labelled, LabelledPoint, TransferOptions};
use crestline::{Result, Space};

use super::load::report_with_progress;
use super::outputs::check_paths;
use super::report::Report;
use super::surface::{naming, read_image, SeriesArg};
use super::ReportArg;

/// Arguments of `crestline transfer`.
#[derive(clap::Args, Debug)]
pub struct TransferArgs {
    /// The template: a 3D image (.nii, .nii.gz, .nrrd, .nhdr, .mha, .mhd, a DICOM
    /// folder, DICOMDIR or .dcm file).
    pub template: PathBuf,
    /// The template's landmarks, with labels: .mrk.json (3D Slicer markups, the
    /// point lists' control points), .json (as `crestline landmarks` writes) or
    /// .csv (columns label, x, y, z and space: RAS or LPS).
    pub template_landmarks: PathBuf,
    /// The subject: a 3D image of the same anatomy and contrast.
    pub subject: PathBuf,
    /// Output: .mrk.json (3D Slicer markups), .json or .csv: each landmark's label,
    /// position in the subject and confidence (the RMS distance of the nearby lines
    /// to the subject's, mm; lower is better), in the order given.
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    /// The isosurface level of both images.
    #[arg(long, value_name = "I", allow_hyphen_values = true)]
    pub level: f64,
    /// The template's crest lines at that level, computed once (`crestline
    /// crest-lines TEMPLATE --level I -o FILE`, .json) instead of from the template.
    #[arg(long, value_name = "FILE")]
    pub template_lines: Option<PathBuf>,
    /// The smoothing scales of the deformation, coarse to fine (mm, comma-separated).
    #[arg(long, value_name = "S,S,…", value_delimiter = ',',
          default_values_t = TransferOptions::default().scales)]
    pub scales: Vec<f64>,
    /// Iterations at each scale.
    #[arg(long, value_name = "N", default_value_t = TransferOptions::default().iterations)]
    pub iterations: usize,
    /// Pair points of the two scans' lines only if their tangents make at most
    /// this angle (degrees; 90: any).
    #[arg(long, value_name = "DEG", default_value_t = TransferOptions::default().max_angle)]
    pub max_angle: f64,
    /// Write the positions of a .json or .csv output in this frame (default RAS;
    /// .mrk.json is in LPS, as 3D Slicer reads it).
    #[arg(long, ignore_case = true, value_parser = super::named::<Space>(Space::NAMES))]
    pub output_space: Option<Space>,
    #[command(flatten)]
    pub series: SeriesArg,
    #[command(flatten)]
    pub report: ReportArg,
}

/// The crest lines of the image `path` at `level`.
fn lines_of(
    path: &Path,
    level: f64,
    series: &SeriesArg,
    report: &mut Report,
) -> Result<FeatureLines> {
    let volume = read_image(path, series, report)?;
    crest_lines(&volume, level, &CrestLinesOptions::default(), report).map_err(|e| naming(e, path))
}

/// Carry the landmarks and write them.
pub fn run(args: &TransferArgs) -> Result<()> {
    LandmarkFormat::from_path(&args.output)?;
    let options = TransferOptions {
        scales: args.scales.clone(),
        iterations: args.iterations,
        max_angle: args.max_angle,
        ..TransferOptions::default()
    };
    options.validate()?;
    let outputs: Vec<_> = std::iter::once(("-o", args.output.as_path()))
        .chain(args.report.output())
        .collect();
    let mut inputs = vec![
        ("the template", args.template.as_path()),
        (
            "the template's landmarks",
            args.template_landmarks.as_path(),
        ),
        ("the subject", args.subject.as_path()),
    ];
    inputs.extend(
        args.template_lines
            .as_deref()
            .map(|p| ("the template's lines", p)),
    );
    check_paths(&inputs, &outputs)?;
    let mut report = report_with_progress("transfer", &args.subject);
    let landmarks = report.stage("read landmarks", || read_labelled(&args.template_landmarks))?;
    let template = match &args.template_lines {
        Some(path) => report.stage("read template lines", || FeatureLines::read_json(path))?,
        None => lines_of(&args.template, args.level, &args.series, &mut report)?,
    };
    let subject = lines_of(&args.subject, args.level, &args.series, &mut report)?;
    let carried = transfer(&template, &subject, &landmarks, &options, &mut report)
        .map_err(|e| naming(e, &args.subject))?;
    println!(
        "{} landmarks; rigid stage: rotation {:.3}°, rms {:.4}; after the deformation: rms {:.4}",
        landmarks.len(),
        carried.rigid.transform.angle_degrees(),
        carried.rigid.rms,
        carried.rms
    );
    let moved: Vec<LabelledPoint> = landmarks
        .iter()
        .zip(&carried.positions)
        .map(|(l, p)| LabelledPoint {
            label: l.label.clone(),
            position: *p,
        })
        .collect();
    let space = args.output_space.unwrap_or(Space::Ras);
    args.report
        .write_with_output(&mut report, &args.output, |p| {
            write_labelled(p, &moved, &carried.confidence, space)
        })
}
