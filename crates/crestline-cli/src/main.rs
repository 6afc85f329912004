//! The `crestline` command-line tool: a thin layer over the library. Exit codes: 0
//! success, 1 an error (printed as one line `error: <file>: <what is wrong>`), 2 bad
//! usage (printed by clap).

/// mimalloc rather than the system allocator: the Morse cancellation alone makes and
/// merges millions of small heaps, and large meshes allocate and free arrays of
/// hundreds of megabytes stage after stage.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

mod compare;
mod crease;
mod crest;
mod curvature;
mod draw;
mod failure;
mod frame;
mod info;
mod iso;
mod landmarks;
mod load;
mod morse;
mod on_surface;
mod outputs;
mod plot;
mod register;
mod report;
mod ridges;
mod signals;
mod structure;
mod surface;
mod view;
mod volume_info;

use std::path::PathBuf;

use outputs::Role;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// Feature lines on surfaces: ridges and valleys of triangle meshes.
#[derive(Parser, Debug)]
#[command(name = "crestline", version, about, long_about = None)]
struct Cli {
    /// Worker threads for the parallel stages (0: one per core).
    #[arg(long, global = true, default_value_t = 0, value_name = "N")]
    threads: usize,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Print the size, topology and geometry of a mesh and every repair its file needed, or the
    /// grid, placement and value statistics of a 3D image.
    Info(info::InfoArgs),
    /// Estimate principal curvatures and directions per vertex; write them as PLY properties.
    Curvature(curvature::CurvatureArgs),
    /// Extract the isosurface of a 3D image as a closed mesh, with the image's curvature.
    Iso(iso::IsoArgs),
    /// Extract ridge or valley surfaces of a 3D image (Schultz, Theisel and Seidel 2010).
    Crease(crease::CreaseArgs),
    /// Trace crest lines of a 3D image's isosurface (Marching Lines, Thirion & Gourdon 1993).
    CrestLines(crest::CrestArgs),
    /// Trace ridge and valley lines (extremality tracing, Hildebrandt et al. 2005).
    Ridges(ridges::RidgesArgs),
    /// Anatomical landmarks from crest lines (extremal points, curvature maxima, line ends)
    /// as 3D Slicer markups, JSON or CSV.
    Landmarks(Box<landmarks::LandmarksArgs>),
    /// Draw feature lines and silhouettes with hidden lines removed, as SVG (and PNG).
    // Boxed: its arguments are by far the largest.
    Draw(Box<draw::DrawArgs>),
    /// Feature lines from the Morse-Smale complex of a curvature indicator (Sahner et al. 2008).
    Morse(morse::MorseCommand),
    /// Find the rigid motion taking one scan's feature lines onto another's (trimmed ICP).
    Register(register::RegisterArgs),
    /// How well two files of lines or landmarks agree, kind by kind, both ways (test–retest).
    Compare(compare::CompareArgs),
    /// An interactive 3D view of the surface and its lines, as one self-contained HTML file.
    View(Box<view::ViewArgs>),
}

/// Options every computing command accepts.
#[derive(clap::Args, Debug)]
pub struct ReportArg {
    /// Write stage timings and counts as JSON to this file.
    #[arg(long, value_name = "FILE")]
    pub report: Option<PathBuf>,
}

impl ReportArg {
    /// The report as an output of the run, if asked for.
    pub fn output(&self) -> Option<Role<'_>> {
        self.report.as_deref().map(|path| ("--report", path))
    }

    /// Write the command's one output file at `output` (the stage `write`) and then
    /// the report if asked for, both under temporary names renamed together at the
    /// end.
    pub fn write_with_output(
        &self,
        report: &mut report::Report,
        output: &std::path::Path,
        write: impl FnOnce(&std::path::Path) -> crestline::Result<()>,
    ) -> crestline::Result<()> {
        let mut files = outputs::OutputSet::default();
        report.stage("write", || files.write(output, write))?;
        if let Some(path) = &self.report {
            files.write(path, |p| report.write(p))?;
        }
        files.commit()
    }
}

/// The most threads `--threads` may ask for, per core: more only adds switching
/// (and spawning 100,000 threads takes minutes).
const MAX_THREADS_PER_CORE: usize = 8;

/// Size the global thread pool every parallel stage (and the sparse solver) runs
/// on; 0 keeps one thread per core, and more than [`MAX_THREADS_PER_CORE`] per
/// core is capped with a warning.
fn use_threads(threads: usize) -> Result<(), rayon::ThreadPoolBuildError> {
    if threads == 0 {
        return Ok(());
    }
    let cores = std::thread::available_parallelism().map_or(1, usize::from);
    let most = MAX_THREADS_PER_CORE * cores;
    if threads > most {
        eprintln!(
            "warning: --threads {threads}: capped at {most} ({MAX_THREADS_PER_CORE} per core)"
        );
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads.min(most))
        .build_global()
}

/// Print a warning about the input `mesh` on stderr.
pub fn warn(mesh: &std::path::Path, message: &str) {
    eprintln!("warning: {}: {message}", mesh.display());
}

/// Parse the command line, run the command, and turn its outcome into an exit code.
fn main() -> ExitCode {
    let cli = Cli::parse();
    if let Err(err) = signals::install() {
        eprintln!("error: the signal handlers cannot be installed: {err}");
        return ExitCode::from(1);
    }
    if let Err(err) = use_threads(cli.threads) {
        eprintln!("error: --threads {}: {err}", cli.threads);
        return ExitCode::from(1);
    }
    let outcome = match cli.command {
        Command::Info(args) => info::run(&args),
        Command::Curvature(args) => curvature::run(&args),
        Command::Iso(args) => iso::run(&args),
        Command::Crease(args) => crease::run(&args),
        Command::CrestLines(args) => crest::run(&args),
        Command::Landmarks(args) => landmarks::run(&args),
        Command::Ridges(args) => ridges::run(&args),
        Command::Draw(args) => draw::run(&args),
        Command::Morse(args) => morse::run(&args),
        Command::Register(args) => register::run(&args),
        Command::Compare(args) => compare::run(&args),
        Command::View(args) => view::run(&args),
    };
    match (outcome, signals::received()) {
        (Ok(()), _) => ExitCode::SUCCESS,
        (Err(_), Some(signal)) => {
            // Stopped before its outputs were renamed into place: none was written.
            eprintln!("interrupted by signal {signal}: no output was written");
            ExitCode::from(128 + signal as u8)
        }
        (Err(err), None) => {
            eprintln!("error: {}", as_flags(&err.to_string()));
            ExitCode::from(1)
        }
    }
}

/// A parser for an option whose values are the library's `names` of `T` (listed in
/// `--help`), parsed by `T`'s `FromStr`.
pub fn named<T>(names: &'static [&'static str]) -> impl clap::builder::TypedValueParser<Value = T>
where
    T: std::str::FromStr<Err = crestline::Error> + Clone + Send + Sync + 'static,
{
    use clap::builder::TypedValueParser;
    clap::builder::PossibleValuesParser::new(names).try_map(|name| name.parse::<T>())
}

/// `message` of the library with each option it names between backticks
/// (`` `min_length` ``) written as its command-line flag (`--min-length`).
pub fn as_flags(message: &str) -> String {
    let mut parts = message.split('`');
    let mut text = parts.next().unwrap_or_default().to_string();
    for (n, part) in parts.enumerate() {
        if n % 2 == 0 {
            text.push_str("--");
            text.push_str(&part.replace('_', "-"));
        } else {
            text.push_str(part);
        }
    }
    text
}

/// Print `text` to stdout; a closed pipe (e.g. `| head`) is not an error.
pub fn print_stdout(text: &str) {
    use std::io::Write;
    let _ = std::io::stdout().lock().write_all(text.as_bytes());
}
