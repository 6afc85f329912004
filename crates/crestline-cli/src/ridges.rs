//! `crestline ridges`: ridge and valley lines by extremality tracing.

use std::path::{Path, PathBuf};

use crate::report::Report;
use crestline::curvature::DerivativeOrder;
use crestline::jobs::{ridges, IsoOptions, RidgesOptions, Surface};
use crestline::lines::{write_on_surface, FeatureLines, SURFACE_FORMATS};
use crestline::mesh::Mesh;
use crestline::{Error, Result};

use super::failure::{explain, with_values};
use super::frame::OutputSpaceArg;
use super::load::{report_with_progress, ScalarFile, StrictArg};
use super::on_surface::{check_on_surface, line_output};
use super::outputs::{check_paths, Role};
use super::structure::StructureArg;
use super::surface::{load_surface, Loaded, VolumeArgs};
use super::ReportArg;

/// Options of extremality tracing, shared by every command that traces ridges:
/// the library's [`RidgesOptions`], and the files and image options around them.
#[derive(clap::Args, Debug, Clone)]
pub struct TracerArgs {
    #[command(flatten)]
    pub ridges: RidgesOptions,
    /// Per-vertex factors for inhomogeneous extremality smoothing: the name of a PLY
    /// vertex property, or a file with one value per vertex (text with one value
    /// per line, FreeSurfer curv such as lh.sulc, GIfTI .shape.gii/.func.gii).
    #[arg(long, value_name = "PROPERTY|FILE")]
    pub smoothing_weights: Option<String>,
    #[command(flatten)]
    pub strict: StrictArg,
    #[command(flatten)]
    pub volume: VolumeArgs,
}

impl TracerArgs {
    /// The files these options read besides the mesh `mesh`, with the mesh.
    pub fn inputs<'a>(&'a self, mesh: &'a Path) -> Vec<Role<'a>> {
        std::iter::once(("the input mesh", mesh))
            .chain(weights_file(self).map(|f| ("the --smoothing-weights file", f)))
            .collect()
    }

    /// The options of the ridges job, with the image's `--scale`; the smoothing
    /// weights not yet read.
    pub fn options(&self) -> RidgesOptions {
        RidgesOptions {
            scale: self.volume.iso.scale,
            ..self.ridges.clone()
        }
    }

    /// The options of the isosurface of a 3D image: `--sigma`, `--curvature` and
    /// the mesh `--estimator`.
    pub fn iso_options(&self) -> IsoOptions {
        IsoOptions {
            estimator: self.ridges.estimator,
            ..self.volume.iso
        }
    }
}

/// Arguments of `crestline ridges`.
#[derive(clap::Args, Debug)]
pub struct RidgesArgs {
    /// The mesh (.obj, .ply, .off, .stl, .gii, a FreeSurfer surface such as
    /// lh.pial) or 3D image (.nii, .nii.gz, .nrrd, .nhdr, .mha, .mhd, a DICOM
    /// folder, DICOMDIR or .dcm file; with --level).
    #[arg(value_name = "MESH|VOLUME")]
    pub mesh: PathBuf,
    /// Output lines: .json, .obj, .ply, .vtk, .vtp, .vtu (segments, for meshio)
    /// or .mrk.json (3D Slicer markups); or labels of the mesh's vertices the
    /// lines pass near, in the input file's vertex order (not with --fair): a
    /// GIfTI .label.gii (0 none, 1 ridges, 2 valleys) or a FreeSurfer .label
    /// (the labelled vertices, value 1 on ridges and -1 on valleys); or the lines
    /// as a Connectome Workbench .border file (triangles of the input file with
    /// barycentric weights).
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    #[command(flatten)]
    pub structure: StructureArg,
    #[command(flatten)]
    pub tracer: TracerArgs,
    #[command(flatten)]
    pub frame: OutputSpaceArg,
    #[command(flatten)]
    pub report: ReportArg,
}

/// The name under which smoothing weights read from a text file are attached.
const WEIGHTS_FROM_FILE: &str = "crestline_smoothing_weights";

/// Load the surface in `path` (a mesh or a 3D image) for tracing: smoothing
/// weights given as a text file are attached before the repairs, and the repairs
/// are reported as warnings.
pub fn load_for_tracing(path: &Path, args: &TracerArgs, report: &mut Report) -> Result<Loaded> {
    let weights_file = weights_file(args);
    let extra: Vec<ScalarFile<'_>> = weights_file
        .map(|path| ScalarFile {
            name: WEIGHTS_FROM_FILE,
            path,
            option: "--smoothing-weights",
            non_negative: true,
        })
        .into_iter()
        .collect();
    load_surface(
        path,
        (
            args.strict,
            &args.volume,
            args.iso_options(),
            Some(DerivativeOrder::Third),
        ),
        &extra,
        report,
    )
}

/// `--smoothing-weights` when it names an existing file.
fn weights_file(args: &TracerArgs) -> Option<&Path> {
    args.smoothing_weights
        .as_deref()
        .map(Path::new)
        .filter(|p| p.is_file())
}

/// The per-vertex smoothing weights `--smoothing-weights` names on `mesh` (read
/// from `mesh_path`).
fn smoothing_weights(mesh: &Mesh, mesh_path: &Path, args: &TracerArgs) -> Result<Option<Vec<f64>>> {
    match (&args.smoothing_weights, weights_file(args)) {
        (None, _) => Ok(None),
        (Some(_), Some(_)) => Ok(mesh.vertex_scalar(WEIGHTS_FROM_FILE).map(<[f64]>::to_vec)),
        (Some(name), None) => Ok(Some(
            mesh.vertex_scalar(name)
                .ok_or_else(|| Error::File {
                    path: mesh_path.to_path_buf(),
                    message: format!("no vertex property '{name}' (and no file of that name) for --smoothing-weights"),
                })?
                .to_vec(),
        )),
    }
}

/// The options of the ridges job for `mesh` (read from `mesh_path`), with the
/// smoothing weights `--smoothing-weights` names.
pub fn options_for(mesh: &Mesh, mesh_path: &Path, args: &TracerArgs) -> Result<RidgesOptions> {
    Ok(RidgesOptions {
        smoothing_weights: smoothing_weights(mesh, mesh_path, args)?,
        ..args.options()
    })
}

/// Trace the lines of `surface` (loaded by [`load_for_tracing`] from `mesh_path`).
pub fn trace_loaded(
    surface: &Surface,
    mesh_path: &Path,
    args: &TracerArgs,
    report: &mut Report,
) -> Result<FeatureLines> {
    let options = options_for(&surface.mesh, mesh_path, args)?;
    let weights = weights_file(args).map(|file| ("--smoothing-weights", file));
    let mut lines = ridges(surface, &options, report)
        .map_err(|e| with_values(explain(e, mesh_path), weights))?;
    lines.source = mesh_path.display().to_string();
    Ok(lines)
}

/// Trace the lines and write them, or the labels of the vertices they pass near,
/// or a border file.
pub fn run(args: &RidgesArgs) -> Result<()> {
    let format = line_output(&args.output, "ridge and valley lines", &SURFACE_FORMATS)?;
    if format.is_none() {
        check_on_surface(&args.mesh, &args.output, args.tracer.ridges.fair)?;
    }
    let outputs: Vec<Role<'_>> = std::iter::once(("-o", args.output.as_path()))
        .chain(args.report.output())
        .collect();
    check_paths(&args.tracer.inputs(&args.mesh), &outputs)?;
    let mut report = report_with_progress("ridges", &args.mesh);
    let loaded = load_for_tracing(&args.mesh, &args.tracer, &mut report)?;
    let lines = trace_loaded(&loaded.surface, &args.mesh, &args.tracer, &mut report)?;
    match format {
        Some(format) => {
            let lines = args.frame.lines(lines)?;
            args.report
                .write_with_output(&mut report, &args.output, |p| format.write(p, &lines))
        }
        None => args
            .report
            .write_with_output(&mut report, &args.output, |p| {
                write_on_surface(p, &lines, &loaded.surface.mesh, args.structure.structure)
            }),
    }
}
