//! `crestline view`: an interactive 3D view of a mesh or of an image's isosurface
//! with its feature lines, as one self-contained HTML file.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use crestline::draw::Style;
use crestline::io::{choose_format, write_atomically, FileFormat};
use crestline::jobs::{view, ViewOptions};
use crestline::view::view_html;
use crestline::Result;

use super::draw::FeatureLineArgs;
use super::failure::explain;
use super::load::report_with_progress;
use super::outputs::{check_paths, OutputSet, Role};
use super::ridges::{load_for_tracing, options_for};
use super::ReportArg;

/// Arguments of `crestline view`.
#[derive(clap::Args, Debug)]
pub struct ViewArgs {
    /// The mesh (.obj, .ply, .off, .stl, .gii, a FreeSurfer surface) or 3D image
    /// (with --level).
    pub mesh: PathBuf,
    /// Output view (.html): one file that opens in a browser with no network.
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    #[command(flatten)]
    pub view: ViewOptions,
    /// How the feature lines are traced.
    #[command(flatten)]
    pub features: FeatureLineArgs,
    #[command(flatten)]
    pub report: ReportArg,
}

/// Trace the lines, estimate the curvature and write the view.
pub fn run(args: &ViewArgs) -> Result<()> {
    choose_format(&args.output, "a view (HTML)", &[FileFormat::Html])?;
    let outputs: Vec<Role<'_>> = [Some(("-o", args.output.as_path())), args.report.output()]
        .into_iter()
        .flatten()
        .collect();
    let tracer = &args.features.tracer;
    check_paths(&tracer.inputs(&args.mesh), &outputs)?;
    let mut report = report_with_progress("view", &args.mesh);
    let loaded = load_for_tracing(&args.mesh, tracer, &mut report)?;
    let (_, morse) = args.features.options();
    let options = ViewOptions {
        ridges: options_for(&loaded.surface.mesh, &args.mesh, tracer)?,
        morse,
        ..args.view.clone()
    };
    let input = (loaded.volume.as_ref(), None);
    let (lines, curvature) =
        view(&loaded.surface, input, &options, &mut report).map_err(|e| explain(e, &args.mesh))?;
    report.count("lines", lines.len());
    let title = args.mesh.display().to_string();
    let html = report.stage("html", || {
        Ok(view_html(
            &loaded.surface.mesh,
            &lines,
            Some(&curvature),
            &Style::default(),
            &title,
        ))
    })?;
    let mut files = OutputSet::default();
    report.stage("write", || {
        files.write(&args.output, |p| write_html(p, &html))
    })?;
    if let Some(path) = &args.report.report {
        files.write(path, |p| report.write(p))?;
    }
    files.commit()
}

/// Write `html` to `path` (under a temporary name, renamed on success).
fn write_html(path: &Path, html: &str) -> Result<()> {
    write_atomically(path, |w| w.write_all(html.as_bytes()))
}
