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
mod panics;
mod plot;
mod register;
mod report;
mod ridges;
mod signals;
mod structure;
mod surface;
mod transfer;
mod view;
mod volume_info;

use std::path::PathBuf;

use outputs::Role;
use std::process::ExitCode;

use std::collections::BTreeSet;
use std::sync::OnceLock;

use clap::{CommandFactory, Parser, Subcommand};

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
    /// Carry a template's labelled landmarks onto another scan through their crest lines
    /// (rigid, then a smooth deformation).
    Transfer(Box<transfer::TransferArgs>),
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
        report
            .stage("write", || files.write(output, write))
            .map_err(|e| unwritable(e, &report.input, output))?;
        if let Some(path) = &self.report {
            files.write(path, |p| report.write(p))?;
        }
        files.commit()
    }
}

/// A result the output's format cannot hold (a value beyond a 32-bit float, say)
/// came from the input: the error names the input and the output.
fn unwritable(error: crestline::Error, input: &str, output: &std::path::Path) -> crestline::Error {
    match error {
        crestline::Error::Argument(message) => crestline::Error::File {
            path: input.into(),
            message: format!(
                "its result cannot be written to {}: {message}",
                output.display()
            ),
        },
        other => other,
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
    panics::silence();
    if let Err(err) = signals::install() {
        eprintln!("error: the signal handlers cannot be installed: {err}");
        return ExitCode::from(1);
    }
    if let Err(err) = use_threads(cli.threads) {
        eprintln!("error: --threads {}: {err}", cli.threads);
        return ExitCode::from(1);
    }
    let outcome = panics::catch(|| match cli.command {
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
        Command::Transfer(args) => transfer::run(&args),
        Command::Compare(args) => compare::run(&args),
        Command::View(args) => view::run(&args),
    });
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
/// (`` `min_length` ``) written as its command-line flag (`--min-length`). Text
/// between backticks that is not one of the tool's options (a word a library
/// quoted, a command) keeps its backticks, as does a lone backtick.
pub fn as_flags(message: &str) -> String {
    let parts: Vec<&str> = message.split('`').collect();
    // An even number of parts means an odd number of backticks: the last is alone.
    let paired = parts.len() - (parts.len() + 1) % 2;
    let mut text = String::with_capacity(message.len());
    for (n, part) in parts.iter().enumerate() {
        let flag = part.replace('_', "-");
        if n % 2 == 0 {
            text.push_str(part);
        } else if n < paired && option_names().contains(&flag) {
            text.push_str("--");
            text.push_str(&flag);
        } else {
            text.push('`');
            text.push_str(part);
            if n < paired {
                text.push('`');
            }
        }
    }
    text
}

/// The long names of the tool's options, in every command (`min-length`,
/// `series`, ...).
fn option_names() -> &'static BTreeSet<String> {
    static NAMES: OnceLock<BTreeSet<String>> = OnceLock::new();
    NAMES.get_or_init(|| {
        let mut names = BTreeSet::new();
        add_option_names(&Cli::command(), &mut names);
        names
    })
}

/// Add the long names of the options of `command` and its subcommands to `names`.
fn add_option_names(command: &clap::Command, names: &mut BTreeSet<String>) {
    names.extend(
        command
            .get_arguments()
            .filter_map(clap::Arg::get_long)
            .map(str::to_string),
    );
    for subcommand in command.get_subcommands() {
        add_option_names(subcommand, names);
    }
}

/// Print `text` to stdout; a closed pipe (e.g. `| head`) is not an error.
pub fn print_stdout(text: &str) {
    use std::io::Write;
    let _ = std::io::stdout().lock().write_all(text.as_bytes());
}

#[cfg(test)]
mod tests {
    use super::as_flags;

    #[test]
    fn only_the_tools_options_become_flags() {
        assert_eq!(
            as_flags("`min_length` is too large; choose one by `series`"),
            "--min-length is too large; choose one by --series"
        );
        assert_eq!(
            as_flags("Missing required attribute `HighBit` (`crestline info`)"),
            "Missing required attribute `HighBit` (`crestline info`)"
        );
        assert_eq!(as_flags("a lone ` and `taper`"), "a lone ` and `taper`");
        assert_eq!(
            as_flags("`smoothing_weights` and `"),
            "--smoothing-weights and `"
        );
    }
}
