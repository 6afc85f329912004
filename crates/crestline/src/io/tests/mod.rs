//! Tests of the module and of what it is built on, with the data sets and
//! cross-checks they read.

mod fuzz_readers;
mod io_readers;
mod neuro_formats;
mod volume_readers;
