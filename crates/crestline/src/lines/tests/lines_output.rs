//! Feature-line output: the `FeatureLines` helpers and the JSON, OBJ, PLY and VTK
//! writers, each file parsed back by hand.

use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

use crate::lines::{
    read_json, write_json, write_lines, write_obj, write_ply, write_vtk, FeatureLines, LineFormat,
    LineKind, Polyline, SurfaceLocation, FORMAT,
};
use crate::{Error, Point, Space};
use serde::de::{Deserializer, IgnoredAny, MapAccess, Visitor};
use serde::Deserialize;

/// An open ridge of four points and a closed valley of three, with values that
/// exercise number formatting.
fn sample() -> FeatureLines {
    let mut lines = FeatureLines::new("meshes/bunny.obj");
    lines.push(Polyline::new(
        LineKind::Ridge,
        false,
        3.2,
        vec![
            Point::new(0.0, 0.0, 0.0),
            Point::new(1.0, 0.0, 0.0),
            Point::new(1.0, 2.0, 0.0),
            Point::new(0.1, 1e-7, -2.5),
        ],
    ));
    lines.push(Polyline::new(
        LineKind::Valley,
        true,
        0.75,
        vec![
            Point::new(0.0, 0.0, 1.0),
            Point::new(3.0, 0.0, 1.0),
            Point::new(0.0, 4.0, 1.0),
        ],
    ));
    lines
}

/// A public writer function.
type Writer = fn(&Path, &FeatureLines) -> crate::Result<()>;

/// The writers under test, with their extension.
fn writers() -> [(&'static str, Writer); 4] {
    [
        ("json", write_json),
        ("obj", write_obj),
        ("ply", write_ply),
        ("vtk", write_vtk),
    ]
}

fn temp_dir() -> tempfile::TempDir {
    tempfile::tempdir().expect("create a temporary directory")
}

/// The names of the entries of `dir`, sorted.
fn dir_entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("list directory")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn helpers_measure_count_and_filter() {
    let mut lines = sample();
    assert_eq!(lines.len(), 2);
    assert!(!lines.is_empty());
    assert_eq!(lines.point_count(), 7);
    let open = 1.0 + 2.0 + (0.81f64 + (2.0f64 - 1e-7).powi(2) + 6.25).sqrt();
    assert!((lines.lines[0].length() - open).abs() < 1e-12);
    // The closed 3-4-5 triangle includes its closing segment.
    assert!((lines.lines[1].length() - 12.0).abs() < 1e-12);
    assert!((lines.total_length() - open - 12.0).abs() < 1e-12);
    assert_eq!(lines.lines[1].segments().count(), 3);

    let counts = lines.count_by_kind();
    assert_eq!(counts.get(&LineKind::Ridge), Some(&1));
    assert_eq!(counts.get(&LineKind::Valley), Some(&1));
    assert_eq!(counts.get(&LineKind::Crest), None);
    assert_eq!(lines.of_kind(LineKind::Valley).count(), 1);
    assert_eq!(lines.iter().count(), 2);

    lines.retain(|line| line.kind == LineKind::Valley);
    assert_eq!(lines.len(), 1);
    assert!(lines.lines[0].closed);
}

#[test]
fn kinds_have_stable_names_and_codes() {
    let names: Vec<&str> = LineKind::ALL.iter().map(|k| k.name()).collect();
    assert_eq!(
        names,
        [
            "ridge",
            "valley",
            "ascending",
            "descending",
            "crest",
            "parabolic",
            "silhouette",
            "contour",
            "border",
            "crease",
            "suggestive",
            "gauss"
        ]
    );
    for (code, kind) in LineKind::ALL.iter().enumerate() {
        assert_eq!(usize::from(kind.code()), code);
        let json = serde_json::to_string(kind).expect("serialize kind");
        assert_eq!(json, format!("\"{}\"", kind.name()));
    }
}

/// The keys of a JSON object in file order (serde_json's `Value` sorts them).
struct KeyOrder(Vec<String>);

impl<'de> Deserialize<'de> for KeyOrder {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Keys;
        impl<'de> Visitor<'de> for Keys {
            type Value = KeyOrder;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("an object")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<KeyOrder, A::Error> {
                let mut keys = Vec::new();
                while let Some(key) = map.next_key::<String>()? {
                    map.next_value::<IgnoredAny>()?;
                    keys.push(key);
                }
                Ok(KeyOrder(keys))
            }
        }
        deserializer.deserialize_map(Keys)
    }
}

#[derive(Deserialize)]
struct LineKeys {
    lines: Vec<KeyOrder>,
}

#[test]
fn json_has_the_documented_shape_and_round_trips() {
    let dir = temp_dir();
    let path = dir.path().join("lines.json");
    let lines = sample();
    write_json(&path, &lines).expect("write json");
    let text = std::fs::read_to_string(&path).expect("read back");

    let top: KeyOrder = serde_json::from_str(&text).expect("top-level keys");
    assert_eq!(top.0, ["format", "source", "space", "units", "lines"]);
    let per_line: LineKeys = serde_json::from_str(&text).expect("line keys");
    assert_eq!(per_line.lines.len(), 2);
    for keys in &per_line.lines {
        assert_eq!(keys.0, ["kind", "closed", "strength", "points"]);
    }

    let value: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");
    assert_eq!(value["format"], FORMAT);
    assert_eq!(FORMAT, "crestline-lines/1.1");
    assert_eq!(value["space"], serde_json::Value::Null);
    assert_eq!(value["units"], serde_json::Value::Null);
    assert_eq!(value["source"], "meshes/bunny.obj");
    let first = &value["lines"][0];
    assert_eq!(first["kind"], "ridge");
    assert_eq!(first["closed"], false);
    assert_eq!(first["strength"], 3.2);
    assert_eq!(first["points"][3], serde_json::json!([0.1, 1e-7, -2.5]));
    let second = &value["lines"][1];
    assert_eq!(second["kind"], "valley");
    assert_eq!(second["closed"], true);
    // A closed line does not repeat its first point.
    assert_eq!(second["points"].as_array().map(Vec::len), Some(3));

    assert_eq!(read_json(&path).expect("read json"), lines);

    let in_lps = FeatureLines {
        space: Some(Space::Lps),
        ..lines.clone()
    };
    write_json(&path, &in_lps).expect("write json");
    let value: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(value["space"], "LPS");
    assert_eq!(value["units"], "mm");
    assert_eq!(read_json(&path).expect("read json"), in_lps);
}

#[test]
fn older_versions_read_and_newer_minor_versions_keep_what_they_know() {
    let dir = temp_dir();
    let write = |name: &str, text: &str| {
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        path
    };
    let line = r#"{"kind": "ridge", "closed": false, "strength": 1.0, "points": [[0,0,0],[1,0,0]]"#;
    let old = write(
        "old.json",
        &format!(r#"{{"format": "crestline-lines/1", "source": "s", "lines": [{line}}}]}}"#),
    );
    let read = read_json(&old).expect("version 1 reads");
    assert_eq!((read.len(), read.space), (1, None));
    let newer = write(
        "newer.json",
        &format!(
            r#"{{"format": "crestline-lines/1.7", "source": "s", "space": "RAS", "scale": 2,
                "lines": [{line}, "colour": "red"}}]}}"#
        ),
    );
    let read = read_json(&newer).expect("a newer minor version reads");
    assert_eq!((read.len(), read.space), (1, Some(Space::Ras)));
    let unknown = write(
        "unknown.json",
        &format!(
            r#"{{"format": "crestline-lines/1.1", "source": "s", "scale": 2, "lines": [{line}}}]}}"#
        ),
    );
    let error = read_json(&unknown).unwrap_err().to_string();
    assert!(
        error.contains("unknown.json") && error.contains("scale"),
        "{error}"
    );
    for format in [
        "crestline-lines/2",
        "crestline-lines/10",
        "crestline-lines/1.x",
    ] {
        let other = write(
            "other.json",
            &format!(r#"{{"format": "{format}", "source": "s", "lines": []}}"#),
        );
        assert!(read_json(&other).is_err(), "{format}");
    }
}

#[test]
fn read_json_rejects_other_content_naming_the_file() {
    let dir = temp_dir();
    let cases = [
        ("syntax.json", "{\"format\": \"crestline-lines/1\", ", "EOF"),
        (
            "version.json",
            r#"{"format": "crestline-lines/2", "source": "", "lines": []}"#,
            "crestline-lines/2",
        ),
        ("noformat.json", r#"{"source": "", "lines": []}"#, "format"),
        (
            "kind.json",
            r#"{"format": "crestline-lines/1", "source": "s", "lines": [
                {"kind": "cliff", "closed": false, "strength": 1.0,
                 "points": [[0, 0, 0], [1, 0, 0]]}]}"#,
            "cliff",
        ),
        (
            "short.json",
            r#"{"format": "crestline-lines/1", "source": "s", "lines": [
                {"kind": "ridge", "closed": false, "strength": 1.0, "points": [[0, 0, 0]]}]}"#,
            "line 0",
        ),
        (
            "point.json",
            r#"{"format": "crestline-lines/1", "source": "s", "lines": [
                {"kind": "ridge", "closed": false, "strength": 1.0, "points": [[0, 0], [1, 0]]}]}"#,
            "array of length 3",
        ),
    ];
    for (name, content, expected) in cases {
        let path = dir.path().join(name);
        std::fs::write(&path, content).expect("write case");
        let err = read_json(&path).expect_err(name);
        assert!(matches!(err, Error::File { .. }), "{name}: {err:?}");
        let message = err.to_string();
        assert!(message.contains(name), "{message}");
        assert!(message.contains(expected), "{name}: {message}");
    }
}

#[test]
fn obj_has_vertices_and_polyline_records() {
    let dir = temp_dir();
    let path = dir.path().join("lines.obj");
    write_obj(&path, &sample()).expect("write obj");
    let text = std::fs::read_to_string(&path).expect("read back");

    assert!(text.starts_with("# crestline-lines/1"));
    assert!(text.contains("# source: meshes/bunny.obj"));
    let vertices: Vec<Vec<f64>> = text
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|rest| {
            rest.split_whitespace()
                .map(|t| t.parse().expect("coordinate"))
                .collect()
        })
        .collect();
    assert_eq!(vertices.len(), 7);
    assert_eq!(vertices[3], [0.1, 1e-7, -2.5]);
    assert_eq!(vertices[5], [3.0, 0.0, 1.0]);

    let records: Vec<Vec<usize>> = text
        .lines()
        .filter_map(|l| l.strip_prefix("l "))
        .map(|rest| {
            rest.split_whitespace()
                .map(|t| t.parse().expect("index"))
                .collect()
        })
        .collect();
    assert_eq!(records, [vec![1, 2, 3, 4], vec![5, 6, 7, 5]]);

    let objects: Vec<&str> = text.lines().filter(|l| l.starts_with("o ")).collect();
    assert_eq!(objects, ["o line0_ridge", "o line1_valley"]);
    assert!(text.contains("# ridge open strength 3.2"));
    assert!(text.contains("# valley closed strength 0.75"));
}

/// A PLY file split into its header lines and binary body.
fn split_ply(bytes: &[u8]) -> (Vec<String>, &[u8]) {
    let marker = b"end_header\n";
    let end = bytes
        .windows(marker.len())
        .position(|w| w == marker)
        .expect("end_header")
        + marker.len();
    let header = String::from_utf8(bytes[..end].to_vec()).expect("ASCII header");
    (header.lines().map(str::to_owned).collect(), &bytes[end..])
}

/// Little-endian reader over a binary PLY body.
struct Body<'a>(&'a [u8]);

impl Body<'_> {
    fn take<const N: usize>(&mut self) -> [u8; N] {
        let (head, rest) = self.0.split_at(N);
        self.0 = rest;
        head.try_into().expect("N bytes")
    }
    fn f32(&mut self) -> f32 {
        f32::from_le_bytes(self.take())
    }
    fn i32(&mut self) -> i32 {
        i32::from_le_bytes(self.take())
    }
    fn u8(&mut self) -> u8 {
        self.take::<1>()[0]
    }
}

#[test]
fn ply_has_vertices_and_edges_with_kind_strength_and_line() {
    let dir = temp_dir();
    let path = dir.path().join("lines.ply");
    let lines = sample();
    write_ply(&path, &lines).expect("write ply");
    let bytes = std::fs::read(&path).expect("read back");
    let (header, body) = split_ply(&bytes);

    assert_eq!(header[0], "ply");
    assert_eq!(header[1], "format binary_little_endian 1.0");
    assert!(header
        .iter()
        .any(|l| l.starts_with("comment") && l.contains("0 ridge, 1 valley")));
    let elements: Vec<&str> = header
        .iter()
        .filter(|l| l.starts_with("element") || l.starts_with("property"))
        .map(String::as_str)
        .collect();
    assert_eq!(
        elements,
        [
            "element vertex 7",
            "property float x",
            "property float y",
            "property float z",
            "element edge 6",
            "property int vertex1",
            "property int vertex2",
            "property uchar kind",
            "property float strength",
            "property int line",
        ]
    );
    assert_eq!(body.len(), 7 * 12 + 6 * 17);

    let mut body = Body(body);
    let points: Vec<Point> = lines.iter().flat_map(|l| l.points.clone()).collect();
    for point in &points {
        for v in [point.x, point.y, point.z] {
            assert_eq!(body.f32(), v as f32);
        }
    }
    let mut edges = Vec::new();
    for _ in 0..6 {
        let (a, b, kind) = (body.i32(), body.i32(), body.u8());
        let (strength, line) = (body.f32(), body.i32());
        edges.push((a, b, kind, strength, line));
    }
    assert_eq!(
        edges,
        [
            (0, 1, 0, 3.2f32, 0),
            (1, 2, 0, 3.2, 0),
            (2, 3, 0, 3.2, 0),
            (4, 5, 1, 0.75, 1),
            (5, 6, 1, 0.75, 1),
            (6, 4, 1, 0.75, 1),
        ]
    );
}

#[test]
fn ply_rejects_values_beyond_f32() {
    let dir = temp_dir();
    let path = dir.path().join("huge.ply");
    let mut lines = sample();
    lines.lines[1].strength = 1e300;
    let err = write_ply(&path, &lines).expect_err("strength overflows f32");
    assert!(matches!(err, Error::Argument(_)), "{err:?}");
    assert!(err.to_string().contains("line 1"), "{err}");
    assert!(!path.exists());
}

/// A legacy VTK file parsed back: points, cells and the two cell scalars.
struct Vtk {
    points: Vec<[f64; 3]>,
    cells: Vec<Vec<usize>>,
    strength: Vec<f64>,
    kind: Vec<i32>,
    /// Per-point scalars by name.
    point_data: BTreeMap<String, Vec<f64>>,
}

/// Whitespace-separated tokens of a text file.
struct Tokens<'a>(std::str::SplitWhitespace<'a>);

impl Tokens<'_> {
    fn expect(&mut self, words: &[&str]) {
        for word in words {
            assert_eq!(self.0.next(), Some(*word));
        }
    }
    fn number(&mut self) -> f64 {
        let token = self.0.next().expect("a number");
        token.parse().unwrap_or_else(|e| panic!("{token}: {e}"))
    }
    fn count(&mut self) -> usize {
        let token = self.0.next().expect("a count");
        token.parse().unwrap_or_else(|e| panic!("{token}: {e}"))
    }
}

/// Parse `text` strictly in the order the writer promises, checking every count field.
fn parse_vtk(text: &str) -> Vtk {
    let header: Vec<&str> = text.lines().take(4).collect();
    assert_eq!(header[0], "# vtk DataFile Version 3.0");
    assert!(header[1].len() <= 255 && header[1].contains("meshes/bunny.obj"));
    assert_eq!(header[2..], ["ASCII", "DATASET POLYDATA"]);
    let body_start = header.iter().map(|l| l.len() + 1).sum::<usize>();
    let mut tokens = Tokens(text[body_start..].split_whitespace());

    tokens.expect(&["POINTS"]);
    let n_points = tokens.count();
    tokens.expect(&["double"]);
    let points = (0..n_points)
        .map(|_| [0; 3].map(|_| tokens.number()))
        .collect();

    tokens.expect(&["LINES"]);
    let n_cells = tokens.count();
    let size = tokens.count();
    let cells: Vec<Vec<usize>> = (0..n_cells)
        .map(|_| {
            let count = tokens.count();
            (0..count).map(|_| tokens.count()).collect()
        })
        .collect();
    assert_eq!(size, cells.iter().map(|c| 1 + c.len()).sum::<usize>());
    assert!(cells.iter().flatten().all(|&i| i < n_points));

    tokens.expect(&["CELL_DATA"]);
    assert_eq!(tokens.count(), n_cells);
    tokens.expect(&[
        "SCALARS",
        "strength",
        "double",
        "1",
        "LOOKUP_TABLE",
        "default",
    ]);
    let strength = (0..n_cells).map(|_| tokens.number()).collect();
    tokens.expect(&["SCALARS", "kind", "int", "1", "LOOKUP_TABLE", "default"]);
    let kind = (0..n_cells)
        .map(|_| {
            let token = tokens.0.next().expect("kind");
            token.parse().unwrap_or_else(|e| panic!("{token}: {e}"))
        })
        .collect();
    let mut point_data = BTreeMap::new();
    if let Some(word) = tokens.0.next() {
        assert_eq!(word, "POINT_DATA");
        assert_eq!(tokens.count(), n_points);
        while let Some(word) = tokens.0.next() {
            assert_eq!(word, "SCALARS");
            let name = tokens.0.next().expect("a name").to_string();
            tokens.expect(&["double", "1", "LOOKUP_TABLE", "default"]);
            point_data.insert(name, (0..n_points).map(|_| tokens.number()).collect());
        }
    }
    Vtk {
        points,
        cells,
        strength,
        kind,
        point_data,
    }
}

#[test]
fn vtk_is_consistent_polydata() {
    let dir = temp_dir();
    let path = dir.path().join("lines.vtk");
    write_vtk(&path, &sample()).expect("write vtk");
    let text = std::fs::read_to_string(&path).expect("read back");
    let vtk = parse_vtk(&text);
    assert_eq!(vtk.points.len(), 7);
    assert_eq!(vtk.points[3], [0.1, 1e-7, -2.5]);
    assert_eq!(vtk.cells, [vec![0, 1, 2, 3], vec![4, 5, 6, 4]]);
    assert_eq!(vtk.strength, [3.2, 0.75]);
    assert_eq!(vtk.kind, [0, 1]);
}

#[test]
fn empty_lines_write_valid_files() {
    let dir = temp_dir();
    let lines = FeatureLines::new("empty");
    for (extension, write) in writers() {
        let path = dir.path().join(format!("empty.{extension}"));
        write(&path, &lines).unwrap_or_else(|e| panic!("{extension}: {e}"));
    }
    assert_eq!(read_json(&dir.path().join("empty.json")).ok(), Some(lines));
    let vtk = std::fs::read_to_string(dir.path().join("empty.vtk")).expect("vtk");
    assert!(vtk.contains("POINTS 0 double\nLINES 0 0\n"));
}

#[test]
fn write_lines_dispatches_on_the_extension() {
    let dir = temp_dir();
    let lines = sample();
    for format in LineFormat::ALL {
        let upper = dir
            .path()
            .join(format!("upper.{}", format.extension().to_uppercase()));
        assert_eq!(LineFormat::from_path(&upper).ok(), Some(format));
        let path = dir.path().join(format!("lines.{}", format.extension()));
        write_lines(&path, &lines).expect("write lines");
        let reference = dir.path().join(format!("reference.{}", format.extension()));
        format.write(&reference, &lines).expect("write reference");
        let written = std::fs::read(&path).expect("read");
        assert_eq!(written, std::fs::read(&reference).expect("read reference"));
    }
}

#[test]
fn unknown_extension_lists_supported_formats() {
    let dir = temp_dir();
    for name in ["lines.svg", "lines"] {
        let path = dir.path().join(name);
        let err = write_lines(&path, &sample()).expect_err(name);
        assert!(matches!(err, Error::File { .. }), "{err:?}");
        let message = err.to_string();
        for extension in [".json", ".obj", ".ply", ".vtk"] {
            assert!(message.contains(extension), "{message}");
        }
        assert!(message.contains(name), "{message}");
        assert!(!path.exists());
    }
}

#[test]
fn non_finite_values_fail_before_any_file_is_written() {
    let dir = temp_dir();
    let mut with_nan = sample();
    with_nan.lines[1].points[2].y = f64::NAN;
    let mut with_inf = sample();
    with_inf.lines[0].strength = f64::INFINITY;
    for (extension, write) in writers() {
        for (lines, index) in [(&with_nan, "line 1"), (&with_inf, "line 0")] {
            let fresh = dir.path().join(format!("fresh.{extension}"));
            let err = write(&fresh, lines).expect_err("non-finite value");
            assert!(matches!(err, Error::Argument(_)), "{err:?}");
            assert!(err.to_string().contains(index), "{err}");
            assert!(!fresh.exists());

            let existing = dir.path().join(format!("existing.{extension}"));
            std::fs::write(&existing, "previous content").expect("seed file");
            assert!(write_lines(&existing, lines).is_err());
            assert_eq!(
                std::fs::read_to_string(&existing).expect("still there"),
                "previous content"
            );
        }
    }
    // No temporary files are left behind either.
    let expected: Vec<String> = ["json", "obj", "ply", "vtk"]
        .iter()
        .map(|e| format!("existing.{e}"))
        .collect();
    assert_eq!(dir_entries(dir.path()), expected);
}

#[test]
fn lines_with_too_few_points_are_rejected() {
    let dir = temp_dir();
    let path = dir.path().join("short.obj");
    let mut lines = sample();
    lines.lines[1].points.truncate(2);
    let err = write_obj(&path, &lines).expect_err("closed line of two points");
    assert!(err.to_string().contains("line 1"), "{err}");
    assert!(lines.validate().is_err());
    lines.lines[1].closed = false;
    assert!(lines.validate().is_ok());
    assert!(!path.exists());
}

#[test]
fn missing_directory_is_an_error_naming_the_path() {
    let dir = temp_dir();
    let path: PathBuf = dir.path().join("no-such-dir").join("lines.json");
    for format in LineFormat::ALL {
        let path = path.with_extension(format.extension());
        let err = write_lines(&path, &sample()).expect_err("missing directory");
        assert!(matches!(err, Error::File { .. }), "{err:?}");
        assert!(err.to_string().contains(&*path.to_string_lossy()), "{err}");
    }
}

/// [`sample`] with surface locations on the ridge and per-point values on both
/// lines: `k` on both (written by every format), `only_ridge` on one (JSON only).
fn sample_with_point_data() -> FeatureLines {
    let mut lines = sample();
    let ridge = lines.lines[0].clone();
    lines.lines[0] = ridge
        .with_locations(vec![
            SurfaceLocation::Vertex { vertex: 4 },
            SurfaceLocation::Edge { edge: 9, t: 0.25 },
            SurfaceLocation::Face {
                face: 2,
                barycentric: [0.5, 0.25, 0.25],
            },
            SurfaceLocation::Edge { edge: 1, t: 1.0 },
        ])
        .with_values("k", vec![1.0, 2.5, -3.0, 1e-3])
        .with_values("only_ridge", vec![0.0; 4]);
    let valley = lines.lines[1].clone();
    lines.lines[1] = valley.with_values("k", vec![7.0, 8.0, 9.0]);
    lines
}

#[test]
fn point_locations_and_values_round_trip_through_json() {
    let dir = temp_dir();
    let path = dir.path().join("lines.json");
    let lines = sample_with_point_data();
    write_json(&path, &lines).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let value: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(
        value["lines"][0]["locations"][1],
        serde_json::json!({"edge": 9, "t": 0.25})
    );
    assert_eq!(value["lines"][0]["values"]["k"][2], -3.0);
    assert!(value["lines"][1].get("locations").is_none());
    assert_eq!(read_json(&path).unwrap(), lines);
}

#[test]
fn shared_point_values_are_written_per_vertex_by_ply_and_vtk() {
    let dir = temp_dir();
    let lines = sample_with_point_data();
    let k: Vec<f64> = vec![1.0, 2.5, -3.0, 1e-3, 7.0, 8.0, 9.0];
    let path = dir.path().join("lines.vtk");
    write_vtk(&path, &lines).unwrap();
    let vtk = parse_vtk(&std::fs::read_to_string(&path).unwrap());
    assert_eq!(vtk.point_data.keys().collect::<Vec<_>>(), ["k"]);
    assert_eq!(vtk.point_data["k"], k);
    let path = dir.path().join("lines.ply");
    write_ply(&path, &lines).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let (header, body) = split_ply(&bytes);
    let vertex = header.iter().position(|l| l == "element vertex 7").unwrap();
    assert_eq!(
        header[vertex + 1..vertex + 5],
        [
            "property float x",
            "property float y",
            "property float z",
            "property float k"
        ]
    );
    let mut body = Body(body);
    for expected in k {
        let [_, _, _, value] = [0; 4].map(|_| body.f32());
        assert_eq!(value, expected as f32);
    }
}

#[test]
fn point_data_of_the_wrong_length_or_name_is_rejected_before_writing() {
    let dir = temp_dir();
    let bad = [
        (
            sample().lines[0].clone().with_values("k", vec![1.0]),
            "1 values of k for 4 points",
        ),
        (
            sample().lines[0]
                .clone()
                .with_values("two words", vec![0.0; 4]),
            "value name",
        ),
        (
            sample().lines[0]
                .clone()
                .with_values("k", vec![0.0, f64::NAN, 0.0, 0.0]),
            "point 1 has k NaN",
        ),
        (
            sample().lines[0]
                .clone()
                .with_locations(vec![SurfaceLocation::Vertex { vertex: 0 }]),
            "1 locations for 4 points",
        ),
    ];
    for (line, words) in bad {
        let mut lines = FeatureLines::new("x");
        lines.push(line);
        for (extension, write) in writers() {
            let path = dir.path().join(format!("bad.{extension}"));
            let err = write(&path, &lines).unwrap_err().to_string();
            assert!(err.contains(words), "{extension}: {err}");
        }
    }
    assert!(dir_entries(dir.path()).is_empty());
}
