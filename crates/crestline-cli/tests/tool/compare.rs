//! `crestline compare`: a turned copy of a mesh, its lines mapped back by the
//! motion given as a transform file (ours or ITK's), agrees with the original's.

use std::path::Path;

use crestline::register::RigidTransform;
use crestline::Vector;
use nalgebra::Rotation3;

use crate::common::{assert_one_line_error, crestline, stderr};

/// The OBJ file `from` with every vertex moved by `motion`, written to `to`.
fn moved_obj(from: &str, to: &Path, motion: &RigidTransform) {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../");
    let text = std::fs::read_to_string(format!("{root}{from}")).unwrap();
    let moved: String = text
        .lines()
        .map(|line| match line.strip_prefix("v ") {
            Some(rest) => {
                let xyz: Vec<f64> = rest
                    .split_whitespace()
                    .map(|t| t.parse().unwrap())
                    .collect();
                let p = motion.apply(&crestline::Point::new(xyz[0], xyz[1], xyz[2]));
                format!("v {} {} {}\n", p.x, p.y, p.z)
            }
            None => format!("{line}\n"),
        })
        .collect();
    std::fs::write(to, moved).unwrap();
}

/// An ITK transform file of `motion`, as SimpleITK writes an affine transform:
/// the matrix row by row and the translation, about the centre 0.
fn itk_file(motion: &RigidTransform) -> String {
    let m = motion.rotation.matrix();
    let t = motion.translation;
    let numbers: Vec<String> = m
        .transpose()
        .iter()
        .chain(t.iter())
        .map(|x| x.to_string())
        .collect();
    format!(
        "#Insight Transform File V1.0\n#Transform 0\nTransform: AffineTransform_double_3_3\n\
         Parameters: {}\nFixedParameters: 0 0 0\n",
        numbers.join(" ")
    )
}

/// The shares of ridge length (A in B, B in A) that `compare` reports.
fn ridge_shares(a: &Path, b: &Path, extra: &[&str], dir: &Path) -> (f64, f64) {
    let report = dir.join("report.json");
    let mut args = vec!["compare", a.to_str().unwrap(), b.to_str().unwrap()];
    args.extend_from_slice(extra);
    args.extend_from_slice(&["--report", report.to_str().unwrap()]);
    let out = crestline(&args);
    assert!(out.status.success(), "{}", stderr(&out));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("ridge") && stdout.contains("valley"),
        "{stdout}"
    );
    let report: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    let rows = report["comparison"]["lines"].as_array().unwrap();
    let ridge = rows.iter().find(|r| r["kind"] == "ridge").unwrap();
    (
        ridge["a_in_b"].as_f64().unwrap(),
        ridge["b_in_a"].as_f64().unwrap(),
    )
}

#[test]
fn a_turned_copy_mapped_back_has_the_same_lines() {
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name);
    let motion = RigidTransform::new(
        Rotation3::from_euler_angles(0.4, -1.1, 2.0),
        Vector::new(0.3, -0.2, 0.5),
    );
    moved_obj("meshes/bunny_small.obj", &path("turned.obj"), &motion);
    for (mesh, lines) in [
        ("meshes/bunny_small.obj", path("a.json")),
        (path("turned.obj").to_str().unwrap(), path("b.json")),
    ] {
        let out = crestline(&["ridges", mesh, "-o", lines.to_str().unwrap()]);
        assert!(out.status.success(), "{}", stderr(&out));
    }
    // Our JSON maps B onto A; ITK's file maps A's frame to B's, in LPS.
    motion.inverse().write(&path("back.json")).unwrap();
    std::fs::write(path("back.tfm"), itk_file(&motion.flip_xy())).unwrap();
    let (a, b) = (path("a.json"), path("b.json"));
    let tolerance = ["--tolerance", "0.5%"];
    let unmoved = ridge_shares(&a, &b, &tolerance, dir.path());
    assert!(unmoved.0 < 0.2, "{unmoved:?}");
    for transform in ["back.json", "back.tfm"] {
        let transform = path(transform);
        let args = [
            tolerance[0],
            tolerance[1],
            "--transform",
            transform.to_str().unwrap(),
        ];
        let (a_in_b, b_in_a) = ridge_shares(&a, &b, &args, dir.path());
        assert!(a_in_b > 0.99 && b_in_a > 0.99, "{a_in_b} {b_in_a}");
    }
}

#[test]
fn a_mesh_is_not_a_lines_file() {
    let out = crestline(&[
        "compare",
        "meshes/bunny_small.obj",
        "meshes/bunny_small.obj",
    ]);
    assert_one_line_error(
        &out,
        "meshes/bunny_small.obj",
        "a mesh (faces and no lines)",
    );
    let out = crestline(&["compare", "meshes/bone.ply", "meshes/bone.ply"]);
    assert_one_line_error(&out, "meshes/bone.ply", "a mesh (faces and no lines)");
    let out = crestline(&["compare", "meshes/README.md", "meshes/README.md"]);
    assert_one_line_error(&out, "meshes/README.md", "not a file of lines or landmarks");
}
