//! Smooth occluding contours (silhouettes): where the surface turns away from the
//! viewer, traced as the zero set of g = n · (eye − p) with interpolated vertex
//! normals (Hertzmann & Zorin 2000), chained into polylines.

use rayon::prelude::*;

use crate::lines::chain::chain;
use crate::lines::zero_set::{LinePoint, ZeroSet};
use crate::lines::{FeatureLines, LineKind, Polyline};
use crate::mesh::Mesh;
use crate::Point;

use super::camera::Camera;

/// The silhouettes of `mesh` seen by `camera`, as [`LineKind::Silhouette`] lines
/// lying on the mesh edges. Per vertex g = n_v · (eye − p_v) (n_v the angle-weighted
/// vertex normal; the eye direction in orthographic projection); the contour is the
/// zero set of g ([`ZeroSet`]: it crosses every edge whose ends differ in sign, at
/// the linear zero, and joins the two crossings of each triangle). Lines shorter
/// than `min_length` mean edge lengths are dropped; a line's strength is its length
/// in mean edge lengths.
///
/// The result says nothing about visibility: back-facing parts of the contour are
/// hidden later, with the feature lines.
pub fn silhouettes(mesh: &Mesh, camera: &Camera, min_length: f64) -> FeatureLines {
    let normals = mesh.vertex_normals();
    let facing: Vec<f64> = mesh
        .par_vertices()
        .map(|v| {
            let p = mesh.position(v);
            normals[v.idx()].dot(&camera.toward_viewer(&p))
        })
        .collect();
    let zero_set = ZeroSet::new(facing);
    let segments = zero_set.segments(mesh);
    let h = mesh.mean_edge_length();
    let locate = |point: LinePoint| (zero_set.location(mesh, point).position(mesh), 1.0 / h);
    let mut lines = FeatureLines::new(String::new());
    for piece in chain(&segments, locate, min_length) {
        let locations: Vec<_> = piece
            .points
            .iter()
            .map(|&p| zero_set.location(mesh, p))
            .collect();
        let points: Vec<Point> = locations.iter().map(|at| at.position(mesh)).collect();
        if points.len() >= if piece.closed { 3 } else { 2 } {
            lines.push(
                Polyline::new(LineKind::Silhouette, piece.closed, piece.strength, points)
                    .with_locations(locations),
            );
        }
    }
    lines
}
