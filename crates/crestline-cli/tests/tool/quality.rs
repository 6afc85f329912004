//! `crestline curvature --quality`: the quantity MeshLab reads as `quality`.

use std::path::Path;

use crestline::curvature::Quality;
use crestline::jobs::CurvatureOptions;

const MESH: &str = "meshes/bunny_small.obj";

use crate::common;

use common::crestline;

/// The vertex property `name` of the PLY file at `path`.
fn property(path: &Path, name: &str) -> Vec<f64> {
    let soup = crestline::io::read_mesh(path).unwrap();
    soup.vertex_scalars
        .into_iter()
        .find(|p| p.name == name)
        .unwrap_or_else(|| panic!("no vertex property {name}"))
        .values
}

/// `crestline curvature MESH -o <dir>/<file> <args>`, checked to succeed.
fn curvature(dir: &Path, file: &str, args: &[&str]) -> std::path::PathBuf {
    let path = dir.join(file);
    let out = crestline(&[&["curvature", MESH, "-o", path.to_str().unwrap()][..], args].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    path
}

#[test]
fn quality_is_the_chosen_curvature_and_the_mean_by_default() {
    let dir = tempfile::tempdir().unwrap();
    let default = curvature(dir.path(), "default.ply", &[]);
    let name = CurvatureOptions::default().quality.name();
    assert_eq!(property(&default, "quality"), property(&default, name));
    for name in ["k_max", "k_min", "mean", "gauss"] {
        let path = curvature(dir.path(), &format!("{name}.ply"), &["--quality", name]);
        assert_eq!(property(&path, "quality"), property(&path, name), "{name}");
    }
    let path = curvature(dir.path(), "c.ply", &["--quality", "curvedness"]);
    let curvedness: Vec<f64> = property(&path, "k_max")
        .iter()
        .zip(property(&path, "k_min"))
        .map(|(a, b)| (0.5 * (a * a + b * b)).sqrt())
        .collect();
    assert_eq!(property(&path, "quality"), curvedness);
}

#[test]
fn an_unknown_quality_is_refused_with_the_names() {
    let out = crestline(&["curvature", MESH, "-o", "never.ply", "--quality", "k1"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    for name in Quality::NAMES {
        assert!(err.contains(name), "{err}");
    }
    assert!(!Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../never.ply")).exists());
}
