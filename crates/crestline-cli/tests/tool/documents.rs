//! The documents' commands and links: every `crestline …` line (and every
//! `cargo run --release -- …` line, run as `crestline …`) of a ```` ```sh ```` block in
//! README.md and docs/guide/*.md runs as written and exits with 0, and every relative
//! link of README.md and docs/ names a file that exists (and a heading, where it
//! names one). Every ```` ```rust ```` block of README.md and docs/guide/*.md is
//! code of this file, compiled and run.
//!
//! The commands of one page run in order in one temporary directory holding links
//! to the repository's `meshes/`, `volumes/` and, when fetched, `data/`, so a command
//! may read what an earlier one on the same page wrote, and nothing is written into
//! the repository. A command naming a file under `data/` that is absent (the
//! `tools/fetch_*` scripts fetch them) is skipped with a message, or fails the test
//! in continuous integration (`CI=true`), where `.ci/run` fetches them all.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;

fn repository() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .canonicalize()
        .expect("the repository's root")
}

/// README.md and the guide's pages, in a fixed order.
fn command_pages(root: &Path) -> Vec<PathBuf> {
    let mut pages = vec![root.join("README.md")];
    let mut guide: Vec<PathBuf> = std::fs::read_dir(root.join("docs/guide"))
        .expect("docs/guide/ exists")
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.extension().is_some_and(|e| e == "md"))
        .collect();
    guide.sort();
    pages.extend(guide);
    pages
}

/// The lines of the ```` ```sh ```` blocks of `text` that run the tool, as
/// `crestline …` (a `cargo run --release -- …` line becomes `crestline …`).
fn tool_commands(text: &str) -> Vec<String> {
    let mut commands = Vec::new();
    let mut in_sh = false;
    for line in text.lines() {
        let trimmed = line.trim();
        if let Some(fence) = trimmed.strip_prefix("```") {
            in_sh = !in_sh && fence.trim() == "sh";
            continue;
        }
        if !in_sh {
            continue;
        }
        if trimmed.starts_with("crestline ") {
            commands.push(trimmed.to_string());
        } else if let Some(rest) = trimmed.strip_prefix("cargo run --release -- ") {
            commands.push(format!("crestline {rest}"));
        }
    }
    commands
}

/// The words of `command` before a `#` comment.
fn words(command: &str) -> Vec<&str> {
    command
        .split_whitespace()
        .take_while(|word| !word.starts_with('#'))
        .collect()
}

/// Why `command` cannot run here, if it names data that a `tools/fetch_*` script
/// fetches and that is absent.
fn missing_data(root: &Path, command: &str) -> Option<String> {
    words(command)
        .into_iter()
        .filter(|word| word.starts_with("data/"))
        .find(|word| !root.join(word).exists())
        .map(|word| format!("{word} is absent (fetched by tools/fetch_*.sh)"))
}

/// Every word of `command` that names a file of the repository's data folders
/// (`meshes/`, `volumes/`), and does not follow `-o`, must exist.
fn missing_inputs(root: &Path, command: &str) -> Vec<String> {
    let words = words(command);
    let mut missing = Vec::new();
    for (i, word) in words.iter().enumerate() {
        let output = i > 0 && words[i - 1] == "-o";
        if !output
            && (word.starts_with("meshes/") || word.starts_with("volumes/"))
            && !root.join(word).exists()
        {
            missing.push(word.to_string());
        }
    }
    missing
}

#[test]
fn every_documented_command_runs_as_written() {
    let root = repository();
    let binary = PathBuf::from(env!("CARGO_BIN_EXE_crestline"));
    let mut ran = 0;
    let mut failures = Vec::new();
    for page in command_pages(&root) {
        let text = std::fs::read_to_string(&page).unwrap();
        let commands = tool_commands(&text);
        if commands.is_empty() {
            continue;
        }
        let name = page.strip_prefix(&root).unwrap().display().to_string();
        let dir = tempfile::tempdir().unwrap();
        for folder in ["meshes", "volumes", "data"] {
            if root.join(folder).exists() {
                std::os::unix::fs::symlink(root.join(folder), dir.path().join(folder)).unwrap();
            }
        }
        // `crestline` on the PATH is the binary under test.
        let bin = dir.path().join(".bin");
        std::fs::create_dir(&bin).unwrap();
        std::os::unix::fs::symlink(&binary, bin.join("crestline")).unwrap();
        let path = match std::env::var_os("PATH") {
            Some(path) => {
                let mut dirs = vec![bin.clone()];
                dirs.extend(std::env::split_paths(&path));
                std::env::join_paths(dirs).unwrap()
            }
            None => bin.clone().into_os_string(),
        };
        for command in commands {
            let missing = missing_inputs(&root, &command);
            if !missing.is_empty() {
                failures.push(format!(
                    "{name}: `{command}` names {missing:?}, not in the repository"
                ));
                continue;
            }
            if let Some(why) = missing_data(&root, &command) {
                common::skip(&format!("{name}: `{command}`: {why}"));
                continue;
            }
            let start = std::time::Instant::now();
            let out = Command::new("sh")
                .arg("-c")
                .arg(&command)
                .current_dir(dir.path())
                .env("PATH", &path)
                .output()
                .expect("sh runs");
            ran += 1;
            eprintln!(
                "{name}: `{command}`: {:.2} s",
                start.elapsed().as_secs_f64()
            );
            if !out.status.success() {
                failures.push(format!(
                    "{name}: `{command}` exited with {:?}: {}",
                    out.status.code(),
                    String::from_utf8_lossy(&out.stderr).trim()
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(
        ran >= 10,
        "only {ran} documented commands ran; the documents promise ten"
    );
}

#[test]
fn command_lines_are_found_in_sh_blocks_only() {
    let text = "```sh\ncrestline info meshes/cow.obj\ncargo run --release -- info x\nvpype read a.svg\n```\n\
                crestline outside\n```python\ncrestline inside python\n```\n```sh\n  crestline  two\n```\n";
    assert_eq!(
        tool_commands(text),
        vec![
            "crestline info meshes/cow.obj".to_string(),
            "crestline info x".to_string(),
            "crestline  two".to_string(),
        ]
    );
    let root = repository();
    assert!(missing_inputs(&root, "crestline info meshes/cow.obj -o meshes/new.json").is_empty());
    assert_eq!(
        missing_inputs(&root, "crestline info meshes/no.obj"),
        vec!["meshes/no.obj"]
    );
    assert!(missing_data(&root, "crestline info data/no/such.ply # comment").is_some());
}

/// The markdown files of README.md and docs/, recursively.
fn markdown_files(root: &Path) -> Vec<PathBuf> {
    fn walk(dir: &Path, files: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(&path, files);
            } else if path.extension().is_some_and(|e| e == "md") {
                files.push(path);
            }
        }
    }
    let mut files = vec![root.join("README.md")];
    walk(&root.join("docs"), &mut files);
    files.sort();
    files
}

/// The targets of the inline links and images of `text` (`[..](target)`), outside
/// code blocks and code spans.
fn link_targets(text: &str) -> Vec<String> {
    let mut targets = Vec::new();
    let mut in_code = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            in_code = !in_code;
            continue;
        }
        if in_code {
            continue;
        }
        // Drop code spans, whose brackets are not links.
        let mut plain = String::new();
        for (i, piece) in line.split('`').enumerate() {
            if i % 2 == 0 {
                plain.push_str(piece);
            }
        }
        let mut rest = plain.as_str();
        while let Some(at) = rest.find("](") {
            rest = &rest[at + 2..];
            if let Some(end) = rest.find(')') {
                let target = rest[..end].split_whitespace().next().unwrap_or("");
                targets.push(target.to_string());
                rest = &rest[end..];
            }
        }
    }
    targets
}

/// GitHub's anchor of a heading: lower case, spaces to hyphens, punctuation dropped.
fn anchor(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

fn anchors(text: &str) -> Vec<String> {
    let mut found = Vec::new();
    let mut in_code = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            in_code = !in_code;
        } else if !in_code && line.starts_with('#') {
            found.push(anchor(line.trim_start_matches('#')));
        }
    }
    found
}

#[test]
fn every_relative_link_of_the_documents_resolves() {
    let root = repository();
    let mut broken = Vec::new();
    let mut checked = 0;
    for file in markdown_files(&root) {
        let text = std::fs::read_to_string(&file).unwrap();
        let name = file.strip_prefix(&root).unwrap().display().to_string();
        for target in link_targets(&text) {
            if target.is_empty() || target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            checked += 1;
            let (path, fragment) = match target.split_once('#') {
                Some((path, fragment)) => (path, Some(fragment)),
                None => (target.as_str(), None),
            };
            let resolved = if path.is_empty() {
                file.clone()
            } else {
                file.parent().unwrap().join(path)
            };
            if !resolved.exists() {
                broken.push(format!("{name}: {target}: no such file"));
                continue;
            }
            if let Some(fragment) = fragment {
                let is_markdown = resolved.extension().is_some_and(|e| e == "md");
                let headings = if resolved.is_dir() || !is_markdown {
                    continue;
                } else {
                    anchors(&std::fs::read_to_string(&resolved).unwrap())
                };
                if !headings.iter().any(|a| a == fragment) {
                    broken.push(format!("{name}: {target}: no heading #{fragment}"));
                }
            }
        }
    }
    assert!(broken.is_empty(), "{}", broken.join("\n"));
    assert!(checked > 0, "no relative link found");
}

#[test]
fn links_and_anchors_are_read_as_github_does() {
    assert_eq!(
        link_targets("see [a](docs/a.md#x-y) and ![b](p.png \"t\"), `[c](not)` [d](https://x)"),
        vec!["docs/a.md#x-y", "p.png", "https://x"]
    );
    assert_eq!(
        anchor(" Images, landmarks and registration"),
        "images-landmarks-and-registration"
    );
    assert_eq!(anchor("The `draw` command"), "the-draw-command");
}

/// README.md's Rust quick start, as the README shows it between the markers (the
/// test below checks that the page's first ```` ```rust ```` block is this text).
#[allow(unused_variables)]
fn readme_rust_quick_start() -> Result<(), Box<dyn std::error::Error>> {
    // README.md begin
    use crestline::jobs::{self, Surface};
    use crestline::progress::Silent;

    let soup = crestline::io::read_mesh("meshes/bunny.obj".as_ref())?;
    let (mesh, _repairs) = jobs::build_mesh(soup, false, &mut Silent)?;
    let ridges = jobs::ridges(&Surface::of_mesh(mesh), &Default::default(), &mut Silent)?;
    ridges.write("ridges.vtk".as_ref())?;
    // README.md end
    Ok(())
}

/// The jobs of docs/guide/library.md, as its first ```` ```rust ```` block shows them.
#[allow(unused_variables)]
fn guide_library_jobs() -> Result<(), Box<dyn std::error::Error>> {
    // docs/guide/library.md begin
    use crestline::jobs::{self, CrestLinesOptions, Surface};
    use crestline::progress::Silent;

    let volume = crestline::io::read_volume("volumes/mni152_t1_1mm.nii.gz".as_ref())?;
    let crests = jobs::crest_lines(&volume, 60.0, &CrestLinesOptions::default(), &mut Silent)?;
    let soup = crestline::io::read_mesh("meshes/bunny.obj".as_ref())?;
    let (mesh, _repairs) = jobs::build_mesh(soup, false, &mut Silent)?;
    let ridges = jobs::ridges(&Surface::of_mesh(mesh), &Default::default(), &mut Silent)?;
    // docs/guide/library.md end
    assert!(!crests.is_empty() && !ridges.is_empty());
    Ok(())
}

/// The extractors of docs/guide/library.md, as its second ```` ```rust ```` block
/// shows them.
#[allow(unused_variables)]
fn guide_library_extractors() -> Result<(), Box<dyn std::error::Error>> {
    // docs/guide/library.md extractors begin
    use crestline::curvature::{estimate_curvature, JetFit};
    use crestline::lines::{LineExtractor, SurfaceWithCurvature};
    use crestline::mesh::Mesh;
    use crestline::progress::Silent;
    use crestline::ridges::ExtremalityTracer;

    let (mesh, _repairs) = Mesh::from_soup(crestline::io::read_mesh("meshes/cow.obj".as_ref())?)?;
    let lines = ExtremalityTracer::default().extract(&mesh, &mut Silent)?; // curvature estimated
    let field = estimate_curvature(&mesh, &JetFit::default())?; // or from elsewhere
    let given = SurfaceWithCurvature {
        mesh: &mesh,
        curvature: &field,
    };
    let lines = ExtremalityTracer::default().extract(&given, &mut Silent)?;
    lines.write("lines.vtk".as_ref())?;
    // docs/guide/library.md extractors end
    assert!(!lines.is_empty());
    Ok(())
}

/// Every page with Rust code, and the markers of its blocks' code in this file, in
/// the page's order.
const RUST_BLOCKS: [(&str, &[&str]); 2] = [
    ("README.md", &["README.md"]),
    (
        "docs/guide/library.md",
        &["docs/guide/library.md", "docs/guide/library.md extractors"],
    ),
];

#[test]
#[ignore = "run by the_documents_rust_blocks_are_this_code_and_run, beside meshes/ and volumes/"]
fn documents_rust_blocks_child() {
    readme_rust_quick_start().unwrap();
    guide_library_jobs().unwrap();
    guide_library_extractors().unwrap();
}

/// Every ```` ```rust ```` block of `text`, in order.
fn rust_blocks(text: &str) -> Vec<String> {
    text.split("```rust\n")
        .skip(1)
        .filter_map(|rest| rest.find("```").map(|end| rest[..end].to_string()))
        .collect()
}

/// The lines of this file between the markers `// <page> begin` and `// <page> end`,
/// as a page would show them (four spaces less indented).
fn marked_code(page: &str) -> String {
    let source = include_str!("documents.rs");
    let begin_marker = format!("\n    // {page} begin\n");
    let end_marker = format!("\n    // {page} end\n");
    let begin = source.find(&begin_marker).unwrap() + begin_marker.len();
    let end = source.find(&end_marker).unwrap() + 1;
    source[begin..end]
        .lines()
        .map(|line| line.strip_prefix("    ").unwrap_or(line))
        .map(|line| format!("{line}\n"))
        .collect()
}

#[test]
fn the_documents_rust_blocks_are_this_code_and_run() {
    let root = repository();
    let guide = std::fs::read_dir(root.join("docs/guide")).unwrap();
    for path in guide.map(|e| e.unwrap().path()) {
        let text = std::fs::read_to_string(&path).unwrap();
        let page = format!("docs/guide/{}", path.file_name().unwrap().to_string_lossy());
        assert!(
            rust_blocks(&text).is_empty() || RUST_BLOCKS.iter().any(|(p, _)| *p == page),
            "{page} has rust blocks that documents.rs does not compile (RUST_BLOCKS)"
        );
    }
    for (page, markers) in RUST_BLOCKS {
        let text = std::fs::read_to_string(root.join(page)).unwrap();
        let compiled: Vec<String> = markers.iter().map(|m| marked_code(m)).collect();
        assert_eq!(
            rust_blocks(&text),
            compiled,
            "{page}'s rust blocks are not the code compiled in documents.rs"
        );
    }
    // Run them where a user would, beside `meshes/` and `volumes/`.
    let dir = tempfile::tempdir().unwrap();
    for folder in ["meshes", "volumes"] {
        std::os::unix::fs::symlink(root.join(folder), dir.path().join(folder)).unwrap();
    }
    let out = Command::new(std::env::current_exe().unwrap())
        .args([
            "--exact",
            "documents::documents_rust_blocks_child",
            "--ignored",
        ])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    assert!(dir.path().join("ridges.vtk").is_file());
}
