//! Feature lines: the output of every extractor, and the writers that save them.
//!
//! A [`FeatureLines`] value is a list of [`Polyline`]s, each tagged with a
//! [`LineKind`], a closed flag and a strength. [`FeatureLines::write`] saves it in the format
//! given by the file extension ([`LineFormat::from_path`]):
//!
//! | extension | format | writer |
//! |---|---|---|
//! | `.json` | `crestline-lines/1` JSON, read back by [`FeatureLines::read_json`] | `write_json` |
//! | `.obj` | Wavefront OBJ, `v` and `l` records | `write_obj` |
//! | `.ply` | binary little-endian PLY, `vertex` and `edge` elements | `write_ply` |
//! | `.vtk` | legacy ASCII VTK `POLYDATA` (ParaView, VisIt) | `write_vtk` |
//! | `.vtp` | VTK XML poly data, a polyline per line (ParaView, 3D Slicer) | `write_vtp` |
//! | `.vtu` | VTK XML unstructured grid of segments (meshio, ParaView, 3D Slicer) | `write_vtu` |
//! | `.mrk.json` | 3D Slicer markups, a curve per line | `write_markups` |
//!
//! Ridge and valley lines traced on a mesh can also be written as labels of its
//! vertices (`write_vertex_labels`: GIfTI `.label.gii`, FreeSurfer `.label`),
//! which needs the mesh besides the lines.
//!
//! Every format that can says the frame of the points ([`FeatureLines::space`]):
//! the JSON's `space` key, 3D Slicer's `SPACE=` mark in the VTK title and in PLY
//! and OBJ comments, LPS positions in markups.
//! Every writer first checks the lines ([`FeatureLines::validate`]), so a NaN or an
//! infinite value is an error before any file is created, then writes under a
//! temporary name and renames on success
//! ([`write_atomically`]).

pub(crate) use crate::chain;
mod border;
pub(crate) mod direction_field;
mod extractor;
pub(crate) mod fair;
mod indexing;
mod json;
mod location;
pub(crate) mod markups;
mod obj;
mod on_surface;
pub(crate) mod oriented;
mod pipeline;
mod ply;
pub(crate) mod surface_fair;
#[cfg(test)]
mod test_meshes;
mod vertex_labels;
mod vtk;
mod vtk_xml;
pub(crate) mod zero_set;

use std::collections::BTreeMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::atomic::write_atomically;
use crate::io::{choose_format, FileFormat, FormatChoice};
use crate::{Error, Point, Result, Space};

pub use crate::chain::{chain, Chain};
pub(crate) use border::{write_border, BorderSurface};
pub(crate) use direction_field::{DirectionField, EdgeSigns};
pub use extractor::{LineExtractor, SurfaceWithCurvature, SurfaceWithValues};
pub(crate) use json::read_json;
pub(crate) use json::{write_json, FORMAT};
pub use location::SurfaceLocation;
pub(crate) use markups::write_markups;
pub(crate) use obj::write_obj;
pub use on_surface::{write_on_surface, SURFACE_FORMATS};
pub use pipeline::{LineExporter, LineFilter, MinLength, MinStrength};
pub(crate) use ply::write_ply;
#[cfg(test)]
pub(crate) use vertex_labels::write_labels;
pub use vertex_labels::write_point_labels;
pub(crate) use vertex_labels::write_vertex_labels;
pub(crate) use vertex_labels::LABEL_FORMATS;
pub(crate) use vtk::write_vtk;
pub(crate) use vtk_xml::{write_vtp, write_vtu};
pub use zero_set::{LinePoint, ZeroSet};

/// What a feature line is. Serialized in lowercase (`"ridge"`, `"valley"`, ...).
///
/// The integer [`code`](LineKind::code) of each kind is what the PLY and VTK writers
/// store per edge or cell; the order of the variants below is the order of the codes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LineKind {
    /// Code 0: a convex crest, where `k_max` is maximal along its principal direction.
    Ridge,
    /// Code 1: a concave crest, where `k_min` is minimal along its principal direction.
    Valley,
    /// Code 2: an ascending 1-cell of a Morse-Smale complex (saddle to maximum).
    Ascending,
    /// Code 3: a descending 1-cell of a Morse-Smale complex (saddle to minimum).
    Descending,
    /// Code 4: a crest line of an isosurface in a 3D image (marching lines), ridge or
    /// valley not distinguished.
    Crest,
    /// Code 5: a parabolic line, where the Gaussian curvature is zero.
    Parabolic,
    /// Code 6: a silhouette seen from a camera, where the surface turns away.
    Silhouette,
    /// Code 7: a contour or iso-line of a scalar field.
    Contour,
    /// Code 8: a border, a boundary loop of an open surface.
    Border,
    /// Code 9: a crease, a chain of edges where the surface folds sharply.
    Crease,
    /// Code 10: a suggestive contour seen from a camera, where the radial curvature
    /// is zero and increasing towards the viewer (DeCarlo et al. 2003).
    Suggestive,
    /// Code 11: an iso-Gaussian curve of an isosurface, where its Gaussian curvature
    /// has a given nonzero value (Thirion & Gourdon 1993).
    Gauss,
}

impl LineKind {
    /// Every kind, in the order of their codes.
    pub const ALL: [LineKind; 12] = [
        LineKind::Ridge,
        LineKind::Valley,
        LineKind::Ascending,
        LineKind::Descending,
        LineKind::Crest,
        LineKind::Parabolic,
        LineKind::Silhouette,
        LineKind::Contour,
        LineKind::Border,
        LineKind::Crease,
        LineKind::Suggestive,
        LineKind::Gauss,
    ];

    /// The lowercase name, as written in JSON and in file comments.
    pub fn name(self) -> &'static str {
        match self {
            LineKind::Ridge => "ridge",
            LineKind::Valley => "valley",
            LineKind::Ascending => "ascending",
            LineKind::Descending => "descending",
            LineKind::Crest => "crest",
            LineKind::Parabolic => "parabolic",
            LineKind::Silhouette => "silhouette",
            LineKind::Contour => "contour",
            LineKind::Border => "border",
            LineKind::Crease => "crease",
            LineKind::Suggestive => "suggestive",
            LineKind::Gauss => "gauss",
        }
    }

    /// The name of the family of lines of this kind, plural where it reads so:
    /// `ridges`, `valleys`, `silhouettes`, `borders`, `creases`, and for the other
    /// kinds their [`LineKind::name`]. Drawings name their layers by it, views
    /// their toggles, label and border files their classes.
    pub fn family(self) -> &'static str {
        match self {
            LineKind::Ridge => "ridges",
            LineKind::Valley => "valleys",
            LineKind::Silhouette => "silhouettes",
            LineKind::Border => "borders",
            LineKind::Crease => "creases",
            other => other.name(),
        }
    }

    /// The colour of the family, as red, green and blue: ridges red, valleys blue,
    /// ascending Morse-Smale lines orange, descending ones teal, crest lines
    /// purple, parabolic lines green, silhouettes dark grey, borders a little
    /// lighter, creases dark brown, suggestive contours mid grey, iso-Gaussian
    /// curves ochre. Drawings, views, label and border files use it.
    pub fn color(self) -> [u8; 3] {
        match self {
            LineKind::Ridge => [0xc0, 0x39, 0x2b],
            LineKind::Valley => [0x24, 0x71, 0xa3],
            LineKind::Ascending => [0xd3, 0x54, 0x00],
            LineKind::Descending => [0x13, 0x8d, 0x75],
            LineKind::Crest => [0x7d, 0x3c, 0x98],
            LineKind::Parabolic => [0x1e, 0x84, 0x49],
            LineKind::Silhouette => [0x33, 0x33, 0x33],
            LineKind::Contour => [0x55, 0x55, 0x55],
            LineKind::Border => [0x47, 0x47, 0x47],
            LineKind::Crease => [0x5d, 0x40, 0x30],
            LineKind::Suggestive => [0x8c, 0x8c, 0x8c],
            LineKind::Gauss => [0xb9, 0x77, 0x0e],
        }
    }

    /// [`LineKind::color`] as CSS writes it, `#rrggbb`.
    pub fn color_hex(self) -> String {
        let [r, g, b] = self.color();
        format!("#{r:02x}{g:02x}{b:02x}")
    }

    /// [`LineKind::color`] with each channel in [0, 1], as GIfTI label tables and
    /// Workbench border files write colours.
    pub fn color_unit(self) -> [f64; 3] {
        self.color().map(|c| f64::from(c) / 255.0)
    }

    /// The integer code stored by the PLY and VTK writers (0 = ridge, 1 = valley, ...,
    /// in the order of [`LineKind::ALL`]).
    pub fn code(self) -> u8 {
        self as u8
    }

    /// The table of codes, `0 ridge, 1 valley, ...`, written into file headers.
    fn code_table() -> String {
        let entries: Vec<String> = Self::ALL
            .iter()
            .map(|kind| format!("{} {}", kind.code(), kind.name()))
            .collect();
        entries.join(", ")
    }
}

impl std::fmt::Display for LineKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// One feature line: a sequence of points with a kind, a closed flag and a strength,
/// and optionally where each point lies on the surface and named values per point.
///
/// A closed polyline does **not** repeat its first point at the end: the segment from
/// the last point back to the first is implied by `closed`. Writers need at least two
/// points on an open line and three on a closed one (see [`FeatureLines::validate`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Polyline {
    /// What the line is.
    pub kind: LineKind,
    /// Whether the line is a loop (last point connected back to the first).
    pub closed: bool,
    /// How pronounced the line is; its meaning depends on the extractor (for ridges
    /// and valleys, the integral of the curvature along the line, dimensionless).
    pub strength: f64,
    /// The points in order, without a repeated first point for closed lines.
    #[serde(with = "json::point_arrays")]
    pub points: Vec<Point>,
    /// Where each point lies on the surface it was traced on (one per point), or
    /// empty when unknown.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub locations: Vec<SurfaceLocation>,
    /// Named per-point values (e.g. `"k_max"`), each with one value per point. Names
    /// are ASCII letters, digits and underscores.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub values: BTreeMap<String, Vec<f64>>,
}

/// The segments of the line through `points` in order, including the closing
/// segment (last point to first) when it is `closed` and has more than one point.
pub(crate) fn segments(
    points: &[Point],
    closed: bool,
) -> impl Iterator<Item = (&Point, &Point)> + '_ {
    let closing = match (closed, points.first(), points.last()) {
        (true, Some(first), Some(last)) if points.len() > 1 => Some((last, first)),
        _ => None,
    };
    points
        .windows(2)
        .map(|pair| (&pair[0], &pair[1]))
        .chain(closing)
}

impl Polyline {
    /// A polyline from its parts.
    pub fn new(kind: LineKind, closed: bool, strength: f64, points: Vec<Point>) -> Polyline {
        Polyline {
            kind,
            closed,
            strength,
            points,
            locations: Vec::new(),
            values: BTreeMap::new(),
        }
    }

    /// The line with the surface location of each point.
    pub fn with_locations(mut self, locations: Vec<SurfaceLocation>) -> Polyline {
        self.locations = locations;
        self
    }

    /// The line with one more named per-point value.
    pub fn with_values(mut self, name: &str, values: Vec<f64>) -> Polyline {
        self.values.insert(name.to_string(), values);
        self
    }

    /// The segments in order, including the closing segment (last point to first)
    /// when the line is closed and has more than one point.
    pub fn segments(&self) -> impl Iterator<Item = (&Point, &Point)> + '_ {
        segments(&self.points, self.closed)
    }

    /// The length of the line, including the closing segment if it is closed.
    pub fn length(&self) -> f64 {
        self.segments().map(|(a, b)| (b - a).norm()).sum()
    }

    /// Why the locations or named values of the line cannot be written, if they
    /// cannot: a length other than the number of points, a bad name, or a value for
    /// which `fits` is false.
    fn per_point_problem(&self, fits: &impl Fn(f64) -> bool, what: &str) -> Option<String> {
        let n = self.points.len();
        if !self.locations.is_empty() && self.locations.len() != n {
            return Some(format!("{} locations for {n} points", self.locations.len()));
        }
        self.values.iter().find_map(|(name, values)| {
            if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
                return Some(format!(
                    "value name {name:?} is not letters, digits and '_'"
                ));
            }
            if values.len() != n {
                return Some(format!("{} values of {name} for {n} points", values.len()));
            }
            let (p, v) = values.iter().enumerate().find(|(_, &v)| !fits(v))?;
            Some(format!("point {p} has {name} {v}, which is {what}"))
        })
    }

    /// The fewest points a writable line needs: three if closed, two if open.
    fn min_points(&self) -> usize {
        if self.closed {
            3
        } else {
            2
        }
    }
}

/// The feature lines found on one input, with the name of that input.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FeatureLines {
    /// Where the lines come from (usually the input file name); written into every
    /// output file.
    pub source: String,
    /// The lines, in the order extractors produced them.
    pub lines: Vec<Polyline>,
    /// The anatomical frame of the points, if the input had one (the image's, or
    /// the frame a mesh file declared); written into every output that can say it.
    pub space: Option<Space>,
}

impl FeatureLines {
    /// An empty set of lines found on `source`.
    pub fn new(source: impl Into<String>) -> FeatureLines {
        FeatureLines {
            source: source.into(),
            lines: Vec::new(),
            space: None,
        }
    }

    /// The lines with their points in `space`: converted from their own frame, or
    /// taken to be in it when they have none.
    pub fn in_space(&self, space: Space) -> FeatureLines {
        let mut moved = self.clone();
        let points = moved
            .lines
            .iter_mut()
            .flat_map(|line| line.points.iter_mut());
        crate::space::convert_all(self.space, space, points);
        moved.space = Some(space);
        moved
    }

    /// Append a line.
    pub fn push(&mut self, line: Polyline) {
        self.lines.push(line);
    }

    /// Number of lines.
    pub fn len(&self) -> usize {
        self.lines.len()
    }

    /// Whether there are no lines.
    pub fn is_empty(&self) -> bool {
        self.lines.is_empty()
    }

    /// The lines in order.
    pub fn iter(&self) -> std::slice::Iter<'_, Polyline> {
        self.lines.iter()
    }

    /// The lines of one kind, in order.
    pub fn of_kind(&self, kind: LineKind) -> impl Iterator<Item = &Polyline> + '_ {
        self.lines.iter().filter(move |line| line.kind == kind)
    }

    /// Keep only the lines for which `keep` returns true (e.g.
    /// `lines.retain(|l| l.kind == LineKind::Ridge)`), preserving their order.
    pub fn retain<F: FnMut(&Polyline) -> bool>(&mut self, keep: F) {
        self.lines.retain(keep);
    }

    /// The summed length of all lines (closing segments included).
    pub fn total_length(&self) -> f64 {
        self.lines.iter().map(Polyline::length).sum()
    }

    /// How many lines there are of each kind present (kinds with no line are absent).
    pub fn count_by_kind(&self) -> BTreeMap<LineKind, usize> {
        let mut counts = BTreeMap::new();
        for line in &self.lines {
            *counts.entry(line.kind).or_insert(0) += 1;
        }
        counts
    }

    /// Total number of points over all lines.
    pub fn point_count(&self) -> usize {
        self.lines.iter().map(|line| line.points.len()).sum()
    }

    /// Check that the lines can be written: every coordinate and strength finite, at
    /// least two points on every open line and three on every closed one. The error
    /// ([`Error::Argument`]) names the first offending line by its index.
    pub fn validate(&self) -> Result<()> {
        self.problem()
            .map_or(Ok(()), |message| Err(Error::Argument(message)))
    }

    /// Why [`validate`](Self::validate) fails, if it does.
    fn problem(&self) -> Option<String> {
        self.first_problem(f64::is_finite, "not finite")
    }

    /// The first reason the lines cannot be written, if any: a value for which `fits`
    /// is false (described as `what`), or a line with too few points.
    fn first_problem(&self, fits: impl Fn(f64) -> bool, what: &str) -> Option<String> {
        self.lines.iter().enumerate().find_map(|(index, line)| {
            if !fits(line.strength) {
                return Some(format!(
                    "line {index}: strength {} is {what}",
                    line.strength
                ));
            }
            if line.points.len() < line.min_points() {
                let closure = if line.closed { "closed" } else { "open" };
                return Some(format!(
                    "line {index}: {closure} lines need at least {} points, this one has {}",
                    line.min_points(),
                    line.points.len()
                ));
            }
            let coordinate = line.points.iter().enumerate().find_map(|(p, point)| {
                point
                    .iter()
                    .find(|&&v| !fits(v))
                    .map(|v| format!("line {index}: point {p} has coordinate {v}, which is {what}"))
            });
            coordinate.or_else(|| {
                line.per_point_problem(&fits, what)
                    .map(|m| format!("line {index}: {m}"))
            })
        })
    }
}

impl<'a> IntoIterator for &'a FeatureLines {
    type Item = &'a Polyline;
    type IntoIter = std::slice::Iter<'a, Polyline>;

    fn into_iter(self) -> Self::IntoIter {
        self.lines.iter()
    }
}

/// A file format for feature lines.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LineFormat {
    /// `crestline-lines/1` JSON (`write_json`, [`FeatureLines::read_json`]).
    Json,
    /// Wavefront OBJ with `l` records (`write_obj`).
    Obj,
    /// Binary little-endian PLY with vertices and edges (`write_ply`).
    Ply,
    /// Legacy ASCII VTK `POLYDATA` (`write_vtk`).
    Vtk,
    /// VTK XML poly data (`write_vtp`).
    Vtp,
    /// VTK XML unstructured grid of segments (`write_vtu`).
    Vtu,
    /// 3D Slicer markups, a curve per line (`write_markups`).
    Markups,
}

impl LineFormat {
    /// Every format, in the order listed in error messages.
    pub const ALL: [LineFormat; 7] = [
        LineFormat::Json,
        LineFormat::Obj,
        LineFormat::Ply,
        LineFormat::Vtk,
        LineFormat::Vtp,
        LineFormat::Vtu,
        LineFormat::Markups,
    ];

    /// The file extension of the format, lowercase and without the dot.
    pub fn extension(self) -> &'static str {
        self.file_format().extension()
    }

    /// The format given by the extension of `path` (case-insensitive,
    /// [`choose_format`]). An unknown or missing extension is an [`Error::File`]
    /// listing the supported ones.
    pub fn from_path(path: &Path) -> Result<LineFormat> {
        choose_format(path, "feature lines", &Self::ALL)
    }

    /// Write `lines` to `path` in this format.
    pub fn write(self, path: &Path, lines: &FeatureLines) -> Result<()> {
        match self {
            LineFormat::Json => write_json(path, lines),
            LineFormat::Obj => write_obj(path, lines),
            LineFormat::Ply => write_ply(path, lines),
            LineFormat::Vtk => write_vtk(path, lines),
            LineFormat::Vtp => write_vtp(path, lines),
            LineFormat::Vtu => write_vtu(path, lines),
            LineFormat::Markups => write_markups(path, lines),
        }
    }
}

impl FormatChoice for LineFormat {
    fn file_format(self) -> FileFormat {
        match self {
            LineFormat::Json => FileFormat::Json,
            LineFormat::Obj => FileFormat::Obj,
            LineFormat::Ply => FileFormat::Ply,
            LineFormat::Vtk => FileFormat::Vtk,
            LineFormat::Vtp => FileFormat::Vtp,
            LineFormat::Vtu => FileFormat::Vtu,
            LineFormat::Markups => FileFormat::SlicerMarkups,
        }
    }
}

/// [`FeatureLines::write`].
pub(crate) fn write_lines(path: &Path, lines: &FeatureLines) -> Result<()> {
    LineFormat::from_path(path)?.write(path, lines)
}

/// Check `lines` ([`FeatureLines::validate`]), then write `path` through `fill` under
/// a temporary name, renamed on success.
fn write_checked<F>(path: &Path, lines: &FeatureLines, fill: F) -> Result<()>
where
    F: FnOnce(&mut BufWriter<&mut File>) -> std::io::Result<()>,
{
    lines.validate()?;
    write_atomically(path, fill)
}

/// `text` on one line, for file headers and comments: line breaks and other control
/// characters become spaces.
fn one_line(text: &str) -> String {
    text.chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect()
}

impl FeatureLines {
    /// Write `lines` to `path` in the format given by its extension
    /// ([`LineFormat::from_path`]).
    pub fn write(&self, path: &Path) -> Result<()> {
        write_lines(path, self)
    }
}

#[cfg(test)]
mod tests;
