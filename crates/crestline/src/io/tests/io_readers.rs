//! Mesh readers and writers: real files, hand-made malformed inputs (each a clear
//! error, never a panic) and write/read round trips.

use std::cell::Cell;
use std::path::{Path, PathBuf};

use crate::io::{
    read_mesh, read_mesh_with_progress, read_obj, read_off, read_ply, read_stl, write_obj,
    write_ply, VertexAttribute, SUPPORTED_MESH_EXTENSIONS,
};
use crate::mesh::{Mesh, TriangleSoup};
use crate::{Error, Result, Vector};

fn mesh_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../meshes")
        .join(name)
}

/// The message of an error, asserting every key word appears in it.
fn assert_error(result: Result<TriangleSoup>, words: &[&str]) -> String {
    let message = result.expect_err("input should be rejected").to_string();
    for word in words {
        assert!(
            message.contains(word),
            "'{word}' missing from the message: {message}"
        );
    }
    message
}

fn assert_counts(soup: &TriangleSoup, vertices: usize, triangles: usize) {
    assert_eq!(soup.positions.len(), vertices);
    assert_eq!(soup.triangles.len(), triangles);
    let n = soup.positions.len() as u32;
    assert!(soup.triangles.iter().flatten().all(|&i| i < n));
}

/// Write `bytes` as `name` in a fresh temporary directory.
fn temp_file(name: &str, bytes: &[u8]) -> (PathBuf, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    (path, dir)
}

// ---------------------------------------------------------------------------
// Real files and dispatch

#[test]
fn reads_the_real_meshes() {
    let expected = [
        ("bunny.obj", 28_088, 56_172),
        ("bunny_small.obj", 1_839, 3_674),
        ("cow.obj", 2_904, 5_804),
        ("airplane.obj", 7_017, 10_796),
        ("fsaverage5_pial_left.obj", 10_242, 20_480),
        ("bone.ply", 1_872, 3_022),
    ];
    for (name, vertices, triangles) in expected {
        let soup = read_mesh(&mesh_path(name)).unwrap();
        assert_counts(&soup, vertices, triangles);
        assert!(soup
            .positions
            .iter()
            .all(|p| p.coords.iter().all(|c| c.is_finite())));
    }
}

#[test]
fn obj_keeps_the_file_vertex_order() {
    let soup = read_mesh(&mesh_path("bunny.obj")).unwrap();
    assert_eq!(
        soup.positions[0].coords,
        Vector::new(0.282611, 0.305877, 0.341089)
    );
    assert_eq!(soup.triangles[0], [0, 1, 2]);
}

#[test]
fn bone_ply_keeps_its_extra_vertex_properties() {
    let soup = read_mesh(&mesh_path("bone.ply")).unwrap();
    let names: Vec<&str> = soup
        .vertex_scalars
        .iter()
        .map(|p| p.name.as_str())
        .collect();
    assert_eq!(names, ["flags", "red", "green", "blue", "alpha"]);
    for property in &soup.vertex_scalars {
        assert_eq!(property.values.len(), 1_872);
    }
    let red = &soup.vertex_scalars[1].values;
    assert!(red
        .iter()
        .all(|&r| (0.0..=255.0).contains(&r) && r.fract() == 0.0));
}

#[test]
fn extension_is_case_insensitive() {
    let bytes = std::fs::read(mesh_path("bunny_small.obj")).unwrap();
    let (path, _dir) = temp_file("BUNNY.OBJ", &bytes);
    assert_counts(&read_mesh(&path).unwrap(), 1_839, 3_674);
}

#[test]
fn unknown_or_missing_extension_lists_the_supported_ones() {
    for name in ["mesh.txt", "mesh"] {
        let (path, _dir) = temp_file(name, b"v 0 0 0\n");
        let err = read_mesh(&path).unwrap_err();
        assert!(matches!(err, Error::File { .. }));
        let message = err.to_string();
        assert!(message.contains(name), "{message}");
        for ext in SUPPORTED_MESH_EXTENSIONS {
            assert!(message.contains(ext), "{message}");
        }
    }
}

#[test]
fn missing_file_and_directory_are_file_errors() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("nothing.obj");
    let err = read_mesh(&missing).unwrap_err();
    assert!(matches!(err, Error::File { .. }));
    assert!(
        err.to_string().contains("nothing.obj: no such file"),
        "{err}"
    );

    let folder = dir.path().join("folder.ply");
    std::fs::create_dir(&folder).unwrap();
    let err = read_mesh(&folder).unwrap_err();
    assert!(matches!(err, Error::File { .. }));
    assert!(err.to_string().contains("is a directory"), "{err}");
}

#[test]
fn parse_errors_name_the_file() {
    let (path, _dir) = temp_file("broken.off", b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
    let err = read_mesh(&path).unwrap_err();
    assert!(matches!(err, Error::File { .. }));
    let message = err.to_string();
    assert!(message.contains("broken.off"), "{message}");
    assert!(message.contains("line 6"), "{message}");
}

#[test]
fn empty_files_are_errors_in_every_format() {
    for ext in SUPPORTED_MESH_EXTENSIONS {
        let (path, _dir) = temp_file(&format!("empty.{ext}"), b"");
        let message = read_mesh(&path).unwrap_err().to_string();
        assert!(message.contains("empty"), "{message}");
        assert!(message.contains(&format!("empty.{ext}")), "{message}");
    }
}

#[test]
fn progress_reaches_the_file_size() {
    let path = mesh_path("bunny.obj");
    let total = std::fs::metadata(&path).unwrap().len();
    let calls = Cell::new(0);
    let last = Cell::new((0, 0));
    let progress = |read: u64, size: u64| {
        assert!(read >= last.get().0);
        calls.set(calls.get() + 1);
        last.set((read, size));
    };
    read_mesh_with_progress(&path, &progress).unwrap();
    assert!(calls.get() >= 3, "{} calls", calls.get());
    assert_eq!(last.get(), (total, total));
}

// ---------------------------------------------------------------------------
// OBJ

#[test]
fn obj_polygons_relative_indices_and_corner_forms() {
    let text = "# quad and triangle\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\n\
                g side\nf 1/1/1 2/2/1 3//1 4\nf -4 -3 -1\nl 1 2\n";
    let soup = read_obj(text.as_bytes()).unwrap();
    assert_counts(&soup, 4, 3);
    assert_eq!(soup.triangles, [[0, 1, 2], [0, 2, 3], [0, 1, 3]]);
}

#[test]
fn obj_faces_may_refer_to_later_vertices() {
    let soup = read_obj(b"f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap();
    assert_counts(&soup, 3, 1);
}

#[test]
fn obj_nan_coordinates_pass_through() {
    let soup = read_obj(b"v nan 0 0\nv 1 inf 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    assert!(soup.positions[0].x.is_nan());
    assert!(soup.positions[1].y.is_infinite());
}

#[test]
fn obj_index_out_of_range_names_the_line() {
    assert_error(
        read_obj(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n"),
        &["line 5", "vertex 9", "3 vertices"],
    );
    assert_error(
        read_obj(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"),
        &["line 4", "index 0"],
    );
    assert_error(
        read_obj(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n"),
        &["line 4", "-4", "before the first vertex"],
    );
}

#[test]
fn obj_unparsable_numbers_and_short_records() {
    assert_error(read_obj(b"v 0 0 0\nv 1 abc 0\n"), &["line 2", "'abc'"]);
    assert_error(read_obj(b"v 0 0 0\nv 1 0 0\nf 1 x 2\n"), &["line 3", "'x'"]);
    // A file cut in the middle of a vertex.
    assert_error(read_obj(b"v 0 0 0\nv 1 0"), &["line 2", "3 coordinates"]);
    assert_error(
        read_obj(b"v 0 0 0\nv 1 0 0\nf 1 2\n"),
        &["line 3", "at least 3 corners"],
    );
}

#[test]
fn obj_garbage_and_empty_input() {
    let garbage: Vec<u8> = (0..2000u32).map(|i| (i * 7919 % 251) as u8).collect();
    assert_error(read_obj(&garbage), &["line 1", "not text"]);
    assert_error(read_obj(b""), &["empty"]);
}

// ---------------------------------------------------------------------------
// PLY

const ASCII_PLY: &str = "ply\nformat ascii 1.0\ncomment a quad\nelement vertex 4\n\
property float x\nproperty float y\nproperty float z\nproperty float nx\n\
property uchar red\nproperty double quality\nelement face 1\n\
property list uchar int vertex_indices\nelement edge 1\nproperty int vertex1\n\
property int vertex2\nend_header\n\
0 0 0 1 10 0.5\n1 0 0 1 20 1.5\n1 1 0 1 30 2.5\n0 1 0 1 40 3.5\n4 0 1 2 3\n0 1\n";

#[test]
fn ascii_ply_fans_polygons_and_keeps_scalars() {
    let soup = read_ply(ASCII_PLY.as_bytes()).unwrap();
    assert_counts(&soup, 4, 2);
    assert_eq!(soup.triangles, [[0, 1, 2], [0, 2, 3]]);
    let names: Vec<&str> = soup
        .vertex_scalars
        .iter()
        .map(|p| p.name.as_str())
        .collect();
    assert_eq!(names, ["red", "quality"]);
    assert_eq!(soup.vertex_scalars[0].values, [10.0, 20.0, 30.0, 40.0]);
    assert_eq!(soup.vertex_scalars[1].values, [0.5, 1.5, 2.5, 3.5]);
}

#[test]
fn ascii_ply_errors_name_the_line() {
    let bad_number = ASCII_PLY.replace("1 1 0 1 30", "1 one 0 1 30");
    assert_error(read_ply(bad_number.as_bytes()), &["line 19", "vertex 2"]);
    let out_of_range = ASCII_PLY.replace("4 0 1 2 3", "4 0 1 2 4");
    assert_error(
        read_ply(out_of_range.as_bytes()),
        &["line 21", "face 0", "index 4", "out of range"],
    );
    let two_corners = ASCII_PLY.replace("4 0 1 2 3", "2 0 1");
    assert_error(read_ply(two_corners.as_bytes()), &["face 0", "at least 3"]);
    let header = ASCII_PLY.replace("comment a quad", "bogus words");
    assert_error(read_ply(header.as_bytes()), &["line 3"]);
}

#[test]
fn ascii_ply_with_absurd_count_is_truncated_not_allocated() {
    let text = "ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\n\
                property float y\nproperty float z\nelement face 1\n\
                property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
    assert_error(
        read_ply(text.as_bytes()),
        &["ends after 3 of 4000000000 'vertex' elements"],
    );
}

/// A binary PLY of a unit square (two triangles) in either byte order, with a
/// `quality` property; `faces` replaces the face records if given.
fn binary_ply(big_endian: bool, vertex_count: &str, faces: Option<&[u8]>) -> Vec<u8> {
    let format = if big_endian {
        "binary_big_endian"
    } else {
        "binary_little_endian"
    };
    let mut bytes = format!(
        "ply\nformat {format} 1.0\nelement vertex {vertex_count}\nproperty float x\n\
         property float y\nproperty float z\nproperty ushort quality\nelement face 2\n\
         property list uchar uint vertex_index\nend_header\n"
    )
    .into_bytes();
    let f32_bytes = |v: f32| {
        if big_endian {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        }
    };
    let corners = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, f32::NAN],
    ];
    for (i, corner) in corners.iter().enumerate() {
        for &c in corner {
            bytes.extend(f32_bytes(c));
        }
        let quality = 100 * i as u16;
        bytes.extend(if big_endian {
            quality.to_be_bytes()
        } else {
            quality.to_le_bytes()
        });
    }
    match faces {
        Some(records) => bytes.extend(records),
        None => {
            for face in [[0u32, 1, 2], [0, 2, 3]] {
                bytes.push(3);
                for i in face {
                    bytes.extend(if big_endian {
                        i.to_be_bytes()
                    } else {
                        i.to_le_bytes()
                    });
                }
            }
        }
    }
    bytes
}

#[test]
fn binary_ply_in_both_byte_orders() {
    for big_endian in [false, true] {
        let soup = read_ply(&binary_ply(big_endian, "4", None)).unwrap();
        assert_counts(&soup, 4, 2);
        assert_eq!(soup.triangles, [[0, 1, 2], [0, 2, 3]]);
        assert_eq!(soup.positions[2].coords, Vector::new(1.0, 1.0, 0.0));
        // NaN is the mesh builder's business, not the reader's.
        assert!(soup.positions[3].z.is_nan());
        assert_eq!(soup.vertex_scalars[0].name, "quality");
        assert_eq!(soup.vertex_scalars[0].values, [0.0, 100.0, 200.0, 300.0]);
    }
}

#[test]
fn binary_ply_truncated_and_absurd_counts() {
    let full = binary_ply(false, "4", None);
    for cut in [full.len() - 1, full.len() - 13, full.len() - 30] {
        let message = assert_error(read_ply(&full[..cut]), &["ends after"]);
        assert!(message.contains("of 2 'face'") || message.contains("of 4 'vertex'"));
    }
    assert_error(
        read_ply(&binary_ply(false, "4000000000", None)),
        &["ends after", "of 4000000000 'vertex'"],
    );
}

#[test]
fn binary_ply_bad_faces_name_the_face_and_offset() {
    let mut records = vec![3];
    records.extend([0u32, 1, 2].iter().flat_map(|i| i.to_le_bytes()));
    records.push(3);
    records.extend([0u32, 2, 99].iter().flat_map(|i| i.to_le_bytes()));
    assert_error(
        read_ply(&binary_ply(false, "4", Some(&records))),
        &["face 1", "byte", "index 99", "out of range", "4 vertices"],
    );
}

#[test]
fn ply_garbage_header_and_missing_elements() {
    let garbage: Vec<u8> = (0..500u32).map(|i| (i * 31 % 256) as u8).collect();
    assert_error(read_ply(&garbage), &["not a PLY file"]);
    assert_error(
        read_ply(b"ply\nformat ascii 1.0\nelement vertex 1\n"),
        &["end_header"],
    );
    assert_error(
        read_ply(b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n"),
        &["no 'face' element"],
    );
    assert_error(
        read_ply(
            b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
              element face 0\nproperty list uchar int vertex_indices\nend_header\n0 0\n",
        ),
        &["no scalar property 'z'"],
    );
    assert_error(
        read_ply(
            b"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n\
              property float z\nelement face 0\nproperty list uchar float vertex_indices\n\
              end_header\n",
        ),
        &["floating-point"],
    );
    assert_error(read_ply(b"ply\n"), &["end_header"]);
}

// ---------------------------------------------------------------------------
// OFF

#[test]
fn off_variants_comments_and_polygons() {
    let text = "# a square\nOFF\n4 1 4\n0 0 0\n1 0 0 # corner\n\n1 1 0\n0 1 0\n4 0 1 2 3 255 0 0\n";
    let soup = read_off(text.as_bytes()).unwrap();
    assert_counts(&soup, 4, 2);
    assert_eq!(soup.triangles, [[0, 1, 2], [0, 2, 3]]);

    let coff = "COFF 3 1 0\n0 0 0 1 0 0 1\n1 0 0 0 1 0 1\n0 1 nan 0 0 1 1\n3 0 1 2\n";
    let soup = read_off(coff.as_bytes()).unwrap();
    assert_counts(&soup, 3, 1);
    assert!(soup.positions[2].z.is_nan());

    let no_keyword = "3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 2 1 0\n";
    assert_counts(&read_off(no_keyword.as_bytes()).unwrap(), 3, 1);
}

#[test]
fn off_malformed_inputs() {
    assert_error(
        read_off(b"OFF\n999999999 999999999 0\n0 0 0\n"),
        &["ends after 1 of 999999999 vertices"],
    );
    assert_error(
        read_off(b"OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
        &["ends after 1 of 2 faces"],
    );
    assert_error(
        read_off(b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"),
        &["line 6", "face 0", "index 3", "out of range"],
    );
    assert_error(
        read_off(b"OFF\n3 1 0\n0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n"),
        &["line 4", "vertex 1", "'zero'"],
    );
    assert_error(
        read_off(b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n"),
        &["line 6", "4 corners", "only 3"],
    );
    assert_error(read_off(b"OFF\n3 x 0\n"), &["line 2", "face count"]);
    assert_error(read_off(b"4OFF\n"), &["unsupported OFF variant"]);
    assert_error(read_off(b"solid cube\n"), &["not an OFF file"]);
    assert_error(read_off(b"# only a comment\n"), &["no OFF header"]);
    let garbage: Vec<u8> = (0..300u32).map(|i| (i * 131 % 256) as u8).collect();
    assert_error(read_off(&garbage), &["not"]);
}

// ---------------------------------------------------------------------------
// STL

/// A binary STL with the given header text and triangles.
fn binary_stl(header: &str, triangles: &[[[f32; 3]; 3]]) -> Vec<u8> {
    let mut bytes = header.as_bytes().to_vec();
    bytes.resize(80, b' ');
    bytes.extend((triangles.len() as u32).to_le_bytes());
    for triangle in triangles {
        bytes.extend([0u8; 12]);
        for corner in triangle {
            for c in corner {
                bytes.extend(c.to_le_bytes());
            }
        }
        bytes.extend([0u8; 2]);
    }
    bytes
}

const TRIANGLES: [[[f32; 3]; 3]; 2] = [
    [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
    [[1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, f32::NAN]],
];

#[test]
fn binary_stl_even_when_the_header_says_solid() {
    for header in ["binary", "solid exported by a tool that says solid"] {
        let soup = read_stl(&binary_stl(header, &TRIANGLES)).unwrap();
        assert_counts(&soup, 6, 2);
        assert_eq!(soup.triangles, [[0, 1, 2], [3, 4, 5]]);
        assert_eq!(soup.positions[4].coords, Vector::new(1.0, 1.0, 0.0));
        assert!(soup.positions[5].z.is_nan());
    }
}

#[test]
fn binary_stl_truncated_or_with_absurd_count() {
    let full = binary_stl("binary", &TRIANGLES);
    assert_error(
        read_stl(&full[..full.len() - 7]),
        &["ends after 1 of 2 triangles"],
    );
    let mut absurd = full[..84].to_vec();
    absurd[80..84].copy_from_slice(&(1u32 << 31).to_le_bytes());
    assert_error(read_stl(&absurd), &["ends after 0 of 2147483648 triangles"]);
    assert_error(read_stl(b"\x01\x02 too short"), &["not an STL file"]);
    let mut extra = full.clone();
    extra.extend([0u8; 9]);
    assert_error(read_stl(&extra), &["9 bytes follow the 2 triangles"]);
}

const ASCII_STL: &str = "solid square
  facet normal 0 0 1
    outer loop
      vertex 0 0 0
      vertex 1 0 0
      vertex 0 1 0
    endloop
  endfacet
  facet normal 0 0 1
    outer loop
      vertex 1 0 0
      vertex 1 1 0
      vertex 0 1 0
    endloop
  endfacet
endsolid square
";

#[test]
fn ascii_stl() {
    let soup = read_stl(ASCII_STL.as_bytes()).unwrap();
    assert_counts(&soup, 6, 2);
    assert_eq!(soup.positions[4].coords, Vector::new(1.0, 1.0, 0.0));
    let nan = ASCII_STL.replace("vertex 1 1 0", "vertex 1 NaN 0");
    assert!(read_stl(nan.as_bytes()).unwrap().positions[4].y.is_nan());
}

#[test]
fn ascii_stl_malformed_inputs() {
    let cut = &ASCII_STL[..ASCII_STL.find("vertex 1 1 0").unwrap()];
    assert_error(read_stl(cut.as_bytes()), &["ends inside a solid"]);
    let bad = ASCII_STL.replace("vertex 1 1 0", "vertex 1 1 zero");
    assert_error(read_stl(bad.as_bytes()), &["line 12", "'zero'"]);
    let stray = ASCII_STL.replace("  endfacet\nendsolid", "  vertex 1 2 3\nendsolid");
    assert_error(
        read_stl(stray.as_bytes()),
        &["line 15", "unexpected 'vertex'"],
    );
    let two = ASCII_STL.replace("      vertex 0 0 0\n", "");
    assert_error(read_stl(two.as_bytes()), &["line 6", "at least 3 corners"]);
    let mut binary_garbage = b"solid ".to_vec();
    binary_garbage.extend((0..200u32).map(|i| (i * 97 % 256) as u8));
    assert_error(read_stl(&binary_garbage), &["not text"]);
}

// ---------------------------------------------------------------------------
// Hostile inputs: absurd counts, duplicate elements, control bytes

/// An ASCII PLY triangle whose face line is `face`.
fn ascii_ply_triangle(face: &str) -> String {
    format!(
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
         property float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n\
         0 0 0\n1 0 0\n0 1 0\n{face}\n"
    )
}

/// The error of reading `bytes` as the file `name`, checked to be one line naming
/// the file, without control characters or Rust debug text.
fn file_error(name: &str, bytes: &[u8]) -> String {
    let (path, _dir) = temp_file(name, bytes);
    let message = read_mesh(&path)
        .expect_err("input should be rejected")
        .to_string();
    assert!(
        message.starts_with(&format!("{}: ", path.display())),
        "{message}"
    );
    assert!(!message.chars().any(char::is_control), "{message:?}");
    for debug in ["{ ", "kind:", "Some(", "PropertyDef", "ParseIntError"] {
        assert!(!message.contains(debug), "{message}");
    }
    message
}

#[test]
fn ply_list_count_of_2_pow_62_is_rejected() {
    let huge = format!("{} 0 1 2", 1u64 << 62);
    let message = file_error("huge_list.ply", ascii_ply_triangle(&huge).as_bytes());
    for words in [
        "line 13: face 0",
        "'4611686018427387904' is out of range for the type uint",
    ] {
        assert!(message.contains(words), "{message}");
    }
    assert_error(
        read_ply(ascii_ply_triangle("4294967295 0 1 2").as_bytes()),
        &["line 13", "face 0", "4294967295 corners", "at most 1024"],
    );
    assert_error(
        read_ply(ascii_ply_triangle("2 0 1").as_bytes()),
        &["face 0", "at least 3 corners, found 2"],
    );
    assert_error(
        read_off(format!("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n{huge}\n").as_bytes()),
        &["line 6", "face 0", "at most 1024"],
    );
    // A binary face list with a count of 2^32 - 1, in both readers (the single-list
    // fast path and the record-by-record path of a face with a second property).
    for extra in ["", "property uchar flags\n"] {
        let mut bytes = format!(
            "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n\
             property float y\nproperty float z\nelement face 1\n\
             property list uint int vertex_indices\n{extra}end_header\n"
        )
        .into_bytes();
        bytes.extend([0u8; 36]);
        let offset = format!("face 0 (byte {})", bytes.len());
        bytes.extend(u32::MAX.to_le_bytes());
        bytes.extend([0u8; 13]);
        assert_error(read_ply(&bytes), &[&offset, "4294967295 corners"]);
    }
}

#[test]
fn ply_duplicate_element_names_are_rejected() {
    let text = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
                element vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
                end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n0 0 0\n1 0 0\n0 1 0\n";
    let message = assert_error(
        read_ply(text.as_bytes()),
        &["line 9", "a second element 'vertex'", "line 3", "unique"],
    );
    assert!(!message.contains("corners"), "{message}");
    let twice = ASCII_PLY.replace("property float y\n", "property float y\nproperty float x\n");
    assert_error(
        read_ply(twice.as_bytes()),
        &["line 7", "a second property 'x' in element 'vertex'"],
    );
}

#[test]
fn ply_huge_element_count_in_a_tiny_file_fails_at_once() {
    let mut text = ascii_ply_triangle("3 0 1 2").replace("vertex 3", "vertex 1000000000000000");
    text += &"# padding to about a kilobyte\n".repeat(30);
    let start = std::time::Instant::now();
    assert_error(
        read_ply(text.as_bytes()),
        &["ends after 34 of 1000000000000000 'vertex' elements"],
    );
    let mut binary = b"ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty double x\n\
                       property double y\nproperty double z\nelement face 1000000000000000\n\
                       property list uchar int vertex_indices\nend_header\n"
        .to_vec();
    binary.resize(1000, 0);
    assert_error(read_ply(&binary), &["of 1000000000000000 'face' elements"]);
    assert!(start.elapsed().as_secs_f64() < 1.0);
}

#[test]
fn ply_header_count_overflow_and_value_overflow_are_plain_words() {
    let text = ascii_ply_triangle("3 0 1 2").replace("vertex 3", "vertex 99999999999999999999");
    assert_error(
        read_ply(text.as_bytes()),
        &[
            "line 3",
            "count of element 'vertex' is too large",
            "99999999999999999999",
        ],
    );
    let text = ascii_ply_triangle("3 0 1 2").replace("vertex 3", "vertex -3");
    assert_error(
        read_ply(text.as_bytes()),
        &["line 3", "'-3' is not a non-negative integer"],
    );
    let uchar = ASCII_PLY.replace("1 1 0 1 30 2.5", "1 1 0 1 300 2.5");
    assert_error(
        read_ply(uchar.as_bytes()),
        &[
            "line 19",
            "vertex 2",
            "'300' is out of range for the type uchar",
        ],
    );
    let message = file_error(
        "overflow.ply",
        ascii_ply_triangle("99999999999999999999999 0 1 2").as_bytes(),
    );
    assert!(
        message.contains("out of range for the type uint"),
        "{message}"
    );
    let message = file_error(
        "orphan.ply",
        b"ply\nformat ascii 1.0\nproperty float x\nend_header\n",
    );
    assert!(
        message.contains("line 3: a 'property' line before any 'element'"),
        "{message}"
    );
    let message = file_error(
        "two_formats.ply",
        b"ply\nformat ascii 1.0\nformat binary_big_endian 1.0\nend_header\n",
    );
    assert!(
        message.contains("line 3: a second 'format' line"),
        "{message}"
    );
}

#[test]
fn control_bytes_of_the_input_are_escaped_in_messages() {
    let message = file_error("bell.obj", b"v 0 0 0\nv 1 0 0\nv 0 1\x07 0\nf 1 2 3\n");
    assert!(
        message.contains(r"line 3: cannot read '1\x07' as a number"),
        "{message}"
    );
    let message = file_error(
        "escape.off",
        b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 \x1b[2J\n",
    );
    assert!(message.contains(r"'\x1b[2J'"), "{message}");
    let header = ascii_ply_triangle("3 0 1 2").replace("property float y", "property flo\u{7}at y");
    let message = file_error("bell.ply", header.as_bytes());
    assert!(
        message.contains(r"line 5: unknown PLY type 'flo\x07at'"),
        "{message}"
    );
    let token = ascii_ply_triangle("3 0 1\x00 2");
    let message = file_error("nul_token.ply", token.as_bytes());
    assert!(message.contains(r"'1\x00'"), "{message}");
    let long = format!("v 0 0 {}\n", "7".repeat(200) + "x");
    let message = file_error("long.obj", long.as_bytes());
    assert!(message.len() < 200, "{message}");
}

// ---------------------------------------------------------------------------
// Writers

fn bunny() -> Mesh {
    let soup = read_mesh(&mesh_path("bunny.obj")).unwrap();
    Mesh::from_soup(soup).unwrap().0
}

#[test]
fn obj_round_trip_is_exact() {
    let mesh = bunny();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bunny_out.obj");
    write_obj(&path, &mesh).unwrap();
    let soup = read_mesh(&path).unwrap();
    assert_eq!(soup.positions, mesh.positions());
    assert_eq!(soup.triangles, mesh.triangles());
}

#[test]
fn ply_round_trip_with_attributes() {
    let mesh = bunny();
    let n = mesh.vertex_count();
    let height: Vec<f64> = mesh.positions().iter().map(|p| p.y).collect();
    let directions: Vec<Vector> = mesh.positions().iter().map(|p| p.coords * 2.0).collect();
    let attributes = [
        VertexAttribute::Scalar {
            name: "height",
            values: &height,
        },
        VertexAttribute::Vector {
            name: "dir",
            values: &directions,
        },
    ];
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bunny_out.ply");
    write_ply(&path, &mesh, &attributes).unwrap();
    let soup = read_mesh(&path).unwrap();

    // Positions and attributes are written in double precision: exact.
    assert_eq!(soup.positions.len(), n);
    assert_eq!(soup.positions, mesh.positions());
    assert_eq!(soup.triangles, mesh.triangles());
    let names: Vec<&str> = soup
        .vertex_scalars
        .iter()
        .map(|p| p.name.as_str())
        .collect();
    assert_eq!(names, ["height", "dir_x", "dir_y", "dir_z"]);
    assert_eq!(soup.vertex_scalars[0].values, height);
    let expected: Vec<f64> = directions.iter().map(|d| d.z).collect();
    assert_eq!(soup.vertex_scalars[3].values, expected);
}

#[test]
fn ply_writer_rejects_bad_attributes_and_leaves_no_file() {
    let mesh = bunny();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.ply");
    let short = vec![0.0; 3];
    let full = vec![0.0; mesh.vertex_count()];
    let cases = [
        (
            VertexAttribute::Scalar {
                name: "short",
                values: &short,
            },
            "3 values",
        ),
        (
            VertexAttribute::Scalar {
                name: "two words",
                values: &full,
            },
            "not a valid",
        ),
        (
            VertexAttribute::Scalar {
                name: "x",
                values: &full,
            },
            "given twice",
        ),
    ];
    for (attribute, words) in cases {
        let err = write_ply(&path, &mesh, &[attribute]).unwrap_err();
        assert!(matches!(err, Error::Argument(_)), "{err}");
        assert!(err.to_string().contains(words), "{err}");
        assert!(!path.exists());
    }
    let missing_dir = dir.path().join("no/such/dir/out.ply");
    assert!(matches!(
        write_ply(&missing_dir, &mesh, &[]),
        Err(Error::File { .. })
    ));
    assert!(std::fs::read_dir(dir.path()).unwrap().next().is_none());
}
