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

pub use accuracy::relative_rms_error;
pub use auto::{AutoEstimator, CLEAN_FIT_RESIDUAL};
pub use choice::Estimator;
pub use field::{CurvatureEstimator, CurvatureField, GivenCurvature, WithoutExtremality};
pub use image::{image_isosurface, DerivativeOrder, ImageCurvature};
pub use jet::JetFit;
pub use output::{estimate_curvature, write_curvature_ply, write_curvature_ply_with_quality};
pub use per_vertex::{
    freesurfer_values, write_curvature_values, PER_VERTEX_FORMATS, SIGN_CONVENTION,
    SIGN_CONVENTION_KEY,
};
pub use quality::Quality;
pub use robust::{repair_outliers, OUTLIER_SCALES};
pub use shape_operator::ShapeOperator;

pub use crate::differential::{
    implicit_curvature, isosurface_curvature, symmetric_2x2_eigen, tangent_basis, IsoCurvature,
    PrincipalCurvatures, ThirdOrder,
};
