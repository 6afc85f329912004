//! `crestline transfer`: a template's labelled landmarks carried onto another
//! scan through their crest lines (rigid, then a smooth deformation;
//! [`crestline::transfer`]): of two images, the crest lines of their isosurfaces;
//! of two meshes, their ridges and valleys.

use std::path::{Path, PathBuf};

use crestline::io::is_volume_path;
use crestline::jobs::{ridges, transfer, Surface};
use crestline::landmarks::LandmarkFormat;
use crestline::lines::{FeatureLines, LineFormat};
use crestline::transfer::{read_labelled, write_labelled, LabelledPoint, TransferOptions};
use crestline::{Error, Result, Space};

use super::failure::explain;
use super::load::{load_mesh, report_with_progress, StrictArg};
use super::outputs::{check_paths, OutputSet};
use super::report::Report;
use super::surface::{naming, read_image, SeriesArg, IMAGES};
use super::ReportArg;

/// Arguments of `crestline transfer`.
#[derive(clap::Args, Debug)]
pub struct TransferArgs {
    /// The template: a 3D image (.nii, .nii.gz, .nrrd, .nhdr, .mha, .mhd, a DICOM
    /// folder, DICOMDIR or .dcm file; with --level: the crest lines of its
    /// isosurface) or a mesh (.obj, .ply, .off, .stl, .gii, a FreeSurfer surface:
    /// its ridges and valleys).
    pub template: PathBuf,
    /// The template's landmarks, with labels: .mrk.json (3D Slicer markups, the
    /// point lists' control points), .json (as `crestline landmarks` writes) or
    /// .csv (columns label, x, y, z and space: RAS or LPS).
    pub template_landmarks: PathBuf,
    /// The subject: a 3D image of the same anatomy and contrast, or a mesh of the
    /// same anatomy; an image if the template is one, a mesh if it is one.
    pub subject: PathBuf,
    /// Output: .mrk.json (3D Slicer markups), .json or .csv: each landmark's label,
    /// position in the subject, confidence (the RMS distance of the nearby lines
    /// to the subject's, mm; lower is better) and whether it is flagged (the
    /// subject lacks the template's lines around it: a part cut off or missing),
    /// in the order given.
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    /// The isosurface level of both images (not for meshes).
    #[arg(long, value_name = "I", allow_hyphen_values = true)]
    pub level: Option<f64>,
    /// The template's lines, computed once instead of from the template (.json),
    /// as --save-template-lines wrote them.
    #[arg(long, value_name = "FILE")]
    pub template_lines: Option<PathBuf>,
    /// Also write the template's lines, as traced here, to FILE (.json): the
    /// --template-lines of the runs on other subjects.
    #[arg(long, value_name = "FILE", conflicts_with = "template_lines")]
    pub save_template_lines: Option<PathBuf>,
    /// The frame of the meshes' coordinates when a mesh does not state it (3D
    /// Slicer's `SPACE=` mark): RAS or LPS; default LPS, as 3D Slicer reads models.
    #[arg(long, ignore_case = true, value_parser = super::named::<Space>(Space::NAMES))]
    pub space: Option<Space>,
    #[command(flatten)]
    pub options: TransferOptions,
    /// Write the positions of a .json or .csv output in this frame (default RAS;
    /// .mrk.json is in LPS, as 3D Slicer reads it).
    #[arg(long, ignore_case = true, value_parser = super::named::<Space>(Space::NAMES))]
    pub output_space: Option<Space>,
    #[command(flatten)]
    pub series: SeriesArg,
    #[command(flatten)]
    pub strict: StrictArg,
    #[command(flatten)]
    pub report: ReportArg,
}

impl TransferArgs {
    /// An error unless the template and the subject are both images (and
    /// `--level` is given) or both meshes (and it is not); whether they are images.
    fn images(&self) -> Result<bool> {
        let images = is_volume_path(&self.template);
        if is_volume_path(&self.subject) != images {
            let (template, subject) = if images {
                ("an image", "a mesh")
            } else {
                ("a mesh", "an image")
            };
            return Err(argument(
                &self.subject,
                format!(
                    "the subject is {subject} and the template ({}) {template}: give two \
                     images ({IMAGES}) or two meshes",
                    self.template.display()
                ),
            ));
        }
        match (images, self.level) {
            (true, None) => Err(argument(
                &self.template,
                "images need --level I for their isosurface (`crestline info` on the image \
                 suggests one)"
                    .to_string(),
            )),
            (false, Some(_)) => Err(argument(
                &self.template,
                format!("--level applies to 3D images ({IMAGES}), not to meshes"),
            )),
            _ => Ok(images),
        }
    }

    /// The lines of the scan `path`: the crest lines of an image's isosurface at
    /// `--level`, or the ridges and valleys of a mesh in the frame it states or
    /// `--space` gives ([`TransferOptions::mesh_tracing`]).
    fn lines_of(
        &self,
        path: &Path,
        options: &TransferOptions,
        report: &mut Report,
    ) -> Result<FeatureLines> {
        match self.level {
            Some(level) if is_volume_path(path) => {
                let volume = read_image(path, &self.series, report)?;
                options
                    .image_lines(&volume, level, report)
                    .map_err(|e| naming(e, path))
            }
            _ => {
                let (mesh, _) = load_mesh(path, self.strict, report)?;
                let surface = Surface::of_mesh(mesh);
                let lines = ridges(&surface, &options.mesh_tracing(), report)
                    .map_err(|e| explain(e, path))?;
                self.in_frame(lines, path)
            }
        }
    }

    /// Lines of a mesh in the frame they state, or `--space`, or LPS.
    fn in_frame(&self, mut lines: FeatureLines, path: &Path) -> Result<FeatureLines> {
        let frame = Space::resolve(lines.space, self.space).map_err(|e| naming(e, path))?;
        lines.space = Some(frame.unwrap_or(Space::Lps));
        Ok(lines)
    }
}

/// The error of an argument that names the file `path`.
fn argument(path: &Path, message: String) -> Error {
    Error::File {
        path: path.to_path_buf(),
        message,
    }
}

/// Carry the landmarks and write them.
pub fn run(args: &TransferArgs) -> Result<()> {
    LandmarkFormat::from_path(&args.output)?;
    if let Some(path) = &args.save_template_lines {
        if LineFormat::from_path(path)? != LineFormat::Json {
            return Err(argument(
                path,
                "the template's lines are saved as .json, which --template-lines reads".into(),
            ));
        }
    }
    let images = args.images()?;
    let options = &args.options;
    options.validate()?;
    let outputs: Vec<_> = std::iter::once(("-o", args.output.as_path()))
        .chain(
            args.save_template_lines
                .as_deref()
                .map(|p| ("--save-template-lines", p)),
        )
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
        Some(path) if images => {
            report.stage("read template lines", || FeatureLines::read_json(path))?
        }
        Some(path) => {
            let lines = report.stage("read template lines", || FeatureLines::read_json(path))?;
            args.in_frame(lines, path)?
        }
        None => args.lines_of(&args.template, options, &mut report)?,
    };
    if let Some(path) = &args.save_template_lines {
        let mut files = OutputSet::default();
        report.stage("write template lines", || {
            files.write(path, |p| LineFormat::Json.write(p, &template))
        })?;
        files.commit()?;
    }
    let subject = args.lines_of(&args.subject, options, &mut report)?;
    let carried = transfer(&template, &subject, &landmarks, options, &mut report)
        .map_err(|e| naming(e, &args.subject))?;
    println!(
        "{} landmarks, {} flagged; rigid stage: rotation {:.3}°, rms {:.4}; after the \
         deformation: rms {:.4}",
        landmarks.len(),
        carried.flagged.iter().filter(|f| **f).count(),
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
            write_labelled(p, &moved, &carried.confidence, &carried.flagged, space)
        })
}
