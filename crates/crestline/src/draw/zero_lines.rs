//! Polylines from the traced segments of a zero set on a mesh.

use crate::lines::chain::chain;
use crate::lines::zero_set::{LinePoint, ZeroSet};
use crate::lines::{FeatureLines, LineKind, Polyline};
use crate::mesh::Mesh;
use crate::Point;

/// The `segments` of `zero_set` chained into lines of `kind`
/// ([`chain`]), each point located on its edge. Lines shorter than `min_length`
/// mean edge lengths are dropped; a line's strength is its length in mean edge
/// lengths.
pub(super) fn zero_set_lines(
    mesh: &Mesh,
    zero_set: &ZeroSet<'_>,
    segments: &[[LinePoint; 2]],
    kind: LineKind,
    min_length: f64,
) -> FeatureLines {
    let h = mesh.mean_edge_length();
    let locate = |point: LinePoint| (zero_set.location(mesh, point).position(mesh), 1.0 / h);
    let mut lines = FeatureLines::new(String::new());
    for piece in chain(segments, locate, min_length) {
        let locations: Vec<_> = piece
            .points
            .iter()
            .map(|&p| zero_set.location(mesh, p))
            .collect();
        let points: Vec<Point> = locations.iter().map(|at| at.position(mesh)).collect();
        if points.len() >= if piece.closed { 3 } else { 2 } {
            lines.push(
                Polyline::new(kind, piece.closed, piece.strength, points).with_locations(locations),
            );
        }
    }
    lines
}
