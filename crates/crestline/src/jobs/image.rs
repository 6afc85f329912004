//! A 3D image made ready for the jobs, and its isosurface (`crestline iso`).

use std::borrow::Cow;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::scale::{chosen_scale, image_scale, mesh_scale};
use super::{Length, Units};
use crate::curvature::{CurvatureEstimator, DerivativeOrder, Estimator, ImageCurvature};
use crate::error::readable;
use crate::isosurface::isosurface as marching_cubes;
use crate::mesh::Mesh;
use crate::progress::{try_stage, Observer};
use crate::volume::{Derivatives, Volume};
use crate::{Error, Result};

/// [`Volume::voxel_size`].
pub(crate) fn voxel_size(volume: &Volume) -> f64 {
    largest_spacing(volume.spacing())
}

/// One voxel of an image of voxel size `spacing`: the largest.
pub(crate) fn largest_spacing(spacing: [f64; 3]) -> f64 {
    spacing.into_iter().fold(0.0, f64::max)
}

/// [`Volume::prepared`], borrowing `volume` when every sample is finite.
pub(crate) fn prepared_image<'v>(
    volume: Cow<'v, Volume>,
    observer: &mut dyn Observer,
) -> Result<Cow<'v, Volume>> {
    if volume.samples().iter().all(|s| s.is_finite()) {
        return Ok(volume);
    }
    let lowest = volume
        .samples()
        .iter()
        .copied()
        .filter(|s| s.is_finite())
        .reduce(f32::min)
        .ok_or_else(|| Error::Argument("the image has no finite sample".into()))?;
    let mut repaired = volume.into_owned();
    let count = repaired.replace_non_finite(lowest);
    observer.warning(&format!(
        "{count} samples are not finite (NaN or infinite); they were set to the smallest value, {lowest}"
    ));
    Ok(Cow::Owned(repaired))
}

/// Where the curvature of an image's isosurface comes from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CurvatureSource {
    /// From the image's derivatives at each vertex (Thirion & Gourdon 1993): the
    /// curvature of the smooth surface the triangles approximate.
    #[default]
    Image,
    /// From the triangles, by the job's mesh estimator, as for any mesh.
    Mesh,
}

crate::named::named!(CurvatureSource, "curvature source", {
    Image => "image",
    Mesh => "mesh",
});

/// Options of [`isosurface`] (`crestline iso`, and every job that works on an
/// image's isosurface). Each field is an option of the tool and a keyword
/// argument of the Python package, documented here once: with the feature
/// `clap` this struct is the tool's arguments.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
#[serde(default, deny_unknown_fields)]
pub struct IsoOptions {
    /// The feature scale in world units, so that a rescan or another sampling finds
    /// the same features. For a 3D image σ and the landmarks' lengths are derived
    /// from it; default: 2% of the cube root of the volume the isosurface encloses,
    /// at least a voxel. For a mesh the surface is smoothed for a time of
    /// (0.7 scale)², its curvature tensor field for scale² and the extremalities
    /// for (scale/2)², in world units; default: none (the smoothing counts mean
    /// edge lengths).
    #[cfg_attr(feature = "clap", arg(long, value_name = "L"))]
    pub scale: Option<f64>,
    /// For a 3D image: standard deviation of the Gaussian smoothing, for the
    /// isosurface and its curvature, in world units (mm), or in feature scales
    /// ("1.5 scales"); 0: no smoothing (the cubic B-spline through the samples).
    #[cfg_attr(feature = "clap", arg(long, value_name = "S", allow_hyphen_values = true,
        default_value_t = IsoOptions::default().sigma))]
    pub sigma: Length,
    /// For a 3D image: the curvature of the isosurface from the image or from the
    /// mesh.
    #[cfg_attr(feature = "clap", arg(long, value_enum,
        default_value_t = IsoOptions::default().curvature))]
    pub curvature: CurvatureSource,
    /// The mesh estimator of the surface's curvature for `curvature` mesh (the
    /// line jobs use their own options' estimator). Default: the shape operator.
    /// (The tool's `--estimator` is its command's.)
    #[cfg_attr(feature = "clap", arg(skip = IsoOptions::default().estimator))]
    pub estimator: Estimator,
    /// For a 3D image: close the surface where it reaches the border of the image
    /// (padding the image by one voxel outside the surface), so that it is
    /// watertight; false leaves it open there. The caps' vertices lie outside the
    /// image, so their image curvature is marked unreliable.
    #[cfg_attr(feature = "clap", arg(long, value_name = "BOOL", action = clap::ArgAction::Set,
        default_value_t = IsoOptions::default().close))]
    pub close: bool,
}

impl Default for IsoOptions {
    fn default() -> Self {
        IsoOptions {
            scale: None,
            sigma: Length::scales(1.0),
            curvature: CurvatureSource::Image,
            estimator: Estimator::default(),
            close: true,
        }
    }
}

/// A surface for the line jobs: a mesh, and where its curvature comes from.
pub struct Surface {
    /// The mesh (repaired, or an isosurface).
    pub mesh: Mesh,
    /// The estimator to use on it; `None`: the one a job's options name.
    pub curvature: Option<Arc<dyn CurvatureEstimator + Send + Sync>>,
    /// For an isosurface: the level, the image's unit and the σ used.
    pub image: Option<FromImage>,
}

/// How an isosurface was extracted from its image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FromImage {
    /// The isosurface level.
    pub level: f64,
    /// One voxel (the largest spacing).
    pub voxel: f64,
    /// The feature scale used (world units).
    pub scale: f64,
    /// The Gaussian σ the image was smoothed by (0: the B-spline).
    pub sigma: f64,
    /// Whether the surface's curvature gives the image's extremalities
    /// ([`ImageCurvature::gives_extremalities`]).
    pub extremalities: bool,
}

impl Surface {
    /// A mesh whose curvature the jobs estimate by the estimator their options
    /// name.
    pub fn of_mesh(mesh: Mesh) -> Surface {
        Surface {
            mesh,
            curvature: None,
            image: None,
        }
    }

    /// The estimator of this surface's curvature: its own, or `choice`.
    pub fn estimator(&self, choice: Estimator) -> Arc<dyn CurvatureEstimator + Send + Sync> {
        self.curvature.clone().unwrap_or_else(|| choice.build())
    }

    /// Whether the surface is an isosurface carrying its image's curvature and
    /// extremalities ([`ImageCurvature::gives_extremalities`]: smoothed by a
    /// Gaussian, σ > 0), rather than one a mesh estimator finds.
    pub fn has_image_extremalities(&self) -> bool {
        self.curvature.is_some() && self.image.is_some_and(|image| image.extremalities)
    }

    /// The units of the relative [`Length`]s on this surface: one voxel and the
    /// image's feature scale for an isosurface; the mean edge length and the
    /// scale of its area (`mesh_scale`) for a mesh.
    pub(crate) fn units(&self) -> Units {
        match self.image {
            Some(image) => Units {
                sample: image.voxel,
                scale: image.scale,
            },
            None => Units {
                sample: self.mesh.mean_edge_length(),
                scale: mesh_scale(&self.mesh),
            },
        }
    }
}

/// The units of the relative [`Length`]s of the isosurface `level` of `volume`:
/// one voxel, and the feature scale `given` (world units) or else the image's
/// ([`image_scale`]), also told to `observer` as the measure `scale`.
pub fn image_units(
    volume: &Volume,
    level: f64,
    given: Option<f64>,
    observer: &mut dyn Observer,
) -> Result<Units> {
    let voxel = voxel_size(volume);
    let scale = chosen_scale(given, || image_scale(volume, level, voxel))?;
    observer.measure("scale", scale);
    Ok(Units {
        sample: voxel,
        scale,
    })
}

/// The image the isosurface is taken from: `volume` smoothed by a Gaussian of
/// standard deviation `sigma` (world units), or `volume` itself for `sigma = 0`
/// (whose curvature is the cubic B-spline's, [`ImageCurvature::new`]).
///
/// Errors as [`ImageCurvature::new`] (a negative or non-finite σ, or one absurd
/// for the grid).
fn smoothed_image(volume: &Volume, sigma: f64) -> Result<Cow<'_, Volume>> {
    if sigma == 0.0 {
        return Ok(Cow::Borrowed(volume));
    }
    ImageCurvature::check_sigma(sigma)?;
    Ok(Cow::Owned(Derivatives::smoothed(volume, sigma)?))
}

/// A sample value outside the surface `f = level` (below the level), as far
/// below it as the largest sample is above, so that a cap closing the surface at
/// the border of the grid lies within half a voxel of the border (`max`: the
/// largest sample).
fn outside(max: f32, level: f64) -> f32 {
    let below = 2.0 * level - f64::from(max);
    below.min(level - level.abs().max(1.0) * 1e-3) as f32
}

/// The largest sample of `surface`, the image the surface is taken from; an error
/// when `level` is above it, checked before the image is padded (whose padding
/// would widen the range the error quotes). When that image is `volume` smoothed by
/// `sigma`, the error says so and quotes both ranges: smoothing lowers the maxima,
/// so a level the samples reach may be out of the smoothed image's reach.
fn check_level(
    volume: &Volume,
    surface: &Volume,
    smoothed: bool,
    level: f64,
    sigma: f64,
) -> Result<f32> {
    let (low, high) = surface.value_range();
    if level <= f64::from(high) {
        return Ok(high);
    }
    let range = format!("[{}, {}]", readable(low.into()), readable(high.into()));
    let message = if smoothed {
        let (raw_low, raw_high) = volume.value_range();
        format!(
            "no isosurface at level {}: the image smoothed by `sigma` {} ranges over {range} \
             (its samples over [{}, {}]); choose a level below {}, or `sigma` 0 for no smoothing",
            readable(level),
            readable(sigma),
            readable(raw_low.into()),
            readable(raw_high.into()),
            readable(high.into()),
        )
    } else {
        format!(
            "no isosurface at level {}: it is above every sample (the samples range over {range})",
            readable(level)
        )
    };
    Err(Error::Argument(message))
}

/// The isosurface `f = level` of `volume` (inside is `f ≥ level`) smoothed as
/// `options` say, as a closed oriented mesh with the curvature `options` choose:
/// the stages `smoothing`, `isosurface`, `mesh` and (for the image's curvature)
/// `derivatives`, and the counts `vertices` and `faces`. Non-finite samples are
/// replaced first ([`Volume::prepared`]). The smoothed image is dropped once the
/// surface is extracted, and the image's derivatives are kept only around the
/// vertices ([`ImageCurvature::at_points`]), up to the order `needs` (the job's
/// that uses the surface: [`DerivativeOrder::Third`] for ridges, which take the
/// image's extremalities); `None` computes none, for a caller that takes the
/// mesh alone (the surface then has no curvature of its own).
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
/// let surface = jobs::isosurface(&volume, 40.0, &jobs::IsoOptions::default(), None, &mut Silent)?;
/// assert!(surface.mesh.face_count() > 0);
/// # Ok::<(), crestline::Error>(())
/// ```
pub fn isosurface(
    volume: &Volume,
    level: f64,
    options: &IsoOptions,
    needs: Option<DerivativeOrder>,
    observer: &mut dyn Observer,
) -> Result<Surface> {
    let volume = prepared_image(Cow::Borrowed(volume), observer)?;
    let units = image_units(&volume, level, options.scale, observer)?;
    let sigma = options.sigma.resolve(units);
    let smoothed = try_stage(observer, "smoothing", || smoothed_image(&volume, sigma))?;
    let surface = try_stage(observer, "isosurface", || {
        let smoothing = matches!(smoothed, Cow::Owned(_));
        let max = check_level(&volume, &smoothed, smoothing, level, sigma)?;
        if options.close {
            marching_cubes(
                &smoothed.into_owned().into_padded(outside(max, level))?,
                level,
            )
        } else {
            marching_cubes(&smoothed, level)
        }
    })?;
    let mesh = try_stage(observer, "mesh", || surface.to_mesh())?;
    observer.count("vertices", mesh.vertex_count());
    observer.count("faces", mesh.face_count());
    let image_curvature = match (options.curvature, needs) {
        (CurvatureSource::Image, Some(order)) => Some(try_stage(observer, "derivatives", || {
            ImageCurvature::at_points(&volume, sigma, mesh.positions(), order)
        })?),
        _ => None,
    };
    let extremalities = image_curvature
        .as_ref()
        .is_some_and(ImageCurvature::gives_extremalities);
    let curvature = image_curvature
        .map(|curvature| Arc::new(curvature) as Arc<dyn CurvatureEstimator + Send + Sync>);
    Ok(Surface {
        mesh,
        curvature,
        image: Some(FromImage {
            level,
            voxel: units.sample,
            scale: units.scale,
            sigma,
            extremalities,
        }),
    })
}

impl Volume {
    /// One voxel: the largest spacing of `volume`, the unit of the image jobs'
    /// relative [`Length`]s.
    pub fn voxel_size(&self) -> f64 {
        voxel_size(self)
    }

    /// This image with its non-finite samples (NaN outside the mask of a resampled
    /// scan, say) set to its smallest finite value, the background, with a warning
    /// to `observer`. An image without a finite sample is an error.
    pub fn prepared(self, observer: &mut dyn Observer) -> Result<Volume> {
        prepared_image(Cow::Owned(self), observer).map(Cow::into_owned)
    }
}
