//! The curvature quantity a curvature PLY file also carries as its `quality`
//! vertex property: the one MeshLab and pymeshlab colour and filter by.

use super::CurvatureField;

/// Which per-vertex curvature quantity is written as the `quality` property.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Quality {
    /// `k_max`: the larger principal curvature.
    KMax,
    /// `k_min`: the smaller principal curvature.
    KMin,
    /// `mean`: the mean curvature (k_max + k_min) / 2.
    #[default]
    Mean,
    /// `gauss`: the Gaussian curvature k_max k_min.
    Gauss,
    /// `curvedness`: √((k_max² + k_min²) / 2) (Koenderink).
    Curvedness,
}

crate::named::named!(Quality, "quality", {
    KMax => "k_max",
    KMin => "k_min",
    Mean => "mean",
    Gauss => "gauss",
    Curvedness => "curvedness",
});

impl Quality {
    /// The chosen quantity at every vertex of `field`.
    pub fn values(self, field: &CurvatureField) -> Vec<f64> {
        match self {
            Quality::KMax => field.k_max.clone(),
            Quality::KMin => field.k_min.clone(),
            Quality::Mean => field.mean(),
            Quality::Gauss => field.gauss(),
            Quality::Curvedness => field.curvedness(),
        }
    }
}
