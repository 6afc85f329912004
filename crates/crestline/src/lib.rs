//! # crestline
//!
//! Feature lines on surfaces: ridge and valley (crest) lines of triangle meshes, and
//! crest lines, isosurfaces and crease surfaces of 3D images.
//!
//! The pipeline runs left to right, each stage a plain function of what the stage
//! before produced: a file is read into a [`mesh::TriangleSoup`] ([`io::read_mesh`]),
//! repaired and connected into a half-edge [`mesh::Mesh`] ([`mesh::Mesh::from_soup`]),
//! and the extracted lines are collected in a [`lines::FeatureLines`] value that the
//! writers in [`lines`] save as JSON, OBJ, PLY or VTK.
//!
//! For 3D images, [`volume::isosurface()`] extracts isosurfaces,
//! [`volume::marching_lines()`] the lines where an isosurface meets the level set of a
//! second field (Thirion & Gourdon's Marching Lines), and [`crest_lines`] turns
//! them into ridge, valley and parabolic lines of the isosurface.
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

pub mod atomic;
pub mod crest_lines;
pub mod curvature;
pub mod differential;
pub mod draw;
pub mod error;
pub mod io;
pub mod jobs;
pub mod landmarks;
pub mod linalg;
pub mod lines;
pub mod mesh;
pub mod morse;
mod named;
pub mod progress;
pub mod register;
pub mod ridges;
pub mod volume;

pub use error::{Error, Result};

/// A point in 3D space.
pub type Point = nalgebra::Point3<f64>;
/// A vector in 3D space.
pub type Vector = nalgebra::Vector3<f64>;
