//! The scalar field whose Morse-Smale complex gives the feature lines (Sahner et
//! al. 2008, §3.1).

use std::str::FromStr;

use crate::curvature::{estimate_curvature, CurvatureEstimator};
use crate::mesh::Mesh;
use crate::{Error, Result};

/// Which per-vertex scalar to analyse.
#[derive(Clone, Debug, PartialEq)]
pub enum Indicator {
    /// Curvedness √((k_max² + k_min²) / 2), the paper's C: ascending lines are
    /// crests of strong bending of either sign.
    Curvedness,
    /// k_max: ascending lines are ridges.
    KMax,
    /// k_min: descending lines are valleys.
    KMin,
    /// A per-vertex property of the input (e.g. a PLY vertex property).
    Property(String),
}

impl Indicator {
    /// The indicator's value at every vertex, estimating curvature with `estimator`
    /// where needed. Errors if a named property is missing.
    pub fn values(&self, mesh: &Mesh, estimator: &dyn CurvatureEstimator) -> Result<Vec<f64>> {
        Ok(match self {
            Indicator::Property(name) => mesh
                .vertex_scalar(name)
                .ok_or_else(|| {
                    let known: Vec<&str> = mesh
                        .vertex_scalars()
                        .iter()
                        .map(|p| p.name.as_str())
                        .collect();
                    Error::Mesh(format!(
                        "no vertex property '{name}' (the mesh has: {})",
                        if known.is_empty() {
                            "none".to_string()
                        } else {
                            known.join(", ")
                        }
                    ))
                })?
                .to_vec(),
            curvature => {
                let field = estimate_curvature(mesh, estimator)?;
                match curvature {
                    Indicator::KMax => field.k_max,
                    Indicator::KMin => field.k_min,
                    _ => field.curvedness(),
                }
            }
        })
    }
}

impl Indicator {
    /// The names of the built-in indicators ([`FromStr`] takes any other name as
    /// a vertex property's).
    pub const NAMES: &'static [&'static str] = &["curvedness", "kmax", "kmin"];

    /// The indicator's name, as [`FromStr`] reads it.
    pub fn name(&self) -> &str {
        match self {
            Indicator::Curvedness => "curvedness",
            Indicator::KMax => "kmax",
            Indicator::KMin => "kmin",
            Indicator::Property(name) => name,
        }
    }
}

impl std::fmt::Display for Indicator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl serde::Serialize for Indicator {
    fn serialize<S: serde::Serializer>(
        &self,
        serializer: S,
    ) -> std::result::Result<S::Ok, S::Error> {
        serializer.serialize_str(self.name())
    }
}

impl<'de> serde::Deserialize<'de> for Indicator {
    fn deserialize<D: serde::Deserializer<'de>>(
        deserializer: D,
    ) -> std::result::Result<Self, D::Error> {
        let name = <std::borrow::Cow<'de, str>>::deserialize(deserializer)?;
        name.parse().map_err(serde::de::Error::custom)
    }
}

impl FromStr for Indicator {
    type Err = Error;

    /// `curvedness`, `kmax`, `kmin`, or else the name of a vertex property.
    fn from_str(name: &str) -> Result<Indicator> {
        Ok(match name {
            "curvedness" => Indicator::Curvedness,
            "kmax" => Indicator::KMax,
            "kmin" => Indicator::KMin,
            "" => return Err(Error::Argument("the indicator needs a name".into())),
            property => Indicator::Property(property.to_string()),
        })
    }
}
