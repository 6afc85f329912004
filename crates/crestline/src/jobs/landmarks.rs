//! Anatomical landmarks from crest lines (`crestline landmarks`).

use serde::{Deserialize, Serialize};

use super::crest::{crest_lines, CrestLinesOptions};
use super::image::{voxel_size, Surface};
use super::ridges::{ridges, RidgesOptions};
use super::Length;
use crate::landmarks::{landmarks as find_landmarks, LandmarkOptions, Landmarks};
use crate::lines::FeatureLines;
use crate::progress::{try_stage, Observer};
use crate::volume::Volume;
use crate::Result;

/// Options of [`landmarks`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LandmarksOptions {
    /// A curvature maximum is the largest within this arc length on both sides.
    /// Default: five units (voxels, or mean edge lengths).
    pub radius: Length,
    /// An extremal point needs the other extremality's sign to hold this long on
    /// both sides. Default: two units.
    pub persistence: Length,
}

impl Default for LandmarksOptions {
    fn default() -> Self {
        LandmarksOptions {
            radius: Length::units(5.0),
            persistence: Length::units(2.0),
        }
    }
}

/// Where the crest lines of [`landmarks`] come from.
pub enum LinesFrom<'a> {
    /// The crest lines of an image's isosurface `level` by Marching Lines
    /// ([`crest_lines`]); the unit is one voxel.
    Image {
        /// The image.
        volume: &'a Volume,
        /// The isosurface level.
        level: f64,
        /// How the lines are traced.
        options: &'a CrestLinesOptions,
    },
    /// The ridges and valleys of a surface by extremality tracing ([`ridges`]);
    /// the unit is one voxel for an isosurface, else the mean edge length.
    Surface {
        /// The surface.
        surface: &'a Surface,
        /// How the lines are traced.
        options: &'a RidgesOptions,
    },
}

/// The landmarks of the crest lines of `input` (Thirion's extremal points,
/// curvature maxima, line ends, and a descriptor per line;
/// [`crate::landmarks::landmarks`]), with the stages of the tracing and
/// `landmarks`, and the counts `landmarks` and `crest_lines`.
pub fn landmarks(
    input: LinesFrom<'_>,
    options: &LandmarksOptions,
    observer: &mut dyn Observer,
) -> Result<Landmarks> {
    let (lines, unit) = match input {
        LinesFrom::Image {
            volume,
            level,
            options,
        } => (
            crest_lines(volume, level, options, observer)?,
            voxel_size(volume),
        ),
        LinesFrom::Surface { surface, options } => {
            (ridges(surface, options, observer)?, surface.unit())
        }
    };
    landmarks_of_lines(&lines, unit, options, observer)
}

/// The landmarks of `lines`, whose relative lengths are in `unit`s: the stage
/// `landmarks` and the counts `landmarks` and `crest_lines`.
pub fn landmarks_of_lines(
    lines: &FeatureLines,
    unit: f64,
    options: &LandmarksOptions,
    observer: &mut dyn Observer,
) -> Result<Landmarks> {
    let resolved = LandmarkOptions {
        radius: options.radius.resolve(unit),
        persistence: options.persistence.resolve(unit),
    };
    let found = try_stage(observer, "landmarks", || find_landmarks(lines, &resolved))?;
    observer.count("landmarks", found.points.len());
    observer.count("crest_lines", found.lines.len());
    Ok(found)
}
