//! Tests of crease surfaces, and the comparison with the paper's baseline.

mod compare_crease;
mod surfaces;
