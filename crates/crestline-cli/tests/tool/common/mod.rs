//! Helpers shared by the tool's integration tests.

use std::process::{Command, Output};

/// Run the tool with `args` from the repository's root.
pub fn crestline(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_crestline"))
        .args(args)
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .output()
        .expect("the binary runs")
}

/// What the tool wrote to standard error.
#[allow(dead_code)] // not every test binary uses every helper
pub fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Exit code 1 and exactly one line `error: <file>: ...` containing `words`.
#[allow(dead_code)]
pub fn assert_one_line_error(out: &Output, file: &str, words: &str) {
    let err = stderr(out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.starts_with(&format!("error: {file}: ")), "{err}");
    assert!(err.contains(words), "{err}");
}

#[path = "../../../../crestline/tests/library/common/ci.rs"]
mod ci;

#[allow(unused_imports)]
pub use ci::{python, skip};
