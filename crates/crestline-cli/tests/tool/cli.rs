//! The command-line tool as a user meets it: exit codes, one-line errors, reports.

use std::process::{Command, Output};

use crate::common;

use common::{assert_one_line_error, crestline, stderr};

/// Run the tool and check that it succeeded (showing its errors otherwise).
fn succeeds(args: &[&str]) -> Output {
    let out = crestline(args);
    assert!(out.status.success(), "{}", stderr(&out));
    out
}

/// The JSON file at `path`.
fn json_file(path: impl AsRef<std::path::Path>) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap()
}

#[test]
fn info_prints_the_bunny_summary() {
    let out = succeeds(&["info", "meshes/bunny.obj"]);
    let text = String::from_utf8(out.stdout).unwrap();
    for line in [
        "vertices          28088",
        "faces             56172",
        "edges             84258",
        "genus             0",
        "repairs           none",
    ] {
        assert!(text.contains(line), "missing '{line}' in\n{text}");
    }
}

#[test]
fn info_summarises_the_mni_template() {
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("r.json");
    let out = succeeds(&[
        "info",
        "volumes/mni152_t1_1mm.nii.gz",
        "--report",
        report.to_str().unwrap(),
    ]);
    let text = String::from_utf8(out.stdout).unwrap();
    for line in [
        "dimensions        197 × 233 × 189 (8675289 voxels)",
        "origin            [-98.0000, -134.0000, -72.0000]",
        "index axes        i → +x, j → +y, k → +z",
        "values            0.000000 .. 255.000000",
        "non-finite        0",
    ] {
        assert!(text.contains(line), "missing '{line}' in\n{text}");
    }
    let json: serde_json::Value = json_file(&report);
    let values = &json["values"];
    assert_eq!(values["histogram"].as_array().unwrap().len(), 64);
    // Otsu's level of a T1 head lies between the dark background and the tissue.
    let otsu = values["otsu"].as_f64().unwrap();
    assert!(otsu > 40.0 && otsu < 160.0, "Otsu level {otsu}");
}

#[test]
fn info_refuses_a_truncated_volume_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let cut = dir.path().join("cut.nii");
    let bytes = std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../volumes/mni152_t1_1mm.nii.gz"
    ))
    .unwrap();
    let mut decoded = Vec::new();
    use std::io::Read;
    flate2::read::GzDecoder::new(&bytes[..])
        .take(352 + 1000)
        .read_to_end(&mut decoded)
        .unwrap();
    std::fs::write(&cut, &decoded).unwrap();
    let path = cut.to_str().unwrap();
    let out = crestline(&["info", path]);
    assert_one_line_error(&out, path, "ends after");
}

#[test]
fn info_lists_repairs() {
    let out = crestline(&["info", "meshes/cow.obj"]);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("1 non-manifold vertices split"), "{text}");
}

#[test]
fn report_has_the_documented_shape() {
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("r.json");
    succeeds(&[
        "info",
        "meshes/bone.ply",
        "--report",
        report.to_str().unwrap(),
    ]);
    let json: serde_json::Value = json_file(&report);
    assert_eq!(json["command"], "info");
    assert_eq!(json["input"], "meshes/bone.ply");
    let stages: Vec<&str> = json["stages"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| {
            assert!(s["seconds"].as_f64().unwrap() >= 0.0);
            s["name"].as_str().unwrap()
        })
        .collect();
    assert_eq!(stages, ["read", "build", "topology"]);
    assert_eq!(json["counts"]["vertices"], 1513);
    assert_eq!(json["counts"]["faces"], 3022);
    assert_eq!(json["repairs"]["unreferenced_vertices"], 359);
}

#[test]
fn missing_file_is_a_one_line_error() {
    let out = crestline(&["info", "meshes/no-such-mesh.obj"]);
    assert_one_line_error(&out, "meshes/no-such-mesh.obj", "no such file");
}

#[test]
fn directory_is_a_one_line_error() {
    let out = crestline(&["info", "meshes"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stderr(&out).starts_with("error: meshes: "),
        "{}",
        stderr(&out)
    );
}

#[test]
fn unknown_extension_lists_the_supported_ones() {
    let out = crestline(&["info", "Cargo.toml"]);
    assert_one_line_error(&out, "Cargo.toml", ".obj");
    for ext in ["ply", "off", "stl"] {
        assert!(stderr(&out).contains(ext));
    }
}

#[test]
fn malformed_file_is_a_one_line_error_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("broken.off");
    std::fs::write(&path, "OFF\n3 1 0\n0 0 0\n1 0 0\n").unwrap();
    let file = path.to_str().unwrap();
    let out = crestline(&["info", file]);
    assert_one_line_error(&out, file, "vertices");
}

#[test]
fn bad_usage_exits_with_two() {
    assert_eq!(crestline(&["info"]).status.code(), Some(2));
    assert_eq!(crestline(&["no-such-command"]).status.code(), Some(2));
    assert_eq!(
        crestline(&["info", "meshes/bunny.obj", "--bogus"])
            .status
            .code(),
        Some(2)
    );
}

#[test]
fn every_subcommand_has_help() {
    let out = crestline(&["--help"]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    let commands: Vec<&str> = text
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|c| *c != "help")
        .collect();
    assert!(commands.contains(&"info"), "{text}");
    for command in commands {
        let out = crestline(&[command, "--help"]);
        assert!(out.status.success(), "{command} --help");
        assert!(String::from_utf8_lossy(&out.stdout).contains("Usage:"));
    }
}

/// The lines of `lines.obj` and `lines.vtk` in `dir` are those of `lines.json`,
/// kind by kind, point for point (`compare` at a tolerance of 10⁻¹²), and
/// `lines.ply` holds as many points and segments as they have.
fn assert_same_lines_in_every_format(dir: &std::path::Path) {
    let json = dir.join("lines.json");
    let lines = json_file(&json);
    for ext in ["obj", "vtk"] {
        let report = dir.join(format!("{ext}.report.json"));
        let file = dir.join(format!("lines.{ext}"));
        succeeds(&[
            "compare",
            json.to_str().unwrap(),
            file.to_str().unwrap(),
            "--tolerance",
            "1e-12",
            "--report",
            report.to_str().unwrap(),
        ]);
        let rows = json_file(&report)["comparison"]["lines"].clone();
        assert_eq!(rows.as_array().unwrap().len(), 2, "{ext}: {rows}");
        for row in rows.as_array().unwrap() {
            for share in ["a_in_b", "b_in_a"] {
                assert!(row[share].as_f64().unwrap() > 1.0 - 1e-9, "{ext}: {row}");
            }
            assert_eq!(row["a_count"], row["b_count"], "{ext}: {row}");
        }
    }
    let all = lines["lines"].as_array().unwrap();
    let points: usize = all
        .iter()
        .map(|l| l["points"].as_array().unwrap().len())
        .sum();
    let closed = all.iter().filter(|l| l["closed"] == true).count();
    let segments = points - all.len() + closed;
    let ply = std::fs::read(dir.join("lines.ply")).unwrap();
    let header_end = ply.windows(10).position(|w| w == b"end_header").unwrap();
    let header = String::from_utf8_lossy(&ply[..header_end]);
    assert!(
        header.contains(&format!("element vertex {points}\n")),
        "{header}"
    );
    assert!(
        header.contains(&format!("element edge {segments}\n")),
        "{header}"
    );
}

#[test]
fn ridges_writes_every_line_format_and_reports_its_stages() {
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("r.json");
    for ext in ["json", "obj", "ply", "vtk"] {
        let out = dir.path().join(format!("lines.{ext}"));
        succeeds(&[
            "ridges",
            "meshes/cow.obj",
            "-o",
            out.to_str().unwrap(),
            "--report",
            report.to_str().unwrap(),
        ]);
    }
    let json: serde_json::Value = json_file(&report);
    assert_same_lines_in_every_format(dir.path());
    assert_eq!(json["command"], "ridges");
    let stages: Vec<&str> = json["stages"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["name"].as_str().unwrap())
        .collect();
    for stage in [
        "read",
        "build",
        "curvature",
        "extremality",
        "edge signs",
        "smoothing analysis",
        "smoothing",
        "ridges: tracing",
        "valleys: tracing",
        "write",
    ] {
        assert!(stages.contains(&stage), "{stage} missing from {stages:?}");
    }
    let counts = &json["counts"];
    let share = counts["ridges_singular_share"].as_f64().unwrap();
    assert!(share > 0.0 && share < 0.5, "{share}");
    assert!(counts["lines"].as_u64().unwrap() > 0);
    assert!(counts["total_length"].as_f64().unwrap() > 0.0);
}

#[test]
fn ridges_rejects_absurd_parameters_without_writing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("lines.json");
    let out_str = out.to_str().unwrap();
    for arg in [
        "--smooth-time=-1",
        "--threshold=nan",
        "--smooth-steps=100000",
        "--smooth-time=inf",
    ] {
        let run = crestline(&["ridges", "meshes/bunny_small.obj", "-o", out_str, arg]);
        assert_eq!(run.status.code(), Some(1), "{arg}: {}", stderr(&run));
        assert!(
            stderr(&run).starts_with("error: invalid argument: "),
            "{}",
            stderr(&run)
        );
        assert!(!out.exists());
    }
    let run = crestline(&["ridges", "meshes/bunny_small.obj", "-o", "lines.xyz"]);
    assert_one_line_error(&run, "lines.xyz", ".json");
}

#[test]
fn smoothing_weights_come_from_a_text_file_or_a_property() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("lines.json");
    let weights = dir.path().join("weights.txt");
    let vertices = 1839; // bunny_small.obj
    std::fs::write(&weights, "1.0\n".repeat(vertices)).unwrap();
    let run = |w: &str| {
        crestline(&[
            "ridges",
            "meshes/bunny_small.obj",
            "-o",
            out.to_str().unwrap(),
            "--smoothing-weights",
            w,
        ])
    };
    let ok = run(weights.to_str().unwrap());
    assert!(ok.status.success(), "{}", stderr(&ok));
    std::fs::write(&weights, "1.0\n".repeat(vertices - 1)).unwrap();
    let short = run(weights.to_str().unwrap());
    assert_one_line_error(
        &short,
        weights.to_str().unwrap(),
        "1838 values for the 1839 vertices",
    );
    std::fs::write(&weights, "1.0\nabc\n").unwrap();
    let garbage = run(weights.to_str().unwrap());
    assert_one_line_error(&garbage, weights.to_str().unwrap(), "line 2");
    let missing = run("no_such_property");
    assert_one_line_error(
        &missing,
        "meshes/bunny_small.obj",
        "no vertex property 'no_such_property'",
    );
}

#[test]
fn morse_reports_critical_points_before_and_after_and_writes_the_hierarchy() {
    let dir = tempfile::tempdir().unwrap();
    let (out, report, hierarchy, plot) = (
        dir.path().join("m.json"),
        dir.path().join("r.json"),
        dir.path().join("h.json"),
        dir.path().join("h.png"),
    );
    succeeds(&[
        "morse",
        "meshes/bunny_small.obj",
        "-o",
        out.to_str().unwrap(),
        "--keep-saddles",
        "20",
        "--report",
        report.to_str().unwrap(),
        "--hierarchy",
        hierarchy.to_str().unwrap(),
        "--hierarchy-plot",
        plot.to_str().unwrap(),
    ]);
    let json: serde_json::Value = json_file(&report);
    let chi = |counts: &serde_json::Value| {
        counts["minima"].as_i64().unwrap() - counts["saddles"].as_i64().unwrap()
            + counts["maxima"].as_i64().unwrap()
    };
    assert_eq!(chi(&json["counts"]), 2);
    assert_eq!(chi(&json["counts_after"]), 2);
    assert_eq!(json["counts_after"]["saddles"], 20);
    let cancellations: serde_json::Value = json_file(&hierarchy);
    let cancelled = cancellations["cancellations"].as_array().unwrap();
    let initial = json["counts"]["saddles"].as_u64().unwrap() as usize;
    assert_eq!(cancelled.len(), initial - 20);
    assert!(cancelled
        .iter()
        .all(|c| c["t"].is_number() && c["saddle"].is_u64()));
    // Significance never decreases, is at least each t, and one saddle goes per
    // cancellation down to the 20 kept.
    let field = |c: &serde_json::Value, key: &str| c[key].as_f64().unwrap();
    assert!(cancelled
        .windows(2)
        .all(|w| field(&w[0], "significance") <= field(&w[1], "significance")));
    assert!(cancelled
        .iter()
        .all(|c| field(c, "significance") >= field(c, "t")));
    let left: Vec<u64> = cancelled
        .iter()
        .map(|c| c["saddles_left"].as_u64().unwrap())
        .collect();
    assert_eq!(left.first(), Some(&(initial as u64 - 1)));
    assert_eq!(left.last(), Some(&20));
    let png = std::fs::read(&plot).unwrap();
    assert!(png.starts_with(b"\x89PNG"), "not a PNG");
    let lines = crestline::lines::FeatureLines::read_json(&out).unwrap();
    assert!(lines
        .iter()
        .all(|l| l.kind == crestline::lines::LineKind::Ascending));
    assert!(!lines.is_empty() && lines.len() <= 20);
}

/// A copy of the bundled mesh `name` in `dir`, under `as_name`.
fn copy_mesh(dir: &std::path::Path, name: &str, as_name: &str) -> std::path::PathBuf {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../meshes");
    let path = dir.join(as_name);
    std::fs::copy(std::path::Path::new(root).join(name), &path).unwrap();
    path
}

/// The names of the files in `dir`, sorted.
fn files_in(dir: &std::path::Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// Run `args` (`{}` stands for `dir`), expecting exit 1 with a one-line error that
/// names `file` and contains `words`, and no file created or changed in `dir`.
fn assert_refused_untouched(dir: &std::path::Path, args: &[&str], file: &str, words: &str) {
    let before: Vec<(String, Vec<u8>)> = files_in(dir)
        .into_iter()
        .map(|name| {
            let bytes = std::fs::read(dir.join(&name)).unwrap();
            (name, bytes)
        })
        .collect();
    let dir_text = dir.to_str().unwrap();
    let args: Vec<String> = args.iter().map(|a| a.replace("{}", dir_text)).collect();
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let out = crestline(&args);
    assert_one_line_error(&out, &file.replace("{}", dir_text), words);
    let after: Vec<(String, Vec<u8>)> = files_in(dir)
        .into_iter()
        .map(|name| {
            let bytes = std::fs::read(dir.join(&name)).unwrap();
            (name, bytes)
        })
        .collect();
    assert!(before == after, "{args:?} changed the files in {dir_text}");
}

#[test]
fn an_output_that_is_an_input_is_refused_and_the_input_kept() {
    let dir = tempfile::tempdir().unwrap();
    copy_mesh(dir.path(), "bunny_small.obj", "x.obj");
    copy_mesh(dir.path(), "bone.ply", "x.ply");
    std::fs::write(dir.path().join("style.json"), "{}\n").unwrap();
    let cases: [(&[&str], &str); 9] = [
        (&["ridges", "{}/x.obj", "-o", "{}/x.obj"], "{}/x.obj"),
        (&["morse", "{}/x.obj", "-o", "{}/x.obj"], "{}/x.obj"),
        (&["ridges", "{}/x.obj", "-o", "{}/./x.obj"], "{}/./x.obj"),
        (
            &[
                "ridges",
                "{}/x.obj",
                "-o",
                "{}/l.json",
                "--report",
                "{}/x.obj",
            ],
            "{}/x.obj",
        ),
        (
            &[
                "morse",
                "{}/x.obj",
                "-o",
                "{}/l.json",
                "--hierarchy",
                "{}/x.obj",
            ],
            "{}/x.obj",
        ),
        (&["info", "{}/x.obj", "--report", "{}/x.obj"], "{}/x.obj"),
        (&["curvature", "{}/x.ply", "-o", "{}/x.ply"], "{}/x.ply"),
        (
            &["draw", "{}/x.obj", "-o", "{}/d.svg", "--report", "{}/x.obj"],
            "{}/x.obj",
        ),
        (
            &[
                "draw",
                "{}/x.obj",
                "-o",
                "{}/d.svg",
                "--style",
                "{}/style.json",
                "--report",
                "{}/style.json",
            ],
            "{}/style.json",
        ),
    ];
    for (args, file) in cases {
        assert_refused_untouched(dir.path(), args, file, "would replace");
    }
}

#[cfg(unix)]
#[test]
fn an_output_that_links_to_the_input_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = copy_mesh(dir.path(), "bunny_small.obj", "x.obj");
    std::os::unix::fs::symlink(&mesh, dir.path().join("link.obj")).unwrap();
    let args = ["ridges", "{}/link.obj", "-o", "{}/x.obj"];
    assert_refused_untouched(dir.path(), &args, "{}/x.obj", "the input mesh");
}

#[test]
fn an_output_given_twice_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    copy_mesh(dir.path(), "bunny_small.obj", "x.obj");
    let cases: [&[&str]; 3] = [
        &[
            "ridges",
            "{}/x.obj",
            "-o",
            "{}/a.json",
            "--report",
            "{}/a.json",
        ],
        &[
            "morse",
            "{}/x.obj",
            "-o",
            "{}/a.json",
            "--hierarchy",
            "{}/h.json",
            "--report",
            "{}/h.json",
        ],
        &[
            "draw", "{}/x.obj", "-o", "{}/d.svg", "--png", "--report", "{}/d.png",
        ],
    ];
    for args in cases {
        let file = args.last().unwrap();
        assert_refused_untouched(dir.path(), args, file, "given for both");
    }
}

#[test]
fn a_missing_output_directory_fails_before_any_file_is_written() {
    let dir = tempfile::tempdir().unwrap();
    copy_mesh(dir.path(), "bunny_small.obj", "x.obj");
    let cases: [&[&str]; 3] = [
        &[
            "ridges",
            "{}/x.obj",
            "-o",
            "{}/a.json",
            "--report",
            "{}/no/r.json",
        ],
        &[
            "morse",
            "{}/x.obj",
            "-o",
            "{}/a.json",
            "--hierarchy",
            "{}/no/h.json",
        ],
        &[
            "draw",
            "{}/x.obj",
            "-o",
            "{}/d.svg",
            "--report",
            "{}/no/r.json",
        ],
    ];
    for args in cases {
        let file = args.last().unwrap();
        assert_refused_untouched(dir.path(), args, file, "does not exist");
    }
}

/// A Möbius strip of `n` quads (two triangles each), consistently wound along the
/// strip, whose ends meet with a half twist.
fn moebius_obj(n: usize) -> String {
    let mut text = String::new();
    for i in 0..n {
        let theta = std::f64::consts::TAU * i as f64 / n as f64;
        for u in [-0.3, 0.3] {
            let r = 1.0 + u * (theta / 2.0).cos();
            let z = u * (theta / 2.0).sin();
            text += &format!("v {} {} {z}\n", r * theta.cos(), r * theta.sin());
        }
    }
    for i in 0..n {
        let (a, b) = (2 * i + 1, 2 * i + 2);
        // The last quad meets the first with the two sides swapped.
        let (c, d) = if i + 1 < n { (a + 2, b + 2) } else { (2, 1) };
        text += &format!("f {a} {c} {d}\nf {a} {d} {b}\n");
    }
    text
}

#[test]
fn strict_refuses_a_moebius_strip_that_the_default_cuts_open() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("moebius.obj");
    std::fs::write(&mesh, moebius_obj(24)).unwrap();
    let mesh = mesh.to_str().unwrap();
    succeeds(&["info", mesh]);
    let refused = crestline(&["info", mesh, "--strict"]);
    assert_one_line_error(&refused, mesh, "orient");
    let out = dir.path().join("lines.json");
    let refused = crestline(&["ridges", mesh, "--strict", "-o", out.to_str().unwrap()]);
    assert_one_line_error(&refused, mesh, "orient");
    assert!(!out.exists());
}

/// `copies` tori (major radius 1, minor 0.35) side by side along x, each an
/// `nu` × `nv` grid of quads split in two, faces wound counter-clockwise seen from
/// outside.
fn tori_obj(copies: usize, nu: usize, nv: usize) -> String {
    let (mut vertices, mut faces) = (String::new(), String::new());
    for k in 0..copies {
        for i in 0..nu {
            for j in 0..nv {
                let (u, v) = (
                    std::f64::consts::TAU * i as f64 / nu as f64,
                    std::f64::consts::TAU * j as f64 / nv as f64,
                );
                let r = 1.0 + 0.35 * v.cos();
                let x = r * u.cos() + 3.0 * k as f64;
                vertices += &format!("v {x} {} {}\n", r * u.sin(), 0.35 * v.sin());
            }
        }
        let id = |i: usize, j: usize| k * nu * nv + (i % nu) * nv + (j % nv) + 1;
        for i in 0..nu {
            for j in 0..nv {
                let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                faces += &format!("f {a} {b} {c}\nf {a} {c} {d}\n");
            }
        }
    }
    vertices + &faces
}

#[test]
fn morse_keeps_saddles_forced_by_topology_and_warns_when_nothing_is_left() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("tori.obj");
    std::fs::write(&mesh, tori_obj(3, 40, 16)).unwrap();
    let (mesh, out, report) = (
        mesh.to_str().unwrap(),
        dir.path().join("lines.json"),
        dir.path().join("r.json"),
    );
    let run = |extra: &[&str]| {
        let mut args = vec![
            "morse",
            mesh,
            "-o",
            out.to_str().unwrap(),
            "--report",
            report.to_str().unwrap(),
        ];
        args.extend(extra);
        let run = crestline(&args);
        assert!(run.status.success(), "{}", stderr(&run));
        let json: serde_json::Value = json_file(&report);
        let lines = crestline::lines::FeatureLines::read_json(&out).unwrap();
        let saddles = json["counts_after"]["saddles"].as_u64().unwrap();
        let forced = json["counts_after"]["forced_saddles"].as_u64().unwrap();
        (stderr(&run), saddles - forced, forced, lines.len())
    };
    // Everything that can be cancelled is: the six saddles left (two per torus)
    // are forced by topology and hidden, which is said.
    let (warning, cancellable, forced, lines) = run(&["--keep-saddles", "0"]);
    assert_eq!((cancellable, forced, lines), (0, 6, 0));
    assert!(
        warning.starts_with(&format!("warning: {mesh}: ")),
        "{warning}"
    );
    assert!(warning.contains("--keep-forced"), "{warning}");
    // Forced saddles do not count towards --keep-saddles: fewer than six saddles
    // kept still leaves lines.
    let (warning, cancellable, forced, lines) = run(&["--keep-saddles", "4"]);
    assert!(cancellable > 0 && cancellable <= 4, "{cancellable}");
    assert!(forced > 0 && lines > 0, "{forced} forced, {lines} lines");
    assert!(warning.is_empty(), "{warning}");
}

#[test]
fn empty_results_are_warned_about_with_the_option_to_change() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("lines.json");
    let run = succeeds(&[
        "ridges",
        "meshes/bunny_small.obj",
        "-o",
        out.to_str().unwrap(),
        "--threshold",
        "1e9",
    ]);
    assert!(crestline::lines::FeatureLines::read_json(&out)
        .unwrap()
        .is_empty());
    assert!(
        stderr(&run).starts_with("warning: meshes/bunny_small.obj: ")
            && stderr(&run).contains("--threshold"),
        "{}",
        stderr(&run)
    );
    let svg = dir.path().join("d.svg");
    let run = succeeds(&[
        "draw",
        "meshes/bunny_small.obj",
        "-o",
        svg.to_str().unwrap(),
        "--lines",
        "none",
    ]);
    assert!(stderr(&run).contains("--silhouettes"), "{}", stderr(&run));
}

#[test]
fn morse_smoothing_iterations_are_capped() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("lines.json");
    let run = crestline(&[
        "morse",
        "meshes/bunny_small.obj",
        "-o",
        out.to_str().unwrap(),
        "--smooth",
        "5000",
    ]);
    assert_eq!(run.status.code(), Some(1), "{}", stderr(&run));
    assert!(stderr(&run).contains("at most 1000"), "{}", stderr(&run));
    assert_eq!(stderr(&run).lines().count(), 1);
    assert!(!out.exists());
}

#[test]
fn a_failed_solve_names_the_file_the_stage_and_what_to_try() {
    let dir = tempfile::tempdir().unwrap();
    let (out, weights) = (dir.path().join("lines.json"), dir.path().join("w.txt"));
    // Weights and a time step so large that the smoothing matrix overflows.
    std::fs::write(&weights, "1e300\n".repeat(1839)).unwrap();
    let run = crestline(&[
        "ridges",
        "meshes/bunny_small.obj",
        "-o",
        out.to_str().unwrap(),
        "--smoothing-weights",
        weights.to_str().unwrap(),
        "--smooth-time",
        "1e300",
    ]);
    assert_one_line_error(
        &run,
        "meshes/bunny_small.obj",
        "extremality smoothing failed: ",
    );
    assert!(stderr(&run).contains("try "), "{}", stderr(&run));
    assert!(stderr(&run).contains("--smooth-time"), "{}", stderr(&run));
    assert!(!out.exists());
}

/// The lines do not depend on how many threads compute them.
#[test]
fn one_thread_gives_the_same_lines_as_many() {
    let dir = tempfile::tempdir().unwrap();
    let outputs: Vec<Vec<u8>> = ["1", "0"]
        .iter()
        .map(|threads| {
            let out = dir.path().join(format!("lines-{threads}.json"));
            succeeds(&[
                "--threads",
                threads,
                "ridges",
                "meshes/bunny_small.obj",
                "-o",
                out.to_str().unwrap(),
            ]);
            std::fs::read(out).unwrap()
        })
        .collect();
    assert!(outputs[0].len() > 100);
    assert_eq!(outputs[0], outputs[1]);
}

const MNI: &str = "volumes/mni152_t1_1mm.nii.gz";

#[test]
fn iso_writes_a_closed_brain_surface_with_image_curvature() {
    let dir = tempfile::tempdir().unwrap();
    let surface = dir.path().join("brain.ply");
    let report = dir.path().join("r.json");
    succeeds(&[
        "iso",
        MNI,
        "--level",
        "60",
        "-o",
        surface.to_str().unwrap(),
        "--report",
        report.to_str().unwrap(),
    ]);
    let json: serde_json::Value = json_file(&report);
    let counts = &json["counts"];
    // The brain's outer surface is one sphere-like sheet, closed by a cap where
    // the brain stem leaves the grid through its lowest slice: χ = 2.
    assert_eq!(counts["boundary_loops"], 0, "{counts}");
    assert_eq!(counts["euler_characteristic"], 2, "{counts}");
    assert!(counts["vertices"].as_u64().unwrap() > 100_000, "{counts}");
    // σ is the feature scale, from the volume the surface encloses (1.9 litres).
    let scale = counts["scale"].as_f64().unwrap();
    assert!((2.4..2.55).contains(&scale), "{counts}");
    assert_eq!(json["sigma"], scale);
    // Left open: one hole there, χ = 2 − 1.
    let open = dir.path().join("open.obj");
    succeeds(&[
        "iso",
        MNI,
        "--level",
        "60",
        "--close",
        "false",
        "-o",
        open.to_str().unwrap(),
        "--report",
        report.to_str().unwrap(),
    ]);
    let counts = &json_file(&report)["counts"];
    assert_eq!(counts["boundary_loops"], 1, "{counts}");
    assert_eq!(counts["euler_characteristic"], 1, "{counts}");
    let header = std::fs::read(&surface).unwrap();
    let header = String::from_utf8_lossy(&header[..600]);
    for property in ["k_max", "k_min", "n_x", "unreliable"] {
        assert!(
            header.contains(&format!("property double {property}")),
            "{header}"
        );
    }
}

#[test]
fn a_volume_without_level_or_a_mesh_with_one_is_refused_in_one_line() {
    let out = crestline(&["ridges", MNI, "-o", "never.json"]);
    assert_one_line_error(&out, MNI, "--level");
    let out = crestline(&[
        "morse",
        "meshes/bunny.obj",
        "--level",
        "3",
        "-o",
        "never.json",
    ]);
    assert_one_line_error(&out, "meshes/bunny.obj", "apply to 3D images");
    assert!(!std::path::Path::new("never.json").exists());
}

#[test]
fn iso_at_a_level_outside_the_values_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let surface = dir.path().join("none.ply");
    let out = crestline(&[
        "iso",
        MNI,
        "--level",
        "1000",
        "-o",
        surface.to_str().unwrap(),
    ]);
    assert_one_line_error(&out, MNI, "1000");
    assert!(!surface.exists());
}

#[test]
fn landmarks_of_the_brain_land_on_it_in_slicer_coordinates() {
    let dir = tempfile::tempdir().unwrap();
    let (json, slicer) = (
        dir.path().join("brain.json"),
        dir.path().join("brain.mrk.json"),
    );
    for path in [&json, &slicer] {
        succeeds(&[
            "landmarks",
            MNI,
            "--level",
            "60",
            "-o",
            path.to_str().unwrap(),
        ]);
    }
    let json: serde_json::Value = json_file(&json);
    assert_eq!(json["space"], "RAS");
    let points = json["points"].as_array().unwrap();
    let count = |kind: &str| points.iter().filter(|p| p["kind"] == kind).count();
    assert!(count("extremal") > 100 && count("curvature_maximum") > 100 && count("end") > 100);
    // The same points in the Slicer file, in LPS: x and y negated.
    let slicer: serde_json::Value = json_file(&slicer);
    let fiducials = slicer["markups"][0]["controlPoints"].as_array().unwrap();
    assert_eq!(fiducials.len(), points.len());
    for (lps, ras) in fiducials.iter().zip(points) {
        let [x, y, z] = [0, 1, 2].map(|i| ras["position"][i].as_f64().unwrap());
        assert_eq!(lps["position"], serde_json::json!([-x, -y, z]));
        // On the brain: within the template's world box (RAS).
        assert!(
            (-98.0..=98.0).contains(&x)
                && (-134.0..=98.0).contains(&y)
                && (-72.0..=116.0).contains(&z)
        );
    }
    let curves = slicer["markups"].as_array().unwrap().len() - 1;
    assert_eq!(curves, json["lines"].as_array().unwrap().len());
}

#[test]
fn landmarks_of_a_mesh_need_a_known_format_and_sane_options() {
    let dir = tempfile::tempdir().unwrap();
    let out_path = dir.path().join("bunny.csv");
    succeeds(&[
        "landmarks",
        "meshes/bunny.obj",
        "-o",
        out_path.to_str().unwrap(),
    ]);
    let text = std::fs::read_to_string(&out_path).unwrap();
    assert!(text.starts_with("id,kind,x,y,z,curvature,line,space\n") && text.lines().count() > 50);
    let bad = crestline(&[
        "landmarks",
        "meshes/bunny.obj",
        "-o",
        dir.path().join("b.txt").to_str().unwrap(),
    ]);
    assert!(!bad.status.success() && stderr(&bad).contains(".mrk.json"));
    let bad = crestline(&[
        "landmarks",
        "meshes/bunny.obj",
        "--radius",
        "0",
        "-o",
        out_path.to_str().unwrap(),
    ]);
    assert!(
        !bad.status.success() && stderr(&bad).contains("finite and positive"),
        "{}",
        stderr(&bad)
    );
    // The failed run left the earlier output as it was.
    assert_eq!(std::fs::read_to_string(&out_path).unwrap(), text);
}

/// The lines of a crest-lines JSON file: kind, length and points.
fn crest_json(path: &std::path::Path) -> Vec<(String, f64, Vec<[f64; 3]>)> {
    let json: serde_json::Value = json_file(path);
    let line = |l: &serde_json::Value| {
        let points: Vec<[f64; 3]> = l["points"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| [0, 1, 2].map(|i| p[i].as_f64().unwrap()))
            .collect();
        let mut length: f64 = points
            .windows(2)
            .map(|w| {
                (0..3)
                    .map(|i| (w[1][i] - w[0][i]).powi(2))
                    .sum::<f64>()
                    .sqrt()
            })
            .sum();
        if l["closed"].as_bool().unwrap() {
            let (a, b) = (points[0], points[points.len() - 1]);
            length += (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt();
        }
        (l["kind"].as_str().unwrap().to_string(), length, points)
    };
    json["lines"].as_array().unwrap().iter().map(line).collect()
}

#[test]
fn seeded_crest_lines_of_the_brain_are_its_long_lines_longest_first() {
    let dir = tempfile::tempdir().unwrap();
    let run = |name: &str, extra: &[&str]| {
        let path = dir.path().join(name);
        // σ of one voxel: thousands of lines, most short, so that drawing 60
        // seeds picks out the long ones.
        let mut args = vec![
            "crest-lines",
            MNI,
            "--level",
            "60",
            "--sigma",
            "1",
            "--min-length",
            "3",
            "-o",
            path.to_str().unwrap(),
        ];
        args.extend(extra);
        let out = crestline(&args);
        assert!(out.status.success(), "{}", stderr(&out));
        crest_json(&path)
    };
    let every = run("every.json", &[]);
    let seeded = run("seeded.json", &["--seeds", "60", "--rng-seed", "3"]);
    assert!(!seeded.is_empty() && seeded.len() * 20 < every.len());
    let first_points: std::collections::HashSet<[u64; 3]> = every
        .iter()
        .flat_map(|(_, _, points)| points.iter().map(|p| p.map(f64::to_bits)))
        .collect();
    for kind in ["ridge", "valley"] {
        let lengths: Vec<f64> = seeded.iter().filter(|l| l.0 == kind).map(|l| l.1).collect();
        assert!(
            lengths.windows(2).all(|w| w[0] >= w[1]),
            "{kind}s not longest first"
        );
        // A line is hit with a probability that grows with its length: the longest
        // seeded line is among the longest tenth of all lines.
        let mut all: Vec<f64> = every.iter().filter(|l| l.0 == kind).map(|l| l.1).collect();
        all.sort_by(f64::total_cmp);
        let tenth = all[all.len() * 9 / 10];
        assert!(
            lengths[0] > tenth,
            "{kind}: the longest seeded line {} is shorter than 10% of all lines ({tenth})",
            lengths[0]
        );
    }
    // Every seeded line is a line of the full sweep, point for point.
    assert!(seeded.iter().all(|(_, _, points)| points
        .iter()
        .all(|p| first_points.contains(&p.map(f64::to_bits)))));
}

#[test]
fn crest_lines_of_the_brain_are_gyri_and_sulci() {
    let dir = tempfile::tempdir().unwrap();
    let lines = dir.path().join("crest.json");
    succeeds(&[
        "crest-lines",
        MNI,
        "--level",
        "60",
        "--min-length",
        "10",
        "-o",
        lines.to_str().unwrap(),
    ]);
    let json: serde_json::Value = json_file(&lines);
    let lines = json["lines"].as_array().unwrap();
    let count = |kind: &str| lines.iter().filter(|l| l["kind"] == kind).count();
    // Convex crests (gyri) and concave ones (sulci) both, and nothing else.
    assert!(
        count("ridge") > 100 && count("valley") > 100,
        "{} ridges, {} valleys",
        count("ridge"),
        count("valley")
    );
    assert_eq!(count("ridge") + count("valley"), lines.len());
    // Every point lies on the brain: within the template's world box.
    for line in lines {
        for p in line["points"].as_array().unwrap() {
            let [x, y, z] = [0, 1, 2].map(|i| p[i].as_f64().unwrap());
            assert!(
                (-98.0..=98.0).contains(&x)
                    && (-134.0..=98.0).contains(&y)
                    && (-72.0..=116.0).contains(&z)
            );
        }
    }
}

/// `p` turned by `degrees` about the unit `axis` (Rodrigues' formula), then shifted
/// by `shift`.
fn rigidly_moved(p: [f64; 3], axis: [f64; 3], degrees: f64, shift: [f64; 3]) -> [f64; 3] {
    let (sin, cos) = degrees.to_radians().sin_cos();
    let dot: f64 = (0..3).map(|i| axis[i] * p[i]).sum();
    let cross = [
        axis[1] * p[2] - axis[2] * p[1],
        axis[2] * p[0] - axis[0] * p[2],
        axis[0] * p[1] - axis[1] * p[0],
    ];
    std::array::from_fn(|i| p[i] * cos + cross[i] * sin + axis[i] * dot * (1.0 - cos) + shift[i])
}

#[test]
fn register_recovers_the_motion_between_ridge_lines_of_a_moved_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let text = std::fs::read_to_string(root.join("meshes/bunny.obj")).unwrap();
    // The moving mesh is the bunny under the inverse motion: its lines, moved by
    // (axis, 30°, shift), land on the bunny's. Inverse: −30° about the axis, after
    // undoing the shift.
    let norm = (0.3f64 * 0.3 + 1.0 + 0.5 * 0.5).sqrt();
    let axis = [0.3 / norm, -1.0 / norm, 0.5 / norm];
    let shift = [0.04, -0.03, 0.05];
    let moved: String = text
        .lines()
        .map(|line| match line.strip_prefix("v ") {
            Some(rest) => {
                let v: Vec<f64> = rest
                    .split_whitespace()
                    .map(|x| x.parse().unwrap())
                    .collect();
                let back = [v[0] - shift[0], v[1] - shift[1], v[2] - shift[2]];
                let p = rigidly_moved(back, axis, -30.0, [0.0; 3]);
                format!("v {} {} {}\n", p[0], p[1], p[2])
            }
            None => format!("{line}\n"),
        })
        .collect();
    let moved_obj = dir.path().join("moved.obj");
    std::fs::write(&moved_obj, moved).unwrap();
    let path = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    for (mesh, lines) in [
        ("meshes/bunny.obj".to_string(), path("fixed.json")),
        (moved_obj.to_str().unwrap().to_string(), path("moving.json")),
    ] {
        succeeds(&["ridges", &mesh, "-o", &lines]);
    }
    // Lines of a mesh do not say their frame: without --space they are refused.
    let refused = crestline(&[
        "register",
        &path("fixed.json"),
        &path("moving.json"),
        "-o",
        &path("t.json"),
    ]);
    let said = String::from_utf8_lossy(&refused.stderr).into_owned();
    assert_eq!(refused.status.code(), Some(1), "{said}");
    assert!(
        said.contains("fixed.json") && said.contains("--space"),
        "{said}"
    );
    let run = succeeds(&[
        "register",
        &path("fixed.json"),
        &path("moving.json"),
        "-o",
        &path("t.json"),
        "--report",
        &path("r.json"),
        "--space",
        "ras",
    ]);
    let said = String::from_utf8_lossy(&run.stdout).into_owned();
    assert!(said.contains("rotation 30.000°"), "{said}");
    let json: serde_json::Value = json_file(path("t.json"));
    assert_eq!(json["coordinate_system"], "RAS");
    // The matrix applied to a point of the moving scan gives the point moved.
    let point = [0.01, 0.12, -0.02];
    let expected = rigidly_moved(point, axis, 30.0, shift);
    for row in 0..3 {
        let m = |c: usize| json["matrix"][row][c].as_f64().unwrap();
        let mapped = m(0) * point[0] + m(1) * point[1] + m(2) * point[2] + m(3);
        assert!(
            (mapped - expected[row]).abs() < 1e-6,
            "{mapped} vs {expected:?}"
        );
    }
    let report: serde_json::Value = json_file(path("r.json"));
    assert_eq!(report["command"], "register");
    assert!(report["counts"]["matched_share"].as_f64().unwrap() > 0.9);
    succeeds(&[
        "register",
        &path("fixed.json"),
        &path("moving.json"),
        "-o",
        &path("t.tfm"),
        "--space",
        "RAS",
    ]);
    let tfm = std::fs::read_to_string(path("t.tfm")).unwrap();
    assert!(
        tfm.starts_with("#Insight Transform File V1.0\n#Transform 0\n"),
        "{tfm}"
    );
    let bad = crestline(&[
        "register",
        &path("fixed.json"),
        &path("moving.json"),
        "-o",
        &path("t.mat"),
    ]);
    assert_one_line_error(&bad, &path("t.mat"), ".json, .tfm");
    // Landmark files: the extremal points lead, the lines follow; the same motion.
    for (mesh, landmarks) in [
        ("meshes/bunny.obj".to_string(), path("fixed.mrk.json")),
        (
            moved_obj.to_str().unwrap().to_string(),
            path("moving.mrk.json"),
        ),
    ] {
        let json = landmarks.replace(".mrk.json", ".landmarks.json");
        succeeds(&["landmarks", &mesh, "-o", &json, "--space", "ras"]);
    }
    succeeds(&[
        "register",
        &path("fixed.landmarks.json"),
        &path("moving.landmarks.json"),
        "-o",
        &path("l.json"),
    ]);
    let json: serde_json::Value = json_file(path("l.json"));
    for row in 0..3 {
        let m = |c: usize| json["matrix"][row][c].as_f64().unwrap();
        let mapped = m(0) * point[0] + m(1) * point[1] + m(2) * point[2] + m(3);
        assert!(
            (mapped - expected[row]).abs() < 1e-6,
            "landmarks: {mapped} vs {expected:?}"
        );
    }
}

/// A NRRD image (float samples, raw, attached) of a spherical shell of radius
/// `radius` and width `width` on a unit grid of `n³` samples.
fn shell_nrrd(path: &std::path::Path, n: usize, radius: f64, width: f64) {
    let c = (n - 1) as f64 / 2.0;
    let mut bytes = format!(
        "NRRD0004\ntype: float\ndimension: 3\nsizes: {n} {n} {n}\nspacings: 1 1 1\nencoding: raw\nendian: little\n\n"
    )
    .into_bytes();
    for i in 0..n * n * n {
        let [x, y, z] = [i % n, (i / n) % n, i / (n * n)].map(|a| a as f64 - c);
        let r = (x * x + y * y + z * z).sqrt();
        let value = (-((r - radius) / width).powi(2)).exp() as f32;
        bytes.extend(value.to_le_bytes());
    }
    std::fs::write(path, bytes).unwrap();
}

#[test]
fn crease_writes_the_ridge_surface_with_its_strength_and_degenerate_marks() {
    let dir = tempfile::tempdir().unwrap();
    let image = dir.path().join("shell.nrrd");
    shell_nrrd(&image, 32, 10.0, 3.0);
    let surface = dir.path().join("shell.ply");
    succeeds(&[
        "crease",
        image.to_str().unwrap(),
        "--sigma",
        "0",
        "-o",
        surface.to_str().unwrap(),
    ]);
    let ply = std::fs::read(&surface).unwrap();
    let header_end = ply.windows(10).position(|w| w == b"end_header").unwrap();
    let header = String::from_utf8_lossy(&ply[..header_end]);
    assert!(
        header.contains("strength") && header.contains("degenerate"),
        "{header}"
    );
    let vertices: usize = header
        .lines()
        .find_map(|l| l.strip_prefix("element vertex "))
        .unwrap()
        .parse()
        .unwrap();
    // The sphere of radius 10 with vertices about a voxel apart.
    assert!(vertices > 1000, "{vertices} vertices");
    let bad = crestline(&[
        "crease",
        image.to_str().unwrap(),
        "--strength",
        "2",
        "-o",
        surface.to_str().unwrap(),
    ]);
    assert!(!bad.status.success());
    // The failed run left the surface as it was.
    assert_eq!(std::fs::read(&surface).unwrap(), ply);
}

#[test]
fn image_commands_set_non_finite_samples_to_the_background_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let image = dir.path().join("shell.nrrd");
    shell_nrrd(&image, 32, 10.0, 3.0);
    // A NaN in the corner, as outside the mask of a resampled scan.
    let mut bytes = std::fs::read(&image).unwrap();
    let data = bytes.windows(2).position(|w| w == b"\n\n").unwrap() + 2;
    bytes[data..data + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    std::fs::write(&image, bytes).unwrap();
    let surface = dir.path().join("shell.ply");
    let lines = dir.path().join("lines.json");
    let runs = [
        vec![
            "crease",
            image.to_str().unwrap(),
            "--sigma",
            "0",
            "-o",
            surface.to_str().unwrap(),
        ],
        vec![
            "crest-lines",
            image.to_str().unwrap(),
            "--level",
            "0.5",
            "--kind",
            "parabolic",
            "-o",
            lines.to_str().unwrap(),
        ],
    ];
    for args in runs {
        let out = crestline(&args);
        assert!(out.status.success(), "{}", stderr(&out));
        assert!(
            stderr(&out).contains("1 samples are not finite"),
            "{}",
            stderr(&out)
        );
    }
    assert!(surface.exists() && lines.exists());
}

/// The smoothing defaults follow the estimator: `--estimator jet-fit` alone
/// smooths as `--smooth-steps 3 --smooth-time 3`, the shape operator as
/// `--smooth-steps 3 --smooth-time 2`; given values override them.
#[test]
fn ridges_smoothing_defaults_follow_the_estimator() {
    let dir = tempfile::tempdir().unwrap();
    let run = |name: &str, extra: &[&str]| {
        let out = dir.path().join(format!("{name}.json"));
        let mut args = vec![
            "ridges",
            "meshes/bunny_small.obj",
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let run = crestline(&args);
        assert!(run.status.success(), "{}", stderr(&run));
        std::fs::read(&out).unwrap()
    };
    let jet = run("jet", &["--estimator", "jet-fit"]);
    let jet_explicit = run(
        "jet_explicit",
        &[
            "--estimator",
            "jet-fit",
            "--smooth-steps",
            "3",
            "--smooth-time",
            "3",
        ],
    );
    let jet_tau_2 = run(
        "jet_tau_2",
        &["--estimator", "jet-fit", "--smooth-time", "2"],
    );
    let shape = run("shape", &[]);
    let shape_explicit = run(
        "shape_explicit",
        &["--smooth-steps", "3", "--smooth-time", "2"],
    );
    assert_eq!(jet, jet_explicit);
    assert_ne!(jet, jet_tau_2);
    assert_eq!(shape, shape_explicit);
}

/// Ctrl-C (SIGINT) during a long command ends it at once, with status 130, and
/// leaves no output file behind.
#[cfg(unix)]
#[test]
fn sigint_stops_a_long_command_promptly_without_output() {
    use std::os::unix::process::ExitStatusExt;
    use std::time::{Duration, Instant};

    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("crease.ply");
    let crest_lines = [
        "crest-lines",
        "volumes/mni152_t1_1mm.nii.gz",
        "--level",
        "80",
    ];
    // Crest lines take 0.6 s on two cores, less on more: they are interrupted a
    // third of the way through a run as long as it takes here. Crease surfaces
    // take about 10 s.
    let measured = tempfile::tempdir().unwrap();
    let whole_json = measured.path().join("whole.json");
    let started = Instant::now();
    let whole = crestline(&[&crest_lines[..], &["-o", whole_json.to_str().unwrap()]].concat());
    assert!(whole.status.success(), "{}", stderr(&whole));
    let third = (started.elapsed().as_millis() as u64 / 3).max(20);
    for (command, delay) in [
        (vec!["crease", "volumes/mni152_t1_1mm.nii.gz"], 700),
        (crest_lines.to_vec(), third),
    ] {
        let output = if command[0] == "crease" {
            out.clone()
        } else {
            dir.path().join("lines.json")
        };
        let mut child = Command::new(env!("CARGO_BIN_EXE_crestline"))
            .args(&command)
            .arg("-o")
            .arg(&output)
            .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(delay));
        assert!(
            child.try_wait().unwrap().is_none(),
            "{command:?} ended too soon to interrupt"
        );
        let sent = Instant::now();
        let kill = Command::new("kill")
            .args(["-INT", &child.id().to_string()])
            .status()
            .unwrap();
        assert!(kill.success());
        let status = child.wait().unwrap();
        let took = sent.elapsed();
        assert_eq!(status.code(), Some(130), "{command:?}: {status:?}");
        assert_eq!(status.signal(), None);
        assert!(
            took < Duration::from_secs(5),
            "{command:?} took {took:?} to stop"
        );
        assert!(!output.exists(), "{command:?} left {}", output.display());
        let leftovers: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert!(leftovers.is_empty(), "{leftovers:?}");
    }
}

/// A 6³ ball of bright voxels as a header (`name`, with `header` the text before
/// the data file's name) and a detached raw data file `data`, in `dir`.
fn detached_ball(dir: &std::path::Path, name: &str, header: &str, data: &str) -> (String, String) {
    let samples: Vec<u8> = (0..216)
        .map(|i| {
            let (x, y, z) = (i % 6, (i / 6) % 6, i / 36);
            let d2 =
                (x * 2 - 5) * (x * 2 - 5) + (y * 2 - 5) * (y * 2 - 5) + (z * 2 - 5) * (z * 2 - 5);
            if d2 < 30 {
                200
            } else {
                0
            }
        })
        .collect();
    let data_path = dir.join(data);
    std::fs::write(&data_path, &samples).unwrap();
    let header_path = dir.join(name);
    std::fs::write(&header_path, format!("{header}{data}\n")).unwrap();
    (
        header_path.to_str().unwrap().to_string(),
        data_path.to_str().unwrap().to_string(),
    )
}

#[test]
fn the_data_file_of_an_input_image_is_never_written_over() {
    let dir = tempfile::tempdir().unwrap();
    let mhd = "ObjectType = Image\nNDims = 3\nDimSize = 6 6 6\nElementType = MET_UCHAR\nElementDataFile = ";
    let nhdr = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 6 6 6\nencoding: raw\ndata file: ";
    for (name, header, data) in [
        ("ball.mhd", mhd, "ball_u8.raw"),
        ("ball.nhdr", nhdr, "ball.vtk"),
    ] {
        let (image, data) = detached_ball(dir.path(), name, header, data);
        let before = std::fs::read(&data).unwrap();
        let out = dir.path().join("out.ply");
        // A data file named like an output (ball.vtk) is refused as -o too.
        let flags: &[&str] = if data.ends_with(".vtk") {
            &["--report", "-o"]
        } else {
            &["--report"]
        };
        for &flag in flags {
            let mut args = vec!["iso", image.as_str(), "--level", "50"];
            if flag == "--report" {
                args.extend(["-o", out.to_str().unwrap()]);
            }
            args.extend([flag, data.as_str()]);
            let refused = crestline(&args);
            assert_one_line_error(&refused, &data, "the data file of the input image");
            assert_eq!(std::fs::read(&data).unwrap(), before, "{name} {flag}");
        }
        succeeds(&["iso", &image, "--level", "50", "-o", out.to_str().unwrap()]);
    }
}

#[test]
fn a_data_file_that_is_a_device_is_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    for (name, header) in [
        ("zero.nhdr", "NRRD0004\ntype: float\ndimension: 3\nsizes: 512 512 512\nendian: little\nencoding: raw\ndata file: /dev/zero\n"),
        ("zero.mhd", "ObjectType = Image\nNDims = 3\nDimSize = 512 512 512\nElementType = MET_FLOAT\nElementDataFile = /dev/zero\n"),
    ] {
        let path = dir.path().join(name);
        std::fs::write(&path, header).unwrap();
        let out = crestline(&["info", path.to_str().unwrap()]);
        assert_one_line_error(&out, path.to_str().unwrap(), "not a regular file");
    }
}

#[test]
fn absurd_thread_and_seed_counts_are_bounded() {
    let start = std::time::Instant::now();
    let out = succeeds(&["--threads", "100000", "info", "meshes/bunny_small.obj"]);
    assert!(
        stderr(&out).contains("--threads 100000: capped at"),
        "{}",
        stderr(&out)
    );
    let dir = tempfile::tempdir().unwrap();
    let lines = dir.path().join("l.json");
    succeeds(&[
        "crest-lines",
        MNI,
        "--level",
        "80",
        "--seeds",
        "18446744073709551615",
        "-o",
        lines.to_str().unwrap(),
    ]);
    // Not a timing: a run that drew 2⁶⁴ seeds would never end at all.
    eprintln!("bounded runs took {:.1} s", start.elapsed().as_secs_f64());
}

#[test]
fn a_level_outside_the_image_or_filters_that_keep_nothing_are_errors_not_empty_files() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("l.json");
    let out = out.to_str().unwrap();
    for (command, level) in [("crest-lines", "300"), ("landmarks", "1000")] {
        let refused = crestline(&[command, MNI, "--level", level, "-o", out]);
        assert_one_line_error(&refused, MNI, "--level");
        assert!(
            stderr(&refused).contains("[0, 255]"),
            "{}",
            stderr(&refused)
        );
    }
    for option in ["--min-length=nan", "--min-length=-1", "--min-strength=inf"] {
        let refused = crestline(&["crest-lines", MNI, "--level", "80", option, "-o", out]);
        let flag = option.split('=').next().unwrap();
        assert_one_line_error(&refused, MNI, flag);
    }
    assert!(!std::path::Path::new(out).exists());
}

#[test]
fn info_of_a_constant_image_prints_no_non_finite_number() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("flat.nrrd");
    let mut bytes =
        b"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 4\nencoding: raw\n\n".to_vec();
    bytes.extend([7u8; 64]);
    std::fs::write(&path, bytes).unwrap();
    let out = succeeds(&["info", path.to_str().unwrap()]);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("Otsu level        none"), "{text}");
    for bad in ["NaN", "inf"] {
        assert!(!text.contains(bad), "{text}");
    }
}

#[test]
fn option_errors_name_the_option_as_typed() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.json");
    let out = out.to_str().unwrap();
    for (args, flag) in [
        (
            vec!["landmarks", "meshes/bunny_small.obj", "--radius=0"],
            "--radius",
        ),
        (
            vec!["landmarks", "meshes/bunny_small.obj", "--persistence=nan"],
            "--persistence",
        ),
        (
            vec!["ridges", "meshes/bunny_small.obj", "--threshold=-1"],
            "--threshold",
        ),
        (
            vec!["ridges", "meshes/bunny_small.obj", "--smooth-time=0"],
            "--smooth-time",
        ),
    ] {
        let mut args = args;
        args.extend(["-o", out]);
        let refused = crestline(&args);
        let said = stderr(&refused);
        assert_eq!(refused.status.code(), Some(1), "{said}");
        assert!(
            said.contains(flag) && said.lines().count() == 1,
            "{args:?}: {said}"
        );
    }
}

/// SIGTERM at any moment of a run, the writing included: either the run had
/// finished (its output complete) or it ends with status 143 and leaves no file,
/// temporary or not.
#[cfg(unix)]
#[test]
fn sigterm_at_any_moment_leaves_a_whole_output_or_nothing() {
    use std::time::{Duration, Instant};

    let spawn = |output: &std::path::Path| {
        Command::new(env!("CARGO_BIN_EXE_crestline"))
            .args(["iso", MNI, "--level", "80", "-o"])
            .arg(output)
            .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap()
    };
    // The signals fall across a whole run as long as it takes on this machine
    // (0.3 s on two idle cores), and once after it; never before 100 ms, when
    // the handlers might not be installed yet.
    let dir = tempfile::tempdir().unwrap();
    let started = Instant::now();
    assert!(spawn(&dir.path().join("brain.vtk"))
        .wait()
        .unwrap()
        .success());
    let whole = started.elapsed().as_millis() as u64;
    let delays: Vec<u64> = (1..=6)
        .map(|k| (whole * k / 6).max(100))
        .chain([whole * 3 / 2])
        .collect();
    let mut interrupted = 0;
    for delay in delays {
        let dir = tempfile::tempdir().unwrap();
        let output = dir.path().join("brain.vtk");
        let mut child = spawn(&output);
        std::thread::sleep(Duration::from_millis(delay));
        Command::new("kill")
            .args(["-TERM", &child.id().to_string()])
            .status()
            .unwrap();
        let status = child.wait().unwrap();
        let files: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|entry| entry.unwrap().file_name())
            .collect();
        match status.code() {
            Some(0) => {
                assert_eq!(files, vec![std::ffi::OsString::from("brain.vtk")]);
                let text = std::fs::read_to_string(&output).unwrap();
                assert!(text.trim_end().ends_with(|c: char| c.is_ascii_digit()));
            }
            Some(143) => {
                interrupted += 1;
                assert!(files.is_empty(), "after {delay} ms: {files:?}");
            }
            other => panic!("after {delay} ms: status {other:?}"),
        }
    }
    assert!(interrupted > 0, "no run was interrupted");
}

#[test]
fn an_image_placed_beyond_the_representable_world_is_refused_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("far.nrrd");
    let mut bytes =
        b"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 4\nspacings: 1e308 1 1\nencoding: raw\n\n"
            .to_vec();
    bytes.extend([7u8; 64]);
    std::fs::write(&path, bytes).unwrap();
    let path = path.to_str().unwrap();
    for command in [
        vec!["info", path],
        vec!["iso", path, "--level", "3", "-o", "never.ply"],
    ] {
        let refused = crestline(&command);
        assert_one_line_error(&refused, path, "spacing");
    }
}

/// A FreeSurfer triangle surface as FreeSurfer writes it: the magic number, a
/// "created by" line, the counts, then big-endian float coordinates and int
/// corners; no footer.
fn write_freesurfer_surface(
    path: &std::path::Path,
    positions: &[crestline::Point],
    triangles: &[[u32; 3]],
) {
    let mut bytes = vec![0xFF, 0xFF, 0xFE];
    bytes.extend_from_slice(b"created by crestline\n\n");
    for count in [positions.len(), triangles.len()] {
        bytes.extend_from_slice(&(count as i32).to_be_bytes());
    }
    for c in positions.iter().flat_map(|p| p.iter()) {
        bytes.extend_from_slice(&(*c as f32).to_be_bytes());
    }
    for &v in triangles.iter().flatten() {
        bytes.extend_from_slice(&(v as i32).to_be_bytes());
    }
    std::fs::write(path, bytes).unwrap();
}

#[test]
fn neuroimaging_outputs_fit_the_input_surface_or_are_refused_up_front() {
    let dir = tempfile::tempdir().unwrap();
    // fsaverage5's pial surface as FreeSurfer writes it: no extension.
    let obj = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../meshes/fsaverage5_pial_left.obj"
    );
    let soup = crestline::io::read_mesh(obj.as_ref()).unwrap();
    let pial = dir.path().join("lh.pial");
    write_freesurfer_surface(&pial, &soup.positions, &soup.triangles);
    let pial = pial.to_str().unwrap();
    let path = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let (curv, shape, label) = (
        path("lh.mean.curv"),
        path("lh.mean.shape.gii"),
        path("lh.r.label"),
    );
    succeeds(&["curvature", pial, "-o", &curv]);
    succeeds(&["curvature", pial, "-o", &shape]);
    succeeds(&["ridges", pial, "-o", &label]);
    let curv = crestline::io::read_vertex_values(curv.as_ref()).unwrap();
    let shape = crestline::io::read_vertex_values(shape.as_ref()).unwrap();
    assert_eq!((curv.len(), shape.len()), (10_242, 10_242));
    assert!(curv.iter().zip(&shape).all(|(c, s)| *c == -*s));
    let text = std::fs::read_to_string(&label).unwrap();
    let count: usize = text.lines().nth(1).unwrap().parse().unwrap();
    assert!(count > 100 && count == text.lines().count() - 2, "{count}");

    let (x, y, z) = (path("x.label.gii"), path("y.label"), path("z.func.gii"));
    let refused = crestline(&["ridges", pial, "--fair", "-o", &x]);
    assert_one_line_error(&refused, &x, "--fair");
    let image = "volumes/mni152_wm_1mm.nii.gz";
    let refused = crestline(&["ridges", image, "--level", "0.5", "-o", &y]);
    assert_one_line_error(&refused, &y, "isosurface");
    let refused = crestline(&["curvature", pial, "-o", &z]);
    assert_one_line_error(&refused, &z, ".shape.gii, .curv");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 4);
}
