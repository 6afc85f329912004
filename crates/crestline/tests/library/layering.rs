//! The core crate's modules form layers along the data flow
//! (base helpers → mesh → chaining → volume → io and isosurfaces → curvature →
//! lines → extractors → drawing, comparison and transfer → views → jobs, which assemble them for the
//! command-line tool and Python), and no module imports from a layer above its
//! own: volumes produce meshes (isosurfaces), so `volume` sits above `mesh`. This
//! test reads every `crate::` path in `src/` and fails on an upward (or sideways,
//! between extractors) edge.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// The layer of each top-level module; lower layers may not import higher ones.
/// Items defined in `lib.rs` itself (`Point`, `Vector`, `Error`, `Result`) are base.
const LAYERS: &[(&str, u32)] = &[
    ("error", 0),
    ("atomic", 0),
    ("differential", 0),
    ("progress", 0),
    ("length", 0),
    ("linalg", 0),
    ("named", 0),
    ("slices", 0),
    ("space", 0),
    ("xml", 0),
    ("mesh", 1),
    ("chain", 2),
    ("volume", 3),
    ("io", 4),
    ("isosurface", 4),
    ("curvature", 5),
    ("lines", 6),
    ("ridges", 7),
    ("morse", 7),
    ("crest_lines", 7),
    ("crease", 7),
    ("landmarks", 7),
    ("register", 7),
    ("draw", 8),
    ("compare", 8),
    ("transfer", 8),
    ("view", 9),
    ("jobs", 10),
];

fn layer(module: &str) -> Option<u32> {
    LAYERS
        .iter()
        .find(|(name, _)| *name == module)
        .map(|&(_, rank)| rank)
}

/// The top-level module a source file belongs to (`src/ridges/trace.rs` → `ridges`).
fn owner(src: &Path, file: &Path) -> Option<String> {
    let relative = file.strip_prefix(src).ok()?;
    let first = relative.components().next()?.as_os_str().to_str()?;
    let name = first.trim_end_matches(".rs");
    (name != "lib").then(|| name.to_string())
}

/// The first segment of every path that starts with `crate::` in the code of `text`
/// (comments, doc links included, are skipped), groups (`crate::{mesh::Mesh, Point}`)
/// expanded.
fn crate_roots(text: &str) -> BTreeSet<String> {
    let code: String = text
        .lines()
        .map(|line| line.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n");
    let mut roots = BTreeSet::new();
    let mut rest = code.as_str();
    while let Some(at) = rest.find("crate::") {
        rest = &rest[at + "crate::".len()..];
        if let Some(group) = rest.strip_prefix('{') {
            roots.extend(group_heads(group));
        } else {
            roots.insert(identifier(rest));
        }
    }
    roots.retain(|root| !root.is_empty());
    roots
}

/// The first identifier of each top-level item of a `{...}` group (the text after
/// the opening brace).
fn group_heads(group: &str) -> Vec<String> {
    let mut heads = vec![identifier(group.trim_start())];
    let mut depth = 0;
    for (i, c) in group.char_indices() {
        match c {
            '{' => depth += 1,
            '}' if depth == 0 => break,
            '}' => depth -= 1,
            ',' if depth == 0 => heads.push(identifier(group[i + 1..].trim_start())),
            _ => {}
        }
    }
    heads
}

fn identifier(text: &str) -> String {
    text.chars()
        .take_while(|c| c.is_alphanumeric() || *c == '_')
        .collect()
}

fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            files.extend(rust_files(&path));
        } else if path.extension().is_some_and(|e| e == "rs") {
            files.push(path);
        }
    }
    files
}

/// Unit tests may use any module (generated meshes, say): a file of tests
/// (`tests.rs`, or under a `tests/` folder; `file` relative to `src`) is not layered.
fn is_test_file(file: &Path) -> bool {
    file.file_name().is_some_and(|name| name == "tests.rs")
        || file.components().any(|c| c.as_os_str() == "tests")
}

/// The code of a file before its inline unit tests (`#[cfg(test)] mod tests`).
fn without_tests(text: &str) -> &str {
    text.find("#[cfg(test)]\nmod tests")
        .map_or(text, |at| &text[..at])
}

/// Every `(file, importer, imported)` edge that breaks the layering.
fn violations(src: &Path) -> Vec<String> {
    let mut bad = Vec::new();
    for file in rust_files(src) {
        let Some(module) = owner(src, &file) else {
            continue;
        };
        let own = layer(&module).unwrap_or_else(|| panic!("{module} has no layer"));
        if is_test_file(file.strip_prefix(src).unwrap()) {
            continue;
        }
        let text = std::fs::read_to_string(&file).unwrap();
        for root in crate_roots(without_tests(&text)) {
            if root.starts_with(char::is_uppercase) || root == module {
                continue;
            }
            let theirs = layer(&root).unwrap_or_else(|| panic!("{root} has no layer"));
            let allowed = theirs < own || (theirs == 0 && own == 0);
            if !allowed {
                bad.push(format!("{}: {module} imports {root}", file.display()));
            }
        }
    }
    bad
}

#[test]
fn no_module_imports_from_a_layer_above_its_own() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let bad = violations(&src);
    assert!(bad.is_empty(), "upward imports:\n{}", bad.join("\n"));
}

#[test]
fn every_top_level_module_has_a_layer() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    for file in rust_files(&src) {
        if let Some(module) = owner(&src, &file) {
            assert!(layer(&module).is_some(), "{module} has no layer");
        }
    }
}

#[test]
fn the_reader_sees_plain_and_grouped_imports() {
    let text = "use crate::mesh::Mesh;\nuse crate::{lines::{Polyline, LineKind}, Point,\n draw};\nlet e = crate::Error::Argument(x); // crate::io\n/// [`crate::morse`]";
    let roots: Vec<String> = crate_roots(text).into_iter().collect();
    assert_eq!(roots, ["Error", "Point", "draw", "lines", "mesh"]);
}

#[test]
fn an_upward_import_is_caught() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("mesh")).unwrap();
    std::fs::write(
        dir.path().join("mesh").join("mod.rs"),
        "use crate::{Point, curvature::CurvatureField};",
    )
    .unwrap();
    std::fs::write(dir.path().join("ridges.rs"), "use crate::morse::Cells;").unwrap();
    let mut bad = violations(dir.path());
    bad.sort();
    assert_eq!(bad.len(), 2, "{bad:?}");
    assert!(bad[0].ends_with("mesh imports curvature"), "{bad:?}");
    assert!(bad[1].ends_with("ridges imports morse"), "{bad:?}");
}
