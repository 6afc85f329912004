//! Lines along the edges of a mesh: its borders (boundary loops) and its creases
//! (edges where the two faces meet at a sharp angle), as polylines through mesh
//! vertices. Neither depends on the view.

use crate::lines::chain::chain;
use crate::lines::{FeatureLines, LineKind, Polyline, SurfaceLocation};
use crate::mesh::{Mesh, VertexId};
use crate::{Error, Result};

/// The borders of `mesh`: every boundary loop as a closed [`LineKind::Border`] line
/// through its vertices, in the order of the loop. A closed mesh has none. A loop
/// of two vertices (a slit, where a mesh was cut open along an edge to make it
/// orientable) encloses nothing and is left out. A line's strength is its length in
/// mean edge lengths.
pub fn borders(mesh: &Mesh) -> FeatureLines {
    let h = mesh.mean_edge_length();
    let mut lines = FeatureLines::new(String::new());
    for boundary in mesh.boundary_loops().into_iter().filter(|b| b.len() >= 3) {
        let vertices = boundary.iter().map(|&b| mesh.source(b)).collect();
        lines.push(vertex_line(mesh, LineKind::Border, true, vertices, h));
    }
    lines
}

/// The creases of `mesh`: the interior edges whose dihedral angle (the angle
/// between the normals of their two faces, on convex and concave edges alike)
/// exceeds `angle` degrees, chained into [`LineKind::Crease`] lines. A line ends at
/// a vertex where the number of crease edges is not two (a corner, a junction or an
/// end); a loop of crease edges is one closed line. A line's strength is its length
/// in mean edge lengths.
///
/// Errors ([`Error::Argument`]): `angle` not strictly between 0 and 180 degrees.
pub fn creases(mesh: &Mesh, angle: f64) -> Result<FeatureLines> {
    let threshold = check_crease_angle(angle)?.to_radians();
    let edges: Vec<[VertexId; 2]> = mesh
        .edges()
        .filter(|&e| mesh.dihedral_angle(e).abs() > threshold)
        .map(|e| mesh.edge_vertices(e))
        .collect();
    let h = mesh.mean_edge_length();
    let mut lines = FeatureLines::new(String::new());
    // No piece is too weak: every chain is kept (∫ 0 ds ≥ 0).
    for piece in chain(&edges, |v| (mesh.position(v), 0.0), 0.0) {
        lines.push(vertex_line(
            mesh,
            LineKind::Crease,
            piece.closed,
            piece.points,
            h,
        ));
    }
    Ok(lines)
}

/// `angle` if it is a usable crease angle: finite and strictly between 0 and 180
/// degrees.
pub(super) fn check_crease_angle(angle: f64) -> Result<f64> {
    if angle > 0.0 && angle < 180.0 {
        Ok(angle)
    } else {
        Err(Error::Argument(format!(
            "the crease angle must be strictly between 0 and 180 degrees, got {angle}"
        )))
    }
}

/// The line of `kind` through `vertices` of `mesh`, located at them, with its
/// length in units of `h` as strength.
fn vertex_line(
    mesh: &Mesh,
    kind: LineKind,
    closed: bool,
    vertices: Vec<VertexId>,
    h: f64,
) -> Polyline {
    let points = vertices.iter().map(|&v| mesh.position(v)).collect();
    let locations = vertices
        .iter()
        .map(|v| SurfaceLocation::Vertex { vertex: v.0 })
        .collect();
    let mut line = Polyline::new(kind, closed, 0.0, points).with_locations(locations);
    line.strength = line.length() / h;
    line
}
