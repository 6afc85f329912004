//! `crestline draw`: a line drawing of a mesh (feature lines, silhouettes, borders,
//! creases and suggestive contours, hidden lines removed) as SVG, with an optional
//! PNG preview.

use std::path::{Path, PathBuf};

use crate::report::Report;
use crestline::curvature::estimate_curvature;
use crestline::draw::{
    borders, check_taper, creases, group_name, runs_along_outlines, silhouettes,
    suggestive_contours, svg_document, visible_drawing, with_facing, write_png, write_svg, Camera,
    DepthBuffer, DrawOptions, Projection, Style, SuggestiveOptions, View,
};
use crestline::lines::{FeatureLines, LineKind};
use crestline::{Error, Point, Result, Vector};

use super::load::report_with_progress;
use super::morse::{extract as extract_morse, MorseArgs};
use super::outputs::{check_paths, OutputSet, Role};
use super::ridges::{load_for_tracing, trace_loaded, TracerArgs};
use super::surface::Loaded;
use super::ReportArg;
use crestline::jobs::{crest_lines, CrestLinesOptions, Length};

/// Which feature lines to draw.
#[derive(clap::ValueEnum, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LinesChoice {
    /// Ridges and valleys by extremality tracing (the options of `crestline ridges`).
    #[default]
    Ridges,
    /// Ascending and descending lines of the Morse-Smale complex.
    Morse,
    /// For a 3D image: crest lines of its isosurface by Marching Lines (Thirion &
    /// Gourdon), traced in the image rather than on the triangles.
    Crest,
    /// No feature lines (e.g. silhouettes only).
    None,
}

/// Arguments of `crestline draw`.
#[derive(clap::Args, Debug)]
pub struct DrawArgs {
    /// The mesh file (.obj, .ply, .off, .stl).
    pub mesh: PathBuf,
    /// Output drawing (.svg).
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    /// Which feature lines to draw.
    #[arg(long, value_enum, default_value_t)]
    pub lines: LinesChoice,
    /// Also draw the silhouettes (smooth occluding contours).
    #[arg(long)]
    pub silhouettes: bool,
    /// Feature lines are left out where they run beside a visible silhouette
    /// (nearly parallel) closer than this many pixels; 0 keeps them.
    #[arg(long, value_name = "PX", default_value_t = DrawOptions::default().silhouette_clearance)]
    pub silhouette_clearance: f64,
    /// Borders, creases and suggestive contours.
    #[command(flatten)]
    pub families: FamilyArgs,
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
    /// Perspective projection with this field of view in degrees (across the
    /// shorter side); orthographic without it.
    #[arg(long, value_name = "FOV")]
    pub perspective: Option<f64>,
    /// Canvas size in pixels.
    #[arg(long, value_name = "WxH", default_value = "800x800", value_parser = parse_size)]
    pub size: [u32; 2],
    /// JSON file overriding colours and widths per kind of line.
    #[arg(long, value_name = "FILE")]
    pub style: Option<PathBuf>,
    /// Narrow the ends of every open line over this many pixels (as the style
    /// key `taper` of every kind).
    #[arg(long, value_name = "PX")]
    pub taper: Option<f64>,
    /// Thin every line with depth, down to half its width at the farthest point
    /// (as the style key `width_by_depth` of every kind).
    #[arg(long)]
    pub width_by_depth: bool,
    /// Fade the ridges, valleys and Morse-Smale lines where the surface turns away
    /// from the viewer (as the style key `fade_by_view` of those kinds).
    #[arg(long)]
    pub fade_by_view: bool,
    /// Also render a PNG preview next to the SVG (same name, .png).
    #[arg(long)]
    pub png: bool,
    /// Options of the Morse-Smale lines (with `--lines morse`).
    #[command(flatten)]
    pub morse: MorseArgs,
    #[command(flatten)]
    pub tracer: TracerArgs,
    #[command(flatten)]
    pub report: ReportArg,
}

/// The line families `draw` can add besides the silhouettes.
#[derive(clap::Args, Debug)]
pub struct FamilyArgs {
    /// Also draw the borders (boundary loops) of an open mesh.
    #[arg(long)]
    pub borders: bool,
    /// Also draw the creases: edges whose two faces meet at a dihedral angle above
    /// DEG degrees (strictly between 0 and 180).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub creases: Option<f64>,
    /// Also draw the suggestive contours (DeCarlo et al. 2003), from the curvature
    /// of --estimator.
    #[arg(long)]
    pub suggestive: bool,
}

/// `style` with the line weights asked for on the command line.
fn line_weights(mut style: Style, args: &DrawArgs) -> Result<Style> {
    if let Some(taper) = args.taper {
        check_taper("--taper", taper).map_err(Error::Argument)?;
    }
    for kind in LineKind::ALL {
        let stroke = style.kind_mut(kind);
        stroke.taper = args.taper.unwrap_or(stroke.taper);
        stroke.width_by_depth |= args.width_by_depth;
        stroke.fade_by_view |= args.fade_by_view && runs_along_outlines(kind);
    }
    Ok(style)
}

/// The files `draw` reads: the mesh, the smoothing weights and the style.
fn inputs(args: &DrawArgs) -> Vec<Role<'_>> {
    let mut inputs = args.tracer.inputs(&args.mesh);
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
    let style = line_weights(
        args.style
            .as_deref()
            .map(Style::read)
            .transpose()?
            .unwrap_or_default(),
        args,
    )?;
    let options = DrawOptions {
        silhouettes: args.silhouettes,
        silhouette_clearance: args.silhouette_clearance,
        borders: args.families.borders,
        crease_angle: args.families.creases,
        suggestive: args.families.suggestive.then(SuggestiveOptions::default),
        ..DrawOptions::default()
    };
    options.check()?;
    let mut report = report_with_progress("draw", &args.mesh);
    let loaded = load_for_tracing(&args.mesh, &args.tracer, &mut report)?;
    let mesh = &loaded.surface.mesh;
    let [width, height] = args.size;
    let camera = Camera::framing(
        mesh.positions(),
        view(args),
        projection(args),
        width,
        height,
    )?;

    let mut extraction = Report::new("draw", &args.mesh);
    extraction.observer = report.observer.clone();
    let mut lines = report.stage("extraction", || extract(&loaded, args, &mut extraction))?;
    report.counts.append(&mut extraction.counts);
    report.section("extraction_stages", &extraction.stages);

    if options.silhouettes {
        add_stage(&mut report, &mut lines, LineKind::Silhouette, || {
            Ok(silhouettes(mesh, &camera, options.silhouette_min_length))
        })?;
    }
    if options.borders {
        add_stage(&mut report, &mut lines, LineKind::Border, || {
            Ok(borders(mesh))
        })?;
    }
    if let Some(angle) = options.crease_angle {
        add_stage(&mut report, &mut lines, LineKind::Crease, || {
            creases(mesh, angle)
        })?;
    }
    if let Some(suggestive) = &options.suggestive {
        add_stage(&mut report, &mut lines, LineKind::Suggestive, || {
            let estimator = loaded.surface.estimator(args.tracer.estimator);
            let field = estimate_curvature(mesh, &*estimator)?;
            suggestive_contours(mesh, &field, &camera, suggestive)
        })?;
    }
    let drawing = report.stage("visibility", || {
        // n · v per point is only drawn by lines faded by view.
        if LineKind::ALL
            .into_iter()
            .any(|kind| style.kind(kind).fade_by_view)
        {
            with_facing(mesh, &camera, &mut lines);
        }
        let buffer = DepthBuffer::render(mesh, &camera, options.supersampling);
        visible_drawing(&lines, &camera, &buffer, &options)
    })?;
    let paths: serde_json::Map<String, serde_json::Value> = drawing
        .path_counts()
        .into_iter()
        .map(|(group, count)| (group.to_string(), count.into()))
        .collect();
    report.count("paths", serde_json::Value::Object(paths));

    warn_if_empty(args, &drawing, lines.is_empty());

    let svg = svg_document(&drawing, &style);
    let mut files = OutputSet::default();
    report.stage("write", || {
        files.write(&args.output, |p| write_svg(p, &svg))
    })?;
    if let Some(png) = &png {
        report.stage("png", || files.write(png, |p| write_png(p, &svg)))?;
    }
    if let Some(path) = &args.report.report {
        files.write(path, |p| report.write(p))?;
    }
    files.commit()
}

/// Run `trace` as the stage named after the SVG group of `kind`, count its lines
/// as `<kind>_lines` and add them to `lines`.
fn add_stage(
    report: &mut Report,
    lines: &mut FeatureLines,
    kind: LineKind,
    trace: impl FnOnce() -> Result<FeatureLines>,
) -> Result<()> {
    let traced = report.stage(group_name(kind), trace)?;
    report.count(&format!("{}_lines", kind.name()), traced.len());
    lines.lines.extend(traced.lines);
    Ok(())
}

/// Warn when the drawing has no path, saying why where it can (an empty result
/// of the feature lines is warned about where they are extracted).
fn warn_if_empty(args: &DrawArgs, drawing: &crestline::draw::Drawing, no_lines: bool) {
    if drawing
        .path_counts()
        .into_iter()
        .any(|(_, count)| count > 0)
    {
        return;
    }
    let FamilyArgs {
        borders,
        creases,
        suggestive,
    } = args.families;
    let families = args.silhouettes || borders || creases.is_some() || suggestive;
    let why = if args.lines == LinesChoice::None && !families {
        "the drawing is empty: --lines none without --silhouettes, --borders, --creases or --suggestive draws nothing"
    } else if no_lines {
        "the drawing is empty: no lines were found"
    } else {
        "the drawing is empty: every line is hidden in this view; try another --view"
    };
    super::warn(&args.mesh, why);
}

/// The feature lines of the surface, by the chosen method.
fn extract(loaded: &Loaded, args: &DrawArgs, report: &mut Report) -> Result<FeatureLines> {
    let surface = &loaded.surface;
    match args.lines {
        LinesChoice::Ridges => trace_loaded(surface, &args.mesh, &args.tracer, report),
        LinesChoice::Morse => {
            let surface = (surface, args.tracer.estimator);
            extract_morse(surface, &args.mesh, &args.morse, report).map(|(lines, _)| lines)
        }
        LinesChoice::Crest => marching_crest_lines(loaded, args, report),
        LinesChoice::None => Ok(FeatureLines::new(args.mesh.display().to_string())),
    }
}

/// The crest lines of the image the surface was extracted from, with its σ, at
/// least three voxels long and as strong as `--threshold` (∫|k| ds, as for
/// ridges).
fn marching_crest_lines(
    loaded: &Loaded,
    args: &DrawArgs,
    report: &mut Report,
) -> Result<FeatureLines> {
    let (Some(volume), Some(from)) = (&loaded.volume, loaded.surface.image) else {
        return Err(Error::File {
            path: args.mesh.clone(),
            message: "--lines crest traces lines in a 3D image; for a mesh use ridges or morse"
                .into(),
        });
    };
    let options = CrestLinesOptions {
        sigma: Length::World(from.sigma),
        min_strength: args.tracer.threshold,
        ..CrestLinesOptions::default()
    };
    let mut lines = crest_lines(volume, from.level, &options, report)?;
    lines.source = args.mesh.display().to_string();
    Ok(lines)
}

/// The drawing must be an `.svg` file.
fn check_output(path: &Path) -> Result<()> {
    let is_svg = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("svg"));
    if is_svg {
        Ok(())
    } else {
        Err(Error::File {
            path: path.to_path_buf(),
            message: "drawings are written as SVG: give a .svg file name".into(),
        })
    }
}

/// The view from `--view` or `--camera` (the default orbit view without either).
fn view(args: &DrawArgs) -> View {
    match (args.view, args.camera) {
        (_, Some([ex, ey, ez, tx, ty, tz, ux, uy, uz])) => View::LookAt {
            eye: Point::new(ex, ey, ez),
            target: Point::new(tx, ty, tz),
            up: Vector::new(ux, uy, uz),
        },
        (Some([azimuth, elevation]), None) => View::Orbit { azimuth, elevation },
        (None, None) => View::default(),
    }
}

/// Perspective with `--perspective FOV`, orthographic otherwise.
fn projection(args: &DrawArgs) -> Projection {
    args.perspective
        .map_or(Projection::Orthographic, |fov| Projection::Perspective {
            fov,
        })
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

fn parse_view(text: &str) -> std::result::Result<[f64; 2], String> {
    parse_numbers(text)
}

fn parse_camera(text: &str) -> std::result::Result<[f64; 9], String> {
    parse_numbers(text)
}

/// `WIDTHxHEIGHT` in pixels, e.g. `800x600`.
fn parse_size(text: &str) -> std::result::Result<[u32; 2], String> {
    let (w, h) = text
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("'{text}' is not WIDTHxHEIGHT, e.g. 800x600"))?;
    let side = |s: &str| {
        s.trim()
            .parse::<u32>()
            .map_err(|_| format!("'{}' is not a whole number of pixels", s.trim()))
    };
    Ok([side(w)?, side(h)?])
}
