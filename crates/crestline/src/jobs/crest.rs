//! Crest lines of a 3D image's isosurface by Marching Lines (`crestline
//! crest-lines`).

use std::borrow::Cow;

use serde::{Deserialize, Serialize};

use super::image::{image_units, prepared_image};
use super::Length;
use crate::crest_lines::Sweep;
use crate::crest_lines::{LineFamily, LineTracing};
use crate::lines::{FeatureLines, LineExtractor, MinLength, MinStrength};
use crate::progress::Observer;
use crate::volume::Volume;
use crate::{Error, Result};

/// Options of [`crest_lines`]. Each field is an option of the tool and a keyword
/// argument of the Python package (which spells `gauss=J` as `kind="gauss",
/// gauss=J`), documented here once: with the feature `clap` this struct is the
/// tool's arguments.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
#[serde(default, deny_unknown_fields)]
pub struct CrestLinesOptions {
    /// The feature scale in world units (mm), from which σ, the shortest line's length
    /// and the landmarks' lengths are derived; default from the size of the object the
    /// isosurface encloses (2% of the cube root of its volume, at least a voxel),
    /// not from the grid, so that a rescan finds the same lines.
    #[cfg_attr(feature = "clap", arg(long, value_name = "L"))]
    pub scale: Option<f64>,
    /// Gaussian smoothing σ of the image, in world units (mm) or in feature scales
    /// ("1.5 scales").
    #[cfg_attr(feature = "clap", arg(long, value_name = "S",
        default_value_t = CrestLinesOptions::default().sigma))]
    pub sigma: Length,
    /// Which lines: crest (ridges and valleys), parabolic (K = 0) or gauss=J (the
    /// iso-Gaussian curves K = J, J in world units⁻²).
    #[cfg_attr(feature = "clap", arg(long, value_name = "crest|parabolic|gauss=J",
        default_value_t = CrestLinesOptions::default().kind))]
    pub kind: LineFamily,
    /// The randomized Marching Lines: follow only the lines through N cells drawn
    /// at random on the isosurface; the longest lines come first, at a fraction of
    /// the cost. Default: every cell, every line.
    #[cfg_attr(feature = "clap", arg(long, value_name = "N",
        value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..)))]
    pub seeds: Option<usize>,
    /// The seed of the random draw of the seeds (the same seed, the same lines).
    #[cfg_attr(feature = "clap", arg(long, value_name = "S", requires = "seeds",
        default_value_t = CrestLinesOptions::default().rng_seed))]
    pub rng_seed: u64,
    /// Keep lines at least this long, in world units (mm) or in feature scales.
    #[cfg_attr(feature = "clap", arg(long, value_name = "L",
        default_value_t = CrestLinesOptions::default().min_length))]
    pub min_length: Length,
    /// Keep lines whose strength ∫|k| ds (dimensionless) is at least this.
    #[cfg_attr(feature = "clap", arg(long, value_name = "T",
        default_value_t = CrestLinesOptions::default().min_strength))]
    pub min_strength: f64,
}

impl Default for CrestLinesOptions {
    fn default() -> Self {
        CrestLinesOptions {
            scale: None,
            sigma: Length::scales(1.0),
            kind: LineFamily::Crest,
            seeds: None,
            rng_seed: 1,
            min_length: Length::scales(1.5),
            min_strength: 0.0,
        }
    }
}

/// The lines `options` ask for on the isosurface `f = level` of `volume` (inside
/// is `f ≥ level`), by Marching Lines (Thirion & Gourdon 1993;
/// `crate::crest_lines::trace`), at least `min_length` long and `min_strength`
/// strong: the stages of `crate::crest_lines::trace_observed`, the counts `traced` and `lines`, and
/// a warning when no line is left. Non-finite samples are replaced first
/// ([`Volume::prepared`]).
///
/// # Examples
///
/// ```
/// # use crestline::progress::Silent;
/// # use crestline::jobs;
/// // A small image of an ellipsoid: values fall off from 100 at its centre.
/// let n = 24;
/// let samples = (0..n * n * n)
///     .map(|i| {
///         let [x, y, z] = [i % n, i / n % n, i / (n * n)].map(|c| c as f32 - 11.5);
///         100.0 - 10.0 * (x * x + 2.0 * y * y + 3.0 * z * z).sqrt()
///     })
///     .collect();
/// let identity = nalgebra::Matrix3::identity();
/// let volume = crestline::volume::Volume::new([n; 3], [1.0; 3], [0.0; 3], identity, samples)?;
/// let options = jobs::CrestLinesOptions::default();
/// let lines = jobs::crest_lines(&volume, 40.0, &options, &mut Silent)?;
/// println!("{} crest lines", lines.len());
/// # Ok::<(), crestline::Error>(())
/// ```
pub fn crest_lines(
    volume: &Volume,
    level: f64,
    options: &CrestLinesOptions,
    observer: &mut dyn Observer,
) -> Result<FeatureLines> {
    let volume = prepared_image(Cow::Borrowed(volume), observer)?;
    let units = image_units(&volume, level, options.scale, observer)?;
    let (min_length, min_strength) = (options.min_length.resolve(units), options.min_strength);
    check_filters(min_length, min_strength)?;
    check_level(&volume, level)?;
    let tracing = LineTracing {
        family: options.kind,
        sweep: options.seeds.map_or(Sweep::Every, |count| Sweep::Seeds {
            count,
            rng_seed: options.rng_seed,
        }),
        ..LineTracing::new(level, options.sigma.resolve(units))
    };
    let mut lines = tracing.extract(&volume, observer)?;
    observer.count("traced", lines.len());
    lines.filter(&MinLength(min_length));
    lines.filter(&MinStrength(min_strength));
    observer.count("lines", lines.len());
    if lines.is_empty() {
        observer.warning(
            "no line is as long and strong as asked; try a lower `min_length` or `min_strength`",
        );
    }
    Ok(lines)
}

/// The shortest length and least strength a line may have must be finite and at
/// least 0: a NaN or infinite one keeps no line (or every line) whatever the image.
fn check_filters(min_length: f64, min_strength: f64) -> Result<()> {
    for (name, value) in [("min_length", min_length), ("min_strength", min_strength)] {
        if !(value.is_finite() && value >= 0.0) {
            return Err(Error::Argument(format!(
                "`{name}` is {value}; it must be a finite length or strength of at least 0"
            )));
        }
    }
    Ok(())
}

/// A level outside the samples' range crosses no isosurface, so there can be no
/// line: an error saying the range rather than an empty result.
fn check_level(volume: &Volume, level: f64) -> Result<()> {
    let (low, high) = volume.value_range();
    if (f64::from(low)..=f64::from(high)).contains(&level) {
        return Ok(());
    }
    Err(Error::Argument(format!(
        "`level` {level} is outside the image's values [{low}, {high}]: there is no isosurface \
         to trace lines on"
    )))
}
