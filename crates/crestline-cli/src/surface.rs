//! The surface a command works on: a mesh file, or the isosurface of a 3D image with
//! the image's own curvature ([`crestline::jobs::isosurface`]).

use std::path::Path;

use crate::report::Report;
use crestline::curvature::DerivativeOrder;
use crestline::io::{is_volume_path, VolumeReadOptions};
use crestline::jobs::{self, IsoOptions, Surface};
use crestline::volume::Volume;
use crestline::{Error, Result};

use super::load::{load_mesh_with_scalars, ScalarFile, StrictArg};

/// How a 3D image becomes a surface: options of every command that reads a mesh
/// or an image.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct VolumeArgs {
    /// For a 3D image: the isosurface level I; inside is value ≥ I. `crestline info
    /// IMAGE` suggests one.
    #[arg(long, value_name = "I", allow_hyphen_values = true)]
    pub level: Option<f64>,
    #[command(flatten)]
    pub iso: IsoOptions,
    #[command(flatten)]
    pub series: SeriesArg,
}

/// `--series`: the series to read from DICOM input holding several.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct SeriesArg {
    /// For a DICOM folder or DICOMDIR holding several series: the Series Instance
    /// UID of the one to read (without it, the error lists them).
    #[arg(long, value_name = "UID")]
    pub series: Option<String>,
}

impl SeriesArg {
    /// The options of reading an image with this series.
    pub fn options(&self) -> VolumeReadOptions {
        VolumeReadOptions {
            series: self.series.clone(),
        }
    }
}

impl VolumeArgs {
    /// Whether an option that applies to 3D images alone was given: `--level`,
    /// `--sigma`, `--close` or `--series`.
    fn any_image_option(&self) -> bool {
        let defaults = IsoOptions::default();
        self.level.is_some()
            || self.iso.sigma != defaults.sigma
            || self.iso.close != defaults.close
            || self.series.series.is_some()
    }
}

/// A surface loaded for a command, with the image it came from.
pub struct Loaded {
    /// The mesh and where its curvature comes from.
    pub surface: Surface,
    /// For an isosurface: the image, its non-finite samples replaced.
    pub volume: Option<Volume>,
}

/// The surface in `path`: a mesh file (with per-vertex `scalars` read from text
/// files, repairs warned about), or the isosurface of a 3D image as `volume` says
/// (`iso` choosing the mesh estimator for `--curvature mesh`; `needs` the image's
/// derivatives the command uses, [`jobs::isosurface`]).
pub fn load_surface(
    path: &Path,
    (strict, volume, iso, needs): (StrictArg, &VolumeArgs, IsoOptions, Option<DerivativeOrder>),
    scalars: &[ScalarFile<'_>],
    report: &mut Report,
) -> Result<Loaded> {
    if is_volume_path(path) {
        if !scalars.is_empty() {
            return Err(argument(
                path,
                "per-vertex values from a file apply to meshes, not to 3D images",
            ));
        }
        let level = required_level(path, volume)?;
        let image = read_image(path, &volume.series, report)?;
        let surface =
            jobs::isosurface(&image, level, &iso, needs, report).map_err(|e| naming(e, path))?;
        if let Some(from) = surface.image {
            report.section("sigma", from.sigma);
            report.section("level", from.level);
        }
        return Ok(Loaded {
            surface,
            volume: Some(image),
        });
    }
    if volume.any_image_option() {
        return Err(argument(
            path,
            &format!("--level, --sigma, --close and --series apply to 3D images ({IMAGES}), not to meshes"),
        ));
    }
    let (mesh, _) = load_mesh_with_scalars(path, strict, report, scalars)?;
    Ok(Loaded {
        surface: Surface::of_mesh(mesh),
        volume: None,
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

/// The 3D images commands read, for their messages.
pub const IMAGES: &str =
    ".nii, .nii.gz, .nrrd, .nhdr, .mha, .mhd, or a DICOM folder, DICOMDIR or .dcm file";

/// The 3D image at `path` (the stage `read`; of DICOM input, the series
/// `series` chooses), its non-finite samples set to the background with a
/// warning ([`Volume::prepared`]).
pub fn read_image(path: &Path, series: &SeriesArg, report: &mut Report) -> Result<Volume> {
    let volume = report.stage("read", || series.options().read(path))?;
    volume.prepared(report).map_err(|e| naming(e, path))
}

/// An error unless `path` names a 3D image; `command` is the one that needs it.
pub fn require_image(path: &Path, command: &str) -> Result<()> {
    if is_volume_path(path) {
        Ok(())
    } else {
        Err(argument(
            path,
            &format!("{command} needs a 3D image ({IMAGES})"),
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
