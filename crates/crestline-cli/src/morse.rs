//! `crestline morse`: feature lines from the Morse-Smale complex of a curvature
//! indicator (Sahner et al. 2008).

use std::path::{Path, PathBuf};

use crate::report::Report;
use crestline::curvature::Estimator;
use crestline::io::FileFormat;
use crestline::lines::{write_on_surface, FeatureLines};
use crestline::morse::{Cancellation, Indicator, MorseSummary};
use crestline::Result;

use super::failure::{explain, with_values};
use super::frame::OutputSpaceArg;
use super::load::{report_with_progress, ScalarFile, StrictArg};
use super::on_surface::{check_on_surface, line_output};
use super::outputs::{check_paths, OutputSet, Role};
use super::plot::write_hierarchy_png;
use super::structure::StructureArg;
use super::surface::{load_surface, VolumeArgs};
use super::ReportArg;
use crestline::curvature::DerivativeOrder;
use crestline::jobs::{morse, IsoOptions, MorseOptions, Surface};

/// Options of the Morse-Smale extractor, shared by every command that uses it:
/// the library's [`MorseOptions`] but the curvature estimator, which is the
/// command's.
#[derive(clap::Args, Debug, Clone)]
pub struct MorseArgs {
    #[command(flatten)]
    pub options: MorseOptions,
}

impl MorseArgs {
    /// `--indicator` when it names an existing file of per-vertex values, with
    /// the property name its values are attached under (the name given).
    pub fn indicator_file(&self) -> Option<(&str, &Path)> {
        match &self.options.indicator {
            Indicator::Property(name) if Path::new(name).is_file() => {
                Some((name.as_str(), Path::new(name)))
            }
            _ => None,
        }
    }

    /// The job's options, with the curvature `estimator`.
    pub fn options(&self, estimator: Estimator) -> MorseOptions {
        MorseOptions {
            estimator,
            ..self.options.clone()
        }
    }
}

/// Arguments of `crestline morse`.
#[derive(clap::Args, Debug)]
pub struct MorseCommand {
    /// The mesh (.obj, .ply, .off, .stl, .gii, a FreeSurfer surface) or 3D image
    /// (.nii, .nii.gz, .nrrd, .nhdr, .mha, .mhd, a DICOM folder, DICOMDIR or .dcm
    /// file; with --level).
    #[arg(value_name = "MESH|VOLUME")]
    pub mesh: PathBuf,
    /// Output lines: .json, .obj, .ply, .vtk, .vtp, .vtu (segments, for meshio)
    /// or .mrk.json (3D Slicer markups); or, of a mesh, a Connectome Workbench
    /// .border file (triangles of the input file with barycentric weights).
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    #[command(flatten)]
    pub structure: StructureArg,
    /// Curvature estimator for curvature indicators (jet-fit is steadier on
    /// irregular meshes, where the shape operator's spikes become long-lived maxima).
    #[arg(long, default_value_t = MorseOptions::default().estimator,
          value_parser = super::named::<Estimator>(Estimator::NAMES))]
    pub estimator: Estimator,
    #[command(flatten)]
    pub morse: MorseArgs,
    /// Write the cancellation sequence as JSON: per cancellation the saddle, the
    /// extremum, the criterion t, the significance (the largest t so far, so it
    /// never decreases) and the saddles left.
    #[arg(long, value_name = "FILE")]
    pub hierarchy: Option<PathBuf>,
    /// Plot significance against saddles left (PNG) to choose --keep-saddles: a
    /// knee in the curve is a natural place to stop. Run with --keep-saddles 0
    /// to see the whole hierarchy.
    #[arg(long, value_name = "FILE.png")]
    pub hierarchy_plot: Option<PathBuf>,
    #[command(flatten)]
    pub strict: StrictArg,
    #[command(flatten)]
    pub volume: VolumeArgs,
    #[command(flatten)]
    pub frame: OutputSpaceArg,
    #[command(flatten)]
    pub report: ReportArg,
}

/// Extract the Morse-Smale lines of `surface` (read from `mesh_path`), its
/// curvature from `estimator` unless it carries its own, recording in `report`.
pub fn extract(
    (surface, estimator): (&Surface, Estimator),
    mesh_path: &Path,
    args: &MorseArgs,
    report: &mut Report,
) -> Result<(FeatureLines, MorseSummary)> {
    let indicator = args.indicator_file().map(|(_, file)| ("--indicator", file));
    let (mut lines, summary) = morse(surface, None, &args.options(estimator), report)
        .map_err(|e| with_values(explain(e, mesh_path), indicator))?;
    lines.source = mesh_path.display().to_string();
    let after = summary.after;
    report.section(
        "counts_after",
        serde_json::json!({
            "minima": after.minima,
            "saddles": after.saddles,
            "maxima": after.maxima,
            "forced_saddles": summary.forced_saddles,
        }),
    );
    Ok((lines, summary))
}

/// Extract and write the lines (and the hierarchy).
pub fn run(args: &MorseCommand) -> Result<()> {
    let format = line_output(&args.output, "Morse-Smale lines", &[FileFormat::Border])?;
    if format.is_none() {
        check_on_surface(&args.mesh, &args.output, false)?;
    }
    let outputs: Vec<Role<'_>> = [
        Some(("-o", args.output.as_path())),
        args.hierarchy.as_deref().map(|h| ("--hierarchy", h)),
        args.hierarchy_plot
            .as_deref()
            .map(|h| ("--hierarchy-plot", h)),
        args.report.output(),
    ]
    .into_iter()
    .flatten()
    .collect();
    let indicator_file: Vec<ScalarFile<'_>> = args
        .morse
        .indicator_file()
        .map(|(name, path)| ScalarFile {
            name,
            path,
            option: "--indicator",
            non_negative: false,
        })
        .into_iter()
        .collect();
    let inputs: Vec<Role<'_>> = std::iter::once(("the input mesh", args.mesh.as_path()))
        .chain(
            indicator_file
                .iter()
                .map(|f| ("the --indicator file", f.path)),
        )
        .collect();
    check_paths(&inputs, &outputs)?;
    let mut report = report_with_progress("morse", &args.mesh);
    let iso = IsoOptions {
        estimator: args.estimator,
        ..args.volume.iso
    };
    let loaded = load_surface(
        &args.mesh,
        (
            args.strict,
            &args.volume,
            iso,
            Some(DerivativeOrder::Second),
        ),
        &indicator_file,
        &mut report,
    )?;
    let surface = (&loaded.surface, args.estimator);
    let (lines, summary) = extract(surface, &args.mesh, &args.morse, &mut report)?;
    let mut files = OutputSet::default();
    match format {
        Some(format) => {
            let lines = args.frame.lines(lines)?;
            report.stage("write", || {
                files.write(&args.output, |p| format.write(p, &lines))
            })?;
        }
        None => report.stage("write", || {
            files.write(&args.output, |p| {
                write_on_surface(p, &lines, &loaded.surface.mesh, args.structure.structure)
            })
        })?,
    }
    if let Some(path) = &args.hierarchy {
        files.write(path, |p| write_hierarchy(p, &summary))?;
    }
    if let Some(path) = &args.hierarchy_plot {
        let points: Vec<(f64, f64)> = hierarchy_steps(&summary)
            .map(|step| (step.saddles_left as f64, step.significance))
            .collect();
        let kept = summary.after.saddles as f64;
        files.write(path, |p| write_hierarchy_png(p, &points, kept))?;
    }
    if let Some(path) = &args.report.report {
        files.write(path, |p| report.write(p))?;
    }
    files.commit()
}

/// One cancellation of the hierarchy as written.
#[derive(serde::Serialize)]
struct Step<'a> {
    #[serde(flatten)]
    cancellation: &'a Cancellation,
    /// The largest criterion value so far: non-decreasing along the sequence.
    significance: f64,
    /// Saddles left after this cancellation.
    saddles_left: usize,
}

/// The cancellations with their significance and the saddles left.
fn hierarchy_steps(summary: &MorseSummary) -> impl Iterator<Item = Step<'_>> {
    let initial = summary.initial.saddles;
    summary.hierarchy.iter().enumerate().scan(
        f64::NEG_INFINITY,
        move |significance, (k, cancellation)| {
            *significance = significance.max(cancellation.t);
            Some(Step {
                cancellation,
                significance: *significance,
                saddles_left: initial.saturating_sub(k + 1),
            })
        },
    )
}

/// Write the cancellation sequence as
/// `{"initial_saddles": n, "cancellations": [...]}`.
fn write_hierarchy(path: &Path, summary: &MorseSummary) -> Result<()> {
    let steps: Vec<Step<'_>> = hierarchy_steps(summary).collect();
    crestline::io::write_atomically(path, |w| {
        serde_json::to_writer_pretty(
            &mut *w,
            &serde_json::json!({
                "initial_saddles": summary.initial.saddles,
                "cancellations": steps,
            }),
        )?;
        std::io::Write::write_all(w, b"\n")
    })
}
