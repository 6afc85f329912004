//! Line drawings of a surface (`crestline draw`): its feature lines, silhouettes,
//! borders, creases and suggestive contours with hidden lines removed.

use serde::{Deserialize, Serialize};

use super::crest::{crest_lines, CrestLinesOptions};
use super::image::Surface;
use super::morse::{morse, MorseOptions};
use super::ridges::{ridges, RidgesOptions};
use super::Length;
use crate::draw::{
    check_taper, draw_observed, for_plotter, runs_along_outlines, Camera, DrawOptions, Drawing,
    Page, Projection, Style, SuggestiveOptions, View,
};
use crate::lines::{FeatureLines, LineKind};
use crate::progress::{try_stage_with, Observer};
use crate::volume::Volume;
use crate::{Error, Point, Result, Vector};

/// Which feature lines a drawing shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LinesChoice {
    /// Ridges and valleys by extremality tracing ([`super::ridges`]).
    #[default]
    Ridges,
    /// Ascending and descending lines of the Morse-Smale complex ([`super::morse`]).
    Morse,
    /// For an isosurface: the crest lines of its image by Marching Lines
    /// ([`super::crest_lines`]), traced in the image rather than on the triangles.
    Crest,
    /// No feature lines (e.g. silhouettes only).
    None,
}

crate::named::named!(LinesChoice, "kind of lines", {
    Ridges => "ridges",
    Morse => "morse",
    Crest => "crest",
    None => "none",
});

/// Options of [`draw`]. Each field is an option of the tool and a keyword
/// argument of the Python package, documented here once: with the feature `clap`
/// this struct is the tool's arguments, but for the view, camera, size and page,
/// which the tool reads from text of its own (`AZIMUTH,ELEVATION`, `WxH`, a paper
/// name), and the ridges' and Morse-Smale lines' options, which are their jobs'.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
#[serde(default, deny_unknown_fields)]
pub struct DrawingOptions {
    /// Which feature lines: ridges (the options of the ridges job), morse (those
    /// of the Morse-Smale job), crest (for a 3D image: its crest lines by Marching
    /// Lines, traced in the image) or none (e.g. silhouettes only).
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = LinesChoice::default()))]
    pub lines: LinesChoice,
    /// The viewing direction, azimuth and elevation in degrees (0, 0 looks along
    /// −z with +y up). Default: 0, 0.
    #[cfg_attr(feature = "clap", arg(skip = DrawingOptions::default().view))]
    pub view: [f64; 2],
    /// An explicit camera instead of `view`: eye, target and up vector.
    /// Default: none.
    #[cfg_attr(feature = "clap", arg(skip))]
    pub camera: Option<[f64; 9]>,
    /// Perspective projection with this field of view in degrees (across the
    /// shorter side); orthographic without it.
    #[cfg_attr(feature = "clap", arg(long, value_name = "FOV"))]
    pub perspective: Option<f64>,
    /// Canvas width and height in pixels. Default: 800 × 800. With a `page` the
    /// canvas is its printable area, and `size` must be left at its default.
    #[cfg_attr(feature = "clap", arg(skip = DrawingOptions::default().size))]
    pub size: [u32; 2],
    /// A physical page for pen plotters and print (paper, margin, pen): the SVG
    /// declares the paper's size in millimetres, every line is stroked with the
    /// pen, and `taper` and `silhouette_clearance` are in millimetres ([`Page`]).
    /// Default: none, a canvas of `size` pixels.
    #[cfg_attr(feature = "clap", arg(skip))]
    pub page: Option<Page>,
    /// Also draw the silhouettes (smooth occluding contours).
    #[cfg_attr(feature = "clap", arg(long))]
    pub silhouettes: bool,
    /// Feature lines are left out where they run beside a visible silhouette
    /// (nearly parallel) closer than this many pixels (millimetres on a page); 0
    /// keeps them. Default: 4 pixels (0.4 mm on a page).
    #[cfg_attr(feature = "clap", arg(long, value_name = "PX"))]
    pub silhouette_clearance: Option<f64>,
    /// Also draw the borders (boundary loops) of an open mesh.
    #[cfg_attr(feature = "clap", arg(long))]
    pub borders: bool,
    /// Also draw the creases: edges whose two faces meet at a dihedral angle above
    /// DEG degrees (strictly between 0 and 180).
    #[cfg_attr(
        feature = "clap",
        arg(long, value_name = "DEG", allow_hyphen_values = true)
    )]
    pub creases: Option<f64>,
    /// Also draw the suggestive contours (DeCarlo et al. 2003), from the curvature
    /// of the ridges' estimator.
    #[cfg_attr(feature = "clap", arg(long))]
    pub suggestive: bool,
    /// Narrow the ends of every open line over this many pixels, millimetres on a
    /// page (as the style key `taper` of every kind). Default: the style's.
    #[cfg_attr(feature = "clap", arg(long, value_name = "PX"))]
    pub taper: Option<f64>,
    /// Thin every line with depth, down to half its width at the farthest point
    /// (as the style key `width_by_depth` of every kind).
    #[cfg_attr(feature = "clap", arg(long))]
    pub width_by_depth: bool,
    /// Fade the ridges, valleys and Morse-Smale lines where the surface turns away
    /// from the viewer (as the style key `fade_by_view` of those kinds).
    #[cfg_attr(feature = "clap", arg(long))]
    pub fade_by_view: bool,
    /// For a pen plotter: every stroke drawn once, strokes joined where their ends
    /// meet and ordered to keep the pen's travel in the air short; every stroke of
    /// constant width (no taper, width by depth or fading by view; the style's are
    /// ignored).
    #[cfg_attr(feature = "clap", arg(long,
        conflicts_with_all = ["taper", "width_by_depth", "fade_by_view"]))]
    pub plot: bool,
    /// How ridges are traced (`lines` ridges; their estimator also serves the
    /// suggestive contours, and their threshold the crest lines).
    #[cfg_attr(feature = "clap", arg(skip))]
    pub ridges: RidgesOptions,
    /// How Morse-Smale lines are extracted (`lines` morse). Default: the Morse-Smale
    /// job's, with the ridges' estimator.
    #[cfg_attr(feature = "clap", arg(skip = morse_of_a_picture()))]
    pub morse: MorseOptions,
}

impl Default for DrawingOptions {
    fn default() -> Self {
        let drawing = DrawOptions::default();
        DrawingOptions {
            lines: LinesChoice::default(),
            view: [0.0, 0.0],
            camera: None,
            perspective: None,
            size: [800, 800],
            page: None,
            silhouettes: drawing.silhouettes,
            silhouette_clearance: None,
            borders: drawing.borders,
            creases: drawing.crease_angle,
            suggestive: drawing.suggestive.is_some(),
            taper: None,
            width_by_depth: false,
            fade_by_view: false,
            plot: false,
            ridges: RidgesOptions::default(),
            morse: morse_of_a_picture(),
        }
    }
}

/// The Morse-Smale options of a drawing or a view: the job's, but for the
/// estimator, which is the ridges' (a picture's curvature comes from one
/// estimator, which the tool's `--estimator` sets).
pub(crate) fn morse_of_a_picture() -> MorseOptions {
    MorseOptions {
        estimator: RidgesOptions::default().estimator,
        ..MorseOptions::default()
    }
}

impl DrawingOptions {
    /// Checks the settings of the drawing step: errors ([`Error::Argument`]) for
    /// a negative or non-finite silhouette clearance, or a crease angle not strictly
    /// between 0 and 180 degrees.
    pub fn check(&self) -> Result<()> {
        self.draw_options().check()
    }

    /// The settings of the drawing step ([`crate::draw::draw`]).
    pub(crate) fn draw_options(&self) -> DrawOptions {
        let clearance = self.silhouette_clearance.map(|c| self.pixels(c));
        DrawOptions {
            silhouettes: self.silhouettes,
            silhouette_clearance: clearance.unwrap_or(DrawOptions::default().silhouette_clearance),
            borders: self.borders,
            crease_angle: self.creases,
            suggestive: self.suggestive.then(SuggestiveOptions::default),
            plot: self.plot,
            ..DrawOptions::default()
        }
    }

    /// A length of these options in canvas pixels: as given without a page, from
    /// millimetres on one.
    fn pixels(&self, length: f64) -> f64 {
        if self.page.is_some() {
            Page::pixels(length)
        } else {
            length
        }
    }

    /// The canvas size: `size`, or the printable area of the page.
    ///
    /// Errors ([`Error::Argument`]) for a page that leaves nothing to draw on or a
    /// pen that does not fit ([`Page::check`]), or a `size` given with a page.
    pub fn canvas(&self) -> Result<[u32; 2]> {
        let Some(page) = &self.page else {
            return Ok(self.size);
        };
        page.check()?;
        if self.size != DrawingOptions::default().size {
            return Err(Error::Argument(
                "`size` is the page's printable area on a `page`; leave `size` out".into(),
            ));
        }
        Ok(page.canvas())
    }

    /// The camera that frames `surface` as these options say.
    pub(crate) fn camera(&self, surface: &Surface) -> Result<Camera> {
        let view = match self.camera {
            Some([ex, ey, ez, tx, ty, tz, ux, uy, uz]) => View::LookAt {
                eye: Point::new(ex, ey, ez),
                target: Point::new(tx, ty, tz),
                up: Vector::new(ux, uy, uz),
            },
            None => View::Orbit {
                azimuth: self.view[0],
                elevation: self.view[1],
            },
        };
        let projection =
            self.perspective
                .map_or(Projection::Orthographic, |fov| Projection::Perspective {
                    fov,
                });
        let [width, height] = self.canvas()?;
        Camera::framing(surface.mesh.positions(), view, projection, width, height)
    }

    /// `style` with the line weights these options ask for; on a page every line
    /// stroked with the pen.
    pub fn style(&self, mut style: Style) -> Result<Style> {
        if self.plot && (self.taper.is_some() || self.width_by_depth || self.fade_by_view) {
            return Err(Error::Argument(
                "a pen draws every stroke alike: `plot` takes no `taper`, `width_by_depth` or \
                 `fade_by_view`"
                    .into(),
            ));
        }
        let taper = self.taper.map(|taper| self.pixels(taper));
        if let Some(taper) = taper {
            check_taper("`taper`", taper).map_err(Error::Argument)?;
        }
        for kind in LineKind::ALL {
            let stroke = style.kind_mut(kind);
            if let Some(page) = &self.page {
                stroke.width = Page::pixels(page.pen.0);
            }
            stroke.taper = taper.unwrap_or(stroke.taper);
            stroke.width_by_depth |= self.width_by_depth;
            stroke.fade_by_view |= self.fade_by_view && runs_along_outlines(kind);
            if self.plot {
                (stroke.taper, stroke.width_by_depth, stroke.fade_by_view) = (0.0, false, false);
            }
        }
        Ok(style)
    }

    /// Whether anything besides the feature lines is drawn.
    fn draws_families(&self) -> bool {
        self.silhouettes || self.borders || self.creases.is_some() || self.suggestive
    }
}

/// The drawing of `surface` as `options` say: the feature lines (the stage
/// `extraction`, with the stages of their job; or the `given` lines instead), the
/// other families and the visibility (`draw_observed`), a warning saying why
/// when nothing is seen. `volume` is the image of an isosurface, which `lines`
/// crest needs.
///
/// # Examples
///
/// ```
/// # use crestline::jobs::{self, Surface};
/// # use crestline::progress::Silent;
/// # let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../meshes/bunny_small.obj");
/// # let (mesh, _repairs) = jobs::build_mesh(crestline::io::read_mesh(path.as_ref())?, false, &mut Silent)?;
/// # let surface = Surface::of_mesh(mesh);
/// let options = jobs::DrawingOptions::default();
/// let drawing = jobs::draw(&surface, (None, None), &options, &mut Silent)?;
/// let svg = drawing.svg(&options.style(Default::default())?);
/// assert!(svg.starts_with("<?xml"));
/// # Ok::<(), crestline::Error>(())
/// ```
pub fn draw(
    surface: &Surface,
    (volume, given): (Option<&Volume>, Option<FeatureLines>),
    options: &DrawingOptions,
    observer: &mut dyn Observer,
) -> Result<Drawing> {
    let drawing_options = options.draw_options();
    drawing_options.check()?;
    let camera = options.camera(surface)?;
    let choice = (options.lines, &options.ridges, &options.morse);
    let lines = given_or_traced(surface, (volume, given), choice, observer)?;
    let no_lines = lines.is_empty();
    let estimator = surface.estimator(options.ridges.estimator);
    let mut drawing = draw_observed(
        &surface.mesh,
        lines,
        &camera,
        &drawing_options,
        estimator.as_ref(),
        observer,
    )?;
    if drawing.path_counts().iter().all(|&(_, count)| count == 0) {
        observer.warning(empty_drawing(options, no_lines));
    }
    drawing.page = options.page;
    if options.plot {
        for_plotter(&mut drawing);
    }
    Ok(drawing)
}

/// The `given` lines, or else (the stage `extraction`, with the stages of their
/// job) those `lines` chooses, traced with `ridges` or `morse` (the ridges'
/// threshold also filters crest lines; `volume` is the image of an isosurface,
/// which crest lines need).
pub(super) fn given_or_traced(
    surface: &Surface,
    (volume, given): (Option<&Volume>, Option<FeatureLines>),
    choice: (LinesChoice, &RidgesOptions, &MorseOptions),
    observer: &mut dyn Observer,
) -> Result<FeatureLines> {
    match given {
        Some(lines) => Ok(lines),
        None => try_stage_with(observer, "extraction", |observer| {
            traced(surface, volume, choice, observer)
        }),
    }
}

/// The feature lines `lines` chooses (see [`given_or_traced`]).
fn traced(
    surface: &Surface,
    volume: Option<&Volume>,
    (lines, ridges_options, morse_options): (LinesChoice, &RidgesOptions, &MorseOptions),
    observer: &mut dyn Observer,
) -> Result<FeatureLines> {
    match lines {
        LinesChoice::Ridges => ridges(surface, ridges_options, observer),
        LinesChoice::Morse => Ok(morse(surface, None, morse_options, observer)?.0),
        LinesChoice::Crest => {
            let (Some(volume), Some(from)) = (volume, surface.image) else {
                return Err(Error::Argument(
                    "crest lines are traced in a 3D image; for a mesh draw ridges or morse lines"
                        .into(),
                ));
            };
            let crest = CrestLinesOptions {
                scale: Some(from.scale),
                sigma: Length::World(from.sigma),
                min_strength: ridges_options.threshold,
                ..CrestLinesOptions::default()
            };
            crest_lines(volume, from.level, &crest, observer)
        }
        LinesChoice::None => Ok(FeatureLines::new(String::new())),
    }
}

/// Why a drawing shows nothing, and what to change.
fn empty_drawing(options: &DrawingOptions, no_lines: bool) -> &'static str {
    if options.lines == LinesChoice::None && !options.draws_families() {
        "the drawing is empty: `lines` none without `silhouettes`, `borders`, `creases` or `suggestive` draws nothing"
    } else if no_lines {
        "the drawing is empty: no lines were found"
    } else {
        "the drawing is empty: every line is hidden in this view; try another `view`"
    }
}
