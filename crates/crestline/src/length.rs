//! Lengths given in world units, relative to the input's sampling, or relative to
//! the feature scale.

use serde::{Deserialize, Serialize};

/// A length: in world units (millimetres for most scans), a multiple of the
/// input's own unit — the largest voxel spacing of an image, the mean edge length
/// of a mesh — or a multiple of the feature scale (`jobs::scale`), resolved by
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
    /// The feature scale (`jobs::scale`).
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
        let plural = |count: f64| if count == 1.0 { "" } else { "s" };
        match *self {
            Length::World(length) => write!(f, "{length}"),
            Length::Relative { units } => write!(f, "{units} unit{}", plural(units)),
            Length::Scaled { scales } => write!(f, "{scales} scale{}", plural(scales)),
        }
    }
}

/// A length as a user writes it, the way [`Length`] displays: a number (world
/// units), or a number followed by `scale`/`scales` (feature scales) or
/// `unit`/`units` (the input's unit: a voxel, a mean edge length).
impl std::str::FromStr for Length {
    type Err = crate::Error;

    fn from_str(text: &str) -> crate::Result<Length> {
        let text = text.trim();
        // Any number, `nan` and `inf` included: the job says what it accepts.
        if let Ok(value) = text.parse::<f64>() {
            return Ok(Length::World(value));
        }
        let split = text
            .find(|c: char| c.is_alphabetic() && c != 'e' && c != 'E')
            .unwrap_or(text.len());
        let (number, unit) = (text[..split].trim(), text[split..].trim());
        let value: f64 = number.parse().map_err(|_| {
            crate::Error::Argument(format!(
                "'{text}' is not a length: a number, optionally followed by 'scales' or 'units'"
            ))
        })?;
        match unit {
            "" => Ok(Length::World(value)),
            "scale" | "scales" => Ok(Length::scales(value)),
            "unit" | "units" => Ok(Length::units(value)),
            _ => Err(crate::Error::unknown_name(
                "length unit",
                unit,
                &["scales", "units"],
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Length;

    #[test]
    fn a_length_reads_as_it_displays() {
        for length in [
            Length::World(2.5),
            Length::World(-1e-3),
            Length::scales(1.0),
            Length::scales(1.5),
            Length::units(3.0),
        ] {
            assert_eq!(length.to_string().parse::<Length>().unwrap(), length);
        }
        assert_eq!("2".parse::<Length>().unwrap(), Length::World(2.0));
        assert_eq!("1.5scales".parse::<Length>().unwrap(), Length::scales(1.5));
        assert_eq!(
            " 2e-1 units ".parse::<Length>().unwrap(),
            Length::units(0.2)
        );
        for bad in ["", "mm", "2 voxels", "two scales", "1.5 scales extra"] {
            assert!(bad.parse::<Length>().is_err(), "{bad:?} parsed");
        }
    }
}
