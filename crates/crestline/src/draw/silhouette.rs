//! Smooth occluding contours (silhouettes): where the surface turns away from the
//! viewer, traced as the zero set of g = n · (eye − p) with interpolated vertex
//! normals (Hertzmann & Zorin 2000), chained into polylines.

use rayon::prelude::*;

use crate::lines::{FeatureLines, LineKind, Polyline};
use crate::mesh::{EdgeId, Mesh};
use crate::ridges::chain::chain;
use crate::ridges::trace::LinePoint;
use crate::Point;

use super::camera::Camera;

/// The silhouettes of `mesh` seen by `camera`, as [`LineKind::Silhouette`] lines
/// lying on the mesh edges. Per vertex g = n_v · (eye − p_v) (n_v the angle-weighted
/// vertex normal; the eye direction in orthographic projection); the contour crosses
/// every edge whose ends differ in sign, at the linear zero, and joins the two
/// crossings of each triangle. Lines shorter than `min_length` mean edge lengths are
/// dropped; a line's strength is its length in mean edge lengths.
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
    let crossing = |e: EdgeId| -> Option<f64> {
        let [a, b] = mesh.edge_vertices(e).map(|v| facing[v.idx()]);
        ((a >= 0.0) != (b >= 0.0)).then(|| a / (a - b))
    };
    let segments: Vec<[LinePoint; 2]> = mesh
        .par_faces()
        .filter_map(|f| {
            let crossed: Vec<EdgeId> = mesh
                .face_halfedges(f)
                .iter()
                .map(|&h| mesh.edge(h))
                .filter(|&e| crossing(e).is_some())
                .collect();
            match crossed[..] {
                [first, second] => Some([LinePoint::Edge(first), LinePoint::Edge(second)]),
                _ => None,
            }
        })
        .collect();
    let h = mesh.mean_edge_length();
    let locate = |point: LinePoint| -> (Point, f64) {
        let position = match point {
            LinePoint::Edge(e) => {
                let [a, b] = mesh.edge_vertices(e).map(|v| mesh.position(v));
                a + (b - a) * crossing(e).unwrap_or(0.0)
            }
            LinePoint::Face(f) => {
                let [a, b, c] = mesh.face_points(f);
                Point::from((a.coords + b.coords + c.coords) / 3.0)
            }
        };
        (position, 1.0 / h)
    };
    let mut lines = FeatureLines::new(String::new());
    for piece in chain(&segments, locate, min_length) {
        let points: Vec<Point> = piece.points.iter().map(|&p| locate(p).0).collect();
        if points.len() >= if piece.closed { 3 } else { 2 } {
            lines.push(Polyline::new(
                LineKind::Silhouette,
                piece.closed,
                piece.strength,
                points,
            ));
        }
    }
    lines
}
