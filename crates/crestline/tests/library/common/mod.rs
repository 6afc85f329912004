//! Helpers shared by the integration tests.

pub mod mutation;

use crestline::mesh::{Mesh, TriangleSoup};
use crestline::Point;

/// A copy of `mesh` with every position mapped by `map` (same triangles).
pub fn transformed(mesh: &Mesh, map: impl Fn(&Point) -> Point) -> Mesh {
    let soup = TriangleSoup {
        positions: mesh.positions().iter().map(map).collect(),
        triangles: mesh.triangles(),
        ..TriangleSoup::default()
    };
    Mesh::from_soup(soup).unwrap().0
}
