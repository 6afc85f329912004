//! Anatomical landmarks from crest lines (`crestline landmarks`).

use serde::{Deserialize, Serialize};

use super::crest::{crest_lines, CrestLinesOptions};
use super::image::{image_units, Surface};
use super::ridges::{ridges, RidgesOptions};
use super::{Length, Units};
use crate::landmarks::{landmarks as find_landmarks, LandmarkOptions, Landmarks};
use crate::lines::FeatureLines;
use crate::progress::{try_stage, Observer};
use crate::volume::Volume;
use crate::Result;

/// Options of [`landmarks`]. Each field is an option of the tool and a keyword
/// argument of the Python package, documented here once: with the feature `clap`
/// this struct is the tool's arguments.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
#[serde(default, deny_unknown_fields)]
pub struct LandmarksOptions {
    /// A curvature maximum is the largest within this arc length on both sides, in
    /// world units or in feature scales (of a mesh: 1% of the square root of its
    /// area, at least a mean edge length).
    #[cfg_attr(feature = "clap", arg(long, value_name = "R",
        default_value_t = LandmarksOptions::default().radius))]
    pub radius: Length,
    /// An extremal point needs the other extremality's sign to hold this long on
    /// both sides, in world units or in feature scales.
    #[cfg_attr(feature = "clap", arg(long, value_name = "P",
        default_value_t = LandmarksOptions::default().persistence))]
    pub persistence: Length,
}

impl Default for LandmarksOptions {
    fn default() -> Self {
        LandmarksOptions {
            radius: Length::scales(2.5),
            persistence: Length::scales(1.0),
        }
    }
}

/// Where the crest lines of [`landmarks`] come from.
pub enum LinesFrom<'a> {
    /// The crest lines of an image's isosurface `level` by Marching Lines
    /// ([`crest_lines`]); its units are one voxel and the image's feature scale.
    Image {
        /// The image.
        volume: &'a Volume,
        /// The isosurface level.
        level: f64,
        /// How the lines are traced.
        options: &'a CrestLinesOptions,
    },
    /// The ridges and valleys of a surface by extremality tracing ([`ridges`]);
    /// its units are the surface's: one voxel and the image's feature scale on an
    /// isosurface, the mean edge length and the scale of its area on a mesh.
    Surface {
        /// The surface.
        surface: &'a Surface,
        /// How the lines are traced.
        options: &'a RidgesOptions,
    },
    /// Lines found elsewhere (read from a file, say), whose relative lengths are
    /// in `unit`s: both the sampling's and the feature scale's.
    Lines {
        /// The lines.
        lines: &'a FeatureLines,
        /// The unit of the relative lengths, in world units.
        unit: f64,
    },
}

/// The landmarks of the crest lines of `input` (Thirion's extremal points,
/// curvature maxima, line ends, and a descriptor per line;
/// `crate::landmarks::landmarks`), with the stages of the tracing and
/// `landmarks`, and the counts `landmarks` and `crest_lines`.
///
/// # Examples
///
/// ```
/// # use crestline::jobs::{self, Surface};
/// # use crestline::progress::Silent;
/// # let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../meshes/bunny_small.obj");
/// # let (mesh, _repairs) = jobs::build_mesh(crestline::io::read_mesh(path.as_ref())?, false, &mut Silent)?;
/// # let surface = Surface::of_mesh(mesh);
/// let ridges = jobs::RidgesOptions::default();
/// let input = jobs::LinesFrom::Surface { surface: &surface, options: &ridges };
/// let found = jobs::landmarks(input, &jobs::LandmarksOptions::default(), &mut Silent)?;
/// println!("{} extremal points", found.points.len());
/// # Ok::<(), crestline::Error>(())
/// ```
pub fn landmarks(
    input: LinesFrom<'_>,
    options: &LandmarksOptions,
    observer: &mut dyn Observer,
) -> Result<Landmarks> {
    let (lines, units) = match input {
        LinesFrom::Image {
            volume,
            level,
            options,
        } => {
            // The scale once: the lines are traced at the one the landmarks use.
            let units = image_units(volume, level, options.scale, observer)?;
            let at_scale = CrestLinesOptions {
                scale: Some(units.scale),
                ..*options
            };
            (crest_lines(volume, level, &at_scale, observer)?, units)
        }
        LinesFrom::Surface { surface, options } => {
            (ridges(surface, options, observer)?, surface.units())
        }
        LinesFrom::Lines { lines, unit } => {
            let units = Units {
                sample: unit,
                scale: unit,
            };
            return landmarks_of_lines(lines, units, options, observer);
        }
    };
    landmarks_of_lines(&lines, units, options, observer)
}

/// The landmarks of `lines`, whose relative lengths are in `units`: the stage
/// `landmarks` and the counts `landmarks` and `crest_lines`.
pub(crate) fn landmarks_of_lines(
    lines: &FeatureLines,
    units: Units,
    options: &LandmarksOptions,
    observer: &mut dyn Observer,
) -> Result<Landmarks> {
    let resolved = LandmarkOptions {
        radius: options.radius.resolve(units),
        persistence: options.persistence.resolve(units),
    };
    let found = try_stage(observer, "landmarks", || find_landmarks(lines, &resolved))?;
    observer.count("landmarks", found.points.len());
    observer.count("crest_lines", found.lines.len());
    Ok(found)
}
