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
