//! The surface a command works on: a mesh file, or the isosurface of a 3D image with
//! the image's own curvature.

use std::path::Path;
use std::sync::Arc;

use crate::report::Report;
use crestline::curvature::{CurvatureEstimator, Estimator, ImageCurvature};
use crestline::io::{is_volume_path, read_volume};
use crestline::mesh::Mesh;
use crestline::volume::{isosurface, Volume};
use crestline::{Error, Result};

use super::load::{load_mesh_with_scalars, warn_repairs, StrictArg};

/// Where the curvature of an image's isosurface comes from.
#[derive(clap::ValueEnum, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CurvatureSource {
    /// From the image's derivatives at each vertex (Thirion & Gourdon): the
    /// curvature of the smooth surface the triangles approximate.
    #[default]
    Image,
    /// From the triangles, by --estimator, as for any mesh.
    Mesh,
}

/// How a 3D image becomes a surface: options of every command that reads a mesh
/// or an image.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct VolumeArgs {
    /// For a 3D image: the isosurface level I; inside is value ≥ I. `crestline info
    /// IMAGE` suggests one.
    #[arg(long, value_name = "I", allow_hyphen_values = true)]
    pub level: Option<f64>,
    /// For a 3D image: standard deviation of the Gaussian smoothing, in world units
    /// (mm), for the isosurface and its curvature. Default: one voxel (the largest
    /// spacing). 0: no smoothing (the cubic B-spline through the samples).
    #[arg(long, value_name = "S", allow_hyphen_values = true)]
    pub sigma: Option<f64>,
    /// For a 3D image: the curvature of the isosurface from the image or from the
    /// mesh.
    #[arg(long, value_enum, default_value_t)]
    pub curvature: CurvatureSource,
}

/// A surface to extract lines from, with the curvature estimator that fits it.
pub struct Surface {
    /// The mesh (repaired, or an isosurface).
    pub mesh: Mesh,
    /// The mesh estimator chosen on the command line, or the image's curvature.
    pub estimator: Arc<dyn CurvatureEstimator + Send + Sync>,
    /// For an isosurface: the image, its level and smoothing.
    pub image: Option<ImageSource>,
}

/// The image an isosurface was extracted from.
pub struct ImageSource {
    /// The image (non-finite samples replaced).
    pub volume: Volume,
    /// The isosurface level.
    pub level: f64,
    /// The Gaussian σ in world units (0: the B-spline).
    pub sigma: f64,
}

/// The surface in `path`: a mesh file (with per-vertex `scalars` read from text
/// files, repairs warned about), or the isosurface of a 3D image as `volume` says.
/// `estimator` serves meshes (and images with `--curvature mesh`).
pub fn load_surface(
    path: &Path,
    (strict, volume, estimator): (StrictArg, &VolumeArgs, Estimator),
    scalars: &[(&str, &Path)],
    report: &mut Report,
) -> Result<Surface> {
    if is_volume_path(path) {
        if !scalars.is_empty() {
            return Err(argument(
                path,
                "per-vertex values from a file apply to meshes, not to 3D images",
            ));
        }
        return image_surface(path, volume, estimator, report);
    }
    if volume.level.is_some() || volume.sigma.is_some() {
        return Err(argument(
            path,
            "--level and --sigma apply to 3D images (.nii, .nii.gz, .nrrd, .nhdr, .mha, .mhd), not to meshes",
        ));
    }
    let (mesh, repairs) = load_mesh_with_scalars(path, strict, report, scalars)?;
    warn_repairs(path, &repairs);
    Ok(Surface {
        mesh,
        estimator: estimator.build(),
        image: None,
    })
}

/// `--level`, which the image at `path` needs.
pub fn required_level(path: &Path, args: &VolumeArgs) -> Result<f64> {
    args.level.ok_or_else(|| {
        argument(
            path,
            "a 3D image needs --level I for its isosurface (`crestline info` on the image suggests one)",
        )
    })
}

/// The isosurface of the image at `path` and its curvature, with the stages
/// `read`, `smoothing` and `isosurface` in `report`.
fn image_surface(
    path: &Path,
    args: &VolumeArgs,
    estimator: Estimator,
    report: &mut Report,
) -> Result<Surface> {
    let level = required_level(path, args)?;
    let volume = read_image(path, report)?;
    let sigma = args.sigma.unwrap_or_else(|| default_sigma(&volume));
    report.section("sigma", sigma);
    report.section("level", level);
    let curvature = report
        .stage("smoothing", || ImageCurvature::new(&volume, sigma))
        .map_err(|e| naming(e, path))?;
    let surface_volume = curvature.surface_volume(&volume)?;
    let iso = report
        .stage("isosurface", || isosurface(&surface_volume, level))
        .map_err(|e| naming(e, path))?;
    let mesh = report.stage("mesh", || iso.to_mesh())?;
    report.count("vertices", mesh.vertex_count());
    report.count("faces", mesh.face_count());
    let estimator: Arc<dyn CurvatureEstimator + Send + Sync> = match args.curvature {
        CurvatureSource::Image => Arc::new(curvature),
        CurvatureSource::Mesh => estimator.build(),
    };
    drop(surface_volume);
    Ok(Surface {
        mesh,
        estimator,
        image: Some(ImageSource {
            volume,
            level,
            sigma,
        }),
    })
}

/// The 3D image at `path` (the stage `read`), its non-finite samples set to the
/// background with a warning ([`replace_non_finite`]).
pub fn read_image(path: &Path, report: &mut Report) -> Result<Volume> {
    let mut volume = report.stage("read", || read_volume(path))?;
    replace_non_finite(path, &mut volume)?;
    Ok(volume)
}

/// Set non-finite samples (NaN outside the mask of a resampled scan, say) to the
/// smallest finite value, the background, with a warning; an image without a
/// finite sample is an error.
fn replace_non_finite(path: &Path, volume: &mut Volume) -> Result<()> {
    let lowest = volume
        .samples()
        .iter()
        .copied()
        .filter(|s| s.is_finite())
        .reduce(f32::min)
        .ok_or_else(|| argument(path, "the image has no finite sample"))?;
    let count = volume.replace_non_finite(lowest);
    if count > 0 {
        super::warn(
            path,
            &format!("{count} samples are not finite (NaN or infinite); they were set to the smallest value, {lowest}"),
        );
    }
    Ok(())
}

/// One voxel: the largest spacing.
pub fn default_sigma(volume: &Volume) -> f64 {
    volume.spacing().into_iter().fold(0.0, f64::max)
}

/// An error unless `path` names a 3D image; `command` is the one that needs it.
pub fn require_image(path: &Path, command: &str) -> Result<()> {
    if is_volume_path(path) {
        Ok(())
    } else {
        Err(argument(
            path,
            &format!("{command} needs a 3D image (.nii, .nii.gz, .nrrd, .nhdr, .mha, .mhd)"),
        ))
    }
}

/// `err` naming the image it is about (its argument errors too: a level or σ
/// that does not fit the image).
pub fn naming(err: Error, path: &Path) -> Error {
    match err {
        Error::Argument(message) => argument(path, &message),
        other => other.in_file(path),
    }
}

/// An argument error about the input `path`.
fn argument(path: &Path, message: &str) -> Error {
    Error::File {
        path: path.to_path_buf(),
        message: message.to_string(),
    }
}
