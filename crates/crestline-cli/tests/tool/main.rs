//! The command-line tool's tests, as one test binary: each module runs the built
//! `crestline` as its users do. `cargo test --release --test tool parity::` runs one.

mod common;

mod cli;
mod compare;
mod dicom;
mod documents;
mod draw;
mod fuzz_volumes;
mod hostile;
mod hostile_readers;
mod info_percentiles;
mod options;
mod parity;
mod quality;
mod transfer;
mod view;
