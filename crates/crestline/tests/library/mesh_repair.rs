//! Construction of the halfedge mesh from small hand-written files, one per repair
//! case, checking both the repair counts and that the result is a valid manifold.

use std::path::{Path, PathBuf};

use crestline::io::read_mesh;
use crestline::lines::LineExtractor;
use crestline::mesh::{HalfedgeId, Mesh, RepairReport, TriangleSoup};
use crestline::progress::Silent;
use crestline::ridges::ExtremalityTracer;
use crestline::{Error, Result};

use crate::common;

/// A way to build a mesh from a soup: [`Mesh::from_soup`], [`Mesh::from_soup_strict`]
/// or [`Mesh::from_oriented_soup`].
type Build = fn(TriangleSoup) -> Result<(Mesh, RepairReport)>;

/// Write `text` as `name` in a fresh temporary directory and load it as a mesh.
fn load(name: &str, text: &str) -> (Result<(Mesh, RepairReport)>, PathBuf, tempfile::TempDir) {
    load_with(Mesh::from_soup, name, text)
}

/// [`load`], building the mesh with `build`.
fn load_with(
    build: Build,
    name: &str,
    text: &str,
) -> (Result<(Mesh, RepairReport)>, PathBuf, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, text).unwrap();
    let result = read_mesh(&path).and_then(|soup| build(soup).map_err(|e| e.in_file(&path)));
    (result, path, dir)
}

fn load_ok(text: &str) -> (Mesh, RepairReport) {
    let (result, _, _dir) = load("mesh.obj", text);
    let (mesh, report) = result.expect("mesh should load");
    assert_valid(&mesh);
    (mesh, report)
}

/// Check the halfedge structure, and that every halfedge and its twin form one edge:
/// the twin runs back the other way, twice twin is the identity, at least one side
/// has a face, and two faces across an edge run along it in opposite directions.
fn assert_valid(mesh: &Mesh) {
    mesh.check_connectivity().expect("valid halfedge structure");
    for h in (0..mesh.halfedge_count() as u32).map(HalfedgeId) {
        let t = mesh.twin(h);
        assert_ne!(t, h);
        assert_eq!(mesh.twin(t), h);
        assert_eq!(mesh.edge(t), mesh.edge(h));
        assert_eq!(
            (mesh.source(t), mesh.target(t)),
            (mesh.target(h), mesh.source(h))
        );
        assert!(!(mesh.is_boundary_halfedge(h) && mesh.is_boundary_halfedge(t)));
    }
    for f in mesh.faces() {
        for h in mesh.face_halfedges(f) {
            assert_eq!(mesh.face(h), f);
            let across = mesh.face(mesh.twin(h));
            assert_ne!(across, f, "a face is its own neighbour");
        }
    }
}

fn error_message(name: &str, text: &str) -> String {
    error_message_with(Mesh::from_soup, name, text)
}

/// [`error_message`], building the mesh with `build`.
fn error_message_with(build: Build, name: &str, text: &str) -> String {
    let (result, path, _dir) = load_with(build, name, text);
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
fn oriented_soup_keeps_an_inside_out_closed_mesh_as_given() {
    // A cavity's boundary: consistent, negative volume, and meant that way.
    let text = format!("{TETRA_POINTS}f 1 2 3\nf 1 4 2\nf 2 4 3\nf 1 3 4\n");
    let (result, _, _dir) = load_with(Mesh::from_oriented_soup, "cavity.obj", &text);
    let (mesh, report) = result.unwrap();
    assert_valid(&mesh);
    assert!(report.is_clean(), "{report}");
    assert!(signed_volume(&mesh) < 0.0);
}

#[test]
fn oriented_soup_refuses_faces_that_disagree_naming_the_edge() {
    let text = format!("{TETRA_POINTS}f 1 3 2\nf 1 2 4\nf 2 4 3\nf 1 4 3\n");
    let message = error_message_with(Mesh::from_oriented_soup, "mixed.obj", &text);
    assert!(message.contains("disagree in orientation"), "{message}");
    assert!(message.contains("edge from vertex"), "{message}");
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
fn mobius_strip_is_refused_in_strict_mode_naming_the_component() {
    let message = error_message_with(Mesh::from_soup_strict, "strip.obj", &mobius_obj(8));
    assert!(
        message.contains(
            "component 0 (the faces connected to face 0) cannot be oriented consistently \
             (it is Möbius-like)"
        ),
        "{message}"
    );
}

#[test]
fn mobius_strip_is_cut_into_an_orientable_disk() {
    let n = 8;
    let (mesh, report) = load_ok(&mobius_obj(n));
    // One cut across the strip suffices; both ends of the cut edge lie on the
    // strip's boundary, so each becomes two vertices.
    assert_eq!(report.cut_edges, 1, "{report}");
    assert_eq!(report.non_manifold_vertices, 2, "{report}");
    assert_eq!(report.non_manifold_edges, 0);
    assert!(report
        .messages()
        .iter()
        .any(|m| m.starts_with("1 edges cut open")));
    assert_eq!(
        (mesh.vertex_count(), mesh.edge_count(), mesh.face_count()),
        (2 * n + 2, 4 * n + 1, 2 * n)
    );
    // The strip (χ = 0, one boundary loop of 2n edges) became a disk whose boundary
    // also runs along both sides of the cut.
    let components = mesh.components();
    assert_eq!(components.len(), 1);
    assert_eq!(components[0].euler_characteristic, 1);
    assert_eq!(components[0].genus, 0);
    let loops = mesh.boundary_loops();
    assert_eq!(loops.len(), 1);
    assert_eq!(loops[0].len(), 2 * n + 2);
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

/// A tetrahedron with positive volume on the vertices `a`, `b`, `c`, `d` (1-based,
/// with det[b - a, c - a, d - a] > 0), as OBJ faces.
fn tetra_faces(a: usize, b: usize, c: usize, d: usize) -> String {
    format!("f {a} {c} {b}\nf {a} {b} {d}\nf {b} {c} {d}\nf {a} {d} {c}\n")
}

/// `k` closed tetrahedra sharing the edge from vertex 1 at the origin to vertex 2 at
/// (1, 0, 0), fanned around it: the edge has `2k` faces.
fn tetrahedra_on_one_edge(k: usize) -> String {
    let mut text = String::from("v 0 0 0\nv 1 0 0\n");
    let mut faces = String::new();
    for i in 0..k {
        for j in 0..2 {
            let angle = std::f64::consts::TAU * (2 * i + j) as f64 / (2 * k) as f64;
            text += &format!("v 0.5 {} {}\n", angle.cos(), angle.sin());
        }
        faces += &tetra_faces(1, 2, 3 + 2 * i, 4 + 2 * i);
    }
    text + &faces
}

#[test]
fn back_to_back_fin_is_dropped_with_both_faces() {
    // A closed tetrahedron with a fin of zero thickness on its edge 1-2: the face
    // 1 2 5 and its reverse. Edge 1-2 has four faces, 1-5 and 2-5 two each.
    let text = format!(
        "{TETRA_POINTS}v 1 1 1\n{}f 1 2 5\nf 1 5 2\n",
        tetra_faces(1, 2, 3, 4)
    );
    let (mesh, report) = load_ok(&text);
    let expected = RepairReport {
        back_to_back_pairs: 1,
        unreferenced_vertices: 1,
        ..RepairReport::default()
    };
    assert_eq!(report, expected, "{report}");
    assert_eq!(
        report.messages(),
        [
            "1 unreferenced vertices dropped",
            "1 back-to-back face pairs dropped (a face and its reverse on the same corners)"
        ]
    );
    assert_eq!(
        (mesh.vertex_count(), mesh.edge_count(), mesh.face_count()),
        (4, 6, 4)
    );
    assert_eq!(mesh.euler_characteristic(), 2);
    assert!(signed_volume(&mesh) > 0.0);
}

#[test]
fn face_given_in_both_orientations_leaves_a_hole() {
    // The tetrahedron's face 1 3 2 also given as 1 2 3 (rotated to 2 3 1): neither
    // can be told to be the surface, so both go and the box is open.
    let text = format!("{TETRA_POINTS}{}f 2 3 1\n", tetra_faces(1, 2, 3, 4));
    let (mesh, report) = load_ok(&text);
    assert_eq!(report.back_to_back_pairs, 1, "{report}");
    assert_eq!(report.duplicate_faces, 0, "{report}");
    assert_eq!(report.flipped_faces, 0, "{report}");
    assert_eq!(
        (mesh.vertex_count(), mesh.edge_count(), mesh.face_count()),
        (4, 6, 3)
    );
    assert_eq!(mesh.euler_characteristic(), 1);
    let loops = mesh.boundary_loops();
    assert_eq!(loops.len(), 1);
    assert_eq!(loops[0].len(), 3);
}

#[test]
fn more_frequent_orientation_of_repeated_corners_is_kept_once() {
    // Face 1 3 2 three times (twice rotated) against its reverse twice: one 1 3 2
    // stays, the four others are duplicates, and the tetrahedron stays closed.
    let text = format!(
        "{TETRA_POINTS}{}f 1 2 3\nf 3 2 1\nf 1 2 3\nf 2 1 3\n",
        tetra_faces(1, 2, 3, 4)
    );
    let (mesh, report) = load_ok(&text);
    assert_eq!(report.duplicate_faces, 4, "{report}");
    assert_eq!(report.back_to_back_pairs, 0, "{report}");
    assert_eq!(mesh.face_count(), 4);
    assert_eq!(mesh.euler_characteristic(), 2);
    assert!(mesh.boundary_loops().is_empty());
    assert!(signed_volume(&mesh) > 0.0);
}

#[test]
fn edge_with_four_faces_is_split_into_two_closed_surfaces() {
    let (mesh, report) = load_ok(&tetrahedra_on_one_edge(2));
    let expected = RepairReport {
        non_manifold_edges: 1,
        // The ends of the shared edge, one extra copy each.
        non_manifold_vertices: 2,
        ..RepairReport::default()
    };
    assert_eq!(report, expected, "{report}");
    assert_eq!(
        (mesh.vertex_count(), mesh.edge_count(), mesh.face_count()),
        (8, 12, 8)
    );
    let components = mesh.components();
    assert_eq!(components.len(), 2);
    assert!(components
        .iter()
        .all(|c| c.euler_characteristic == 2 && c.boundary_loops == 0 && c.faces == 4));
    assert!(signed_volume(&mesh) > 0.0);
}

#[test]
fn edge_with_six_faces_is_split_into_three_closed_surfaces() {
    let (mesh, report) = load_ok(&tetrahedra_on_one_edge(3));
    let expected = RepairReport {
        non_manifold_edges: 1,
        non_manifold_vertices: 4,
        ..RepairReport::default()
    };
    assert_eq!(report, expected, "{report}");
    assert_eq!(
        (mesh.vertex_count(), mesh.edge_count(), mesh.face_count()),
        (12, 18, 12)
    );
    let components = mesh.components();
    assert_eq!(components.len(), 3);
    assert!(components
        .iter()
        .all(|c| c.euler_characteristic == 2 && c.boundary_loops == 0 && c.faces == 4));
}

#[test]
fn strict_mode_makes_every_other_repair() {
    // An orientable input with a back-to-back pair and a non-manifold edge: both
    // builds agree.
    let text = format!("{}f 1 3 5\nf 1 5 3\n", tetrahedra_on_one_edge(2));
    let (strict, _, _dir) = load_with(Mesh::from_soup_strict, "mesh.obj", &text);
    let (strict_mesh, strict_report) = strict.expect("orientable input is accepted");
    let (mesh, report) = load_ok(&text);
    assert_valid(&strict_mesh);
    assert_eq!(strict_report, report);
    assert_eq!(report.back_to_back_pairs, 1);
    assert_eq!(report.non_manifold_edges, 1);
    assert_eq!(strict_mesh.triangles(), mesh.triangles());
}

#[test]
fn twisted_band_glued_to_a_closed_surface_is_cut_once() {
    // A Möbius strip sharing no vertex with a tetrahedron, in one file: only the strip
    // is cut, the tetrahedron stays closed.
    let n = 6;
    let strip = mobius_obj(n);
    let offset = 2 * n;
    let mut text = strip;
    text += "v 5 0 0\nv 6 0 0\nv 5 1 0\nv 5 0 1\n";
    text += &tetra_faces(offset + 1, offset + 2, offset + 3, offset + 4);
    let (mesh, report) = load_ok(&text);
    assert_eq!(report.cut_edges, 1, "{report}");
    let mut chis: Vec<(i64, usize)> = mesh
        .components()
        .iter()
        .map(|c| (c.euler_characteristic, c.boundary_loops))
        .collect();
    chis.sort_unstable();
    assert_eq!(chis, [(1, 1), (2, 0)]);
}

/// The decimated Stanford dragon scans, fetched by `tools/fetch_dragon.sh`.
const DRAGONS: [&str; 4] = [
    "dragon_vrip_res4.ply",
    "dragon_vrip_res3.ply",
    "dragon_vrip_res2.ply",
    "dragon_vrip.ply",
];

#[test]
fn dragon_scans_open_with_their_repairs_reported() {
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/dragon"));
    let missing: Vec<&str> = DRAGONS
        .iter()
        .copied()
        .filter(|name| !dir.join(name).is_file())
        .collect();
    if !missing.is_empty() {
        common::skip(&format!(
            "{} missing from {} (run tools/fetch_dragon.sh to fetch the scans)",
            missing.join(", "),
            dir.display()
        ));
        return;
    }
    for name in DRAGONS {
        let path = dir.join(name);
        let soup = read_mesh(&path).unwrap_or_else(|e| panic!("{e}"));
        let triangles = soup.triangles.len();
        let (mesh, report) = Mesh::from_soup(soup).unwrap_or_else(|e| panic!("{name}: {e}"));
        mesh.check_connectivity()
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        eprintln!(
            "{name}: {triangles} triangles -> {} faces, {} vertices; {report}",
            mesh.face_count(),
            mesh.vertex_count()
        );
        // Every face that went is accounted for by the report.
        let dropped =
            report.degenerate_faces + report.duplicate_faces + 2 * report.back_to_back_pairs;
        assert_eq!(mesh.face_count(), triangles - dropped, "{name}: {report}");
        // The coarser scans lose up to 7% of their faces to back-to-back pairs, where
        // thin parts collapsed into one sheet seen from both sides.
        assert!(
            100 * mesh.face_count() >= 90 * triangles,
            "{name}: only {} of {triangles} faces kept",
            mesh.face_count()
        );
        assert!(!report.messages().is_empty(), "{name}");
        // Repairs leave edges between the same two vertices in the decimated
        // scans: the smoothing systems sum them into one entry.
        if name != "dragon_vrip.ply" {
            let lines = ExtremalityTracer::default()
                .extract(&mesh, &mut Silent)
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            assert!(lines.len() > 20, "{name}: {} lines", lines.len());
        }
    }
}
