//! The command-line tool and the library's jobs give the same result for the same
//! input: every command's output file equals what the job of the same name returns
//! with the options the command's arguments stand for — its defaults, and two
//! options changed — on the bundled bunny and the MNI template. (The Python
//! package's tests hold its functions to the same files.)

use std::path::{Path, PathBuf};
use std::process::Command;

use crestline::io::{read_mesh, read_volume};
use crestline::jobs::{self, Length, Surface};
use crestline::landmarks::Landmarks;
use crestline::lines::FeatureLines;
use crestline::mesh::{Mesh, TriangleSoup};
use crestline::progress::Silent;
use crestline::volume::Volume;

const BUNNY: &str = "meshes/bunny.obj";
const MNI: &str = "volumes/mni152_t1_1mm.nii.gz";
/// An isosurface level between the background and the brain's tissue.
const LEVEL: f64 = 80.0;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Run the tool with `args` from the repository's root, writing `-o` into `dir`
/// as `output`; the path of the output.
fn tool(dir: &Path, output: &str, args: &[&str]) -> PathBuf {
    let path = dir.join(output);
    let out = Command::new(env!("CARGO_BIN_EXE_crestline"))
        .args(args)
        .arg("-o")
        .arg(&path)
        .current_dir(root())
        .output()
        .expect("the binary runs");
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    path
}

fn bunny() -> Mesh {
    let soup = read_mesh(&root().join(BUNNY)).unwrap();
    jobs::build_mesh(soup, false, &mut Silent).unwrap().0
}

fn mni() -> Volume {
    read_volume(&root().join(MNI)).unwrap()
}

/// The template with every `step`-th sample along each axis, written into `dir` as
/// NRRD: its path, and the volume read back from it. A coarser image keeps the
/// slower image commands short; the command and the job are the same.
fn coarse_mni(dir: &Path, step: usize) -> (PathBuf, Volume) {
    let path = dir.join(format!("mni_every_{step}.nrrd"));
    write_nrrd(&path, &every_nth_sample(&mni(), step));
    let volume = read_volume(&path).unwrap();
    (path, volume)
}

/// Two numbers equal to 1e-12 of their size.
fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * a.abs().max(b.abs()).max(1.0)
}

/// The same lines, in the same order: kinds, closedness, strengths and points.
fn assert_same_lines(file: &FeatureLines, job: &FeatureLines) {
    assert_eq!(file.len(), job.len(), "line counts");
    assert!(
        !job.is_empty(),
        "no lines: the comparison would prove nothing"
    );
    for (a, b) in file.iter().zip(job.iter()) {
        assert_eq!((a.kind, a.closed), (b.kind, b.closed));
        assert!(
            close(a.strength, b.strength),
            "{} {}",
            a.strength,
            b.strength
        );
        assert_eq!(a.points.len(), b.points.len());
        for (p, q) in a.points.iter().zip(&b.points) {
            assert!((p - q).norm() <= 1e-12 * (1.0 + p.coords.norm()), "{p} {q}");
        }
    }
}

/// The same vertices (to 1e-12) and triangles.
fn assert_same_surface(
    file: &TriangleSoup,
    positions: &[crestline::Point],
    triangles: &[[u32; 3]],
) {
    assert!(!triangles.is_empty());
    assert_eq!(file.triangles, triangles);
    assert_eq!(file.positions.len(), positions.len());
    for (p, q) in file.positions.iter().zip(positions) {
        assert!((p - q).norm() <= 1e-12 * (1.0 + p.coords.norm()), "{p} {q}");
    }
}

/// The same point landmarks and line descriptors.
fn assert_same_landmarks(file: &Landmarks, job: &Landmarks) {
    assert!(!job.points.is_empty());
    assert_eq!(file.points.len(), job.points.len(), "landmark counts");
    for (a, b) in file.points.iter().zip(&job.points) {
        assert_eq!((a.id, a.kind, a.line), (b.id, b.kind, b.line));
        assert!((a.position - b.position).norm() <= 1e-9, "{a:?} {b:?}");
        assert!(close(a.curvature, b.curvature));
    }
    assert_eq!(file.lines.len(), job.lines.len());
    for (a, b) in file.lines.iter().zip(&job.lines) {
        assert_eq!((a.id, a.kind, a.closed), (b.id, b.kind, b.closed));
        assert!(close(a.length, b.length));
    }
}

#[test]
fn curvature_equals_the_job() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = Surface::of_mesh(bunny());
    for (args, estimator) in [
        (vec![], jobs::CurvatureOptions::default().estimator),
        (vec!["--estimator", "jet-fit"], "jet-fit".parse().unwrap()),
    ] {
        let file = tool(
            dir.path(),
            "k.ply",
            &[&["curvature", BUNNY][..], &args].concat(),
        );
        let options = jobs::CurvatureOptions {
            estimator,
            ..Default::default()
        };
        let field = jobs::curvature(&mesh, &options, &mut Silent).unwrap();
        let written = read_mesh(&file).unwrap();
        let k_max = &written
            .vertex_scalars
            .iter()
            .find(|s| s.name == "k_max")
            .unwrap();
        assert_eq!(k_max.values.len(), field.k_max.len());
        for (a, b) in k_max.values.iter().zip(&field.k_max) {
            assert!(close(*a, *b), "{a} {b}");
        }
    }
}

#[test]
fn iso_equals_the_job() {
    let dir = tempfile::tempdir().unwrap();
    let volume = mni();
    let level = LEVEL.to_string();
    let cases = [
        (vec![], jobs::IsoOptions::default()),
        (
            vec!["--sigma", "2", "--curvature", "mesh"],
            jobs::IsoOptions {
                sigma: Length::World(2.0),
                curvature: jobs::CurvatureSource::Mesh,
                ..jobs::IsoOptions::default()
            },
        ),
    ];
    for (args, options) in cases {
        let file = tool(
            dir.path(),
            "iso.ply",
            &[&["iso", MNI, "--level", &level][..], &args].concat(),
        );
        let curvature = Some(crestline::curvature::DerivativeOrder::Second);
        let surface = jobs::isosurface(&volume, LEVEL, &options, curvature, &mut Silent).unwrap();
        let written = read_mesh(&file).unwrap();
        let mesh = &surface.mesh;
        assert_same_surface(&written, mesh.positions(), &mesh.triangles());
        let field =
            jobs::curvature(&surface, &jobs::CurvatureOptions::default(), &mut Silent).unwrap();
        let k_max = &written
            .vertex_scalars
            .iter()
            .find(|s| s.name == "k_max")
            .unwrap();
        assert!(k_max
            .values
            .iter()
            .zip(&field.k_max)
            .all(|(a, b)| close(*a, *b)));
    }
}

#[test]
fn crest_lines_equal_the_job() {
    let dir = tempfile::tempdir().unwrap();
    let (path, volume) = coarse_mni(dir.path(), 2);
    let image = path.to_str().unwrap();
    let level = LEVEL.to_string();
    let defaults = jobs::CrestLinesOptions::default();
    let cases = [
        (vec![], defaults),
        (
            vec!["--seeds", "300"],
            jobs::CrestLinesOptions {
                seeds: Some(300),
                ..defaults
            },
        ),
        (
            vec!["--sigma", "1.5", "--min-length", "10"],
            jobs::CrestLinesOptions {
                sigma: Length::World(1.5),
                min_length: Length::World(10.0),
                ..defaults
            },
        ),
    ];
    for (args, options) in cases {
        let file = tool(
            dir.path(),
            "crests.json",
            &[&["crest-lines", image, "--level", &level][..], &args].concat(),
        );
        let lines = jobs::crest_lines(&volume, LEVEL, &options, &mut Silent).unwrap();
        assert_same_lines(&FeatureLines::read_json(&file).unwrap(), &lines);
    }
}

/// The template's sampling step for crease surfaces, the slowest image command.
const CREASE_STEP: usize = 4;

#[test]
fn crease_equals_the_job() {
    let dir = tempfile::tempdir().unwrap();
    let (path, volume) = coarse_mni(dir.path(), CREASE_STEP);
    let image = path.to_str().unwrap();
    let defaults = jobs::CreaseOptions::default();
    let cases = [
        (vec![], defaults),
        (
            vec!["--valley", "--strength", "0.2"],
            jobs::CreaseOptions {
                valley: true,
                strength: 0.2,
                ..defaults
            },
        ),
    ];
    for (args, options) in cases {
        let file = tool(
            dir.path(),
            "crease.ply",
            &[&["crease", image][..], &args].concat(),
        );
        let soup = jobs::crease(&volume, &options, &mut Silent).unwrap();
        assert_same_surface(&read_mesh(&file).unwrap(), &soup.positions, &soup.triangles);
    }
}

#[test]
fn ridges_equal_the_job() {
    let dir = tempfile::tempdir().unwrap();
    let surface = Surface::of_mesh(bunny());
    let defaults = jobs::RidgesOptions::default();
    let cases = [
        (vec![], defaults.clone()),
        (
            vec!["--estimator", "jet-fit", "--threshold", "4"],
            jobs::RidgesOptions {
                estimator: "jet-fit".parse().unwrap(),
                threshold: 4.0,
                ..defaults
            },
        ),
    ];
    for (args, options) in cases {
        let file = tool(
            dir.path(),
            "ridges.json",
            &[&["ridges", BUNNY][..], &args].concat(),
        );
        let lines = jobs::ridges(&surface, &options, &mut Silent).unwrap();
        assert_same_lines(&FeatureLines::read_json(&file).unwrap(), &lines);
    }
}

#[test]
fn landmarks_of_a_mesh_equal_the_job() {
    let dir = tempfile::tempdir().unwrap();
    let surface = Surface::of_mesh(bunny());
    let unit = surface.mesh.mean_edge_length();
    let (radius, persistence) = (8.0 * unit, 3.0 * unit);
    let cases = [
        (vec![], jobs::LandmarksOptions::default()),
        (
            vec![
                "--radius".to_string(),
                radius.to_string(),
                "--persistence".to_string(),
                persistence.to_string(),
            ],
            jobs::LandmarksOptions {
                radius: Length::World(radius),
                persistence: Length::World(persistence),
            },
        ),
    ];
    let ridges = jobs::RidgesOptions::default();
    for (args, options) in cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let file = tool(
            dir.path(),
            "marks.json",
            &[&["landmarks", BUNNY][..], &args].concat(),
        );
        let input = jobs::LinesFrom::Surface {
            surface: &surface,
            options: &ridges,
        };
        let found = jobs::landmarks(input, &options, &mut Silent).unwrap();
        assert_same_landmarks(&Landmarks::read(&file).unwrap().0, &found);
    }
}

#[test]
fn landmarks_of_an_image_equal_the_job() {
    let dir = tempfile::tempdir().unwrap();
    let (path, volume) = coarse_mni(dir.path(), 2);
    let image = path.to_str().unwrap();
    let level = LEVEL.to_string();
    let defaults = jobs::CrestLinesOptions::default();
    let cases = [
        (vec![], defaults, jobs::LandmarksOptions::default()),
        (
            vec!["--sigma", "1.5", "--radius", "7"],
            jobs::CrestLinesOptions {
                sigma: Length::World(1.5),
                ..defaults
            },
            jobs::LandmarksOptions {
                radius: Length::World(7.0),
                ..jobs::LandmarksOptions::default()
            },
        ),
    ];
    for (args, crest, options) in cases {
        let file = tool(
            dir.path(),
            "marks.json",
            &[&["landmarks", image, "--level", &level][..], &args].concat(),
        );
        let input = jobs::LinesFrom::Image {
            volume: &volume,
            level: LEVEL,
            options: &crest,
        };
        let found = jobs::landmarks(input, &options, &mut Silent).unwrap();
        assert_same_landmarks(&Landmarks::read(&file).unwrap().0, &found);
    }
}

#[test]
fn morse_equals_the_job() {
    let dir = tempfile::tempdir().unwrap();
    let surface = Surface::of_mesh(bunny());
    let defaults = jobs::MorseOptions::default();
    let cases = [
        (vec![], defaults.clone()),
        (
            vec!["--keep-saddles", "20", "--cells", "both"],
            jobs::MorseOptions {
                keep_saddles: 20,
                cells: "both".parse().unwrap(),
                ..defaults
            },
        ),
    ];
    for (args, options) in cases {
        let file = tool(
            dir.path(),
            "morse.json",
            &[&["morse", BUNNY][..], &args].concat(),
        );
        let (lines, _) = jobs::morse(&surface, None, &options, &mut Silent).unwrap();
        assert_same_lines(&FeatureLines::read_json(&file).unwrap(), &lines);
    }
}

#[test]
fn draw_equals_the_job() {
    let dir = tempfile::tempdir().unwrap();
    let surface = Surface::of_mesh(bunny());
    let defaults = jobs::DrawingOptions::default();
    let cases = [
        (
            vec!["--view", "20,15", "--silhouettes"],
            jobs::DrawingOptions {
                view: [20.0, 15.0],
                silhouettes: true,
                ..defaults.clone()
            },
        ),
        (
            vec!["--lines", "morse", "--suggestive", "--size", "400x300"],
            jobs::DrawingOptions {
                lines: jobs::LinesChoice::Morse,
                suggestive: true,
                size: [400, 300],
                ..defaults
            },
        ),
    ];
    for (args, options) in cases {
        let file = tool(dir.path(), "d.svg", &[&["draw", BUNNY][..], &args].concat());
        let mut drawing = jobs::draw(&surface, (None, None), &options, &mut Silent).unwrap();
        drawing.source = BUNNY.to_string();
        let style = options.style(crestline::draw::Style::default()).unwrap();
        let svg = drawing.svg(&style);
        assert!(svg.matches("<path").count() > 10);
        assert_eq!(std::fs::read_to_string(&file).unwrap(), svg);
    }
}

/// `volume` as a raw NRRD file (its grid axes along the world axes).
fn write_nrrd(path: &Path, volume: &Volume) {
    let [nx, ny, nz] = volume.dims();
    let [sx, sy, sz] = volume.spacing();
    let [ox, oy, oz] = volume.origin();
    let header = format!(
        "NRRD0004\ntype: float\ndimension: 3\nspace: right-anterior-superior\n\
         sizes: {nx} {ny} {nz}\nspace directions: ({sx},0,0) (0,{sy},0) (0,0,{sz})\n\
         space origin: ({ox},{oy},{oz})\nencoding: raw\nendian: little\n\n"
    );
    let mut bytes = header.into_bytes();
    bytes.extend(volume.samples().iter().flat_map(|s| s.to_le_bytes()));
    std::fs::write(path, bytes).unwrap();
}

/// Every `step`-th sample of `volume` along each axis, `step` times the spacing.
fn every_nth_sample(volume: &Volume, step: usize) -> Volume {
    let [nx, ny, nz] = volume.dims();
    let dims = [nx, ny, nz].map(|n| n.div_ceil(step));
    let mut samples = Vec::with_capacity(dims.iter().product());
    for k in (0..nz).step_by(step) {
        for j in (0..ny).step_by(step) {
            for i in (0..nx).step_by(step) {
                samples.push(volume.samples()[i + nx * (j + ny * k)]);
            }
        }
    }
    let spacing = volume.spacing().map(|s| step as f64 * s);
    Volume::new(dims, spacing, volume.origin(), *volume.direction(), samples).unwrap()
}
