//! `crestline draw`: a line drawing of a mesh (feature lines, silhouettes, borders,
//! creases and suggestive contours, hidden lines removed) as SVG, with an optional
//! PNG preview.

use std::io::Write;
use std::path::{Path, PathBuf};

use crestline::draw::{write_png, Page, Paper, PaperLength, Style};
use crestline::io::{choose_format, write_atomically, FileFormat};
use crestline::jobs::{draw, DrawingOptions, MorseOptions, RidgesOptions};
use crestline::Result;

use super::failure::explain;
use super::load::report_with_progress;
use super::morse::MorseArgs;
use super::outputs::{check_paths, OutputSet, Role};
use super::ridges::{load_for_tracing, options_for, TracerArgs};
use super::ReportArg;

/// Arguments of `crestline draw`.
#[derive(clap::Args, Debug)]
pub struct DrawArgs {
    /// The mesh file (.obj, .ply, .off, .stl, .gii, a FreeSurfer surface).
    pub mesh: PathBuf,
    /// Output drawing (.svg).
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    #[command(flatten)]
    pub drawing: DrawingOptions,
    /// How the feature lines are traced.
    #[command(flatten)]
    pub features: FeatureLineArgs,
    /// Viewing direction in degrees; 0,0 looks along -z with +y up, a positive
    /// azimuth turns the eye about +y towards +x, a positive elevation raises it.
    #[arg(long, value_name = "AZIMUTH,ELEVATION", value_parser = parse_view,
          allow_hyphen_values = true, conflicts_with = "camera")]
    pub view: Option<[f64; 2]>,
    /// Explicit camera: eye, target and up vector. In orthographic projection only
    /// the direction is used and the mesh is framed automatically.
    #[arg(long, value_name = "EX,EY,EZ,TX,TY,TZ,UX,UY,UZ", value_parser = parse_camera,
          allow_hyphen_values = true)]
    pub camera: Option<[f64; 9]>,
    /// Canvas size in pixels.
    #[arg(long, value_name = "WxH", default_value_t = Size(DrawingOptions::default().size),
          value_parser = parse_size, conflicts_with = "page")]
    pub size: Size,
    /// Lay the drawing out on a page for a pen plotter or print: a4, a3, a5, a2,
    /// letter, legal, tabloid or WxH with a unit (200x200mm, 8.5x11in), portrait.
    /// The SVG gets the paper's size in millimetres, every line the pen's width,
    /// and --taper and --silhouette-clearance are then in millimetres
    #[arg(long, value_name = "PAPER")]
    pub page: Option<Paper>,
    /// Turn the page to landscape
    #[arg(long, requires = "page")]
    pub landscape: bool,
    /// The blank border on every side of the page (mm, cm or in)
    #[arg(long, value_name = "LENGTH", requires = "page",
          default_value_t = PaperLength(Page::DEFAULT_MARGIN_MM), value_parser = parse_length)]
    pub margin: PaperLength,
    /// The pen's width: the stroke of every line on the page (mm, cm or in)
    #[arg(long, value_name = "LENGTH", requires = "page",
          default_value_t = PaperLength(Page::DEFAULT_PEN_MM), value_parser = parse_length)]
    pub pen: PaperLength,
    /// JSON file overriding colours and widths per kind of line.
    #[arg(long, value_name = "FILE")]
    pub style: Option<PathBuf>,
    /// Also render a PNG preview next to the SVG (same name, .png).
    #[arg(long)]
    pub png: bool,
    #[command(flatten)]
    pub report: ReportArg,
}

/// How the feature lines of `draw` and `view` are traced: the options of the
/// ridges and of the Morse-Smale lines.
#[derive(clap::Args, Debug)]
pub struct FeatureLineArgs {
    /// Options of the Morse-Smale lines (with `--lines morse`).
    #[command(flatten)]
    pub morse: MorseArgs,
    #[command(flatten)]
    pub tracer: TracerArgs,
}

impl FeatureLineArgs {
    /// The ridges' and the Morse-Smale lines' options, the smoothing weights not
    /// yet read.
    pub fn options(&self) -> (RidgesOptions, MorseOptions) {
        let ridges = self.tracer.options();
        let morse = self.morse.options(ridges.estimator);
        (ridges, morse)
    }
}

impl DrawArgs {
    /// The job's options.
    fn options(&self) -> DrawingOptions {
        let (ridges, morse) = self.features.options();
        DrawingOptions {
            view: self.view.unwrap_or(DrawingOptions::default().view),
            camera: self.camera,
            size: self.size.0,
            page: self.page.map(|paper| Page {
                paper: if self.landscape {
                    paper.turned()
                } else {
                    paper
                },
                margin: self.margin,
                pen: self.pen,
            }),
            ridges,
            morse,
            ..self.drawing.clone()
        }
    }
}

/// The files `draw` reads: the mesh, the smoothing weights and the style.
fn inputs(args: &DrawArgs) -> Vec<Role<'_>> {
    let mut inputs = args.features.tracer.inputs(&args.mesh);
    inputs.extend(args.style.as_deref().map(|s| ("the --style file", s)));
    inputs
}

/// Draw the mesh and write the SVG (and the PNG).
pub fn run(args: &DrawArgs) -> Result<()> {
    check_output(&args.output)?;
    let png = args.png.then(|| args.output.with_extension("png"));
    let outputs: Vec<Role<'_>> = [
        Some(("-o", args.output.as_path())),
        png.as_deref().map(|p| ("the --png preview", p)),
        args.report.output(),
    ]
    .into_iter()
    .flatten()
    .collect();
    check_paths(&inputs(args), &outputs)?;
    let mut options = args.options();
    let base = args.style.as_deref().map(Style::read).transpose()?;
    let style = options.style(base.unwrap_or_default())?;
    options.check()?;
    let mut report = report_with_progress("draw", &args.mesh);
    let loaded = load_for_tracing(&args.mesh, &args.features.tracer, &mut report)?;
    options.ridges = options_for(&loaded.surface.mesh, &args.mesh, &args.features.tracer)?;
    let input = (loaded.volume.as_ref(), None);
    let mut drawing =
        draw(&loaded.surface, input, &options, &mut report).map_err(|e| explain(e, &args.mesh))?;
    drawing.source = args.mesh.display().to_string();
    let paths: serde_json::Map<String, serde_json::Value> = drawing
        .path_counts()
        .into_iter()
        .map(|(group, count)| (group.to_string(), count.into()))
        .collect();
    report.count("paths", serde_json::Value::Object(paths));
    let svg = drawing.svg(&style);
    let mut files = OutputSet::default();
    report.stage("write", || {
        files.write(&args.output, |p| {
            write_atomically(p, |w| w.write_all(svg.as_bytes()))
        })
    })?;
    if let Some(png) = &png {
        let background = style.background.as_deref();
        report.stage("png", || {
            files.write(png, |p| write_png(p, &svg, background))
        })?;
    }
    if let Some(path) = &args.report.report {
        files.write(path, |p| report.write(p))?;
    }
    files.commit()
}

/// The drawing must be an `.svg` file.
fn check_output(path: &Path) -> Result<()> {
    choose_format(path, "a drawing (SVG)", &[FileFormat::Svg]).map(drop)
}

/// `N` comma-separated numbers.
fn parse_numbers<const N: usize>(text: &str) -> std::result::Result<[f64; N], String> {
    let values: Vec<f64> = text
        .split(',')
        .map(|part| {
            part.trim()
                .parse::<f64>()
                .map_err(|_| format!("'{}' is not a number", part.trim()))
        })
        .collect::<std::result::Result<_, _>>()?;
    values
        .try_into()
        .map_err(|v: Vec<f64>| format!("expected {N} comma-separated numbers, got {}", v.len()))
}

/// A length on paper ([`PaperLength`]).
fn parse_length(text: &str) -> std::result::Result<PaperLength, String> {
    text.parse().map_err(|e: crestline::Error| e.to_string())
}

fn parse_view(text: &str) -> std::result::Result<[f64; 2], String> {
    parse_numbers(text)
}

fn parse_camera(text: &str) -> std::result::Result<[f64; 9], String> {
    parse_numbers(text)
}

/// A canvas size in pixels, shown as `WIDTHxHEIGHT`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Size(pub [u32; 2]);

impl std::fmt::Display for Size {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}x{}", self.0[0], self.0[1])
    }
}

/// `WIDTHxHEIGHT` in pixels, e.g. `800x600`.
fn parse_size(text: &str) -> std::result::Result<Size, String> {
    let (w, h) = text
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("'{text}' is not WIDTHxHEIGHT, e.g. 800x600"))?;
    let side = |s: &str| {
        s.trim()
            .parse::<u32>()
            .map_err(|_| format!("'{}' is not a whole number of pixels", s.trim()))
    };
    Ok(Size([side(w)?, side(h)?]))
}
