//! The command-line tool as a user meets it: exit codes, one-line errors, reports.

use std::process::{Command, Output};

fn crestline(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_crestline"))
        .args(args)
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .output()
        .expect("the binary runs")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Exit code 1 and exactly one line `error: <file>: ...` containing `words`.
fn assert_one_line_error(out: &Output, file: &str, words: &str) {
    let err = stderr(out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.starts_with(&format!("error: {file}: ")), "{err}");
    assert!(err.contains(words), "{err}");
}

#[test]
fn info_prints_the_bunny_summary() {
    let out = crestline(&["info", "meshes/bunny.obj"]);
    assert!(out.status.success(), "{}", stderr(&out));
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
fn info_lists_repairs() {
    let out = crestline(&["info", "meshes/cow.obj"]);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("1 non-manifold vertices split"), "{text}");
}

#[test]
fn report_has_the_documented_shape() {
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("r.json");
    let out = crestline(&[
        "info",
        "meshes/bone.ply",
        "--report",
        report.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
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

#[test]
fn ridges_writes_every_line_format_and_reports_its_stages() {
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("r.json");
    for ext in ["json", "obj", "ply", "vtk"] {
        let out = dir.path().join(format!("lines.{ext}"));
        let run = crestline(&[
            "ridges",
            "meshes/cow.obj",
            "-o",
            out.to_str().unwrap(),
            "--report",
            report.to_str().unwrap(),
        ]);
        assert!(run.status.success(), "{}", stderr(&run));
        assert!(std::fs::metadata(&out).unwrap().len() > 100, "{ext}");
    }
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
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
        "ridges: smoothing",
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
    let (out, report, hierarchy) = (
        dir.path().join("m.json"),
        dir.path().join("r.json"),
        dir.path().join("h.json"),
    );
    let run = crestline(&[
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
    ]);
    assert!(run.status.success(), "{}", stderr(&run));
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    let chi = |counts: &serde_json::Value| {
        counts["minima"].as_i64().unwrap() - counts["saddles"].as_i64().unwrap()
            + counts["maxima"].as_i64().unwrap()
    };
    assert_eq!(chi(&json["counts"]), 2);
    assert_eq!(chi(&json["counts_after"]), 2);
    assert_eq!(json["counts_after"]["saddles"], 20);
    let cancellations: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&hierarchy).unwrap()).unwrap();
    let cancelled = cancellations["cancellations"].as_array().unwrap();
    let initial = json["counts"]["saddles"].as_u64().unwrap() as usize;
    assert_eq!(cancelled.len(), initial - 20);
    assert!(cancelled
        .iter()
        .all(|c| c["t"].is_number() && c["saddle"].is_u64()));
    let lines = crestline::lines::read_json(&out).unwrap();
    assert!(lines
        .iter()
        .all(|l| l.kind == crestline::lines::LineKind::Ascending));
    assert!(!lines.is_empty() && lines.len() <= 20);
}
