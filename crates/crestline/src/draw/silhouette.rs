//! Smooth occluding contours (silhouettes): where the surface turns away from the
//! viewer, traced as the zero set of g = n · (eye − p) with interpolated vertex
//! normals (Hertzmann & Zorin 2000), chained into polylines.

use rayon::prelude::*;

use crate::lines::zero_set::ZeroSet;
use crate::lines::{FeatureLines, LineKind};
use crate::mesh::Mesh;

use super::camera::Camera;
use super::zero_lines::zero_set_lines;

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
    zero_set_lines(mesh, &zero_set, &segments, LineKind::Silhouette, min_length)
}
