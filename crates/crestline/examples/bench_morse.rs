//! Morse-Smale benchmark (Sahner et al. 2008, Table 1: 3.8 s to build the complex
//! and 30 s to cancel it fully on the 280k-triangle bunny): stage times of the
//! indicator, the discrete gradient, the 1-cell measures and the full cancellation
//! hierarchy on a large generated surface.
//!
//! ```sh
//! cargo run --release --example bench_morse -- [VERTICES] [NOISE]
//! ```
//!
//! The surface is a jittered torus with about `VERTICES` vertices (default 150 000,
//! about 300 000 triangles) whose vertices are moved along the normals by Gaussian
//! noise of `NOISE` mean edge lengths (default 0.2), so that the curvedness has
//! many critical points. Prints the counts and the time of each stage in seconds.

use std::time::Instant;

use crestline::curvature::ShapeOperator;
use crestline::mesh::generate::{self, Sampling};
use crestline::morse::cancel::{Criterion, Hierarchy};
use crestline::morse::cells::{maximum_regions, measure_saddles, minimum_regions};
use crestline::morse::gradient::{Gradient, Keys};
use crestline::morse::Indicator;
use crestline::Result;

fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let vertices: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(150_000);
    let noise: f64 = args.next().and_then(|a| a.parse().ok()).unwrap_or(0.2);
    let torus = generate::torus(1.0, 0.35, vertices, Sampling::jittered(1))?.mesh;
    let mesh = generate::with_normal_noise(&torus, noise, 2)?;
    println!(
        "torus: {} vertices, {} triangles, noise {noise} mean edge lengths",
        mesh.vertex_count(),
        mesh.face_count()
    );
    for criterion in [Criterion::Feature, Criterion::Persistence] {
        let start = Instant::now();
        let values = Indicator::Curvedness.values(&mesh, &ShapeOperator)?;
        let keys = Keys::new(&mesh, values);
        let indicator = start.elapsed().as_secs_f64();

        let start = Instant::now();
        let gradient = Gradient::new(&mesh, &keys);
        let gradient_time = start.elapsed().as_secs_f64();

        let start = Instant::now();
        let saddles = measure_saddles(&mesh, &keys, &gradient);
        let regions = (
            minimum_regions(&mesh, &keys, &gradient),
            maximum_regions(&mesh, &keys, &gradient),
        );
        let cells = start.elapsed().as_secs_f64();
        let counts = (
            gradient.minima.len(),
            gradient.saddles.len(),
            gradient.maxima.len(),
        );

        let start = Instant::now();
        let mut hierarchy = Hierarchy::new(&mesh, &keys, gradient, saddles, regions, criterion);
        let mut cancellations = 0usize;
        while hierarchy.cancel_next().is_some() {
            cancellations += 1;
        }
        let cancellation = start.elapsed().as_secs_f64();

        println!(
            "{criterion:?}: {} minima, {} saddles, {} maxima; {cancellations} cancellations",
            counts.0, counts.1, counts.2
        );
        println!(
            "  indicator {indicator:.3} s, gradient {gradient_time:.3} s, cells {cells:.3} s, \
             cancellation {cancellation:.3} s; construction + cancellation {:.3} s",
            gradient_time + cells + cancellation
        );
    }
    Ok(())
}
