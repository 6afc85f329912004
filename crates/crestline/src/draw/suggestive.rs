//! Suggestive contours (DeCarlo, Finkelstein, Rusinkiewicz, Santella, "Suggestive
//! Contours for Conveying Shape", SIGGRAPH 2003): the lines where the surface
//! would turn into a contour from a nearby viewpoint.
//!
//! With v the unit vector towards the viewer, n the normal and w = v − (n · v) n the
//! projection of v onto the tangent plane, the radial curvature is the normal
//! curvature along w (Euler's formula, DeCarlo et al. §3):
//!
//! κ_r = k_max cos²φ + k_min sin²φ, φ the angle between d_max and w.
//!
//! The suggestive contour generator is where κ_r = 0 and D_w κ_r > 0 (definition I,
//! §3.1). It is unstable where w is short, i.e. where the surface faces the viewer,
//! and where κ_r barely changes across it, so two filters drop such points (§4):
//! the angle θ between n and v must exceed θ_c, and D_w κ_r / ‖w‖ must exceed a
//! threshold t_d relative to the feature size of the mesh.

use rayon::prelude::*;

use crate::curvature::CurvatureField;
use crate::lines::fair::fair_polyline;
use crate::lines::zero_set::{LinePoint, ZeroSet};
use crate::lines::{FeatureLines, LineKind};
use crate::mesh::{EdgeId, FaceId, Mesh};
use crate::{Error, Point, Result, Vector};

use super::camera::Camera;
use super::zero_lines::zero_set_lines;

/// The share of vertices whose curvedness is at most the feature curvature
/// ([`feature_curvature`]).
const FEATURE_QUANTILE: f64 = 0.9;

/// The filters of [`suggestive_contours`] (DeCarlo et al. 2003, §4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SuggestiveOptions {
    /// θ_c in degrees: points where the angle between the normal and the view
    /// vector is smaller are dropped (there w is short and its direction unstable).
    pub min_view_angle: f64,
    /// t_d: points where D_w κ_r / ‖w‖ is below this many times the squared
    /// feature curvature of the mesh are dropped.
    pub min_derivative: f64,
    /// Lines shorter than this many mean edge lengths are dropped.
    pub min_length: f64,
    /// Fairing iterations of the lines (`fair_polyline`, each point kept
    /// within half a mean edge length of the zero set): the zero set of a
    /// scan's noisy curvature zigzags from edge to edge.
    pub fairing: usize,
}

impl Default for SuggestiveOptions {
    fn default() -> Self {
        SuggestiveOptions {
            min_view_angle: 15.0,
            min_derivative: 0.1,
            min_length: 8.0,
            fairing: 10,
        }
    }
}

impl SuggestiveOptions {
    /// Check the settings: a view angle in [0°, 90°), a finite and non-negative
    /// derivative threshold and minimum length.
    pub fn check(&self) -> Result<()> {
        if !(self.min_view_angle >= 0.0 && self.min_view_angle < 90.0) {
            return Err(Error::Argument(format!(
                "the suggestive contours' view angle must be at least 0 and below 90 degrees, got {}",
                self.min_view_angle
            )));
        }
        for (name, value) in [
            ("derivative threshold", self.min_derivative),
            ("minimum length", self.min_length),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(Error::Argument(format!(
                    "the suggestive contours' {name} must be finite and not negative, got {value}"
                )));
            }
        }
        Ok(())
    }
}

/// What the filters need at each vertex.
struct VertexView {
    /// κ_r ‖w‖² = k_max (w · d_max)² + k_min (w · d_min)²: the sign of κ_r, smooth
    /// where w vanishes (the function whose zero set is traced).
    scaled: f64,
    /// κ_r itself; the mean curvature where w vanishes (the mean of the normal
    /// curvatures over all directions).
    radial: f64,
    /// cos θ = n · v.
    facing: f64,
}

/// The suggestive contours of `mesh` seen by `camera`, as [`LineKind::Suggestive`]
/// lines on the mesh edges, from the principal curvatures of `field`. The zero set
/// of κ_r is traced per face by linear interpolation on the edges ([`ZeroSet`], as
/// the silhouettes); a face keeps its segment if, at the segment's midpoint, the
/// surface faces the viewer (n · v > 0) at an angle θ > θ_c, and
/// D_w κ_r / ‖w‖ > t_d K², with D κ_r the gradient of the linear interpolant of κ_r
/// on the face and K the curvature of the mesh's features (the 90th percentile of
/// the curvedness). Faces with a vertex whose curvature is unreliable are skipped.
/// A line's strength is its length in mean edge lengths.
///
/// A mesh without curvature (K = 0, e.g. a plane) has none. The result says nothing
/// about visibility. Errors: settings that fail [`SuggestiveOptions::check`], a
/// field that does not fit the mesh.
pub fn suggestive_contours(
    mesh: &Mesh,
    field: &CurvatureField,
    camera: &Camera,
    options: &SuggestiveOptions,
) -> Result<FeatureLines> {
    options.check()?;
    field.check(mesh)?;
    let feature = feature_curvature(field);
    if feature == 0.0 {
        return Ok(FeatureLines::new(String::new()));
    }
    let views: Vec<VertexView> = mesh
        .par_vertices()
        .map(|v| vertex_view(field, v.idx(), &view_vector(camera, &mesh.position(v))))
        .collect();
    let zero_set = ZeroSet::new(views.iter().map(|at| at.scaled).collect());
    let radial: Vec<f64> = views.iter().map(|at| at.radial).collect();
    let facing: Vec<f64> = views.iter().map(|at| at.facing).collect();
    let max_facing = options.min_view_angle.to_radians().cos();
    let min_derivative = options.min_derivative * feature * feature;
    let keep = |f: FaceId, crossed: [EdgeId; 2]| {
        let corners = mesh.face_vertices(f);
        if corners.iter().any(|v| field.unreliable[v.idx()]) {
            return false;
        }
        let at = crossed.map(|e| zero_set.location(mesh, LinePoint::Edge(e)));
        let cos_theta = 0.5 * (at[0].interpolate(mesh, &facing) + at[1].interpolate(mesh, &facing));
        if !(cos_theta > 0.0 && cos_theta < max_facing) {
            return false;
        }
        let midpoint = nalgebra::center(&at[0].position(mesh), &at[1].position(mesh));
        radial_derivative(mesh, f, &radial, &view_vector(camera, &midpoint))
            .is_some_and(|d| d > min_derivative)
    };
    let segments: Vec<[LinePoint; 2]> = zero_set
        .face_segments(mesh, keep)
        .into_iter()
        .flatten()
        .map(|[a, b]| [LinePoint::Edge(a), LinePoint::Edge(b)])
        .collect();
    let mut lines = zero_set_lines(
        mesh,
        &zero_set,
        &segments,
        LineKind::Suggestive,
        options.min_length,
    );
    if options.fairing > 0 {
        let h = mesh.mean_edge_length();
        for line in &mut lines.lines {
            fair_polyline(&mut line.points, line.closed, options.fairing, 0.5 * h);
            // Faired points leave the surface.
            line.locations.clear();
        }
    }
    Ok(lines)
}

/// The unit vector from `p` towards the viewer.
fn view_vector(camera: &Camera, p: &Point) -> Vector {
    camera.toward_viewer(p).normalize()
}

/// κ_r and n · v at vertex `i` seen along the unit vector `v`.
fn vertex_view(field: &CurvatureField, i: usize, v: &Vector) -> VertexView {
    let facing = field.normal[i].dot(v);
    let w = v - field.normal[i] * facing;
    let (along_max, along_min) = (w.dot(&field.d_max[i]), w.dot(&field.d_min[i]));
    let (cos2, sin2) = (along_max * along_max, along_min * along_min);
    let scaled = field.k_max[i] * cos2 + field.k_min[i] * sin2;
    let radial = if cos2 + sin2 > 0.0 {
        scaled / (cos2 + sin2)
    } else {
        0.5 * (field.k_max[i] + field.k_min[i])
    };
    VertexView {
        scaled,
        radial,
        facing,
    }
}

/// D_w κ_r / ‖w‖ on face `f`: the gradient of the linear interpolant of `radial`
/// on the face along the projection of `v` onto the face's plane; `None` where the
/// face is degenerate or seen head-on.
fn radial_derivative(mesh: &Mesh, f: FaceId, radial: &[f64], v: &Vector) -> Option<f64> {
    let area = mesh.face_area_vector(f);
    let area_squared = area.norm_squared();
    let normal = area.try_normalize(0.0)?;
    let w = (v - normal * normal.dot(v)).try_normalize(0.0)?;
    // ∇f = Σ f_i (a × e_i) / |a|², e_i the edge opposite corner i (counter-clockwise)
    // and a the area vector: the gradient of the linear interpolant on a triangle.
    let corners = mesh.face_vertices(f);
    let points = mesh.face_points(f);
    let gradient: Vector = (0..3)
        .map(|i| {
            let edge = points[(i + 2) % 3] - points[(i + 1) % 3];
            area.cross(&edge) * radial[corners[i].idx()]
        })
        .sum::<Vector>()
        / area_squared;
    Some(gradient.dot(&w))
}

/// The curvature of the features of a surface, K: the 90th percentile of the
/// curvedness √((k_max² + k_min²) / 2) over the reliable vertices (0 without any).
/// Its reciprocal plays the part of DeCarlo et al.'s feature size.
fn feature_curvature(field: &CurvatureField) -> f64 {
    let mut curvedness: Vec<f64> = field
        .curvedness()
        .into_iter()
        .zip(&field.unreliable)
        .filter(|&(_, &unreliable)| !unreliable)
        .map(|(c, _)| c)
        .collect();
    if curvedness.is_empty() {
        return 0.0;
    }
    let rank = ((curvedness.len() - 1) as f64 * FEATURE_QUANTILE).round() as usize;
    let (_, value, _) = curvedness.select_nth_unstable_by(rank, f64::total_cmp);
    *value
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_gradient_of_a_linear_function_is_exact_on_a_face() {
        let soup = crate::mesh::TriangleSoup {
            positions: vec![
                Point::new(0.0, 0.0, 0.0),
                Point::new(2.0, 0.0, 0.0),
                Point::new(0.5, 1.5, 0.0),
            ],
            triangles: vec![[0, 1, 2]],
            vertex_scalars: Vec::new(),
            space: None,
            volume_geometry: None,
        };
        let (mesh, _) = Mesh::from_soup(soup).unwrap();
        // f = 3x − 2y at the corners; its gradient (3, −2) along x is 3.
        let values: Vec<f64> = mesh
            .positions()
            .iter()
            .map(|p| 3.0 * p.x - 2.0 * p.y)
            .collect();
        let along_x = radial_derivative(&mesh, FaceId(0), &values, &Vector::new(1.0, 0.0, 1.0));
        assert!((along_x.unwrap() - 3.0).abs() < 1e-12, "{along_x:?}");
        let head_on = radial_derivative(&mesh, FaceId(0), &values, &Vector::new(0.0, 0.0, 1.0));
        assert_eq!(head_on, None);
    }
}
