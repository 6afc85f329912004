use nalgebra::Rotation3;

use super::*;
use crate::lines::{LineKind, Polyline};
use crate::Vector;

/// Features with one open line of `kind` through `points`.
fn line(kind: &str, points: &[Point]) -> Features {
    let mut features = Features::default();
    features.add_line(kind, points, false);
    features
}

/// `count` + 1 evenly spaced points from `from` to `to`.
fn sampled(from: Point, to: Point, count: usize) -> Vec<Point> {
    (0..=count)
        .map(|i| from.coords.lerp(&to.coords, i as f64 / count as f64).into())
        .collect()
}

fn p(x: f64, y: f64, z: f64) -> Point {
    Point::new(x, y, z)
}

#[test]
fn distance_is_to_the_other_lines_segments_not_their_vertices() {
    // B is the same straight line as A with only its two ends: every point of A is
    // on it, though most lie far from both of its vertices.
    let a = line("ridge", &sampled(p(0.0, 0.0, 0.0), p(10.0, 0.0, 0.0), 100));
    let b = line("ridge", &[p(0.0, 0.0, 0.0), p(10.0, 0.0, 0.0)]);
    let found = compare(&a, &b, 0.01);
    assert_eq!(found.lines.len(), 1);
    assert!((found.lines[0].a_in_b - 1.0).abs() < 1e-12);
    assert!((found.lines[0].b_in_a - 1.0).abs() < 1e-12);
    assert!((found.lines[0].a - 10.0).abs() < 1e-12);
}

#[test]
fn a_parallel_line_counts_within_the_tolerance_and_not_beyond() {
    let a = line("valley", &sampled(p(0.0, 0.0, 0.0), p(5.0, 5.0, 0.0), 37));
    let offset = |d: f64| {
        let normal = Vector::new(-1.0, 1.0, 0.0).normalize() * d;
        line(
            "valley",
            &[p(0.0, 0.0, 0.0) + normal, p(5.0, 5.0, 0.0) + normal],
        )
    };
    assert!((compare(&a, &offset(0.09), 0.1).lines[0].a_in_b - 1.0).abs() < 1e-12);
    assert_eq!(compare(&a, &offset(0.11), 0.1).lines[0].a_in_b, 0.0);
}

#[test]
fn half_a_line_is_half_covered_and_covers_itself_whole() {
    let a = line("ridge", &[p(0.0, 0.0, 0.0), p(10.0, 0.0, 0.0)]);
    let b = line("ridge", &[p(0.0, 0.0, 0.0), p(5.0, 0.0, 0.0)]);
    let found = &compare(&a, &b, 0.04).lines[0];
    // Pieces of a hundredth; those within the tolerance beyond B's end count too.
    assert!((found.a_in_b - 0.504).abs() < 0.002, "{}", found.a_in_b);
    assert!((found.b_in_a - 1.0).abs() < 1e-12);
}

#[test]
fn kinds_are_compared_with_their_own_kind_only() {
    let points = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0)];
    let found = compare(&line("ridge", &points), &line("valley", &points), 0.1);
    let kinds: Vec<&str> = found.lines.iter().map(|a| a.kind.as_str()).collect();
    assert_eq!(kinds, ["ridge", "valley"]);
    assert!(found
        .lines
        .iter()
        .all(|a| a.a_in_b == 0.0 && a.b_in_a == 0.0));
    assert_eq!((found.lines[0].a_count, found.lines[0].b_count), (1, 0));
}

#[test]
fn a_moved_copy_moved_back_agrees_whole() {
    let mut a = line("crest", &sampled(p(1.0, 2.0, 3.0), p(40.0, -7.0, 12.0), 50));
    a.points.insert(
        "extremal".into(),
        vec![p(1.0, 2.0, 3.0), p(20.0, 0.0, 0.0), p(3.0, 3.0, 3.0)],
    );
    let motion = RigidTransform::new(
        Rotation3::from_euler_angles(0.3, -0.2, 0.5),
        Vector::new(5.0, -3.0, 2.0),
    );
    let b = a.moved(&motion);
    let unmoved = compare(&a, &b, 0.05);
    assert!(unmoved.lines[0].a_in_b < 0.1);
    let back = compare(&a, &b.moved(&motion.inverse()), 0.05);
    assert!((back.lines[0].a_in_b - 1.0).abs() < 1e-12);
    assert_eq!(back.landmarks[0].a_in_b, 1.0);
    assert_eq!(back.landmarks[0].a_count, 3);
}

#[test]
fn landmarks_count_by_the_nearest_of_their_kind() {
    let mut a = Features::default();
    a.points
        .insert("end".into(), vec![p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0)]);
    let mut b = Features::default();
    b.points.insert("end".into(), vec![p(0.0, 0.0, 0.3)]);
    let found = &compare(&a, &b, 0.5).landmarks[0];
    assert_eq!((found.a_in_b, found.b_in_a), (0.5, 1.0));
}

#[test]
fn the_default_tolerance_is_a_share_of_as_diagonal() {
    let a = line("ridge", &[p(0.0, 0.0, 0.0), p(3.0, 4.0, 12.0)]);
    assert!((Tolerance::DEFAULT.resolve(&a).unwrap() - 0.065).abs() < 1e-12);
    assert!(Tolerance::World(0.0).resolve(&a).is_err());
    assert!(Tolerance::DEFAULT.resolve(&Features::default()).is_err());
}

#[test]
fn tolerances_read_as_lengths_or_percentages() {
    assert_eq!("1.5".parse::<Tolerance>().unwrap(), Tolerance::World(1.5));
    assert_eq!(
        " 0.5% ".parse::<Tolerance>().unwrap(),
        Tolerance::OfDiagonal(0.005)
    );
    assert!("half".parse::<Tolerance>().is_err());
    assert_eq!(Tolerance::DEFAULT.to_string(), "0.5%");
}

#[test]
fn a_closed_line_has_its_closing_segment() {
    let square = [
        p(0.0, 0.0, 0.0),
        p(1.0, 0.0, 0.0),
        p(1.0, 1.0, 0.0),
        p(0.0, 1.0, 0.0),
    ];
    let mut closed = Features::default();
    closed.add_line("crest", &square, true);
    let found = compare(&closed, &line("crest", &square), 0.01);
    assert!((found.lines[0].a - 4.0).abs() < 1e-12);
    assert!(
        (found.lines[0].a_in_b - 0.75).abs() < 0.01,
        "{}",
        found.lines[0].a_in_b
    );
}

#[test]
fn a_tolerance_far_below_the_lengths_costs_bounded_work() {
    // A hundred million pieces of a tenth of a micrometre would be asked for.
    let a = line("ridge", &[p(0.0, 0.0, 0.0), p(10.0, 0.0, 0.0)]);
    let b = line("ridge", &[p(0.0, 0.0, 0.0), p(5.0, 0.0, 0.0)]);
    let found = &compare(&a, &b, 1e-7).lines[0];
    assert!((found.a_in_b - 0.5).abs() < 1e-4, "{}", found.a_in_b);
    assert!((found.b_in_a - 1.0).abs() < 1e-12);
}

#[test]
fn a_file_without_a_frame_meets_the_other_as_it_was_written() {
    // A mesh's lines (no frame) against its markups (LPS, held in RAS).
    let points = [p(1.0, 2.0, 3.0), p(4.0, 5.0, 6.0)];
    let raw = line("ridge", &points);
    let mut markups = line("ridge", &points.map(|q| Space::Lps.to_ras(&q)));
    markups.declared = Some(Space::Lps);
    assert_eq!(compare(&raw, &markups, 0.01).lines[0].a_in_b, 0.0);
    let (a, b) = in_one_frame(raw.clone(), markups.clone());
    assert!((compare(&a, &b, 0.01).lines[0].a_in_b - 1.0).abs() < 1e-12);
    // Both with frames: both in RAS already, left as they are.
    let mut nifti = line("ridge", &points.map(|q| Space::Lps.to_ras(&q)));
    nifti.declared = Some(Space::Ras);
    let (a, b) = in_one_frame(nifti, markups);
    assert!((compare(&a, &b, 0.01).lines[0].a_in_b - 1.0).abs() < 1e-12);
}

/// Lines of two kinds, one closed, in a frame, as the jobs write them.
fn written_lines() -> FeatureLines {
    let mut lines = FeatureLines::new("a test");
    lines.space = Some(Space::Lps);
    let square = vec![
        p(0.0, 0.0, 0.0),
        p(1.0, 0.0, 0.0),
        p(1.0, 1.0, 0.5),
        p(0.0, 1.0, 0.0),
    ];
    lines.push(Polyline::new(LineKind::Ridge, true, 2.5, square));
    let bend = vec![
        p(0.1, 0.2, 0.3),
        p(0.4, 0.25, 1.0 / 3.0),
        p(2.0, -1.0, 1e-7),
    ];
    lines.push(Polyline::new(LineKind::Valley, false, 3.0, bend));
    lines
}

#[test]
fn obj_and_vtk_lines_read_as_the_json_of_the_same_lines() {
    let folder = tempfile::tempdir().unwrap();
    let lines = written_lines();
    let expected = Features::of_lines(&lines);
    for name in ["lines.obj", "lines.vtk", "lines.json"] {
        let path = folder.path().join(name);
        crate::lines::write_lines(&path, &lines).unwrap();
        let read = Features::read(&path).unwrap();
        assert_eq!(read, expected, "{name}");
        assert_eq!(read.line_counts["ridge"], 1, "{name}");
        // The closed square's four segments, its closing one included.
        assert_eq!(read.segments["ridge"].len(), 4, "{name}");
    }
    // PLY holds 32-bit floats: the same segments to their precision.
    let path = folder.path().join("lines.ply");
    crate::lines::write_lines(&path, &lines).unwrap();
    let read = Features::read(&path).unwrap();
    assert_eq!(read.line_counts, expected.line_counts);
    assert_eq!(read.declared, expected.declared);
    for (kind, segments) in &expected.segments {
        let near = read.segments[kind]
            .iter()
            .zip(segments)
            .all(|(a, b)| (0..2).all(|end| (a[end] - b[end]).norm() < 1e-6));
        assert!(
            near && read.segments[kind].len() == segments.len(),
            "{kind}"
        );
    }
}

#[test]
fn another_programs_obj_polylines_are_lines_of_no_kind() {
    let folder = tempfile::tempdir().unwrap();
    let path = folder.path().join("drawn.obj");
    // Corners with texture indices, relative indices, a closed triangle, and a
    // lone vertex record, as Blender and others write polylines.
    let text = "o Curve\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nl 1/1 2/1 3/1 1/1\nv 5 5 5\nv 6 5 5\nl -2 -1\n";
    std::fs::write(&path, text).unwrap();
    let read = Features::read(&path).unwrap();
    assert_eq!(read.declared, None);
    assert_eq!(read.line_counts[line_files::UNNAMED_KIND], 2);
    let segments = &read.segments[line_files::UNNAMED_KIND];
    assert_eq!(segments.len(), 4);
    assert_eq!(segments[2], [p(1.0, 1.0, 0.0), p(0.0, 0.0, 0.0)]);
    assert_eq!(segments[3], [p(5.0, 5.0, 5.0), p(6.0, 5.0, 5.0)]);
}

#[test]
fn vtk_5_1_cells_and_field_arrays_give_the_kinds() {
    let folder = tempfile::tempdir().unwrap();
    let path = folder.path().join("lines.vtk");
    let text = "# vtk DataFile Version 5.1\nlines SPACE=RAS\nASCII\nDATASET POLYDATA\n\
        POINTS 4 float\n0 0 0 1 0 0 2 0 0 3 1 0\n\
        LINES 3 4\nOFFSETS vtktypeint64\n0 2 4\nCONNECTIVITY vtktypeint64\n0 1 2 3\n\
        CELL_DATA 2\nFIELD FieldData 1\nkind 1 2 int\n1 0\n";
    std::fs::write(&path, text).unwrap();
    let read = Features::read(&path).unwrap();
    assert_eq!(read.declared, Some(Space::Ras));
    assert_eq!(
        read.segments["valley"],
        vec![[p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0)]]
    );
    assert_eq!(
        read.segments["ridge"],
        vec![[p(2.0, 0.0, 0.0), p(3.0, 1.0, 0.0)]]
    );
}

#[test]
fn a_mesh_or_a_broken_lines_file_is_refused_naming_it() {
    let folder = tempfile::tempdir().unwrap();
    let refused = |name: &str, text: &str, says: &str| {
        let path = folder.path().join(name);
        std::fs::write(&path, text).unwrap();
        let message = Features::read(&path).unwrap_err().to_string();
        assert!(
            message.contains(name) && message.contains(says),
            "{message}"
        );
    };
    refused("mesh.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "a mesh");
    let ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
        property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
        0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    refused("mesh.ply", ply, "a mesh");
    let edge = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n\
        property float z\nelement edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n\
        0 0 0\n1 0 0\n";
    refused("far.ply", &format!("{edge}0 5\n"), "joins vertices 0 and 5");
    refused("short.ply", edge, "edge");
    refused(
        "far.obj",
        "v 0 0 0\nv 1 0 0\nl 1 3\n",
        "line 3: a line refers to point 3",
    );
    refused(
        "zero.obj",
        "v 0 0 0\nl 0 1\n",
        "line 2: `0` is not a vertex index",
    );
    refused(
        "nan.obj",
        "v 0 NaN 0\n",
        "line 1: the coordinate NaN is not finite",
    );
    let header = "# vtk DataFile Version 3.0\nt\n";
    refused("binary.vtk", &format!("{header}BINARY\n"), "only ASCII");
    refused(
        "mesh.vtk",
        &format!("{header}ASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\nPOLYGONS 1 4\n3 0 1 2\n"),
        "a mesh",
    );
    refused(
        "short.vtk",
        &format!("{header}ASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0 1 0 0\n"),
        "ends early",
    );
    refused(
        "huge.vtk",
        &format!("{header}ASCII\nDATASET POLYDATA\nPOINTS 1 float\n0 0 0\nLINES 18446744073709551615 2\n2 0 0\n"),
        "ends early",
    );
}
