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
    /// its units are the surface's ([`Surface::units`]).
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
    };
    landmarks_of_lines(&lines, units, options, observer)
}

/// The landmarks of `lines`, whose relative lengths are in `units`: the stage
/// `landmarks` and the counts `landmarks` and `crest_lines`.
pub fn landmarks_of_lines(
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
