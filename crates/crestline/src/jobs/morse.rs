//! Feature lines from the Morse-Smale complex of a curvature indicator
//! (`crestline morse`; Sahner, Weber, Prohaska and Lamecker 2008).

use serde::{Deserialize, Serialize};

use super::image::Surface;
use crate::curvature::Estimator;
use crate::lines::FeatureLines;
use crate::morse::{Cells, Criterion, Indicator, MorseSmale, MorseSummary, Simplification};
use crate::progress::Observer;
use crate::Result;

/// Options of [`morse`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MorseOptions {
    /// The scalar field whose complex is built: curvedness, kmax, kmin, or the
    /// name of a vertex property of the mesh. Default: curvedness.
    pub indicator: Indicator,
    /// Curvature estimator of curvature indicators (an isosurface may carry its
    /// image's curvature instead). Default: the shape operator.
    pub estimator: Estimator,
    /// How saddles are ranked for cancellation. Default: the paper's feature
    /// significance.
    pub criterion: Criterion,
    /// Make this many cancellations; `None`: cancel down to `keep_saddles`.
    /// Default: `None`.
    pub cancel: Option<usize>,
    /// Cancel until at most this many saddles that could be cancelled remain
    /// (saddles forced by topology are kept besides). Default:
    /// [`MorseSmale::DEFAULT_KEEP_SADDLES`].
    pub keep_saddles: usize,
    /// Which 1-cells to output. Default: the ascending ones.
    pub cells: Cells,
    /// Keep lines forced by topology. Default: no.
    pub keep_forced: bool,
    /// Fairing iterations of the lines on the surface. Default:
    /// [`MorseSmale::DEFAULT_SMOOTH_ITERATIONS`].
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
            keep_forced: !defaults.hide_forced,
            smooth: defaults.smooth_iterations,
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
            hide_forced: !self.keep_forced,
            smooth_iterations: self.smooth,
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
