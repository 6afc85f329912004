//! Principal curvatures and directions of a mesh, per vertex.
//!
//! Sign convention, used everywhere in crestline: with outward normals (faces
//! counter-clockwise seen from outside) a sphere has both principal curvatures
//! positive. `k_max ≥ k_min` algebraically.
//!
//! Estimators implement [`CurvatureEstimator`]; two come with the crate:
//! - [`ShapeOperator`] (the default): the edge-based discrete shape operator of
//!   Hildebrandt, Polthier and Wardetzky (2005), §3. Linear in the number of edges
//!   and parallel; accurate on regular meshes, noisier on irregular ones.
//! - [`JetFit`]: an unweighted least-squares quartic fit (a 4-jet in the sense of
//!   Cazals and Pouget) over an adaptive neighbourhood of rings. Accurate on irregular
//!   meshes; use it where the mesh has many 3- and 4-valent vertices or strongly
//!   varying triangle sizes.
//! - [`AutoEstimator`]: the jet fit on clean meshes, the shape operator on noisy ones
//!   (by the fit's residual); the default of line extraction.

mod accuracy;
mod auto;
mod choice;
mod field;
mod image;
mod jet;
mod output;
mod per_vertex;
mod quality;
mod robust;
mod shape_operator;

pub use auto::AutoEstimator;
pub(crate) use auto::CLEAN_FIT_RESIDUAL;
pub use choice::Estimator;
pub use field::{CurvatureEstimator, CurvatureField, GivenCurvature, WithoutExtremality};
#[cfg(test)]
pub(crate) use image::image_isosurface;
pub use image::{DerivativeOrder, ImageCurvature};
pub use jet::JetFit;
pub use output::estimate_curvature;
pub use per_vertex::PER_VERTEX_FORMATS;
pub use quality::Quality;
#[cfg(test)]
pub(crate) use robust::repair_outliers;
pub use shape_operator::ShapeOperator;

#[cfg(test)]
pub(crate) use crate::differential::ThirdOrder;
pub use crate::differential::{implicit_curvature, PrincipalCurvatures};
pub(crate) use crate::differential::{
    isosurface_curvature, symmetric_2x2_eigen, tangent_basis, IsoCurvature,
};

#[cfg(test)]
mod tests;
