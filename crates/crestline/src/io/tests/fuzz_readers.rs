//! Mutation fuzzing of the mesh readers, on stable Rust and without extra crates.
//!
//! Small valid files of every format (a cube written as ASCII PLY, binary PLY in
//! both byte orders, OBJ, OFF, ASCII and binary STL, a FreeSurfer surface with
//! its volume geometry, GIfTI with ASCII, base64 and gzipped base64 arrays) are
//! mutated with a seeded generator (bit flips, interesting bytes, truncation,
//! duplicated and deleted chunks, swapped numbers, huge numbers) and read back
//! through [`read_mesh`] and [`Mesh::from_soup`]; per-vertex value files (GIfTI
//! `.shape.gii` in gzipped base64 and ASCII, FreeSurfer curv) go through
//! [`read_vertex_values`]. No mutant may panic or hang, and every error is one
//! line naming the file, in plain words. (DICOM files are fuzzed in `dicom.rs`,
//! on pydicom's test files; hostile files built on purpose — gzip bombs, pipes,
//! elements with 200,000 attributes — are in `neuro_formats.rs`.)
//!
//! `cargo test --release` runs [`DEFAULT_MUTANTS`] mutants per format. For a longer run set
//! `CRESTLINE_FUZZ_MUTANTS=N` (and optionally `CRESTLINE_FUZZ_SEED=S`; with
//! `CRESTLINE_FUZZ_SHOW=1` every error message is printed for review), e.g.
//! `CRESTLINE_FUZZ_MUTANTS=20000 cargo test --release -p crestline --test
//! library fuzz_readers -- --nocapture`; the table of outcomes is printed either way.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use crate::io::{read_mesh, read_vertex_values};
use crate::mesh::Mesh;

use crate::common::mutation;

use mutation::{env_number, message_problem, mutate, Rng};

/// Mutants per format in a plain `cargo test --release`.
const DEFAULT_MUTANTS: usize = 300;
/// A mutant taking longer than this to read and build is a hang.
const HANG: Duration = Duration::from_secs(5);

// ---------------------------------------------------------------------------
// Seed files: a unit cube with quad faces

const CUBE_VERTICES: [[f32; 3]; 8] = [
    [0.0, 0.0, 0.0],
    [1.5, 0.0, 0.0],
    [1.5, 1.5, 0.0],
    [0.0, 1.5, 0.0],
    [0.0, 0.0, -1.25],
    [1.5, 0.0, -1.25],
    [1.5, 1.5, -1.25],
    [0.0, 1.5, -1.25],
];

/// Counter-clockwise seen from outside (the cube lies below z = 0).
const CUBE_QUADS: [[u32; 4]; 6] = [
    [0, 1, 2, 3],
    [4, 7, 6, 5],
    [0, 4, 5, 1],
    [1, 5, 6, 2],
    [2, 6, 7, 3],
    [3, 7, 4, 0],
];

fn cube_triangles() -> impl Iterator<Item = [u32; 3]> {
    CUBE_QUADS
        .iter()
        .flat_map(|[a, b, c, d]| [[*a, *b, *c], [*a, *c, *d]])
}

fn ascii_ply() -> Vec<u8> {
    let mut text = String::from(
        "ply\nformat ascii 1.0\ncomment a cube\nelement vertex 8\nproperty float x\n\
         property float y\nproperty float z\nproperty uchar red\nelement face 6\n\
         property list uchar int vertex_indices\nelement edge 2\nproperty int vertex1\n\
         property int vertex2\nend_header\n",
    );
    for (i, [x, y, z]) in CUBE_VERTICES.iter().enumerate() {
        text += &format!("{x} {y} {z:e} {}\n", 30 * i);
    }
    for [a, b, c, d] in CUBE_QUADS {
        text += &format!("4 {a} {b} {c} {d}\n");
    }
    text += "0 1\n1 2\n";
    text.into_bytes()
}

/// A binary PLY: little endian with the common layout (fast decoders), or big
/// endian with a face colour and a vertex list (record-by-record reader).
fn binary_ply(big_endian: bool) -> Vec<u8> {
    let (format, vertex_extra, face_extra) = if big_endian {
        (
            "binary_big_endian",
            "property list uchar short tags\n",
            "property uchar flags\n",
        )
    } else {
        ("binary_little_endian", "property ushort quality\n", "")
    };
    let mut bytes = format!(
        "ply\nformat {format} 1.0\nelement vertex 8\nproperty float x\nproperty float y\n\
         property float z\n{vertex_extra}element face 6\n\
         property list uchar uint vertex_indices\n{face_extra}end_header\n"
    )
    .into_bytes();
    let word = |b: [u8; 4]| {
        if big_endian {
            b
        } else {
            [b[3], b[2], b[1], b[0]]
        }
    };
    for (i, corner) in CUBE_VERTICES.iter().enumerate() {
        for c in corner {
            bytes.extend(word(c.to_be_bytes()));
        }
        if big_endian {
            bytes.extend([1, 0, i as u8]);
        } else {
            bytes.extend((7 * i as u16).to_le_bytes());
        }
    }
    for quad in CUBE_QUADS {
        bytes.push(4);
        for i in quad {
            bytes.extend(word(i.to_be_bytes()));
        }
        if big_endian {
            bytes.push(0xff);
        }
    }
    bytes
}

fn obj() -> Vec<u8> {
    let mut text = String::from("# a cube\no cube\n");
    for [x, y, z] in CUBE_VERTICES {
        text += &format!("v {x} {y} {z}\n");
    }
    text += "vn 0 0 1\n";
    for [a, b, c, d] in CUBE_QUADS {
        text += &format!("f {}//1 {} {} -{}\n", a + 1, b + 1, c + 1, 8 - d);
    }
    text.into_bytes()
}

fn off() -> Vec<u8> {
    let mut text = String::from("OFF\n# a cube\n8 6 12\n");
    for [x, y, z] in CUBE_VERTICES {
        text += &format!("{x} {y} {z}\n");
    }
    for [a, b, c, d] in CUBE_QUADS {
        text += &format!("4 {a} {b} {c} {d}\n");
    }
    text.into_bytes()
}

fn ascii_stl() -> Vec<u8> {
    let mut text = String::from("solid cube\n");
    for triangle in cube_triangles() {
        text += "  facet normal 0 0 0\n    outer loop\n";
        for v in triangle {
            let [x, y, z] = CUBE_VERTICES[v as usize];
            text += &format!("      vertex {x} {y} {z:e}\n");
        }
        text += "    endloop\n  endfacet\n";
    }
    text += "endsolid cube\n";
    text.into_bytes()
}

fn binary_stl() -> Vec<u8> {
    let mut bytes = b"binary cube".to_vec();
    bytes.resize(80, b' ');
    bytes.extend(12u32.to_le_bytes());
    for triangle in cube_triangles() {
        bytes.extend([0u8; 12]);
        for v in triangle {
            bytes.extend(
                CUBE_VERTICES[v as usize]
                    .iter()
                    .flat_map(|c| c.to_le_bytes()),
            );
        }
        bytes.extend([0u8; 2]);
    }
    bytes
}

/// What a seed file is read as.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    /// A mesh, by [`read_mesh`] and [`Mesh::from_soup`].
    Mesh,
    /// Per-vertex values, by [`read_vertex_values`].
    Values,
}

/// A valid file to mutate.
struct Seed {
    name: &'static str,
    extension: &'static str,
    bytes: Vec<u8>,
    kind: Kind,
}

fn seeds() -> Vec<Seed> {
    let seed = |name, extension, bytes| Seed {
        name,
        extension,
        bytes,
        kind: Kind::Mesh,
    };
    let values = |name, extension, bytes| Seed {
        name,
        extension,
        bytes,
        kind: Kind::Values,
    };
    vec![
        seed("ASCII PLY", "ply", ascii_ply()),
        seed("binary PLY (LE)", "ply", binary_ply(false)),
        seed("binary PLY (BE, lists)", "ply", binary_ply(true)),
        seed("OBJ", "obj", obj()),
        seed("OFF", "off", off()),
        seed("ASCII STL", "stl", ascii_stl()),
        seed("binary STL", "stl", binary_stl()),
        seed("FreeSurfer surface", "pial", freesurfer_surface()),
        seed("GIfTI (ASCII)", "gii", gifti_ascii()),
        seed("GIfTI (gzip base64)", "gii", gifti_gzip()),
        seed("GIfTI (base64)", "gii", gifti_base64()),
        values("GIfTI values (gzip)", "shape.gii", gifti_values()),
        values("GIfTI values (ASCII)", "func.gii", gifti_ascii_values()),
        values("FreeSurfer curv", "curv", curv()),
    ]
}

/// The per-vertex values of the value seeds: one per cube vertex.
const VALUES: [f64; 8] = [0.5, -1.25, 3.0, 0.0, 0.125, 7.5, -2.0, 4.25];

/// A `.shape.gii` as crestline writes it (gzipped base64).
fn gifti_values() -> Vec<u8> {
    written("v.shape.gii", |path| {
        crate::io::gifti::write_gifti_values(path, &VALUES, "NIFTI_INTENT_SHAPE", &[], &[]).unwrap()
    })
}

/// A `.func.gii` with an ASCII `N x 1` array.
fn gifti_ascii_values() -> Vec<u8> {
    let data: Vec<String> = VALUES.iter().map(f64::to_string).collect();
    format!(
        "<?xml version=\"1.0\"?>\n<GIFTI Version=\"1.0\" NumberOfDataArrays=\"1\">\n\
         <DataArray Intent=\"NIFTI_INTENT_NONE\" DataType=\"NIFTI_TYPE_FLOAT32\" \
         ArrayIndexingOrder=\"RowMajorOrder\" Dimensionality=\"2\" Dim0=\"8\" Dim1=\"1\" \
         Encoding=\"ASCII\" Endian=\"LittleEndian\"><Data>{}</Data></DataArray>\n</GIFTI>\n",
        data.join("\n")
    )
    .into_bytes()
}

/// A FreeSurfer curv file of the cube's vertices.
fn curv() -> Vec<u8> {
    written("lh.curv", |path| {
        crate::io::freesurfer::write_curv(path, &VALUES, 12).unwrap()
    })
}

/// A GIfTI surface with plain base64 arrays (`Base64Binary`), big-endian points.
fn gifti_base64() -> Vec<u8> {
    use base64::Engine;
    let encode = |bytes: Vec<u8>| base64::engine::general_purpose::STANDARD.encode(bytes);
    let points: Vec<u8> = CUBE_VERTICES
        .iter()
        .flatten()
        .flat_map(|c| c.to_be_bytes())
        .collect();
    let corners: Vec<u8> = cube_triangles()
        .flatten()
        .flat_map(|v| (v as i32).to_le_bytes())
        .collect();
    let array = |intent: &str, data_type: &str, endian: &str, dim0: usize, data: String| {
        format!(
            "<DataArray Intent=\"{intent}\" DataType=\"{data_type}\" \
             ArrayIndexingOrder=\"RowMajorOrder\" Dimensionality=\"2\" Dim0=\"{dim0}\" \
             Dim1=\"3\" Encoding=\"Base64Binary\" Endian=\"{endian}\">\
             <Data>{data}</Data></DataArray>\n"
        )
    };
    let text = String::from("<?xml version=\"1.0\"?>\n<GIFTI Version=\"1.0\">\n")
        + &array(
            "NIFTI_INTENT_POINTSET",
            "NIFTI_TYPE_FLOAT32",
            "BigEndian",
            8,
            encode(points),
        )
        + &array(
            "NIFTI_INTENT_TRIANGLE",
            "NIFTI_TYPE_INT32",
            "LittleEndian",
            12,
            encode(corners),
        )
        + "</GIFTI>\n";
    text.into_bytes()
}

/// The cube as a file written by one of crestline's writers.
fn written(name: &str, write: impl FnOnce(&Path)) -> Vec<u8> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    write(&path);
    std::fs::read(path).unwrap()
}

fn cube_points() -> Vec<crate::Point> {
    CUBE_VERTICES
        .iter()
        .map(|v| crate::Point::from(v.map(f64::from)))
        .collect()
}

/// A FreeSurfer triangle surface with a volume geometry footer.
fn freesurfer_surface() -> Vec<u8> {
    let geometry = crate::io::freesurfer::VolumeGeometry::conformed("orig.mgz", [2.0, -3.0, 4.5]);
    let triangles: Vec<[u32; 3]> = cube_triangles().collect();
    written("lh.pial", |path| {
        crate::io::freesurfer::write_surface(path, &cube_points(), &triangles, Some(&geometry))
            .unwrap()
    })
}

/// A GIfTI surface with gzipped base64 arrays, as crestline writes it.
fn gifti_gzip() -> Vec<u8> {
    let triangles: Vec<[u32; 3]> = cube_triangles().collect();
    written("cube.surf.gii", |path| {
        crate::io::gifti::write_gifti_surface(path, (&cube_points(), None), &triangles, &[])
            .unwrap()
    })
}

/// A GIfTI surface with ASCII arrays, the points column-major.
fn gifti_ascii() -> Vec<u8> {
    let array = |intent: &str, data_type: &str, order: &str, dim0: usize, data: String| {
        format!(
            "<DataArray Intent=\"{intent}\" DataType=\"{data_type}\" ArrayIndexingOrder=\"{order}\" \
             Dimensionality=\"2\" Dim0=\"{dim0}\" Dim1=\"3\" Encoding=\"ASCII\" \
             Endian=\"BigEndian\"><Data>{data}</Data></DataArray>\n"
        )
    };
    let columns: Vec<String> = (0..3)
        .flat_map(|axis| CUBE_VERTICES.iter().map(move |v| v[axis].to_string()))
        .collect();
    let corners: Vec<String> = cube_triangles().flatten().map(|v| v.to_string()).collect();
    let text = String::from("<?xml version=\"1.0\"?>\n<GIFTI Version=\"1.0\">\n")
        + &array(
            "NIFTI_INTENT_POINTSET",
            "NIFTI_TYPE_FLOAT32",
            "ColumnMajorOrder",
            8,
            columns.join(" "),
        )
        + &array(
            "NIFTI_INTENT_TRIANGLE",
            "NIFTI_TYPE_INT32",
            "RowMajorOrder",
            12,
            corners.join(" "),
        )
        + "</GIFTI>\n";
    text.into_bytes()
}

// ---------------------------------------------------------------------------
// Running mutants

/// What reading a mutant gave.
enum Outcome {
    /// Read and built into a mesh.
    Mesh,
    /// Rejected by the reader.
    ReadError(String),
    /// Read, but rejected by the mesh builder.
    MeshError(String),
    Panic(String),
}

/// Read `path` as `kind` says (and build a mesh), as a program would.
fn read_and_build(path: &Path, kind: Kind) -> Outcome {
    if kind == Kind::Values {
        return match read_vertex_values(path) {
            Ok(_) => Outcome::Mesh,
            Err(e) => Outcome::ReadError(e.to_string()),
        };
    }
    let soup = match read_mesh(path) {
        Ok(soup) => soup,
        Err(e) => return Outcome::ReadError(e.to_string()),
    };
    match Mesh::from_soup(soup) {
        Ok(_) => Outcome::Mesh,
        Err(e) => Outcome::MeshError(e.in_file(path).to_string()),
    }
}

/// Run one mutant file, timing it.
fn run(path: &Path, kind: Kind) -> (Outcome, Duration) {
    let start = Instant::now();
    let outcome =
        catch_unwind(AssertUnwindSafe(|| read_and_build(path, kind))).unwrap_or_else(|p| {
            let message = p
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            Outcome::Panic(message)
        });
    (outcome, start.elapsed())
}

/// Tallies of one format.
#[derive(Default)]
struct Tally {
    mutants: usize,
    meshes: usize,
    read_errors: usize,
    mesh_errors: usize,
    total: Duration,
    slowest: Slowest,
    failures: Vec<String>,
}

/// The slowest mutant of a format.
#[derive(Default)]
struct Slowest {
    time: Duration,
    label: String,
    bytes: Vec<u8>,
    /// The fastest of a few more runs, to tell a slow input from a busy machine.
    rerun: Duration,
}

impl Tally {
    fn record(&mut self, outcome: &Outcome, elapsed: Duration, label: &str, path: &Path) {
        self.mutants += 1;
        self.total += elapsed;
        if elapsed > HANG {
            self.failures
                .push(format!("{label}: took {elapsed:?} (a hang)"));
        }
        let problem = match outcome {
            Outcome::Mesh => {
                self.meshes += 1;
                None
            }
            Outcome::ReadError(message) => {
                self.read_errors += 1;
                message_problem(message, path).map(|p| format!("{p}: {message}"))
            }
            Outcome::MeshError(message) => {
                self.mesh_errors += 1;
                message_problem(message, path).map(|p| format!("{p}: {message}"))
            }
            Outcome::Panic(message) => Some(format!("panicked: {message}")),
        };
        if let Some(problem) = problem {
            self.failures.push(format!("{label}: {problem}"));
        }
    }
}

/// Keep a failing mutant where it can be read again.
fn save_failure(bytes: &[u8], seed: &Seed, index: usize) -> PathBuf {
    let dir = std::env::temp_dir().join("crestline_fuzz_readers_failures");
    std::fs::create_dir_all(&dir).unwrap();
    let name = format!("{}-{index}.{}", seed.name, seed.extension);
    let path = dir.join(name.replace([' ', '(', ')', ','], "_"));
    std::fs::write(&path, bytes).unwrap();
    path
}

/// Run `count` mutants of `seed`.
fn fuzz(seed: &Seed, count: usize, rng: &mut Rng, dir: &Path) -> Tally {
    let path = dir.join(format!("mutant.{}", seed.extension));
    let show = std::env::var_os("CRESTLINE_FUZZ_SHOW").is_some();
    let mut tally = Tally::default();
    for index in 0..count {
        let (bytes, mutations) = mutate(&seed.bytes, rng);
        std::fs::write(&path, &bytes).unwrap();
        let (outcome, elapsed) = run(&path, seed.kind);
        let label = format!("{} mutant {index} {mutations:?}", seed.name);
        if show {
            show_message(&outcome);
        }
        let failures_before = tally.failures.len();
        tally.record(&outcome, elapsed, &label, &path);
        if tally.failures.len() > failures_before {
            let kept = save_failure(&bytes, seed, index);
            let note = format!("  (kept as {})", kept.display());
            tally.failures.push(note);
        }
        if elapsed > tally.slowest.time {
            tally.slowest = Slowest {
                time: elapsed,
                label,
                bytes,
                rerun: Duration::ZERO,
            };
        }
    }
    tally.slowest.rerun = rerun(&tally.slowest.bytes, &path, seed.kind);
    tally
}

/// The fastest of three more runs of a mutant.
fn rerun(bytes: &[u8], path: &Path, kind: Kind) -> Duration {
    std::fs::write(path, bytes).unwrap();
    (0..3).map(|_| run(path, kind).1).min().unwrap_or_default()
}

/// Print the error message of an outcome, if it has one.
fn show_message(outcome: &Outcome) {
    if let Outcome::ReadError(message) | Outcome::MeshError(message) = outcome {
        println!("{message}");
    }
}

fn print_table(tallies: &[(&str, Tally)], seed: u64) {
    println!("\nreader fuzzing, seed {seed}");
    println!(
        "{:<24} {:>8} {:>8} {:>11} {:>11} {:>9} {:>11} {:>9}",
        "format",
        "mutants",
        "read",
        "read error",
        "mesh error",
        "mean µs",
        "slowest ms",
        "re-run ms"
    );
    for (name, t) in tallies {
        let mean = t.total.as_secs_f64() * 1e6 / t.mutants.max(1) as f64;
        println!(
            "{:<24} {:>8} {:>8} {:>11} {:>11} {:>9.1} {:>11.3} {:>9.3}",
            name,
            t.mutants,
            t.meshes,
            t.read_errors,
            t.mesh_errors,
            mean,
            t.slowest.time.as_secs_f64() * 1e3,
            t.slowest.rerun.as_secs_f64() * 1e3
        );
    }
    if let Some((_, t)) = tallies.iter().max_by_key(|(_, t)| t.slowest.time) {
        println!(
            "slowest mutant: {} ({:?}; {:?} when run again)",
            t.slowest.label, t.slowest.time, t.slowest.rerun
        );
    }
}

#[test]
fn seed_files_are_valid_meshes() {
    let dir = tempfile::tempdir().unwrap();
    for seed in seeds() {
        let path = dir.path().join(format!("seed.{}", seed.extension));
        std::fs::write(&path, &seed.bytes).unwrap();
        if seed.kind == Kind::Values {
            let values = read_vertex_values(&path).unwrap_or_else(|e| panic!("{}: {e}", seed.name));
            assert_eq!(values, VALUES, "{}", seed.name);
            continue;
        }
        let soup = read_mesh(&path).unwrap_or_else(|e| panic!("{}: {e}", seed.name));
        assert_eq!(soup.triangles.len(), 12, "{}", seed.name);
        let (mesh, _) = Mesh::from_soup(soup).unwrap();
        assert_eq!(mesh.vertex_count(), 8, "{}", seed.name);
    }
}

#[test]
fn mutants_never_panic_hang_or_garble_their_errors() {
    let count = env_number("CRESTLINE_FUZZ_MUTANTS").map_or(DEFAULT_MUTANTS, |n| n as usize);
    let seed = env_number("CRESTLINE_FUZZ_SEED").unwrap_or(0x0c2e_571e);
    let dir = tempfile::tempdir().unwrap();
    let mut tallies = Vec::new();
    for (k, file) in seeds().iter().enumerate() {
        let mut rng = Rng(seed ^ (k as u64).wrapping_mul(0x1000_0001));
        tallies.push((file.name, fuzz(file, count, &mut rng, dir.path())));
    }
    print_table(&tallies, seed);
    let failures: Vec<&String> = tallies.iter().flat_map(|(_, t)| &t.failures).collect();
    assert!(
        failures.is_empty(),
        "{} failures:\n{}",
        failures.len(),
        failures
            .iter()
            .take(40)
            .map(|f| f.as_str())
            .collect::<Vec<_>>()
            .join("\n")
    );
}
