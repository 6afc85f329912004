//! What an interactive view of a surface shows (`crestline view`): its lines and
//! its curvature, for [`crate::view::view_html`] (feature `view`) to write.

use serde::{Deserialize, Serialize};

use super::draw::{given_or_traced, morse_of_a_picture, LinesChoice};
use super::image::Surface;
use super::morse::MorseOptions;
use super::ridges::RidgesOptions;
use crate::curvature::{estimate_curvature, CurvatureField};
use crate::lines::FeatureLines;
use crate::progress::{try_stage, Observer};
use crate::volume::Volume;
use crate::Result;

/// Options of [`view`]. With the feature `clap` this struct is the tool's
/// arguments, but for the ridges' and Morse-Smale lines' options, which are their
/// jobs'.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
#[serde(default, deny_unknown_fields)]
pub struct ViewOptions {
    /// Which feature lines: ridges (the options of the ridges job), morse (those
    /// of the Morse-Smale job), crest (for a 3D image: its crest lines by Marching
    /// Lines, traced in the image) or none (e.g. silhouettes only).
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = LinesChoice::default()))]
    pub lines: LinesChoice,
    /// How ridges are traced (`lines` ridges; their estimator also gives the
    /// curvature the surface is coloured by, and their threshold the crest lines).
    #[cfg_attr(feature = "clap", arg(skip))]
    pub ridges: RidgesOptions,
    /// How Morse-Smale lines are extracted (`lines` morse). Default: the Morse-Smale
    /// job's, with the ridges' estimator.
    #[cfg_attr(feature = "clap", arg(skip = morse_of_a_picture()))]
    pub morse: MorseOptions,
}

impl Default for ViewOptions {
    fn default() -> Self {
        ViewOptions {
            lines: LinesChoice::default(),
            ridges: RidgesOptions::default(),
            morse: morse_of_a_picture(),
        }
    }
}

/// The lines (the stage `extraction`, with the stages of their job; or the `given`
/// lines instead) and the curvature (the stage `curvature`, by the surface's
/// estimator or the ridges' one) of `surface` that a view shows. `volume` is the
/// image of an isosurface, which `lines` crest needs.
///
/// # Examples
///
/// ```
/// # use crestline::jobs::{self, Surface, ViewOptions};
/// # use crestline::progress::Silent;
/// # let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../meshes/bunny_small.obj");
/// # let (mesh, _repairs) = jobs::build_mesh(crestline::io::read_mesh(path.as_ref())?, false, &mut Silent)?;
/// let surface = Surface::of_mesh(mesh);
/// let (lines, curvature) = jobs::view(&surface, (None, None), &ViewOptions::default(), &mut Silent)?;
/// assert!(!lines.is_empty());
/// assert_eq!(curvature.k_max.len(), surface.mesh.vertex_count());
/// # Ok::<(), crestline::Error>(())
/// ```
pub fn view(
    surface: &Surface,
    (volume, given): (Option<&Volume>, Option<FeatureLines>),
    options: &ViewOptions,
    observer: &mut dyn Observer,
) -> Result<(FeatureLines, CurvatureField)> {
    let choice = (options.lines, &options.ridges, &options.morse);
    let lines = given_or_traced(surface, (volume, given), choice, observer)?;
    let estimator = surface.estimator(options.ridges.estimator);
    let curvature = try_stage(observer, "curvature", || {
        estimate_curvature(&surface.mesh, estimator.as_ref())
    })?;
    Ok((lines, curvature))
}
