//! The library's integration tests, as one test binary (each binary links the whole
//! library: one instead of one a file keeps `cargo test` short). A module a subject;
//! `cargo test --release --test library ridges::` runs one.

mod common;

mod crease;
mod curvature;
mod dicom;
mod draw;
mod families;
mod fuzz_readers;
mod generators;
mod image_curvature;
mod io_readers;
mod isosurface;
mod isosurface_vtk;
mod landmarks;
mod layering;
mod lines_output;
mod long_stages;
mod marching_lines;
mod mesh_repair;
mod morse_drawing;
mod neuro_formats;
mod nibabel_data;
mod numerics;
mod register;
mod ridges;
mod sampling;
mod solver;
mod soup_writer;
mod transfer;
mod volume_derivatives;
mod volume_readers;
