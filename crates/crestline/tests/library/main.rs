//! The library's integration tests, as one test binary (each binary links the whole
//! library: one instead of one a file keeps `cargo test` short). A module a subject;
//! `cargo test --release --test library ridges::` runs one.

mod common;

mod dicom;
mod generators;
mod isosurface;
mod isosurface_vtk;
mod layering;
mod long_stages;
mod mesh_repair;
mod nibabel_data;
mod ridges;
mod solver;
mod soup_writer;
mod transfer;
