//! `crestline register`: the rigid motion taking the feature lines of one scan
//! onto those of another (trimmed ICP on the line points), written as JSON or as an
//! ITK/3D Slicer transform.

use std::path::{Path, PathBuf};

use crestline::jobs::register;
use crestline::register::{PointSet, Registration, RegistrationOptions, TransformFormat};
use crestline::{Error, Result, Space};

use super::load::report_with_progress;
use super::outputs::check_paths;
use super::ReportArg;

/// Arguments of `crestline register`.
#[derive(clap::Args, Debug)]
pub struct RegisterArgs {
    /// Lines or landmarks of the fixed scan (.json as written by `ridges`,
    /// `crest-lines` or `landmarks`).
    pub fixed: PathBuf,
    /// Lines or landmarks of the moving scan (.json), to be moved onto the fixed
    /// ones. With landmark files on both sides their extremal points lead the
    /// coarse alignment.
    pub moving: PathBuf,
    /// The transform: .json (moving → fixed, RAS) or .tfm (ITK/3D Slicer: fixed →
    /// moving, LPS).
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    #[command(flatten)]
    pub options: RegistrationOptions,
    /// The frame of the points of files that do not state theirs (lines of a
    /// mesh, or from an older version): RAS (NIfTI images) or LPS (DICOM, NRRD
    /// and MetaImage images, 3D Slicer's models). Files of images and landmark
    /// files state their own; a contradiction is an error. Points are registered
    /// in RAS.
    #[arg(long, ignore_case = true, value_parser = super::named::<Space>(Space::NAMES))]
    pub space: Option<Space>,
    #[command(flatten)]
    pub report: ReportArg,
}

/// [`read_point_set`], with an error naming `path` if it holds too few line points.
fn enough_points(path: &Path, space: Option<Space>) -> Result<PointSet> {
    let set = PointSet::read(path, space)?;
    if set.line_points.len() < 3 {
        return Err(Error::File {
            path: path.to_path_buf(),
            message: format!(
                "{} line points; registration needs at least 3 (no lines were found in that scan?)",
                set.line_points.len()
            ),
        });
    }
    Ok(set)
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
    let options = args.options;
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
    let space = args.space;
    let fixed = report.stage("read fixed", || enough_points(&args.fixed, space))?;
    let moving = report.stage("read moving", || enough_points(&args.moving, space))?;
    let registration = register(&fixed, &moving, &options, &mut report)?;
    report.count("matched_share", registration.matched_share);
    report.count("rms", registration.rms);
    report.count("rotation_degrees", registration.transform.angle_degrees());
    report.count("iterations", registration.iterations);
    println!("{}", summary(&registration, moving.line_points.len()));
    args.report
        .write_with_output(&mut report, &args.output, |p| registration.write(p))
}
