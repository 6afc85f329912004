//! Lengths given in world units, relative to the input's sampling, or relative to
//! the feature scale.

use serde::{Deserialize, Serialize};

/// A length: in world units (millimetres for most scans), a multiple of the
/// input's own unit — the largest voxel spacing of an image, the mean edge length
/// of a mesh — or a multiple of the feature scale (`super::scale`), resolved by
/// the job. Serialized as a number, as `{"units": x}` or as `{"scales": x}`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Length {
    /// A length in world units.
    World(f64),
    /// A multiple of the input's unit (voxel or mean edge length).
    Relative {
        /// How many units.
        units: f64,
    },
    /// A multiple of the feature scale.
    Scaled {
        /// How many scales.
        scales: f64,
    },
}

/// What the relative [`Length`]s of one input are relative to, in world units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Units {
    /// The input's sampling: one voxel (the largest spacing), or the mean edge
    /// length of a mesh.
    pub sample: f64,
    /// The feature scale (`super::scale`).
    pub scale: f64,
}

impl Length {
    /// `units` times the input's unit.
    pub const fn units(units: f64) -> Length {
        Length::Relative { units }
    }

    /// `scales` times the feature scale.
    pub const fn scales(scales: f64) -> Length {
        Length::Scaled { scales }
    }

    /// The length in world units, for an input whose units are `units`.
    pub(crate) fn resolve(self, units: Units) -> f64 {
        match self {
            Length::World(length) => length,
            Length::Relative { units: count } => count * units.sample,
            Length::Scaled { scales } => scales * units.scale,
        }
    }
}

impl From<f64> for Length {
    fn from(length: f64) -> Length {
        Length::World(length)
    }
}

impl std::fmt::Display for Length {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Length::World(length) => write!(f, "{length}"),
            Length::Relative { units } => write!(f, "{units} units"),
            Length::Scaled { scales } => write!(f, "{scales} scales"),
        }
    }
}
