//! Lengths given in world units or relative to the input.

use serde::{Deserialize, Serialize};

/// A length: in world units (millimetres for most scans), or a multiple of the
/// input's own unit — the largest voxel spacing of an image, the mean edge length
/// of a mesh — resolved by the job. Serialized as a number, or as `{"units": x}`.
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
}

impl Length {
    /// `units` times the input's unit.
    pub const fn units(units: f64) -> Length {
        Length::Relative { units }
    }

    /// The length in world units, for an input whose unit is `unit`.
    pub fn resolve(self, unit: f64) -> f64 {
        match self {
            Length::World(length) => length,
            Length::Relative { units } => units * unit,
        }
    }

    /// The length, checked to be finite and at least 0 (positive if `positive`),
    /// for an input whose unit is `unit`; the error names the option `name`.
    pub fn resolve_checked(self, unit: f64, name: &str, positive: bool) -> crate::Result<f64> {
        let length = self.resolve(unit);
        let valid = length.is_finite()
            && if positive {
                length > 0.0
            } else {
                length >= 0.0
            };
        if valid {
            Ok(length)
        } else {
            let least = if positive { "positive" } else { "at least 0" };
            Err(crate::Error::Argument(format!(
                "{name} is a length, finite and {least}, not {length}"
            )))
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
        }
    }
}
