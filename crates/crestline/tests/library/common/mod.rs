//! Helpers shared by the integration tests.

pub mod mutation;

use crestline::mesh::{Mesh, TriangleSoup};
use crestline::register::RigidTransform;
use crestline::volume::Volume;
use crestline::Point;
use rayon::prelude::*;

// Each test module takes what it needs, in the library's unit tests and here.

/// The mesh of `positions` and `triangles` (repaired as a file's would be).
#[allow(dead_code)]
pub fn mesh_of(positions: Vec<Point>, triangles: Vec<[u32; 3]>) -> Mesh {
    let soup = TriangleSoup {
        positions,
        triangles,
        ..TriangleSoup::default()
    };
    Mesh::from_soup(soup).unwrap().0
}

/// A copy of `mesh` with every position mapped by `map` (same triangles).
#[allow(dead_code)]
pub fn transformed(mesh: &Mesh, map: impl Fn(&Point) -> Point) -> Mesh {
    let soup = TriangleSoup {
        positions: mesh.positions().iter().map(map).collect(),
        triangles: mesh.triangles(),
        ..TriangleSoup::default()
    };
    Mesh::from_soup(soup).unwrap().0
}

/// `volume` moved by the inverse of `transform`, on the same grid: the value at
/// world point `x` is `interpolate(transform(x))` (an interpolant of `volume`), 0
/// outside it. Anatomy at `p` in `volume` lies at `transform⁻¹(p)` in the copy.
#[allow(dead_code)]
pub fn resampled(
    volume: &Volume,
    transform: &RigidTransform,
    interpolate: impl Fn(&Point) -> Option<f64> + Sync,
) -> Volume {
    let [nx, ny, nz] = volume.dims();
    let samples = (0..nx * ny * nz)
        .into_par_iter()
        .map(|at| {
            let index = [at % nx, (at / nx) % ny, at / (nx * ny)].map(|i| i as f64);
            let source = transform.apply(&volume.index_to_world(index));
            interpolate(&source).unwrap_or(0.0) as f32
        })
        .collect();
    volume.with_samples(samples).unwrap()
}

pub mod ci;

#[allow(unused_imports)]
pub use ci::{python, skip};
