//! `crestline register`: the rigid motion taking the feature lines of one scan
//! onto those of another (trimmed ICP on the line points), written as JSON or as an
//! ITK/3D Slicer transform.

use std::path::{Path, PathBuf};

use crestline::lines::read_json;
use crestline::register::{
    register, write_transform, PointSet, Registration, RegistrationOptions, TransformFormat,
};
use crestline::Result;

use super::load::report_with_progress;
use super::outputs::check_paths;
use super::ReportArg;

/// Arguments of `crestline register`.
#[derive(clap::Args, Debug)]
pub struct RegisterArgs {
    /// Lines of the fixed scan (.json as written by `ridges` or `crest-lines`).
    pub fixed: PathBuf,
    /// Lines of the moving scan (.json), to be moved onto the fixed ones.
    pub moving: PathBuf,
    /// The transform: .json (moving → fixed, RAS) or .tfm (ITK/3D Slicer: fixed →
    /// moving, LPS).
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    /// The smallest share of moving points that may be matched (0.1 to 1).
    #[arg(long, value_name = "S", default_value_t = RegistrationOptions::default().min_overlap)]
    pub min_overlap: f64,
    /// At most this many ICP iterations after the coarse stage.
    #[arg(long, value_name = "N", default_value_t = RegistrationOptions::default().max_iterations)]
    pub max_iterations: usize,
    #[command(flatten)]
    pub report: ReportArg,
}

/// The points of every line of a `crestline-lines/1` file.
fn line_points(path: &Path) -> Result<PointSet> {
    let lines = read_json(path)?;
    let line_points = lines
        .iter()
        .flat_map(|line| line.points.iter().copied())
        .collect();
    Ok(PointSet {
        line_points,
        key_points: Vec::new(),
    })
}

/// One line summing up `registration` for the terminal.
fn summary(registration: &Registration, moving_points: usize) -> String {
    let t = registration.transform.translation;
    format!(
        "rotation {:.3}°, translation ({:.3}, {:.3}, {:.3}), rms {:.4}, matched {} of {} \
         moving points ({:.1}%), {} iterations",
        registration.transform.angle_degrees(),
        t.x,
        t.y,
        t.z,
        registration.rms,
        registration.matched,
        moving_points,
        100.0 * registration.matched_share,
        registration.iterations
    )
}

/// Register the moving lines onto the fixed ones and write the transform.
pub fn run(args: &RegisterArgs) -> Result<()> {
    TransformFormat::from_path(&args.output)?;
    let options = RegistrationOptions {
        min_overlap: args.min_overlap,
        max_iterations: args.max_iterations,
        ..RegistrationOptions::default()
    };
    options.validate()?;
    let outputs: Vec<_> = std::iter::once(("-o", args.output.as_path()))
        .chain(args.report.output())
        .collect();
    check_paths(
        &[
            ("the fixed lines", &args.fixed),
            ("the moving lines", &args.moving),
        ],
        &outputs,
    )?;
    let mut report = report_with_progress("register", &args.moving);
    let fixed = report.stage("read fixed", || line_points(&args.fixed))?;
    let moving = report.stage("read moving", || line_points(&args.moving))?;
    let registration = report.stage("registration", || register(&fixed, &moving, &options))?;
    report.count("fixed_points", fixed.line_points.len());
    report.count("moving_points", moving.line_points.len());
    report.count("matched", registration.matched);
    report.count("matched_share", registration.matched_share);
    report.count("rms", registration.rms);
    report.count("rotation_degrees", registration.transform.angle_degrees());
    report.count("iterations", registration.iterations);
    println!("{}", summary(&registration, moving.line_points.len()));
    args.report
        .write_with_output(&mut report, &args.output, |p| {
            write_transform(p, &registration)
        })
}
