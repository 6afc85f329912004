//! Tests of the module and of what it is built on, with the data sets and
//! cross-checks they read.

mod landmarks;
