//! Reading and repairing the input mesh, with a progress bar on a terminal.

use std::io::IsTerminal;
use std::path::Path;
use std::sync::OnceLock;

use crate::report::{Report, StageObserver};
use crestline::io::{read_mesh_with_progress, read_vertex_values};
use crestline::jobs::build_mesh;
use crestline::mesh::{Mesh, RepairReport, ScalarProperty};
use crestline::{Error, Result};
use indicatif::{MultiProgress, ProgressBar, ProgressFinish, ProgressStyle};

/// How the input mesh is built, an option of every command that reads one.
#[derive(clap::Args, Debug, Clone, Copy, Default)]
pub struct StrictArg {
    /// Refuse a mesh with a component that cannot be oriented consistently (e.g. a
    /// Möbius strip) instead of cutting that component open.
    #[arg(long)]
    pub strict: bool,
}

/// Read `path` and build the repaired halfedge mesh (refusing unorientable
/// components if `strict`), recording the stages `read` and `build` in `report`
/// and each repair as a warning.
/// A byte progress bar is drawn on stderr when it is a terminal and the file is
/// large enough for the wait to be noticeable.
pub fn load_mesh(
    path: &Path,
    strict: StrictArg,
    report: &mut Report,
) -> Result<(Mesh, RepairReport)> {
    load_mesh_with_scalars(path, strict, report, &[])
}

/// Per-vertex values an option reads from a file of their own.
#[derive(Clone, Copy, Debug)]
pub struct ScalarFile<'a> {
    /// The vertex property they are attached under.
    pub name: &'a str,
    /// The file.
    pub path: &'a Path,
    /// The option that names the file (`--indicator`), for messages.
    pub option: &'static str,
    /// Whether the values must also be at least 0 (they must always be finite).
    pub non_negative: bool,
}

impl ScalarFile<'_> {
    /// An error naming the file at its first value that is not finite, or negative
    /// when the values must not be.
    fn check(&self, values: &[f64]) -> Result<()> {
        let wrong = |x: f64| !x.is_finite() || (self.non_negative && x < 0.0);
        let Some(v) = values.iter().position(|&x| wrong(x)) else {
            return Ok(());
        };
        let wanted = if self.non_negative {
            "finite numbers ≥ 0"
        } else {
            "finite numbers"
        };
        Err(Error::File {
            path: self.path.to_path_buf(),
            message: format!(
                "the value of vertex {v} is {}; the values of {} must be {wanted}",
                values[v], self.option
            ),
        })
    }
}

/// [`load_mesh`], attaching per-vertex scalars read from [`ScalarFile`]s of
/// one value per vertex in the mesh file's vertex order (text with one value per
/// line, FreeSurfer curv such as `lh.sulc`, GIfTI `.shape.gii`/`.func.gii`) before
/// the repairs, so the values follow welding and splitting of vertices.
pub fn load_mesh_with_scalars(
    path: &Path,
    strict: StrictArg,
    report: &mut Report,
    scalars: &[ScalarFile<'_>],
) -> Result<(Mesh, RepairReport)> {
    let bar = progress_bar(path);
    let update = |done: u64, total: u64| {
        bar.set_length(total);
        bar.set_position(done);
    };
    let soup = report.stage("read", || read_mesh_with_progress(path, &update));
    bar.finish_and_clear();
    let mut soup = soup?;
    for scalar in scalars {
        let (name, file) = (scalar.name, scalar.path);
        let values = read_vertex_values(file)?;
        if values.len() != soup.positions.len() {
            return Err(Error::File {
                path: file.to_path_buf(),
                message: format!(
                    "{} values for the {} vertices of {}",
                    values.len(),
                    soup.positions.len(),
                    path.display()
                ),
            });
        }
        scalar.check(&values)?;
        soup.vertex_scalars.push(ScalarProperty {
            name: name.to_string(),
            values,
        });
    }
    build_mesh(soup, strict.strict, report).map_err(|e| e.in_file(path))
}

fn progress_bar(path: &Path) -> ProgressBar {
    const WORTH_SHOWING: u64 = 16 << 20;
    let size = std::fs::metadata(path).map(|m| m.len()).unwrap_or(0);
    if !std::io::stderr().is_terminal() || size < WORTH_SHOWING {
        return ProgressBar::hidden();
    }
    let bar = terminal_bars().add(ProgressBar::new(size));
    let style =
        ProgressStyle::with_template("reading {msg} {bar:30} {bytes}/{total_bytes} ({eta})")
            .unwrap_or_else(|_| ProgressStyle::default_bar());
    bar.set_style(style);
    bar.set_message(path.display().to_string());
    bar
}

/// A report for `command` on `input` that, on a terminal, shows the running stage
/// next to a spinner (cleared when the report is dropped).
pub fn report_with_progress(command: &str, input: &Path) -> Report {
    let mut report = Report::new(command, input);
    if std::io::stderr().is_terminal() {
        let spinner =
            terminal_bars().add(ProgressBar::new_spinner().with_finish(ProgressFinish::AndClear));
        spinner.enable_steady_tick(std::time::Duration::from_millis(120));
        let prefix = format!("{command} {}", input.display());
        report.observer =
            StageObserver::new(move |stage| spinner.set_message(format!("{prefix}: {stage}")));
    }
    report
}

/// The progress displays on stderr, drawn together so they do not overwrite each other.
fn terminal_bars() -> &'static MultiProgress {
    static BARS: OnceLock<MultiProgress> = OnceLock::new();
    BARS.get_or_init(MultiProgress::new)
}
