//! One function per command of the `crestline` tool, with every default in one
//! place.
//!
//! Each job takes its input (a [`Mesh`](crate::mesh::Mesh), a
//! [`Volume`](crate::volume::Volume) or the lines another job found), an options
//! struct whose [`Default`] holds every default of the job, and an
//! [`Observer`](crate::progress::Observer) that is told the stages, counts and
//! warnings and can stop the run ([`crate::Error::Cancelled`]). It returns typed
//! results; writing them is the caller's. The command-line tool parses its
//! arguments into these options and the Python package fills them from keyword
//! arguments (`None` meaning the default here), so that every door gives the
//! same result for the same input.
//!
//! Defaults that depend on the input are values too: a [`Length`] is either in
//! world units or a multiple of the input's own unit (the largest voxel spacing
//! of an image, the mean edge length of a mesh), which the job resolves.
//!
//! | command | job | options |
//! |---|---|---|
//! | `info` | [`mesh_info`], [`image_info`] | none |
//! | `curvature` | [`curvature`] | [`CurvatureOptions`] |
//! | `iso` | [`isosurface`] | [`IsoOptions`] |
//! | `crest-lines` | [`crest_lines`] | [`CrestLinesOptions`] |
//! | `crease` | [`crease`] | [`CreaseOptions`] |
//! | `ridges` | [`ridges`] | [`RidgesOptions`] |
//! | `morse` | [`morse`] | [`MorseOptions`] |
//! | `draw` | [`draw`] | [`DrawingOptions`] |
//! | `register` | [`register()`] | [`RegistrationOptions`](crate::register::RegistrationOptions) |
//! | `landmarks` | [`landmarks`] | [`LandmarksOptions`] |
//! | `transfer` | [`transfer()`], [`ridges`] of meshes with [`TransferOptions::mesh_tracing`](crate::transfer::TransferOptions::mesh_tracing) | [`TransferOptions`](crate::transfer::TransferOptions) |
//! | `view` | [`view`] | [`ViewOptions`] |
//!
//! [`defaults`] gives every options struct's defaults as JSON, as the Python
//! package reads them.

mod crease;
mod crest;
mod curvature;
mod draw;
mod image;
mod info;
mod landmarks;
mod mesh;
mod morse;
mod register;
mod ridges;
mod scale;
mod transfer;
mod view;

pub use crate::length::Length;
pub(crate) use crate::length::Units;
pub use crease::{crease, CreaseOptions};
pub use crest::{crest_lines, CrestLinesOptions};
pub use curvature::{curvature, CurvatureOptions};
pub use draw::{draw, DrawingOptions, LinesChoice};
#[cfg(test)]
pub(crate) use image::image_units;
pub use image::{isosurface, CurvatureSource, FromImage, IsoOptions, Surface};
pub use info::{image_info, mesh_info, MeshInfo};
pub use landmarks::{landmarks, LandmarksOptions, LinesFrom};
pub use mesh::build_mesh;
pub use morse::{morse, MorseOptions};
pub use register::register;
pub use ridges::{ridges, RidgesOptions};
pub use transfer::transfer;
pub use view::{view, ViewOptions};

/// The defaults of every job's options, as JSON: `{"curvature": {...}, "iso": {...}, "crest_lines":
/// {...}, ...}`, keyed by job and then by option, as the options structs
/// serialize.
///
/// # Examples
///
/// ```
/// let defaults = crestline::jobs::defaults();
/// assert_eq!(defaults["ridges"]["threshold"], 2.0);
/// assert_eq!(defaults["crest_lines"]["sigma"], serde_json::json!({"scales": 1.0}));
/// ```
pub fn defaults() -> serde_json::Value {
    serde_json::json!({
        "curvature": CurvatureOptions::default(),
        "iso": IsoOptions::default(),
        "crest_lines": CrestLinesOptions::default(),
        "crease": CreaseOptions::default(),
        "ridges": RidgesOptions::default(),
        "morse": MorseOptions::default(),
        "draw": DrawingOptions::default(),
        "register": crate::register::RegistrationOptions::default(),
        "landmarks": LandmarksOptions::default(),
        "transfer": crate::transfer::TransferOptions::default(),
        "view": ViewOptions::default(),
    })
}

/// The options of `job` (a key of [`defaults`]) with the values of `overrides` (a
/// JSON object of some of its options) in place of the defaults; an unknown
/// option or a value of the wrong type is an error naming it.
pub fn options_from_json<T>(job: &str, overrides: &serde_json::Value) -> crate::Result<T>
where
    T: serde::de::DeserializeOwned + serde::Serialize + Default,
{
    let mut options = serde_json::to_value(T::default()).expect("options serialize");
    let (Some(fields), Some(given)) = (options.as_object_mut(), overrides.as_object()) else {
        return Err(crate::Error::Argument(format!(
            "the options of {job} are a JSON object"
        )));
    };
    for (key, value) in given {
        if !fields.contains_key(key) {
            let known: Vec<&str> = fields.keys().map(String::as_str).collect();
            return Err(crate::Error::unknown_name(
                &format!("option of {job}"),
                key,
                &known,
            ));
        }
        fields.insert(key.clone(), value.clone());
    }
    serde_json::from_value(options)
        .map_err(|e| crate::Error::Argument(format!("the options of {job}: {e}")))
}

#[cfg(test)]
mod tests;
