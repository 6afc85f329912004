//! The 1-cells of the simplified complex as feature lines.

use rayon::prelude::*;

use crate::lines::surface_fair::fair_on_surface;
use crate::lines::{FeatureLines, LineKind, Polyline, SurfaceLocation};
use crate::mesh::{EdgeId, FaceId, Mesh, VertexId};
use crate::Point;

use super::cancel::Hierarchy;
use super::MorseSmale;

/// Which 1-cells to output.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Cells {
    /// Saddle-to-maximum lines: crests of the indicator.
    #[default]
    Ascending,
    /// Saddle-to-minimum lines: troughs of the indicator.
    Descending,
    /// Both.
    Both,
}

crate::named::named!(Cells, "cells", {
    Ascending => "ascending",
    Descending => "descending",
    Both => "both",
});

/// The live saddles' 1-cells, strongest first; each branch stops where it joins a
/// line already drawn (including that point), so shared tails appear once. The
/// strength of a line is its saddle's significance. Ascending lines pass through
/// triangle centroids and the midpoints of the edges between them, descending lines
/// through vertices; each point keeps its location on the surface (where the
/// fairing of [`MorseSmale::smooth`] moves it) and the indicator there
/// (`"indicator"`).
pub fn lines(
    mesh: &Mesh,
    values: &[f64],
    hierarchy: &Hierarchy<'_>,
    config: &MorseSmale,
) -> FeatureLines {
    let last_t = hierarchy
        .cancelled
        .last()
        .map_or(f64::NEG_INFINITY, |c| c.t);
    let mut shown: Vec<(usize, f64)> = (0..hierarchy.saddles.len())
        .filter(|&s| hierarchy.alive[s])
        .filter_map(|s| {
            let best = hierarchy.best(s).map(|(t, _)| t);
            let significance = best.unwrap_or_else(|| hierarchy.significance(s));
            let forced = best.is_none() && significance < last_t;
            (config.keep_forced || !forced).then_some((s, significance))
        })
        .collect();
    shown.sort_by(|a, b| b.1.total_cmp(&a.1));

    let fairing = CrestFairing::new(values, config.smooth, config.cells);
    let mut drawn_faces = vec![false; mesh.face_count()];
    let mut drawn_vertices = vec![false; mesh.vertex_count()];
    let mut cells = Vec::new();
    for (s, strength) in shown {
        let saddle = &hierarchy.saddles[s];
        let mut polylines = Vec::new();
        if config.cells != Cells::Descending {
            let points =
                ascending_points(mesh, hierarchy, saddle.faces, saddle.edge, &mut drawn_faces);
            polylines.push((LineKind::Ascending, points));
        }
        if config.cells != Cells::Ascending {
            let points = descending_points(mesh, hierarchy, saddle.vertices, &mut drawn_vertices);
            polylines.push((LineKind::Descending, points));
        }
        cells.extend(
            polylines
                .into_iter()
                .map(|(kind, locations)| (kind, strength, locations)),
        );
    }
    // The walks above mark what is drawn, in order; the fairing of each line is
    // independent.
    let mut lines = FeatureLines::new(String::new());
    lines.space = mesh.space();
    lines.lines = cells
        .into_par_iter()
        .map(|(kind, strength, locations)| {
            polyline(mesh, values, kind, strength, locations, &fairing)
        })
        .collect();
    lines
}

/// One output line through `locations`, faired on the surface ([`CrestFairing`]),
/// with the indicator at every point.
fn polyline(
    mesh: &Mesh,
    values: &[f64],
    kind: LineKind,
    strength: f64,
    mut locations: Vec<SurfaceLocation>,
    fairing: &CrestFairing,
) -> Polyline {
    fairing.fair(mesh, kind, &mut locations);
    let points: Vec<Point> = locations.iter().map(|at| at.position(mesh)).collect();
    let indicator = locations
        .iter()
        .map(|at| at.interpolate(mesh, values))
        .collect();
    Polyline::new(kind, false, strength, points)
        .with_values("indicator", indicator)
        .with_locations(locations)
}

/// The fairing of the output lines (§3.6), done on the surface so that the
/// lines keep their crest ([`fair_on_surface`]): a point of an ascending line
/// may move only where the indicator is at least the lower of its value at the
/// point and the indicator's upper quartile over the mesh (a descending line: at
/// most the higher of its value and the lower quartile). Lines on the crest stay
/// on it; lines below it do not sink.
struct CrestFairing<'a> {
    iterations: usize,
    /// The indicator and its upper quartile, for ascending lines.
    ascending: Option<(&'a [f64], f64)>,
    /// The negated indicator and its upper quartile, for descending lines.
    descending: Option<(Vec<f64>, f64)>,
}

impl<'a> CrestFairing<'a> {
    /// The fairing of the `cells` asked for; nothing is prepared without
    /// iterations.
    fn new(values: &'a [f64], iterations: usize, cells: Cells) -> CrestFairing<'a> {
        let faired = |side: Cells| iterations > 0 && cells != side;
        let ascending = faired(Cells::Descending).then(|| (values, upper_quartile(values)));
        let descending = faired(Cells::Ascending).then(|| {
            let negated: Vec<f64> = values.iter().map(|v| -v).collect();
            let quartile = upper_quartile(&negated);
            (negated, quartile)
        });
        CrestFairing {
            iterations,
            ascending,
            descending,
        }
    }

    fn fair(&self, mesh: &Mesh, kind: LineKind, locations: &mut [SurfaceLocation]) {
        let side = match kind {
            LineKind::Descending => self.descending.as_ref().map(|(f, q)| (f.as_slice(), *q)),
            _ => self.ascending,
        };
        let Some((field, quartile)) = side else {
            return;
        };
        let floors: Vec<f64> = locations
            .iter()
            .map(|at| at.interpolate(mesh, field).min(quartile))
            .collect();
        fair_on_surface(mesh, locations, false, self.iterations, field, |i| {
            floors[i]
        });
    }
}

/// The upper quartile of the finite `values` (−∞ without any).
fn upper_quartile(values: &[f64]) -> f64 {
    let mut finite: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    if finite.is_empty() {
        return f64::NEG_INFINITY;
    }
    let at = 3 * (finite.len() - 1) / 4;
    *finite.select_nth_unstable_by(at, f64::total_cmp).1
}

fn centroid(f: FaceId) -> SurfaceLocation {
    SurfaceLocation::Face {
        face: f.0,
        barycentric: [1.0 / 3.0; 3],
    }
}

fn midpoint(e: EdgeId) -> SurfaceLocation {
    SurfaceLocation::Edge { edge: e.0, t: 0.5 }
}

/// Follow the gradient from `start` with `step`, collecting `node_point` of every
/// node and `edge_point` of every edge crossed between nodes, and stop after the
/// first node already drawn (marking the nodes drawn on the way).
fn walk<N: Copy>(
    start: N,
    drawn: &mut [bool],
    index: impl Fn(N) -> usize,
    step: impl Fn(N) -> Option<(EdgeId, N)>,
    node_point: impl Fn(N) -> SurfaceLocation,
    edge_point: impl Fn(EdgeId) -> Option<SurfaceLocation>,
) -> Vec<SurfaceLocation> {
    let mut points = Vec::new();
    let mut current = start;
    loop {
        points.push(node_point(current));
        if std::mem::replace(&mut drawn[index(current)], true) {
            break;
        }
        let Some((e, next)) = step(current) else {
            break;
        };
        points.extend(edge_point(e));
        current = next;
    }
    points
}

/// Centroids and crossed-edge midpoints from `start` up to its maximum.
fn strip(
    mesh: &Mesh,
    hierarchy: &Hierarchy<'_>,
    start: FaceId,
    drawn: &mut [bool],
) -> Vec<SurfaceLocation> {
    walk(
        start,
        drawn,
        FaceId::idx,
        |f| hierarchy.gradient().face_step(mesh, f),
        centroid,
        |e| Some(midpoint(e)),
    )
}

/// The ascending line of a saddle: one strip reversed, the saddle edge's midpoint,
/// the other strip.
fn ascending_points(
    mesh: &Mesh,
    hierarchy: &Hierarchy<'_>,
    faces: [FaceId; 2],
    edge: EdgeId,
    drawn: &mut [bool],
) -> Vec<SurfaceLocation> {
    let [first, second] = faces.map(|f| {
        if f.is_valid() {
            strip(mesh, hierarchy, f, drawn)
        } else {
            Vec::new()
        }
    });
    let mut points: Vec<SurfaceLocation> = first.into_iter().rev().collect();
    points.push(midpoint(edge));
    points.extend(second);
    points
}

/// The vertex path from `start` down to its minimum.
fn path(
    mesh: &Mesh,
    hierarchy: &Hierarchy<'_>,
    start: VertexId,
    drawn: &mut [bool],
) -> Vec<SurfaceLocation> {
    walk(
        start,
        drawn,
        VertexId::idx,
        |v| hierarchy.gradient().vertex_step(mesh, v),
        |v| SurfaceLocation::Vertex { vertex: v.0 },
        |_| None,
    )
}

/// The descending line of a saddle: one path reversed, then the other.
fn descending_points(
    mesh: &Mesh,
    hierarchy: &Hierarchy<'_>,
    ends: [VertexId; 2],
    drawn: &mut [bool],
) -> Vec<SurfaceLocation> {
    let [first, second] = ends.map(|v| path(mesh, hierarchy, v, drawn));
    first.into_iter().rev().chain(second).collect()
}
