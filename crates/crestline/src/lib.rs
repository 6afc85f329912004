//! # crestline
//!
//! Feature lines on surfaces: ridge and valley (crest) lines of triangle meshes, and
//! crest lines, isosurfaces and crease surfaces of 3D images.
//!
//! ## The public API
//!
//! - [`jobs`]: one function per command of the `crestline` tool — [`jobs::isosurface`],
//!   [`jobs::crest_lines`], [`jobs::crease`], [`jobs::curvature`], [`jobs::ridges`],
//!   [`jobs::morse`], [`jobs::landmarks`], [`jobs::register()`], [`jobs::draw`],
//!   [`jobs::mesh_info`] — each with an options struct whose `Default` holds every
//!   default. The command-line tool and the Python package call these, so every
//!   door gives the same result; start here.
//! - Input and output: [`io`] reads meshes ([`io::read_mesh`]) and images
//!   ([`io::read_volume`]) and picks every format from a file name in one place
//!   ([`io::choose_format`]); [`lines`], [`landmarks`], [`register`] and
//!   [`curvature`] write their results.
//! - The data: [`mesh::Mesh`] (half-edge, repaired from a [`mesh::TriangleSoup`]),
//!   [`volume::Volume`], [`lines::FeatureLines`], [`curvature::CurvatureField`].
//! - The methods, for finer control than the jobs: [`curvature`] (estimators),
//!   [`ridges`] (extremality tracing, Hildebrandt, Polthier and Wardetzky 2005),
//!   [`morse`] (Morse-Smale lines, Sahner et al. 2008), [`isosurface`] and
//!   [`crest_lines`] of [`volume`]s (isosurfaces, and crest lines by Marching Lines,
//!   after Thirion and Gourdon 1993), [`landmarks`], [`register`] and [`draw`].
//! - [`progress`]: the [`progress::Observer`] every long computation reports to and
//!   asks whether to go on; [`Error`]: the one error type.
//!
//! Everything else is private to the crate: the sparse solvers, the discrete
//! gradient and cancellation queue of the Morse-Smale complex, the smoothing and
//! tracing steps of the ridge pipeline, grid arithmetic and the Gaussian
//! derivative kernels of images. Their design, with the details
//! the papers leave open, is `docs/design/` in the repository; their tests are
//! unit tests next to them.
//!
//! ## Where new things go
//!
//! - A curvature estimator: implement [`curvature::CurvatureEstimator`] (one
//!   method, the field of a mesh). To offer it by name on the command line and in
//!   Python, add it to [`curvature::Estimator`] (its names come from one table).
//! - A line extractor: implement [`lines::LineExtractor`] for the input it needs
//!   (a [`mesh::Mesh`], a [`lines::SurfaceWithCurvature`], a
//!   [`lines::SurfaceWithValues`], a [`volume::Volume`]); filters, writers and
//!   drawings then take its lines. A command for it is a job in [`jobs`].
//! - An output format: add it to [`io::FileFormat`] and to the `choose_format`
//!   choices of what it writes (lines: [`lines::LineFormat`]; surfaces:
//!   [`io::write_soup`]), and write it atomically ([`io::write_atomically`]).
//!
//! The pipeline runs left to right, each stage a plain function of what the stage
//! before produced: a file is read into a [`mesh::TriangleSoup`] ([`io::read_mesh`]),
//! repaired and connected into a half-edge [`mesh::Mesh`] ([`mesh::Mesh::from_soup`]),
//! and the extracted lines are collected in a [`lines::FeatureLines`] value that the
//! writers in [`lines`] save as JSON, OBJ, PLY or VTK.
//!
//! ## Conventions
//! - Geometry is `f64`. Ids are `u32` newtypes ([`mesh::VertexId`], ...).
//! - Faces are counter-clockwise seen from outside; on a sphere with outward normals
//!   both principal curvatures are positive. Ridges are maxima of `k_max` along its
//!   direction, valleys minima of `k_min`.
//! - Every length-like parameter is relative to the mesh (mean edge length or
//!   bounding-box diagonal), so results do not change with the unit of the file.
//! - Bad input is an [`Error`] naming the file and what is wrong, never a panic; output
//!   files are written under a temporary name and renamed on success.

#![warn(missing_docs)]

pub(crate) mod atomic;
pub(crate) mod chain;
pub mod compare;
mod crease;
pub mod crest_lines;
pub mod curvature;
pub(crate) mod differential;
pub mod draw;
mod error;
pub mod io;
pub mod isosurface;
pub mod jobs;
pub mod landmarks;
mod length;
pub(crate) mod linalg;
pub mod lines;
pub mod mesh;
pub mod morse;
mod named;
pub mod progress;
pub mod register;
pub mod ridges;
mod slices;
pub mod space;
pub mod transfer;
#[cfg(feature = "view")]
pub mod view;
pub mod volume;
mod xml;

// The unit tests' helpers, shared with the integration tests, which name the
// crate `crestline`.
#[cfg(test)]
extern crate self as crestline;
#[cfg(test)]
#[path = "../tests/library/common/mod.rs"]
mod common;

pub use error::{Error, Result};
pub use space::Space;

/// A point in 3D space.
pub type Point = nalgebra::Point3<f64>;
/// A vector in 3D space.
pub type Vector = nalgebra::Vector3<f64>;
