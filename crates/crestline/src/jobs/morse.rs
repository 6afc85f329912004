//! Feature lines from the Morse-Smale complex of a curvature indicator
//! (`crestline morse`; Sahner, Weber, Prohaska and Lamecker 2008).

use serde::{Deserialize, Serialize};

use super::image::Surface;
use crate::curvature::Estimator;
use crate::lines::FeatureLines;
use crate::morse::{Cells, Criterion, Indicator, MorseSmale, MorseSummary, Simplification};
use crate::progress::Observer;
use crate::Result;

/// Options of [`morse`]. Each field is an option of the tool (`--keep-saddles`)
/// and a keyword argument of the Python package (`keep_saddles=`), documented
/// here once: with the feature `clap` this struct is the tool's arguments.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
#[serde(default, deny_unknown_fields)]
pub struct MorseOptions {
    /// Indicator: curvedness, kmax, kmin, the name of a PLY vertex property, or a
    /// file of one value per vertex (text with one value per line, FreeSurfer curv
    /// such as lh.sulc, GIfTI .shape.gii/.func.gii).
    #[cfg_attr(feature = "clap", arg(long, value_name = "NAME",
        default_value_t = MorseOptions::default().indicator))]
    pub indicator: Indicator,
    /// Curvature estimator of curvature indicators (an isosurface may carry its
    /// image's curvature instead). Default: the shape operator. (The tool's
    /// `--estimator` is its command's, shared with the ridges of a drawing.)
    #[cfg_attr(feature = "clap", arg(skip = MorseOptions::default().estimator))]
    pub estimator: Estimator,
    /// Cancellation criterion: feature (the paper's significance) or persistence.
    #[cfg_attr(feature = "clap", arg(long, value_enum,
        default_value_t = MorseOptions::default().criterion))]
    pub criterion: Criterion,
    /// Number of cancellations to make [default: cancel down to --keep-saddles].
    #[cfg_attr(
        feature = "clap",
        arg(long, value_name = "N", conflicts_with = "keep_saddles")
    )]
    pub cancel: Option<usize>,
    /// Cancel until at most this many saddles that could be cancelled remain
    /// (saddles forced by topology, e.g. 2g on a closed surface of genus g, are
    /// kept besides).
    #[cfg_attr(feature = "clap", arg(long, value_name = "N",
        default_value_t = MorseOptions::default().keep_saddles))]
    pub keep_saddles: usize,
    /// Which 1-cells to output: ascending (saddle to maximum: crests of the
    /// indicator), descending (saddle to minimum: troughs) or both.
    #[cfg_attr(feature = "clap", arg(long, value_enum,
        default_value_t = MorseOptions::default().cells))]
    pub cells: Cells,
    /// Keep lines forced by topology (no valid cancellation, low significance).
    #[cfg_attr(feature = "clap", arg(long))]
    pub keep_forced: bool,
    /// Fairing iterations of the output lines on the surface, keeping them on
    /// their crest (at most 1000; 0 leaves the staircases of mesh edges).
    #[cfg_attr(feature = "clap", arg(long, value_name = "N",
        default_value_t = MorseOptions::default().smooth))]
    pub smooth: usize,
}

impl Default for MorseOptions {
    fn default() -> Self {
        let defaults = MorseSmale::default();
        MorseOptions {
            indicator: defaults.indicator,
            estimator: Estimator::default(),
            criterion: defaults.criterion,
            cancel: None,
            keep_saddles: MorseSmale::DEFAULT_KEEP_SADDLES,
            cells: defaults.cells,
            keep_forced: defaults.keep_forced,
            smooth: defaults.smooth,
        }
    }
}

impl MorseOptions {
    /// The extractor these options describe, on `surface`.
    pub fn extractor(&self, surface: &Surface) -> MorseSmale {
        MorseSmale {
            estimator: surface.estimator(self.estimator),
            indicator: self.indicator.clone(),
            criterion: self.criterion,
            simplification: match self.cancel {
                Some(n) => Simplification::Cancel(n),
                None => Simplification::KeepSaddles(self.keep_saddles),
            },
            cells: self.cells,
            keep_forced: self.keep_forced,
            smooth: self.smooth,
        }
    }
}

/// The Morse-Smale lines of `surface` as `options` say ([`MorseSmale::run`]),
/// or of the per-vertex `values` when given instead of the indicator: the lines
/// and what the run found besides (critical points before and after, the
/// cancellation sequence), the counts `minima`, `saddles`, `maxima` and `lines`,
/// and a warning saying why when no line is left.
///
/// # Examples
///
/// ```
/// # use crestline::jobs::{self, Surface};
/// # use crestline::progress::Silent;
/// # let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../meshes/bunny_small.obj");
/// # let (mesh, _repairs) = jobs::build_mesh(crestline::io::read_mesh(path.as_ref())?, false, &mut Silent)?;
/// # let surface = Surface::of_mesh(mesh);
/// let (lines, summary) = jobs::morse(&surface, None, &jobs::MorseOptions::default(), &mut Silent)?;
/// assert!(!lines.is_empty());
/// # Ok::<(), crestline::Error>(())
/// ```
pub fn morse(
    surface: &Surface,
    values: Option<Vec<f64>>,
    options: &MorseOptions,
    observer: &mut dyn Observer,
) -> Result<(FeatureLines, MorseSummary)> {
    let extractor = options.extractor(surface);
    let (lines, summary) = match values {
        Some(values) => extractor.run_with_values(&surface.mesh, values, observer)?,
        None => extractor.run(&surface.mesh, observer)?,
    };
    observer.count("minima", summary.initial.minima);
    observer.count("saddles", summary.initial.saddles);
    observer.count("maxima", summary.initial.maxima);
    observer.count("lines", lines.len());
    if lines.is_empty() {
        observer.warning(&empty_result_advice(options, &summary));
    }
    Ok((lines, summary))
}

/// Why no line came out, and which option to change.
fn empty_result_advice(options: &MorseOptions, summary: &MorseSummary) -> String {
    let simplify = if options.cancel.is_some() {
        "fewer `cancel`"
    } else {
        "a larger `keep_saddles`"
    };
    match summary.after.saddles {
        0 => format!("no saddle is left after the cancellations, so no lines; try {simplify}"),
        n => format!(
            "no lines: the {n} saddles left are forced by topology and hidden; \
             show them with `keep_forced`, or try {simplify}"
        ),
    }
}
