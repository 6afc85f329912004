//! Principal curvatures per vertex (`crestline curvature`).

use serde::{Deserialize, Serialize};

use super::image::Surface;
use crate::curvature::{estimate_curvature, CurvatureField, Estimator, Quality};
use crate::progress::{try_stage, Observer};
use crate::Result;

/// Options of [`curvature`]. Each field is an option of the tool and a keyword
/// argument of the Python package, documented here once: with the feature `clap`
/// this struct is the tool's arguments.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
#[serde(default, deny_unknown_fields)]
pub struct CurvatureOptions {
    /// Curvature estimator: shape-operator is fast and best on regular meshes;
    /// jet-fit (a quartic least-squares fit over a ring neighbourhood) is slower and
    /// accurate on irregular ones. An image's isosurface may carry its image's
    /// curvature instead.
    #[cfg_attr(feature = "clap", arg(long, value_enum,
        default_value_t = CurvatureOptions::default().estimator))]
    pub estimator: Estimator,
    /// The curvature quantity also written as the vertex property `quality`, the
    /// one MeshLab and pymeshlab colour and filter by; the quantity of a .shape.gii
    /// or .curv output.
    #[cfg_attr(feature = "clap", arg(long, value_enum,
        default_value_t = CurvatureOptions::default().quality))]
    pub quality: Quality,
}

/// The principal curvatures and directions at every vertex of `surface`: the
/// stage `curvature`, and the count `unreliable` of vertices whose estimate was
/// flagged (the boundary, outliers).
///
/// # Examples
///
/// ```
/// # use crestline::jobs::{self, Surface};
/// # use crestline::progress::Silent;
/// # let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../meshes/bunny_small.obj");
/// # let (mesh, _repairs) = jobs::build_mesh(crestline::io::read_mesh(path.as_ref())?, false, &mut Silent)?;
/// # let surface = Surface::of_mesh(mesh);
/// let field = jobs::curvature(&surface, &jobs::CurvatureOptions::default(), &mut Silent)?;
/// assert_eq!(field.k_max.len(), surface.mesh.vertex_count());
/// # Ok::<(), crestline::Error>(())
/// ```
pub fn curvature(
    surface: &Surface,
    options: &CurvatureOptions,
    observer: &mut dyn Observer,
) -> Result<CurvatureField> {
    let estimator = surface.estimator(options.estimator);
    let field = try_stage(observer, "curvature", || {
        estimate_curvature(&surface.mesh, estimator.as_ref())
    })?;
    observer.count(
        "unreliable",
        field.unreliable.iter().filter(|&&u| u).count(),
    );
    Ok(field)
}
