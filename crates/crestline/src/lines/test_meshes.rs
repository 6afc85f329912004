//! Small meshes for the line modules' unit tests.

use crate::mesh::{Mesh, TriangleSoup};
use crate::Point;

/// The unit square in the plane z = 0, cut into the triangles (0, 1, 2) and
/// (0, 2, 3) along its diagonal from vertex 0 to vertex 2.
pub(super) fn unit_square() -> Mesh {
    let soup = TriangleSoup {
        positions: vec![
            Point::new(0.0, 0.0, 0.0),
            Point::new(1.0, 0.0, 0.0),
            Point::new(1.0, 1.0, 0.0),
            Point::new(0.0, 1.0, 0.0),
        ],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        ..TriangleSoup::default()
    };
    Mesh::from_soup(soup).expect("a clean square").0
}
