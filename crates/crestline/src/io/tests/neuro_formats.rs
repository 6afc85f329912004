//! FreeSurfer and GIfTI surfaces, per-vertex values and labels: files told by
//! their content, coordinates placed through the volume geometry and written
//! back, and per-vertex outputs that follow the input file's vertices whatever
//! the repairs did.

use std::path::{Path, PathBuf};

use crate::curvature::{estimate_curvature, Quality, ShapeOperator};
use crate::io::freesurfer::{write_surface, VolumeGeometry};
use crate::io::gifti::write_gifti_surface;
use crate::io::{read_mesh, read_vertex_values, Structure};
use crate::jobs::{ridges, RidgesOptions, Surface};
use crate::lines::{
    write_labels, write_vertex_labels, FeatureLines, LineKind, Polyline, SurfaceLocation,
};
use crate::mesh::{Mesh, TriangleSoup, VertexId};
use crate::progress::Silent;
use crate::{Point, Space};

use crate::common;

/// An octahedron (closed, outward) with two extra input vertices: vertex 6 a
/// copy of vertex 0 that one face uses instead (welded), and vertex 7 that no
/// face uses (dropped).
fn octahedron_with_repairs() -> TriangleSoup {
    let mut positions: Vec<Point> = [
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, -1.0],
    ]
    .map(Point::from)
    .to_vec();
    positions.push(positions[0]);
    positions.push(Point::new(5.0, 5.0, 5.0));
    let triangles = vec![
        [6, 1, 2],
        [0, 2, 3],
        [0, 3, 4],
        [0, 4, 1],
        [5, 2, 1],
        [5, 3, 2],
        [5, 4, 3],
        [5, 1, 4],
    ];
    TriangleSoup {
        positions,
        triangles,
        ..TriangleSoup::default()
    }
}

#[test]
fn per_vertex_outputs_follow_the_input_vertices_after_repairs() {
    let (mesh, report) = Mesh::from_soup(octahedron_with_repairs()).unwrap();
    assert_eq!(
        (report.welded_vertices, report.unreferenced_vertices),
        (1, 1)
    );
    assert_eq!(mesh.vertex_count(), 6);
    let inputs = mesh.input_vertices();
    assert_eq!(inputs.len(), 8);
    assert_eq!(inputs[6], inputs[0]);
    assert_eq!(inputs[7], None);
    for (i, v) in inputs.iter().enumerate().take(6) {
        let v = v.expect("a used vertex has a mesh vertex");
        assert_eq!(mesh.position(v), octahedron_with_repairs().positions[i]);
    }

    let field = estimate_curvature(&mesh, &ShapeOperator).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let shape = dir.path().join("lh.mean.shape.gii");
    let curv = dir.path().join("lh.mean.curv");
    field
        .write_values(&shape, &mesh, Quality::Mean, Structure::OTHER)
        .unwrap();
    field
        .write_values(&curv, &mesh, Quality::Mean, Structure::OTHER)
        .unwrap();
    let shape = read_vertex_values(&shape).unwrap();
    let curv = read_vertex_values(&curv).unwrap();
    assert_eq!((shape.len(), curv.len()), (8, 8));
    // The welded copy has its original's value; the dropped vertex has none.
    assert_eq!(shape[6], shape[0]);
    assert!(shape[7].is_nan());
    assert_eq!(curv[7], 0.0);
    let mean = field.mean();
    for i in 0..6 {
        let v = inputs[i].unwrap().idx();
        // A convex surface: crestline's mean curvature is positive,
        // FreeSurfer's negative; both as 32-bit floats.
        assert!(mean[v] > 0.1, "vertex {i}: {}", mean[v]);
        assert_eq!(shape[i], f64::from(mean[v] as f32));
        assert_eq!(curv[i], f64::from(-mean[v] as f32));
    }
}

#[test]
fn labels_follow_the_input_vertices_after_repairs() {
    let (mesh, _) = Mesh::from_soup(octahedron_with_repairs()).unwrap();
    let top = mesh.input_vertices()[0].unwrap();
    let bottom = mesh.input_vertices()[5].unwrap();
    let line = |kind, v: VertexId, w: VertexId| {
        let at = |v: VertexId| SurfaceLocation::Vertex { vertex: v.0 };
        Polyline::new(kind, false, 1.0, vec![mesh.position(v), mesh.position(w)])
            .with_locations(vec![at(v), at(w)])
    };
    let side = mesh.input_vertices()[1].unwrap();
    let mut lines = FeatureLines::new("test");
    lines.push(line(LineKind::Ridge, top, side));
    lines.push(line(LineKind::Valley, bottom, bottom));
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("x.label.gii");
    write_vertex_labels(&path, &lines, &mesh, Structure::OTHER).unwrap();
    let labels = read_vertex_values(&path).unwrap();
    assert_eq!(labels, [1.0, 1.0, 0.0, 0.0, 0.0, 2.0, 1.0, 0.0]);

    let label = dir.path().join("lh.x.label");
    write_vertex_labels(&label, &lines, &mesh, Structure::OTHER).unwrap();
    let text = std::fs::read_to_string(&label).unwrap();
    let rows: Vec<&str> = text.lines().skip(2).collect();
    assert_eq!(text.lines().nth(1), Some("4"));
    assert_eq!(rows[0], "0 0.000 0.000 1.000 1.0000000000");
    assert_eq!(rows[2], "5 0.000 0.000 -1.000 -1.0000000000");
    assert!(rows[3].starts_with("6 "));

    let bad_count = write_labels(&path, &[0; 6], &mesh, Structure::OTHER)
        .unwrap_err()
        .to_string();
    assert!(
        bad_count.contains("6 labels for a surface of 8 vertices"),
        "{bad_count}"
    );
    let bad_label =
        write_labels(&path, &[0, 0, 0, 7, 0, 0, 0, 0], &mesh, Structure::OTHER).unwrap_err();
    assert!(
        bad_label.to_string().contains("vertex 3 has the label 7"),
        "{bad_label}"
    );

    let mut faired = lines.clone();
    faired.lines[0].locations.clear();
    let error = write_vertex_labels(&path, &faired, &mesh, Structure::OTHER)
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("x.label.gii") && error.contains("faired"),
        "{error}"
    );
}

/// A conformed image's geometry with its centre at `c_ras`.
fn geometry(c_ras: [f64; 3]) -> VolumeGeometry {
    VolumeGeometry::conformed("../mri/filled-pretess255.mgz", c_ras)
}

/// The octahedron scaled to 30 mm in scanner RAS, written to `pial` as a
/// FreeSurfer surface with a conformed image's footer: the soup, the scanner
/// positions and the footer.
fn written_pial(pial: &Path) -> (TriangleSoup, Vec<Point>, VolumeGeometry) {
    let soup = octahedron_with_repairs();
    let scanner: Vec<Point> = soup.positions.iter().map(|p| p * 30.0).collect();
    let footer = geometry([1.5, -17.25, 20.0]);
    write_surface(pial, &scanner, &soup.triangles, Some(&footer)).unwrap();
    (soup, scanner, footer)
}

#[test]
fn freesurfer_surfaces_are_told_by_content_and_written_back_unchanged() {
    let dir = tempfile::tempdir().unwrap();
    let pial = dir.path().join("lh.pial");
    let (soup, scanner, footer) = written_pial(&pial);
    // The file holds tkr-RAS: the scanner position less c_ras.
    let bytes = std::fs::read(&pial).unwrap();
    let first = bytes.iter().position(|&b| b == b'\n').unwrap() + 2 + 8;
    let z = f32::from_be_bytes(bytes[first + 8..first + 12].try_into().unwrap());
    assert_eq!(z, 10.0);
    let read = read_mesh(&pial).unwrap();
    assert_eq!(read.space, Some(Space::Ras));
    assert_eq!(read.volume_geometry.as_ref(), Some(&footer));
    assert_eq!(read.positions[0], Point::new(0.0, 0.0, 30.0));
    assert_eq!(read.positions, scanner);
    assert_eq!(read.triangles, soup.triangles);

    let again = dir.path().join("rh.white");
    write_surface(
        &again,
        &read.positions,
        &read.triangles,
        read.volume_geometry.as_ref(),
    )
    .unwrap();
    assert_eq!(
        std::fs::read(&again).unwrap(),
        std::fs::read(&pial).unwrap()
    );

    // A curv file is not a surface, whatever its name.
    let curv = dir.path().join("lh.curv.ply");
    std::fs::write(&curv, [0xFF, 0xFF, 0xFF, 0, 0, 0, 1]).unwrap();
    let error = read_mesh(&curv).unwrap_err().to_string();
    assert!(error.contains("curv file"), "{error}");
}

/// The FreeSurfer surface we write, read by nibabel (`read_geometry` with its
/// metadata): the vertices in tkr-RAS (the scanner positions less c_ras, as
/// FreeSurfer keeps them), the triangles, and the footer's volume geometry.
#[test]
fn nibabel_reads_the_freesurfer_surfaces_we_write() {
    let dir = tempfile::tempdir().unwrap();
    let pial = dir.path().join("lh.pial");
    let (soup, scanner, footer) = written_pial(&pial);
    let script = "import json, sys, nibabel\n\
        coords, faces, meta = nibabel.freesurfer.read_geometry(sys.argv[1], read_metadata=True)\n\
        print(json.dumps({'coords': coords.tolist(), 'faces': faces.tolist(),\n\
        'volume': [int(v) for v in meta['volume']], 'voxelsize': list(map(float, meta['voxelsize'])),\n\
        'xras': list(map(float, meta['xras'])), 'cras': list(map(float, meta['cras']))}))";
    let out = common::python()
        .args(["-c", script, pial.to_str().unwrap()])
        .output();
    let Some(out) = out.ok().filter(|out| out.status.success()) else {
        common::skip(
            "python3 with nibabel is not installed (pip install -r tools/requirements.txt)",
        );
        return;
    };
    let read: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let numbers = |key: &str| -> Vec<f64> {
        read[key]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect()
    };
    let coords = read["coords"].as_array().unwrap();
    assert_eq!(coords.len(), scanner.len());
    for (row, p) in coords.iter().zip(&scanner) {
        let tkr = p.coords - nalgebra::Vector3::from(footer.c_ras);
        for axis in 0..3 {
            let value = row[axis].as_f64().unwrap();
            assert!((value - tkr[axis]).abs() < 1e-5, "{row} against {p}");
        }
    }
    let faces: Vec<[u64; 3]> = read["faces"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| [0, 1, 2].map(|k| f[k].as_u64().unwrap()))
        .collect();
    let ours: Vec<[u64; 3]> = soup.triangles.iter().map(|t| t.map(u64::from)).collect();
    assert_eq!(faces, ours);
    assert_eq!(numbers("cras"), footer.c_ras.to_vec());
    assert_eq!(numbers("xras"), footer.x_ras.to_vec());
    assert_eq!(numbers("voxelsize"), footer.voxel_size.to_vec());
    assert_eq!(numbers("volume"), footer.volume.map(|v| v as f64).to_vec());
}

/// fsaverage5's left pial surface: from `data/fsaverage/` when
/// `tools/fetch_fsaverage.sh` has fetched it, else the bundled OBJ made from it.
fn fsaverage_pial() -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let fetched = root.join("data/fsaverage/pial_left.gii");
    if fetched.is_file() {
        fetched
    } else {
        println!("data/fsaverage/ is absent (tools/fetch_fsaverage.sh): using the bundled OBJ");
        root.join("meshes/fsaverage5_pial_left.obj")
    }
}

#[test]
fn fsaverage_ridges_label_the_vertices_they_pass() {
    let path = fsaverage_pial();
    let (mesh, _) = Mesh::from_soup(read_mesh(&path).unwrap()).unwrap();
    assert_eq!(mesh.input_vertices().len(), 10_242);
    let surface = Surface::of_mesh(mesh);
    let lines = ridges(&surface, &RidgesOptions::default(), &mut Silent).unwrap();
    let mesh = &surface.mesh;
    let dir = tempfile::tempdir().unwrap();
    let labels_path = dir.path().join("lh.ridges.label.gii");
    write_vertex_labels(&labels_path, &lines, mesh, Structure::OTHER).unwrap();
    let labels = read_vertex_values(&labels_path).unwrap();
    assert_eq!(labels.len(), 10_242);
    assert!(labels.iter().all(|&l| l == 0.0 || l == 1.0 || l == 2.0));
    let count = |label: f64| labels.iter().filter(|&&l| l == label).count();
    assert!(
        count(1.0) > 100 && count(2.0) > 100,
        "{} {}",
        count(1.0),
        count(2.0)
    );
    // Every labelled vertex lies within one of its edge lengths of a line point
    // of its family.
    let points: Vec<(f64, Point)> = lines
        .iter()
        .flat_map(|l| {
            let label = if l.kind == LineKind::Ridge { 1.0 } else { 2.0 };
            l.points.iter().map(move |p| (label, *p))
        })
        .collect();
    for (i, &label) in labels.iter().enumerate().filter(|(_, &l)| l != 0.0) {
        let v = mesh.input_vertices()[i].unwrap();
        let p = mesh.position(v);
        let reach = mesh
            .neighbors(v)
            .map(|w| (mesh.position(w) - p).norm())
            .fold(0.0, f64::max);
        let nearest = points
            .iter()
            .filter(|(l, _)| *l == label)
            .map(|(_, q)| (q - p).norm())
            .fold(f64::INFINITY, f64::min);
        assert!(nearest <= reach, "vertex {i}: {nearest} > {reach}");
    }
}

#[test]
fn gifti_surfaces_read_back_in_ras() {
    let dir = tempfile::tempdir().unwrap();
    let soup = octahedron_with_repairs();
    let path = dir.path().join("lh.test.surf.gii");
    let frame = Some(Space::Ras);
    write_gifti_surface(&path, (&soup.positions, frame), &soup.triangles, &[]).unwrap();
    let read = read_mesh(&path).unwrap();
    assert_eq!(read.positions, soup.positions);
    assert_eq!(read.triangles, soup.triangles);
    assert_eq!(read.space, Some(Space::Ras));
}

/// A GIfTI surface of one triangle whose point set declares `dim0` points, held
/// as `encoding` with the `data` text.
fn gifti_declaring(dim0: usize, encoding: &str, data: &str, intent: &str) -> String {
    format!(
        "<?xml version=\"1.0\"?><GIFTI Version=\"1.0\">\
         <DataArray Intent=\"{intent}\" DataType=\"NIFTI_TYPE_FLOAT32\" \
         ArrayIndexingOrder=\"RowMajorOrder\" Dimensionality=\"2\" Dim0=\"{dim0}\" Dim1=\"3\" \
         Encoding=\"{encoding}\" Endian=\"LittleEndian\"><Data>{data}</Data></DataArray>\
         <DataArray Intent=\"NIFTI_INTENT_TRIANGLE\" DataType=\"NIFTI_TYPE_INT32\" \
         Dimensionality=\"2\" Dim0=\"1\" Dim1=\"3\" Encoding=\"ASCII\"><Data>0 1 2</Data></DataArray>\
         </GIFTI>"
    )
}

/// zlib-compressed, then base64: GIfTI's GZipBase64Binary.
fn gzip_base64(bytes: &[u8]) -> String {
    use base64::Engine;
    use std::io::Write;
    let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::best());
    z.write_all(bytes).unwrap();
    base64::engine::general_purpose::STANDARD.encode(z.finish().unwrap())
}

#[test]
fn hostile_files_are_refused_in_one_line_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let soup = octahedron_with_repairs();
    let pial = dir.path().join("lh.pial");
    write_surface(&pial, &soup.positions, &soup.triangles, None).unwrap();
    let whole = std::fs::read(&pial).unwrap();
    let counts = whole.iter().position(|&b| b == b'\n').unwrap() + 2;
    let mut absurd = whole.clone();
    absurd[counts..counts + 4].copy_from_slice(&0x7FFF_FFFFi32.to_be_bytes());
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        (
            "lh.truncated",
            whole[..whole.len() - 5].to_vec(),
            "truncated",
        ),
        ("lh.absurd", absurd, "announces 2147483647 vertices"),
        (
            "huge.surf.gii",
            gifti_declaring(
                1 << 40,
                "Base64Binary",
                "AAAAAAAAAAAAAAAA",
                "NIFTI_INTENT_POINTSET",
            )
            .into_bytes(),
            "DataArray 0: the base64 data holds about 12 bytes where the dimensions declare",
        ),
        (
            "huge_gzip.surf.gii",
            gifti_declaring(
                1 << 40,
                "GZipBase64Binary",
                &gzip_base64(&[0; 36]),
                "NIFTI_INTENT_POINTSET",
            )
            .into_bytes(),
            "DataArray 0: the dimensions declare 13194139533312 bytes, more than",
        ),
        (
            // 64 MiB of zeros behind a header of three points.
            "bomb.surf.gii",
            gifti_declaring(
                3,
                "GZipBase64Binary",
                &gzip_base64(&vec![0; 64 << 20]),
                "NIFTI_INTENT_POINTSET",
            )
            .into_bytes(),
            "DataArray 0: the compressed data holds more than the 36 bytes",
        ),
        (
            "bad64.surf.gii",
            gifti_declaring(
                3,
                "Base64Binary",
                "AAAA*AAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAA",
                "NIFTI_INTENT_POINTSET",
            )
            .into_bytes(),
            "DataArray 0: the data is not valid base64",
        ),
        (
            "intent.surf.gii",
            gifti_declaring(3, "ASCII", "0 0 0 1 0 0 0 1 0", "NIFTI_INTENT_SHAPE").into_bytes(),
            "no NIFTI_INTENT_POINTSET DataArray",
        ),
        (
            "external.surf.gii",
            gifti_declaring(3, "ExternalFileBinary", "", "NIFTI_INTENT_POINTSET").into_bytes(),
            "DataArray 0: the data is in an external file",
        ),
        (
            "broken.gii",
            b"<GIFTI><DataArray".to_vec(),
            "not well-formed XML",
        ),
    ];
    for (name, bytes, expected) in cases {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        let started = std::time::Instant::now();
        let error = read_mesh(&path).unwrap_err().to_string();
        assert!(started.elapsed().as_secs() < 2, "{name}: slow");
        assert!(!error.contains('\n'), "{name}: {error}");
        assert!(
            error.starts_with(&path.display().to_string()),
            "{name}: {error}"
        );
        assert!(error.contains(expected), "{name}: {error}");
    }
}
