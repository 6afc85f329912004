//! Crease (ridge and valley) surfaces of 3D scalar fields after Schultz, Theisel and
//! Seidel (2010), "Crease Surfaces: From Theory to Extraction and Application to
//! Diffusion Tensor MRI", §3–4, with the rules of docs/design/crease.md ("Crease surfaces").
//!
//! A ridge surface is where g·e3 = 0 and λ3 < 0 (λ1 ≥ λ2 ≥ λ3 the Hessian's
//! eigenvalues, e3 the eigenvector of λ3); valleys are ridges of −f. The building
//! blocks: the transformed tensor T and h = T g − g at a point ([`Eigenframe`]),
//! derivatives stored at the grid points ([`CreaseField`]), the crossings of h with
//! the grid edges ([`edge_crossings`]), the degenerate points (λ2 = λ3) on the
//! faces crossed an odd number of times, where a crease ends, and the surface of their per-face pairings and per-cell
//! polygons ([`crease_surface`]), whose boundary follows the degenerate lines.
//! For comparison, the paper's baseline (§5): marching cubes of g·e3 after orienting
//! e3 per cell ([`oriented_marching_cubes`]).

#[cfg(test)]
mod baseline;
mod cells;
mod degenerate;
mod edge_index;
mod edges;
mod faces;
mod field;
mod points;
mod strong;
mod surface;
mod tensor;
mod trim;

#[cfg(test)]
pub(crate) use baseline::oriented_marching_cubes;
#[cfg(test)]
pub(crate) use edges::{edge_crossings, CrossingOptions};
#[cfg(test)]
pub(crate) use field::CreaseField;
pub use field::{default_options, Survey};
pub use surface::crease_surface_of;
#[cfg(test)]
pub(crate) use surface::{crease_surface, crease_surface_observed, DEGENERATE, STRENGTH};
#[cfg(test)]
pub(crate) use tensor::Eigenframe;

/// The default ε of the tensor T, as a fraction of the range of the Hessian's
/// eigenvalues over the volume.
pub const DEFAULT_EPSILON_FRACTION: f64 = 0.005;

/// The default similarity below which an edge is bisected (eq. 6).
pub const DEFAULT_THETA: f64 = 0.7;

/// The default least ridge strength −λ3, as a fraction of the strongest over the
/// volume: it keeps the faint shoulders of a ridge, where −λ3 is a few percent of
/// the crest's, from making sheets of their own.
pub const DEFAULT_STRENGTH_FRACTION: f64 = 0.1;

#[cfg(test)]
mod tests;
