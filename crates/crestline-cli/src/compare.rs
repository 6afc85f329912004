//! `crestline compare`: how well two files of feature lines or landmarks agree,
//! kind by kind and both ways — a test–retest measure.

use std::path::PathBuf;

use crestline::compare::{Agreement, Comparison, Features, Tolerance};
use crestline::register::RigidTransform;
use crestline::Result;

use super::load::report_with_progress;
use super::outputs::check_paths;
use super::ReportArg;

/// Arguments of `crestline compare`.
#[derive(clap::Args, Debug)]
pub struct CompareArgs {
    /// Lines or landmarks (.json as `ridges`, `crest-lines`, `morse` or
    /// `landmarks` write them; lines as .obj or legacy .vtk, from any program;
    /// 3D Slicer markups, .mrk.json; .csv landmarks).
    pub a: PathBuf,
    /// The lines or landmarks to compare with A's.
    pub b: PathBuf,
    /// Move B's points into A's frame first by this rigid motion: a .json as
    /// `crestline register A B` writes it (B onto A), or an ITK .tfm.
    #[arg(long, value_name = "FILE")]
    pub transform: Option<PathBuf>,
    /// How near a counterpart must be: a length (1.5) or a share of the diagonal
    /// of A's features (0.5%).
    #[arg(long, value_name = "L", default_value_t = Tolerance::DEFAULT, allow_hyphen_values = true)]
    pub tolerance: Tolerance,
    #[command(flatten)]
    pub report: ReportArg,
}

/// One row of the table: a kind, A's and B's amounts and counts, and both shares.
fn row(agreement: &Agreement, lines: bool) -> String {
    let amounts = if lines {
        format!(
            "{:>12.4} {:>12.4} {:>6} {:>6}",
            agreement.a, agreement.b, agreement.a_count, agreement.b_count
        )
    } else {
        format!("{:>12} {:>12}", agreement.a_count, agreement.b_count)
    };
    format!(
        "{:<18} {amounts} {:>7.1}% {:>7.1}%",
        agreement.kind,
        100.0 * agreement.a_in_b,
        100.0 * agreement.b_in_a
    )
}

/// The comparison as a table for the terminal.
fn table(comparison: &Comparison) -> String {
    let mut text = format!("tolerance {:.6}\n", comparison.tolerance);
    if !comparison.lines.is_empty() {
        text += &format!(
            "{:<18} {:>12} {:>12} {:>6} {:>6} {:>8} {:>8}\n",
            "lines", "A length", "B length", "A", "B", "A in B", "B in A"
        );
        for agreement in &comparison.lines {
            text += &(row(agreement, true) + "\n");
        }
    }
    if !comparison.landmarks.is_empty() {
        text += &format!(
            "{:<18} {:>12} {:>12} {:>8} {:>8}\n",
            "landmarks", "A", "B", "A in B", "B in A"
        );
        for agreement in &comparison.landmarks {
            text += &(row(agreement, false) + "\n");
        }
    }
    text
}

/// Compare the two files and print the table (and the report if asked for).
pub fn run(args: &CompareArgs) -> Result<()> {
    let transform = args.transform.as_deref().map(|t| ("--transform", t));
    let inputs: Vec<_> = [("A", args.a.as_path()), ("B", args.b.as_path())]
        .into_iter()
        .chain(transform)
        .collect();
    let outputs: Vec<_> = args.report.output().into_iter().collect();
    check_paths(&inputs, &outputs)?;
    let mut report = report_with_progress("compare", &args.a);
    let a = report.stage("read A", || Features::read(&args.a))?;
    let mut b = report.stage("read B", || Features::read(&args.b))?;
    if let Some(path) = &args.transform {
        b = b.moved(&RigidTransform::read(path)?);
    }
    let (a, b) = Features::in_one_frame(a, b);
    let tolerance = args.tolerance.resolve(&a)?;
    let comparison = report.stage("compare", || a.compare(&b, tolerance));
    super::print_stdout(&table(&comparison));
    report.section("comparison", &comparison);
    if let Some(path) = &args.report.report {
        let mut files = super::outputs::OutputSet::default();
        files.write(path, |p| report.write(p))?;
        files.commit()?;
    }
    Ok(())
}
