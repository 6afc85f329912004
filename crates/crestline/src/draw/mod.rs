//! Line drawings: feature lines and silhouettes of a mesh, with hidden lines
//! removed, as SVG (and a PNG preview).
//!
//! Drawing takes lines, not an extractor, so the output of any
//! [`LineExtractor`](crate::lines::LineExtractor) can be drawn. The steps, each a
//! function of its own:
//! 1. a `Camera` frames the mesh (`Camera::framing`: orthographic by default,
//!    an orbit direction or an explicit eye, target and up);
//! 2. optionally the `silhouettes` (smooth occluding contours), the `borders`
//!    of an open mesh, its `creases` and its `suggestive_contours` are traced
//!    on the mesh and drawn like any other line;
//! 3. a `DepthBuffer` of the mesh is rasterized (`DepthBuffer::render`);
//! 4. every line is resampled below a pixel, each sample tested against the buffer,
//!    and the visible runs kept and simplified (Douglas–Peucker)
//!    (`visible_drawing`);
//! 5. the [`Drawing`] is written as SVG in a [`Style`] ([`Drawing::svg`],
//!    `write_svg`) and optionally rendered to PNG (`write_png`, with the `png`
//!    feature).
//!
//! `draw` runs steps 2–4 with `DrawOptions` (`draw_observed` reporting
//! each), and [`crate::jobs::draw`] the whole of `crestline draw`.
//!
//! Depth tolerances are in mean edge lengths of the mesh, so a drawing does not
//! depend on the unit of the file.

mod camera;
mod depth;
mod duplicates;
mod edge_lines;
mod page;
mod plot;
#[cfg(feature = "png")]
mod raster;
mod silhouette;
mod simplify;
mod style;
mod suggestive;
mod svg;
mod visibility;
mod zero_lines;

use rayon::prelude::*;

#[cfg(test)]
use crate::curvature::ShapeOperator;
use crate::curvature::{estimate_curvature, CurvatureEstimator};
use crate::lines::{FeatureLines, LineKind};
use crate::mesh::Mesh;
#[cfg(test)]
use crate::progress::Silent;
use crate::progress::{try_stage, Observer};
use crate::{Error, Result};

pub(crate) use camera::{Camera, Projection, View};
pub(crate) use depth::DepthBuffer;
pub(crate) use duplicates::{clear_of_silhouettes, runs_along_outlines, SilhouetteIndex};
pub(crate) use edge_lines::{borders, creases};
pub use page::{Page, Paper, PaperLength};
pub(crate) use plot::for_plotter;
#[cfg(feature = "png")]
pub use raster::{render_png, write_png};
pub(crate) use silhouette::silhouettes;
pub(crate) use simplify::douglas_peucker_kept;
pub(crate) use style::check_taper;
pub use style::{KindStyle, Style};
pub(crate) use suggestive::{suggestive_contours, SuggestiveOptions};
pub(crate) use visibility::visible_pieces;

/// A visible piece of a line on the canvas.
#[derive(Clone, Debug, PartialEq)]
pub struct ScreenPath {
    /// Canvas points in pixels (x right, y down).
    pub points: Vec<[f64; 2]>,
    /// The depth of every point along the viewing direction (mesh units; larger
    /// is farther), for widths that vary with depth.
    pub depths: Vec<f64>,
    /// n · v at every point (the surface normal against the unit vector towards
    /// the viewer), for lines that fade where the surface turns away; empty if
    /// the line did not carry it (`with_facing`).
    pub facings: Vec<f64>,
    /// Whether the piece is a whole closed line.
    pub closed: bool,
    /// The strength of the line the piece comes from.
    pub strength: f64,
}

impl ScreenPath {
    /// Keep the points Douglas–Peucker keeps at `tolerance` pixels
    /// (`douglas_peucker_kept`), with their depths.
    pub fn simplify(&mut self, tolerance: f64) {
        let kept = douglas_peucker_kept(&self.points, self.closed, tolerance);
        retain_flagged(&mut self.points, &kept);
        retain_flagged(&mut self.depths, &kept);
        retain_flagged(&mut self.facings, &kept);
    }
}

/// Keep the values whose flag is set (values past the flags are kept).
fn retain_flagged<T>(values: &mut Vec<T>, flags: &[bool]) {
    let mut flags = flags.iter();
    values.retain(|_| *flags.next().unwrap_or(&true));
}

/// The visible pieces of the lines of one kind.
#[derive(Clone, Debug, PartialEq)]
pub struct Group {
    /// The kind of every line in the group.
    pub kind: LineKind,
    /// The visible pieces, in screen coordinates.
    pub paths: Vec<ScreenPath>,
}

/// A line drawing: a canvas and its groups of visible pieces, in drawing order
/// (silhouettes first, underneath the feature lines).
#[derive(Clone, Debug, PartialEq)]
pub struct Drawing {
    /// Where the lines come from (written as the SVG title).
    pub source: String,
    /// Canvas width in pixels.
    pub width: u32,
    /// Canvas height in pixels.
    pub height: u32,
    /// One group per kind of line, in drawing order.
    pub groups: Vec<Group>,
    /// The page the canvas is the printable area of, if any ([`Page`]).
    pub page: Option<Page>,
}

impl Drawing {
    /// The group of `kind`, if the drawing has one.
    pub fn group(&self, kind: LineKind) -> Option<&Group> {
        self.groups.iter().find(|g| g.kind == kind)
    }

    /// Number of paths of each group, by [`LineKind::family`].
    pub fn path_counts(&self) -> Vec<(&'static str, usize)> {
        self.groups
            .iter()
            .map(|g| (g.kind.family(), g.paths.len()))
            .collect()
    }
}

/// The per-point value of a line that holds n · v, the cosine between the surface
/// normal and the direction towards the viewer ([`with_facing`]).
pub(crate) const FACING: &str = "facing";

/// Gives every line of `lines` that keeps its surface locations the value
/// [`FACING`]: n · v at each point, with n the vertex normals interpolated at the
/// location and v the unit vector towards the viewer. Lines faded by view
/// ([`KindStyle::fade_by_view`]) need it.
pub(crate) fn with_facing(mesh: &Mesh, camera: &Camera, lines: &mut FeatureLines) {
    let normals = mesh.vertex_normals();
    lines.lines.par_iter_mut().for_each(|line| {
        if line.locations.len() != line.points.len() {
            return;
        }
        let facing = line
            .locations
            .iter()
            .map(|at| {
                let normal: crate::Vector = at
                    .weights(mesh)
                    .iter()
                    .map(|&(v, w)| normals[v.idx()] * w)
                    .sum();
                let toward = camera.toward_viewer(&at.position(mesh));
                normal.normalize().dot(&toward.normalize())
            })
            .collect();
        line.values.insert(FACING.to_string(), facing);
    });
}

/// The settings of [`draw`] and [`visible_drawing`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct DrawOptions {
    /// Trace and draw the silhouettes. Default: no.
    pub silhouettes: bool,
    /// Silhouette lines shorter than this many mean edge lengths are dropped.
    pub silhouette_min_length: f64,
    /// Draw the borders (boundary loops) of an open mesh.
    pub borders: bool,
    /// Draw the creases: edges whose dihedral angle exceeds this many degrees.
    pub crease_angle: Option<f64>,
    /// Trace and draw the suggestive contours with these settings.
    pub suggestive: Option<SuggestiveOptions>,
    /// How far behind the surface a feature line may lie and still be drawn, in
    /// mean edge lengths.
    pub depth_tolerance: f64,
    /// The same for silhouettes, which sit where the surface is seen edge-on.
    pub silhouette_depth_tolerance: f64,
    /// Depth-buffer pixels per canvas pixel along each axis.
    pub supersampling: u32,
    /// Largest distance between visibility samples along a line, in pixels.
    pub sample_spacing: f64,
    /// Douglas–Peucker tolerance of the drawn paths, in pixels.
    pub simplify_tolerance: f64,
    /// Feature lines (ridges, valleys, Morse cells, crests, creases) are not drawn where
    /// they run beside a visible silhouette (within [`PARALLEL_ANGLE`]) closer
    /// than this many pixels: the outline already shows that crest. 0 keeps them.
    pub silhouette_clearance: f64,
    /// For a pen plotter: every stroke drawn once ([`DUPLICATE_DISTANCE`]; the
    /// joining and ordering of the strokes is [`for_plotter`]'s, on the drawing).
    pub plot: bool,
}

impl Default for DrawOptions {
    fn default() -> Self {
        DrawOptions {
            silhouettes: false,
            silhouette_min_length: 3.0,
            borders: false,
            crease_angle: None,
            suggestive: None,
            depth_tolerance: 1.0,
            silhouette_depth_tolerance: 2.0,
            supersampling: 2,
            sample_spacing: 0.5,
            simplify_tolerance: 0.25,
            silhouette_clearance: 4.0,
            plot: false,
        }
    }
}

impl DrawOptions {
    /// Check that every setting is usable: finite, non-negative lengths and
    /// tolerances, a positive sample spacing and supersampling, a crease angle
    /// strictly between 0 and 180 degrees and usable suggestive contour settings.
    pub fn check(&self) -> Result<()> {
        if let Some(angle) = self.crease_angle {
            edge_lines::check_crease_angle(angle)?;
        }
        if let Some(suggestive) = &self.suggestive {
            suggestive.check()?;
        }
        let non_negative = [
            ("silhouette minimum length", self.silhouette_min_length),
            ("depth tolerance", self.depth_tolerance),
            (
                "silhouette depth tolerance",
                self.silhouette_depth_tolerance,
            ),
            ("simplification tolerance", self.simplify_tolerance),
            ("silhouette clearance", self.silhouette_clearance),
        ];
        for (name, value) in non_negative {
            if !(value.is_finite() && value >= 0.0) {
                return Err(Error::Argument(format!(
                    "{name} must be finite and not negative, got {value}"
                )));
            }
        }
        if !(self.sample_spacing.is_finite() && self.sample_spacing > 0.0) {
            return Err(Error::Argument(format!(
                "sample spacing must be finite and positive, got {}",
                self.sample_spacing
            )));
        }
        if self.supersampling == 0 {
            return Err(Error::Argument("supersampling must be at least 1".into()));
        }
        Ok(())
    }
}

/// Draw `lines` on `mesh` as seen by `camera`: the silhouettes, borders, creases
/// and suggestive contours (with curvature by the [`ShapeOperator`]) if asked
/// for, a depth buffer, and the visible pieces of every line.
#[cfg(test)]
pub(crate) fn draw(
    mesh: &Mesh,
    lines: &FeatureLines,
    camera: &Camera,
    options: &DrawOptions,
) -> Result<Drawing> {
    draw_observed(
        mesh,
        lines.clone(),
        camera,
        options,
        &ShapeOperator,
        &mut Silent,
    )
}

/// [`draw`] with the suggestive contours' curvature from `estimator`, telling
/// `observer` of the stages — each family traced (named after its SVG group, with
/// the count `<kind>_lines`) and `visibility` — and asking it between them
/// whether to go on.
pub(crate) fn draw_observed(
    mesh: &Mesh,
    mut lines: FeatureLines,
    camera: &Camera,
    options: &DrawOptions,
    estimator: &dyn CurvatureEstimator,
    observer: &mut dyn Observer,
) -> Result<Drawing> {
    options.check()?;
    let mut add = |kind: LineKind, trace: &dyn Fn() -> Result<FeatureLines>| -> Result<()> {
        let traced = try_stage(observer, kind.family(), trace)?;
        observer.count(&format!("{}_lines", kind.name()), traced.len());
        lines.lines.extend(traced.lines);
        Ok(())
    };
    if options.silhouettes {
        add(LineKind::Silhouette, &|| {
            Ok(silhouettes(mesh, camera, options.silhouette_min_length))
        })?;
    }
    if options.borders {
        add(LineKind::Border, &|| Ok(borders(mesh)))?;
    }
    if let Some(angle) = options.crease_angle {
        add(LineKind::Crease, &|| creases(mesh, angle))?;
    }
    if let Some(suggestive) = &options.suggestive {
        add(LineKind::Suggestive, &|| {
            let field = estimate_curvature(mesh, estimator)?;
            suggestive_contours(mesh, &field, camera, suggestive)
        })?;
    }
    try_stage(observer, "visibility", || {
        with_facing(mesh, camera, &mut lines);
        let buffer = DepthBuffer::render(mesh, camera, options.supersampling);
        visible_drawing(&lines, camera, &buffer, options)
    })
}

/// The visible, simplified pieces of `lines` against `buffer`: one group for
/// every kind among the lines (silhouettes first), even if nothing of it is seen.
pub(crate) fn visible_drawing(
    lines: &FeatureLines,
    camera: &Camera,
    buffer: &DepthBuffer,
    options: &DrawOptions,
) -> Result<Drawing> {
    options.check()?;
    lines.validate()?;
    let h = buffer.edge_length();
    let mut pieces: Vec<(LineKind, Vec<ScreenPath>)> = lines
        .lines
        .par_iter()
        .map(|line| {
            let tolerance = h * match line.kind {
                LineKind::Silhouette => options.silhouette_depth_tolerance,
                _ => options.depth_tolerance,
            };
            let pieces = visible_pieces(line, camera, buffer, tolerance, options.sample_spacing);
            (line.kind, pieces)
        })
        .collect();
    if options.silhouette_clearance > 0.0 {
        clear_feature_lines(&mut pieces, options.silhouette_clearance);
    }
    if options.plot {
        pieces.sort_by_key(|(kind, _)| plotting_rank(*kind));
        plot::without_duplicates(&mut pieces);
    }
    pieces.par_iter_mut().for_each(|(_, paths)| {
        for path in paths {
            path.simplify(options.simplify_tolerance);
        }
    });
    let mut kinds: Vec<LineKind> = lines.count_by_kind().into_keys().collect();
    kinds.sort_by_key(|&kind| plotting_rank(kind));
    let groups = kinds
        .into_iter()
        .map(|kind| Group {
            kind,
            paths: pieces
                .iter()
                .filter(|(k, _)| *k == kind)
                .flat_map(|(_, paths)| paths.iter().cloned())
                .collect(),
        })
        .collect();
    Ok(Drawing {
        source: lines.source.clone(),
        width: camera.width(),
        height: camera.height(),
        groups,
        page: None,
    })
}

/// The place of `kind` in the drawing (and plotting) order: silhouettes first,
/// underneath the feature lines, then the kinds in their order.
fn plotting_rank(kind: LineKind) -> (bool, LineKind) {
    (kind != LineKind::Silhouette, kind)
}

/// Drops the parts of the feature lines' visible `pieces` that run beside a
/// visible silhouette closer than `clearance` pixels ([`clear_of_silhouettes`]).
fn clear_feature_lines(pieces: &mut [(LineKind, Vec<ScreenPath>)], clearance: f64) {
    let silhouettes = pieces
        .iter()
        .filter(|(kind, _)| *kind == LineKind::Silhouette)
        .flat_map(|(_, paths)| paths);
    let index = SilhouetteIndex::new(silhouettes, clearance);
    pieces
        .par_iter_mut()
        .filter(|(kind, _)| runs_along_outlines(*kind))
        .for_each(|(_, paths)| {
            *paths = paths
                .iter()
                .flat_map(|path| clear_of_silhouettes(path, &index, clearance))
                .collect();
        });
}

#[cfg(test)]
mod tests;
