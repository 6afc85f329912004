//! The drawing as an SVG document made for Inkscape and pen plotters as well as
//! browsers:
//!
//! - one `<g>` per kind of line, an Inkscape layer (`inkscape:groupmode="layer"`)
//!   labelled with its plotting order and [`LineKind::family`](crate::lines::LineKind::family) (`1 silhouettes`,
//!   `2 ridges`), its `id` the name: Inkscape and the AxiDraw extension plot layers
//!   in the order of that leading number, and vpype numbers its layers by it;
//! - one `<path>` per visible piece, coordinates in canvas pixels with two
//!   decimals;
//! - the background is not a shape, which a plotter would draw as a frame: it is
//!   the root's CSS `background-color` (browsers) and the page colour of
//!   Inkscape's `sodipodi:namedview`;
//! - without a page, the size is the canvas in pixels; on a [`Page`], the physical
//!   size of the paper (`width="210mm"`) and a `viewBox` that maps the canvas's
//!   pixels to millimetres ([`PIXELS_PER_MM`]), the canvas offset by the margin.

use std::fmt::Write as _;

use crate::xml::escape;

use super::page::{Page, PIXELS_PER_MM};
use super::style::{KindStyle, Style};
use super::{Drawing, Group, ScreenPath};

/// The smallest and largest factor [`KindStyle::width_by_strength`] applies.
const WIDTH_FACTORS: (f64, f64) = (0.5, 2.0);

/// [`Drawing::svg`].
pub(crate) fn svg_document(drawing: &Drawing, style: &Style) -> String {
    let mut svg = String::new();
    svg.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let background = style
        .background
        .as_ref()
        .map(|color| format!(" style=\"background-color:{color}\""))
        .unwrap_or_default();
    let _ = writeln!(
        svg,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:inkscape=\"{INKSCAPE}\" xmlns:sodipodi=\"{SODIPODI}\" version=\"1.1\" {}{background}>",
        size_and_view_box(drawing)
    );
    let _ = writeln!(svg, "<title>{}</title>", escape(&drawing.source));
    if let Some(color) = &style.background {
        let _ = writeln!(
            svg,
            "<sodipodi:namedview pagecolor=\"{color}\" inkscape:pageopacity=\"1\" inkscape:document-units=\"{}\"/>",
            if drawing.page.is_some() { "mm" } else { "px" }
        );
    }
    let depths = depth_range(drawing);
    for (order, group) in drawing.groups.iter().enumerate() {
        write_group(&mut svg, order + 1, group, style.kind(group.kind), depths);
    }
    svg.push_str("</svg>\n");
    svg
}

/// The Inkscape namespace, of its layers.
const INKSCAPE: &str = "http://www.inkscape.org/namespaces/inkscape";

/// The Sodipodi namespace, of Inkscape's document settings.
const SODIPODI: &str = "http://sodipodi.sourceforge.net/DTD/sodipodi-0.dtd";

/// The `width`, `height` and `viewBox` attributes: the canvas in pixels, or the
/// drawing's page in millimetres with the canvas inside its margin.
fn size_and_view_box(drawing: &Drawing) -> String {
    let (width, height) = (drawing.width, drawing.height);
    match &drawing.page {
        None => format!("width=\"{width}\" height=\"{height}\" viewBox=\"0 0 {width} {height}\""),
        Some(page) => {
            let [w, h] = page.paper.size_mm;
            let margin = Page::pixels(page.margin.0);
            format!(
                "width=\"{w}mm\" height=\"{h}mm\" viewBox=\"{x} {x} {vw} {vh}\"",
                x = -margin,
                vw = w * PIXELS_PER_MM,
                vh = h * PIXELS_PER_MM
            )
        }
    }
}

/// One `<g>`, the Inkscape layer `order` (from 1, the plotting order), with the
/// stroke of its kind and a `<path>` per piece; a piece whose width or opacity
/// varies along it (by depth, tapered, faded by view) is written as short paths of
/// constant width and opacity ([`write_varying`]). `depths` is the drawing's depth
/// range.
fn write_group(
    svg: &mut String,
    order: usize,
    group: &Group,
    stroke: &KindStyle,
    depths: (f64, f64),
) {
    let name = group.kind.family();
    let _ = writeln!(
        svg,
        "<g id=\"{name}\" inkscape:groupmode=\"layer\" inkscape:label=\"{order} {name}\" fill=\"none\" stroke=\"{}\" stroke-width=\"{}\" stroke-linecap=\"round\" stroke-linejoin=\"round\">",
        stroke.color,
        stroke.width
    );
    let median = median_strength(&group.paths);
    for path in &group.paths {
        let mut width = stroke.width;
        if stroke.width_by_strength && median > 0.0 {
            width *= (path.strength / median).clamp(WIDTH_FACTORS.0, WIDTH_FACTORS.1);
        }
        let profile = Profile {
            depths: (stroke.width_by_depth && path.depths.len() == path.points.len())
                .then_some(depths),
            taper: if path.closed { 0.0 } else { stroke.taper },
            fade: stroke.fade_by_view && path.facings.len() == path.points.len(),
        };
        if profile.varies() {
            write_varying(svg, path, width, &profile.along(path));
            continue;
        }
        svg.push_str("<path d=\"");
        path_data(svg, &path.points, path.closed);
        svg.push('"');
        if width != stroke.width {
            let _ = write!(svg, " stroke-width=\"{width:.2}\"");
        }
        svg.push_str("/>\n");
    }
    svg.push_str("</g>\n");
}

/// The smallest share of the width a line keeps at its farthest point (by depth)
/// and at its very ends (tapered).
const THINNEST: (f64, f64) = (0.5, 0.15);

/// Faded by view, a line is fully opaque where n · v is at least this, and fades
/// linearly to nothing where the surface is seen edge-on (n · v = 0).
const FADE_FACING: f64 = 0.5;

/// How the width and opacity of a path vary along it.
struct Profile {
    /// The drawing's depth range, if the width follows depth.
    depths: Option<(f64, f64)>,
    /// The taper length in pixels (0 for none).
    taper: f64,
    /// Whether the opacity follows n · v.
    fade: bool,
}

impl Profile {
    fn varies(&self) -> bool {
        self.depths.is_some() || self.taper > 0.0 || self.fade
    }

    /// (width factor, opacity) at every point of `path`: the width from 1 at the
    /// nearest depth of the drawing to [`THINNEST`]`.0` at the farthest, times a
    /// ramp from [`THINNEST`]`.1` at each end up to 1 at `taper` pixels from it;
    /// the opacity n · v / [`FADE_FACING`], clamped to [0, 1].
    fn along(&self, path: &ScreenPath) -> Vec<(f64, f64)> {
        let mut along = Vec::with_capacity(path.points.len());
        let mut length = 0.0;
        for (i, p) in path.points.iter().enumerate() {
            if i > 0 {
                let q = path.points[i - 1];
                length += (p[0] - q[0]).hypot(p[1] - q[1]);
            }
            along.push(length);
        }
        along
            .iter()
            .enumerate()
            .map(|(i, &s)| {
                let by_depth = self.depths.map_or(1.0, |(near, far)| {
                    let t = if far > near {
                        (path.depths[i] - near) / (far - near)
                    } else {
                        0.0
                    };
                    1.0 - (1.0 - THINNEST.0) * t.clamp(0.0, 1.0)
                });
                let by_taper = if self.taper > 0.0 {
                    let ramp = (s.min(length - s) / self.taper).clamp(0.0, 1.0);
                    THINNEST.1 + (1.0 - THINNEST.1) * ramp
                } else {
                    1.0
                };
                let opacity = if self.fade {
                    (path.facings[i] / FADE_FACING).clamp(0.0, 1.0)
                } else {
                    1.0
                };
                (by_depth * by_taper, opacity)
            })
            .collect()
    }
}

/// Steps of the width (as a share of it) and of the opacity a varying path is
/// split at.
const STEP: f64 = 0.1;

/// `path` as consecutive `<path>`s over which the width (`width` times the
/// point's factor) and the opacity, each rounded to a [`STEP`], are constant;
/// they share their end points, and round caps join them. Invisible runs are
/// left out.
fn write_varying(svg: &mut String, path: &ScreenPath, width: f64, profile: &[(f64, f64)]) {
    let mut points = path.points.clone();
    let mut profile = profile.to_vec();
    if path.closed {
        points.extend(points.first().copied());
        profile.extend(profile.first().copied());
    }
    let level = |i: usize| {
        let (w, o) = profile[i];
        ((w / STEP).round().max(1.0), (o / STEP).round())
    };
    let mut start = 0;
    for end in 1..points.len() {
        let last = end + 1 == points.len();
        if last || level(end) != level(start) {
            let (w, o) = level(start);
            if o > 0.0 {
                svg.push_str("<path d=\"");
                path_data(svg, &points[start..=end], false);
                let _ = write!(svg, "\" stroke-width=\"{:.2}\"", width * w * STEP);
                if o < 1.0 / STEP {
                    let _ = write!(svg, " stroke-opacity=\"{:.1}\"", o * STEP);
                }
                svg.push_str("/>\n");
            }
            start = end;
        }
    }
}

/// The nearest and farthest depth of any point of `drawing` ((0, 0) without
/// depths).
fn depth_range(drawing: &Drawing) -> (f64, f64) {
    let depths = drawing
        .groups
        .iter()
        .flat_map(|g| &g.paths)
        .flat_map(|p| &p.depths)
        .copied()
        .filter(|d| d.is_finite());
    depths
        .fold(None, |range: Option<(f64, f64)>, d| {
            Some(range.map_or((d, d), |(near, far)| (near.min(d), far.max(d))))
        })
        .unwrap_or((0.0, 0.0))
}

/// `M x y L x y ... [Z]` with two decimals.
fn path_data(svg: &mut String, points: &[[f64; 2]], closed: bool) {
    for (i, [x, y]) in points.iter().enumerate() {
        let command = if i == 0 { 'M' } else { 'L' };
        let _ = write!(svg, "{command}{x:.2} {y:.2}");
    }
    if closed {
        svg.push('Z');
    }
}

/// The median strength of the paths (0 without paths or strengths).
fn median_strength(paths: &[ScreenPath]) -> f64 {
    let mut strengths: Vec<f64> = paths.iter().map(|p| p.strength).collect();
    strengths.sort_by(f64::total_cmp);
    strengths.get(strengths.len() / 2).copied().unwrap_or(0.0)
}

impl Drawing {
    /// The SVG text of `drawing` in `style`.
    pub fn svg(&self, style: &Style) -> String {
        svg_document(self, style)
    }
}
