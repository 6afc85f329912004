//! Reading and repairing the input mesh, with a progress bar on a terminal.

use std::io::IsTerminal;
use std::path::Path;

use crestline::io::read_mesh_with_progress;
use crestline::mesh::{Mesh, RepairReport};
use crestline::report::Report;
use crestline::Result;
use indicatif::{ProgressBar, ProgressStyle};

/// Read `path` and build the repaired halfedge mesh, recording the stages `read`
/// and `build` in `report`. A byte progress bar is drawn on stderr when it is a
/// terminal and the file is large enough for the wait to be noticeable.
pub fn load_mesh(path: &Path, report: &mut Report) -> Result<(Mesh, RepairReport)> {
    let bar = progress_bar(path);
    let update = |done: u64, total: u64| {
        bar.set_length(total);
        bar.set_position(done);
    };
    let soup = report.stage("read", || read_mesh_with_progress(path, &update));
    bar.finish_and_clear();
    let soup = soup?;
    report
        .stage("build", || Mesh::from_soup(soup))
        .map_err(|e| e.in_file(path))
}

fn progress_bar(path: &Path) -> ProgressBar {
    const WORTH_SHOWING: u64 = 16 << 20;
    let size = std::fs::metadata(path).map(|m| m.len()).unwrap_or(0);
    if !std::io::stderr().is_terminal() || size < WORTH_SHOWING {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(size);
    let style =
        ProgressStyle::with_template("reading {msg} {bar:30} {bytes}/{total_bytes} ({eta})")
            .unwrap_or_else(|_| ProgressStyle::default_bar());
    bar.set_style(style);
    bar.set_message(path.display().to_string());
    bar
}

/// Print each repair as a warning naming the file.
pub fn warn_repairs(path: &Path, repairs: &RepairReport) {
    for message in repairs.messages() {
        eprintln!("warning: {}: {message}", path.display());
    }
}
