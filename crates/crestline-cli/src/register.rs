//! `crestline register`: the rigid motion taking the feature lines of one scan
//! onto those of another (trimmed ICP on the line points), written as JSON or as an
//! ITK/3D Slicer transform.

use std::path::{Path, PathBuf};

use crestline::jobs::register;
use crestline::landmarks::FORMAT as LANDMARKS;
use crestline::landmarks::{read_landmarks, LandmarkKind, Space};
use crestline::lines::read_json;
use crestline::register::{
    write_transform, PointSet, Registration, RegistrationOptions, TransformFormat,
};
use crestline::{Error, Result};

use super::landmarks::{space_of, SpaceArg};
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
    /// The smallest share of moving points that may be matched (0.1 to 1).
    #[arg(long, value_name = "S", default_value_t = RegistrationOptions::default().min_overlap)]
    pub min_overlap: f64,
    /// At most this many ICP iterations after the coarse stage.
    #[arg(long, value_name = "N", default_value_t = RegistrationOptions::default().max_iterations)]
    pub max_iterations: usize,
    /// The frame of the points of line files (landmark files state their own):
    /// ras (NIfTI images) or lps (DICOM, NRRD and MetaImage images, 3D Slicer's
    /// models). Points are registered in RAS.
    #[arg(long, value_enum, default_value = "ras")]
    pub space: SpaceArg,
    #[command(flatten)]
    pub report: ReportArg,
}

/// The `format` key of a JSON file, read before the file itself.
#[derive(serde::Deserialize)]
struct FormatOnly {
    format: Option<String>,
}

/// The points to register of a `crestline-lines/1` file (every line point, in
/// `space`) or of a landmarks file (every line point, and the extremal points as
/// key points, in the file's space), in RAS.
fn point_set(path: &Path, space: Space) -> Result<PointSet> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let format = serde_json::from_str::<FormatOnly>(&text)
        .ok()
        .and_then(|f| f.format);
    if format.as_deref() == Some(LANDMARKS) {
        let (landmarks, space) = read_landmarks(path)?;
        let line_points = landmarks.lines.iter().flat_map(|line| &line.points);
        let extremal = landmarks
            .points
            .iter()
            .filter(|p| p.kind == LandmarkKind::Extremal);
        return Ok(PointSet {
            line_points: line_points.map(|p| space.to_ras(p)).collect(),
            key_points: extremal.map(|p| space.to_ras(&p.position)).collect(),
        });
    }
    let lines = read_json(path)?;
    let line_points = lines.iter().flat_map(|line| &line.points);
    Ok(PointSet {
        line_points: line_points.map(|p| space.to_ras(p)).collect(),
        key_points: Vec::new(),
    })
}

/// [`point_set`], with an error naming `path` if it holds too few line points.
fn enough_points(path: &Path, space: Space) -> Result<PointSet> {
    let set = point_set(path, space)?;
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
    let space = space_of(args.space);
    let fixed = report.stage("read fixed", || enough_points(&args.fixed, space))?;
    let moving = report.stage("read moving", || enough_points(&args.moving, space))?;
    let registration = register(&fixed, &moving, &options, &mut report)?;
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
