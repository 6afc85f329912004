//! Construction of the halfedge mesh from small hand-written files, one per repair
//! case, checking both the repair counts and that the result is a valid manifold.

use std::path::PathBuf;

use crestline::io::read_mesh;
use crestline::mesh::{Mesh, RepairReport};
use crestline::{Error, Result};

/// Write `text` as `name` in a fresh temporary directory and load it as a mesh.
fn load(name: &str, text: &str) -> (Result<(Mesh, RepairReport)>, PathBuf, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, text).unwrap();
    let result =
        read_mesh(&path).and_then(|soup| Mesh::from_soup(soup).map_err(|e| e.in_file(&path)));
    (result, path, dir)
}

fn load_ok(text: &str) -> (Mesh, RepairReport) {
    let (result, _, _dir) = load("mesh.obj", text);
    let (mesh, report) = result.expect("mesh should load");
    mesh.check_connectivity().expect("valid halfedge structure");
    (mesh, report)
}

fn error_message(name: &str, text: &str) -> String {
    let (result, path, _dir) = load(name, text);
    let err = result.expect_err("mesh should be rejected");
    let message = err.to_string();
    assert!(matches!(err, Error::File { .. }), "{message}");
    assert!(
        message.contains(&*path.to_string_lossy()),
        "error should name the file: {message}"
    );
    message
}

/// Six times the signed volume of a closed mesh.
fn signed_volume(mesh: &Mesh) -> f64 {
    mesh.faces()
        .map(|f| {
            let [a, b, c] = mesh.face_points(f).map(|p| p.coords);
            a.dot(&b.cross(&c))
        })
        .sum()
}

const TETRA_POINTS: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";

#[test]
fn clean_tetrahedron_needs_no_repair() {
    let (mesh, report) = load_ok(&format!(
        "{TETRA_POINTS}f 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n"
    ));
    assert!(report.is_clean(), "{report}");
    assert_eq!(
        (mesh.vertex_count(), mesh.edge_count(), mesh.face_count()),
        (4, 6, 4)
    );
    assert_eq!(mesh.euler_characteristic(), 2);
    assert!(signed_volume(&mesh) > 0.0);
    assert!(mesh.boundary_loops().is_empty());
}

#[test]
fn inside_out_closed_mesh_is_turned_outward() {
    // The same tetrahedron with every face reversed: consistent, but inside out.
    let (mesh, report) = load_ok(&format!(
        "{TETRA_POINTS}f 1 2 3\nf 1 4 2\nf 2 4 3\nf 1 3 4\n"
    ));
    assert_eq!(report.inverted_components, 1);
    assert_eq!(report.flipped_faces, 0);
    assert!(signed_volume(&mesh) > 0.0);
}

#[test]
fn inconsistent_orientation_is_made_consistent() {
    // Tetrahedron with one face reversed: the majority orientation wins.
    let (mesh, report) = load_ok(&format!(
        "{TETRA_POINTS}f 1 3 2\nf 1 2 4\nf 2 4 3\nf 1 4 3\n"
    ));
    assert_eq!(report.flipped_faces, 1);
    assert_eq!(report.inverted_components, 0);
    assert!(signed_volume(&mesh) > 0.0);
    // Every edge is interior and runs both ways.
    assert!(mesh.edges().all(|e| !mesh.is_boundary_edge(e)));
}

#[test]
fn duplicate_vertices_are_welded() {
    // Two triangles of a square given with their own copies of the shared corners,
    // as STL files do; also a -0.0 that must weld with 0.0.
    let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv -0.0 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 4 5 6\n";
    let (mesh, report) = load_ok(text);
    assert_eq!(report.welded_vertices, 2);
    assert_eq!(
        (mesh.vertex_count(), mesh.edge_count(), mesh.face_count()),
        (4, 5, 2)
    );
    assert_eq!(mesh.boundary_loops().len(), 1);
    assert_eq!(mesh.boundary_loops()[0].len(), 4);
}

#[test]
fn degenerate_and_repeated_faces_are_dropped() {
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\n\
                f 1 2 3\n\
                f 1 2 4\n\
                f 1 1 3\n\
                f 1 2 3\n\
                f 1 3 2\n";
    let (mesh, report) = load_ok(text);
    assert_eq!(
        report.degenerate_faces, 2,
        "collinear face and repeated corner"
    );
    assert_eq!(
        report.duplicate_faces, 2,
        "same corners, either orientation"
    );
    assert_eq!(
        report.unreferenced_vertices, 1,
        "vertex 4 only had a degenerate face"
    );
    assert_eq!((mesh.vertex_count(), mesh.face_count()), (3, 1));
}

#[test]
fn unreferenced_vertices_are_dropped() {
    let (mesh, report) = load_ok("v 0 0 0\nv 5 5 5\nv 1 0 0\nv 0 1 0\nf 1 3 4\n");
    assert_eq!(report.unreferenced_vertices, 1);
    assert_eq!(mesh.vertex_count(), 3);
    assert!(mesh.positions().iter().all(|p| p.x != 5.0));
}

#[test]
fn non_manifold_edge_is_split() {
    // Three triangles hinged on the edge 1-2.
    let text = "v 0 0 0\nv 1 0 0\nv 0.5 1 0\nv 0.5 -1 0\nv 0.5 0 1\n\
                f 1 2 3\nf 2 1 4\nf 1 2 5\n";
    let (mesh, report) = load_ok(text);
    assert_eq!(report.non_manifold_edges, 1);
    assert_eq!(mesh.face_count(), 3);
    // The two faces that were paired share an edge; the third is attached by a
    // boundary edge only, so its corners on the hinge became separate vertices.
    assert_eq!(report.non_manifold_vertices, 2);
    assert_eq!(mesh.vertex_count(), 7);
    assert_eq!(mesh.components().len(), 2);
}

#[test]
fn bow_tie_vertex_is_split() {
    // Two triangles touching at vertex 1 only.
    let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv -1 0 0\nv -1 -1 0\nf 1 2 3\nf 1 4 5\n";
    let (mesh, report) = load_ok(text);
    assert_eq!(report.non_manifold_vertices, 1);
    assert_eq!(mesh.vertex_count(), 6);
    let components = mesh.components();
    assert_eq!(components.len(), 2);
    assert!(components
        .iter()
        .all(|c| c.euler_characteristic == 1 && c.boundary_loops == 1));
}

#[test]
fn two_cones_sharing_an_apex_are_split_and_stay_closed() {
    // Two closed tetrahedra glued at one vertex: a non-manifold vertex whose fans
    // are both closed cycles.
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv -1 0 0\nv 0 -1 0\nv 0 0 -1\n\
                f 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n\
                f 1 6 5\nf 1 5 7\nf 5 6 7\nf 1 7 6\n";
    let (mesh, report) = load_ok(text);
    assert_eq!(report.non_manifold_vertices, 1);
    assert_eq!(mesh.vertex_count(), 8);
    let components = mesh.components();
    assert_eq!(components.len(), 2);
    assert!(components
        .iter()
        .all(|c| c.euler_characteristic == 2 && c.genus == 0));
    assert!(signed_volume(&mesh) > 0.0);
}

/// A Möbius strip of `n` quads, each split into two triangles, as OBJ text.
fn mobius_obj(n: usize) -> String {
    let mut text = String::new();
    for side in [1.0, -1.0] {
        for i in 0..n {
            let theta = std::f64::consts::TAU * i as f64 / n as f64;
            let (c, s) = (theta.cos(), theta.sin());
            let (tc, ts) = (
                (theta / 2.0).cos() * 0.3 * side,
                (theta / 2.0).sin() * 0.3 * side,
            );
            let radius = 1.0 + tc;
            text += &format!("v {} {} {}\n", radius * c, radius * s, ts);
        }
    }
    let top = |i: usize| i + 1;
    let bottom = |i: usize| n + i + 1;
    let mut quads: Vec<[usize; 4]> = (0..n - 1)
        .map(|i| [top(i), top(i + 1), bottom(i + 1), bottom(i)])
        .collect();
    // The twist: the top rail continues into the bottom one.
    quads.push([top(n - 1), bottom(0), top(0), bottom(n - 1)]);
    for [a, b, c, d] in quads {
        text += &format!("f {a} {b} {c}\nf {a} {c} {d}\n");
    }
    text
}

#[test]
fn mobius_strip_is_an_error_naming_the_component() {
    let message = error_message("strip.obj", &mobius_obj(8));
    assert!(message.contains("cannot be oriented"), "{message}");
    assert!(message.contains("component 0"), "{message}");
}

#[test]
fn nan_coordinate_is_an_error_naming_the_vertex() {
    let message = error_message("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
    assert!(message.contains("vertex 1"), "{message}");
    assert!(message.contains("non-finite"), "{message}");
}

#[test]
fn only_degenerate_faces_is_an_error() {
    let message = error_message("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
    assert!(message.contains("no faces"), "{message}");
}

#[test]
fn vertex_rotation_visits_every_neighbour_once() {
    let (mesh, _) = load_ok(&format!(
        "{TETRA_POINTS}f 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n"
    ));
    for v in mesh.vertices() {
        let mut neighbours: Vec<u32> = mesh.neighbors(v).map(|w| w.0).collect();
        assert_eq!(neighbours.len(), 3);
        neighbours.sort_unstable();
        neighbours.dedup();
        assert_eq!(neighbours.len(), 3);
        assert_eq!(mesh.vertex_faces(v).count(), 3);
    }
}

#[test]
fn exploded_sphere_welds_back_to_the_same_closed_mesh() {
    // Every face with its own three vertices, as an STL file stores a mesh.
    let sphere = crestline::mesh::generate::sphere(
        1.0,
        3000,
        crestline::mesh::generate::Sampling::jittered(4),
    )
    .unwrap()
    .mesh;
    let mut soup = crestline::mesh::TriangleSoup::default();
    for f in sphere.faces() {
        let first = soup.positions.len() as u32;
        soup.positions.extend(sphere.face_points(f));
        soup.triangles.push([first, first + 1, first + 2]);
    }
    let (mesh, report) = Mesh::from_soup(soup).unwrap();
    mesh.check_connectivity().unwrap();
    assert_eq!(
        report.welded_vertices,
        3 * sphere.face_count() - sphere.vertex_count()
    );
    assert_eq!(
        (mesh.vertex_count(), mesh.face_count()),
        (sphere.vertex_count(), sphere.face_count())
    );
    assert_eq!(mesh.euler_characteristic(), 2);
    // Faces keep their order and corners: the same geometry, now connected.
    assert!(mesh
        .faces()
        .all(|f| mesh.face_points(f) == sphere.face_points(f)));
}
