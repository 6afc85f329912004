//! Ridge and valley surfaces of a 3D image (`crestline crease`; Schultz, Theisel
//! and Seidel 2010).

use std::borrow::Cow;

use serde::{Deserialize, Serialize};

use super::image::prepared_image;
use crate::crease::{crease_surface_of, default_options, Survey, DEFAULT_STRENGTH_FRACTION};
use crate::mesh::TriangleSoup;
use crate::progress::{try_stage, Observer};
use crate::volume::{Smoothing, Volume};
use crate::{Error, Result};

/// Options of [`crease`]. Each field is an option of the tool and a keyword
/// argument of the Python package, documented here once: with the feature `clap`
/// this struct is the tool's arguments.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
#[serde(default, deny_unknown_fields)]
pub struct CreaseOptions {
    /// Valley surfaces (ridges of −f) instead of ridge surfaces.
    #[cfg_attr(feature = "clap", arg(long))]
    pub valley: bool,
    /// Gaussian smoothing σ in world units (mm); 0 differentiates the approximating
    /// cubic B-spline of the samples, which smooths least.
    #[cfg_attr(feature = "clap", arg(long, value_name = "S", allow_hyphen_values = true,
        default_value_t = CreaseOptions::default().sigma))]
    pub sigma: f64,
    /// Least ridge strength −λ3, as a fraction of the strongest in the image.
    #[cfg_attr(feature = "clap", arg(long, value_name = "T",
        default_value_t = CreaseOptions::default().strength))]
    pub strength: f64,
    /// Drop connected pieces of fewer triangles than this.
    #[cfg_attr(feature = "clap", arg(long, value_name = "N",
        default_value_t = CreaseOptions::default().min_component))]
    pub min_component: usize,
}

impl Default for CreaseOptions {
    fn default() -> Self {
        CreaseOptions {
            valley: false,
            sigma: 0.0,
            strength: DEFAULT_STRENGTH_FRACTION,
            min_component: 20,
        }
    }
}

impl CreaseOptions {
    /// An error unless the strength is a fraction from 0 to 1.
    pub fn check(&self) -> Result<()> {
        if self.strength.is_finite() && (0.0..=1.0).contains(&self.strength) {
            Ok(())
        } else {
            Err(Error::Argument(format!(
                "strength is a fraction of the strongest ridge, from 0 to 1, not {}",
                self.strength
            )))
        }
    }
}

/// The ridge (or valley) surface of `volume` as `options` say: triangles that need
/// not be orientable, with the per-vertex scalars `strength` (−λ3) and `degenerate`
/// (`crate::crease::crease_surface`). Stages `reconstruction` (the
/// survey of the eigenvalues, `Survey`), `eigenframes` (the field kept where
/// creases are as strong as asked) and those of `crease_surface_of`; the counts
/// `kept samples`, `vertices` and `triangles`, and a warning naming the option that
/// emptied the surface. Non-finite samples are replaced first ([`Volume::prepared`]).
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
/// let surface = jobs::crease(&volume, &jobs::CreaseOptions::default(), &mut Silent)?;
/// println!("{} triangles", surface.triangles.len());
/// # Ok::<(), crestline::Error>(())
/// ```
pub fn crease(
    volume: &Volume,
    options: &CreaseOptions,
    observer: &mut dyn Observer,
) -> Result<TriangleSoup> {
    options.check()?;
    let volume = prepared_image(Cow::Borrowed(volume), observer)?;
    let smoothing = if options.sigma == 0.0 {
        Smoothing::CubicSpline
    } else {
        Smoothing::Gaussian(options.sigma)
    };
    let survey = try_stage(observer, "reconstruction", || {
        Survey::new(&volume, smoothing, !options.valley)
    })?;
    let mut crossing = default_options(survey.eigenvalue_range());
    crossing.strength *= options.strength / DEFAULT_STRENGTH_FRACTION;
    let field = try_stage(observer, "eigenframes", || {
        survey.field(&volume, crossing.strength)
    })?;
    observer.count("kept samples", field.kept_len());
    let soup = crease_surface_of(field, &crossing, options.min_component, observer)?;
    observer.count("vertices", soup.positions.len());
    observer.count("triangles", soup.triangles.len());
    Ok(soup)
}
