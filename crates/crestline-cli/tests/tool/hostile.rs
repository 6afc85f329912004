//! Hostile but realistic input and options: every refusal is one line naming the
//! file or the option as typed, never a panic, an abort or an empty file.

use std::io::Write;
use std::path::Path;

use crate::common;

use common::{assert_one_line_error, crestline, stderr};

/// A 20³ NRRD image (unsigned bytes): 0 around a 10³ cube of 255.
fn cube_nrrd(dir: &Path) -> String {
    let n = 20;
    let mut bytes = format!(
        "NRRD0004\ntype: uchar\ndimension: 3\nsizes: {n} {n} {n}\nspace: right-anterior-superior\nspace directions: (1,0,0) (0,1,0) (0,0,1)\nencoding: raw\n\n"
    )
    .into_bytes();
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let inside = [i, j, k].iter().all(|c| (5..15).contains(c));
                bytes.push(if inside { 255 } else { 0 });
            }
        }
    }
    let path = dir.join("cube.nrrd");
    std::fs::write(&path, bytes).unwrap();
    path.to_str().unwrap().to_string()
}

/// The names of the files in `dir`.
fn files_in(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|entry| entry.unwrap().file_name().to_string_lossy().into_owned())
        .collect()
}

#[test]
fn a_level_the_smoothed_image_cannot_reach_is_refused_saying_it_was_smoothed() {
    let dir = tempfile::tempdir().unwrap();
    let image = cube_nrrd(dir.path());
    let out = dir.path().join("out");
    let out = out.to_str().unwrap();
    // `info` says the maximum is 255; the default smoothing lowers it.
    for command in ["iso", "ridges", "morse", "draw"] {
        let output = format!("{out}.{}", if command == "draw" { "svg" } else { "ply" });
        let refused = crestline(&[command, &image, "--level", "255", "-o", &output]);
        assert_one_line_error(&refused, &image, "smoothed by --sigma 1");
        let said = stderr(&refused);
        assert!(said.contains("its samples over [0, 255]"), "{said}");
        assert!(said.contains("or --sigma 0"), "{said}");
    }
    let out = format!("{out}.ply");
    let out = out.as_str();
    let refused = crestline(&["iso", &image, "--sigma", "0", "--level", "256", "-o", out]);
    assert_one_line_error(&refused, &image, "above every sample");
    assert!(
        stderr(&refused).contains("[0, 255]"),
        "{}",
        stderr(&refused)
    );
    // Without smoothing the maximum itself is a level (the cube's faces).
    let kept = crestline(&["iso", &image, "--sigma", "0", "--level", "255", "-o", out]);
    assert!(kept.status.success(), "{}", stderr(&kept));
    std::fs::remove_file(out).unwrap();
    assert_eq!(files_in(dir.path()), ["cube.nrrd"]);
}

#[test]
fn a_minimum_piece_size_above_the_whole_surface_is_refused_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let image = cube_nrrd(dir.path());
    let out = dir.path().join("c.ply");
    let refused = crestline(&[
        "crease",
        &image,
        "--min-component",
        "18446744073709551615",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_one_line_error(&refused, &image, "--min-component 18446744073709551615");
    assert!(stderr(&refused).contains("no piece could be kept"));
    assert!(!out.exists());
}

#[test]
fn camera_errors_name_the_option_and_the_real_cause() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("d.svg");
    let out = out.to_str().unwrap();
    let mesh = "meshes/bunny_small.obj";
    for (option, words, not) in [
        (
            "--camera=0,0,1e308,0,0,0,0,1,0",
            "a distance a double can hold",
            "up vector",
        ),
        ("--camera=0,0,1,0,0,0,0,1,1e308", "up vector", "distance"),
        ("--camera=0,0,1,0,0,0,0,0,2", "parallel", "distance"),
        ("--perspective=0", "between 0 and 180", "camera"),
        ("--size=0x10", "between 1 and", "camera"),
    ] {
        let refused = crestline(&["draw", mesh, option, "-o", out]);
        let said = stderr(&refused);
        let flag = option.split('=').next().unwrap();
        assert_eq!(refused.status.code(), Some(1), "{said}");
        assert_eq!(said.lines().count(), 1, "{said}");
        assert!(
            said.contains(flag) && said.contains(words),
            "{option}: {said}"
        );
        assert!(!said.contains(not), "{option}: {said}");
    }
    assert!(files_in(dir.path()).is_empty());
}

/// A unit sphere of about `n` vertices.
fn sphere(n: usize) -> crestline::mesh::TriangleSoup {
    use crestline::mesh::generate::{sphere, Sampling};
    sphere(1.0, n, Sampling::Regular).unwrap().mesh.to_soup()
}

/// A sphere as ASCII PLY with a double vertex property `quality` alternating
/// ±1e308.
fn extreme_quality_ply(path: &Path) {
    let soup = sphere(200);
    let mut text = format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nproperty double quality\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
        soup.positions.len(),
        soup.triangles.len()
    );
    for (v, p) in soup.positions.iter().enumerate() {
        let q = if v % 2 == 0 { "1e308" } else { "-1e308" };
        text.push_str(&format!("{} {} {} {q}\n", p.x, p.y, p.z));
    }
    for [a, b, c] in &soup.triangles {
        text.push_str(&format!("3 {a} {b} {c}\n"));
    }
    std::fs::write(path, text).unwrap();
}

#[test]
fn values_too_wide_or_a_mesh_too_large_are_refused_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let ply = dir.path().join("extreme.ply");
    extreme_quality_ply(&ply);
    let ply = ply.to_str().unwrap();
    let lines = dir.path().join("m.json");
    let refused = crestline(&[
        "morse",
        ply,
        "--indicator",
        "quality",
        "-o",
        lines.to_str().unwrap(),
    ]);
    assert_one_line_error(&refused, ply, "too wide");

    let obj = dir.path().join("far.obj");
    let soup = sphere(12);
    let mut text = String::new();
    for p in &soup.positions {
        let p = p * 1e307;
        text.push_str(&format!("v {:e} {:e} {:e}\n", p.x, p.y, p.z));
    }
    for [a, b, c] in &soup.triangles {
        text.push_str(&format!("f {} {} {}\n", a + 1, b + 1, c + 1));
    }
    std::fs::write(&obj, text).unwrap();
    let obj = obj.to_str().unwrap();
    let svg = dir.path().join("d.svg");
    let refused = crestline(&["draw", obj, "-o", svg.to_str().unwrap()]);
    assert_one_line_error(&refused, obj, "too large to draw");
    assert_eq!(files_in(dir.path()).len(), 2);
}

#[test]
fn an_unwritable_folder_is_reported_for_the_output_not_a_probe_file() {
    // /proc takes no new files, whoever runs the test.
    for (option, path) in [
        ("-o", "/proc/lines.json"),
        ("--report", "/proc/report.json"),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let lines = dir.path().join("l.json");
        let mut args = vec!["ridges", "meshes/bunny_small.obj"];
        if option == "-o" {
            args.extend(["-o", path]);
        } else {
            args.extend(["-o", lines.to_str().unwrap(), "--report", path]);
        }
        let refused = crestline(&args);
        assert_one_line_error(&refused, path, &format!("cannot write {option}"));
        assert!(
            !stderr(&refused).contains(".crestline-"),
            "{}",
            stderr(&refused)
        );
        assert!(files_in(dir.path()).is_empty());
    }
}

/// A gzip-compressed NIfTI-1 file of unsigned bytes whose header claims
/// `dims` voxels while the stream holds only `held` bytes of zeros.
fn nifti_claiming(path: &Path, dims: [i16; 3], held: usize) {
    let mut header = vec![0u8; 352];
    header[0..4].copy_from_slice(&348i32.to_le_bytes());
    let dim = [3, dims[0], dims[1], dims[2], 1, 1, 1, 1];
    for (n, d) in dim.iter().enumerate() {
        header[40 + 2 * n..42 + 2 * n].copy_from_slice(&d.to_le_bytes());
    }
    header[70..72].copy_from_slice(&2i16.to_le_bytes()); // uint8
    header[72..74].copy_from_slice(&8i16.to_le_bytes());
    for n in 0..4 {
        header[76 + 4 * n..80 + 4 * n].copy_from_slice(&1f32.to_le_bytes());
    }
    header[108..112].copy_from_slice(&352f32.to_le_bytes());
    header[344..348].copy_from_slice(b"n+1\0");
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
    gz.write_all(&header).unwrap();
    gz.write_all(&vec![0u8; held]).unwrap();
    std::fs::write(path, gz.finish().unwrap()).unwrap();
}

/// Run the tool under an address-space limit of 4 GiB.
#[cfg(unix)]
fn crestline_in_4_gib(args: &[&str]) -> std::process::Output {
    std::process::Command::new("sh")
        .arg("-c")
        .arg("ulimit -v 4194304 && exec \"$0\" \"$@\"")
        .arg(env!("CARGO_BIN_EXE_crestline"))
        .args(args)
        .output()
        .unwrap()
}

#[cfg(unix)]
#[test]
fn a_gzip_bomb_is_refused_cleanly_under_an_address_space_limit() {
    let dir = tempfile::tempdir().unwrap();
    // 1024³ samples claimed: 4 GiB as floats, more than the limit allows.
    let bomb = dir.path().join("bomb.nii.gz");
    nifti_claiming(&bomb, [1024, 1024, 1024], 16 << 20);
    assert!(std::fs::metadata(&bomb).unwrap().len() < 1 << 20);
    let bomb = bomb.to_str().unwrap();
    let out = dir.path().join("o.ply");
    for args in [
        vec!["info", bomb],
        vec!["iso", bomb, "--level", "1", "-o", out.to_str().unwrap()],
    ] {
        let refused = crestline_in_4_gib(&args);
        assert_one_line_error(&refused, bomb, "GiB of memory");
    }
    // Without the limit the short stream is found out after the bytes it holds.
    let refused = crestline(&["info", bomb]);
    assert_one_line_error(&refused, bomb, "ends after");
    assert_eq!(files_in(dir.path()), ["bomb.nii.gz"]);
}

#[test]
fn an_image_curvature_that_fails_names_the_image_and_the_way_around() {
    // Voxels 10¹¹ times longer along x than along y and z: the image's own
    // curvature of the surface is not finite; the mesh's is.
    let dir = tempfile::tempdir().unwrap();
    let data: Vec<u8> = (0..120)
        .map(|v| ((v % 6) * 37 + (v / 6 % 5) * 11 + (v / 30) * 53) as u8)
        .collect();
    std::fs::write(dir.path().join("aniso.raw"), data).unwrap();
    let header = dir.path().join("aniso.mhd");
    std::fs::write(
        &header,
        "ObjectType = Image\nNDims = 3\nDimSize = 6 5 4\nElementSpacing = 1e11 1 1\n\
         ElementType = MET_UCHAR\nElementDataFile = aniso.raw\n",
    )
    .unwrap();
    let header = header.to_str().unwrap();
    let out = dir.path().join("o.ply");
    let out = out.to_str().unwrap();
    let args = ["iso", header, "--level", "51", "--sigma", "0", "-o", out];
    let refused = crestline(&args);
    assert_one_line_error(&refused, header, "--curvature mesh");
    let mut args = args.to_vec();
    args.extend(["--curvature", "mesh"]);
    let kept = crestline(&args);
    assert!(kept.status.success(), "{}", stderr(&kept));
}
